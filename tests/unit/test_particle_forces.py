"""The fluid's force on each wall particle (seawall.boundary.particle_forces), written as the wall VTU field
``force``: it sums to the wall's total force, changes nothing in the run, and is the pair reaction."""

import glob

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.particle_forces import defines_particle_forces, wall_colours
from seawall.boundary.registry import BOUNDARIES, boundary_by_name
from seawall.io import read_vtu, read_vtu_metadata

PAIRWISE = [b for b in BOUNDARIES if type(boundary_by_name(b)).pairwise_momentum]


def tank(boundary):
    return sw.cases.build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3, boundary=boundary)


@pytest.mark.parametrize("boundary", PAIRWISE)
def test_wall_particle_forces_sum_to_the_wall_force_and_change_nothing(boundary, tmp_path):
    with_field = tank(boundary)
    with_field.add(sw.output.VTK(str(tmp_path / "vtk"), every=0.004))
    with_field.run(0.01, progress=False)
    frames = sorted(glob.glob(str(tmp_path / "vtk" / "wall_tank_*.vtu")))
    assert len(frames) >= 3                                       # t = 0, the output times, the end
    for frame in frames:
        _, data = read_vtu(frame)
        total = np.asarray(read_vtu_metadata(frame)["wall_force"])
        force = data["force"][:, :2]
        # the same pair reactions summed in another order: equal to rounding
        assert np.allclose(force.sum(axis=0), total, rtol=0.0, atol=1e-11 * np.abs(total).max())
        assert np.abs(total[1]) > 0.0
    # the per-particle forces use scratch arrays only: the run is bit for bit the run without them
    plain = tank(boundary)
    plain.run(0.01, progress=False)
    for name in ("x", "v", "rho"):
        assert np.array_equal(with_field.fluid.particles[name], plain.fluid.particles[name]), name


def test_colour_classes_keep_two_supports_apart():
    sim = tank("adami")
    wall = sim.walls[0]
    colours = wall_colours(wall, sim.grid)
    x = wall.particles["x"]
    reach = 2.0 * sim.grid.radius
    for c in range(colours.max() + 1):
        members = x[colours == c]
        d = np.sqrt(((members[:, None, :] - members[None, :, :]) ** 2).sum(axis=2))
        np.fill_diagonal(d, np.inf)
        assert d.min() >= reach
    # greedy colouring of a 3-layer 2D wall: a few tens of classes (measured 21 at dx 0.05, h 1.3 dx)
    assert colours.max() + 1 < 60


def test_floor_carries_the_weight_of_still_water(tmp_path):
    """Water at rest on the floor: the floor particles' forces point down and add up to about the weight."""
    sim = tank("adami")
    sim.add(sw.output.VTK(str(tmp_path), every=1.0))
    sim.run(0.002, progress=False)
    x, data = read_vtu(str(tmp_path / "wall_tank_00000.vtu"))
    force = data["force"]
    floor = x[:, 1] < 0.0
    sides = ~floor
    weight = sim.fluid.particles["m"].sum() * 9.81
    # side-wall particles below the floor's level belong to the floor here (the corners)
    assert force[floor, 1].sum() == pytest.approx(-weight, rel=0.01)     # measured 0.1 % above the weight
    assert np.all(force[floor, 1] <= 1e-9 * weight)               # no floor particle pulls the water down
    # the two side walls push outwards equally (a symmetric tank)
    left, right = sides & (x[:, 0] < 0.25), sides & (x[:, 0] > 0.25)
    assert force[left, 0].sum() < 0.0 < force[right, 0].sum()
    assert force[left, 0].sum() == pytest.approx(-force[right, 0].sum(), rel=1e-9)


def test_no_force_field_with_adhesion():
    sim = tank("adami")
    sim.walls[0].adhesion_coefficient = 0.5
    assert not defines_particle_forces(sim.walls[0])
    assert defines_particle_forces(tank("adami").walls[0])
