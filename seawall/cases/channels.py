"""Flows through open boundaries: the plane Poiseuille channel (2D), the duct (3D).

``channel``: water between two no-slip plates y = 0 and y = H, fed through
an inflow zone at x = 0 and leaving through an outflow zone at x = L
([TrixiBoundary] InFlow / OutFlow with the Lastiwka model). The fluid starts at
rest; the reference flow of both zones is the analytic plane Poiseuille
flow, u(y) = 4 U y (H - y) / H^2 with the pressure p(x) = G (L - x),
G = 8 mu U / H^2 (the pressure gradient that sustains it), so the zones
prescribe what the open boundaries of a long channel would see, and the
fluid in between has to develop the profile by itself.

``pipe-3d``: the same in a square duct |y|, |z| < a, with the analytic duct
profile (a Fourier series, e.g. White, Viscous Fluid Flow, eq. 3-48).
"""

import math

import numpy as np

from .. import probes, shapes
from ..boundary.base import WallSystem
from ..eos import Tait
from ..errors import ParameterError, require_positive
from ..fluid import DeltaSPH, FluidSystem, LaminarViscosity
from ..integrators import Symplectic
from ..kernels import CubicSpline
from ..openboundary import FluidCount, InFlow, MaxSpeed, OpenBoundary, OutFlow, ZoneInflow
from ..simulation import Simulation
from .base import Case, Parameter, require_noslip, wall_layers


def poiseuille_velocity(y, height, u_max):
    """Plane Poiseuille profile u(y) = 4 U y (H - y) / H^2 [m/s]."""
    y = np.asarray(y, dtype=np.float64)
    return 4.0 * u_max * y * (height - y) / height ** 2


def duct_velocity(y, z, a, b, u_max=None, gradient=None, mu=None, n_terms=40):
    """Fully developed laminar flow in the rectangular duct |y| < a, |z| < b.

        u = (16 a^2 G / (mu pi^3)) sum_{i = 1, 3, 5, ...} (-1)^((i-1)/2)
            [1 - cosh(i pi z / 2a) / cosh(i pi b / 2a)] cos(i pi y / 2a) / i^3

    (White, Viscous Fluid Flow, 3rd ed., eq. 3-48), G = -dp/dx. Given
    ``u_max`` instead of G and mu, the profile is scaled to that centre value.
    """
    y = np.asarray(y, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)

    def series(yy, zz):
        s = np.zeros(np.broadcast(yy, zz).shape)
        for k in range(n_terms):
            i = 2 * k + 1
            arg_b = i * math.pi * b / (2 * a)
            # cosh(i pi z/2a)/cosh(i pi b/2a) written with decaying exponentials
            ratio = (np.exp(i * math.pi * (np.abs(zz) - b) / (2 * a))
                     + np.exp(-i * math.pi * (np.abs(zz) + b) / (2 * a))) / (1.0 + math.exp(-2 * arg_b))
            s += (-1) ** k * (1.0 - ratio) * np.cos(i * math.pi * yy / (2 * a)) / i ** 3
        return s

    if u_max is not None:
        return u_max * series(y, z) / series(np.zeros(1), np.zeros(1))[0]
    return 16.0 * a * a * gradient / (mu * math.pi ** 3) * series(y, z)


def duct_gradient(a, b, u_max, mu):
    """-dp/dx that gives the centre velocity u_max in the duct |y| < a, |z| < b."""
    return u_max / duct_velocity(np.zeros(1), np.zeros(1), a, b, gradient=1.0, mu=mu)[0]


_require_noslip = require_noslip


class CentreVelocity(probes.Probe):
    """Mean x-velocity of the fluid particles within one dx of a point [m/s]."""

    def __init__(self, name, point):
        super().__init__(name)
        self.point = np.asarray(point, dtype=np.float64)

    def sample(self, sim):
        fp = sim.fluid.particles
        near = (np.sum((fp["x"] - self.point) ** 2, axis=1) < sim.fluid.spacing ** 2) & (fp["zone"] < 0)
        return float(fp["v"][near, 0].mean()) if near.any() else float("nan")


COMMON = {
    "dx": Parameter(None, "particle spacing [m] (default H / 20)"),
    "h_factor": Parameter(1.3, "smoothing length h / dx"),
    "u_max": Parameter(0.1, "centreline velocity U of the reference flow [m/s]"),
    "reynolds": Parameter(10.0, "Reynolds number U H / nu (U the centreline velocity)"),
    "c0": Parameter(None, "speed of sound [m/s] (default 10 U)"),
    "delta": Parameter(0.1, "delta-SPH diffusion coefficient (0 = off)"),
    "cfl": Parameter(0.2, "CFL number"),
    "rho0": Parameter(1000.0, "reference density [kg/m^3]"),
    "layers": Parameter(4, "particle layers of each open boundary zone", int),
    "buffer_size": Parameter(0, "spare particles of the open boundary (0 = twice the inflow zone)", int),
}


def _duct_settings(params, across):
    """Checked (height, dx, length, h, u_max, nu, rho0, c0) of a channel or duct; dx defaults to height/across."""
    height = require_positive("height", params["height"])
    if params["dx"] is None:
        params["dx"] = height / across
    dx = require_positive("dx", params["dx"])
    n_across = height / dx
    if abs(n_across - round(n_across)) > 1e-6:
        raise ParameterError(f"height / dx must be a whole number, got {n_across:g}")
    length = round(require_positive("length", params["length"]) / dx) * dx
    h = require_positive("h_factor", params["h_factor"]) * dx
    u_max = require_positive("u_max", params["u_max"])
    nu = u_max * height / require_positive("reynolds", params["reynolds"])
    rho0 = require_positive("rho0", params["rho0"])
    c0 = params["c0"] or 10.0 * u_max
    params["c0"] = c0
    return height, dx, length, h, u_max, nu, rho0, c0


def build_channel(params, wall_model, threads):
    height, dx, length, h, u_max, nu, rho0, c0 = _duct_settings(params, 20)
    kernel = CubicSpline()
    model = wall_model()
    _require_noslip(model, "channel")
    gradient = 8.0 * rho0 * nu * u_max / height ** 2
    fluid = FluidSystem(shapes.rectangle((0.0, 0.0), (length, height), dx), rho0=rho0, eos=Tait(c0=c0, gamma=7.0),
                        viscosity=LaminarViscosity(nu=nu),
                        density_diffusion=DeltaSPH(delta=params["delta"]) if params["delta"] > 0 else None)

    def velocity(x, t):
        v = np.zeros_like(x)
        v[:, 0] = poiseuille_velocity(x[:, 1], height, u_max)
        return v

    def pressure(x, t):
        return gradient * (length - x[:, 0])

    layers = params["layers"]
    common = dict(particle_spacing=dx, density=rho0, open_boundary_layers=layers,
                  reference_velocity=velocity, reference_pressure=pressure)
    inflow = InFlow(plane=((0.0, 0.0), (0.0, height)), flow_direction=(1.0, 0.0), name="inflow", **common)
    outflow = OutFlow(plane=((length, 0.0), (length, height)), flow_direction=(1.0, 0.0), name="outflow", **common)
    depth = layers * dx
    buffer_size = params["buffer_size"] or 2 * inflow.positions.shape[0]
    boundary = OpenBoundary([inflow, outflow], fluid_system=fluid, buffer_size=buffer_size)
    nwall = wall_layers(kernel, h, dx)
    x0, x1 = -depth, length + depth
    plates = shapes.tank((x0, 0.0), (x1, height), dx, layers=nwall, open_top=False)
    px = plates.positions[:, 0]
    plates = plates.subset((px > x0) & (px < x1))
    walls = WallSystem(plates, model=model, name="plates")
    support = kernel.support(h)
    domain = ((x0 - 3 * support, -nwall * dx - 2 * support), (x1 + 3 * support, height + nwall * dx + 2 * support))
    sim = Simulation([fluid, walls, boundary], kernel=kernel, h=h, integrator=Symplectic(cfl=params["cfl"]),
                     domain=domain, threads=threads)
    sim.add(CentreVelocity("u_centre", (0.5 * length, 0.5 * height)), FluidCount(), MaxSpeed(),
            ZoneInflow("mass_in", boundary, 0), ZoneInflow("mass_out", boundary, 1, outward=True),
            probes.Pressure("p_inlet", (2 * dx, 0.5 * height)), probes.Pressure("p_outlet", (length - 2 * dx, 0.5 * height)))
    sim.open_boundary = boundary
    sim.reference = {"type": "poiseuille", "height": height, "length": length, "u_max": u_max, "nu": nu,
                     "rho0": rho0, "gradient": gradient, "viscous_time": height ** 2 / nu}
    return sim


CHANNEL = Case(
    name="channel",
    free_surface=False,
    default_boundary="adami-noslip",
    description="plane Poiseuille flow through an inflow and an outflow zone (Lastiwka), no-slip plates "
                "(adami-noslip by default)",
    builder=build_channel,
    parameters={**COMMON,
                "height": Parameter(0.1, "channel height H [m]"),
                "length": Parameter(0.2, "length L between the inflow and the outflow plane [m]")},
    t_end=6.0, probe_every=0.02, output_every=0.2)


def channel_profile(sim, x_range=(0.25, 0.75), axis=1):
    """Mean x-velocity of the fluid particles in lanes of width dx across the channel.

    Only fluid particles (zone particles excluded) with x / L in ``x_range``.
    Returns (lane centres [m], mean u [m/s], particle count per lane).
    """
    ref = sim.reference
    fp = sim.fluid.particles
    x, v = fp["x"], fp["v"]
    dx = sim.fluid.spacing
    length = ref["length"]
    sel = (fp["zone"] < 0) & (x[:, 0] > x_range[0] * length) & (x[:, 0] < x_range[1] * length)
    lo = ref.get("lo", 0.0)
    n = int(round(ref["height"] / dx))
    lane = np.clip(np.floor((x[sel, axis] - lo) / dx).astype(np.int64), 0, n - 1)
    count = np.bincount(lane, minlength=n)
    total = np.bincount(lane, weights=v[sel, 0], minlength=n)
    centres = lo + (np.arange(n) + 0.5) * dx
    with np.errstate(invalid="ignore", divide="ignore"):
        return centres, total / count, count


def build_pipe_3d(params, wall_model, threads):
    """Square duct |y - a|, |z - a| < a (side H = 2a) with the duct profile as reference flow."""
    height, dx, length, h, u_max, nu, rho0, c0 = _duct_settings(params, 10)
    a = 0.5 * height
    kernel = CubicSpline()
    model = wall_model()
    _require_noslip(model, "pipe-3d")
    gradient = duct_gradient(a, a, u_max, rho0 * nu)
    fluid = FluidSystem(shapes.box((0.0, 0.0, 0.0), (length, height, height), dx), rho0=rho0,
                        eos=Tait(c0=c0, gamma=7.0), viscosity=LaminarViscosity(nu=nu),
                        density_diffusion=DeltaSPH(delta=params["delta"]) if params["delta"] > 0 else None)

    def velocity(x, t):
        v = np.zeros_like(x)
        v[:, 0] = duct_velocity(x[:, 1] - a, x[:, 2] - a, a, a, u_max=u_max)
        return v

    def pressure(x, t):
        return gradient * (length - x[:, 0])

    layers = params["layers"]
    common = dict(particle_spacing=dx, density=rho0, open_boundary_layers=layers,
                  reference_velocity=velocity, reference_pressure=pressure, flow_direction=(1.0, 0.0, 0.0))
    inflow = InFlow(plane=((0, 0, 0), (0, height, 0), (0, 0, height)), name="inflow", **common)
    outflow = OutFlow(plane=((length, 0, 0), (length, height, 0), (length, 0, height)), name="outflow", **common)
    depth = layers * dx
    buffer_size = params["buffer_size"] or 2 * inflow.positions.shape[0]
    boundary = OpenBoundary([inflow, outflow], fluid_system=fluid, buffer_size=buffer_size)
    nwall = wall_layers(kernel, h, dx)
    x0, x1 = -depth, length + depth
    duct = shapes.tank((x0, 0.0, 0.0), (x1, height, height), dx, layers=nwall, open_top=False)
    px = duct.positions[:, 0]
    walls = WallSystem(duct.subset((px > x0) & (px < x1)), model=model, name="duct")
    support = kernel.support(h)
    pad = nwall * dx + 2 * support
    domain = ((x0 - 3 * support, -pad, -pad), (x1 + 3 * support, height + pad, height + pad))
    sim = Simulation([fluid, walls, boundary], kernel=kernel, h=h, integrator=Symplectic(cfl=params["cfl"]),
                     domain=domain, threads=threads)
    sim.add(CentreVelocity("u_centre", (0.5 * length, a, a)), FluidCount(), MaxSpeed(),
            ZoneInflow("mass_in", boundary, 0), ZoneInflow("mass_out", boundary, 1, outward=True))
    sim.open_boundary = boundary
    sim.reference = {"type": "duct", "height": height, "length": length, "u_max": u_max, "nu": nu,
                     "rho0": rho0, "gradient": gradient, "viscous_time": height ** 2 / nu, "a": a}
    return sim


def duct_profile_error(sim, x_range=(0.25, 0.75)):
    """Largest |mean u - u_exact| over the (y, z) lanes of the duct, divided by U, and the lane means."""
    ref = sim.reference
    fp = sim.fluid.particles
    x, v = fp["x"], fp["v"]
    dx = sim.fluid.spacing
    a = ref["a"]
    length = ref["length"]
    sel = (fp["zone"] < 0) & (x[:, 0] > x_range[0] * length) & (x[:, 0] < x_range[1] * length)
    n = int(round(ref["height"] / dx))
    ly = np.clip(np.floor(x[sel, 1] / dx).astype(np.int64), 0, n - 1)
    lz = np.clip(np.floor(x[sel, 2] / dx).astype(np.int64), 0, n - 1)
    lane = ly * n + lz
    count = np.bincount(lane, minlength=n * n)
    err = v[sel, 0] - duct_velocity(x[sel, 1] - a, x[sel, 2] - a, a, a, u_max=ref["u_max"])
    mean_err = np.bincount(lane, weights=err, minlength=n * n) / np.maximum(count, 1)
    mean_u = np.bincount(lane, weights=v[sel, 0], minlength=n * n) / np.maximum(count, 1)
    return float(np.abs(mean_err[count > 0]).max() / ref["u_max"]), mean_u.reshape(n, n), count.reshape(n, n)


PIPE_3D = Case(
    name="pipe-3d",
    free_surface=False,
    default_boundary="adami-noslip",
    description="laminar flow through a square duct between an inflow and an outflow zone (Lastiwka), "
                "no-slip walls (adami-noslip by default)",
    builder=build_pipe_3d,
    parameters={**{k: v for k, v in COMMON.items() if k != "dx"},
                "dx": Parameter(None, "particle spacing [m] (default H / 10)"),
                "height": Parameter(0.1, "side H of the square duct [m]"),
                "length": Parameter(0.2, "length L between the inflow and the outflow plane [m]")},
    t_end=4.0, probe_every=0.02, output_every=0.2, dimension=3)
