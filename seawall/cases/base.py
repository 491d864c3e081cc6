"""What a named case is: parameters with defaults and a build function.

One definition of each case serves the CLI, the tests, the benchmarks and
the validation scripts. ``build(boundary=..., dx=..., **params)`` returns a
ready :class:`~seawall.Simulation` carrying its probes and metadata.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any, Callable

from ..boundary.registry import boundary_by_name, boundary_options
from ..errors import ParameterError
from ..runner import Runner

GRAVITY = 9.81


@dataclass
class Parameter:
    """A case parameter: its default, a one-line help text, its type and its unit.

    ``unit`` may be left empty when the help text names the unit in square
    brackets ("column height [m]"); :attr:`units` returns either.
    """

    default: object
    doc: str
    kind: type = float
    unit: str = ""

    @property
    def units(self):
        """The unit: ``unit`` if given, else the first ``[...]`` of the help text ("" if none)."""
        if self.unit:
            return self.unit
        for found in re.finditer(r"\[([^\]]+)\]", self.doc):
            if not re.fullmatch(r"[A-Z][A-Za-z]+\d{4}[a-z]?", found.group(1)):   # a citation key, not a unit
                return found.group(1)
        return ""


@dataclass
class Case:
    """A named, parametrised simulation set-up.

    ``builder(params, wall_model_factory)`` receives every parameter
    resolved (defaults filled in, types converted) and a function that
    returns a fresh wall model for the chosen boundary.
    """

    name: str
    description: str
    builder: object
    parameters: dict = field(default_factory=dict)
    t_end: float = 1.0
    probe_every: float = 1e-3
    output_every: float = 0.02
    dimension: int = 2
    #: wall model used when none is named (cases whose physics needs no slip default to a no-slip model)
    default_boundary: str = "adami"
    #: a case read from a file: {"path": ..., "sha256": ...} (None for the built-in cases)
    source: dict = None
    #: whether the fluid has a free surface (the transport velocity then needs its free-surface correction)
    free_surface: bool = True
    #: the case's default particle regularisation (--set keys of :data:`REGULARISATION_KEYS`)
    regularisation: dict = field(default_factory=dict)
    #: the case's default pressure model (--set keys of :data:`PRESSURE_KEYS`; empty: the equation of state)
    pressure: dict = field(default_factory=dict)
    #: the case's default damage budget (--set keys of :data:`GUARD_KEYS`; empty: Simulation's 0.001 in 0.05 s)
    guards: dict = field(default_factory=dict)

    def _regularisation(self, sim, given):
        return _case_regularisation(self, sim, given)

    def resolve(self, overrides):
        params = {}
        unknown = set(overrides) - set(self.parameters)
        if unknown:
            raise ParameterError(
                f"case {self.name!r} has no parameter {sorted(unknown)[0]!r}; "
                f"its parameters: {', '.join(sorted(self.parameters))}")
        for key, spec in self.parameters.items():
            value = overrides.get(key, spec.default)
            if value is None:
                params[key] = None
                continue
            try:
                if spec.kind is bool and isinstance(value, str):
                    low = value.strip().lower()
                    if low not in ("1", "0", "true", "false", "yes", "no", "on", "off"):
                        raise ValueError(value)
                    value = low in ("1", "true", "yes", "on")
                else:
                    value = spec.kind(value)
            except (TypeError, ValueError):
                raise ParameterError(f"parameter {key} of case {self.name!r} must be {spec.kind.__name__}, got {value!r}") from None
            if spec.kind is float and not math.isfinite(value):
                raise ParameterError(f"parameter {key} must be finite, got {value!r}")
            params[key] = value
        _check_ranges(self.name, params)
        return params

    def build(self, *, boundary: str | Callable[..., Any] | None = None, threads: int | None = None,
              **overrides: Any) -> Runner:
        """Build the simulation with wall model ``boundary`` (a name or a WallModel factory; default
        the case's ``default_boundary``)."""
        if boundary is None:
            boundary = self.default_boundary
        # a --set key belongs to the wall model if its registry factory takes it (boundary_options)
        model_keys = boundary_options(boundary) if isinstance(boundary, str) else ()
        model_options = {k: overrides.pop(k) for k in list(overrides) if k in model_keys}
        adhesion = overrides.pop(ADHESION_KEY, None)
        given_regularisation = {k: overrides.pop(k) for k in REGULARISATION_KEYS if k in overrides}
        given_pressure = {k: overrides.pop(k) for k in PRESSURE_KEYS if k in overrides}
        given_guards = {k: overrides.pop(k) for k in GUARD_KEYS if k in overrides}
        check_guard_settings(given_guards)   # before the build: a bad value costs no set-up
        given_options = dict(sorted({**model_options, **({ADHESION_KEY: adhesion} if adhesion is not None else {})}
                                    .items()))
        params = self.resolve(overrides)

        def wall_model():
            opts = dict(model_options)
            model = boundary_by_name(boundary, opts) if isinstance(boundary, str) else boundary()
            if opts:
                raise ParameterError(f"boundary {boundary!r} does not take option {sorted(opts)[0]!r}")
            return model

        if isinstance(boundary, str):
            wall_model()   # the name and options are checked even by cases without walls
        sim = self.builder(params, wall_model, threads)
        regularisation = self._regularisation(sim, given_regularisation)
        if regularisation is not None:
            params.update(regularisation)
        pressure = _case_pressure(self, sim, given_pressure)
        if pressure is not None:
            params.update(pressure)
        _case_guards(self, sim, given_guards)
        if adhesion is not None:
            try:
                beta = float(adhesion)
            except (TypeError, ValueError):
                raise ParameterError(f"adhesion_coefficient must be a number, got {adhesion!r}") from None
            if not beta >= 0.0:
                raise ParameterError(f"adhesion_coefficient must be >= 0, got {adhesion!r}")
            for wall in getattr(sim, "walls", []):
                wall.adhesion_coefficient = beta
        sim.metadata.update({"case": self.name, "boundary": boundary if isinstance(boundary, str) else "custom",
                             "parameters": params, "boundary_options": given_options})
        if self.source is not None:
            # the path says where it came from; the hash is part of the set-up a restart must match
            sim.metadata["case_file"] = self.source["path"]
            sim.metadata["case_sha256"] = self.source["sha256"]
        return sim


#: case parameters that, wherever a case has them, must be > 0 when given (None = the case's default)
POSITIVE_IF_GIVEN = ("c0",)
#: ... must be >= 0 (0 switches the term off; a negative value is not "off", it is wrong)
NON_NEGATIVE = ("alpha", "delta", "nu", "seed")
#: ... must be >= 1
AT_LEAST_ONE = ("layers",)


#: the --set keys of the fluid's particle regularisation (seawall.fluid.regularisation), any SPH case:
#: shifting = none | sun2017 | lind2012; transport_velocity = true | false; tvf_background = p_b / (rho0 c0^2);
#: tvf_free_surface = the transport velocity's free-surface correction (true | false)
REGULARISATION_KEYS = ("shifting", "transport_velocity", "tvf_background", "tvf_free_surface")


#: the --set keys of the fluid's pressure model, any SPH case: pressure_model = eos | edac ([Ramachandran2019],
#: seawall.fluid.edac); edac_alpha = alpha of nu_edac = alpha h c0 / 8 (0.5). Not "pressure": lust takes
#: that key for its wall pressure
PRESSURE_KEYS = ("pressure_model", "edac_alpha")


#: the --set keys of the damage budget, any SPH case: the run stops as unstable when the particles removed as
#: wall or unstable within the last unstable_window seconds exceed unstable_fraction of the fluid (seawall.health).
#: Not case parameters: a budget only decides when a run stops, not how its particles move, so it is recorded in
#: summary.json's damage_budget and, like the end time, may change on a restart
GUARD_KEYS = ("unstable_fraction", "unstable_window")


def check_guard_settings(given):
    """Refuse a bad damage-budget value (:data:`GUARD_KEYS` -> value or text) in one line naming its key."""
    from ..health import parse_guard_settings

    for key, value in given.items():
        if isinstance(value, bool):    # float(True) is 1.0: a boolean is a slip, not a number
            raise ParameterError(f"{key} must be a number, got {value!r}")
        if key == "unstable_fraction":
            parse_guard_settings(None, value, 1.0)
        else:
            parse_guard_settings(None, 0.5, value)


def _case_guards(case, sim, given):
    """Apply the case's damage budget overridden by ``given`` (--set keys) to ``sim``."""
    if not hasattr(sim, "unstable_fraction"):
        if given:
            raise ParameterError(f"case {case.name!r} has no SPH fluid: {sorted(given)[0]} does not apply")
        return
    from ..health import parse_guard_settings

    opts = {**case.guards, **given}
    if opts:
        _, sim.unstable_fraction, sim.unstable_window = parse_guard_settings(
            None, opts.get("unstable_fraction", sim.unstable_fraction),
            opts.get("unstable_window", sim.unstable_window))


def _no_fluid(case, sim, setter, given):
    """True when ``sim`` has no SPH fluid (no ``setter``); a fluid key given to such a case stops in one line."""
    if hasattr(sim, setter):
        return False
    if given:
        raise ParameterError(f"case {case.name!r} has no SPH fluid: {sorted(given)[0]} does not apply")
    return True


def _finite_option(opts, key, default, positive):
    """``opts[key]`` (else ``default``) as a finite float, > 0 if ``positive`` else >= 0; one line otherwise."""
    try:
        value = float(opts.get(key, default))
    except (TypeError, ValueError):
        raise ParameterError(f"{key} must be a number, got {opts[key]!r}") from None
    if not (math.isfinite(value) and (value > 0.0 if positive else value >= 0.0)):
        raise ParameterError(f"{key} must be a finite number {'>' if positive else '>='} 0, got {opts[key]!r}")
    return value


def _case_pressure(case, sim, given):
    """Apply the case's default pressure model overridden by ``given`` (--set keys) to ``sim``; return the
    resolved keys (for the parameters in summary.json and checkpoints), or None for a run without a fluid."""
    from ..fluid.edac import EDAC, PRESSURE_MODELS

    if _no_fluid(case, sim, "set_pressure_model", given):
        return None
    opts = {**case.pressure, **given}
    name = str(opts.get("pressure_model", "eos")).strip().lower()
    if name not in PRESSURE_MODELS:
        raise ParameterError(f"pressure_model must be one of {', '.join(PRESSURE_MODELS)}; "
                             f"got {opts['pressure_model']!r}")
    if name != "edac":
        if "edac_alpha" in given:
            raise ParameterError("edac_alpha needs --set pressure_model=edac")
        if sim.fluid.edac is not None:     # a builder that chose EDAC itself
            return {"pressure_model": "edac", "edac_alpha": sim.fluid.edac.alpha}
        return {"pressure_model": "eos", "edac_alpha": None}
    alpha = _finite_option(opts, "edac_alpha", 0.5, positive=True)
    sim.set_pressure_model(EDAC(alpha=alpha))
    return {"pressure_model": "edac", "edac_alpha": alpha}


def _bool_option(key, value):
    if isinstance(value, bool):
        return value
    low = str(value).strip().lower()
    if low not in ("1", "0", "true", "false", "yes", "no", "on", "off"):
        raise ParameterError(f"{key} must be true or false, got {value!r}")
    return low in ("1", "true", "yes", "on")


def _case_regularisation(case, sim, given):
    """Apply the case's default regularisation overridden by ``given`` (--set keys) to ``sim``; return the
    resolved keys (for the parameters in summary.json and checkpoints), or None for a run without a fluid."""
    from ..fluid.regularisation import ParticleShifting, SHIFTING_KINDS, TransportVelocity

    if _no_fluid(case, sim, "set_regularisation", given):
        return None
    opts = {**case.regularisation, **given}
    fluid = sim.fluid
    if not opts:    # what the builder gave the fluid
        tv = fluid.transport_velocity
        return {"shifting": fluid.shifting.kind if fluid.shifting is not None else "none",
                "transport_velocity": tv is not None,
                "tvf_background": (tv.background_factor if tv.background_pressure is None else None) if tv else None,
                "tvf_free_surface": tv.free_surface if tv else None}
    shifting = str(opts.get("shifting", "none")).strip().lower()
    if shifting not in SHIFTING_KINDS:
        raise ParameterError(f"shifting must be one of {', '.join(SHIFTING_KINDS)}; got {opts['shifting']!r}")
    tvf = _bool_option("transport_velocity", opts.get("transport_velocity", False))
    factor = _finite_option(opts, "tvf_background", 1.0, positive=False)
    tvf_surface = _bool_option("tvf_free_surface", opts.get("tvf_free_surface", False))
    if not tvf and ("tvf_background" in given or "tvf_free_surface" in given):
        raise ParameterError(f"{'tvf_background' if 'tvf_background' in given else 'tvf_free_surface'} needs "
                             f"--set transport_velocity=true")
    if tvf and case.free_surface and not tvf_surface:
        raise ParameterError(f"transport_velocity on case {case.name!r} (a free surface) needs its free-surface "
                             f"correction, --set tvf_free_surface=true: without it the background pressure pulls "
                             f"the surface particles into the fluid")
    sim.set_regularisation(
        shifting=ParticleShifting(shifting) if shifting != "none" else None,
        transport_velocity=TransportVelocity(background_factor=factor, free_surface=tvf_surface) if tvf else None)
    return {"shifting": shifting, "transport_velocity": tvf, "tvf_background": factor if tvf else None,
            "tvf_free_surface": tvf_surface if tvf else None}


def _check_ranges(case_name, params):
    """Refuse impossible values instead of letting a builder replace or ignore them."""
    for key in POSITIVE_IF_GIVEN:
        if params.get(key) is not None and not params[key] > 0:
            raise ParameterError(f"parameter {key} of case {case_name!r} must be > 0 (leave it out for the "
                                 f"case's default), got {params[key]!r}")
    for key in NON_NEGATIVE:
        if params.get(key) is not None and not params[key] >= 0:
            raise ParameterError(f"parameter {key} of case {case_name!r} must be >= 0, got {params[key]!r}")
    for key in AT_LEAST_ONE:
        if params.get(key) is not None and not params[key] >= 1:
            raise ParameterError(f"parameter {key} of case {case_name!r} must be at least 1, got {params[key]!r}")
    lo, hi = params.get("rho_min"), params.get("rho_max")
    if lo is not None and hi is not None and not 0 < lo < hi:
        raise ParameterError(f"parameters rho_min and rho_max of case {case_name!r} must satisfy "
                             f"0 < rho_min < rho_max, got {lo!r} and {hi!r}")


#: the --set key of the walls' adhesion (a WallSystem option, any model)
ADHESION_KEY = "adhesion_coefficient"


def require_noslip(model, case, hint=""):
    """Cases whose physics is the no-slip condition (channel flows) refuse free-slip walls."""
    if getattr(model, "slip", None) == "free":
        raise ParameterError(f"case {case!r} needs no-slip walls: use --boundary adami-noslip "
                             f"(or a ghost model with --set slip=noslip){hint}")


def tank_wall(model, lo, hi, dx, kernel, h, open_top=True):
    """The tank's wall particles in the layout the wall model needs.

    Layered walls (dummy, ghost, DBC) continue the fluid lattice in
    ceil(support / dx) layers; repulsive walls (``layout = "surface"``)
    are one row on the surface at spacing dx / beta.
    """
    from .. import shapes

    if model.layout == "surface":
        return shapes.tank_surface(lo, hi, dx / model.beta, open_top=open_top)
    return shapes.tank(lo, hi, dx, layers=wall_layers(kernel, h, dx), open_top=open_top)


def outline_wall(model, points, dx, kernel, h, *, fluid="outside", origin=None, layers=None, inside=None,
                 label="outline"):
    """A 2D structure's wall particles (:func:`seawall.polygons.polygon_wall`) in the layout the wall
    model needs: ``layers`` (default ceil(support / dx), :func:`wall_layers`; fewer is refused, the
    kernel would reach past the wall) layers of the lattice ``origin + (i + 1/2) dx``, or one surface
    row at dx / beta (repulsive models). ``inside``: the (lo, hi) box of a tank's interior; particles
    outside it are dropped, the tank's own walls being there already (a foot buried in the floor), and
    edges on its faces meet the tank's walls, so they are no wall surface (``junction`` of
    :func:`seawall.polygons.polygon_wall`).
    """
    import numpy as np

    from .. import polygons

    needed = wall_layers(kernel, h, dx)
    if layers is None:
        layers = needed
    elif isinstance(layers, bool) or not isinstance(layers, (int, np.integer)) or layers < needed:
        raise ParameterError(f"{label}: layers must be a whole number >= {needed} (the kernel support at "
                             f"h = {h / dx:g} dx fills {needed} layers), got {layers!r}")
    if model.layout == "surface":
        shape = polygons.polygon_wall(points, dx, fluid=fluid, origin=origin, layout="surface", beta=model.beta,
                                      junction=inside, label=label)
    else:
        shape = polygons.polygon_wall(points, dx, int(layers), fluid=fluid, origin=origin, junction=inside,
                                      label=label)
    if inside is not None:
        lo, hi = (np.asarray(c, dtype=np.float64) for c in inside)
        tol = 1e-9 * dx
        keep = np.all((shape.positions > lo - tol) & (shape.positions < hi + tol), axis=1)
        if not keep.any():
            raise ParameterError(f"{label}: no wall particle lies inside the tank {lo.tolist()} - {hi.tolist()}")
        shape = shape.subset(keep)
    return shape


def wall_layers(kernel, h, dx):
    """Number of wall layers that fill the kernel support: ceil(support / dx)."""
    return max(1, int(math.ceil(kernel.support(h) / dx - 1e-9)))


def density_and_diffusion(params, default_delta):
    """The fluid's density mode and delta-SPH term from the case parameters ``density`` and ``delta``.

    ``density`` is ``continuity`` (evolved) or ``summation`` (rho_i = sum_j m_j W_ij, as [Adami2013]).
    ``delta`` left out (None) becomes ``default_delta`` with an evolved density and 0 with a summed one,
    which is not evolved and so has nothing to diffuse; delta > 0 with a summed density stops in one line.
    The resolved delta is written back into ``params`` (summary.json records what ran). Returns
    ``(density, DeltaSPH or None)``.
    """
    from ..fluid import DeltaSPH
    from ..fluid.system import DENSITY_MODES

    density = params["density"]
    if density not in DENSITY_MODES:
        raise ParameterError(f"density must be one of {', '.join(DENSITY_MODES)}, got {density!r}")
    if params["delta"] is None:
        params["delta"] = default_delta if density == "continuity" else 0.0
    if density == "summation" and params["delta"] > 0:
        raise ParameterError("delta: delta-SPH needs density=continuity (a summed density is not evolved)")
    return density, (DeltaSPH(delta=params["delta"]) if params["delta"] > 0 else None)
