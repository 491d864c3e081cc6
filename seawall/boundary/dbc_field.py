"""Dimensionless force and potential of dynamic boundary particles ([Li2022] Fig. 1, 2 and 4).

Two particles of equal mass m with summation densities ([Li2022] eq. 15-17)
rho_a = rho_b = m (W_ab + W_0), rho_0 = m W_0, and the EOS expanded to N
terms (eq. 21) push each other with (eq. 18, 23)

    dv_a/dt = -2 c^2 W_ab / (W_ab + W_0)^2 f_N(theta) grad_a W_ab,
    theta = W_ab / W_0,  f_N = sum_{k<N} a_k theta^k,  a = (1, 3, 5, 5, 3, 1, 1/7).

With W = sigma w(q) (w(0) = 1 for the cubic spline) the kernel
normalisation cancels: the dimensionless force F* = |dv_a/dt| h / c^2 is

    F*(q) = 2 theta f_N(theta) |w'(q)| / (1 + theta)^2,   theta = w(q).

The dimensionless potential is U*(q) = int_q^2 F*(s) ds; U*(0) is the
"total potential energy" of the seed's Fig. 2.

For the rectangular support (eq. 26) with the correction alpha_DB (eq. 28)
the kernel of the pair is alpha_DB sigma w(|r_1|/h), so theta = alpha_DB w
and grad W gains the factor alpha_DB: F* = 2 theta f_N |alpha_DB w'| / (1 + theta)^2,
along the wall normal and only within the rectangle's tangential window.
"""

import numpy as np

from ..kernels import CUBIC_SPLINE, kernel_shape, kernel_shape_dq
from .dbc import EXPANSION, alpha_db

__all__ = ["f_order", "pair_force", "pair_potential", "potential_energy", "row_force_field"]


def f_order(theta, order):
    """f_N(theta) of [Li2022] eq. 23, N = ``order`` terms."""
    theta = np.asarray(theta, dtype=np.float64)
    f = np.zeros_like(theta)
    for k in range(order - 1, -1, -1):
        f = f * theta + EXPANSION[k]
    return f


def _w(q):
    return np.array([kernel_shape(CUBIC_SPLINE, float(v)) for v in np.ravel(q)]).reshape(np.shape(q))


def _dw(q):
    return np.array([kernel_shape_dq(CUBIC_SPLINE, float(v)) for v in np.ravel(q)]).reshape(np.shape(q))


def pair_force(q, order, scale=1.0):
    """Dimensionless repulsion F* = |dv/dt| h / c^2 of one wall particle at distance q h (eq. 23).

    ``scale`` multiplies the kernel (alpha_DB for the corrected rectangular support).
    """
    q = np.asarray(q, dtype=np.float64)
    theta = scale * _w(q)
    return 2.0 * theta * f_order(theta, order) * np.abs(scale * _dw(q)) / (1.0 + theta) ** 2


def pair_potential(q, order, scale=1.0, samples=4001):
    """U*(q) = int_q^2 F*(s) ds (trapezoidal rule on ``samples`` points of [0, 2])."""
    s = np.linspace(0.0, 2.0, samples)
    f = pair_force(s, order, scale)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(s))])
    tail = cum[-1] - cum  # int_s^2
    return np.interp(np.asarray(q, dtype=np.float64), s, tail)


def potential_energy(order, scale=1.0):
    """Total dimensionless potential U*(0) = int_0^2 F* dq ([Li2022] Fig. 2)."""
    return float(pair_potential(0.0, order, scale))


def row_force_field(x, y, *, order=1, rectangular=False, correction=False, n_particles=6, h_over_dx=1.3):
    """Dimensionless force field (F*_x, F*_y) of a row of wall particles ([Li2022] Fig. 4).

    The row has ``n_particles`` particles at x = (k - (n-1)/2) dx, y = 0, normal +y;
    ``x``, ``y`` are arrays of fluid positions in units of dx. Each wall
    particle adds its two-particle force (eq. 23, pairwise superposition) with
    the circular kernel or the rectangular support of eq. 26 (window |x - x_k|
    <= dx, edges counted one half), times alpha_DB when ``correction``.
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    h = float(h_over_dx)
    scale = alpha_db(h, 1.0) if (rectangular and correction) else 1.0
    fx = np.zeros(np.broadcast(x, y).shape)
    fy = np.zeros_like(fx)
    for k in range(n_particles):
        xk = k - 0.5 * (n_particles - 1)
        dx_ = x - xk
        if rectangular:
            q = np.abs(y) / h
            a = np.abs(dx_)
            win = np.where(a < 1.0 - 1e-9, 1.0, np.where(a <= 1.0 + 1e-9, 0.5, 0.0))
            f = np.where(q < 2.0, pair_force(np.minimum(q, 2.0), order, scale), 0.0) * win
            fy += f * np.sign(y)
        else:
            r = np.hypot(dx_, y)
            q = r / h
            f = np.where(q < 2.0, pair_force(np.minimum(q, 2.0), order), 0.0)
            with np.errstate(invalid="ignore", divide="ignore"):
                fx += np.where(r > 0, f * dx_ / r, 0.0)
                fy += np.where(r > 0, f * y / r, 0.0)
    return fx, fy
