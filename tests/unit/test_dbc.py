"""DBC / IDBC ([Li2022]) on hand-built configurations: one wall and one fluid particle, a row of walls."""

import math

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.base import EvaluationContext
from seawall.boundary.dbc import (DynamicBoundary, ImprovedDynamicBoundary, alpha_db, expanded_pressure,
                                  wall_kernel)
from seawall.boundary.dbc_field import pair_force, potential_energy, row_force_field
from seawall.boundary.registry import boundary_by_name
from seawall.errors import ParameterError
from seawall.kernels import CUBIC_SPLINE, kernel_shape, kernel_shape_dq
from seawall.shapes import Shape

RHO0 = 998.1
C0 = 50.0
DX = 1.0e-3
# h with m W0 = rho0 (m = rho0 dx^2, W0 = 10 / (7 pi h^2)): the two-particle model of eq. 17
H2P = DX * math.sqrt(10.0 / (7.0 * math.pi))


def _pair(model, fluid_pos, wall_pos, normal=(0.0, 1.0), h=H2P, wall_rows=None):
    wall_pos = np.atleast_2d(np.asarray(wall_pos, dtype=float))
    n = wall_pos.shape[0]
    normals = np.tile(normal, (n, 1))
    wall = sw.WallSystem(Shape(wall_pos, DX, normals, wall_pos + 0.5 * DX * np.asarray(normal), np.zeros(n, int)),
                         model=model)
    fluid = sw.FluidSystem(Shape(np.atleast_2d(fluid_pos), DX), rho0=RHO0, eos=sw.Tait(c0=C0), viscosity=None)
    lo = np.minimum(wall_pos.min(0), np.min(np.atleast_2d(fluid_pos), 0)) - 5 * h
    hi = np.maximum(wall_pos.max(0), np.max(np.atleast_2d(fluid_pos), 0)) + 5 * h
    sim = sw.Simulation([fluid, wall], h=h, domain=(lo, hi))
    return sim, fluid, wall


def _forces(sim, fluid, wall, rho_f, rho_w):
    fp = fluid.particles
    fp["rho"][:] = rho_f
    wall.particles["rho"][:] = rho_w
    g = sim.grid
    cells = g.build(fp["x"])
    ctx = EvaluationContext(physics=sim.physics, grid=g, fluid_cells=cells, time=0.0, dx=DX)
    dv = np.zeros((fp.n, 2))
    drho = np.zeros(fp.n)
    fp["mu_max"][:] = 0.0
    fp["xsph"][:] = 0.0
    wall.model.interact(fluid, wall, ctx, dv, drho)
    return dv, drho


def test_expanded_eos_order_1_is_linear_and_order_7_is_tait():
    tait = sw.Tait(c0=C0)
    for rho in (990.0, 998.1, 1010.0, 1200.0):
        assert expanded_pressure(rho, RHO0, C0, 1, 0.0) == pytest.approx(C0 ** 2 * (rho - RHO0))
        assert expanded_pressure(rho, RHO0, C0, 7, 0.0) == pytest.approx(float(tait.pressure(rho, RHO0)),
                                                                         rel=1e-12, abs=1e-9)


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5, 6, 7])
def test_two_particle_force_matches_eq23(order):
    """rho_a = rho_b = m (W + W0), rho0 = m W0: force = -2 c^2 W/(W+W0)^2 f_theta grad W (eq. 23)."""
    fpos = (0.3 * DX, 0.8 * DX)
    sim, fluid, wall = _pair(ImprovedDynamicBoundary(order=order, rectangular=False), fpos, (0.0, 0.0))
    h = H2P
    sigma = 10.0 / (7.0 * math.pi * h * h)
    m = RHO0 * DX * DX
    assert m * sigma == pytest.approx(RHO0)
    r = math.hypot(*fpos)
    q = r / h
    W = sigma * kernel_shape(CUBIC_SPLINE, q)
    W0 = sigma
    theta = W / W0
    f_theta = sum(a * theta ** k for k, a in enumerate([1, 3, 5, 5, 3, 1, 1 / 7][:order]))
    gradW = sigma / h * kernel_shape_dq(CUBIC_SPLINE, q) * np.array(fpos) / r
    expected = -2.0 * C0 ** 2 * W / (W + W0) ** 2 * f_theta * gradW
    rho = m * (W + W0)
    dv, _ = _forces(sim, fluid, wall, rho, rho)
    np.testing.assert_allclose(dv[0], expected, rtol=1e-9)
    assert dv[0, 1] > 0  # repulsive


def test_order_1_equals_plain_dbc_with_linear_eos():
    fpos = (0.2 * DX, 1.1 * DX)
    rho_f, rho_w = 1003.0, 1007.0
    out = []
    for model in (DynamicBoundary(), ImprovedDynamicBoundary(order=1, rectangular=False), boundary_by_name("dbc")):
        sim, fluid, wall = _pair(model, fpos, (0.0, 0.0), h=1.3 * DX)
        out.append(_forces(sim, fluid, wall, rho_f, rho_w)[0][0])
    # by hand: -m (c^2 (rho_a - rho0)/rho_a^2 + c^2 (rho_b - rho0)/rho_b^2) grad W
    h = 1.3 * DX
    r = math.hypot(*fpos)
    grad = 10.0 / (7.0 * math.pi * h ** 2) / h * kernel_shape_dq(CUBIC_SPLINE, r / h) * np.array(fpos) / r
    m = RHO0 * DX ** 2
    hand = -m * C0 ** 2 * ((rho_f - RHO0) / rho_f ** 2 + (rho_w - RHO0) / rho_w ** 2) * grad
    for o in out:
        np.testing.assert_allclose(o, hand, rtol=1e-9)


def test_rectangular_support_force_is_along_the_normal_and_projected():
    h = 1.3 * DX
    fpos = (0.4 * DX, 0.9 * DX)
    model = ImprovedDynamicBoundary(order=7, rectangular=True, correction=True)
    sim, fluid, wall = _pair(model, fpos, (0.0, 0.0), h=h)
    rho_f, rho_w = 1004.0, 1009.0
    dv, _ = _forces(sim, fluid, wall, rho_f, rho_w)
    assert dv[0, 0] == 0.0 and dv[0, 1] > 0.0
    # eq. 26: r1 = r . n = 0.9 dx, grad W = n alpha_DB sigma w'(r1/h)/h
    a = alpha_db(h, DX)
    assert a == pytest.approx(7 * math.pi * h / (30 * DX))
    gy = a * 10.0 / (7.0 * math.pi * h ** 2) / h * kernel_shape_dq(CUBIC_SPLINE, 0.9 * DX / h)
    m = RHO0 * DX ** 2
    pa = expanded_pressure(rho_f, RHO0, C0, 7, 0.0)
    pb = expanded_pressure(rho_w, RHO0, C0, 7, 0.0)
    assert dv[0, 1] == pytest.approx(-m * (pa / rho_f ** 2 + pb / rho_w ** 2) * gy, rel=1e-9)
    # outside the tangential window (|s| > dx): no force; tilted normal: force along that normal
    sim, fluid, wall = _pair(ImprovedDynamicBoundary(), (1.2 * DX, 0.5 * DX), (0.0, 0.0), h=h)
    assert np.all(_forces(sim, fluid, wall, rho_f, rho_w)[0] == 0.0)
    n = np.array([0.6, 0.8])
    sim, fluid, wall = _pair(ImprovedDynamicBoundary(), (0.9 * DX, 0.4 * DX), (0.0, 0.0), normal=n, h=h)
    dv = _forces(sim, fluid, wall, rho_f, rho_w)[0][0]
    assert abs(dv[0] * n[1] - dv[1] * n[0]) < 1e-12 * np.linalg.norm(dv) and dv @ n > 0


def test_row_force_independent_of_tangential_position_with_rectangle():
    """A uniform row pushes equally wherever the fluid particle is along it (the ridge of Fig. 4d)."""
    h = 1.3 * DX
    row = np.stack([np.arange(-10, 11) * DX, np.zeros(21)], axis=1)
    forces = []
    for s in (0.0, 0.13, 0.5, 0.77, 1.0):
        sim, fluid, wall = _pair(ImprovedDynamicBoundary(), (s * DX, 1.1 * DX), row, h=h)
        forces.append(_forces(sim, fluid, wall, 1002.0, 1005.0)[0][0])
    forces = np.array(forces)
    np.testing.assert_allclose(forces[:, 0], 0.0, atol=1e-12 * abs(forces[0, 1]))
    np.testing.assert_allclose(forces[:, 1], forces[0, 1], rtol=1e-12)
    # the circular support ripples along the row
    circ = []
    for s in (0.0, 0.5):
        sim, fluid, wall = _pair(DynamicBoundary(), (s * DX, 1.1 * DX), row, h=h)
        circ.append(_forces(sim, fluid, wall, 1002.0, 1005.0)[0][0, 1])
    assert abs(circ[0] - circ[1]) > 1e-3 * abs(circ[0])


def _row_kernel_sum(h, dx, r1, s, dim=2):
    """sum_b W_B of a full row (2D) or plane (3D) of wall particles at normal distance r1, offset s."""
    sigma = (10.0 / (7.0 * math.pi * h * h)) if dim == 2 else 1.0 / (math.pi * h ** 3)
    corr = alpha_db(h, dx, dx, dim=dim)
    total = 0.0
    ks = range(-6, 7)
    for i in ks:
        for j in (ks if dim == 3 else [0]):
            d = (s[0] - i * dx, (s[1] - j * dx) if dim == 3 else 0.0, r1)
            if dim == 2:
                d = (s[0] - i * dx, r1, 0.0)
                n, t1, t2 = (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 0.0)
            else:
                n, t1, t2 = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)
            out = wall_kernel(CUBIC_SPLINE, True, dim, d[0], d[1], d[2], *n, *t1, *t2, dx, dx, corr, sigma,
                              1.0 / h, 2.0 * h, 4.0 * h * h)
            if out[0] >= 0.0:
                total += out[1]
    return total


@pytest.mark.parametrize("dim", [2, 3])
def test_alpha_db_gives_unity_for_a_full_row(dim):
    """Eq. 28: dx^(d-1) sum_b int W_B dn = 1 at any tangential position; at the wall sum_b W_B is
    2/(3 h dx) in 2D (1/(3 h dx dy) * 2 in 3D), within 3% of the circular kernel's row sum."""
    h, dx = 1.3, 1.0
    if dim == 2:
        assert alpha_db(h, dx) == pytest.approx(7 * math.pi * h / (30 * dx))
    else:
        assert alpha_db(h, dx, 0.8, dim=3) == pytest.approx(math.pi * h * h / (6 * dx * 0.8))
    rs = np.linspace(-2 * h, 2 * h, 2001)
    for s in ((0.0, 0.0), (0.37, 0.81), (0.5, 0.5), (1.0, 0.25)):
        vals = np.array([_row_kernel_sum(h, dx, r, s, dim) for r in rs])
        integral = float(np.sum(0.5 * (vals[1:] + vals[:-1]) * np.diff(rs)))
        assert integral * dx ** (dim - 1) == pytest.approx(1.0, rel=1e-5)
        at_wall = _row_kernel_sum(h, dx, 0.0, s, dim)
        assert at_wall == pytest.approx(2.0 / (3.0 * h * dx ** (dim - 1)), rel=1e-12)
    if dim == 2:
        circular = 15.0 / (7.0 * math.pi * h * dx)  # (1/dx) int W dx along the row
        assert abs(2.0 / (3.0 * h * dx) / circular - 1.0) < 0.03


def test_potential_energy_full_expansion_exceeds_seven_times_first_order():
    ratio = potential_energy(7) / potential_energy(1)
    assert ratio > 7.0
    q = np.linspace(0.0, 2.0, 2001)
    f1, f7 = pair_force(q, 1), pair_force(q, 7)
    assert f7.max() > f1.max() and q[f7.argmax()] < q[f1.argmax()]  # higher and closer (Fig. 1)


def test_row_force_field_rectangle_is_a_ridge():
    x = np.linspace(-1.5, 1.5, 31)
    fx, fy = row_force_field(x, np.full_like(x, 0.8), order=7, rectangular=True, correction=True)
    np.testing.assert_allclose(fy, fy[0])
    assert np.all(fx == 0.0)
    fx, fy = row_force_field(x, np.full_like(x, 0.8), order=7)
    assert fy.std() > 1e-3 * fy.mean()


def test_options_and_errors():
    m = boundary_by_name("idbc", {"order": "3", "rectangular": "1", "correction": "0", "alpha_wall": "0.1"})
    assert (m.order, m.rectangular, m.correction, m.alpha_wall) == (3, True, False, 0.1)
    with pytest.raises(ParameterError):
        ImprovedDynamicBoundary(order=8)
    with pytest.raises(ParameterError):
        ImprovedDynamicBoundary(rectangular=False, correction=True)
    assert ImprovedDynamicBoundary(rectangular=False).correction is False


def test_wall_density_follows_continuity():
    """A fluid particle approaching a wall raises the wall density as sum m W does (no XSPH, one particle)."""
    h = 1.3 * DX
    for model in (DynamicBoundary(), ImprovedDynamicBoundary()):
        sim, fluid, wall = _pair(model, (0.1 * DX, 2.7 * DX), (0.0, 0.0), h=h)
        fluid.particles["v"][:] = (0.0, -1.5)
        sim.run_steps(200)
        sim.evaluate(sim.time)  # brings the wall density to the current positions
        y = fluid.particles["x"][0, 1]
        r = math.hypot(fluid.particles["x"][0, 0], y) if not model.rectangular else y
        w = 10.0 / (7 * math.pi * h * h) * kernel_shape(CUBIC_SPLINE, r / h)
        if model.rectangular:
            w *= alpha_db(h, DX)
        assert wall.particles["rho"][0] - RHO0 == pytest.approx(RHO0 * DX * DX * w, rel=2e-3)
