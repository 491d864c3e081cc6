"""DEM contact law (seawall.dem) against the spring-dashpot formula by hand; restitution of a rebound."""

import math

import numpy as np
import pytest

from seawall.dem import DEMSimulation, DEMSystem, DEMWall, contact_time, damping_ratio
from seawall.errors import ParameterError
from seawall.shapes import Shape

R = 0.01
K = 2.0e5
E = 0.6


def pair(separation, velocity_j, dim=2, radius_j=R, density=2000.0):
    """Element 0 at the origin at rest, element 1 at +separation along the first axis moving with velocity_j."""
    x = np.zeros((2, dim))
    x[1, 0] = separation
    v = np.zeros((2, dim))
    v[1] = velocity_j
    dem = DEMSystem(x, np.array([R, radius_j]), density=density, normal_stiffness=K, restitution=E, velocity=v)
    sim = DEMSimulation([dem], domain=(np.full(dim, -0.1), np.full(dim, 0.1)))
    return sim, dem.particles


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("overlap", [1e-5, 1e-4, 1e-3])
def test_contact_force_is_the_spring_dashpot_formula(dim, overlap):
    r_j = 0.7 * R
    vj = np.zeros(dim)
    vj[0] = -0.3            # approaching
    vj[1] = 0.2             # tangential part: no effect (normal contact only)
    sim, pa = pair(R + r_j - overlap, vj, dim=dim, radius_j=r_j)
    m = pa["m"]
    m_eff = m[0] * m[1] / (m[0] + m[1])
    zeta = -math.log(E) / math.sqrt(math.pi ** 2 + math.log(E) ** 2)
    n = np.zeros(dim)
    n[0] = -1.0
    vn = float(np.dot(pa["v"][0] - pa["v"][1], n))
    f = (K * overlap - 2.0 * zeta * math.sqrt(K * m_eff) * vn) * n
    np.testing.assert_allclose(m[0] * pa["a"][0], f, rtol=1e-10)
    np.testing.assert_allclose(m[1] * pa["a"][1], -f, rtol=1e-10)   # action = reaction


def test_no_force_without_overlap():
    sim, pa = pair(2 * R * 1.0001, np.array([-1.0, 0.0]))
    assert np.all(pa["a"] == 0.0)
    assert np.all(pa["overlap"] == 0.0)


@pytest.mark.parametrize("e", [0.6, 0.9])
@pytest.mark.parametrize("gap", [0.05, 0.0523, 0.0551])
def test_rebound_on_a_wall_particle_has_the_chosen_restitution(e, gap):
    # head on, no gravity: a disc moving down onto one wall particle directly below; the gap sets
    # where in a step the contact starts. Within 2 % for e >= 0.6 at the default step t_c / 50
    # (measured at most 0.97 %); strongly damped contacts are less accurate (see seawall/dem.py).
    wall = DEMWall(Shape(np.array([[0.0, 0.0]]), 2 * R), K)
    dem = DEMSystem(np.array([[0.0, (2 + gap) * R]]), R, density=2000.0, normal_stiffness=K, restitution=e,
                    velocity=(0.0, -0.5))
    sim = DEMSimulation([dem, wall], domain=((-0.1, -0.1), (0.1, 0.1)))
    t_c = contact_time(K, dem.particles["m"][0], damping_ratio(e))
    assert sim.dt <= t_c / 50 * (1 + 1e-12)     # the stiffest, lightest contact sets the step
    sim.run(4 * t_c + 0.06 * R / 0.5, progress=False)
    v_out = dem.particles["v"][0, 1]
    assert v_out > 0
    assert v_out / 0.5 == pytest.approx(e, rel=0.02)
    assert np.all(dem.particles["a"] == 0.0)        # contact over


def test_bad_parameters_name_themselves():
    with pytest.raises(ParameterError, match="restitution"):
        DEMSystem(np.zeros((1, 2)), R, restitution=1.5)
    with pytest.raises(ParameterError, match="normal_stiffness"):
        DEMWall(Shape(np.zeros((1, 2)), R), -1.0)
    with pytest.raises(ParameterError, match="radius"):
        DEMSystem(np.zeros((1, 2)), 0.0)
