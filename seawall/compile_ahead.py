"""Compiling a cold start on two cores: a forked helper compiles the run's largest loops ahead of it.

A run from an empty Numba cache spends most of its start compiling, one loop after another, on
one core (docs/performance.md, "Start-up"). Which loops the first step calls, and with which
argument types, is known without running them: the types of their arguments do not depend on
the values the earlier loops compute. So at the start of the first run in a process,
:func:`start` forks a helper that

1. *rehearses* the start of the run (rates, the probes' read-out, the first step; not the
   guards, which the run calls first anyway) on its own copy of the state, with every particle
   loop (:func:`seawall.jit.particle_loop`) only recorded -- its argument types noted, the loop
   not compiled and not run, so the state stays the initial one and the rehearsal takes
   seconds;
2. *publishes* the recorded loops, in the order the run will call them, as a plan; and
3. compiles them into Numba's on-disk cache, the largest first (by the length of their
   bytecode), while the run compiles what it calls in its own order.

Every compile of a seawall function called from Python is first *claimed* (a file created with
``O_EXCL`` in a directory both processes share): the process that claims it compiles it, and
the other, reaching it, loads it from the cache once it is there. A run that reaches a loop the
helper is still compiling does not idle: it compiles the plan's next unclaimed loops meanwhile
(the small ones the helper left for last), so the two finish close together. Neither process
ever waits while it holds an unfinished claim, so they cannot wait on each other; and each
gives up waiting when the other has ended, compiling for itself. The run's results do not
change: the machine code loaded from the cache is the code the run would have compiled. The
helper writes no output and ends when its list is done, or is stopped when the run has
finished its first step (everything a step calls is compiled then) or ends. Its copy of the
state shares the run's memory until one of them writes; the rehearsal may reorder the
particles, so while it lives it can hold one more copy of the particle arrays.

The fork must come before Numba starts its thread pool (GNU OpenMP, Numba's default layer on
Linux, ends a process forked from one that uses it): a :class:`~seawall.simulation.Simulation`
sets its thread count only when its first run starts (:func:`seawall.jit.use_threads`), and
the loops its set-up runs (the walls' cell lists) are serial.

It is used when the process can fork (Linux), at least two cores are usable, the process runs
no other thread and Numba's thread pool has not started;
``SEAWALL_COMPILE_AHEAD=0`` in the environment turns it off (the test suite does, as its two
worker processes already fill both cores).
"""

import atexit
import hashlib
import os
import pickle
import shutil
import signal
import sys
import tempfile
import threading
import time

from numba.core.dispatcher import Dispatcher

ENV_VARIABLE = "SEAWALL_COMPILE_AHEAD"
#: how often a waiting process looks for the other's result [s]
POLL_SECONDS = 0.02
#: a helper that waits longer than this for the run gives up (the run has stopped making progress)
HELPER_PATIENCE_SECONDS = 900.0

_original_compile_for_args = Dispatcher._compile_for_args
_state = {"started": False, "session": None}


def enabled(environ=None):
    """Whether this process may use a compile helper (see the module's docstring)."""
    value = (os.environ if environ is None else environ).get(ENV_VARIABLE, "1").strip().lower()
    if value in ("0", "false", "no", "off"):
        return False
    if value not in ("1", "true", "yes", "on"):
        raise ValueError(f"{ENV_VARIABLE}={value!r}: must be 1 or 0")
    if not hasattr(os, "fork") or not sys.platform.startswith("linux"):
        return False
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    if cores < 2:
        return False
    # a forked copy of a process with other threads (a dask worker, a progress bar's monitor) could
    # inherit a lock one of them held at the fork
    if threading.current_thread() is not threading.main_thread() or threading.active_count() > 1:
        return False
    from .jit import pool_started

    # a process whose thread pool has started cannot fork safely (GNU OpenMP ends the child)
    return not pool_started()


def _is_seawall(dispatcher):
    return getattr(dispatcher.py_func, "__module__", "").startswith("seawall")


def _name(dispatcher):
    return f"{dispatcher.py_func.__module__}.{dispatcher.py_func.__qualname__}"


def _size(dispatcher):
    """A loop's compile cost, estimated by the length of its bytecode (the dam break's longest
    compiles are its largest loops: fluid_rates 4.0k bytes, dummy_wall_forces 2.4k, adami_wall_state 2.0k)."""
    return len(dispatcher.py_func.__code__.co_code)


def _signature(dispatcher, args):
    """The argument types Numba would compile ``dispatcher`` for, called with ``args``."""
    return tuple(dispatcher.typeof_pyval(a) for a in args)


def _key(dispatcher, signature):
    text = f"{_name(dispatcher)}|{signature}"
    return hashlib.sha1(text.encode()).hexdigest()


class _Session:
    """The claims of one run-helper pair: a shared directory of ``<key>.claim`` / ``<key>.done`` files.

    ``other_alive()``: whether the other process still runs; ``patience``: the longest wait for
    one of its results [s] (None: as long as it runs).
    """

    def __init__(self, directory, other_alive, patience=None, loops=()):
        self.directory = directory
        self.other_alive = other_alive
        self.patience = patience
        self.pid = None
        #: compiles claimed by this process, and results of the other one loaded from the cache
        self.compiled_here = 0
        self.loaded_from_other = 0
        #: the loops a published plan may name (the run's side; see :meth:`take_from_plan`)
        self.loops = {_name(d): d for d in loops}
        self._plan = None

    def _path(self, key, suffix):
        return os.path.join(self.directory, key + suffix)

    def claim(self, key):
        try:
            os.close(os.open(self._path(key, ".claim"), os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            return True
        except FileExistsError:
            return False

    def done(self, key):
        with open(self._path(key, ".done"), "w"):
            pass

    def wait(self, key):
        """Until the other process has finished ``key`` (True), or has ended or kept us waiting too long.

        While it waits, a process with a published plan compiles the plan's unclaimed loops
        (:meth:`take_from_plan`) instead of idling.
        """
        waited = 0.0
        done = self._path(key, ".done")
        while not os.path.exists(done):
            if not self.other_alive() or (self.patience is not None and waited > self.patience):
                return False
            if self.take_from_plan():
                continue
            time.sleep(POLL_SECONDS)
            waited += POLL_SECONDS
        return True

    def publish_plan(self, plan):
        """Write the helper's list of (key, loop, argument types), in the order the run needs them."""
        entries = [(key, _name(dispatcher), signature) for key, dispatcher, signature in plan]
        path = self._path("plan", ".pickle")
        try:
            with open(path + ".tmp", "wb") as file:
                pickle.dump(entries, file)
            os.replace(path + ".tmp", path)      # the reader sees the whole plan or none
        except Exception:                        # unpicklable types: the run just waits, as without a plan
            pass

    def take_from_plan(self):
        """Claim and compile the first loop of the published plan nobody has claimed; whether one was found.

        The plan lists the loops in the order the run calls them, so a run that would wait for the
        helper compiles its own next loops meanwhile. It holds no unfinished claim while waiting,
        as each compile here is finished (and marked done) before it looks again.
        """
        if self._plan is None:
            try:
                with open(self._path("plan", ".pickle"), "rb") as file:
                    self._plan = [(key, self.loops.get(name), signature) for key, name, signature in pickle.load(file)]
            except (OSError, EOFError, pickle.UnpicklingError):
                return False
        for key, dispatcher, signature in self._plan:
            if dispatcher is None or not self.claim(key):
                continue          # not a loop of this process, or claimed already
            try:
                if dispatcher.overloads.get(signature) is None:
                    dispatcher.compile(signature)
                    self.compiled_here += 1
            except Exception:      # not this wait's business: the run meets it again when it calls the loop
                pass
            finally:
                self.done(key)
            return True
        return False

    def compile_claimed(self, dispatcher, args):
        """``Dispatcher._compile_for_args`` under the claims: compile here, or load what the other compiled."""
        signature = _signature(dispatcher, args)
        if dispatcher.overloads.get(signature) is not None:
            return _original_compile_for_args(dispatcher, *args)
        key = _key(dispatcher, signature)
        if self.claim(key):
            try:
                return _original_compile_for_args(dispatcher, *args)
            finally:
                self.compiled_here += 1
                self.done(key)        # also after a failed compile: the other then tries for itself
        if self.wait(key):
            self.loaded_from_other += 1
        return _original_compile_for_args(dispatcher, *args)   # from the cache, or compiled here after all


def _noop(*args, **kws):
    return None


def _install(hook):
    def compile_for_args(self, *args, **kws):
        if kws or not _is_seawall(self):
            return _original_compile_for_args(self, *args, **kws)
        return hook(self, args)
    Dispatcher._compile_for_args = compile_for_args


def _uninstall():
    Dispatcher._compile_for_args = _original_compile_for_args


def _helper(session, rehearsal, loops):
    """The forked helper's whole life: rehearse, publish the plan, compile its loops the largest first."""
    recorded = []

    def hook(dispatcher, args):
        if dispatcher in loops:
            signature = _signature(dispatcher, args)
            if all(dispatcher is not d or signature != s for d, s in recorded):
                recorded.append((dispatcher, signature))
            return _noop          # recorded, neither compiled nor run: the state stays as it was
        return session.compile_claimed(dispatcher, args)

    _install(hook)
    for stage in rehearsal:
        try:
            stage()
        except Exception:        # a stage cut short still leaves what it recorded
            pass
    plan = [(_key(dispatcher, signature), dispatcher, signature) for dispatcher, signature in recorded]
    session.publish_plan(plan)
    # the largest first: the run compiles its loops in the order it calls them and, when it would
    # wait for one the helper holds, the plan's next unclaimed ones, so the small loops fill the gaps
    order = sorted(range(len(plan)), key=lambda k: (-_size(plan[k][1]), -k))
    for k in order:
        key, dispatcher, signature = plan[k]
        if not session.other_alive():
            break                 # the run has ended
        if dispatcher.overloads.get(signature) is not None or not session.claim(key):
            continue              # compiled already, or the run's
        try:
            dispatcher.compile(signature)
        finally:
            session.done(key)


def start(rehearsal, loops):
    """Fork a helper that rehearses the run's start and compiles ``loops`` ahead of this process.

    ``rehearsal``: callables, run in turn in the helper on its copy of the state; one that
    raises does not stop the next (they run on the values the skipped loops did not compute).

    ``loops``: the dispatchers the rehearsal records instead of running
    (:data:`seawall.jit.PARTICLE_LOOPS`, which only write into arrays they are given, so
    skipping them leaves the state as it was). Does nothing after the first
    call in a process or when :func:`enabled` says no. Returns whether a helper was started.
    """
    if _state["started"]:
        return False
    _state["started"] = True
    if not enabled():
        return False
    directory = tempfile.mkdtemp(prefix="seawall-compile-")
    parent = os.getpid()
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        pid = os.fork()
    except OSError:               # no process to spare: the run compiles alone
        shutil.rmtree(directory, ignore_errors=True)
        return False
    if pid == 0:  # the helper
        status = 0
        try:
            # Ctrl-C or a stop ends the helper at once (the run may have its own handlers)
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            _helper(_Session(directory, lambda: os.getppid() == parent, HELPER_PATIENCE_SECONDS), rehearsal, loops)
        except BaseException:
            status = 1
        finally:
            os._exit(status)     # no atexit handlers, no flushing of the run's buffers

    def helper_alive():
        try:
            ended, _ = os.waitpid(pid, os.WNOHANG)
        except ChildProcessError:
            ended = pid
        if ended == pid:
            session.pid = None    # reaped
            finish()
            return False
        return True

    session = _Session(directory, helper_alive, loops=loops)
    session.pid = pid
    _state["session"] = session
    _install(session.compile_claimed)
    atexit.register(finish)
    return True


def finish():
    """End the sharing: uninstall the hook, stop and reap the helper if it still runs, remove the claims.

    Stopping a helper mid-compile loses nothing: Numba writes a cache entry to a temporary file
    and renames it into place.
    """
    session = _state["session"]
    if session is None:
        return
    _state["session"] = None
    _uninstall()
    if session.pid is not None:
        try:
            os.kill(session.pid, signal.SIGKILL)
            os.waitpid(session.pid, 0)
        except (ProcessLookupError, ChildProcessError):
            pass
    shutil.rmtree(session.directory, ignore_errors=True)
