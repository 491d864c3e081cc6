"""Command-line names of the wall models and how to build each from options.

A factory takes the options given with ``--set KEY=VALUE`` that it knows
(unknown keys are left for the case) and returns a WallModel.
"""

from ..errors import ParameterError
from .dummy import DummyParticles


def _dummy(density, default_slip="free"):
    def factory(options):
        slip = options.pop("slip", default_slip)
        nu = options.pop("wall_nu", None)
        clip = options.pop("clip_negative", None)
        clip = None if clip is None else _flag(clip)
        return DummyParticles(density=density, slip=slip, nu=None if nu is None else float(nu),
                              clip_negative_pressure=clip)
    return factory


def _flag(value):
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("1", "true", "yes", "on"):
        return True
    if text in ("0", "false", "no", "off"):
        return False
    raise ParameterError(f"expected a true/false value, got {value!r}")


#: name -> (factory, one-line description)
BOUNDARIES = {
    "adami": (_dummy("adami"), "dummy particles, Adami et al. (2012) pressure extrapolation, free slip"),
    "adami-noslip": (_dummy("adami", "noslip"), "dummy particles, Adami pressure extrapolation, no slip (Adami wall velocity)"),
    "summation": (_dummy("summation"), "dummy particles, wall density by summation, EOS pressure"),
    "continuity": (_dummy("continuity"), "dummy particles, wall density by the continuity equation, EOS pressure"),
    "zeroing": (_dummy("zeroing"), "dummy particles at reference density and pressure (pressure zeroing)"),
    "mirroring": (_dummy("mirroring"), "dummy particles mirroring the fluid particle's pressure (pressure mirroring)"),
}


def boundary_by_name(name, options=None):
    """Build the wall model called ``name``; ``options`` (dict) is consumed for known keys."""
    options = {} if options is None else options
    try:
        factory, _ = BOUNDARIES[name]
    except KeyError:
        raise ParameterError(f"unknown boundary {name!r}; available: {', '.join(BOUNDARIES)}") from None
    return factory(options)
