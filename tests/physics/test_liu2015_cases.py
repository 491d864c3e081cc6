"""[Liu2015] sec. 4 with the Liu et al. (2015) wall: the block between plates and the Re = 1 cavity.

plates (full resolution, dx = 1 mm, 1600 particles, 810 steps): with liu2015 every
particle stays on its rigid-translation path to 5e-13 m (the wall never acts on
a block sliding along it). Adami and Monaghan-Kajtar on the same case: see
docs/liu2015.md (validation/liu2015/run.py).

cavity (fluid liu2015, 4 layers) at Re = 1, dx = L/30, c0 = 0.05 m/s: at the
steady state (t = 0.2 s; the seed calls its run steady at 0.15 s) the largest
centreline deviation from the computed Re = 1 reference (stations at least dx
from the walls) is within 5 % of U. Later the [Liu2015] fluid without
regularisation (``--set transport_velocity=false``) lets the particle
distribution degrade and the vortex weakens: 10.1 % (u) and 5.4 % (v) at
t = 0.5 s -- the strict xfail records it. With the transport velocity of
[Adami2013] (p_b = rho0 c0^2), the case's default since issue 17, the same run
stays within 5 % (measured 1.4 % / 1.2 % at 0.2 s, 0.9 % / 0.8 % at 0.5 s).
"""

import numpy as np
import pytest

from seawall.cases import build
from seawall.cases.lid_cavity import centrelines


def test_block_leaves_the_plates_undeformed_with_liu2015():
    sim = build("plates", boundary="liu2015")
    result = sim.run(0.048, progress=False)
    assert result.summary["escaped_particles"] == 0
    # the block has left the plates (its top passed their lower end at t = 0.045 s)
    assert sim.fluid.particles["x"][:, 1].max() < 0.0
    # rigid translation to round-off: measured 4.6e-16 m (5e-13 m with an earlier version), i.e. the
    # wall never acts on the block; any wall action would move particles by a fraction of dx
    assert result["deformation_between"].max() < 1e-11
    assert result["deformation"].max() < 1e-11
    # nor is it compressed: measured pressure 0.0 Pa throughout (rho0 c0^2 is ~1e5 Pa)
    assert np.abs(result["p_min"]).max() < 1e-6 and np.abs(result["p_max"]).max() < 1e-6


REFERENCE = np.loadtxt("data/lid_driven_cavity_stokes_computed/cavity_Re1_centerlines.csv", delimiter=",",
                       skiprows=1)
N = 30
#: the Stokes start-up transient decays as exp(-52.3 nu t / L^2) (slowest Stokes mode of the square): 3e-5 at 0.2 s
STEADY = 0.2


def _deviation(sim):
    s = REFERENCE[:, 0]
    keep = (s >= 1.0 / N) & (s <= 1.0 - 1.0 / N)
    u, v = centrelines(sim, s[keep])
    return u, v, u - REFERENCE[keep, 1], v - REFERENCE[keep, 2]


@pytest.fixture(scope="module")
def cavity_re1():
    """The seed's scheme: the [Liu2015] fluid without regularisation."""
    sim = build("cavity", boundary="liu2015-noslip", fluid="liu2015", layers=4, dx=1e-3 / N, reynolds=1.0,
                c0=0.05, transport_velocity=False)
    steady = sim.run(STEADY, progress=False)
    at_steady = _deviation(sim)
    later = sim.run(0.5, progress=False)
    return steady, at_steady, later, _deviation(sim)


def test_cavity_re1_runs_and_turns_the_right_way(cavity_re1):
    steady, (u, v, du, dv), later, _ = cavity_re1
    assert steady.summary["escaped_particles"] == 0 and later.summary["escaped_particles"] == 0
    # the primary vortex: backflow below the lid on the vertical centreline, up on the right, down on the left
    assert u.min() < -0.1
    assert v.max() > 0.1 and v.min() < -0.1


def test_cavity_re1_centrelines_within_5_percent_at_steady_state(cavity_re1):
    _, (_, _, du, dv), _, _ = cavity_re1
    assert np.abs(du).max() < 0.05 and np.abs(dv).max() < 0.05


@pytest.mark.xfail(strict=True, reason="t = 0.5 s: 10.1 % (u) and 5.4 % (v) of U; the [Liu2015] fluid's particle "
                                       "distribution degrades after the steady state, see docs/liu2015.md")
def test_cavity_re1_centrelines_stay_within_5_percent(cavity_re1):
    _, _, _, (_, _, du, dv) = cavity_re1
    assert np.abs(du).max() < 0.05 and np.abs(dv).max() < 0.05


@pytest.fixture(scope="module")
def cavity_re1_transport_velocity():
    """The case's default scheme with the [Liu2015] fluid: [Adami2013]'s transport velocity."""
    sim = build("cavity", boundary="liu2015-noslip", fluid="liu2015", layers=4, dx=1e-3 / N, reynolds=1.0,
                c0=0.05)
    assert sim.fluid.transport_velocity is not None
    result = sim.run(0.5, progress=False)
    return result, _deviation(sim)


def test_cavity_re1_with_transport_velocity_stays_within_5_percent(cavity_re1_transport_velocity):
    result, (u, v, du, dv) = cavity_re1_transport_velocity
    assert result.summary["escaped_particles"] == 0
    assert u.min() < -0.1 and v.max() > 0.1 and v.min() < -0.1
    assert np.abs(du).max() < 0.05 and np.abs(dv).max() < 0.05


def test_case_parameters_are_checked():
    from seawall.errors import ParameterError

    with pytest.raises(ParameterError, match="gap"):
        build("plates", boundary="liu2015", gap=0.02)
    with pytest.raises(ParameterError, match="fluid"):
        build("cavity", boundary="liu2015-noslip", fluid="water")
    with pytest.raises(ParameterError, match="no-slip"):
        build("cavity", boundary="liu2015", fluid="liu2015")
    with pytest.raises(ParameterError, match="gate_speed"):
        build("dam-break-etsin", boundary="liu2015", gate_speed=-1.0)
