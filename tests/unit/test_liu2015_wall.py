"""Liu et al. (2015) dummy wall ([Liu2015] eq. 21-29) and the Liu et al. (2012) boundary force, on hand-built set-ups."""

import math

import numpy as np
import pytest

from seawall import shapes
from seawall.boundary.base import EvaluationContext, WallSystem
from seawall.boundary.liu2012 import Liu2012Force, liu2012_factor, liu2012_shape
from seawall.boundary.liu2015 import Liu2015Wall
from seawall.errors import ParameterError
from seawall.fluid.presets import liu2015
from seawall.simulation import Simulation

DX = 0.01


def _rotated_setup(dim, angle, *, tilt=0.3, slip="free", n_fluid=4, jitter=0.0):
    """A wall of 3 layers below the plane n . x = 0 and fluid above it, lattice and normal rotated by ``angle``.

    Returns (simulation, wall system, unit normal n, a unit tangent t).
    """
    rng = np.random.default_rng(1)
    c, s = math.cos(angle), math.sin(angle)
    if dim == 2:
        rot = np.array([[c, -s], [s, c]])
        span = [np.arange(-8, 9)]
    else:
        ct, st = math.cos(tilt), math.sin(tilt)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.array([[1, 0, 0], [0, ct, -st], [0, st, ct]])
        span = [np.arange(-5, 6), np.arange(-5, 6)]
    normal = rot[:, -1].copy()
    tangent = rot[:, 0].copy()

    def lattice(heights):
        grids = np.meshgrid(*span, heights, indexing="ij")
        local = np.stack([g.ravel() for g in grids], axis=1).astype(float) * DX
        return local @ rot.T

    wall_pos = lattice(np.array([-0.5, -1.5, -2.5]))
    fluid_pos = lattice(np.arange(n_fluid) + 0.5)
    fluid_pos += jitter * DX * rng.uniform(-1, 1, fluid_pos.shape)
    normals = np.tile(normal, (wall_pos.shape[0], 1))
    surface = wall_pos - np.outer(wall_pos @ normal, normal)
    wall_shape = shapes.Shape(wall_pos, DX, normals, surface, np.zeros(wall_pos.shape[0], dtype=int))
    preset = liu2015(10.0, h_factor=1.3)
    fluid = preset.fluid(shapes.Shape(fluid_pos, DX), rho0=1000.0)
    model = Liu2015Wall(slip=slip)
    wall = WallSystem(wall_shape, model=model, name="wall")
    lo = np.minimum(wall_pos.min(axis=0), fluid_pos.min(axis=0)) - 0.1
    hi = np.maximum(wall_pos.max(axis=0), fluid_pos.max(axis=0)) + 0.1
    sim = Simulation([fluid, wall], kernel=preset.kernel, h=1.3 * DX, integrator=preset.integrator, domain=(lo, hi),
                     threads=1)
    sim.evaluate(0.0)
    return sim, wall, normal, tangent


def _wall_terms(sim, wall):
    """The wall's contribution to dv and drho at the current state (pressures as currently stored)."""
    fp = sim.fluid.particles
    dv = np.zeros_like(fp["v"])
    drho = np.zeros(fp.n)
    ctx = EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.fluid_cells, time=sim.time,
                            dx=sim.fluid.spacing)
    wall.model.interact(sim.fluid, wall, ctx, dv, drho)
    return dv, drho


@pytest.mark.parametrize("dim", [2, 3])
def test_wall_force_is_along_the_normal_and_repulsive(dim):
    sim, wall, n, _ = _rotated_setup(dim, 0.37, jitter=0.2)
    fp = sim.fluid.particles
    wall.particles["p"][:] = 100.0
    fp["p"][:] = 50.0 + 30.0 * np.random.default_rng(2).uniform(size=fp.n)
    dv, _ = _wall_terms(sim, wall)
    along = dv @ n
    across = dv - np.outer(along, n)
    near = along > 0.0
    assert near.sum() >= 10                                # the first rows of fluid are pushed
    assert np.all(along >= 0.0)                            # repulsive only: never towards the wall
    assert np.abs(across).max() <= 1e-12 * np.abs(along).max()


def test_no_wall_force_when_pressure_sum_is_not_positive():
    sim, wall, n, _ = _rotated_setup(2, 0.37, jitter=0.2)
    fp = sim.fluid.particles
    wall.particles["p"][:] = 100.0
    fp["p"][:] = -100.0                                    # P_i + P_b = 0
    dv, _ = _wall_terms(sim, wall)
    assert np.all(dv == 0.0)
    fp["p"][:] = -250.0                                    # P_i + P_b < 0: no attraction either
    dv, _ = _wall_terms(sim, wall)
    assert np.all(dv == 0.0)
    fp["p"][:] = -99.0                                     # just positive: a (small) push
    dv, _ = _wall_terms(sim, wall)
    assert (dv @ n).max() > 0.0


@pytest.mark.parametrize("slip", ["free", "noslip"])
@pytest.mark.parametrize("dim", [2, 3])
def test_tangential_motion_gets_no_density_change_from_the_wall(dim, slip):
    sim, wall, n, t = _rotated_setup(dim, 0.37, slip=slip, jitter=0.2)
    fp = sim.fluid.particles
    fp["v"][:] = 0.7 * t
    sim.evaluate(0.0)                                      # the no-slip dummy velocity follows the fluid
    _, drho = _wall_terms(sim, wall)
    # the same particles approaching the wall at 0.1 m/s do get compressed by it
    fp["v"][:] = -0.1 * n
    sim.evaluate(0.0)
    _, drho_normal = _wall_terms(sim, wall)
    assert drho_normal.max() > 0.0 and drho_normal.min() >= 0.0
    assert np.abs(drho).max() <= 1e-12 * drho_normal.max()


def test_literal_conditional_continuity_does_count_tangential_motion():
    """The alternative reading of eq. 21 (full term whenever v_ib . n_b != 0) is not normal-only."""
    sim, wall, n, t = _rotated_setup(2, 0.37, jitter=0.2)
    wall.model.continuity = "conditional"
    fp = sim.fluid.particles
    fp["v"][:] = 0.7 * t + 1e-3 * n
    _, drho = _wall_terms(sim, wall)
    wall.model.continuity = "normal"
    _, drho_normal = _wall_terms(sim, wall)
    assert np.abs(drho).max() > 10.0 * np.abs(drho_normal).max()


@pytest.mark.parametrize("dim", [2, 3])
def test_noslip_normal_velocity_mirror_doubles_the_approach_and_wall_keeps_it(dim):
    """Eq. 21 with no slip: the mirrored dummy velocity (eq. 29) sees uniform fluid approaching the wall at
    twice its speed; ``normal_velocity="wall"`` gives the free-slip wall's density rate."""
    rates = {}
    for slip, normal in (("free", "mirror"), ("noslip", "mirror"), ("noslip", "wall")):
        sim, wall, n, t = _rotated_setup(dim, 0.37, slip=slip, jitter=0.2)
        wall.model.normal_velocity = normal
        sim.fluid.particles["v"][:] = -0.1 * n + 0.3 * t
        sim.evaluate(0.0)                                  # the dummy velocities follow the fluid
        rates[slip, normal] = _wall_terms(sim, wall)[1]
    free = rates["free", "mirror"]
    assert free.max() > 0.0
    np.testing.assert_allclose(rates["noslip", "wall"], free, rtol=1e-12, atol=1e-12 * free.max())
    np.testing.assert_allclose(rates["noslip", "mirror"], 2.0 * free, rtol=1e-9, atol=1e-9 * free.max())


def test_normal_velocity_option_is_checked():
    with pytest.raises(ParameterError, match="normal_velocity"):
        Liu2015Wall(slip="noslip", normal_velocity="fluid")
    with pytest.raises(ParameterError, match="continuity='normal'"):
        Liu2015Wall(slip="noslip", normal_velocity="wall", continuity="conditional")


def _has_fluid_neighbour(sim, x):
    xf = sim.fluid.particles["x"]
    support = sim.kernel.support(sim.h)
    d2 = ((x[:, None, :] - xf[None, :, :]) ** 2).sum(axis=2)
    return (d2 < support * support).any(axis=1)


def _tank(velocity=None, wall_velocity=None):
    depth = 0.2
    preset = liu2015(20.0, h_factor=1.3)
    rho0, g = 1000.0, 9.81
    fluid = preset.fluid(shapes.rectangle((0.0, 0.0), (0.3, depth), DX), rho0=rho0,
                         pressure=lambda x: rho0 * g * (depth - x[:, 1]), velocity=velocity)
    wall = WallSystem(shapes.tank((0.0, 0.0), (0.3, 0.3), DX, layers=3), model=Liu2015Wall(), name="tank",
                      velocity=wall_velocity)
    sim = Simulation([fluid, wall], kernel=preset.kernel, h=1.3 * DX, gravity=(0.0, -g),
                     integrator=preset.integrator, threads=1)
    sim.evaluate(0.0)
    return sim, wall, depth, rho0, g


def test_taylor_cspm_dummy_pressure_reproduces_hydrostatics():
    sim, wall, depth, rho0, g = _tank()
    x = wall.particles["x"]
    p = wall.particles["p"]
    # dummy particles that see fluid, away from the free surface
    wet = (x[:, 1] < depth - 3 * DX) & _has_fluid_neighbour(sim, x)
    exact = rho0 * g * (depth - x[:, 1])
    assert wet.sum() > 100
    err = np.abs(p[wet] - exact[wet]).max()
    # exact up to rho_j / rho0 - 1 (<= 0.5 % here) times the extrapolation distance
    assert err < 2e-3 * rho0 * g * depth
    # the floor's dummy pressure exceeds the bottom fluid pressure: a pushing, not a pulling, wall
    floor = (x[:, 1] < 0.0) & wet
    assert np.all(p[floor] >= rho0 * g * depth * 0.99)


def test_dummy_pressure_adds_rho_c_vn_for_fluid_moving_into_the_wall():
    u = 0.05
    sim_still, wall_still, depth, rho0, g = _tank()
    sim_move, wall_move, *_ = _tank(velocity=(0.0, -u))
    x = wall_move.particles["x"]
    wet = (x[:, 1] < 0.0) & (x[:, 0] > 3 * DX) & (x[:, 0] < 0.3 - 3 * DX) & _has_fluid_neighbour(sim_move, x)
    assert wet.sum() > 40
    rise = wall_move.particles["p"][wet] - wall_still.particles["p"][wet]
    # rho_j c_s u with rho_j within 0.5 % of rho0
    assert np.allclose(rise, rho0 * 20.0 * u, rtol=1e-2)


def test_a_sliding_wall_has_no_normal_velocity_even_at_diagonal_corner_normals():
    # a wall given only a (tangential) velocity stays put: its surface has no normal velocity, so eq. 26's
    # c_s term and eq. 21 must not see v_w . n where the corner normals are diagonal (the cavity lid's corners)
    sim_still, wall_still, *_ = _tank()
    sim_slide, wall_slide, *_ = _tank(wall_velocity=(0.1, 0.0))
    x = wall_slide.particles["x"]
    wet = _has_fluid_neighbour(sim_slide, x)
    corner = wet & (x[:, 1] < 0.0) & ((x[:, 0] < 0.0) | (x[:, 0] > 0.3))
    assert corner.sum() >= 4
    assert np.array_equal(wall_slide.particles["p"][wet], wall_still.particles["p"][wet])
    assert np.array_equal(sim_slide.fluid.particles["drho"], sim_still.fluid.particles["drho"])


def test_liu2015_needs_wall_normals():
    fluid = liu2015(10.0).fluid(shapes.rectangle((0.0, 0.0), (0.1, 0.1), DX))
    bare = shapes.Shape(shapes.tank((0.0, 0.0), (0.1, 0.2), DX).positions, DX)
    with pytest.raises(ParameterError, match="normals"):
        Simulation([fluid, WallSystem(bare, model=Liu2015Wall())], h=1.3 * DX)
    with pytest.raises(ParameterError, match="slip"):
        Liu2015Wall(slip="sticky")
    with pytest.raises(ParameterError, match="continuity"):
        Liu2015Wall(continuity="maybe")


def test_liu2012_force_shape():
    # f(eta) is continuous at 2/3 and 1 and vanishes at 2
    for eta in (2.0 / 3.0, 1.0):
        assert liu2012_shape(eta - 1e-12) == pytest.approx(liu2012_shape(eta + 1e-12), abs=1e-9)
    assert liu2012_shape(2.0) == 0.0
    h, dd, c = 0.013, 0.01, 10.0
    r = np.linspace(1e-4, 1.2 * dd, 200)
    s = np.array([liu2012_factor(q, h, dd, c) for q in r])
    assert np.all(s[r < dd] > 0.0) and np.all(s[r >= dd] == 0.0)   # repulsive, acting within dd only
    # 0.01 c^2 chi f(eta) / r at r = dd / 2, eta = 0.5 dd / (0.75 h) <= 2/3
    q = 0.5 * dd
    assert liu2012_factor(q, h, dd, c) * q == pytest.approx(0.01 * c * c * 0.5 * (2.0 / 3.0) / q)
    with pytest.raises(ParameterError):
        Liu2012Force(beta=0.0)
