"""Filling of an S-shaped cavity through an inflow ([Liu2015], sec. 4.3; Schmid & Klein's water model).

[Liu2015] fills a horizontal die-casting cavity of round and square bends
with water entering at v_in = 8.7 m/s from an inlet at its bottom (no
gravity, free slip, dx = 1 mm, h = 1.2 dx, c = 20 v_in = 174 m/s, 3 wall
layers). Its Fig. 8 gives the shape only as a drawing, so this is an
S-shaped (serpentine) cavity of the same kind and size, in millimetres:

* three horizontal legs 30 wide: bottom y = 0..30 (x = 0..135, flowing +x),
  middle y = 60..90 (x = 30..135, flowing -x), top y = 120..150 (x = 0..180,
  flowing +x, closed at x = 180);
* a ROUND 180 degree bend joining bottom and middle legs: outer radius 45,
  inner radius 15 (a half-round core end), both centred at (135, 45);
* a SQUARE bend joining middle and top legs at x = 0..30, y = 90..120;
* the gate: a straight inlet channel x = 0..30 below the bottom leg, whose
  first 10 mm (y = -10..0) hold water at t = 0; the inflow zone lies below
  y = -10 (its plane is the segment (0, -10) - (30, -10), flow +y).

Cavity area 17 227 mm^2 (without the gate), so the cavity is full after
about 17227 / (8.7 * 30) = 66 ms at the nominal inflow. The seed's run had
about 24 300 fluid particles at the end and 4383 wall particles; this one
has ~17 500 and ~4400 at dx = 1 mm.

Probes: ``fill`` (fluid area / cavity area), ``front`` (how far the water
has reached along the cavity's centre line [m], spray excluded),
``spray_front`` (the same for the foremost particle), ``max_speed`` (largest
fluid speed [m/s]), ``speed_p99`` (99th percentile of the speed) and
``mass_in`` (mass that entered [kg/m]).
"""

import math

import numpy as np

from .. import probes, shapes
from ..boundary.base import WallSystem
from ..eos import Tait
from ..errors import require_positive
from ..fluid import ArtificialViscosity, DeltaSPH, FluidSystem, LaminarViscosity
from ..integrators import Symplectic
from ..kernels import CubicSpline
from ..openboundary import FluidCount, InFlow, MaxSpeed, OpenBoundary, ZoneInflow
from ..simulation import Simulation
from .base import Case, Parameter

MM = 1e-3
WIDTH = 30.0          # leg width [mm]
GATE = 10.0           # length of the gate channel initially full of water [mm]
CAVITY_AREA = (135 * 90 - 135 * 30) + 0.5 * math.pi * (45 ** 2 - 15 ** 2) + 30 * 30 + 180 * 30   # mm^2


def _arc(centre, radius, a0, a1, step):
    n = max(2, int(math.ceil(abs(a1 - a0) * radius / step)))
    ang = np.linspace(a0, a1, n + 1)
    return np.column_stack([centre[0] + radius * np.cos(ang), centre[1] + radius * np.sin(ang)])


def cavity_outline(bottom, step=1.0):
    """Wall polyline of the cavity in mm (fluid on the left when walking along it), from the gate's right side."""
    pts = [np.array([[30.0, bottom], [30.0, 0.0]]),
           _arc((135.0, 45.0), 45.0, -0.5 * math.pi, 0.5 * math.pi, step),       # round bend, outer wall
           np.array([[30.0, 90.0], [30.0, 120.0], [180.0, 120.0], [180.0, 150.0], [0.0, 150.0], [0.0, 60.0]]),
           _arc((135.0, 45.0), 15.0, 0.5 * math.pi, -0.5 * math.pi, step),       # round bend, core end
           np.array([[0.0, 30.0], [0.0, bottom]])]
    return np.concatenate(pts)


def centre_line():
    """Centre line of the gate and the three legs in mm, from the inflow plane to the closed end."""
    return np.concatenate([np.array([[15.0, -GATE], [15.0, 15.0]]),
                           _arc((135.0, 45.0), 30.0, -0.5 * math.pi, 0.5 * math.pi, 2.0),
                           np.array([[15.0, 75.0], [15.0, 135.0], [180.0, 135.0]])])


def arc_length_along(points, line):
    """Arc length along the polyline ``line`` of the closest point to each of ``points``."""
    seg = np.diff(line, axis=0)
    seg_len = np.linalg.norm(seg, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg_len)])
    best = np.full(points.shape[0], np.inf)
    s_best = np.zeros(points.shape[0])
    for k in range(seg.shape[0]):
        t = np.clip(((points - line[k]) @ seg[k]) / seg_len[k] ** 2, 0.0, 1.0)
        d2 = np.sum((points - line[k] - t[:, None] * seg[k]) ** 2, axis=1)
        better = d2 < best
        best[better] = d2[better]
        s_best[better] = cum[k] + t[better] * seg_len[k]
    return s_best


class FillFront(probes.Probe):
    """How far the water has reached along the cavity's centre line [m].

    The centre line is cut into 5 mm bins; the front is the far end of the
    last bin holding at least a quarter of the particles of a full bin (so
    that spray flying ahead does not count). With ``spray=True`` the probe
    gives the arc length of the foremost fluid particle instead.
    """

    def __init__(self, name="front", spray=False):
        super().__init__(name)
        self._line = centre_line() * MM
        self.spray = bool(spray)

    def sample(self, sim):
        fp = sim.fluid.particles
        x = fp["x"][fp["zone"] < 0]
        if x.shape[0] == 0:
            return 0.0
        s = arc_length_along(x, self._line)
        if self.spray:
            return float(s.max())
        dx = sim.fluid.spacing
        bin_len = 5.0 * MM
        counts = np.bincount(np.floor(s / bin_len).astype(np.int64))
        full = WIDTH * MM * bin_len / dx ** 2
        filled = np.flatnonzero(counts >= 0.25 * full)
        return float((filled[-1] + 1) * bin_len) if filled.size else 0.0


class SpeedPercentile(probes.Probe):
    """The q-th percentile of the fluid particles' speed [m/s] (q = 100: the largest)."""

    def __init__(self, name, q):
        super().__init__(name)
        self.q = float(q)

    def sample(self, sim):
        fp = sim.fluid.particles
        v = fp["v"][fp["zone"] < 0]
        return float(np.percentile(np.sqrt((v * v).sum(axis=1)), self.q)) if v.shape[0] else 0.0


class FillFraction(probes.Probe):
    """Area of the fluid particles above the gate (n dx^2) over the cavity area."""

    def __init__(self, name="fill"):
        super().__init__(name)

    def sample(self, sim):
        fp = sim.fluid.particles
        inside = (fp["zone"] < 0) & (fp["x"][:, 1] > 0.0)
        return float(np.count_nonzero(inside) * sim.fluid.spacing ** 2 / (CAVITY_AREA * MM * MM))


def build_s_cavity(params, wall_model, threads):
    dx = params["dx"]
    if dx is None:
        dx = params["dx"] = 1e-3
    dx = require_positive("dx", dx)
    v_in = require_positive("v_in", params["v_in"])
    c0 = params["c0"] or 20.0 * v_in
    params["c0"] = c0
    h = require_positive("h_factor", params["h_factor"]) * dx
    rho0 = require_positive("rho0", params["rho0"])
    kernel = CubicSpline()
    layers = params["layers"]
    depth = layers * dx
    gate = GATE * MM
    fluid = FluidSystem(shapes.rectangle((0.0, -gate), (WIDTH * MM, 0.0), dx), rho0=rho0,
                        eos=Tait(c0=c0, gamma=7.0), velocity=(0.0, v_in),
                        viscosity=[ArtificialViscosity(alpha=params["alpha"]), LaminarViscosity(nu=params["nu"])],
                        density_diffusion=DeltaSPH(delta=params["delta"]) if params["delta"] > 0 else None)
    inflow = InFlow(plane=((0.0, -gate), (WIDTH * MM, -gate)), flow_direction=(0.0, 1.0),
                    open_boundary_layers=layers, particle_spacing=dx, density=rho0,
                    reference_velocity=(0.0, v_in), reference_pressure=0.0, name="gate")
    buffer_size = params["buffer_size"] or int(1.2 * CAVITY_AREA * MM * MM / dx ** 2)
    boundary = OpenBoundary(inflow, fluid_system=fluid, buffer_size=buffer_size)
    bottom = -(GATE + 2.0) * MM - depth
    outline = cavity_outline(bottom / MM, step=dx / MM) * MM
    walls = WallSystem(shapes.polyline_wall(outline, dx, layers=params["wall_layers"], side="right"),
                       model=wall_model(), name="cavity")
    support = kernel.support(h)
    margin = params["wall_layers"] * dx + 2 * support
    domain = ((-margin, bottom - margin), (180.0 * MM + margin, 150.0 * MM + margin))
    sim = Simulation([fluid, walls, boundary], kernel=kernel, h=h, integrator=Symplectic(cfl=params["cfl"]),
                     domain=domain, threads=threads)
    sim.add(FillFraction(), FillFront(), FillFront("spray_front", spray=True), MaxSpeed(),
            SpeedPercentile("speed_p99", 99.0), ZoneInflow("mass_in", boundary, 0), FluidCount())
    sim.open_boundary = boundary
    sim.reference = {"type": "s-cavity", "v_in": v_in, "width": WIDTH * MM, "cavity_area": CAVITY_AREA * MM * MM,
                     "rho0": rho0, "fill_time_nominal": CAVITY_AREA / (v_in * 1e3 * WIDTH)}
    return sim


S_CAVITY = Case(
    name="s-cavity",
    description="filling of an S-shaped cavity (round and square bends) through an inflow at 8.7 m/s "
                "([Liu2015] sec. 4.3), no gravity",
    builder=build_s_cavity,
    parameters={
        "dx": Parameter(None, "particle spacing [m] ([Liu2015]: 1 mm)"),
        "h_factor": Parameter(1.2, "smoothing length h / dx ([Liu2015]: 1.2)"),
        "v_in": Parameter(8.7, "inflow velocity [m/s] ([Liu2015]: 8.7)"),
        "c0": Parameter(None, "speed of sound [m/s] (default 20 v_in = 174, [Liu2015])"),
        "alpha": Parameter(0.02, "artificial viscosity alpha"),
        "nu": Parameter(1e-6, "kinematic viscosity [m^2/s] (water)"),
        "delta": Parameter(0.1, "delta-SPH diffusion coefficient (0 = off)"),
        "cfl": Parameter(0.2, "CFL number"),
        "rho0": Parameter(1000.0, "reference density [kg/m^3]"),
        "layers": Parameter(4, "particle layers of the inflow zone", int),
        "wall_layers": Parameter(3, "wall particle layers ([Liu2015]: 3)", int),
        "buffer_size": Parameter(0, "spare particles (0 = 1.2 x the cavity's particle count)", int),
    },
    t_end=0.065, probe_every=5e-4, output_every=5e-3)
