"""Exceptions raised by seawall.

`ParameterError` is for bad user input: its message names the parameter and
what is allowed, and the CLI prints it as one line without a traceback.
`InstabilityError` is raised when a run blows up; it carries where and when.
`OutputError` is raised when an output file cannot be written (disk full,
output directory removed during the run); `RunInterrupted` when a signal
(Ctrl-C, SIGTERM) stopped a run.
"""


class SeawallError(Exception):
    """Base class of every error seawall raises on purpose."""


class ParameterError(SeawallError, ValueError):
    """A user-supplied parameter is outside its allowed range."""


class InstabilityError(SeawallError, RuntimeError):
    """The run became unstable: the guards removed more than ``unstable_fraction`` of the
    fluid as damage (non-finite state, density out of band, wall crossing) within
    ``unstable_window``, or the time step is not finite (``seawall.health``).

    Attributes give the step, simulated time and the particle (its id and
    position) where the guard fired, and the last good checkpoint if any.
    """

    def __init__(self, message, *, step=None, time=None, particle_id=None,
                 position=None, checkpoint=None):
        super().__init__(message)
        self.step = step
        self.time = time
        self.particle_id = particle_id
        self.position = position
        self.checkpoint = checkpoint


class OutputError(SeawallError, OSError):
    """An output file could not be written; ``path`` is the file (or directory) concerned."""

    def __init__(self, message, *, path=None):
        super().__init__(message)
        self.path = path

    def __str__(self):
        return self.args[0] if self.args else ""


class RunInterrupted(KeyboardInterrupt):
    """A run stopped by a signal; ``signal_name`` is ``"SIGINT"`` (Ctrl-C) or ``"SIGTERM"``.

    A KeyboardInterrupt, so code that handles Ctrl-C handles SIGTERM the same way.
    """

    def __init__(self, signal_name="SIGINT"):
        super().__init__(signal_name)
        self.signal_name = signal_name


def require_positive(name, value):
    """Raise ParameterError unless ``value`` is a finite number > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a positive number, got {value!r}") from None
    if not (v > 0.0) or v != v or v == float("inf"):
        raise ParameterError(f"{name} must be a positive finite number, got {value!r}")
    return v


def require_nonnegative(name, value):
    """Raise ParameterError unless ``value`` is a finite number >= 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a non-negative number, got {value!r}") from None
    if not (v >= 0.0) or v == float("inf"):
        raise ParameterError(f"{name} must be a non-negative finite number, got {value!r}")
    return v
