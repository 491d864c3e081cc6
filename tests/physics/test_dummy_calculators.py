"""Every dummy-particle density calculator on the hydrostatic tank (dx = 0.02 m, hydrostatic start, 1.5 s).

Measured means of the bottom-wall pressure P0 against rho g H over 1.0-1.5 s:
adami -0.09 %, summation -2.2 %, continuity +0.1 % (+0.2 % with no slip), mirroring +18.8 %, zeroing
+165 % (zeroing lets particles sink 0.04 m into the floor; [TrixiBoundary] calls it the
worst option). The models that are meant to be usable must keep the bottom
pressure within 5 % (twice the worst measured, summation's 2.2 %) and every
particle inside the tank; mirroring and zeroing are only required to run and to
keep every particle in the domain.
"""

import numpy as np
import pytest

import seawall as sw
from seawall.cases import build

EXACT_P0 = 1000 * 9.81 * 0.3
RHO0_WALL = 1000.0  # the continuity wall starts at the reference density


def run(boundary, **options):
    sim = build("hydrostatic", dx=0.02, boundary=boundary, **options)
    sim.add(every=0.01)
    return sim, sim.run(1.5, progress=False)


@pytest.mark.parametrize("boundary,options", [("adami", {}), ("adami-noslip", {}), ("summation", {}),
                                              ("continuity", {}), ("continuity", {"slip": "noslip"})])
def test_usable_calculators_hold_still_water(boundary, options):
    sim, result = run(boundary, **options)
    late = result.times >= 1.0
    assert abs(result["P0"][late].mean() - EXACT_P0) < 0.05 * EXACT_P0
    x = sim.fluid.particles["x"]
    assert result.summary["escaped_particles"] == 0
    assert x[:, 1].min() > 0.0 and x[:, 0].min() > 0.0 and x[:, 0].max() < 1.0


@pytest.mark.parametrize("boundary", ["mirroring", "zeroing"])
def test_research_calculators_run(boundary):
    sim, result = run(boundary)
    assert result.summary["escaped_particles"] == 0
    assert np.isfinite(result["P0"]).all()


class RecordingDummy(sw.DummyParticles):
    """A dummy wall that records (time, wall density, wall density rate) at every update."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.log = []

    def update(self, wall, fluid, ctx):
        super().update(wall, fluid, ctx)
        pa = wall.particles
        self.log.append((float(ctx.time), pa["rho"].copy(), pa["drho"].copy() if "drho" in pa else None))


def wall_density_after_steps(density, slip, steps=30):
    model = RecordingDummy(density=density, slip=slip)
    sim = build("hydrostatic", dx=0.05, boundary=lambda: model, threads=1)
    sim.run_steps(steps)
    return model


def test_continuity_noslip_integrates_its_own_wall_density():
    # Adami's extrapolated density must not leak into the continuity wall: with no slip the Adami pass
    # only supplies the wall velocity. Measured on this set-up (30 steps, dx = 0.05 m, largest difference
    # over the wall particles): continuity vs adami 5.72 kg/m^3 free slip, 5.73 kg/m^3 no slip; before
    # the fix continuity-noslip differed from adami-noslip by 0.0053 kg/m^3 (it was adami).
    rho = {(d, s): wall_density_after_steps(d, s).log[-1][1]
           for d in ("adami", "continuity") for s in ("free", "noslip")}
    free_gap = np.abs(rho["continuity", "free"] - rho["adami", "free"]).max()
    noslip_gap = np.abs(rho["continuity", "noslip"] - rho["adami", "noslip"]).max()
    assert free_gap > 1.0
    assert noslip_gap > 0.5 * free_gap


def test_continuity_noslip_wall_density_is_the_integrated_rate():
    # explicit Euler over the interval between evaluations (seawall/boundary/dummy.py, `continuity`)
    log = wall_density_after_steps("continuity", "noslip").log
    t = np.array([e[0] for e in log])
    expected = RHO0_WALL + sum((t[k + 1] - t[k]) * log[k][2] for k in range(len(log) - 1))
    np.testing.assert_allclose(log[-1][1], expected, rtol=1e-12, atol=0)
