"""A piston wall pushing water in a tank (issue 3's ``moving-wall`` case).

The left wall of a tank (the wall particles above the floor) moves as a
piston, x(t) = x0 + A (1 - cos(2 pi t / T)) / 2: it starts from rest, pushes
in by A and comes back. Probes: the horizontal force of the water on the
piston (``Fx``), the piston displacement, wall pressure at its foot.
"""

import math

from .. import probes
from ..boundary.base import WallSystem
from ..boundary.movement import PrescribedMotion, sinusoidal_piston
from ..errors import require_positive
from ..integrators import Symplectic
from ..kernels import CubicSpline
from ..simulation import Simulation
from .base import GRAVITY, Case, Parameter, tank_wall
from .tanks import COMMON, _fluid, _gravity, _hydrostatic, _common, snap


class PistonDisplacement(probes.Probe):
    """Displacement of the piston along x [m] at the sampling time."""

    #: a function of time alone: every rank of a decomposed run computes the same value
    mpi_reduction = "global"

    def __init__(self, name, displacement):
        super().__init__(name)
        self._displacement = displacement

    def sample(self, sim):
        return float(self._displacement(sim.time)[0])


def build_moving_wall(params, wall_model, threads):
    depth = require_positive("depth", params["depth"])
    if params["dx"] is None:
        params["dx"] = depth / 15.0
    dx, h = _common(params)
    length = snap(require_positive("length", params["length"]), dx)
    amplitude = require_positive("amplitude", params["amplitude"])
    period = require_positive("period", params["period"])
    c0 = params["c0"] or 10.0 * max(math.sqrt(2 * GRAVITY * depth), math.pi * amplitude / period)
    params["c0"] = c0
    kernel = CubicSpline()
    from .. import shapes

    fluid = _fluid(shapes.rectangle((0.0, 0.0), (length, depth), dx), params, c0=c0,
                   pressure=_hydrostatic(depth, params["rho0"], 2))
    tank_model = wall_model()
    walls = tank_wall(tank_model, (0.0, 0.0), (length, snap(1.6 * depth, dx)), dx, kernel, h)
    x, y = walls.positions[:, 0], walls.positions[:, 1]
    is_piston = (x < 0.25 * dx) & (y > 0.25 * dx)   # the left wall above the floor
    displacement, velocity, acceleration = sinusoidal_piston(amplitude, period)
    piston = WallSystem(walls.subset(is_piston), model=wall_model(), name="piston",
                        movement=PrescribedMotion(displacement, velocity=velocity, acceleration=acceleration))
    tank = WallSystem(walls.subset(~is_piston), model=tank_model, name="tank")
    sim = Simulation([fluid, tank, piston], kernel=kernel, h=h, gravity=_gravity(2),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads,
                     domain=((-4 * dx - amplitude, -6 * dx), (length + 6 * dx, 3.2 * depth)))
    sim.add(probes.WallForce("Fx", "piston", axis=0), PistonDisplacement("piston_x", displacement),
            probes.WallPressure("P_foot", (0.0, 0.2 * depth)), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "moving-wall", "amplitude": amplitude, "period": period, "depth": depth,
                     "rho0": params["rho0"], "g": GRAVITY, "acceleration": acceleration}
    return sim


MOVING_WALL = Case(
    name="moving-wall",
    description="piston wall (left wall) moving sinusoidally into still water; force on the piston",
    builder=build_moving_wall,
    parameters={**COMMON,
                "depth": Parameter(0.3, "water depth [m]"),
                "length": Parameter(1.0, "tank length [m]"),
                "amplitude": Parameter(0.02, "piston stroke A [m]"),
                "period": Parameter(0.5, "piston period T [s]")},
    t_end=1.0, probe_every=2e-3, output_every=0.02)
