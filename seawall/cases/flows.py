"""Viscous channel flows and fluid-only flows with exact solutions.

* ``poiseuille`` / ``couette`` -- start-up flow between parallel plates, periodic
  along x (Morris, Fox & Zhu 1997, sec. 4.1-4.2; parameters of their Fig. 2-3:
  L = 1 mm, nu = 1e-6 m^2/s, rho0 = 1000 kg/m^3, F = 2e-4 m/s^2, Re = 0.0125;
  Couette with U = 2.5e-5 m/s). The walls are the case's wall model: use a
  no-slip one, e.g. ``--boundary adami-noslip`` (with free slip there is no
  shear at the wall and the flow is a plug). Laminar viscosity (Morris form,
  [Liu2015] eq. 9), linear EOS, no artificial viscosity or density diffusion.
  Speed of sound from Morris et al. (1997) sec. 2.4: c0^2 = max(U^2, nu U / L,
  F L) / delta with a density variation delta = 1 %.
* ``taylor-green`` -- the 2D Taylor-Green vortex on the periodic unit square,
  fluid only (no walls), U = 1, Re = U L / nu = 100, rho0 = 1; c0 = 10 U,
  linear EOS with background pressure rho0 U^2 (twice the largest suction of
  the exact pressure, so that no particle pressure is negative), laminar
  viscosity, delta-SPH (delta = 0.1), particle shifting ``lind2012`` by default
  (seawall.fluid.regularisation; chosen by the validation, docs/validation-notes.md).
  ``density=summation`` sums the density instead of evolving it (delta-SPH then
  off) and ``kernel`` chooses the kernel, as in the cavity: [Adami2013]'s set-up
  for the transport velocity is a summed density with no background pressure in
  the equation of state (``background=0``).
* ``elliptical-drop`` -- Monaghan (1994) sec. 5: an inviscid circular patch of
  radius 1 with u = -100 x, v = 100 y, no gravity, free surface all round;
  rho0 = 1, Tait (gamma 7) with c0 = 1400, artificial viscosity alpha = 0.1,
  XSPH epsilon = 0.5 (Monaghan 1994's settings as carried by PySPH's example,
  see data/elliptic_and_oscillating_drop_computed/README.txt). The initial
  pressure is the exact one, p = rho A0^2 (1 - x^2 - y^2) / 2
  (``seawall.analytic.elliptical_drop_pressure``; ``initial=zero`` starts from
  p = 0, which launches a pressure wave). Particle shifting ``sun2017`` by
  default (chosen by the validation, docs/validation-notes.md): without it the
  particles keep the Lagrangian lattice, stretched 1 : 3.8 by t = 7.6 ms, which
  the kernel at h = 1.3 dx no longer samples consistently.
"""

import math

import numpy as np

from .. import probes, shapes
from ..analytic import elliptical_drop_pressure, taylor_green_2d
from ..boundary.base import WallSystem
from ..eos import Linear, Tait
from ..errors import ParameterError, require_positive
from ..fluid import ArtificialViscosity, DeltaSPH, FluidSystem, LaminarViscosity
from ..integrators import Symplectic
from ..sampling import FieldProbe
from ..kernels import KERNELS, CubicSpline, kernel_by_name
from ..simulation import Simulation
from .base import Case, Parameter, density_and_diffusion, require_noslip, wall_layers


def channel_walls(length, width, dx, layers):
    """Wall particles below y = 0 and above y = width, x in [0, length) (periodic), normals into the fluid.

    Returns the (bottom, top) shapes; the lattice continues the fluid's
    (particles at (i + 1/2) dx), so the surfaces lie half a spacing from the
    first fluid and wall rows.
    """
    nx = int(round(length / dx))
    xs = (np.arange(nx) + 0.5) * dx
    out = []
    for side in (-1.0, 1.0):
        pos, nrm, srf = [], [], []
        for layer in range(layers):
            y = -(layer + 0.5) * dx if side < 0 else width + (layer + 0.5) * dx
            ys = np.full(nx, y)
            pos.append(np.stack([xs, ys], axis=1))
            nrm.append(np.tile([0.0, -side], (nx, 1)))
            srf.append(np.stack([xs, np.full(nx, 0.0 if side < 0 else width)], axis=1))
        out.append(shapes.Shape(np.concatenate(pos), dx, normals=np.concatenate(nrm),
                                surface_points=np.concatenate(srf)))
    return out


def _channel(params, wall_model, threads, *, force, wall_speed):
    width = require_positive("width", params["width"])
    if params["dx"] is None:
        params["dx"] = width / 40.0
    dx = require_positive("dx", params["dx"])
    ny = int(round(width / dx))
    if abs(ny * dx - width) > 1e-9 * width or ny < 4:
        raise ParameterError(f"width ({width:g} m) must be a whole number (>= 4) of particle spacings dx = {dx:g} m")
    nx = max(int(params["nx"]), 1)
    h = require_positive("h", params["h_factor"] * dx)
    kernel = CubicSpline()
    length = nx * dx
    if length < 2.5 * kernel.support(h) * (1 + 1e-9):
        raise ParameterError(f"nx = {nx} gives a channel {length:g} m long; the periodic axis needs at least "
                             f"2.5 kernel supports ({2.5 * kernel.support(h):g} m): increase nx")
    nu = require_positive("nu", params["nu"])
    rho0 = require_positive("rho0", params["rho0"])
    speed = max(force * width * width / (8.0 * nu), abs(wall_speed))
    c0 = params["c0"] or math.sqrt(max(speed * speed, nu * speed / width, force * width) / 0.01)
    params["c0"] = c0
    fluid = FluidSystem(shapes.rectangle((0.0, 0.0), (length, width), dx), rho0=rho0, eos=Linear(c0=c0),
                        viscosity=LaminarViscosity(nu=nu))
    layers = wall_layers(kernel, h, dx)
    bottom, top = channel_walls(length, width, dx, layers)
    walls = [WallSystem(bottom, model=wall_model(), name="bottom"),
             WallSystem(top, model=wall_model(), velocity=(wall_speed, 0.0), name="top")]
    if not params["free_slip"]:
        for wall in walls:
            require_noslip(wall.model, "couette" if wall_speed else "poiseuille",
                           "; --set free_slip=true runs the plug flow of free-slip walls on purpose")
    margin = (layers + 2) * dx
    sim = Simulation([fluid, *walls], kernel=kernel, h=h, gravity=(force, 0.0),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads,
                     domain=((0.0, -margin), (length, width + margin)), periodic=(True, False))
    sim.add(FieldProbe("u_centre", (0.5 * length, 0.5 * width), "u"),
            FieldProbe("u_quarter", (0.5 * length, 0.25 * width), "u"),
            probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "channel", "width": width, "nu": nu, "force": force, "wall_speed": wall_speed}
    return sim


def build_poiseuille(params, wall_model, threads):
    """Start-up Poiseuille flow driven by the body force ``force`` between fixed plates."""
    return _channel(params, wall_model, threads, force=require_positive("force", params["force"]), wall_speed=0.0)


def build_couette(params, wall_model, threads):
    """Start-up Couette flow: the upper plate moves with ``wall_speed`` from t = 0."""
    return _channel(params, wall_model, threads, force=0.0,
                    wall_speed=require_positive("wall_speed", params["wall_speed"]))


PLATE_FLOW_PARAMETERS = {
    "dx": Parameter(None, "particle spacing [m] (default width/40)"),
    "h_factor": Parameter(1.3, "smoothing length h / dx"),
    "width": Parameter(1e-3, "distance L between the plates [m]"),
    "nx": Parameter(10, "particles along the periodic channel axis x", int),
    "nu": Parameter(1e-6, "kinematic viscosity [m^2/s]"),
    "rho0": Parameter(1000.0, "reference density [kg/m^3]"),
    "c0": Parameter(None, "speed of sound [m/s] (default: Morris et al. 1997 sec. 2.4 with 1 % density variation)"),
    "cfl": Parameter(0.2, "CFL number (the viscous limit 0.125 h^2/nu applies too)"),
    "free_slip": Parameter(False, "accept free-slip walls (the flow is then a plug, not the analytic profile)",
                           bool),
}

POISEUILLE = Case(
    name="poiseuille",
    free_surface=False,
    default_boundary="adami-noslip",
    description="start-up Poiseuille flow between plates 1 mm apart, periodic in x, body force "
                "(Morris et al. 1997); no-slip walls, adami-noslip by default",
    builder=build_poiseuille,
    parameters={**PLATE_FLOW_PARAMETERS, "force": Parameter(2e-4, "body force per unit mass along x [m/s^2]")},
    t_end=1.0, probe_every=0.005, output_every=0.05)

COUETTE = Case(
    name="couette",
    free_surface=False,
    default_boundary="adami-noslip",
    description="start-up Couette flow between plates 1 mm apart, upper plate moving, periodic in x "
                "(Morris et al. 1997); no-slip walls, adami-noslip by default",
    builder=build_couette,
    parameters={**PLATE_FLOW_PARAMETERS, "wall_speed": Parameter(2.5e-5, "speed U of the upper plate [m/s]")},
    t_end=1.0, probe_every=0.005, output_every=0.05)


# ---------------------------------------------------------------- Taylor-Green
def build_taylor_green(params, wall_model, threads):
    """2D Taylor-Green vortex on the periodic unit square (no walls; the boundary choice is unused)."""
    n = int(params["n"])
    if n < 8:
        raise ParameterError(f"n must be at least 8 particles per side, got {n}")
    dx = 1.0 / n
    h = require_positive("h_factor", params["h_factor"]) * dx
    kernel = kernel_by_name(params["kernel"])
    density, diffusion = density_and_diffusion(params, default_delta=0.1)
    U = require_positive("U", params["U"])
    Re = require_positive("Re", params["Re"])
    rho0 = 1.0
    nu = U / Re
    c0 = params["c0"] or 10.0 * U
    params["c0"] = c0
    block = shapes.rectangle((0.0, 0.0), (1.0, 1.0), dx)
    x = block.positions
    u, v, p = taylor_green_2d(x[:, 0], x[:, 1], 0.0, U=U, Re=Re, rho=rho0)
    p_b = params["background"] * rho0 * U * U
    # a summed density is read from the lattice at every evaluation, so it starts from p = p_b, not from the
    # exact pressure that an evolved density is given here
    fluid = FluidSystem(block, rho0=rho0, eos=Linear(c0=c0, background_pressure=p_b),
                        viscosity=LaminarViscosity(nu=nu), density=density, density_diffusion=diffusion,
                        velocity=np.stack([u, v], axis=1), pressure=p)
    sim = Simulation([fluid], kernel=kernel, h=h, gravity=(0.0, 0.0),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads,
                     domain=((0.0, 0.0), (1.0, 1.0)), periodic=(True, True))
    sim.add(MaxSpeed("u_max"), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "taylor-green", "U": U, "Re": Re, "rho0": rho0}
    return sim


class MaxSpeed(probes.Probe):
    """Largest particle speed |v| [m/s]."""

    def sample(self, sim):
        v = sim.fluid.particles["v"]
        return float(np.sqrt((v * v).sum(axis=1).max())) if v.shape[0] else float("nan")


TAYLOR_GREEN = Case(
    name="taylor-green",
    free_surface=False,
    # the scheme chosen by the validation (docs/validation-notes.md): without shifting the lattice tears at the
    # hyperbolic points and E_kin is -82 % at t = 0.5 s; lind2012 kept it within 0.7 %, sun2017 within 1.3 %
    regularisation={"shifting": "lind2012"},
    description="2D Taylor-Green vortex, periodic unit square, Re = 100, fluid only (no walls); particle shifting "
                "of Lind et al. (2012) by default (--set shifting=none for the plain scheme); the transport velocity "
                "on [Adami2013]'s set-up (--set transport_velocity=true shifting=none density=summation "
                "background=0) was -27 % of the exact kinetic energy at t = 0.5 s at 100 x 100, -60 % at 50 x 50 "
                "(docs/validation-notes.md)",
    builder=build_taylor_green,
    parameters={"n": Parameter(50, "particles per side of the unit square", int),
                "h_factor": Parameter(1.3, "smoothing length h / dx"),
                "U": Parameter(1.0, "velocity amplitude [m/s]"),
                "Re": Parameter(100.0, "Reynolds number U L / nu (L = 1 m)"),
                "c0": Parameter(None, "speed of sound [m/s] (default 10 U)"),
                "background": Parameter(1.0, "background pressure / (rho0 U^2) in the equation of state"),
                "density": Parameter("continuity", "density: continuity (evolved) or summation (sum_j m_j W_ij, "
                                     "as [Adami2013])", str),
                "delta": Parameter(None, "delta-SPH coefficient (0 = off; default 0.1 with density=continuity, "
                                         "0 with summation)"),
                "kernel": Parameter("cubic", "kernel: " + ", ".join(KERNELS) + " (with h_factor)", str),
                "cfl": Parameter(0.2, "CFL number")},
    t_end=2.0, probe_every=0.01, output_every=0.1)


# ---------------------------------------------------------------- elliptical drop
class SemiAxis(probes.Probe):
    """Half-extent of the fluid along ``axis`` plus dx/2: max |x_axis - centre| + dx / 2 [m]."""

    def __init__(self, name, axis):
        super().__init__(name)
        self.axis = int(axis)

    def sample(self, sim):
        x = sim.fluid.particles["x"]
        if x.shape[0] == 0:
            return float("nan")
        return float(np.abs(x[:, self.axis]).max() + 0.5 * sim.fluid.spacing)


class MomentSemiAxis(probes.Probe):
    """Semi-axis along ``axis`` of the uniform ellipse with the fluid's second moment: 2 sqrt(<x_axis^2>) [m].

    For a uniform elliptical patch centred at the origin with semi-axis s along
    an axis, the mass-weighted mean of x^2 is s^2 / 4; this measure uses every
    particle rather than the outermost one.
    """

    def __init__(self, name, axis):
        super().__init__(name)
        self.axis = int(axis)

    def sample(self, sim):
        fp = sim.fluid.particles
        if fp.n == 0:
            return float("nan")
        m = fp["m"]
        c = fp["x"][:, self.axis]
        mean = float(np.sum(m * c) / np.sum(m))
        return float(2.0 * np.sqrt(np.sum(m * (c - mean) ** 2) / np.sum(m)))


def build_elliptical_drop(params, wall_model, threads):
    """Monaghan (1994) elliptical drop (no walls; the boundary choice is unused)."""
    dx = require_positive("dx", params["dx"] if params["dx"] is not None else 0.025)
    params["dx"] = dx
    h = require_positive("h", params["h_factor"] * dx)
    A0 = require_positive("A0", params["A0"])
    c0 = require_positive("c0", params["c0"])
    if params["initial"] not in ("analytic", "zero"):
        raise ParameterError(f"initial must be 'analytic' or 'zero', got {params['initial']!r}")
    disc = shapes.circle((0.0, 0.0), 1.0, dx)
    x = disc.positions
    velocity = np.stack([-A0 * x[:, 0], A0 * x[:, 1]], axis=1)
    pressure = None
    if params["initial"] == "analytic":
        # the exact field at t = 0 (a = 1, dA/dt = 0); a zero start is not the flow the ODE describes
        pressure = elliptical_drop_pressure(x[:, 0], x[:, 1], A=A0, a=1.0, dAdt=0.0, rho=1.0)
    alpha = params["alpha"]
    delta = params["delta"]
    fluid = FluidSystem(disc, rho0=1.0, eos=Tait(c0=c0, gamma=7.0),
                        viscosity=ArtificialViscosity(alpha=alpha) if alpha > 0 else None,
                        density_diffusion=DeltaSPH(delta=delta) if delta > 0 else None,
                        density=params["density"], tensile_correction=params["tensile"],
                        xsph=params["xsph"], velocity=velocity, pressure=pressure)
    sim = Simulation([fluid], kernel=CubicSpline(), h=h, gravity=(0.0, 0.0),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads,
                     domain=((-2.5, -3.0), (2.5, 3.0)))
    sim.add(SemiAxis("semi_axis_x", 0), SemiAxis("semi_axis_y", 1), MomentSemiAxis("moment_semi_axis_x", 0),
            MomentSemiAxis("moment_semi_axis_y", 1), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "elliptical-drop", "A0": A0}
    return sim


ELLIPTICAL_DROP = Case(
    name="elliptical-drop",
    # the scheme chosen by the validation (docs/validation-notes.md): without shifting the lattice stretched
    # 1 : 3.8 reads 7 % too dense to the kernel at h = 1.3 dx and the short semi-axis ends +6.8 % too long;
    # sun2017 kept both semi-axes within 1.5 %
    regularisation={"shifting": "sun2017"},
    description="Monaghan (1994) elliptical drop: circular patch, u = -100 x, v = 100 y, free surface, "
                "fluid only (no walls); particle shifting of Sun et al. (2017) by default (--set shifting=none "
                "for the plain scheme)",
    builder=build_elliptical_drop,
    parameters={"dx": Parameter(None, "particle spacing (default 0.025; radius 1)"),
                "h_factor": Parameter(1.3, "smoothing length h / dx"),
                "A0": Parameter(100.0, "initial strain rate [1/s]"),
                "c0": Parameter(1400.0, "speed of sound [m/s]"),
                "alpha": Parameter(0.1, "artificial viscosity alpha"),
                "xsph": Parameter(0.5, "XSPH epsilon"),
                "cfl": Parameter(0.2, "CFL number"),
                "initial": Parameter("analytic", "initial pressure: analytic (the exact field) or zero", str),
                "density": Parameter("continuity", "density: continuity or summation", str),
                "delta": Parameter(0.0, "delta-SPH coefficient (0 = off)"),
                "tensile": Parameter(False, "Monaghan (2000) tensile correction", bool)},
    t_end=0.0076, probe_every=1e-4, output_every=5e-4)
