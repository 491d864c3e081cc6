"""The lid-driven cavity ([Liu2015] sec. 4.2; Ghia, Ghia & Shin 1982 for Re >= 100).

A square cavity of side L closed by no-slip walls; the top wall (the lid,
its whole row of wall particles including the corner columns) slides along
+x with speed U. Re = U L / nu. [Liu2015] runs Re = 1 with L = 1 mm, U = 1 mm/s,
dx = 2e-5 m (L/50), h = 1.2 dx; the defaults here are the seed's, with
Re = 100 and 1000 reached through ``reynolds`` (nu = U L / Re).

Two fluids (parameter ``fluid``):

* ``standard`` (default): laminar viscosity (Morris et al. 1997, [Liu2015]
  eq. 9), linear EOS, no artificial viscosity, symplectic integrator, no
  gravity; the density summed over fluid and wall particles (default,
  ``density=summation``, as [Adami2013]) or evolved by the continuity equation
  with delta-SPH (delta = 0.1; ``density=continuity``); ``kernel`` chooses the
  kernel ([Adami2013]: the quintic spline at h = dx);
* ``liu2015``: the seed's own fluid of sec. 2 (Tait EOS, laminar plus
  artificial viscosity alpha = 0.02, continuity density with delta-SPH and the
  Bonet-Lok gradient, leap-frog with the dt rule of eq. 18-20;
  :func:`seawall.fluid.presets.liu2015`), no background pressure unless asked
  for; ``dt`` fixes the step.

Both run with the transport velocity of [Adami2013] (p_b = rho0 c0^2,
:mod:`seawall.fluid.regularisation`) by default, chosen by the centreline
errors (the case's description, docs/validation-notes.md);
``--set transport_velocity=false`` switches it off, and
``--set transport_velocity=false density=continuity`` is the standard fluid's
scheme before issue 17 (no regularisation, delta-SPH, EOS background 0.05).

Speed of sound from Morris et al. (1997) sec. 2.4 with a 1 % density
variation: c0^2 = max(U^2, nu U / L) / 0.01, i.e. c0 = 10 U max(1, Re^-1/2).
A background pressure of ``background`` x rho0 c0^2 in the equation of state
(default 0.05 with the standard fluid's evolved density, else 0: [Adami2013]'s
scheme puts its background pressure into the transport velocity) keeps
the wall-corner suction from turning the pressure negative, where the
pairwise pressure force would pull particles into clumps (tensile
instability); with the symmetric pressure term a uniform background exerts
no net force on a regular lattice.

The reference solutions are steady. The slowest viscous mode decays as
exp(-2 pi^2 nu t / L^2), so 0.5 L^2 / nu leaves e^-10 of the start-up at
Re = 1; at Re >= 100 the flow settles within some 30 lid passages L / U.
:func:`default_t_end` is the smaller of the two.
"""

import numpy as np

from .. import probes, shapes
from ..boundary.base import WallSystem
from ..eos import Linear
from ..errors import ParameterError, require_positive
from ..fluid import FluidSystem, LaminarViscosity
from ..fluid.presets import liu2015
from ..integrators import Symplectic
from ..kernels import KERNELS, kernel_by_name
from ..sampling import FieldProbe, interpolate
from ..simulation import Simulation
from .base import Case, Parameter, density_and_diffusion, wall_layers


FLUIDS = ("standard", "liu2015")


def build_cavity(params, wall_model, threads):
    side = require_positive("side", params["side"])
    if params["dx"] is None:
        params["dx"] = side / 50.0
    dx = require_positive("dx", params["dx"])
    n = int(round(side / dx))
    if abs(n * dx - side) > 1e-9 * side or n < 8:
        raise ParameterError(f"side ({side:g} m) must be a whole number (>= 8) of particle spacings dx = {dx:g} m")
    lid = require_positive("lid_speed", params["lid_speed"])
    reynolds = require_positive("reynolds", params["reynolds"])
    nu = lid * side / reynolds
    rho0 = require_positive("rho0", params["rho0"])
    c0 = params["c0"] or 10.0 * lid * max(1.0, reynolds ** -0.5)
    params["c0"] = c0
    h_factor = require_positive("h_factor", params["h_factor"])
    h = h_factor * dx
    kind = params["fluid"]
    if kind not in FLUIDS:
        raise ParameterError(f"fluid must be one of {', '.join(FLUIDS)}, got {kind!r}")
    if params["density"] is None:
        # [Adami2013] sum the density; the liu2015 fluid has only its evolved one
        params["density"] = "summation" if kind == "standard" else "continuity"
    density, diffusion = density_and_diffusion(params, default_delta=0.1)
    if params["background"] is None:
        # the EOS background guards an evolved density against the corner suction (see the module docstring);
        # [Adami2013]'s scheme puts its background pressure in the transport velocity instead
        params["background"] = 0.05 if kind == "standard" and density == "continuity" else 0.0
    background = params["background"] * rho0 * c0 * c0
    block = shapes.rectangle((0.0, 0.0), (side, side), dx)
    if kind == "standard":
        if params["dt"]:
            raise ParameterError("dt fixes the step of the liu2015 fluid; the standard fluid takes cfl")
        kernel = kernel_by_name(params["kernel"])
        fluid = FluidSystem(block, rho0=rho0, eos=Linear(c0=c0, background_pressure=background),
                            viscosity=LaminarViscosity(nu=nu), density=density, density_diffusion=diffusion)
        integrator = Symplectic(cfl=params["cfl"])
    else:
        if params["kernel"] != "cubic" or density != "continuity":
            raise ParameterError(f"{'kernel' if params['kernel'] != 'cubic' else 'density'}: the liu2015 fluid "
                                 f"keeps its own kernel and continuity density ([Liu2015] sec. 2)")
        preset = liu2015(c0, alpha=params["alpha"], delta=params["delta"], nu=nu, h_factor=h_factor,
                         background_pressure=background, dt=params["dt"])
        kernel = preset.kernel
        fluid = preset.fluid(block, rho0=rho0)
        integrator = preset.integrator
    if params["layers"] is not None and params["layers"] < 1:
        raise ParameterError(f"layers must be >= 1, got {params['layers']}")
    layers = params["layers"] or wall_layers(kernel, h, dx)
    walls = shapes.tank((0.0, 0.0), (side, side), dx, layers=layers, open_top=False)
    is_lid = walls.positions[:, 1] > side   # the whole top row of wall particles, corner columns included
    model = wall_model()
    if model.layout != "layers":
        raise ParameterError("the cavity needs a layered wall model (dummy, ghost or DBC family)")
    if getattr(model, "slip", "noslip") != "noslip":
        raise ParameterError("the cavity needs a no-slip wall: use e.g. --boundary adami-noslip or liu2015-noslip "
                             "(or --set slip=noslip)")
    systems = [fluid, WallSystem(walls.subset(~is_lid), model=model, name="walls"),
               WallSystem(walls.subset(is_lid), model=wall_model(), velocity=(lid, 0.0), name="lid")]
    margin = (layers + 2) * dx
    sim = Simulation(systems, kernel=kernel, h=h, gravity=(0.0, 0.0), integrator=integrator,
                     threads=threads, domain=((-margin, -margin), (side + margin, side + margin)))
    sim.add(FieldProbe("u_centre", (0.5 * side, 0.5 * side), "u"), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "cavity", "side": side, "lid_speed": lid, "reynolds": reynolds, "nu": nu}
    return sim


def default_t_end(sim):
    """Time to a steady state: min(0.5 L^2 / nu, 30 L / U)."""
    ref = sim.reference
    return min(0.5 * ref["side"] ** 2 / ref["nu"], 30.0 * ref["side"] / ref["lid_speed"])


def centrelines(sim, s, s_horizontal=None):
    """u/U on the vertical centreline at y = s L and v/U on the horizontal one at x = s_horizontal L.

    ``s_horizontal`` defaults to ``s`` (Shepard interpolation, seawall.sampling).
    """
    ref = sim.reference
    side, lid = ref["side"], ref["lid_speed"]
    s = np.asarray(s, dtype=np.float64)
    sh = s if s_horizontal is None else np.asarray(s_horizontal, dtype=np.float64)
    vertical = np.stack([np.full_like(s, 0.5 * side), s * side], axis=1)
    horizontal = np.stack([sh * side, np.full_like(sh, 0.5 * side)], axis=1)
    u = interpolate(sim, vertical, ("u",))["u"] / lid
    v = interpolate(sim, horizontal, ("v",))["v"] / lid
    return u, v


CAVITY = Case(
    name="cavity",
    free_surface=False,
    default_boundary="adami-noslip",
    description="lid-driven cavity, L = 1 mm, lid 1 mm/s, Re = 1 ([Liu2015] sec. 4.2; --set reynolds=100/1000 for "
                "Ghia; --set fluid=liu2015 for the seed's fluid); needs no-slip walls, adami-noslip by default; "
                "[Adami2013]'s scheme by default: the transport velocity (p_b = rho0 c0^2) with, for the standard "
                "fluid, the density summed over fluid and wall particles and no EOS background (the liu2015 fluid "
                "keeps its continuity density and delta-SPH). Chosen by the worst centreline errors (against Ghia et al. "
                "at Re >= 100; docs/validation-notes.md): at Re = 100, L/50 2.5 % / 2.6 % of U (u / v; entries "
                "cavity-re100, cavity-re100-tvf) "
                "against 16 % / 12 % without regularisation (continuity density, delta-SPH, EOS background "
                "0.05 rho0 c0^2: --set transport_velocity=false density=continuity, entries cavity-re*-plain); at "
                "Re = 1000 13.9 % / 16.1 % at L/50 (entry cavity-re1000) against 42 % / 47 %, and 5.9 % / 5.9 % at "
                "L/100, t = 30 s (entry cavity-re1000-tvf, target 8 %); at Re = 1, L/50 4.3 % / 2.4 % against 6.4 % / 2.7 % (entries cavity-re1, "
                "cavity-re1-plain); with the seed's fluid at Re = 1 0.9-1.8 % at t = 0.5 s against 10-16 %",
    builder=build_cavity,
    parameters={
        "dx": Parameter(None, "particle spacing [m] (default side/50, the seed's 2e-5 m)"),
        "side": Parameter(1e-3, "side L of the square cavity [m]"),
        "lid_speed": Parameter(1e-3, "lid speed U [m/s]"),
        "reynolds": Parameter(1.0, "Reynolds number U L / nu"),
        "h_factor": Parameter(1.2, "smoothing length / dx ([Liu2015]: 1.2)"),
        "rho0": Parameter(1000.0, "reference density [kg/m^3]"),
        "c0": Parameter(None, "speed of sound [m/s] (default 10 U max(1, Re^-1/2))"),
        "fluid": Parameter("standard", "fluid scheme: standard (linear EOS, symplectic) or liu2015 ([Liu2015] sec. 2)",
                           str),
        "background": Parameter(None, "EOS background pressure / (rho0 c0^2) (default 0.05 with the standard fluid's "
                                      "density=continuity, else 0)"),
        "delta": Parameter(None, "delta-SPH diffusion coefficient (0 = off; default 0.1 with density=continuity, "
                                 "0 with summation)"),
        "density": Parameter(None, "density of the standard fluid: summation (default; sum_j m_j W_ij over fluid "
                             "and wall particles, as [Adami2013]) or continuity (evolved); the liu2015 fluid keeps "
                             "continuity", str),
        "kernel": Parameter("cubic", "kernel of the standard fluid: " + ", ".join(KERNELS)
                            + " ([Adami2013]: quintic with h = dx, --set h_factor=1)", str),
        "alpha": Parameter(0.02, "artificial viscosity alpha of the liu2015 fluid ([Liu2015] eq. 11; 0 = off)"),
        "cfl": Parameter(0.2, "CFL number of the standard fluid (the viscous limit 0.125 h^2/nu applies too)"),
        "dt": Parameter(0.0, "fixed time step [s] of the liu2015 fluid (0 = its adaptive rule, eq. 18-20)"),
        "layers": Parameter(None, "wall layers (default: enough to fill the kernel support; [Liu2015] uses 4)",
                            int),
    },
    regularisation={"transport_velocity": True},
    t_end=0.5, probe_every=0.01, output_every=0.05)
