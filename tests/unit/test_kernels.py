"""Kernels: normalisation, gradient consistency, compact support."""

import math

import numpy as np
import pytest

from seawall.kernels import KERNELS, kernel_by_name, kernel_shape, kernel_shape_dq
from seawall.errors import ParameterError

ALL = sorted(KERNELS)


def lattice_sum(kernel, dim, h_factor=1.3):
    """sum_j V_j W(x_0 - x_j) on a regular lattice of unit spacing, at a lattice point."""
    dx = 1.0
    h = h_factor * dx
    reach = int(math.ceil(kernel.support(h) / dx)) + 1
    axes = [np.arange(-reach, reach + 1) * dx] * dim
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    r = np.linalg.norm(grid, axis=1)
    return float(np.sum(kernel.value(r, h, dim)) * dx ** dim)


# Kernels whose lattice sum at h = 1.3 dx is within 1e-3 of one. The others are
# not, by their nature (measured at 1.3 dx: cubic 3D -2.7e-3, Wendland C2 +1.0e-2
# (2D) / +9.5e-3 (3D), Wendland C4 +8.5e-3): see docs/kernels.md.
PARTITION_OF_UNITY_AT_1_3 = [("cubic", 2), ("quintic", 2), ("quintic", 3), ("gaussian", 2), ("gaussian", 3)]
NOT_AT_1_3 = [("cubic", 3), ("wendland-c2", 2), ("wendland-c2", 3), ("wendland-c4", 2), ("wendland-c4", 3)]


@pytest.mark.parametrize("name,dim", PARTITION_OF_UNITY_AT_1_3)
def test_lattice_sum_is_one_at_h_1_3_dx(name, dim):
    assert abs(lattice_sum(kernel_by_name(name), dim) - 1.0) < 1e-3


@pytest.mark.parametrize("name,dim", NOT_AT_1_3)
def test_lattice_sum_converges_with_h_for_the_others(name, dim):
    k = kernel_by_name(name)
    errors = [abs(lattice_sum(k, dim, hf) - 1.0) for hf in (1.3, 1.5, 2.0, 2.5)]
    assert errors[0] > 1e-3  # the fact documented above; a change here means the kernel changed
    assert errors[-1] < 1e-3
    assert errors[0] > errors[2] > errors[3] * 0.5


@pytest.mark.parametrize("name", ALL)
@pytest.mark.parametrize("dim", [2, 3])
def test_integral_is_one(name, dim):
    k = kernel_by_name(name)
    h = 0.7
    R = k.support(h)
    # composite Simpson in r of W(r) * surface(r); the kernels are piecewise polynomials in q
    # (or smooth), so 20001 points integrate them to far better than 1e-6
    r = np.linspace(0.0, R, 20001)
    w = k.value(r, h, dim)
    surface = 2 * math.pi * r if dim == 2 else 4 * math.pi * r * r
    f = w * surface
    dr = r[1] - r[0]
    integral = dr / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum())
    assert abs(integral - 1.0) < 1e-6


@pytest.mark.parametrize("name", ALL)
def test_derivative_matches_finite_difference(name):
    k = kernel_by_name(name)
    q = np.linspace(0.01, k.support_radius - 0.01, 500)
    eps = 1e-6
    fd = np.array([(kernel_shape(k.kind, x + eps) - kernel_shape(k.kind, x - eps)) / (2 * eps) for x in q])
    an = np.array([kernel_shape_dq(k.kind, x) for x in q])
    assert np.max(np.abs(fd - an)) < 1e-6 * max(1.0, np.max(np.abs(an)))


@pytest.mark.parametrize("name", ALL)
@pytest.mark.parametrize("dim", [2, 3])
def test_gradient_vector_against_finite_difference(name, dim):
    k = kernel_by_name(name)
    h = 0.5
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1, 1, size=(50, dim)) * k.support(h) / math.sqrt(dim)
    grad = k.gradient(pts, h)
    eps = 1e-6
    for a in range(dim):
        e = np.zeros(dim)
        e[a] = eps
        fd = (k.value(np.linalg.norm(pts + e, axis=1), h, dim) - k.value(np.linalg.norm(pts - e, axis=1), h, dim)) / (2 * eps)
        assert np.allclose(grad[:, a], fd, rtol=1e-5, atol=1e-7 * k.sigma(h, dim))


@pytest.mark.parametrize("name", ALL)
def test_compact_support_and_monotone(name):
    k = kernel_by_name(name)
    R = k.support_radius
    assert kernel_shape(k.kind, R) == 0.0
    assert kernel_shape(k.kind, R + 0.5) == 0.0
    assert kernel_shape_dq(k.kind, R) == 0.0
    q = np.linspace(0, R, 301)
    w = np.array([kernel_shape(k.kind, x) for x in q])
    assert np.all(np.diff(w) <= 1e-14)  # non-increasing
    assert np.all(w >= 0)
    # continuity at the support edge: the last values approach zero
    assert w[-2] < 1e-3 * w[0]


def test_cubic_spline_values_from_seed_000_eq3():
    k = kernel_by_name("cubic")
    h = 1.0
    assert k.value(0.0, h, 2) == pytest.approx(10 / (7 * math.pi))
    assert k.value(1.0, h, 2) == pytest.approx(10 / (7 * math.pi) * 0.25)
    assert k.value(1.5, h, 3) == pytest.approx(1 / math.pi * 0.25 * 0.5 ** 3)


def test_unknown_kernel_name():
    with pytest.raises(ParameterError, match="kernel must be one of"):
        kernel_by_name("spiky")


@pytest.mark.parametrize("name", ALL)
def test_gradient_factor_is_derivative_over_q(name):
    from seawall.kernels import kernel_gradient_factor
    k = kernel_by_name(name)
    q = np.linspace(1e-3, k.support_radius + 0.2, 777)
    expected = np.array([kernel_shape_dq(k.kind, x) / x for x in q])
    got = np.array([kernel_gradient_factor(k.kind, x) for x in q])
    assert np.allclose(got, expected, rtol=1e-10, atol=1e-12)
    # finite limit at q = 0 consistent with small q
    assert kernel_gradient_factor(k.kind, 0.0) == pytest.approx(kernel_shape_dq(k.kind, 1e-7) / 1e-7, rel=1e-5)
