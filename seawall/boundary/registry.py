"""Command-line names of the wall models and how to build each from options.

A factory takes the options given with ``--set KEY=VALUE`` that it knows
(unknown keys are left for the case) and returns a WallModel.
"""

from ..errors import ParameterError
from .dbc import DynamicBoundary, ImprovedDynamicBoundary
from .dummy import DummyParticles


def _adami(options):
    return DummyParticles(slip="free", clip_negative_pressure=_flag(options.pop("clip_negative", False)))


def _adami_noslip(options):
    nu = options.pop("wall_nu", None)
    return DummyParticles(slip="noslip", nu=None if nu is None else float(nu),
                          clip_negative_pressure=_flag(options.pop("clip_negative", False)))


def _flag(value):
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("1", "true", "yes", "on"):
        return True
    if text in ("0", "false", "no", "off"):
        return False
    raise ParameterError(f"expected a true/false value, got {value!r}")


def _dynamic(cls):
    def factory(options):
        kwargs = {}
        if "order" in options:
            kwargs["order"] = options.pop("order")
        if "rectangular" in options:
            kwargs["rectangular"] = _flag(options.pop("rectangular"))
        if "correction" in options:
            kwargs["correction"] = _flag(options.pop("correction"))
        if "wall_density" in options:
            kwargs["wall_density"] = str(options.pop("wall_density")).strip()
        if "alpha_wall" in options:
            try:
                kwargs["alpha_wall"] = float(options.pop("alpha_wall"))
            except ValueError:
                raise ParameterError("alpha_wall must be a number") from None
        return cls(**kwargs)
    return factory


#: name -> (factory, one-line description)
BOUNDARIES = {
    "adami": (_adami, "dummy particles, Adami et al. (2012) pressure extrapolation, free slip"),
    "adami-noslip": (_adami_noslip, "dummy particles, Adami pressure extrapolation, no slip (Adami wall velocity)"),
    "dbc": (_dynamic(DynamicBoundary),
            "dynamic boundary particles, Crespo et al. (2007): continuity + linear EOS (seed 000 eq. 12)"),
    "idbc": (_dynamic(ImprovedDynamicBoundary),
             "improved DBC, Li et al. (seed 000): order-7 EOS, rectangular support, alpha_DB "
             "(--set order=1..7 rectangular=0/1 correction=0/1 alpha_wall=...)"),
}


def boundary_by_name(name, options=None):
    """Build the wall model called ``name``; ``options`` (dict) is consumed for known keys."""
    options = {} if options is None else options
    try:
        factory, _ = BOUNDARIES[name]
    except KeyError:
        raise ParameterError(f"unknown boundary {name!r}; available: {', '.join(BOUNDARIES)}") from None
    return factory(options)
