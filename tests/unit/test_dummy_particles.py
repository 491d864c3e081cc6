"""Dummy-particle walls ([TrixiBoundary]) and fluid-wall adhesion on hand-built configurations.

Three wall rows under a block of fluid particles whose pressure, density and
velocity are set by hand; the wall state and the forces on the fluid are
compared with the defining formulas evaluated here in numpy.
"""

import math

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.adhesion import adhesion_kernel
from seawall.boundary.base import EvaluationContext
from seawall.kernels import CUBIC_SPLINE, kernel_shape, kernel_shape_dq
from seawall.shapes import Shape

RHO0 = 1000.0
C0 = 20.0
DX = 0.01
H = 1.3 * DX
SUPPORT = 2.0 * H
G = 9.81


def build(model, dim=2, gravity=True, adhesion=0.0):
    """Three wall rows (y < 0) under a 8 x 5 (x 8) block of fluid (y > 0), lattice spacing DX."""
    span = np.arange(-4, 4) * DX + 0.5 * DX
    rows = (np.arange(3) + 0.5) * -DX
    up = (np.arange(5) + 0.5) * DX
    if dim == 2:
        wall = np.array([(x, y) for y in rows for x in span])
        fluid = np.array([(x, y) for y in up for x in span])
    else:
        wall = np.array([(x, z, y) for y in rows for x in span for z in span])
        fluid = np.array([(x, z, y) for y in up for x in span for z in span])
    n = wall.shape[0]
    normal = np.zeros(dim)
    normal[-1] = 1.0
    surface = wall.copy()
    surface[:, -1] = 0.0
    walls = sw.WallSystem(Shape(wall, DX, np.tile(normal, (n, 1)), surface, np.zeros(n, int)), model=model,
                          adhesion_coefficient=adhesion)
    fluid_system = sw.FluidSystem(Shape(fluid, DX), rho0=RHO0, eos=sw.Tait(c0=C0), viscosity=None)
    g = np.zeros(dim)
    if gravity:
        g[-1] = -G
    lo = np.full(dim, -0.1)
    hi = np.full(dim, 0.1)
    sim = sw.Simulation([fluid_system, walls], h=H, gravity=g, domain=(lo, hi))
    return sim, fluid_system, walls


def context(sim):
    cells = sim.grid.build(sim.fluid.particles["x"])
    return EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=cells, time=0.0, dx=DX)


def wall_update(sim, wall):
    wall.model.update(wall, sim.fluid, context(sim))
    return wall.particles


def interaction(sim, wall):
    fp = sim.fluid.particles
    dv = np.zeros((fp.n, sim.dim))
    drho = np.zeros(fp.n)
    wall.model.interact(sim.fluid, wall, context(sim), dv, drho)
    return dv, drho


def weights(xb, xf):
    """Kernel shape values w(|x_b - x_f| / h) of every fluid particle seen from point xb."""
    q = np.linalg.norm(xf - xb, axis=1) / H
    return np.array([kernel_shape(CUBIC_SPLINE, qq) if qq < 2.0 else 0.0 for qq in q])


def gradient(xi, xb, dim, h=H):
    """grad_i W(x_i - x_b) of the cubic spline."""
    d = xi - xb
    r = np.linalg.norm(d)
    sigma = 10.0 / (7.0 * math.pi * h ** 2) if dim == 2 else 1.0 / (math.pi * h ** 3)
    if r == 0.0 or r >= 2.0 * h:
        return np.zeros(dim)
    return sigma / h * kernel_shape_dq(CUBIC_SPLINE, r / h) * d / r


# ----------------------------------------------------------------- Adami extrapolation
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("p_const", [0.0, 1234.5])
def test_adami_is_exact_for_zero_and_constant_pressure(dim, p_const):
    sim, fluid, wall = build(sw.DummyParticles(density="adami"), dim=dim, gravity=False)
    fp = fluid.particles
    fp["p"][:] = p_const
    fp["rho"][:] = RHO0 * 1.003
    pa = wall_update(sim, wall)
    reached = np.array([weights(xb, fp["x"]).sum() > 0 for xb in pa["x"]])
    assert reached.any() and not reached.all()        # the third row is out of reach of the fluid
    np.testing.assert_allclose(pa["p"][reached], p_const, rtol=1e-12, atol=1e-9)
    assert np.all(pa["p"][~reached] == 0.0)           # no fluid neighbour: background pressure
    rho_expected = float(sw.Tait(c0=C0).density(p_const, RHO0))
    np.testing.assert_allclose(pa["rho"][reached], rho_expected, rtol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_adami_reproduces_the_hydrostatic_field_below_a_still_layer(dim):
    # p_f = rho0 g (D - y_f) with rho_f = rho0: sum (p_f + rho_f g . r_bf) W / sum W = rho0 g (D - y_b) exactly
    sim, fluid, wall = build(sw.DummyParticles(density="adami"), dim=dim)
    fp = fluid.particles
    depth = 5 * DX
    fp["p"][:] = RHO0 * G * (depth - fp["x"][:, -1])
    fp["rho"][:] = RHO0
    pa = wall_update(sim, wall)
    reached = np.array([weights(xb, fp["x"]).sum() > 0 for xb in pa["x"]])
    np.testing.assert_allclose(pa["p"][reached], RHO0 * G * (depth - pa["x"][reached, -1]), rtol=1e-12)


def test_adami_wall_acceleration_term():
    # a wall falling freely with gravity (a_b = g) sees no hydrostatic term: p_b = p_f for constant p_f
    sim, fluid, wall = build(sw.DummyParticles(density="adami"))
    fp = fluid.particles
    fp["p"][:] = 500.0
    fp["rho"][:] = RHO0
    wall.particles["a"][:, 1] = -G
    pa = wall_update(sim, wall)
    reached = pa["rho"] != RHO0
    np.testing.assert_allclose(pa["p"][reached], 500.0, rtol=1e-12)
    # with an upward wall acceleration a_b the term is rho_f (g - a_b) . (r_b - r_f): checked by hand
    wall.particles["a"][:, 1] = 3.0
    pa = wall_update(sim, wall)
    for b in np.flatnonzero(reached)[:6]:
        w = weights(pa["x"][b], fp["x"])
        hand = np.sum((500.0 + RHO0 * (-G - 3.0) * (pa["x"][b, 1] - fp["x"][:, 1])) * w) / w.sum()
        assert pa["p"][b] == pytest.approx(hand, rel=1e-12)


# ----------------------------------------------------------------- no slip
def test_noslip_wall_velocity_is_twice_the_wall_velocity_minus_the_shepard_average():
    sim, fluid, wall = build(sw.DummyParticles(density="adami", slip="noslip", nu=1e-3))
    fp = fluid.particles
    x = fp["x"]
    fp["v"][:, 0] = np.sin(40.0 * x[:, 0]) + 3.0 * x[:, 1]         # non-uniform on purpose
    fp["v"][:, 1] = 0.5 * x[:, 0] ** 2 - x[:, 1]
    fp["p"][:] = 0.0
    wall.particles["v"][:] = (0.3, -0.1)
    pa = wall_update(sim, wall)
    checked = 0
    for b in range(wall.n):
        w = weights(pa["x"][b], x)
        if w.sum() == 0.0:
            np.testing.assert_allclose(pa["v_visc"][b], (0.3, -0.1))
            continue
        hand = 2.0 * np.array([0.3, -0.1]) - (w[:, None] * fp["v"]).sum(0) / w.sum()
        np.testing.assert_allclose(pa["v_visc"][b], hand, rtol=1e-12, atol=1e-15)
        checked += 1
    assert checked > 10


# ----------------------------------------------------------------- mirroring and zeroing
@pytest.mark.parametrize("density", ["mirroring", "zeroing"])
def test_mirroring_and_zeroing_forces_follow_their_definitions(density):
    sim, fluid, wall = build(sw.DummyParticles(density=density))
    fp = fluid.particles
    rng = np.random.default_rng(3)
    fp["rho"][:] = RHO0 * (1.0 + 0.01 * rng.random(fp.n))
    fp["p"][:] = 2000.0 * rng.random(fp.n)
    wall_update(sim, wall)
    dv, _ = interaction(sim, wall)
    mb = RHO0 * DX ** 2
    xw = wall.particles["x"]
    for i in range(0, fp.n, 7):
        pi, rhoi = fp["p"][i], fp["rho"][i]
        # mirroring: p_b = p_i, rho_b = rho0; zeroing: p_b = 0 (Tait, no background), rho_b = rho0
        pb = pi if density == "mirroring" else 0.0
        hand = np.zeros(2)
        for b in range(wall.n):
            hand -= mb * (pi / rhoi ** 2 + pb / RHO0 ** 2) * gradient(fp["x"][i], xw[b], 2)
        np.testing.assert_allclose(dv[i], hand, rtol=1e-10, atol=1e-12)
    near = fp["x"][:, 1] < DX
    assert np.all(dv[near, 1] > 0.0)                  # both push the first fluid row away from the wall


# ----------------------------------------------------------------- adhesion (Akinci et al. 2013)
def test_adhesion_kernel_vanishes_at_both_ends_and_peaks_at_three_quarters():
    s = SUPPORT
    assert adhesion_kernel(0.5 * s, s) == 0.0
    assert adhesion_kernel(s, s) == 0.0
    assert adhesion_kernel(0.3 * s, s) == 0.0 and adhesion_kernel(1.01 * s, s) == 0.0
    r = np.linspace(0.5 * s, s, 2001)
    c = np.array([adhesion_kernel(rr, s) for rr in r])
    assert r[np.argmax(c)] == pytest.approx(0.75 * s, abs=1e-3 * s)
    assert c.max() == pytest.approx(0.007 / s ** 3.25 * (s / 4) ** 0.25, rel=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_adhesion_pulls_fluid_towards_the_wall_by_the_akinci_formula(dim):
    beta = 2.5
    plain = build(sw.DummyParticles(density="zeroing"), dim=dim)
    sticky = build(sw.DummyParticles(density="zeroing"), dim=dim, adhesion=beta)
    for sim in (plain[0], sticky[0]):
        sim.evaluate(0.0)
    diff = sticky[1].particles["dv"] - plain[1].particles["dv"]
    x = sticky[1].particles["x"]
    xw = sticky[2].particles["x"]
    psi = RHO0 * DX ** dim
    for i in range(x.shape[0]):
        d = x[i] - xw
        r = np.linalg.norm(d, axis=1)
        c = np.array([adhesion_kernel(rr, SUPPORT) for rr in r])
        hand = -beta * psi * ((c / r)[:, None] * d).sum(0)
        np.testing.assert_allclose(diff[i], hand, rtol=1e-9, atol=1e-12)
    reached = np.abs(diff).sum(1) > 0
    assert reached.any()
    assert np.all(diff[reached, -1] < 0.0)            # towards the wall (below)


def test_adhesion_coefficient_must_not_be_negative():
    with pytest.raises(sw.ParameterError, match="adhesion_coefficient"):
        build(sw.DummyParticles(), adhesion=-1.0)


# ----------------------------------------------------------------- 3D
@pytest.mark.parametrize("density", ["adami", "summation", "continuity", "zeroing", "mirroring"])
def test_every_calculator_pushes_still_water_up_in_3d(density):
    sim, fluid, wall = build(sw.DummyParticles(density=density, slip="noslip", nu=1e-3), dim=3)
    fp = fluid.particles
    fp["p"][:] = RHO0 * G * (5 * DX - fp["x"][:, -1])
    fp["rho"][:] = np.asarray(sw.Tait(c0=C0).density(fp["p"], RHO0))
    wall_update(sim, wall)
    dv, drho = interaction(sim, wall)
    assert np.isfinite(dv).all() and np.isfinite(drho).all()
    first_row = fp["x"][:, -1] < DX
    assert np.all(dv[first_row, 2] > 0.0)
    # a still fluid over a still wall gets no density change and no sideways push in the middle
    assert np.all(drho == 0.0)
    middle = first_row & (np.abs(fp["x"][:, 0]) < DX) & (np.abs(fp["x"][:, 1]) < DX)
    np.testing.assert_allclose(dv[middle, :2], 0.0, atol=1e-9 * np.abs(dv[middle, 2]).max())


# ----------------------------------------------------------------- the wall's own EOS, kernel, h
def test_wall_eos_is_the_fluids_unless_given():
    sim, fluid, wall = build(sw.DummyParticles(density="adami", eos=sw.Linear(c0=30.0)), gravity=False)
    fp = fluid.particles
    fp["p"][:] = 900.0
    pa = wall_update(sim, wall)
    reached = pa["p"] > 0
    np.testing.assert_allclose(pa["rho"][reached], RHO0 + 900.0 / 30.0 ** 2, rtol=1e-12)
    sim, fluid, wall = build(sw.DummyParticles(density="adami"), gravity=False)
    fluid.particles["p"][:] = 900.0
    pa = wall_update(sim, wall)
    np.testing.assert_allclose(pa["rho"][pa["p"] > 0], float(sw.Tait(c0=C0).density(900.0, RHO0)), rtol=1e-12)


def test_wall_smoothing_length_of_its_own():
    h_wall = 0.8 * H
    sim, fluid, wall = build(sw.DummyParticles(density="mirroring", smoothing_length=h_wall))
    fp = fluid.particles
    fp["p"][:] = 1000.0
    wall_update(sim, wall)
    dv, _ = interaction(sim, wall)
    mb = RHO0 * DX ** 2
    for i in range(0, fp.n, 5):
        hand = np.zeros(2)
        for b in range(wall.n):
            hand -= mb * 2.0 * 1000.0 / RHO0 ** 2 * gradient(fp["x"][i], wall.particles["x"][b], 2, h=h_wall)
        np.testing.assert_allclose(dv[i], hand, rtol=1e-10, atol=1e-12)
    with pytest.raises(sw.ParameterError, match="smoothing_length"):
        build(sw.DummyParticles(smoothing_length=1.5 * H))
    with pytest.raises(sw.ParameterError, match="smoothing_length"):
        sw.DummyParticles(smoothing_length=-1.0)
