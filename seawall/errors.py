"""Exceptions raised by seawall.

`ParameterError` is for bad user input: its message names the parameter and
what is allowed, and the CLI prints it as one line without a traceback.
`InstabilityError` is raised when a run blows up; it carries where and when.
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
