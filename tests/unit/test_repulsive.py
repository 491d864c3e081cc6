"""Monaghan-Kajtar repulsive walls ([TrixiBoundary]): the acceleration against the formula evaluated by hand."""

import math

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.repulsive import MonaghanKajtar
from seawall.shapes import Shape, tank_surface

DX, BETA = 0.01, 3.0
H = 1.3 * DX
D = DX / BETA


def phi(q):
    return 0.0 if q >= 2 else 1.77 / 32 * (1 + 2.5 * q + 2 * q * q) * (2 - q) ** 5


def by_hand(r_vec, K, m_a, m_b, dim=2):
    r = np.linalg.norm(r_vec)
    return K / BETA ** (dim - 1) * r_vec / (r * (r - D)) * phi(r / H) * 2 * m_b / (m_a + m_b)


def one_particle_acceleration(y, K=2.0, mass_factor="pair"):
    """A single fluid particle at height y above a row of wall particles on y = 0 (no gravity)."""
    # built at a legal height (the overlap check wants >= 0.5 dx), then moved to y
    fluid = sw.FluidSystem(Shape(np.array([[0.0013, DX]]), DX), eos=sw.Tait(c0=10.0), viscosity=None)
    xs = np.arange(-10, 11) * D
    wall_shape = Shape(np.stack([xs, np.zeros_like(xs)], axis=1), D,
                       normals=np.tile([0.0, 1.0], (xs.size, 1)),
                       surface_points=np.stack([xs, np.zeros_like(xs)], axis=1))
    wall = sw.WallSystem(wall_shape, model=MonaghanKajtar(K=K, beta=BETA, mass_factor=mass_factor))
    sim = sw.Simulation([fluid, wall], h=H, domain=((-0.1, -0.05), (0.1, 0.1)))
    sim.fluid.particles["x"][0, 1] = y
    sim.evaluate(0.0)
    m_a = sim.fluid.particles["m"][0]
    m_b = sim.walls[0].particles["m"][0]
    expected = sum(by_hand(np.array([0.0013, y]) - np.array([xb, 0.0]), K, m_a, m_b) for xb in xs
                   if math.hypot(0.0013 - xb, y) < 2 * H)
    return sim.fluid.particles["dv"][0], expected


@pytest.mark.parametrize("y", [0.4 * DX, 0.5 * DX, 0.8 * DX, 1.2 * DX, 2.0 * DX])
def test_acceleration_equals_the_formula(y):
    got, expected = one_particle_acceleration(y)
    assert np.allclose(got, expected, rtol=1e-10, atol=1e-12)
    assert got[1] > 0  # pushes away from the wall


def test_grows_without_bound_towards_the_wall_row():
    ys = [1.0 * DX, 0.6 * DX, 0.45 * DX, 0.36 * DX, 0.34 * DX]
    push = [one_particle_acceleration(y)[0][1] for y in ys]
    assert all(b > a for a, b in zip(push, push[1:]))
    assert push[-1] > 20 * push[0]


def test_zero_beyond_the_support():
    got, _ = one_particle_acceleration(2.2 * H)
    assert np.allclose(got, 0.0)


def test_tank_surface_and_spacing_check():
    t = tank_surface((0, 0), (0.3, 0.2), D)
    assert np.allclose(np.linalg.norm(t.normals, axis=1), 1.0)
    fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.3, 0.1), DX), eos=sw.Tait(c0=10.0))
    wrong = sw.WallSystem(tank_surface((0, 0), (0.3, 0.2), DX / 2), model=MonaghanKajtar(K=1.0, beta=BETA))
    with pytest.raises(sw.ParameterError, match="dx / beta"):
        sw.Simulation([fluid, wrong], h=H, gravity=(0, -9.81))


def test_acceleration_equals_the_formula_in_3d():
    # one fluid particle above a square patch of surface particles at spacing dx / beta on z = 0
    xs = np.arange(-8, 9) * D
    patch = np.array([(a, b, 0.0) for a in xs for b in xs])
    n = patch.shape[0]
    wall_shape = Shape(patch, D, normals=np.tile([0.0, 0.0, 1.0], (n, 1)), surface_points=patch.copy())
    fluid = sw.FluidSystem(Shape(np.array([[0.0013, -0.0007, DX]]), DX), eos=sw.Tait(c0=10.0), viscosity=None)
    wall = sw.WallSystem(wall_shape, model=MonaghanKajtar(K=2.0, beta=BETA))
    sim = sw.Simulation([fluid, wall], h=H, domain=((-0.1, -0.1, -0.05), (0.1, 0.1, 0.1)))
    for z in (0.5 * DX, DX, 1.5 * DX):
        sim.fluid.particles["x"][0, 2] = z
        sim.evaluate(0.0)
        p = np.array([0.0013, -0.0007, z])
        m_a = sim.fluid.particles["m"][0]
        m_b = sim.walls[0].particles["m"][0]
        expected = sum(by_hand(p - q, 2.0, m_a, m_b, dim=3) for q in patch if np.linalg.norm(p - q) < 2 * H)
        np.testing.assert_allclose(sim.fluid.particles["dv"][0], expected, rtol=1e-9)
        assert sim.fluid.particles["dv"][0][2] > 0.0


@pytest.mark.parametrize("y", [0.5 * DX, 1.2 * DX])
def test_mass_factor_none_is_the_pair_form_over_its_factor(y):
    # TrixiParticles' code form: the same force without 2 m_b / (m_a + m_b); with seawall's masses
    # (m_b / m_a = beta^-2 in 2D) the pair form is 2 / (1 + beta^2) = 0.2 of it (docs/boundaries.md)
    pair, _ = one_particle_acceleration(y)
    none, _ = one_particle_acceleration(y, mass_factor="none")
    scale = np.abs(pair).max()
    np.testing.assert_allclose(pair, none * 2.0 / (1.0 + BETA ** 2), rtol=1e-12, atol=1e-12 * scale)
    # the conversion of K: K_none = K_pair 2 / (1 + beta^2) gives the same acceleration
    converted, _ = one_particle_acceleration(y, K=2.0 * 2.0 / (1.0 + BETA ** 2), mass_factor="none")
    np.testing.assert_allclose(converted, pair, rtol=1e-12, atol=1e-12 * scale)


def test_mass_factor_refuses_unknown_values():
    with pytest.raises(sw.ParameterError, match="mass_factor"):
        MonaghanKajtar(K=1.0, mass_factor="trixi")
    from seawall.boundary.registry import boundary_by_name

    assert boundary_by_name("monaghan-kajtar", {"mass_factor": "none"}).mass_factor == "none"
