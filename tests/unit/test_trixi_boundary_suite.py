"""TrixiParticles.jl's own boundary unit tests, set up through seawall's API with their published values.

TrixiParticles ([TrixiBoundary] is its documentation) tests its wall models in its repository's
``test/schemes/boundary/`` and its viscosities in ``test/schemes/fluid/viscosity.jl``. The inputs
(geometry, kernel, state equation, fields) and the expected numbers below are those files'; the code
that produces the numbers is seawall's. Where the two codes differ by design the test says so:

* the Monaghan-Kajtar force: seawall keeps the factor 2 m_b / (m_a + m_b) of [TrixiBoundary]'s
  formula by default, TrixiParticles' code drops it (``mass_factor="none"``), so by default seawall
  gives 2 * 40 / (10 + 40) = 1.6 times TrixiParticles' numbers in its RHS test
  (docs/boundaries.md, "Monaghan-Kajtar: the mass factor and K");
* TrixiParticles' ``ViscosityAdami`` on a pair with m_a = m_b and rho_a = rho_b is seawall's
  laminar (Morris) term with the neighbour's mass, which is what seawall's no-slip dummy wall adds.

Not carried over: the energy/momentum-conservation RHS test of the dummy particles (random
perturbed patches drawn with Julia's random generator: no published numbers).
"""

import math

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.base import EvaluationContext
from seawall.boundary.dummy import DummyParticles
from seawall.boundary.repulsive import MonaghanKajtar
from seawall.kernels import CubicSpline
from seawall.pairs import gradient_factor, laminar_viscosity, monaghan_viscosity, pressure_acceleration
from seawall.shapes import Shape


def _context(sim):
    fp = sim.fluid.particles
    return EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.grid.build(fp["x"]), time=0.0,
                             dx=sim.fluid.spacing)


def _set_state(fluid, rho, eos_c0, rho0, gamma=7.0):
    fp = fluid.particles
    fp["rho"][:] = rho
    b = eos_c0 * eos_c0 * rho0 / gamma
    fp["p"][:] = b * ((fp["rho"] / rho0) ** gamma - 1.0)
    fp["p_over_rho2"][:] = fp["p"] / fp["rho"] ** 2


# ------------------------------------------------------------------ dummy_particles.jl: Adami extrapolation
DX_TANK = 0.1
RHO0_TANK = 257.0
C_TANK = 10.0


def _adami_tank(gravity, **model_options):
    """RectangularTank(0.1, (1, 1), (1, 1), 257, n_layers=2, faces=(left, right, bottom, no lid)),
    Schoenberg cubic spline with h = 1.5 dx, StateEquationCole(c = 10, rho0 = 257, exponent 7)."""
    fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (1.0, 1.0), DX_TANK), rho0=RHO0_TANK,
                           eos=sw.Tait(c0=C_TANK, gamma=7.0))
    # TrixiParticles' tank without a lid: seawall's closed tank without its lid rows (an open
    # shapes.tank is thicker at the sides, its crest and back faces surfaces of their own)
    closed = sw.shapes.tank((0, 0), (1.0, 1.0), DX_TANK, layers=2, open_top=False)
    wall = sw.WallSystem(closed.subset(closed.positions[:, 1] < 1.0), model=DummyParticles(**model_options))
    sim = sw.Simulation([fluid, wall], kernel=CubicSpline(), h=1.5 * DX_TANK, gravity=gravity)
    return sim, fluid, wall


def test_adami_extrapolation_of_zero_pressure_is_zero():
    sim, fluid, wall = _adami_tank((0.0, 0.0))
    _set_state(fluid, RHO0_TANK, C_TANK, RHO0_TANK)
    wall.model.update(wall, fluid, _context(sim))
    assert np.all(wall.particles["p"] == 0.0) and np.all(fluid.particles["p"] == 0.0)


def test_adami_extrapolation_of_a_constant_pressure_is_that_pressure():
    sim, fluid, wall = _adami_tank((0.0, 0.0))
    _set_state(fluid, 260.0, C_TANK, RHO0_TANK)
    wall.model.update(wall, fluid, _context(sim))
    p = fluid.particles["p"]
    assert np.all(np.isclose(p, p[0])) and p[0] > 0.0
    np.testing.assert_allclose(wall.particles["p"], p[0], rtol=0, atol=1e-12)


def _hydrostatic_column(depths, g, c0, rho0, gamma=7.0):
    """TrixiParticles' RectangularTank hydrostatic initialisation: dp/dr = rho(p) g integrated from the
    surface with explicit Euler steps of dx (a half step to the first row), rho(p) the inverse Cole EOS."""
    b = c0 * c0 * rho0 / gamma
    rho = lambda p: rho0 * (p / b + 1.0) ** (1.0 / gamma)   # noqa: E731
    n = int(round(max(depths) / DX_TANK + 0.5))
    column = [0.5 * DX_TANK * g * rho(0.0)]
    for _ in range(n - 1):
        column.append(column[-1] + DX_TANK * g * rho(column[-1]))
    column = np.array(column)
    index = np.rint(np.asarray(depths) / DX_TANK - 0.5).astype(int)
    return column[index]


def test_adami_extrapolation_continues_the_hydrostatic_field_into_the_wall():
    """TrixiParticles' "Hydrostatic Pressure Gradient": the wall pressures of a tank of still water equal,
    within 4 Pa, the pressures at the same places in a wall-less water column that is two layers wider
    on each side and two layers deeper."""
    g = 9.81
    sim, fluid, wall = _adami_tank((0.0, -g))
    fp = fluid.particles
    p = _hydrostatic_column(1.0 - fp["x"][:, 1], g, C_TANK, RHO0_TANK)
    b = C_TANK ** 2 * RHO0_TANK / 7.0
    fp["p"][:] = p
    fp["rho"][:] = RHO0_TANK * (p / b + 1.0) ** (1.0 / 7.0)
    fp["p_over_rho2"][:] = fp["p"] / fp["rho"] ** 2
    wall.model.update(wall, fluid, _context(sim))
    # the reference column's surface is 1.0 m above y = 0 as well: its pressure at depth 1.0 - y
    reference = _hydrostatic_column(1.0 - wall.x[:, 1], g, C_TANK, RHO0_TANK)
    assert wall.n == 2 * 2 * 10 + 2 * 14          # two side walls of 10 rows, the floor with its corners
    np.testing.assert_allclose(wall.particles["p"], reference, rtol=0, atol=4.0)


def test_adami_clipping_follows_the_state_equation_clipping_of_trixiparticles():
    """TrixiParticles clips negative pressure in its state equation (StateEquationCole(c = 10, rho0 = 1000,
    clip_negative_pressure=true): p(999) = p(900) = 0; without clipping p(999) < -10); seawall clips
    the Adami wall pressure instead (``clip_negative_pressure``). A still fluid at those densities gives
    those pressures on every wall particle that has a fluid neighbour."""

    def wall_pressure(rho, clip):
        fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.4, 0.4), DX_TANK), rho0=1000.0, eos=sw.Tait(c0=10.0))
        wall = sw.WallSystem(sw.shapes.tank((0, 0), (0.4, 0.4), DX_TANK, layers=2),
                             model=DummyParticles(clip_negative_pressure=clip))
        sim = sw.Simulation([fluid, wall], kernel=CubicSpline(), h=1.2 * DX_TANK, gravity=(0.0, 0.0))
        _set_state(fluid, rho, 10.0, 1000.0)
        wall.model.update(wall, fluid, _context(sim))
        return wall.particles["p"].copy()

    unclipped = wall_pressure(999.0, False)
    reached = unclipped != 0.0                      # wall particles with a fluid neighbour
    assert reached.sum() > 20 and np.all(unclipped[reached] < -10.0)
    assert np.all(wall_pressure(999.0, True)[reached] == 0.0)
    assert np.all(wall_pressure(900.0, True)[reached] == 0.0)


# ------------------------------------------------------------------ dummy_particles.jl: Adami wall velocity
def _wall_velocity_setup():
    """Three wall rows y = 0.25, 0.15, 0.05 (x = 0.05 ... 0.95) under 16 x 5 fluid particles from
    (-0.3, 0.3), spacing 0.1, x first; cubic spline h = 1.2 dx, Cole c = 10, rho0 = 257."""
    dx = 0.1
    xs = 0.05 + dx * np.arange(10)
    rows = [np.stack([xs, np.full(10, y)], axis=1) for y in (0.25, 0.15, 0.05)]
    wall_shape = Shape(np.concatenate(rows), dx)
    fx, fy = np.meshgrid(-0.25 + dx * np.arange(16), 0.35 + dx * np.arange(5), indexing="xy")
    fluid_shape = Shape(np.stack([fx.ravel(), fy.ravel()], axis=1), dx)
    fluid = sw.FluidSystem(fluid_shape, rho0=257.0, eos=sw.Tait(c0=10.0))
    wall = sw.WallSystem(wall_shape, model=DummyParticles(slip="noslip", nu=1e-6))
    sim = sw.Simulation([fluid, wall], kernel=CubicSpline(), h=1.2 * dx, gravity=(0.0, 0.0), hull=None,
                        domain=((-1.0, -0.5), (2.0, 1.5)))
    _set_state(fluid, 257.0, 10.0, 257.0)
    return sim, fluid, wall


@pytest.mark.parametrize("v_fluid", [(0.0, -1.0), (1.0, 1.0), (-1.0, 0.0), (0.7, 0.2), (0.3, 0.8)])
def test_adami_wall_velocity_of_a_uniform_flow_is_its_mirror(v_fluid):
    sim, fluid, wall = _wall_velocity_setup()
    fluid.particles["v"][:] = v_fluid
    wall.model.update(wall, fluid, _context(sim))
    y = wall.x[:, 1]
    expected = np.zeros((30, 2))
    expected[y > 0.1] = -np.array(v_fluid)       # rows y = 0.25, 0.15 within the support; y = 0.05 outside
    np.testing.assert_allclose(wall.particles["v_visc"], expected, rtol=0, atol=1e-14)


@pytest.mark.parametrize("scale", [1.0, 0.5, 0.7, 1.8, 67.5])
def test_adami_wall_velocity_of_a_staggered_flow_has_the_published_values(scale):
    sim, fluid, wall = _wall_velocity_setup()
    v = np.zeros((fluid.particles.n, 2))
    # TrixiParticles' odd (1-based) particles. Its loop_order=:x_first makes x the outer loop (y runs
    # fastest, 5 per column), so the odd ones form a checkerboard: ix + iy even (the published values
    # are reproduced with this pattern, not with rows of alternate particles)
    ix = np.rint((fluid.particles["x"][:, 0] + 0.25) / 0.1).astype(int)
    iy = np.rint((fluid.particles["x"][:, 1] - 0.35) / 0.1).astype(int)
    v[(ix + iy) % 2 == 0] = scale
    fluid.particles["v"][:] = v
    wall.model.update(wall, fluid, _context(sim))
    # (seawall stores the wall particles in its own order: select them by position)
    x, y = wall.x[:, 0], wall.x[:, 1]
    odd = np.rint((x - 0.05) / 0.1).astype(int) % 2 == 0    # 1-based odd: diagonal to a moving fluid particle
    first, second = np.isclose(y, 0.25), np.isclose(y, 0.15)
    expected = np.zeros((30, 2))
    expected[first & odd] = -0.42040669416720744 * scale
    expected[first & ~odd] = -0.5795933058327924 * scale
    expected[second & odd] = -0.12101100073462243 * scale
    expected[second & ~odd] = -0.8789889992653775 * scale
    np.testing.assert_allclose(wall.particles["v_visc"], expected, rtol=0, atol=2e-15 * max(scale, 1.0))


# ------------------------------------------------------------------ fluid/viscosity.jl
H_VISC = 1.2 * 0.2
POS_DIFF = np.array([-0.5 * H_VISC, 0.75 * H_VISC])
V_DIFF = np.array([0.1, -0.75])


def _pair():
    """grad W factor F (grad_a W = F r_ab) of the Schoenberg cubic spline, h = 0.24, and r^2, eta^2 = (0.1 h)^2."""
    kernel = CubicSpline()
    sigma = kernel.sigma(H_VISC, 2)
    r2 = float(POS_DIFF @ POS_DIFF)
    f = gradient_factor(kernel.kind, sigma / H_VISC ** 2, math.sqrt(r2) / H_VISC)
    return f, r2, 0.01 * H_VISC ** 2


def test_artificial_viscosity_monaghan_has_the_published_acceleration():
    f, r2, eta2 = _pair()
    c = 10.0 * math.sqrt(9.81 * 0.9)
    mu = H_VISC * float(V_DIFF @ POS_DIFF) / (r2 + eta2)
    pi_ab = monaghan_viscosity(0.02, 0.0, mu, c, 1000.0)
    dv = pressure_acceleration(1.0, pi_ab, f) * POS_DIFF      # per unit neighbour mass, as the published call
    np.testing.assert_allclose(dv, [-0.007073849138494646, 0.01061077370774197], rtol=0, atol=6e-15)


def test_viscosity_morris_has_the_published_acceleration():
    f, r2, eta2 = _pair()
    dv = laminar_viscosity(1.0, 7e-3, 1000.0, 1000.0, f, r2, eta2) * V_DIFF
    np.testing.assert_allclose(dv, [-0.00018421886647594437, 0.0013816414985695826], rtol=0, atol=6e-15)


def test_viscosity_adami_is_seawalls_noslip_wall_term_with_the_published_acceleration():
    """One fluid particle (v = v_diff) and one no-slip dummy wall particle at x_a - pos_diff with wall
    velocity 0, m_a = m_b = 0.01, rho = 1000, nu = 7e-3, zero pressure: seawall's dummy-wall loop."""
    fluid = sw.FluidSystem(Shape(np.array([[0.0, 0.0]]), 0.2), rho0=1000.0, eos=sw.Tait(c0=10.0 * math.sqrt(9.81 * 0.9)),
                           velocity=tuple(V_DIFF))
    wall = sw.WallSystem(Shape(np.array([-POS_DIFF]), 0.2), model=DummyParticles(slip="noslip", nu=7e-3))
    sim = sw.Simulation([fluid, wall], kernel=CubicSpline(), h=H_VISC, gravity=(0.0, 0.0), hull=None,
                        domain=((-1.0, -1.0), (1.0, 1.0)))
    fp = fluid.particles
    fp["m"][:] = 0.01
    _set_state(fluid, 1000.0, 1.0, 1000.0)
    pa = wall.particles
    pa["m"][:] = 0.01
    pa["p"][:] = 0.0
    pa["rho"][:] = 1000.0
    pa["v_visc"][:] = 0.0                           # the neighbour's velocity of the published call
    dv = np.zeros((1, 2))
    wall.model.interact(fluid, wall, _context(sim), dv, np.zeros(1))
    np.testing.assert_allclose(dv[0], [-1.8421886647594435e-6, 1.3816414985695826e-5], rtol=0, atol=6e-15)


# ------------------------------------------------------------------ monaghan_kajtar.jl: RHS
def _mk_rhs(mass_factor):
    """3 x 3 fluid particles (spacing 0.1, x = -0.25, -0.15, -0.05; y = -0.1, 0, 0.1; x first) left of
    three wall particles at x = 0, y = -0.2, 0, 0.2 (spacing 0.2 = dx / beta with beta = 0.5); K = 1,
    cubic spline h = 1.2 dx, density 1000 (masses 10 and 40)."""
    dx = 0.1
    fx, fy = np.meshgrid(-0.25 + dx * np.arange(3), -0.1 + dx * np.arange(3), indexing="xy")
    fluid = sw.FluidSystem(Shape(np.stack([fx.ravel(), fy.ravel()], axis=1), dx), rho0=1000.0,
                           eos=sw.Tait(c0=1.0))
    wall = sw.WallSystem(Shape(np.array([[0.0, -0.2], [0.0, 0.0], [0.0, 0.2]]), 2 * dx),
                         model=MonaghanKajtar(K=1.0, beta=0.5, mass_factor=mass_factor))
    sim = sw.Simulation([fluid, wall], kernel=CubicSpline(), h=1.2 * dx, gravity=(0.0, 0.0), hull=None,
                        domain=((-1.0, -1.0), (1.0, 1.0)))
    assert np.allclose(fluid.particles["m"], 10.0) and np.allclose(wall.particles["m"], 40.0)
    dv = np.zeros((9, 2))
    wall.model.interact(fluid, wall, _context(sim), dv, np.zeros(9))
    # back to TrixiParticles' order (x first, then y), whatever order seawall keeps the particles in
    x = fluid.particles["x"]
    return dv[np.lexsort((x[:, 0], x[:, 1]))]


def test_monaghan_kajtar_rhs_without_the_mass_factor_gives_trixiparticles_numbers():
    dv = _mk_rhs("none")
    # symmetric: horizontal only (TrixiParticles: |dv_y| <= 1e-14; here round-off of its 1e-17 scale)
    assert np.abs(dv[:, 1]).max() <= 1e-16 * np.abs(dv[:, 0]).max()
    assert not dv[[0, 3, 6]].any()                                       # leftmost column out of reach
    assert np.all(dv[[2, 5, 8], 0] < -300)                               # rightmost: strong push left
    np.testing.assert_allclose(dv[[1, 4, 7], 0], [-26.052449, -95.162888, -26.052449], rtol=2e-8)


def test_monaghan_kajtar_rhs_with_the_pair_factor_is_16_times_that():
    """seawall's default keeps 2 m_b / (m_a + m_b) = 2 * 40 / 50 = 1.6 ([TrixiBoundary]'s formula)."""
    pair, none = _mk_rhs("pair"), _mk_rhs("none")
    np.testing.assert_allclose(pair[:, 0], 1.6 * none[:, 0], rtol=1e-14, atol=0)
    assert np.abs(pair[:, 1]).max() <= 1e-16 * np.abs(pair[:, 0]).max()
