"""Command-line names of the wall models and how to build each from options.

A factory takes the options given with ``--set KEY=VALUE`` that it knows
(unknown keys are left for the case) and returns a WallModel.
"""

from ..errors import ParameterError
from .dbc import DynamicBoundary, ImprovedDynamicBoundary
from .dummy import DummyParticles
from .ghost import GhostParticles
from .interpolation import MLS, SFDI, ImprovedShepard, Normalised


def _dummy(density, default_slip="free"):
    def factory(options):
        slip = options.pop("slip", default_slip)
        nu = options.pop("wall_nu", None)
        clip = options.pop("clip_negative", None)
        clip = None if clip is None else _flag(clip)
        return DummyParticles(density=density, slip=slip, nu=None if nu is None else _number("wall_nu", nu),
                              clip_negative_pressure=clip)
    return factory


def _ghost(make):
    """Factory of a ghost-particle wall (seed 001) with interpolation ``make(options)``; ``slip=free|noslip``."""
    def factory(options):
        slip = str(options.pop("slip", "free"))
        return GhostParticles(make(options), slip=slip)
    return factory


def _shepard(options):
    return ImprovedShepard(mu=_number("shepard_mu", options.pop("shepard_mu", 4.0)),
                           lam=_number("shepard_lambda", options.pop("shepard_lambda", 2.0)))


def _monaghan_kajtar(options):
    from .repulsive import MonaghanKajtar

    K = options.pop("K", None)
    return MonaghanKajtar(K=None if K is None else _number("K", K), beta=_number("beta", options.pop("beta", 3.0)),
                          alpha_wall=_number("alpha_wall", options.pop("alpha_wall", 0.0)))


def _liu2015(default_slip="free"):
    def factory(options):
        from .liu2015 import Liu2015Wall

        nu = options.pop("wall_nu", None)
        return Liu2015Wall(slip=str(options.pop("slip", default_slip)), nu=None if nu is None else _number("wall_nu", nu),
                           continuity=str(options.pop("continuity", "normal")))
    return factory


def _liu2012(options):
    from .liu2012 import Liu2012Force

    return Liu2012Force(beta=_number("beta", options.pop("beta", 2.0)))


def _number(name, value):
    """A wall option as a finite float; the error names the option."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"wall option {name} must be a number, got {value!r}") from None
    if number != number or number in (float("inf"), float("-inf")):
        raise ParameterError(f"wall option {name} must be finite, got {value!r}")
    return number


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
            kwargs["alpha_wall"] = _number("alpha_wall", options.pop("alpha_wall"))
        return cls(**kwargs)
    return factory


#: name -> (factory, one-line description)
BOUNDARIES = {
    "adami": (_dummy("adami"), "dummy particles, Adami et al. (2012) pressure extrapolation, free slip"),
    "adami-noslip": (_dummy("adami", "noslip"), "dummy particles, Adami pressure extrapolation, no slip (Adami wall velocity)"),
    "summation": (_dummy("summation"), "dummy particles, wall density by summation, EOS pressure"),
    "continuity": (_dummy("continuity"), "dummy particles, wall density by the continuity equation, EOS pressure"),
    "zeroing": (_dummy("zeroing"), "dummy particles at reference density and pressure (pressure zeroing)"),
    "mirroring": (_dummy("mirroring"), "dummy particles mirroring the fluid particle's pressure (pressure mirroring)"),
    "ghost-mls1": (_ghost(lambda o: MLS(1)),
                   "fixed ghost particles, MLS linear interpolation at mirror points (seed 001); slip=free|noslip"),
    "ghost-mls2": (_ghost(lambda o: MLS(2)),
                   "fixed ghost particles, MLS quadratic interpolation at mirror points (seed 001); slip=free|noslip"),
    "ghost-sfdi": (_ghost(lambda o: SFDI(diagonal=_flag(o.pop("sfdi_diagonal", False)))),
                   "fixed ghost particles, SFDI interpolation (Ma 2008, seed 001); slip=free|noslip, sfdi_diagonal"),
    "ghost-normalized": (_ghost(lambda o: Normalised()),
                         "fixed ghost particles, normalised (Shepard kernel) interpolation (seed 001); slip=free|noslip"),
    "ghost-shepard": (_ghost(_shepard),
                      "fixed ghost particles, improved Shepard interpolation (seed 001); slip, shepard_mu, shepard_lambda"),
    "monaghan-kajtar": (_monaghan_kajtar, "repulsive wall particles, Monaghan & Kajtar (2009), one row at dx/beta "
                        "(--set K=... beta=3 alpha_wall=0)"),
    "dbc": (_dynamic(DynamicBoundary),
            "dynamic boundary particles, Crespo et al. (2007): continuity + linear EOS (seed 000 eq. 12)"),
    "idbc": (_dynamic(ImprovedDynamicBoundary),
             "improved DBC, Li et al. (seed 000): order-7 EOS, rectangular support, alpha_DB "
             "(--set order=1..7 rectangular=0/1 correction=0/1 alpha_wall=...)"),
    "liu2015": (_liu2015(), "dummy particles of Liu et al. (2015, seed 003): normal-only repulsive pressure term, "
                "Taylor/CSPM dummy pressure (--set slip=free|noslip continuity=normal|conditional|off)"),
    "liu2015-noslip": (_liu2015("noslip"), "Liu et al. (2015) dummy particles with no slip (eq. 28-29)"),
    "liu2012": (_liu2012, "boundary force of Liu, Shao & Chang (2012), one row at dx/beta (--set beta=2)"),
}


def boundary_by_name(name, options=None):
    """Build the wall model called ``name``; ``options`` (dict) is consumed for known keys."""
    options = {} if options is None else options
    try:
        factory, _ = BOUNDARIES[name]
    except KeyError:
        raise ParameterError(f"unknown boundary {name!r}; available: {', '.join(BOUNDARIES)}") from None
    return factory(options)
