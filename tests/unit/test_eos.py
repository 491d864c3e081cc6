"""Equations of state: round trip, sound speed, the seed's constants."""

import numpy as np
import pytest

from seawall import Linear, Tait
from seawall.errors import ParameterError


@pytest.mark.parametrize("eos", [Tait(c0=25.0), Tait(c0=1460.0, gamma=7.0, background_pressure=1e3),
                                 Linear(c0=20.0), Linear(c0=10.0, background_pressure=-50.0)])
def test_round_trip(eos):
    rho0 = 998.1
    rho = np.linspace(0.9, 1.1, 41) * rho0
    p = eos.pressure(rho, rho0)
    assert np.allclose(eos.density(p, rho0), rho, rtol=1e-12, atol=0)


@pytest.mark.parametrize("eos", [Tait(c0=25.0), Linear(c0=20.0)])
def test_sound_speed_is_dp_drho(eos):
    rho0 = 1000.0
    rho = np.linspace(0.95, 1.05, 11) * rho0
    eps = 1e-3
    dpdrho = (eos.pressure(rho + eps, rho0) - eos.pressure(rho - eps, rho0)) / (2 * eps)
    assert np.allclose(np.sqrt(dpdrho), eos.sound_speed(rho, rho0), rtol=1e-6)


def test_tait_constant_b_and_reference():
    eos = Tait(c0=10.0, gamma=7.0)
    rho0 = 1000.0
    assert eos.pressure(rho0, rho0) == 0.0
    b = 10.0 ** 2 * rho0 / 7.0
    assert eos.pressure(1.01 * rho0, rho0) == pytest.approx(b * (1.01 ** 7 - 1))


def test_linear_is_first_order_tait():
    rho0 = 1000.0
    small = rho0 * (1 + 1e-6)
    assert Linear(c0=30.0).pressure(small, rho0) == pytest.approx(Tait(c0=30.0).pressure(small, rho0), rel=1e-5)


def test_tait_inverse_floor_keeps_density_positive():
    eos = Tait(c0=10.0)
    rho = eos.density(-1e9, 1000.0)
    assert rho > 0 and np.isfinite(rho)


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), "fast"])
def test_bad_c0(bad):
    with pytest.raises(ParameterError, match="c0"):
        Tait(c0=bad)
