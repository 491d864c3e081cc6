"""The test cases of Liu et al. (2015), [Liu2015] sec. 4, with the fluid of its sec. 2 (preset ``liu2015``).

* ``plates`` (sec. 4.1): a 0.04 x 0.04 m water block moving down at 1 m/s
  between two vertical plates 0.05 m long, 5 mm above their lower edge; no
  gravity, dx = 1 mm, h = 1.5 dx, c_s = 10 m/s (1 m/s for Monaghan-Kajtar,
  as in the seed). Ideally the block leaves undeformed. Probes: the largest
  distance of any particle from its rigid-translation position
  (``deformation``; ``deformation_between`` for the particles still between
  the plates) and the fluid pressure range.
* sec. 4.2, the lid-driven cavity, is the ``cavity`` case
  (:mod:`seawall.cases.lid_cavity`); ``--set fluid=liu2015`` gives it the
  seed's fluid.
* ``dam-break-etsin`` (sec. 4.4): the dam break of Lobovsky et al. (2014)
  used by the seed: column H = 0.3 m high and 0.6 m long in a 1.61 m tank,
  dx = 6 mm, c_s = 10 sqrt(2 g H), dt = 5e-5 s, gate removed instantaneously
  (or lifted at ``gate_speed``, 3.46 m/s in the experiment); pressure
  sensors on the wall hit by the surge at 3, 15, 30 and 80 mm above the
  floor (S1-S4; the seed's monitoring points 1 and 2 are S1 and S3).
"""

import math

import numpy as np

from .. import probes, shapes
from ..boundary.base import WallSystem
from ..errors import ParameterError, require_positive
from ..fluid.presets import liu2015
from ..boundary.movement import PrescribedMotion
from ..simulation import Simulation
from .base import GRAVITY, Case, Parameter, tank_wall, wall_layers
from .tanks import _gravity, _hydrostatic, snap

RHO0 = 1000.0

FLUID = {
    "alpha": Parameter(0.02, "artificial viscosity alpha ([Liu2015] eq. 11)"),
    "delta": Parameter(0.1, "delta-SPH coefficient ([Liu2015] eq. 12; 0 = off)"),
    "nu": Parameter(1e-6, "kinematic viscosity [m^2/s] of the laminar term ([Liu2015] eq. 9)"),
    "c0": Parameter(None, "speed of sound c_s [m/s]"),
    "dt": Parameter(0.0, "fixed time step [s] (0 = the adaptive rule of [Liu2015] eq. 18-20)"),
}


def _preset(params, c0, h_factor):
    return liu2015(c0, alpha=params["alpha"], delta=params["delta"], nu=params["nu"], h_factor=h_factor,
                   dt=params["dt"])


# ---------------------------------------------------------------- probes
class RigidDeformation(probes.Probe):
    """Largest distance [m] of a fluid particle from its rigid-translation position x0 + v0 t.

    With ``between`` = (axis, lo, hi), only the particles whose rigid position
    lies in [lo, hi] along ``axis`` count (0 if there are none).
    """

    def __init__(self, name, x0, velocity, between=None):
        super().__init__(name)
        self.x0 = np.array(x0, dtype=np.float64)
        self.velocity = np.asarray(velocity, dtype=np.float64)
        self.between = between

    def sample(self, sim):
        fp = sim.fluid.particles
        rigid = self.x0[fp["id"]] + self.velocity[None, :] * sim.time
        dist = np.linalg.norm(fp["x"] - rigid, axis=1)
        if self.between is not None:
            axis, lo, hi = self.between
            keep = (rigid[:, axis] >= lo) & (rigid[:, axis] <= hi)
            dist = dist[keep]
        return float(dist.max()) if dist.size else 0.0


class PressureExtreme(probes.Probe):
    """Smallest (``kind="min"``) or largest fluid gauge pressure [Pa]."""

    def __init__(self, name, kind):
        super().__init__(name)
        if kind not in ("min", "max"):
            raise ParameterError(f"kind must be 'min' or 'max', got {kind!r}")
        self.kind = kind

    def sample(self, sim):
        p = sim.fluid.particles["p"] - sim.physics.p_background
        if p.size == 0:
            return float("nan")
        return float(p.min() if self.kind == "min" else p.max())


# ---------------------------------------------------------------- plates
def _plate(x_surface, y0, y1, dx, layers, side, layout, beta):
    """Wall particles of a vertical plate whose fluid-side surface is x = x_surface (side +1: fluid at larger x)."""
    if layout == "surface":
        spacing = dx / beta
        y = y0 + spacing * np.arange(int(round((y1 - y0) / spacing)) + 1)
        x = np.full_like(y, x_surface)
        layer = np.zeros(y.size, dtype=int)
    else:
        spacing = dx
        ny = int(round((y1 - y0) / dx))
        ys = y0 + (np.arange(ny) + 0.5) * dx
        xs = x_surface - side * (np.arange(layers) + 0.5) * dx
        x, y = (a.ravel() for a in np.meshgrid(xs, ys, indexing="ij"))
        layer = np.repeat(np.arange(layers), ny)
    pos = np.stack([x, y], axis=1)
    normals = np.zeros_like(pos)
    normals[:, 0] = side
    surface = pos.copy()
    surface[:, 0] = x_surface
    return shapes.Shape(pos, spacing, normals, surface, layer)


def build_plates(params, wall_model, threads):
    """[Liu2015] sec. 4.1: a water block sliding out from between two plates (no gravity)."""
    dx = require_positive("dx", params["dx"])
    h = require_positive("h_factor", params["h_factor"]) * dx
    width = require_positive("block", params["block"])
    length = require_positive("plate_length", params["plate_length"])
    gap = params["gap"]
    if not (0.0 <= gap and gap + width <= length):
        raise ParameterError(f"gap ({gap} m) + block ({width} m) must fit on the plates ({length} m)")
    speed = require_positive("speed", params["speed"])
    model = wall_model()
    from ..boundary.repulsive import MonaghanKajtar

    if params["c0"] is None:
        # the seed runs Monaghan-Kajtar with c_s = v0 (its force grows as c_s^2), the others with 10 v0
        params["c0"] = speed if isinstance(model, MonaghanKajtar) else 10.0 * speed
    c0 = require_positive("c0", params["c0"])
    if isinstance(model, MonaghanKajtar) and model.K is None:
        # no gravity: K = 0.01 c_s^2, the force scale of Liu et al. (2012); see docs/liu2015.md
        model.K = 0.01 * c0 * c0
    preset = _preset(params, c0, params["h_factor"])
    block = shapes.rectangle((0.0, gap), (width, gap + width), dx)
    fluid = preset.fluid(block, rho0=RHO0, velocity=(0.0, -speed))
    layout = model.layout
    beta = getattr(model, "beta", 1.0)
    layers = int(params["layers"])
    left = _plate(0.0, 0.0, length, dx, layers, +1, layout, beta)
    right = _plate(snap_width(width, dx), 0.0, length, dx, layers, -1, layout, beta)
    walls = WallSystem(left + right, model=model, name="plates")
    travel = (gap + width) + 0.01
    sim = Simulation([fluid, walls], kernel=preset.kernel, h=h, integrator=preset.integrator, threads=threads,
                     domain=((-0.02, -travel - 0.01), (width + 0.02, length + 0.02)))
    x0 = np.empty_like(fluid.particles["x"])
    x0[fluid.particles["id"]] = fluid.particles["x"]
    v0 = (0.0, -speed)
    sim.add(RigidDeformation("deformation", x0, v0),
            RigidDeformation("deformation_between", x0, v0, between=(1, 0.0, length)),
            PressureExtreme("p_min", "min"), PressureExtreme("p_max", "max"), probes.KineticEnergy())
    sim.reference = {"type": "plates", "dx": dx, "speed": speed, "exit_time": (gap + width) / speed}
    return sim


def snap_width(width, dx):
    return max(1, int(math.floor(width / dx + 1e-9))) * dx


PLATES = Case(
    name="plates",
    description="water block leaving two vertical plates at 1 m/s, no gravity ([Liu2015] sec. 4.1)",
    builder=build_plates,
    parameters={**FLUID,
                "dx": Parameter(1e-3, "particle spacing [m]"),
                "h_factor": Parameter(1.5, "h / dx"),
                "block": Parameter(0.04, "side of the square water block [m]"),
                "plate_length": Parameter(0.05, "plate length [m]"),
                "gap": Parameter(0.005, "height of the block's lower edge above the plates' lower end [m]"),
                "speed": Parameter(1.0, "downward speed of the block [m/s]"),
                "layers": Parameter(4, "dummy-particle layers per plate (layered wall models)", int)},
    t_end=0.048, probe_every=2e-4, output_every=2e-3)


# ---------------------------------------------------------------- dam break (ETSIN)
SENSORS = (("S1", 0.003), ("S2", 0.015), ("S3", 0.030), ("S4", 0.080))


def _gate(x_surface, height, dx, layers, layout, beta, speed):
    """The gate holding the column (fluid at x < x_surface), lifted at ``speed`` until it is ``height`` up.

    speed = 0: no gate (removed at t = 0). The gate is a plate of the same wall model as the tank
    ([Liu2015] sec. 4.4: lifting speed 3.46 m/s); its motion starts impulsively at t = 0.
    """
    if speed == 0.0:
        return None
    plate = _plate(x_surface, 0.0, height, dx, layers, -1, layout, beta)
    t_stop = height / speed

    def lift(t):
        return (0.0, speed * min(max(t, 0.0), t_stop))

    def velocity(t):
        return (0.0, speed if 0.0 <= t < t_stop else 0.0)

    return plate, PrescribedMotion(lift, lambda t: t < t_stop, velocity=velocity,
                                   acceleration=lambda t: (0.0, 0.0))


def build_dam_break_etsin(params, wall_model, threads):
    """[Liu2015] sec. 4.4: H = 0.3 m column, 0.6 m long, in a 1.61 m tank (Lobovsky et al. 2014).

    The column starts in hydrostatic equilibrium, p = rho0 g (H - y) (the seed does not say; a
    column released at p = 0 rings with acoustic waves of amplitude rho0 g H).
    """
    H = require_positive("H", params["H"])
    if params["dx"] is None:
        params["dx"] = H / 50.0
    dx = require_positive("dx", params["dx"])
    h = require_positive("h_factor", params["h_factor"]) * dx
    if params["c0"] is None:
        params["c0"] = 10.0 * math.sqrt(2.0 * GRAVITY * H)
    c0 = require_positive("c0", params["c0"])
    gate_speed = params["gate_speed"]
    if not gate_speed >= 0.0:
        raise ParameterError(f"gate_speed must be >= 0 (0 = gate removed at t = 0), got {gate_speed}")
    preset = _preset(params, c0, params["h_factor"])
    length = snap(params["tank_length"], dx)
    height = snap(2.0 * H, dx)
    width = snap(2.0 * H, dx)
    if width >= length:
        raise ParameterError(f"tank_length ({length} m) must exceed the column length 2 H ({width} m)")
    fluid = preset.fluid(shapes.rectangle((0.0, 0.0), (width, H), dx), rho0=RHO0,
                         pressure=_hydrostatic(H, RHO0, 2))
    model = wall_model()
    tank = tank_wall(model, (0.0, 0.0), (length, height), dx, preset.kernel, h)
    systems = [fluid, WallSystem(tank, model=model, name="tank")]
    gate_model = wall_model()
    gate = _gate(width, height, dx, wall_layers(preset.kernel, h, dx), gate_model.layout,
                 getattr(gate_model, "beta", 1.0), gate_speed)
    if gate is not None:
        systems.append(WallSystem(gate[0], model=gate_model, name="gate", movement=gate[1]))
    margin = 6.0 * dx
    sim = Simulation(systems, kernel=preset.kernel, h=h, gravity=_gravity(2), integrator=preset.integrator,
                     threads=threads, domain=((-margin, -margin), (length + margin, 2.0 * height + margin)))
    for name, y in SENSORS:
        sim.add(probes.WallPressure(name, (length, y)))
    sim.add(probes.SurgeFront("front"), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "dam-break-etsin", "H": H, "rho0": RHO0, "g": GRAVITY, "tank_length": length}
    return sim


DAM_BREAK_ETSIN = Case(
    name="dam-break-etsin",
    description="ETSIN dam break of [Liu2015] sec. 4.4 (H = 0.3 m, 1.61 m tank, sensors at 3/15/30/80 mm), "
                "[Liu2015] fluid, dt = 5e-5 s; --set gate_speed=3.46 lifts the gate as in the experiment",
    builder=build_dam_break_etsin,
    parameters={**FLUID,
                "dt": Parameter(5e-5, "fixed time step [s] ([Liu2015] sec. 4.4: 5e-5; 0 = the adaptive rule of "
                                      "eq. 18-20)"),
                "H": Parameter(0.3, "column height [m] (column length 2H)"),
                "dx": Parameter(None, "particle spacing [m] (default H / 50 = 6 mm as in the seed)"),
                "h_factor": Parameter(1.2, "h / dx"),
                "tank_length": Parameter(1.61, "tank length [m]"),
                "gate_speed": Parameter(0.0, "gate lifting speed [m/s] (0 = removed at t = 0; experiment 3.46)")},
    t_end=1.5, probe_every=5e-4, output_every=0.02)
