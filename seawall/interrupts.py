"""Ctrl-C (SIGINT) and SIGTERM stop a run the same way, leaving consistent files.

While the time-step loop runs, the first signal only asks the simulation to
stop: it finishes the current step, writes a checkpoint of that state and
raises :class:`~seawall.errors.RunInterrupted`. Outside the loop (start-up,
compilation) or at a second signal, ``RunInterrupted`` is raised at once.
Either way the caller sees a KeyboardInterrupt carrying the signal's name.
"""

import contextlib
import signal
import threading

from .errors import RunInterrupted

HANDLED = ("SIGINT", "SIGTERM")


@contextlib.contextmanager
def stop_on_signals(get_sim=lambda: None):
    """Handle SIGINT and SIGTERM inside the block; ``get_sim()`` gives the running simulation, if any."""
    if threading.current_thread() is not threading.main_thread():
        yield   # signal handlers can only be installed by the main thread
        return

    def handler(signum, _frame):
        name = signal.Signals(signum).name
        sim = get_sim()
        if sim is not None and getattr(sim, "in_step_loop", False) and getattr(sim, "stop_requested", None) is None:
            sim.stop_requested = name
            return
        raise RunInterrupted(name)

    previous = {}
    for name in HANDLED:
        signum = getattr(signal, name)
        previous[signum] = signal.signal(signum, handler)
    try:
        yield
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old)
