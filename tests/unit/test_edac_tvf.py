"""EDAC with the transport velocity: the pressure followed along v~ ([Ramachandran2019] sec. 3; seawall.fluid.edac).

dp_i/dt gains (v~_i - v_i) . grad p_i with grad p_i = sum_j V_j (p_j - p_i) grad_i W_ij, over the fluid and
the walls whose particles carry a pressure (their pressure from the model's ``update``, volume m_b / rho_b).

* a uniform pressure gives no term, whatever v~ - v;
* a linear pressure with a uniform v~ - v gives w . grad p in the interior of a lattice (measured: 0.98 %
  to 1.01 % below it with the cubic spline at h = 1.3 dx: the lattice's sum_j V_j r_ji (x) grad_i W_ij is
  not exactly the identity; asserted 2 %);
* at a wall: in the hydrostatic tank (dx = 0.02 m) with the wall pressure of Adami's extrapolation
  (``adami``) or of the ghost interpolation (``ghost-mls1``) the particles within 2h of the floor get the
  same value (measured 0.39 % to 0.59 % below, both; asserted 1.2 %); without the wall's particles the
  one-sided sum is up to 49.8 % off (asserted > 20 %), so the wall's share is what makes it right;
* the term is what an evaluation of an EDAC + TVF fluid adds, and only there (EDAC alone and the EOS
  fluid with the transport velocity do not call it).
"""

import numpy as np
import pytest

from seawall import shapes
from seawall.cases import build
from seawall.eos import Linear
from seawall.fluid import FluidSystem
from seawall.fluid.edac import edac_pressure_advection_rates
from seawall.pairs import edac_pressure_advection
from seawall.simulation import Simulation

C0 = 10.0
W = np.array([0.04, 0.07])      # v~ - v, the same for every particle


def unit_box(pressure, periodic=False, n=20):
    """n x n particles on the unit square, rho0 = 1, EDAC with the transport velocity."""
    block = shapes.rectangle((0.0, 0.0), (1.0, 1.0), 1.0 / n)
    fluid = FluidSystem(block, rho0=1.0, eos=Linear(c0=C0), viscosity=None, pressure_model="edac",
                        transport_velocity=True, pressure=pressure(block.positions))
    sim = Simulation([fluid], h=1.3 / n, gravity=(0.0, 0.0), domain=((0.0, 0.0), (1.0, 1.0)),
                     periodic=(periodic, periodic), threads=1)
    sim.evaluate(0.0)
    return sim


def advection_term(sim, w=W):
    """The term alone for v~ - v = w: what Simulation adds to dp/dt, from zero."""
    fp = sim.fluid.particles
    fp["dv_transport"][:] = w
    fp["dp"][:] = 0.0
    sim._edac_pressure_advection()
    return fp["dp"].copy()


def test_pair_term_is_the_difference_form():
    # V_j (p_j - p_i) (v~_i - v_i) . grad_i W_ij with grad_i W = f r_ij, tr = (v~_i - v_i) . r_ij
    assert edac_pressure_advection(2e-4, 100.0, 130.0, -5.0e3, 0.3) == pytest.approx(2e-4 * 30.0 * -5.0e3 * 0.3,
                                                                                      rel=1e-15)
    assert edac_pressure_advection(2e-4, 100.0, 100.0, -5.0e3, 0.3) == 0.0


def test_uniform_pressure_gives_no_term():
    sim = unit_box(lambda x: np.full(x.shape[0], 7.0), periodic=True)
    rng = np.random.default_rng(1)
    fp = sim.fluid.particles
    fp["dv_transport"][:] = rng.normal(0.0, 0.1, fp["dv_transport"].shape)
    fp["dp"][:] = 0.0
    sim._edac_pressure_advection()
    assert np.all(fp["dp"] == 0.0)


def test_linear_pressure_gives_w_dot_grad_p_in_the_interior():
    # small p against rho0 c0^2 = 100, so that the volumes m / rho are the lattice's to 0.1 %
    grad = np.array([0.03, -0.02])
    sim = unit_box(lambda x: 0.05 + x @ grad)
    dp = advection_term(sim)
    inside = np.all(np.abs(sim.fluid.particles["x"] - 0.5) < 0.3, axis=1)
    expected = W @ grad
    rel = (dp[inside] - expected) / abs(expected)
    assert np.all(np.abs(rel) < 0.02), (rel.min(), rel.max())
    # and the sign: the other direction of v~ - v gives the opposite term
    assert np.allclose(advection_term(sim, -W), -dp, rtol=0, atol=1e-15)


def tank(boundary):
    return build("hydrostatic", dx=0.02, boundary=boundary, delta=0.0, pressure_model="edac",
                 transport_velocity="true", tvf_free_surface="true", threads=1)


@pytest.mark.parametrize("boundary", ["adami", "ghost-mls1"])
def test_walls_extrapolated_pressure_completes_the_gradient_at_the_floor(boundary):
    sim = tank(boundary)
    sim.evaluate(0.0)
    assert [w.name for w in sim._edac_pressure_walls()] == ["tank"]
    fp = sim.fluid.particles
    x, y = fp["x"][:, 0], fp["x"][:, 1]
    reach = 2.0 * sim.h
    floor = (y < y.min() + reach) & (x > x.min() + 1.5 * reach) & (x < x.max() - 1.5 * reach)
    expected = W @ np.array([0.0, -fp["rho"].mean() * 9.81])    # hydrostatic: grad p = -rho g e_y
    with_wall = (advection_term(sim)[floor] - expected) / abs(expected)
    assert np.all(np.abs(with_wall) < 0.012), (with_wall.min(), with_wall.max())
    # the fluid's share alone: the one-sided sum misses the wall's half of the support
    fluid_only = np.zeros(fp.n)
    g, cells = sim.grid, sim.fluid_cells
    edac_pressure_advection_rates(g.layout, fp["x"], fp["p"], fp["dv_transport"], fp["x"], fp["volume"], fp["p"],
                                  cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period, sim.physics, True,
                                  fluid_only)
    assert np.abs((fluid_only[floor] - expected) / abs(expected)).max() > 0.2


def test_an_evaluation_adds_the_term_only_with_edac_and_the_transport_velocity(monkeypatch):
    grad = np.array([0.03, -0.02])
    sim = unit_box(lambda x: 0.05 + x @ grad)
    sim._dt_now = 1e-3          # v~ - v = dt/2 a_b is not zero once a step is being taken
    sim.evaluate(0.0)
    fp = sim.fluid.particles
    with_term = fp["dp"].copy()
    term = advection_term(sim, fp["dv_transport"].copy())
    assert np.abs(term).max() > 0.0
    monkeypatch.setattr(Simulation, "_edac_pressure_advection", lambda self: None)
    sim.evaluate(0.0)
    without = fp["dp"].copy()
    assert np.allclose(with_term - without, term, rtol=0, atol=1e-12 * np.abs(with_term).max())
    # never called by the other fluids: EDAC alone, and the EOS fluid with the transport velocity
    monkeypatch.setattr(Simulation, "_edac_pressure_advection", lambda self: pytest.fail("called"))
    build("taylor-green", n=16, threads=1, pressure_model="edac", delta=0.0).evaluate(0.0)
    eos = build("taylor-green", n=16, threads=1, transport_velocity="true")
    eos._dt_now = 1e-3
    eos.evaluate(0.0)
