"""Prescribed wall motion: positions, velocities and accelerations of the moving particles."""

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.movement import PrescribedMotion, sinusoidal_piston
from seawall.errors import ParameterError


def wall(n=6):
    x = np.stack([np.zeros(n), np.arange(n) * 0.01], axis=1)
    return sw.shapes.Shape(x, 0.01)


def test_finite_difference_derivatives_match_the_analytic_ones():
    f, v, a = sinusoidal_piston(0.05, 0.7)
    fd = PrescribedMotion(f)
    exact = PrescribedMotion(f, velocity=v, acceleration=a)
    for t in np.linspace(0.0, 1.4, 15):
        assert np.allclose(fd.velocity(t), exact.velocity(t), rtol=1e-7, atol=1e-9)
        assert np.allclose(fd.acceleration(t), exact.acceleration(t), rtol=1e-5, atol=1e-6)


def test_apply_moves_only_the_chosen_particles():
    motion = PrescribedMotion(lambda t: (0.1 * t, -0.2 * t * t), moving_particles=[1, 3])
    w = sw.WallSystem(wall(), movement=motion)
    x0 = w.x.copy()
    assert motion.apply(w, 0.5)
    moved = np.zeros(6, dtype=bool)
    moved[[1, 3]] = True
    assert np.allclose(w.x[moved], x0[moved] + [0.05, -0.05])
    assert np.allclose(w.x[~moved], x0[~moved])
    assert np.allclose(w.particles["v"][moved], [0.1, -0.2])
    assert np.allclose(w.particles["a"][moved], [0.0, -0.4], atol=1e-5)
    assert np.allclose(w.particles["v"][~moved], 0.0)


def test_is_moving_false_freezes_the_wall():
    motion = PrescribedMotion(lambda t: (t, 0.0), is_moving=lambda t: t < 1.0)
    w = sw.WallSystem(wall(), movement=motion)
    motion.apply(w, 0.5)
    x_half = w.x.copy()
    assert not motion.apply(w, 2.0)
    assert np.allclose(w.x, x_half)
    assert np.allclose(w.particles["v"], 0.0) and np.allclose(w.particles["a"], 0.0)


def test_bad_movement_input():
    with pytest.raises(ParameterError, match="movement_function"):
        PrescribedMotion(3.0)
    with pytest.raises(ParameterError, match="2 components"):
        sw.WallSystem(wall(), movement=PrescribedMotion(lambda t: (0.0, 0.0, 0.0)))
    with pytest.raises(ParameterError, match="moving_particles"):
        sw.WallSystem(wall(), movement=PrescribedMotion(lambda t: (0.0, 0.0), moving_particles=[9]))
