"""The elliptical drop's exact pressure against the Euler equations of its velocity field."""

import numpy as np
import pytest

from seawall.analytic import elliptical_drop, elliptical_drop_pressure


@pytest.mark.parametrize("t", [0.0, 0.003, 0.0076])
def test_drop_pressure_drives_the_exact_flow_and_vanishes_on_the_surface(t):
    eps = 1e-7
    if t == 0.0:
        A, a, dAdt = 100.0, 1.0, 0.0          # the ODE's dA/dt is A^2 (a^4 - 1) / (a^4 + 1) = 0 at a = 1
    else:
        A, a = elliptical_drop(t)
        dAdt = (elliptical_drop(t + eps)[0] - elliptical_drop(t - eps)[0]) / (2 * eps)
    rng = np.random.default_rng(3)
    th = rng.uniform(0, 2 * np.pi, 50)
    rr = rng.uniform(0, 1, 50)
    x, y = a * rr * np.cos(th), rr * np.sin(th) / a
    # u = -A x, v = A y: Du/Dt = (A^2 - dA/dt) x, Dv/Dt = (A^2 + dA/dt) y must equal -grad p / rho
    h = 1e-6
    p = lambda x, y: elliptical_drop_pressure(x, y, A=A, a=a, dAdt=dAdt, rho=2.0)  # noqa: E731
    gx = (p(x + h, y) - p(x - h, y)) / (2 * h)
    gy = (p(x, y + h) - p(x, y - h)) / (2 * h)
    scale = A * A
    assert np.max(np.abs(-gx / 2.0 - (A * A - dAdt) * x)) < 1e-5 * scale
    assert np.max(np.abs(-gy / 2.0 - (A * A + dAdt) * y)) < 1e-5 * scale
    surface = elliptical_drop_pressure(a * np.cos(th), np.sin(th) / a, A=A, a=a, dAdt=dAdt, rho=2.0)
    assert np.max(np.abs(surface)) < 1e-9 * scale
    assert elliptical_drop_pressure(0.0, 0.0, A=A, a=a, dAdt=dAdt) > 0


def test_drop_pressure_at_the_start_is_half_rho_A0_squared_at_the_centre():
    assert elliptical_drop_pressure(0.0, 0.0, A=100.0, a=1.0, dAdt=0.0, rho=1.0) == pytest.approx(5000.0)
