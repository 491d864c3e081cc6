"""How seawall's particle loops are compiled: threaded (the default) or serial.

Every loop over particles is decorated with :func:`particle_loop`, which is Numba's
``njit(parallel=...)`` with ``prange`` spreading the particles over threads (and only
``prange``: :func:`parallel_options`). Numba's
parallel passes are most of the cold compile time: the default dam break's cold start took
about 120 s of CPU time threaded against 55 s serial on the project's 2-core machine, and
about 78 s against 48 s once the switches became literals (:func:`type_constant`,
:func:`fold_switches`; docs/performance.md, "Start-up"). ``SEAWALL_LOOPS=serial`` in the
environment, read once at import, compiles the same loops without the parallel passes
(``prange`` then runs as ``range``): the results are the same row by row, only one thread
works. The test suite uses it (tests/conftest.py), which is what keeps its cold compile
short; one test runs the threaded build against it.

Numba's on-disk cache does not key its entries on the ``parallel`` flag, so a serial build
would load threaded machine code and the reverse. The serial build therefore caches under
its own directory (``serial-loops`` beside Numba's cache directory, or in the package's
``__pycache__``).
"""

import os
import tempfile

import numba
from numba import njit, types
from numba.extending import intrinsic

LOOPS_VARIABLE = "SEAWALL_LOOPS"
LOOP_MODES = ("threaded", "serial")


def loop_mode(environ=None):
    """The build the environment asks for: ``"threaded"`` (default) or ``"serial"``."""
    value = (os.environ if environ is None else environ).get(LOOPS_VARIABLE, "threaded").strip().lower()
    if value not in LOOP_MODES:
        raise ValueError(f"{LOOPS_VARIABLE}={value!r}: must be one of {', '.join(LOOP_MODES)}")
    return value


THREADED = loop_mode() == "threaded"


def parallel_options(threaded=THREADED):
    """Numba's ``parallel`` option of a particle loop: ``prange`` only, or ``False`` when serial.

    seawall writes its parallelism as explicit ``prange`` loops; the automatic conversions of
    array expressions, slice assignments, comprehensions and NumPy calls into parallel loops,
    and the fusion of such loops, find nothing worth a thread in its loops (3-element
    ``1.0 / inv_cell`` and one ``start[:] = 0`` in the default run) but cost compile time: the
    default dam break's cold compile took about 18 % less process CPU without them (medians)
    (docs/performance.md, "Start-up"). Given as Numba's ``ParallelOptions``, not a dict: Numba
    empties a dict at a loop's first compile, so a second specialisation would get every
    conversion back.
    """
    if not threaded:
        return False
    try:
        from numba.core.cpu import ParallelOptions
    except ImportError:     # a Numba without this class: every conversion, as parallel=True
        return True
    return ParallelOptions({"prange": True, "reduction": True, "numpy": False, "setitem": False,
                            "comprehension": False, "inplace_binop": False, "stencil": False, "fusion": False})


#: the ``parallel`` option every particle loop is compiled with (Numba copies it, never empties it)
PARALLEL = parallel_options()


def _serial_cache_dir():
    base = numba.config.CACHE_DIR or os.path.join(os.path.dirname(os.path.abspath(__file__)), "__pycache__")
    path = os.path.join(base, "serial-loops")
    try:
        os.makedirs(path, exist_ok=True)
    except OSError:
        path = os.path.join(tempfile.gettempdir(), "seawall-serial-loops")
        os.makedirs(path, exist_ok=True)
    return path


if not THREADED:
    # read by Numba when each cached function is decorated, so it must be set before the loops
    # below are defined; every seawall module that compiles a loop imports this one first
    numba.config.CACHE_DIR = _serial_cache_dir()


# the count a Simulation asked for, held until its run starts (None: Numba's own)
_requested_threads = [None]


def use_threads(threads):
    """Ask for ``threads`` threads of the compiled loops.

    Applied now if Numba's thread pool runs already, else when :func:`apply_threads` is called
    at the start of a run: setting the count starts the pool, and a process whose pool runs
    can no longer fork a compile helper (:mod:`seawall.compile_ahead`).
    """
    _requested_threads[0] = int(threads)
    if pool_started():
        numba.set_num_threads(_requested_threads[0])


#: fluid and wall particles per thread below which a thread costs a run more than it saves
PARTICLES_PER_THREAD = 4000


def threads_for(particles, available=None):
    """The thread count of a run of ``particles`` (fluid and wall) that asked for none.

    Every parallel loop wakes the sleeping threads (``OMP_WAIT_POLICY=PASSIVE``, set by ``import
    seawall``), and a step runs about ten, so a small run pays more for the second thread than
    it gains: the 2D dam break, 2 threads against 1 (``seawall bench``, median chunk, quiet
    2-core machine): 1.56 / 2.51 M particle-steps/s at 3.2k particles, 1.93 / 2.27 at 4.5k,
    2.22 / 2.28 at 7.2k, 2.90 / 2.37 at 14.6k. So a thread per ``PARTICLES_PER_THREAD``
    particles, at least one and at most ``available`` (Numba's ``NUMBA_NUM_THREADS``: the cores).
    """
    available = int(numba.config.NUMBA_NUM_THREADS if available is None else available)
    return max(1, min(available, int(particles) // PARTICLES_PER_THREAD))


def apply_threads():
    """Set the thread count asked for by :func:`use_threads`, if any (starts Numba's pool)."""
    if _requested_threads[0] is not None:
        numba.set_num_threads(_requested_threads[0])


def thread_count():
    """The threads the compiled loops use, or will use once the pool starts; does not start it."""
    if pool_started():
        return int(numba.get_num_threads())
    if _requested_threads[0] is not None:
        return _requested_threads[0]
    return int(numba.config.NUMBA_NUM_THREADS)


def pool_started():
    """Whether Numba's thread pool runs (asking does not start it)."""
    from numba.np.ufunc import parallel

    return bool(parallel._is_initialized)


#: every particle loop: what a compile helper's rehearsal records instead of running (:mod:`seawall.compile_ahead`)
PARTICLE_LOOPS = set()


def particle_loop(fastmath=True):
    """Decorator of a compiled loop over particles (``prange``), threaded unless ``SEAWALL_LOOPS=serial``.

    ``fastmath=True`` also selects NumPy's error model (a division by zero gives inf or nan,
    no exception), as every pair loop uses; ``fastmath=False`` is plain ``njit``.
    A particle loop writes values into arrays it is given and returns nothing: Python code
    never steers by what it computes (the cell list, which does, is a serial loop), which is
    what lets a compile helper skip it in its rehearsal (:mod:`seawall.compile_ahead`).
    """
    if fastmath:
        jit = njit(cache=True, parallel=PARALLEL, fastmath=True, error_model="numpy")
    else:
        jit = njit(cache=True, parallel=PARALLEL)

    def decorate(func):
        dispatcher = jit(func)
        PARTICLE_LOOPS.add(dispatcher)
        return dispatcher
    return decorate


def loop_helper(func):
    """Decorator of the small functions the compiled loops call: pair terms, cell arithmetic, equations of state.

    Each is compiled once, with the pair loops' options (``fastmath``, NumPy's error model), and
    LLVM inlines it into every loop that calls it (none is left as a call in the default run's
    loops). Numba's own ``inline="always"`` pastes a function's IR into each caller instead,
    where each of Numba's passes over the loop -- type inference twice, the parallel passes'
    copy propagation and simplification, the lowering -- works through it again: the default
    dam break's cold compile took 32-35 s of CPU with them inlined by Numba and 25-27 s so
    (docs/performance.md, "Start-up", eighth pass), with ``probes.csv`` unchanged bit for bit.
    The functions that branch on a compile-time switch (:func:`type_constant`: the kernel, the
    dimension, periodicity) stay ``inline="always"``, so that Numba folds the switch first.
    A serial caller without ``fastmath`` gets these with ``fastmath`` too.
    """
    return _LOOP_HELPER(func)


_LOOP_HELPER = njit(cache=True, fastmath=True, error_model="numpy")


def type_constant(rule):
    """A compiled function ``f(tag)`` whose value ``rule(type of tag)`` is a compile-time literal.

    seawall passes its switches (dimension, periodicity, the fluid scheme's terms) as zero-size
    arrays whose number of axes is the value (:func:`seawall.neighbors.layout_tag`,
    :func:`seawall.fluid.rates.scheme_tag`): one specialisation per combination. Read through a
    function made here, the value is typed as a Numba literal, so Numba's own branch pruning
    (its literal-propagation pass, which runs where ``isinstance`` appears in a function; see
    :func:`fold_switches`) removes the branches a run does not take before the parallel passes
    copy and simplify the loop body, instead of leaving them to LLVM. The result is the same;
    the compile is shorter (docs/performance.md, "Start-up").
    """
    @intrinsic
    def constant(typingctx, tag):
        value = rule(tag)
        literal = types.literal(value)

        def codegen(context, builder, signature, args):
            return context.get_constant(literal.literal_type, value)
        return literal(tag), codegen
    return constant


@njit(cache=True, inline="always")
def fold_switches():
    """Inlined into a loop, makes Numba fold the literals of :func:`type_constant` into its branches.

    Numba runs its literal-propagation pass (partial type inference, literal values written as
    constants, dead-branch pruning) only on a function whose IR names the global ``isinstance``
    or ``hasattr``; the bare name below is that mark, and does nothing at run time. Without it
    the results are the same and the dead branches reach LLVM, which removes them later.
    """
    isinstance  # noqa: B018 -- the mark that asks Numba for literal propagation
