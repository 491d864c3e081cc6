"""The modified dynamic boundary condition ([English2022]) and its corrected interpolation ([LiuLiu2006]).

Defining properties: the first-order corrected interpolation reproduces linear fields and their
gradients on irregular neighbour sets; the mDBC wall density extrapolated from the ghost node equals
a linear fluid density field at the wall particle; the Shepard fallback takes over where the
correction matrix is ill-conditioned; no slip mirrors the ghost-node velocity (v_b = 2 v_w - v_g).
"""

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.base import EvaluationContext
from seawall.boundary.interpolation import (CORRECTED_LINEAR, CORRECTED_NONE, CORRECTED_SHEPARD,
                                            corrected_point)
from seawall.boundary.mdbc import ModifiedDynamicBoundary
from seawall.boundary.registry import boundary_by_name
from seawall.errors import ParameterError
from seawall.kernels import CubicSpline, Gaussian
from seawall.neighbors import CellGrid
from tests.unit.test_interpolation import DX, half_space_cloud, physics

RHO0 = 1000.0


def _cloud(dim, kernel, seed=1):
    h = 1.3 * DX
    rng = np.random.default_rng(seed)
    xf = half_space_cloud(dim, rng)
    grid = CellGrid(xf.min(axis=0) - 0.1, xf.max(axis=0) + 0.1, kernel.support(h))
    cells = grid.build(xf)
    vol = np.full(xf.shape[0], DX ** dim) * rng.uniform(0.9, 1.1, xf.shape[0])
    return xf, vol, grid, cells, physics(kernel, h, dim), rng


def _corrected(grid, cells, prm, xf, fields, vol, points, first_order=True, det_min=1e-3):
    npt, nf = points.shape[0], fields.shape[1]
    value = np.zeros((npt, nf))
    grad = np.zeros((npt, nf, xf.shape[1]))
    how = []
    for k, p in enumerate(points):
        p3 = list(p) + [0.0] * (3 - len(p))
        _, outcome = corrected_point(grid.layout, first_order, det_min, nf, p3[0], p3[1], p3[2], xf, fields, vol,
                                     cells.start, cells.order, grid.lo, grid.inv_cell, grid.ncell, grid.period,
                                     prm, value, grad, k)
        how.append(outcome)
    return value, grad, np.array(how)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kernel", [CubicSpline(), Gaussian()], ids=["cubic", "gaussian"])
def test_corrected_interpolation_reproduces_linear_fields_and_gradients(dim, kernel):
    xf, vol, grid, cells, prm, rng = _cloud(dim, kernel)
    slope = rng.normal(size=(2, dim))
    fields = np.stack([3.0 + xf @ slope[0] / DX, -1.0 + xf @ slope[1] / DX], axis=1)
    # ghost nodes of the first three layers behind a flat wall at y = 0, and random points near the wall
    points = np.array([[0.0] * dim for _ in range(3)] + [list(rng.uniform(-3 * DX, 3 * DX, dim)) for _ in range(15)])
    points[:3, 1] = (np.arange(3) + 0.5) * DX
    points[3:, 1] = np.abs(points[3:, 1]) + 0.2 * DX
    value, grad, how = _corrected(grid, cells, prm, xf, fields, vol, points)
    assert (how == CORRECTED_LINEAR).all()
    expected = np.stack([3.0 + points @ slope[0] / DX, -1.0 + points @ slope[1] / DX], axis=1)
    np.testing.assert_allclose(value, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    np.testing.assert_allclose(grad, np.broadcast_to(slope / DX, grad.shape), rtol=1e-8)


def test_corrected_interpolation_falls_back_to_shepard():
    xf, vol, grid, cells, prm, rng = _cloud(2, CubicSpline())
    fields = (xf[:, :1] / DX) * 2.0 + 5.0
    point = np.array([[0.0, 0.5 * DX]])
    v1, _, how1 = _corrected(grid, cells, prm, xf, fields, vol, point)
    v0, g0, how0 = _corrected(grid, cells, prm, xf, fields, vol, point, det_min=1e12)
    vz, _, howz = _corrected(grid, cells, prm, xf, fields, vol, point, first_order=False)
    assert how1[0] == CORRECTED_LINEAR and how0[0] == CORRECTED_SHEPARD and howz[0] == CORRECTED_SHEPARD
    assert v0[0, 0] == pytest.approx(vz[0, 0], rel=1e-14) and not g0.any()
    # the Shepard value is the normalised kernel average, by hand
    r = np.linalg.norm(xf - point[0], axis=1)
    q = r / prm.h
    w = np.where(q < 1, 1 - 1.5 * q ** 2 + 0.75 * q ** 3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0)) * vol
    assert v0[0, 0] == pytest.approx(np.sum(w * fields[:, 0]) / np.sum(w), rel=1e-12)
    far, _, howf = _corrected(grid, cells, prm, xf, fields, vol, np.array([[0.0, -0.5]]))
    assert howf[0] == CORRECTED_NONE and far[0, 0] == 0.0


def _tank(model, dim=2, slope=None, velocity=None):
    """Still-water box in a closed 3-layer tank (dx = 0.01 m), fluid density set to a linear field
    (closed: an open tank's back faces mirror behind the tank, where there is no water to read)."""
    dx = 0.01
    if dim == 2:
        fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.2, 0.1), dx), rho0=RHO0, eos=sw.Tait(c0=20.0))
        wall = sw.WallSystem(sw.shapes.tank((0, 0), (0.2, 0.15), dx, open_top=False), model=model)
    else:
        fluid = sw.FluidSystem(sw.shapes.box((0, 0, 0), (0.1, 0.08, 0.06), dx), rho0=RHO0, eos=sw.Tait(c0=20.0))
        wall = sw.WallSystem(sw.shapes.tank((0, 0, 0), (0.1, 0.08, 0.1), dx, open_top=False), model=model)
    sim = sw.Simulation([fluid, wall], h=1.3 * dx, gravity=(0, -9.81) if dim == 2 else (0, 0, -9.81))
    fp = fluid.particles
    if slope is not None:
        fp["rho"][:] = RHO0 + fp["x"] @ slope
    if velocity is not None:
        fp["v"][:] = velocity(fp["x"])
    ctx = EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.grid.build(fp["x"]), time=0.0,
                            dx=dx)
    wall.model.update(wall, fluid, ctx)
    return sim, fluid, wall


@pytest.mark.parametrize("dim", [2, 3])
def test_mdbc_extrapolates_linear_density_exactly_to_the_wall_particles(dim):
    slope = np.array([3.0, -120.0]) if dim == 2 else np.array([2.0, -1.5, -120.0])
    _, _, wall = _tank(ModifiedDynamicBoundary(), dim=dim, slope=slope)
    pa = wall.particles
    linear = pa["mdbc_outcome"] == CORRECTED_LINEAR
    # every wall particle whose ghost node lies under the water (floor, lower side walls) is first order
    ghost = pa["ghost"]
    submerged = ghost[:, -1] < (0.1 if dim == 2 else 0.06) - 2.6 * 0.013
    assert linear[submerged].all()
    expected = RHO0 + pa["x"] @ slope
    np.testing.assert_allclose(pa["rho"][linear], expected[linear], rtol=1e-10)
    # not the ghost node's own density: the extrapolation moved it by (x_b - x_g) . grad rho
    assert np.abs(pa["rho"][linear] - (RHO0 + ghost[linear] @ slope)).max() > 1.0
    # the pressure is the fluid's EOS of the extrapolated density
    eos = sw.Tait(c0=20.0)
    np.testing.assert_allclose(pa["p"], eos.pressure(pa["rho"], RHO0), rtol=1e-12, atol=1e-9)
    # wall particles with no fluid near their ghost node (above the water) stay at rho0
    none = pa["mdbc_outcome"] == CORRECTED_NONE
    assert none.any() and (pa["rho"][none] == RHO0).all()


def test_order_zero_is_the_shepard_density_of_the_ghost_node():
    slope = np.array([0.0, -120.0])
    _, _, w1 = _tank(ModifiedDynamicBoundary(order=1), slope=slope)
    _, _, w0 = _tank(ModifiedDynamicBoundary(order=0), slope=slope)
    _, _, wd = _tank(ModifiedDynamicBoundary(det_min=1e12), slope=slope)
    assert (w0.particles["mdbc_outcome"] != CORRECTED_LINEAR).all()
    np.testing.assert_array_equal(w0.particles["rho"], wd.particles["rho"])
    floor = w1.particles["x"][:, 1] < -0.02  # third layer: ghost node 2.5 dx inside the water
    # zeroth order misses the linear extrapolation over the 5 dx from ghost node to particle
    err0 = np.abs(w0.particles["rho"][floor] - (RHO0 + w0.particles["x"][floor] @ slope))
    err1 = np.abs(w1.particles["rho"][floor] - (RHO0 + w1.particles["x"][floor] @ slope))
    assert err1.max() < 1e-8 and err0.min() > 1.0


def _tank_fluid_y_range():
    """Lowest and highest fluid particle of the 2D tank of :func:`_tank` (rows at (i + 1/2) dx)."""
    return 0.005, 0.095


def test_noslip_mirrors_the_ghost_velocity():
    # simple shear u = (s y, 0): at the ghost node u_g = (s y_g, 0), so v_b = -u_g on the still wall
    s = 2.0

    def shear(x):
        return np.stack([s * x[:, 1], np.zeros(x.shape[0])], axis=1)

    _, _, wall = _tank(ModifiedDynamicBoundary(slip="noslip"), velocity=shear)
    pa = wall.particles
    linear = pa["mdbc_outcome"] == CORRECTED_LINEAR
    # the fit is exact for the shear; the limiter clips it to the neighbours' range [s y_min, s y_max]
    # only for nodes outside the fluid's hull (side-wall nodes above the surface, y_g > 0.095 m)
    fy = _tank_fluid_y_range()
    clipped = np.clip(pa["ghost"][:, 1], *fy)
    expected = -np.stack([s * clipped, np.zeros_like(clipped)], axis=1)
    np.testing.assert_allclose(pa["v_mdbc"][linear], expected[linear], atol=1e-10)
    assert (clipped[linear] != pa["ghost"][linear, 1]).any()  # the limiter acted somewhere
    _, _, still = _tank(ModifiedDynamicBoundary(), velocity=shear)
    assert not still.particles["v_mdbc"].any()  # vel0: the wall's own velocity


def test_clip_negative_keeps_the_wall_density_at_rho0_or_above():
    """A fluid in tension (density falling with height, below rho0 near the floor): unclipped the floor
    takes densities below rho0 (a wall that pulls); with clip_negative exactly max(rho_b, rho0)."""
    slope = np.array([0.0, 120.0])   # rho = rho0 + 120 y: below rho0 under y = 0
    _, _, free = _tank(ModifiedDynamicBoundary(), slope=slope)
    _, _, clipped = _tank(ModifiedDynamicBoundary(clip_negative=True), slope=slope)
    rho = free.particles["rho"]
    assert (rho < RHO0 - 1.0).any()
    np.testing.assert_array_equal(clipped.particles["rho"], np.maximum(rho, RHO0))
    assert (clipped.particles["p"] >= 0.0).all()
    assert boundary_by_name("mdbc", {"clip_negative": "1"}).clip_negative
    assert "clipped" in boundary_by_name("mdbc-noslip", {"clip_negative": "yes"}).describe()


def test_registry_names_and_bad_options():
    assert boundary_by_name("mdbc").slip == "vel0"
    assert boundary_by_name("mdbc-noslip").name == "mdbc-noslip"
    m = boundary_by_name("mdbc", {"order": "0", "det_min": "1e-2"})
    assert (m.order, m.det_min) == (0, 1e-2)
    for options, name in (({"order": 2}, "order"), ({"order": "x"}, "order"), ({"det_min": -1}, "det_min"),
                          ({"det_min": "nan"}, "det_min"), ({"slip": "free"}, "slip"),
                          ({"clip_negative": "maybe"}, "clip_negative")):
        with pytest.raises(ParameterError, match=name):
            boundary_by_name("mdbc", dict(options))
