"""The Riemann formulation of the pair terms ([Zhang2017] sec. 3): properties that must hold.

* P* is symmetric in i and j, so the pair forces m_i dv_i and m_j dv_j cancel (momentum);
* receding pairs and pairs at equal velocity get the plain average pressure (no dissipation);
* the low-dissipation limiter: for a small approach speed du the added pressure is
  eta rho0 du^2 / 2 (quadratic, small), for du >= c0/eta it is the acoustic rho0 c0 du / 2;
* at equal pressures the continuity term is the central one; a pressure jump diffuses
  (the particle with the higher pressure loses density);
* a fluid with the option and artificial viscosity or density diffusion is refused.
"""

import math

import pytest

from seawall import cases
from seawall.eos import Tait
from seawall.errors import ParameterError
from seawall.fluid import ArtificialViscosity, DeltaSPH, FluidSystem, RiemannSolver
from seawall.pairs import (continuity, riemann_continuity, riemann_fluid_jump, riemann_momentum_coefficient,
                           riemann_pressure, riemann_wall_jump)
from seawall import shapes

RHO0, C0, ETA = 1000.0, 20.0, 3.0
Z = RHO0 * C0


def test_interface_pressure_is_symmetric():
    # vr = v_ij . r_ij and r are the same for the pair seen from j; only the pressures swap
    for vr in (-0.3, -1e-3, 0.0, 0.2):
        # seen from j, r_ji = -r_ij and v_ji = -v_ij: the same v . r, the same jump
        a = riemann_pressure(1500.0, 900.0, riemann_fluid_jump(vr, 0.01), Z, C0, ETA)
        b = riemann_pressure(900.0, 1500.0, riemann_fluid_jump(vr, 0.01), Z, C0, ETA)
        assert a == b
        assert riemann_momentum_coefficient(a, 1001.0, 999.0) == riemann_momentum_coefficient(b, 999.0, 1001.0)


def test_no_dissipation_for_receding_or_equal_velocity_pairs():
    for vr in (0.0, 1e-4, 0.5):
        assert riemann_pressure(1200.0, 800.0, riemann_fluid_jump(vr, 0.01), Z, C0, ETA) == pytest.approx(
            1000.0, rel=1e-15)


def test_limiter_quadratic_then_acoustic():
    r = 0.01
    du = 0.01                                  # approach speed, far below c0 / eta
    extra = riemann_pressure(0.0, 0.0, riemann_fluid_jump(-du * r, r), Z, C0, ETA)
    assert extra == pytest.approx(0.5 * ETA * RHO0 * du * du, rel=1e-12)
    du = 2.0 * C0 / ETA                        # beyond the limiter's cap
    extra = riemann_pressure(0.0, 0.0, riemann_fluid_jump(-du * r, r), Z, C0, ETA)
    assert extra == pytest.approx(0.5 * Z * du, rel=1e-12)


def test_wall_jump_is_normal_and_mirrored():
    # a particle moving into the wall at speed u (velocity . n = -u) meets the mirrored state: jump 2u,
    # and with the cap reached the acoustic water-hammer pressure rho0 c0 u of a rigid wall
    u = C0
    assert riemann_wall_jump(-u) == 2.0 * u
    assert riemann_pressure(0.0, 0.0, riemann_wall_jump(-u), Z, C0, ETA) == pytest.approx(Z * u, rel=1e-12)
    # sliding along the wall (velocity . n = 0) or leaving it: no dissipation
    assert riemann_pressure(300.0, 500.0, riemann_wall_jump(0.0), Z, C0, ETA) == 400.0
    assert riemann_pressure(300.0, 500.0, riemann_wall_jump(0.5), Z, C0, ETA) == 400.0


def test_continuity_central_at_equal_pressure_and_diffusive_otherwise():
    f, vr, r, vol = -3.0e4, -0.02 * 0.01, 0.01, 1e-4
    rho = 1000.0
    assert riemann_continuity(rho, vol, vr, 500.0, 500.0, r, Z, f) == pytest.approx(
        continuity(rho * vol, vr, f), rel=1e-14)
    # at rest: the higher-pressure particle loses density, its neighbour gains as much per unit volume
    hi = riemann_continuity(rho, vol, 0.0, 2000.0, 1000.0, r, Z, f)
    lo = riemann_continuity(rho, vol, 0.0, 1000.0, 2000.0, r, Z, f)
    assert hi < 0.0 and lo == pytest.approx(-hi, rel=1e-14)
    # the diffusion is (p_i - p_j) r / (rho0 c0) against the central v_ij . r_ij: the velocity jump
    # that the pressure jump carries in an acoustic wave
    assert hi == pytest.approx(rho * vol * f * 1000.0 * r / Z, rel=1e-14)


def test_refused_with_artificial_viscosity_or_diffusion():
    block = shapes.rectangle((0.0, 0.0), (0.1, 0.1), 0.01)
    with pytest.raises(ParameterError, match="riemann"):
        FluidSystem(block, eos=Tait(c0=C0), riemann=RiemannSolver())
    with pytest.raises(ParameterError, match="riemann"):
        FluidSystem(block, eos=Tait(c0=C0), viscosity=None, density_diffusion=DeltaSPH(delta=0.1),
                    riemann=RiemannSolver())
    FluidSystem(block, eos=Tait(c0=C0), viscosity=ArtificialViscosity(alpha=0.0), riemann=RiemannSolver())
    with pytest.raises(ParameterError, match="eta"):
        RiemannSolver(eta=0.0)
    with pytest.raises(ParameterError, match="alpha=0 and delta=0"):
        cases.build("dam-break", dx=0.05, riemann=True)
    with pytest.raises(ParameterError, match="diffusion"):
        cases.build("dam-break", dx=0.05, diffusion="laplacian")


def test_switches_the_compiled_physics():
    sim = cases.build("hydrostatic", dx=0.05, riemann=True, alpha=0.0, delta=0.0, riemann_eta=2.0)
    assert sim.physics.riemann == 1 and sim.physics.riemann_eta == 2.0
    assert cases.build("hydrostatic", dx=0.05).physics.riemann == 0
    assert math.isfinite(sim.first_time_step())
