"""Waves on seawalls ([Huang2019] sec. 4.3-4.4): solitary waves from a piston wave maker.

``solitary-wave``
    A flume of constant depth d: a Goring piston (left wall above the floor)
    generates a solitary wave of height H that runs to the right end wall,
    vertical or leaning at ``wall_angle`` (the angle between the floor and
    the wall, measured inside the water: 90 = vertical, > 90 leans away from
    the water like a sloped seawall). Probes: surface gauges ``eta_<x>``,
    run-up on the end wall ``runup``, the pairwise force on it ``Fx_wall``
    ([Huang2019] eq. 29) and the integrated wall pressure ``Fx_wall_p``, both
    also divided by the hydrostatic force 0.5 rho g d^2 (``F*``), wall
    pressure probes ``P0``/``P1`` at heights ``probe_y``.
``solitary-seawall``
    [Huang2019] sec. 4.3: the same flume 10 m long, d = 0.25 m, H = 0.15 m, a
    wall leaning at 120 deg, dx = 0.01 m, probes at y = 0.05 and 0.15 m.
``solitary-runup``
    The constant-depth flume with a vertical wall for the run-up sweep
    against Chan & Street (1970) (``validation/solitary-runup/sweep.py``).
``movable-seawall``
    [Huang2019] sec. 4.4 (after Liang et al. 2017): a vertical wall at
    x0 = 2.50 m on a spring (m = 250 kg/m, k = 10 N/m) that moves once the
    force exceeds 1.10 F_static; depth 0.20 m, dx = 0.008 m. The seed does not
    give the wave height of this case; the default H = 0.1 m (H/d = 0.5) is our choice.
"""

import math

import numpy as np

from .. import probes, shapes
from ..boundary.base import WallSystem
from ..errors import ParameterError, require_positive
from ..integrators import Symplectic
from ..kernels import CubicSpline
from ..simulation import Simulation
from ..spring_wall import SpringWall
from ..waves import (FollowingWallPressure, GoringPaddle, RunUp, SurfaceGauge, WallPressureForce, paddle_motion)
from .base import GRAVITY, Case, Parameter, wall_layers
from .tanks import COMMON, _common, _fluid, _gravity, _hydrostatic, snap


def _floats(text, name):
    if text is None or str(text).strip() == "":
        return []
    try:
        return [float(v) for v in str(text).split(",") if v.strip()]
    except ValueError:
        raise ParameterError(f"{name} must be comma-separated numbers, got {text!r}") from None


def _layered(model, case):
    if model.layout == "surface":
        raise ParameterError(f"case {case!r} builds layered polyline walls; the surface-particle model "
                             f"{model.name!r} is not supported here")


def _dbc_hydrostatic(model, depth, rho0):
    """Dynamic boundary walls start from the hydrostatic pressure (like the fluid), not from rho0."""
    if hasattr(model, "initial_pressure") and model.initial_pressure is None:
        model.initial_pressure = lambda x: rho0 * GRAVITY * np.maximum(depth - x[:, -1], 0.0)
    return model


def _paddle_c0(params, depth, height):
    # the wave's celerity c = sqrt(g (d + H)) bounds the fluid's and the paddle's speeds
    # (u = c eta / (d + eta) < c) until the wave breaks: Mach <= 0.1
    c = math.sqrt(GRAVITY * (depth + height))
    c0 = params["c0"] or 10.0 * c
    params["c0"] = c0
    return c0


# ---------------------------------------------------------------- flume with a piston and an end wall
def build_solitary_flume(params, wall_model, threads, case_name="solitary-wave"):
    depth = require_positive("depth", params["depth"])
    height = require_positive("height", params["height"])
    if params["dx"] is None:
        params["dx"] = depth / 10.0
    dx, h = _common(params)
    length = snap(require_positive("length", params["length"]), dx)
    angle = float(params["wall_angle"])
    if not 45.0 <= angle <= 150.0:
        raise ParameterError(f"wall_angle must be between 45 and 150 degrees, got {angle}")
    wall_h = snap(require_positive("wall_height", params["wall_height"]), dx)
    if wall_h <= depth:
        raise ParameterError(f"wall_height ({wall_h} m) must exceed the depth ({depth} m)")
    paddle = GoringPaddle(height, depth)
    c0 = _paddle_c0(params, depth, height)
    rho0 = params["rho0"]
    kernel = CubicSpline()
    layers = wall_layers(kernel, h, dx)
    # the end wall leans by (angle - 90) deg: x_wall(y) = length + y cot(180 - angle)
    run = 1.0 / math.tan(math.radians(180.0 - angle)) if abs(angle - 90.0) > 1e-9 else 0.0
    top = (length + wall_h * run, wall_h)
    pts = [(0.0, wall_h), (0.0, 0.0), (length, 0.0), top]
    model = _dbc_hydrostatic(wall_model(), depth, rho0)
    _layered(model, case_name)
    walls = shapes.polyline_wall(pts, dx, layers=layers, side="right")
    x, y = walls.positions[:, 0], walls.positions[:, 1]
    is_piston = (x < 0.0) & (y > 0.25 * dx)
    is_end = walls.surface_points[:, 0] > length - 1e-9 * dx
    # fluid: the lattice below the still level, on the water side of the end wall (>= dx/2 from it)
    block = shapes.rectangle((0.0, 0.0), (snap(length + depth * max(run, 0.0) + dx, dx), depth), dx)
    wall_dir = np.array([run, 1.0]) / math.hypot(run, 1.0)
    normal_out = np.array([wall_dir[1], -wall_dir[0]])     # from the water into the end wall
    signed = (block.positions - np.array([length, 0.0])) @ normal_out
    block = block.subset(signed <= -0.5 * dx * (1 - 1e-9))
    fluid = _fluid(block, params, c0=c0, pressure=_hydrostatic(depth, rho0, 2))
    tank_model = model
    piston_model = _dbc_hydrostatic(wall_model(), depth, rho0)
    end_model = _dbc_hydrostatic(wall_model(), depth, rho0)
    systems = [fluid,
               WallSystem(walls.subset(~is_piston & ~is_end), model=tank_model, name="tank"),
               WallSystem(walls.subset(is_piston), model=piston_model, name="piston", movement=paddle_motion(paddle)),
               WallSystem(walls.subset(is_end), model=end_model, name="wall")]
    margin = (layers + 3) * dx
    hi_x = max(length, top[0]) + margin
    sim = Simulation(systems, kernel=kernel, h=h, gravity=_gravity(2),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads,
                     domain=((-margin, -margin), (hi_x, wall_h + 2 * depth)))
    static = 0.5 * rho0 * GRAVITY * depth ** 2
    for xg in _floats(params["gauges"], "gauges"):
        sim.add(SurfaceGauge(f"eta_{xg:g}", xg, still_level=depth))
    sim.add(RunUp("runup", (length, 0.0), top, still_level=depth),
            probes.WallForce("Fx_wall", "wall", axis=0),
            WallPressureForce("Fx_wall_p", (length, 0.0), (length + (depth + 2 * height) * run, depth + 2 * height),
                              outward=normal_out, axis=0, n=max(20, int(round((depth + 2 * height) / dx)))))
    for k, yp in enumerate(_floats(params["probe_y"], "probe_y")):
        sim.add(probes.WallPressure(f"P{k}", (length + yp * run, yp)))
    sim.add(_PaddleX("paddle_x", paddle), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "solitary-wave", "depth": depth, "height": height, "rho0": rho0, "g": GRAVITY,
                     "static_force": static, "wall_angle": angle, "wall_x": length, "paddle": paddle,
                     "stroke": paddle.stroke, "c": paddle.c}
    return sim


class _PaddleX(probes.Probe):
    def __init__(self, name, paddle):
        super().__init__(name)
        self.paddle = paddle

    def sample(self, sim):
        return float(self.paddle.displacement(sim.time)[0]) if self.paddle is not None else 0.0


#: wave cases: artificial viscosity alpha = 0.01 (half the tanks' 0.02): its dissipation accumulates
#: over a long propagation (measured: a solitary wave at d/10 keeps 90 % instead of 87 % of its height
#: over 10 d with 0.01 instead of 0.02; docs/waves.md)
WAVE_COMMON = {**COMMON,
               "alpha": Parameter(0.01, "artificial viscosity alpha"),
               "depth": Parameter(0.25, "still-water depth d [m]"),
               "height": Parameter(0.075, "solitary wave height H [m]"),
               "wall_height": Parameter(0.75, "height of the end wall and the piston [m]"),
               "wall_angle": Parameter(90.0, "angle between floor and end wall inside the water [deg]"),
               "probe_y": Parameter("", "heights of wall pressure probes on the end wall [m], comma-separated", str)}

SOLITARY_WAVE = Case(
    name="solitary-wave",
    description="Goring piston wave maker, solitary wave along a flume of constant depth to an end wall",
    builder=build_solitary_flume,
    parameters={**WAVE_COMMON,
                "length": Parameter(5.0, "flume length from the piston to the end wall's toe [m]"),
                "gauges": Parameter("1.25,2.5,3.75", "surface gauge positions [m], comma-separated", str)},
    t_end=5.0, probe_every=5e-3, output_every=0.05)

SOLITARY_SEAWALL = Case(
    name="solitary-seawall",
    description="[Huang2019] sec. 4.3: solitary wave (H 0.15 m, d 0.25 m) on a wall leaning at 120 deg, probes P0/P1",
    builder=lambda p, w, t: build_solitary_flume(p, w, t, "solitary-seawall"),
    parameters={**WAVE_COMMON,
                "height": Parameter(0.15, "solitary wave height H [m]"),
                "wall_angle": Parameter(120.0, "angle between floor and end wall inside the water [deg]"),
                "dx": Parameter(0.01, "particle spacing [m]"),
                "length": Parameter(10.0, "flume length from the piston to the end wall's toe [m]"),
                "probe_y": Parameter("0.05,0.15", "heights of the wall pressure probes [m]", str),
                "gauges": Parameter("2,4,6,8", "surface gauge positions [m], comma-separated", str)},
    t_end=7.0, probe_every=5e-3, output_every=0.05)

SOLITARY_RUNUP = Case(
    name="solitary-runup",
    description="solitary wave run-up on a vertical wall at constant depth (Chan & Street 1970 sweep of H/d)",
    builder=lambda p, w, t: build_solitary_flume(p, w, t, "solitary-runup"),
    parameters={**WAVE_COMMON,
                "length": Parameter(4.0, "flume length from the piston to the wall [m]"),
                "gauges": Parameter("2", "surface gauge positions [m], comma-separated", str)},
    t_end=5.0, probe_every=5e-3, output_every=0.05)


# ---------------------------------------------------------------- movable seawall
def build_movable_seawall(params, wall_model, threads):
    depth = require_positive("depth", params["depth"])
    height = require_positive("height", params["height"])
    dx, h = _common(params)
    x0 = snap(require_positive("wall_x", params["wall_x"]), dx)
    wall_h = snap(require_positive("wall_height", params["wall_height"]), dx)
    mass = require_positive("mass", params["mass"])
    stiffness = float(params["stiffness"])
    paddle = GoringPaddle(height, depth)
    c0 = _paddle_c0(params, depth, height)
    rho0 = params["rho0"]
    kernel = CubicSpline()
    layers = wall_layers(kernel, h, dx)
    floor_end = snap(x0 + params["floor_extra"], dx)
    model = _dbc_hydrostatic(wall_model(), depth, rho0)
    _layered(model, "movable-seawall")
    tank = shapes.polyline_wall([(0.0, wall_h), (0.0, 0.0), (floor_end, 0.0)], dx, layers=layers, side="right")
    x, y = tank.positions[:, 0], tank.positions[:, 1]
    is_piston = (x < 0.0) & (y > 0.25 * dx)
    seawall = shapes.polyline_wall([(x0, 0.0), (x0, wall_h)], dx, layers=layers, side="right")
    fluid = _fluid(shapes.rectangle((0.0, 0.0), (x0, depth), dx), params, c0=c0, pressure=_hydrostatic(depth, rho0, 2))
    static = 0.5 * rho0 * GRAVITY * depth ** 2
    spring = SpringWall("seawall", mass=mass, stiffness=stiffness, static_force=static,
                        threshold_ratio=params["threshold_ratio"])
    systems = [fluid,
               WallSystem(tank.subset(~is_piston), model=model, name="tank"),
               WallSystem(tank.subset(is_piston), model=_dbc_hydrostatic(wall_model(), depth, rho0), name="piston",
                          movement=paddle_motion(paddle) if params["wave"] else None),
               WallSystem(seawall, model=_dbc_hydrostatic(wall_model(), depth, rho0), name="seawall"),
               spring]
    margin = (layers + 3) * dx
    sim = Simulation(systems, kernel=kernel, h=h, gravity=_gravity(2),
                     integrator=Symplectic(cfl=params["cfl"], dt=params["dt"] or None), threads=threads,
                     domain=((-margin, -margin), (floor_end + margin, wall_h + 2 * depth)))
    sim.add(probes.WallForce("Fx_wall", "seawall", axis=0),
            _Scaled("F_star", probes.WallForce("_F", "seawall", axis=0), 1.0 / static),
            WallPressureForce("Fx_wall_p", (x0, 0.0), (x0, wall_h), outward=(1.0, 0.0), n=int(round(wall_h / dx)),
                              follow="seawall"),
            _CouplingValue("wall_x", spring, "displacement", offset=x0),
            _CouplingValue("x_star", spring, "displacement", scale=1.0 / depth),
            RunUp("runup", (x0, 0.0), (x0, wall_h), still_level=depth, follow="seawall"),
            FollowingWallPressure("P_foot", (x0, 0.02), "seawall"),
            SurfaceGauge("eta_1", 1.0, still_level=depth),
            _PaddleX("paddle_x", paddle if params["wave"] else None), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "movable-seawall", "depth": depth, "height": height, "static_force": static,
                     "wall_x0": x0, "threshold": spring.threshold, "paddle": paddle}
    return sim


class _Scaled(probes.Probe):
    def __init__(self, name, probe, scale):
        super().__init__(name)
        self.probe, self.scale = probe, scale

    def sample(self, sim):
        return self.scale * self.probe.sample(sim)


class _CouplingValue(probes.Probe):
    def __init__(self, name, coupling, attribute, offset=0.0, scale=1.0):
        super().__init__(name)
        self.coupling, self.attribute, self.offset, self.scale = coupling, attribute, offset, scale

    def sample(self, sim):
        return self.offset + self.scale * float(getattr(self.coupling, self.attribute))


MOVABLE_SEAWALL = Case(
    name="movable-seawall",
    description="[Huang2019] sec. 4.4: solitary wave on a spring-mounted seawall at x = 2.5 m (m 250 kg/m, k 10 N/m)",
    builder=build_movable_seawall,
    parameters={**COMMON,
                "alpha": Parameter(0.01, "artificial viscosity alpha"),
                "dx": Parameter(0.008, "particle spacing [m]"),
                "depth": Parameter(0.20, "still-water depth d [m]"),
                "height": Parameter(0.10, "solitary wave height H [m] (not given by the seed; our choice)"),
                "wall_x": Parameter(2.50, "initial position of the seawall x0 [m]"),
                "wall_height": Parameter(0.6, "height of the seawall and the piston [m]"),
                "floor_extra": Parameter(1.5, "floor length behind the seawall [m]"),
                "mass": Parameter(250.0, "seawall mass per metre [kg/m]"),
                "stiffness": Parameter(10.0, "spring stiffness k [N/m per metre]"),
                "threshold_ratio": Parameter(1.10, "F_threshold / F_static"),
                "dt": Parameter(0.0, "fixed time step [s] (0 = adaptive CFL)"),
                "wave": Parameter(True, "move the wave maker (false: still water, the hydrostatic check)", bool)},
    t_end=4.0, probe_every=5e-3, output_every=0.05)
