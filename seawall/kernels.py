"""Smoothing kernels W(r, h) and their radial derivatives, in 2D and 3D.

Each kernel is written as W(r, h) = sigma_d(h) * f(q) with q = r / h, where
f is a dimensionless shape and sigma_d the normalisation for dimension d.
Compiled code calls :func:`kernel_shape` / :func:`kernel_shape_dq` with an
integer kernel id and multiplies by a precomputed sigma, so one compiled
function serves every kernel (the branch on the id is perfectly predicted).

Kernels (support radius in units of h in brackets):

* ``CubicSpline`` [2]  -- Monaghan & Lattanzio (1985); [Li2022], eq. (3).
* ``QuinticSpline`` [3] -- Morris, Fox & Zhu (1997), eq. (12).
* ``WendlandC2`` [2], ``WendlandC4`` [2] -- Wendland (1995), in the q in
  [0, 2] scaling of Dehnen & Aly (2012), Table 1.
* ``Gaussian`` [3] -- truncated at 3h and renormalised so that it integrates
  to one ([Huang2019], sec. 2.1, the last equation of the section).
"""

import math

import numpy as np
from numba import njit

from .errors import ParameterError

CUBIC_SPLINE = 0
QUINTIC_SPLINE = 1
WENDLAND_C2 = 2
WENDLAND_C4 = 3
GAUSSIAN = 4

_EXP9 = math.exp(-9.0)


@njit(cache=True, inline="always")
def kernel_shape(kind, q):
    """Dimensionless kernel shape f(q); W = sigma * f(q)."""
    if kind == CUBIC_SPLINE:
        if q < 1.0:
            return 1.0 - 1.5 * q * q + 0.75 * q * q * q
        if q < 2.0:
            t = 2.0 - q
            return 0.25 * t * t * t
        return 0.0
    if kind == WENDLAND_C2:
        if q < 2.0:
            t = 1.0 - 0.5 * q
            t2 = t * t
            return t2 * t2 * (2.0 * q + 1.0)
        return 0.0
    if kind == WENDLAND_C4:
        if q < 2.0:
            t = 1.0 - 0.5 * q
            t2 = t * t
            return t2 * t2 * t2 * (35.0 / 12.0 * q * q + 3.0 * q + 1.0)
        return 0.0
    if kind == QUINTIC_SPLINE:
        if q < 3.0:
            t3 = 3.0 - q
            w = t3 * t3 * t3 * t3 * t3
            if q < 2.0:
                t2 = 2.0 - q
                w -= 6.0 * t2 * t2 * t2 * t2 * t2
                if q < 1.0:
                    t1 = 1.0 - q
                    w += 15.0 * t1 * t1 * t1 * t1 * t1
            return w
        return 0.0
    # GAUSSIAN, truncated at q = 3
    if q < 3.0:
        return math.exp(-q * q) - _EXP9
    return 0.0


@njit(cache=True, inline="always")
def kernel_shape_dq(kind, q):
    """Derivative df/dq of the dimensionless kernel shape (<= 0)."""
    if kind == CUBIC_SPLINE:
        if q < 1.0:
            return -3.0 * q + 2.25 * q * q
        if q < 2.0:
            t = 2.0 - q
            return -0.75 * t * t
        return 0.0
    if kind == WENDLAND_C2:
        if q < 2.0:
            # d/dq [(1-q/2)^4 (2q+1)] = -5 q (1-q/2)^3
            t = 1.0 - 0.5 * q
            return -5.0 * q * t * t * t
        return 0.0
    if kind == WENDLAND_C4:
        if q < 2.0:
            # product rule: d/dq [t^6 P(q)] with t = 1 - q/2 is t^5 (t P' - 3 P)
            t = 1.0 - 0.5 * q
            t5 = t * t * t * t * t
            poly = 35.0 / 12.0 * q * q + 3.0 * q + 1.0
            dpoly = 35.0 / 6.0 * q + 3.0
            return t5 * (t * dpoly - 3.0 * poly)
        return 0.0
    if kind == QUINTIC_SPLINE:
        if q < 3.0:
            t3 = 3.0 - q
            d = -5.0 * t3 * t3 * t3 * t3
            if q < 2.0:
                t2 = 2.0 - q
                d += 30.0 * t2 * t2 * t2 * t2
                if q < 1.0:
                    t1 = 1.0 - q
                    d -= 75.0 * t1 * t1 * t1 * t1
            return d
        return 0.0
    if q < 3.0:
        return -2.0 * q * math.exp(-q * q)
    return 0.0


@njit(cache=True, inline="always")
def kernel_gradient_factor(kind, q):
    """(df/dq) / q, so that grad W = sigma / h^2 * factor * (r_a - r_b).

    Written out per kernel so that most branches need no division (the pair
    loops are bound by divisions); finite at q = 0 and checked against
    kernel_shape_dq(q) / q in tests/unit/test_kernels.py.
    """
    if kind == CUBIC_SPLINE:
        if q < 1.0:
            return -3.0 + 2.25 * q
        if q < 2.0:
            t = 2.0 - q
            return -0.75 * t * t / q
        return 0.0
    if kind == WENDLAND_C2:
        if q < 2.0:
            t = 1.0 - 0.5 * q
            return -5.0 * t * t * t
        return 0.0
    if kind == WENDLAND_C4:
        if q < 2.0:
            # t^5 (t P' - 3 P) = -(7/3) q (2 + 5 q) t^5
            t = 1.0 - 0.5 * q
            return -7.0 / 3.0 * (2.0 + 5.0 * q) * t * t * t * t * t
        return 0.0
    if kind == QUINTIC_SPLINE:
        if q <= 0.0:
            return 20.0 * 27.0 - 120.0 * 8.0 + 300.0  # limit q -> 0: f"(0) = -120
        return kernel_shape_dq(kind, q) / q
    if q < 3.0:
        return -2.0 * math.exp(-q * q)
    return 0.0


def kernel_sigma(kind, h, dim):
    """Normalisation sigma_d(h) such that the integral of W over space is one."""
    if dim not in (2, 3):
        raise ParameterError(f"dim must be 2 or 3, got {dim!r}")
    if kind == CUBIC_SPLINE:
        c = 10.0 / (7.0 * math.pi) if dim == 2 else 1.0 / math.pi
    elif kind == QUINTIC_SPLINE:
        c = 7.0 / (478.0 * math.pi) if dim == 2 else 1.0 / (120.0 * math.pi)
    elif kind == WENDLAND_C2:
        c = 7.0 / (4.0 * math.pi) if dim == 2 else 21.0 / (16.0 * math.pi)
    elif kind == WENDLAND_C4:
        c = 9.0 / (4.0 * math.pi) if dim == 2 else 495.0 / (256.0 * math.pi)
    elif kind == GAUSSIAN:
        if dim == 2:
            c = 1.0 / (math.pi * (1.0 - 10.0 * _EXP9))
        else:
            c = 1.0 / (4.0 * math.pi * (0.25 * math.sqrt(math.pi) * math.erf(3.0) - 10.5 * _EXP9))
    else:
        raise ParameterError(f"unknown kernel id {kind!r}")
    return c / h ** dim


class Kernel:
    """Base class of the kernel descriptions used to configure a simulation.

    A kernel object only describes; compiled code uses ``kind`` and the
    normalisation from :meth:`sigma`.
    """

    kind = -1
    support_radius = 2.0  # in units of h
    name = "kernel"

    def sigma(self, h, dim):
        return kernel_sigma(self.kind, h, dim)

    def support(self, h):
        """Support radius in metres for smoothing length h."""
        return self.support_radius * h

    def value(self, r, h, dim):
        """W(r, h) for an array of distances r (numpy, for tests and plots)."""
        r = np.asarray(r, dtype=np.float64)
        f = np.vectorize(lambda q: kernel_shape(self.kind, q))(r / h) if r.ndim else kernel_shape(self.kind, float(r) / h)
        return self.sigma(h, dim) * f

    def derivative(self, r, h, dim):
        """dW/dr for an array of distances r."""
        r = np.asarray(r, dtype=np.float64)
        f = np.vectorize(lambda q: kernel_shape_dq(self.kind, q))(r / h) if r.ndim else kernel_shape_dq(self.kind, float(r) / h)
        return self.sigma(h, dim) / h * f

    def gradient(self, rvec, h):
        """grad_a W(|r_a - r_b|) for difference vectors rvec = r_a - r_b, shape (n, d)."""
        rvec = np.atleast_2d(np.asarray(rvec, dtype=np.float64))
        dim = rvec.shape[1]
        r = np.linalg.norm(rvec, axis=1)
        dwdr = self.derivative(r, h, dim)
        with np.errstate(invalid="ignore", divide="ignore"):
            g = np.where(r[:, None] > 0, dwdr[:, None] * rvec / r[:, None], 0.0)
        return g

    def __repr__(self):
        return f"{type(self).__name__}()"


class CubicSpline(Kernel):
    """Cubic B-spline, support 2h (Monaghan & Lattanzio 1985; [Li2022] eq. 3)."""

    kind = CUBIC_SPLINE
    support_radius = 2.0
    name = "cubic"


class QuinticSpline(Kernel):
    """Quintic spline, support 3h (Morris, Fox & Zhu 1997, eq. 12)."""

    kind = QUINTIC_SPLINE
    support_radius = 3.0
    name = "quintic"


class WendlandC2(Kernel):
    """Wendland C2, support 2h (Wendland 1995; Dehnen & Aly 2012, Table 1)."""

    kind = WENDLAND_C2
    support_radius = 2.0
    name = "wendland-c2"


class WendlandC4(Kernel):
    """Wendland C4, support 2h (Wendland 1995; Dehnen & Aly 2012, Table 1)."""

    kind = WENDLAND_C4
    support_radius = 2.0
    name = "wendland-c4"


class Gaussian(Kernel):
    """Gaussian truncated at 3h and renormalised to unit integral ([Huang2019], sec. 2.1)."""

    kind = GAUSSIAN
    support_radius = 3.0
    name = "gaussian"


KERNELS = {k.name: k for k in (CubicSpline, QuinticSpline, WendlandC2, WendlandC4, Gaussian)}


def kernel_by_name(name):
    """Return a kernel instance from its name (``cubic``, ``quintic``, ...)."""
    try:
        return KERNELS[name]()
    except KeyError:
        raise ParameterError(f"kernel must be one of {', '.join(KERNELS)}; got {name!r}") from None
