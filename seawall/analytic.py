"""Exact solutions used by the flow cases and the validation entries.

* :func:`poiseuille_startup` -- body-force-driven flow between fixed plates started from rest
  (Morris, Fox & Zhu 1997, J. Comput. Phys. 136, eq. 21, written sign-consistently as in
  data/poiseuille_couette_analytic/README.txt):
      u(y, t) = F/(2 nu) y (L - y) - sum_n 4 F L^2 / (nu pi^3 (2n+1)^3) sin((2n+1) pi y / L)
                exp(-(2n+1)^2 pi^2 nu t / L^2)
* :func:`couette_startup` -- upper plate set in motion with U at t = 0 (Morris et al. 1997, eq. 22):
      u(y, t) = U y / L + sum_{n>=1} 2 U (-1)^n / (n pi) sin(n pi y / L) exp(-n^2 pi^2 nu t / L^2)
* :func:`taylor_green_2d` -- the decaying 2D Taylor-Green vortex on the periodic unit square
  (Taylor & Green 1937; data/taylor_green_vortex/README.txt):
      u = -U e^{bt} cos(2 pi x) sin(2 pi y),  v = U e^{bt} sin(2 pi x) cos(2 pi y),
      p = -(rho U^2 / 4) e^{2bt} (cos 4 pi x + cos 4 pi y),  b = -8 pi^2 / Re.
* :func:`elliptical_drop` -- Monaghan (1994, J. Comput. Phys. 110, sec. 5): an inviscid patch with
  u = -A x, v = A y stays an ellipse x = a cos t, y = sin t / a, with
      dA/dt = A^2 (a^4 - 1) / (a^4 + 1),  da/dt = -a A;
  integrated here with classical RK4 (no scipy dependency). :func:`elliptical_drop_pressure`:
  its pressure, p = rho a^2 (A^2 - dA/dt) (1 - x^2/a^2 - a^2 y^2) / 2 (zero on the surface).
"""

import math

import numpy as np


def poiseuille_startup(y, t, *, L, F, nu, terms=200):
    """Velocity u(y, t) [m/s] of start-up Poiseuille flow, plates at y = 0 and L, body force F [m/s^2]."""
    y = np.asarray(y, dtype=np.float64)
    u = F / (2.0 * nu) * y * (L - y)
    for n in range(terms):
        k = 2 * n + 1
        u = u - 4.0 * F * L * L / (nu * math.pi ** 3 * k ** 3) * np.sin(k * math.pi * y / L) \
            * math.exp(-k * k * math.pi ** 2 * nu * t / (L * L))
    return u


def couette_startup(y, t, *, L, U, nu, terms=2000):
    """Velocity u(y, t) [m/s] of start-up Couette flow, lower plate fixed, upper plate at speed U."""
    y = np.asarray(y, dtype=np.float64)
    u = U * y / L
    for n in range(1, terms + 1):
        decay = math.exp(-n * n * math.pi ** 2 * nu * t / (L * L))
        if decay < 1e-300:
            break
        u = u + 2.0 * U * (-1) ** n / (n * math.pi) * np.sin(n * math.pi * y / L) * decay
    return u


def taylor_green_2d(x, y, t, *, U=1.0, Re=100.0, rho=1.0):
    """(u, v, p) of the 2D Taylor-Green vortex of unit period at time t."""
    b = -8.0 * math.pi ** 2 / Re
    e = math.exp(b * t)
    u = -U * e * np.cos(2 * math.pi * x) * np.sin(2 * math.pi * y)
    v = U * e * np.sin(2 * math.pi * x) * np.cos(2 * math.pi * y)
    p = -0.25 * rho * U * U * e * e * (np.cos(4 * math.pi * x) + np.cos(4 * math.pi * y))
    return u, v, p


def elliptical_drop_pressure(x, y, *, A, a, dAdt, rho=1.0):
    """Pressure of Monaghan's elliptical drop, p = P (1 - x^2/a^2 - a^2 y^2), P = rho a^2 (A^2 - dA/dt) / 2 [Pa].

    [Monaghan1994] sec. 5: the velocity u = -A x, v = A y with semi-axes a (x) and 1/a (y)
    satisfies the Euler equations when p is zero on the ellipse and quadratic inside;
    the x-momentum equation, -(1/rho) dp/dx = (A^2 - dA/dt) x, fixes P. At t = 0
    (a = 1, dA/dt = 0): p = rho A0^2 (1 - x^2 - y^2) / 2.
    """
    P = 0.5 * rho * a * a * (A * A - dAdt)
    return P * (1.0 - (x / a) ** 2 - (a * y) ** 2)


def elliptical_drop(t, *, A0=100.0, steps_per_unit=200_000):
    """(A, a) of Monaghan's elliptical drop at time(s) t; semi-axes are a (x) and 1/a (y)."""
    ts = np.atleast_1d(np.asarray(t, dtype=np.float64))

    def rate(A, a):
        a4 = a ** 4
        return A * A * (a4 - 1.0) / (a4 + 1.0), -a * A

    out = np.empty((ts.size, 2))
    order = np.argsort(ts)
    A, a, now = A0, 1.0, 0.0
    for k in order:
        target = ts[k]
        n = max(1, int(math.ceil((target - now) * steps_per_unit)))
        h = (target - now) / n
        for _ in range(n):
            k1 = rate(A, a)
            k2 = rate(A + 0.5 * h * k1[0], a + 0.5 * h * k1[1])
            k3 = rate(A + 0.5 * h * k2[0], a + 0.5 * h * k2[1])
            k4 = rate(A + h * k3[0], a + h * k3[1])
            A += h / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            a += h / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        now = target
        out[k] = (A, a)
    return out if np.ndim(t) else out[0]
