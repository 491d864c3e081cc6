"""The test cases of [Li2022] sec. 4 (Li, Zhang & Yuan): one particle in a box, a drop impact, break-through.

Fluid settings of the seed (sec. 2): cubic spline, Tait EOS with gamma = 7
and rho0 = 998.1 kg/m^3, artificial viscosity (alpha for fluid-fluid pairs;
the fluid-wall alpha belongs to the wall model, ``alpha_wall``), XSPH with
eps = 0.5, the tensile correction of eq. 20 and the Monaghan-Kos time step
of eq. 11 (symplectic integrator). The seed does not give h; here
h = 1.3 dx (parameter ``h_factor``). Walls are a single row of particles
(parameter ``layers``), as the seed's figures 4-6 and 9 draw them.

* ``particle-in-box`` (sec. 4.1): one particle in a 60 m square box from
  (30, 36) m with velocity (20, -20) m/s, c = 1460 m/s, CFL 0.05, no
  viscosity or gravity. With specular reflection its path is a closed
  rectangle of period 6 s. Probes: ``x``, ``y``, ``kinetic_energy``.
* ``drop-impact`` (sec. 4.2): a drop of radius 1.0 mm centred 2.0 mm above
  the wall row, velocity (0, -2) m/s, gravity, alpha = 0.2 (fluid) and
  0 (wall), c = 50 m/s, CFL 0.05, dx = 0.2 mm; the wall row symmetric about
  the drop's axis (``shift=0``) or shifted by 0.3 dx (``shift=0.3``).
  Probes: ``f_sym`` (eq. 29), ``through`` (particles that broke through the
  wall: seen more than dx/2 below the row), ``lowest`` (lowest particle).
* :func:`breakthrough_speed` raises the drop speed until particles cross
  the wall (sec. 4.2, last paragraph).
"""

import math

import numpy as np

from .. import probes as _probes
from ..boundary.base import WallSystem
from ..eos import Tait
from ..errors import InstabilityError, ParameterError, require_positive
from ..fluid import ArtificialViscosity, FluidSystem
from ..integrators import Symplectic
from ..kernels import CubicSpline
from ..shapes import Shape, ball, tank
from ..simulation import Simulation
from .base import GRAVITY, Case, Parameter

RHO0_SEED = 998.1  # [Li2022] sec. 2, water at 20 degC


class ParticleCoordinate(_probes.Probe):
    """Coordinate ``axis`` of the fluid particle with id ``pid`` (NaN once it has left the domain)."""

    def __init__(self, name, axis, pid=0):
        super().__init__(name)
        self.axis = int(axis)
        self.pid = int(pid)

    def sample(self, sim):
        fp = sim.fluid.particles
        k = np.flatnonzero(fp["id"] == self.pid)
        return float(fp["x"][k[0], self.axis]) if k.size else float("nan")


def f_sym(x, y, dx):
    """Symmetry coefficient of [Li2022] eq. 29 with coordinates in units of dx.

    f_sym = sqrt(f_x^2 + f_y^2) / N,  f_x = sum xi^3,  f_y = sum xi eta^2,
    xi = x / dx measured from the drop's axis, eta = y / dx from the wall row.
    (The extracted eq. 29 divides by N dx with x, y in metres, which is not
    dimensionless; measuring in dx makes it so, see docs/idbc.md.)
    """
    x = np.asarray(x, dtype=np.float64) / dx
    y = np.asarray(y, dtype=np.float64) / dx
    if x.size == 0:
        return float("nan")
    fx = np.sum(x ** 3)
    fy = np.sum(x * y * y)
    return float(math.hypot(fx, fy) / x.size)


class SymmetryProbe(_probes.Probe):
    """f_sym of [Li2022] eq. 29 about the axis x = ``axis_x`` above the wall row y = ``wall_y``."""

    def __init__(self, name, axis_x, wall_y, dx):
        super().__init__(name)
        self.axis_x = float(axis_x)
        self.wall_y = float(wall_y)
        self.dx = float(dx)

    def sample(self, sim):
        x = sim.fluid.particles["x"]
        return f_sym(x[:, 0] - self.axis_x, x[:, 1] - self.wall_y, self.dx)


class ThroughWallProbe(_probes.Probe):
    """Number of fluid particles now on the far side of a horizontal wall row y = ``wall_y``.

    Counts the particles more than ``depth`` below the row within |x| <
    ``half`` (away from the row's ends) plus those that left the domain
    there ([Li2022] sec. 4.2: particles that escape the wall). A particle
    that dips below the row and is pushed back counts only while it is
    below; ``ids`` remembers every particle ever seen below.
    """

    def __init__(self, name, wall_y, half, depth):
        super().__init__(name)
        self.wall_y = float(wall_y)
        self.half = float(half)
        self.depth = float(depth)
        self.ids = set()

    def sample(self, sim):
        fp = sim.fluid.particles
        x = fp["x"]
        below = (x[:, 1] < self.wall_y - self.depth) & (np.abs(x[:, 0]) < self.half)
        self.ids.update(int(i) for i in fp["id"][below])
        gone = 0
        for rec in sim.escaped:
            if rec[3] < self.wall_y - self.depth and abs(rec[2]) < self.half:
                self.ids.add(int(rec[1]))
                gone += 1
        return float(np.count_nonzero(below) + gone)


class LowestProbe(_probes.Probe):
    """Lowest y of the fluid particles within |x| < ``half`` [m]."""

    def __init__(self, name, half):
        super().__init__(name)
        self.half = float(half)

    def sample(self, sim):
        x = sim.fluid.particles["x"]
        m = np.abs(x[:, 0]) < self.half
        return float(x[m, 1].min()) if m.any() else float("nan")


def _seed_fluid(shape, *, c0, alpha, velocity):
    return FluidSystem(shape, rho0=RHO0_SEED, eos=Tait(c0=c0, gamma=7.0),
                       viscosity=ArtificialViscosity(alpha=alpha) if alpha > 0 else None,
                       xsph=0.5, tensile_correction=True, velocity=velocity)


# ---------------------------------------------------------------- particle in a box
def build_particle_in_box(params, wall_model, threads):
    """One particle in a square box with single-row walls on its four sides ([Li2022] sec. 4.1)."""
    dx = require_positive("dx", params["dx"])
    h = require_positive("h", params["h_factor"] * dx)
    L = require_positive("L", params["L"])
    if abs(L / dx - round(L / dx)) > 1e-9:
        raise ParameterError(f"L = {L} m must be a whole multiple of dx = {dx} m")
    x0, y0 = params["x0"], params["y0"]
    if not (0 < x0 < L and 0 < y0 < L):
        raise ParameterError(f"start point ({x0}, {y0}) must lie inside the {L} m box")
    fluid_shape = Shape(np.array([[x0, y0]]), dx)
    fluid = _seed_fluid(fluid_shape, c0=params["c0"], alpha=params["alpha"], velocity=(params["u"], params["v"]))
    # wall particles on the lines x, y = 0 and L: a closed tank whose surface is dx/2 inside them
    walls = tank((0.5 * dx, 0.5 * dx), (L - 0.5 * dx, L - 0.5 * dx), dx, layers=params["layers"], open_top=False)
    wall = WallSystem(walls, model=wall_model(), name="box")
    margin = 4.0 * h + params["layers"] * dx
    sim = Simulation([fluid, wall], kernel=CubicSpline(), h=h, gravity=(0.0, 0.0),
                     integrator=Symplectic(cfl=params["cfl"], rule="monaghan-kos"), threads=threads,
                     domain=((-margin, -margin), (L + margin, L + margin)),
                     hull=None, wall_removal_depth=None)   # the case measures wall penetration itself
    sim.add(ParticleCoordinate("x", 0), ParticleCoordinate("y", 1), _probes.KineticEnergy())
    sim.reference = {"type": "particle-in-box", "start": (x0, y0), "L": L,
                     "period": _box_period(L, x0, y0, params["u"], params["v"])}
    return sim


def _box_period(L, x0, y0, u, v):
    """Time of one loop of the specular path (reflection at the wall lines): 2 L sqrt(2) / |v| for 45 degrees."""
    speed = math.hypot(u, v)
    if abs(abs(u) - abs(v)) > 1e-12 * speed:
        return float("nan")
    return 2.0 * L * math.sqrt(2.0) / speed


PARTICLE_IN_BOX = Case(
    name="particle-in-box",
    description="one particle in a 60 m box at 45 degrees, c = 1460 m/s ([Li2022] sec. 4.1): trajectory, energy",
    builder=build_particle_in_box,
    parameters={
        "dx": Parameter(1.0, "wall particle spacing (and fluid spacing) [m]"),
        "h_factor": Parameter(1.3, "smoothing length h / dx"),
        "L": Parameter(60.0, "side of the box [m]"),
        "x0": Parameter(30.0, "start x [m]"),
        "y0": Parameter(36.0, "start y [m]"),
        "u": Parameter(20.0, "start velocity x [m/s]"),
        "v": Parameter(-20.0, "start velocity y [m/s]"),
        "c0": Parameter(1460.0, "speed of sound [m/s]"),
        "alpha": Parameter(0.0, "artificial viscosity alpha (fluid-fluid; there is one particle)"),
        "cfl": Parameter(0.05, "CFL number of the Monaghan-Kos rule"),
        "layers": Parameter(1, "wall layers", int),
    },
    t_end=6.5, probe_every=2e-3, output_every=0.1)


# ---------------------------------------------------------------- drop impact
def drop_wall(dx, half_length, shift, layers=1):
    """Horizontal wall rows y = -k dx (k < layers) at x = (j + shift) dx, |x| <= half_length; normals +y."""
    m = int(math.ceil(half_length / dx))
    xs = (np.arange(-m, m + 1) + shift) * dx
    xs = xs[np.abs(xs) <= half_length + 1e-12 * dx]
    rows = []
    for k in range(layers):
        rows.append(np.stack([xs, np.full_like(xs, -k * dx)], axis=1))
    pos = np.concatenate(rows)
    normals = np.tile([0.0, 1.0], (pos.shape[0], 1))
    surface = np.stack([pos[:, 0], np.full(pos.shape[0], 0.5 * dx)], axis=1)
    layer = np.repeat(np.arange(layers), xs.size)
    return Shape(pos, dx, normals, surface, layer)


def build_drop_impact(params, wall_model, threads):
    """A 2D drop falling on a wall row ([Li2022] sec. 4.2)."""
    dx = require_positive("dx", params["dx"])
    h = require_positive("h", params["h_factor"] * dx)
    R = require_positive("radius", params["radius"])
    H = require_positive("height", params["height"])
    if H - R < 2.0 * dx:
        raise ParameterError(f"the drop (radius {R} m, centre {H} m) must start at least 2 dx above the wall")
    speed = require_positive("speed", params["speed"])
    half = params["half_length"] or max(8.0 * R, 0.0)
    drop = ball((0.0, H), R, dx)
    fluid = _seed_fluid(drop, c0=params["c0"], alpha=params["alpha"], velocity=(0.0, -speed))
    wall_shape = drop_wall(dx, half, params["shift"], params["layers"])
    wall = WallSystem(wall_shape, model=wall_model(), name="floor")
    margin = 4.0 * h + params["layers"] * dx
    top = H + R + max(2.0 * H, 4.0 * R)
    sim = Simulation([fluid, wall], kernel=CubicSpline(), h=h,
                     gravity=(0.0, -GRAVITY if params["gravity"] else 0.0),
                     integrator=Symplectic(cfl=params["cfl"], rule="monaghan-kos"), threads=threads,
                     domain=((-half - margin, -params["layers"] * dx - margin), (half + margin, top)),
                     density_band=(params["rho_min"], params["rho_max"]),
                     hull=None, wall_removal_depth=None)   # break-through is what the case measures
    sim.add(SymmetryProbe("f_sym", 0.0, 0.0, dx), ThroughWallProbe("through", 0.0, half - 2.0 * h, 0.5 * dx),
            LowestProbe("lowest", half - 2.0 * h),
            _probes.KineticEnergy())
    sim.reference = {"type": "drop-impact", "n": drop.n, "half_length": half}
    return sim


DROP_IMPACT = Case(
    name="drop-impact",
    description="2D drop (R = 1 mm, 2 m/s) on a wall row, symmetric or shifted 0.3 dx ([Li2022] sec. 4.2): f_sym",
    builder=build_drop_impact,
    parameters={
        "dx": Parameter(0.2e-3, "particle spacing [m]"),
        "h_factor": Parameter(1.3, "smoothing length h / dx"),
        "radius": Parameter(1.0e-3, "drop radius [m]"),
        "height": Parameter(2.0e-3, "height of the drop centre above the wall row [m]"),
        "speed": Parameter(2.0, "initial downward speed [m/s]"),
        "c0": Parameter(50.0, "speed of sound [m/s]"),
        "alpha": Parameter(0.2, "artificial viscosity alpha, fluid-fluid"),
        "cfl": Parameter(0.05, "CFL number"),
        "shift": Parameter(0.0, "shift of the wall row along x, in dx (0.3 = the asymmetric wall)"),
        "half_length": Parameter(None, "half length of the wall row [m] (default 8 radii)"),
        "layers": Parameter(1, "wall rows", int),
        "gravity": Parameter(True, "gravity on", bool),
        "rho_min": Parameter(0.5, "lower density bound / rho0 of the instability guard"),
        "rho_max": Parameter(2.0, "upper density bound / rho0 of the instability guard"),
    },
    t_end=0.002, probe_every=2e-5, output_every=1e-4)


def drop_run(boundary="idbc", *, t_end=None, threads=None, **params):
    """Run ``drop-impact``; return (result dict) with f_sym(t), through(t) and the status.

    A run stopped by the instability guard is reported with status "unstable".
    """
    sim = DROP_IMPACT.build(boundary=boundary, threads=threads, **params)
    speed = sim.metadata["parameters"]["speed"]
    if t_end is None:
        t_end = DROP_IMPACT.t_end
    sim.add(every=min(DROP_IMPACT.probe_every, t_end / 200.0))
    status = "completed"
    try:
        res = sim.run(t_end, progress=False)
        times, fs, through = res.times, res["f_sym"], res["through"]
    except InstabilityError:
        status = "unstable"
        res = sim.result({})
        times, fs, through = res.times, res["f_sym"], res["through"]
    x = sim.fluid.particles["x"]
    return {"boundary": boundary, "speed": speed, "status": status, "times": times, "f_sym": fs,
            "through": through, "final_through": float(through[-1]) if through.size else 0.0,
            "dipped": len([p for p in sim.probes if p.name == "through"][0].ids),
            "n": int(sim.reference["n"]), "time": sim.time, "positions": x.copy(),
            "min_y": float(np.nanmin(res["lowest"])) if res["lowest"].size else float("nan")}


def breakthrough_speed(boundary, speeds, *, threads=None, impact_window=6.0, **params):
    """First drop speed in ``speeds`` at which particles escape through the wall (or the run fails).

    Escape: at the end of the run a particle is more than dx/2 below the
    row, or left the domain below it (``through``); ``dipped`` counts the
    particles that went below at some sample but came back.

    Each run lasts from the release to ``impact_window`` drop radii of travel
    after the impact at the initial speed (gravity off), long enough for the
    drop to hit, spread and rebound. Returns (first failing speed or None,
    list of per-speed dicts).
    """
    rows = []
    R = params.get("radius", DROP_IMPACT.parameters["radius"].default)
    H = params.get("height", DROP_IMPACT.parameters["height"].default)
    first = None
    for v in speeds:
        t_end = (H - R + impact_window * R) / v
        out = drop_run(boundary, t_end=t_end, threads=threads, speed=v, gravity=False,
                       rho_min=0.05, rho_max=20.0, **params)
        failed = out["final_through"] > 0 or out["status"] != "completed"
        rows.append({"speed": v, "through": out["final_through"], "dipped": out["dipped"], "status": out["status"],
                     "n": out["n"], "lowest": out["min_y"]})
        if failed and first is None:
            first = v
            break
    return first, rows
