"""Command-line names of the wall models and how to build each from options.

A factory is a function of keyword arguments only: the ``--set KEY=VALUE``
options the model takes (values may arrive as strings from the command
line). :func:`boundary_options` reads them from the factory's signature, so
a case knows which ``--set`` keys belong to the wall model without a list
kept by hand; a model class's own constructor keywords are
:meth:`seawall.boundary.base.WallModel.options`.
"""

import inspect

from ..errors import ParameterError
from .dbc import DynamicBoundary, ImprovedDynamicBoundary
from .dummy import DummyParticles
from .ghost import GhostParticles
from .interpolation import MLS, SFDI, ImprovedShepard, Normalised


def _dummy(density, default_slip="free"):
    def factory(*, slip=default_slip, wall_nu=None, clip_negative=None):
        return DummyParticles(density=density, slip=slip, nu=None if wall_nu is None else _number("wall_nu", wall_nu),
                              clip_negative_pressure=(None if clip_negative is None
                                                      else _flag("clip_negative", clip_negative)))
    return factory


def _ghost(make):
    """Factory of a ghost-particle wall ([Huang2019]) with interpolation ``make(**options)``; ``slip=free|noslip``.

    The factory takes ``slip`` and the keywords of ``make``.
    """
    def factory(*, slip="free", reflect=False, **options):
        return GhostParticles(make(**options), slip=str(slip), reflect=_flag("reflect", reflect))
    factory.__signature__ = inspect.Signature(
        [inspect.Parameter("slip", inspect.Parameter.KEYWORD_ONLY, default="free"),
         inspect.Parameter("reflect", inspect.Parameter.KEYWORD_ONLY, default=False)]
        + [p.replace(kind=inspect.Parameter.KEYWORD_ONLY) for p in inspect.signature(make).parameters.values()])
    return factory


def _shepard(shepard_mu=4.0, shepard_lambda=2.0):
    return ImprovedShepard(mu=_number("shepard_mu", shepard_mu), lam=_number("shepard_lambda", shepard_lambda))


def _sfdi(sfdi_diagonal=False):
    return SFDI(diagonal=_flag("sfdi_diagonal", sfdi_diagonal))


def _monaghan_kajtar(*, K=None, beta=3.0, alpha_wall=0.0, mass_factor="pair"):
    from .repulsive import MonaghanKajtar

    return MonaghanKajtar(K=None if K is None else _number("K", K), beta=_number("beta", beta),
                          alpha_wall=_number("alpha_wall", alpha_wall), mass_factor=str(mass_factor).strip())


def _liu2015(default_slip="free"):
    def factory(*, slip=default_slip, wall_nu=None, continuity="normal", normal_velocity="mirror", sound_speed=True):
        from .liu2015 import Liu2015Wall

        return Liu2015Wall(slip=str(slip), nu=None if wall_nu is None else _number("wall_nu", wall_nu),
                           continuity=str(continuity), normal_velocity=str(normal_velocity),
                           sound_speed_term=_flag("sound_speed", sound_speed))
    return factory


def _mdbc(default_slip):
    def factory(*, slip=default_slip, order=1, det_min=1e-3, clip_negative=False):
        from .mdbc import ModifiedDynamicBoundary

        return ModifiedDynamicBoundary(slip=str(slip), order=order, det_min=det_min,
                                       clip_negative=_flag("clip_negative", clip_negative))
    return factory


def _lust(default_slip="free"):
    def factory(*, slip=default_slip, pressure="hydrostatic", alpha_wall=None):
        from .lust import LocalUniformStencil

        return LocalUniformStencil(slip=str(slip), pressure=str(pressure),
                                   alpha_wall=None if alpha_wall is None else _number("alpha_wall", alpha_wall))
    return factory


def _liu2012(*, beta=2.0, c=None):
    from .liu2012 import Liu2012Force

    return Liu2012Force(beta=_number("beta", beta), c=None if c is None else _number("c", c))


def _number(name, value):
    """A wall option as a finite float; the error names the option."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"wall option {name} must be a number, got {value!r}") from None
    if number != number or number in (float("inf"), float("-inf")):
        raise ParameterError(f"wall option {name} must be finite, got {value!r}")
    return number


def _flag(name, value):
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("1", "true", "yes", "on"):
        return True
    if text in ("0", "false", "no", "off"):
        return False
    raise ParameterError(f"wall option {name} must be a true/false value (1/0, yes/no), got {value!r}")


def _dynamic(cls):
    def factory(*, order=None, rectangular=None, correction=None, wall_density=None, alpha_wall=None):
        kwargs = {}
        if order is not None:
            kwargs["order"] = order
        if rectangular is not None:
            kwargs["rectangular"] = _flag("rectangular", rectangular)
        if correction is not None:
            kwargs["correction"] = _flag("correction", correction)
        if wall_density is not None:
            kwargs["wall_density"] = str(wall_density).strip()
        if alpha_wall is not None:
            kwargs["alpha_wall"] = _number("alpha_wall", alpha_wall)
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
    "ghost-mls1": (_ghost(lambda: MLS(1)),
                   "fixed ghost particles, MLS linear interpolation at mirror points ([Huang2019]); "
                   "slip=free|noslip, reflect"),
    "ghost-mls2": (_ghost(lambda: MLS(2)),
                   "fixed ghost particles, MLS quadratic interpolation at mirror points ([Huang2019]); "
                   "slip=free|noslip, reflect"),
    "ghost-sfdi": (_ghost(_sfdi),
                   "fixed ghost particles, SFDI interpolation (Ma 2008, [Huang2019]); "
                   "slip=free|noslip, reflect, sfdi_diagonal"),
    "ghost-normalized": (_ghost(lambda: Normalised()),
                         "fixed ghost particles, normalised (Shepard kernel) interpolation ([Huang2019]); "
                         "slip=free|noslip, reflect"),
    "ghost-shepard": (_ghost(_shepard),
                      "fixed ghost particles, improved Shepard interpolation ([Huang2019]); "
                      "slip, reflect, shepard_mu, shepard_lambda"),
    "monaghan-kajtar": (_monaghan_kajtar, "repulsive wall particles, Monaghan & Kajtar (2009), one row at dx/beta "
                        "(--set K=... beta=3 alpha_wall=0 mass_factor=pair|none)"),
    "dbc": (_dynamic(DynamicBoundary),
            "dynamic boundary particles, Crespo et al. (2007): continuity + linear EOS ([Li2022] eq. 12)"),
    "idbc": (_dynamic(ImprovedDynamicBoundary),
             "improved DBC, Li et al. ([Li2022]): order-7 EOS, rectangular support, alpha_DB "
             "(--set order=1..7 rectangular=0/1 correction=0/1 alpha_wall=...)"),
    "liu2015": (_liu2015(), "dummy particles of Liu et al. (2015, [Liu2015]): normal-only repulsive pressure term, "
                "Taylor/CSPM dummy pressure (--set slip=free|noslip continuity=normal|conditional|off "
                "normal_velocity=mirror|wall sound_speed=1|0)"),
    "liu2015-noslip": (_liu2015("noslip"), "Liu et al. (2015) dummy particles with no slip (eq. 28-29)"),
    "mdbc": (_mdbc("vel0"), "modified DBC, English et al. (2022, [English2022]): wall density extrapolated from a "
             "mirrored ghost node, first-order corrected (--set order=1|0 det_min=1e-3 slip=vel0|noslip "
             "clip_negative=0|1)"),
    "mdbc-noslip": (_mdbc("noslip"), "mDBC with no slip: v_b = 2 v_w - v_ghost ([English2022])"),
    "liu2012": (_liu2012, "boundary force of Liu, Shao & Chang (2012), one row at dx/beta (--set beta=2 c=<force speed, "
                "default c0>)"),
    "lust": (_lust(), "local uniform stencil, Fourtakas et al. (2019, [Fourtakas2019]): virtual nodes of a lattice "
             "anchored on each fluid particle fill its support behind the wall (--set slip=free|noslip "
             "pressure=hydrostatic|copy alpha_wall=<fluid's alpha>)"),
}


def boundary_option_defaults(name):
    """The ``--set`` keys wall model ``name`` takes and their defaults (key -> default; ``None`` leaves
    the choice to the model or the fluid)."""
    try:
        factory, _ = BOUNDARIES[name]
    except KeyError:
        raise ParameterError(f"unknown boundary {name!r}; available: {', '.join(BOUNDARIES)}") from None
    return {p.name: p.default for p in inspect.signature(factory).parameters.values()
            if p.kind == inspect.Parameter.KEYWORD_ONLY}


def boundary_options(name):
    """The ``--set`` keys wall model ``name`` takes (its factory's keyword arguments)."""
    try:
        factory, _ = BOUNDARIES[name]
    except KeyError:
        raise ParameterError(f"unknown boundary {name!r}; available: {', '.join(BOUNDARIES)}") from None
    return tuple(p.name for p in inspect.signature(factory).parameters.values()
                 if p.kind == inspect.Parameter.KEYWORD_ONLY)


def boundary_by_name(name, options=None):
    """Build the wall model called ``name``; ``options`` (dict) is consumed for the keys it takes."""
    options = {} if options is None else options
    known = boundary_options(name)
    factory, _ = BOUNDARIES[name]
    return factory(**{key: options.pop(key) for key in known if key in options})
