"""The density and kernel options shared by the taylor-green and cavity cases (cases.base.density_and_diffusion)."""

import numpy as np
import pytest

from seawall import integrators
from seawall.cases import build
from seawall.errors import ParameterError
from seawall.kernels import CubicSpline, QuinticSpline

CASES = [("taylor-green", {"n": 16}), ("cavity", {"dx": 1e-4})]


@pytest.mark.parametrize("name,size", CASES)
def test_an_evolved_density_gets_delta_sph_and_the_cubic_spline_by_default(name, size):
    # the cavity's default scheme sums the density ([Adami2013]); asked for, the evolved one is as before
    options = {"density": "continuity"} if name == "cavity" else {}
    sim = build(name, threads=1, **options, **size)
    assert sim.fluid.density_mode == "continuity"
    assert sim.fluid.density_diffusion is not None and sim.fluid.density_diffusion.delta == 0.1
    assert isinstance(sim.kernel, CubicSpline)
    assert sim.metadata["parameters"]["delta"] == 0.1


@pytest.mark.parametrize("name,size", CASES)
def test_summed_density_switches_delta_sph_off_and_records_it(name, size):
    sim = build(name, threads=1, density="summation", **size)
    assert sim.fluid.density_mode == "summation"
    assert sim.fluid.density_diffusion is None
    assert sim.metadata["parameters"]["delta"] == 0.0
    assert sim.metadata["parameters"]["density"] == "summation"


@pytest.mark.parametrize("name,size", CASES)
@pytest.mark.parametrize("options,message", [
    ({"density": "summation", "delta": 0.1}, "^delta: delta-SPH needs density=continuity"),
    ({"density": "summed"}, "^density must be one of continuity, summation, got 'summed'"),
    ({"kernel": "quartic"}, "^kernel must be one of"),
])
def test_bad_density_or_kernel_stops_in_one_line_naming_it(name, size, options, message):
    with pytest.raises(ParameterError, match=message) as err:
        build(name, threads=1, **size, **options)
    assert "\n" not in str(err.value)


def test_taylor_green_kernel_and_h_factor():
    sim = build("taylor-green", n=16, threads=1, kernel="quintic", h_factor=1.0)
    assert isinstance(sim.kernel, QuinticSpline)
    assert sim.h == pytest.approx(1.0 / 16)
    with pytest.raises(ParameterError, match="^h_factor"):
        build("taylor-green", n=16, threads=1, h_factor=0.0)


def test_taylor_green_summed_density_reads_the_periodic_lattice_as_rho0():
    """Summed over the periodic images, every particle of the regular lattice sees the same density, rho0 to
    the lattice's kernel-sum error; an evolved density starts from the exact pressure instead."""
    summed = build("taylor-green", n=16, threads=1, density="summation", background=0.0)
    summed.evaluate(0.0)
    rho = summed.fluid.particles["rho"]
    assert np.ptp(rho) < 1e-12
    assert abs(rho[0] - 1.0) < 5e-3
    evolved = build("taylor-green", n=16, threads=1, background=0.0)
    rho = evolved.fluid.particles["rho"]
    assert np.ptp(rho) > 1e-4     # rho0 + p_exact / c0^2 with p_exact = -(cos 4 pi x + cos 4 pi y) / 4


@pytest.mark.parametrize("integrator", [None, "LeapFrog", "PredictedLeapFrog"])
def test_a_summed_density_is_kept_after_each_step_not_the_first_evaluations(integrator):
    """After a step the stored density (and the pressure that output and probes compute from it) is the step's
    summed density, not the value the integrator's density update (rate zero) puts back: that left rho at the
    first evaluation's values for the whole run."""
    sim = build("cavity", dx=1e-4, threads=1, density="summation", background=0.0)
    if integrator is not None:   # the case's own is the symplectic one
        sim.integrator = getattr(integrators, integrator)(cfl=0.2)
    sim.run_steps(1)
    first = sim.fluid.particles["rho"].copy()
    sim.run_steps(60)
    rho = sim.fluid.particles["rho"].copy()
    assert np.max(np.abs(rho - first)) > 1e-6      # the lid has moved the particles: the sum has changed
    # the summation at the particles' present positions: the last evaluation's sum is half a step older
    sim.evaluate(sim.time)
    fresh = sim.fluid.particles["rho"]
    assert np.max(np.abs(rho - fresh)) < 0.05 * np.max(np.abs(rho - first))
