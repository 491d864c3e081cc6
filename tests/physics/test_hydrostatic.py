"""Still water in a tank ([Huang2019] sec. 4.1) with Adami dummy walls, at CI resolution (dx = 0.02 m).

Reference: p = rho0 g (H - y). Measured with this set-up (cubic spline h = 1.3 dx,
alpha = 0.02, delta-SPH 0.1, c0 = 24.3 m/s): from a hydrostatic start the largest
deviation over 1.0-1.5 s is 0.17 % (P0), 0.43 % (P1), 0.84 % (P2) of rho0 g (H - y);
from rest (p = 0) the mean over 1-2 s is off by 0.95 %, 0.74 %, 2.2 % (asserted 3 %),
but acoustic ringing of +-7 % remains at 2 s (alpha = 0.02 damps it slowly).
"""

import numpy as np
import pytest

from seawall.cases import build

RHO0, G, DEPTH = 1000.0, 9.81, 0.3
PROBE_Y = {"P0": 0.0, "P1": 0.1, "P2": 0.2}  # the probes 0.1 m and more below the surface


@pytest.fixture(scope="module")
def settled():
    sim = build("hydrostatic", dx=0.02, initial="hydrostatic")
    sim.add(every=0.01)
    result = sim.run(1.5, progress=False)
    return sim, result


#: largest |p - rho0 g (H - y)| / (rho0 g (H - y)) over 1.0-1.5 s, about twice the measured
SETTLED_TOLERANCE = {"P0": 0.004,    # measured 0.0017
                     "P1": 0.009,    # measured 0.0043
                     "P2": 0.017}    # measured 0.0084


def test_wall_pressure_after_settling(settled):
    sim, result = settled
    window = result.times >= 1.0
    for name, y in PROBE_Y.items():
        exact = RHO0 * G * (DEPTH - y)
        values = result[name][window]
        limit = SETTLED_TOLERANCE[name] * exact
        assert np.all(np.abs(values - exact) < limit), (name, values.min(), values.max(), exact)


def test_no_particle_leaves_the_tank(settled):
    sim, result = settled
    x = sim.fluid.particles["x"]
    assert result.summary["escaped_particles"] == 0
    assert x[:, 1].min() > 0.0            # floor at y = 0
    assert x[:, 0].min() > 0.0 and x[:, 0].max() < 1.0  # side walls at x = 0 and 1


def test_mass_constant_to_round_off(settled):
    sim, result = settled
    mass = result["mass"]
    assert np.all(np.abs(mass - mass[0]) <= 1e-12 * mass[0])
    assert abs(result.summary["mass_drift"]) < 1e-12


def test_settles_from_rest_to_the_hydrostatic_mean():
    sim = build("hydrostatic", dx=0.02, initial="rest")
    sim.add(every=0.005)
    result = sim.run(2.0, progress=False)
    window = result.times >= 1.0
    for name, y in PROBE_Y.items():
        exact = RHO0 * G * (DEPTH - y)
        mean = result[name][window].mean()
        assert abs(mean - exact) < 0.03 * exact, (name, mean, exact)
    assert sim.fluid.particles["x"][:, 1].min() > 0.0


#: Riemann formulation ([Zhang2017], alpha = 0, delta = 0) from rest: measured mean over 1-2 s off by
#: 0.09 %, 0.08 %, 1.9 % and standard deviation over 1.5-2 s of 0.20 %, 0.23 %, 0.76 % of rho0 g (H - y)
#: at P0, P1, P2 (the central scheme with alpha = 0.02 still rings by +-7 % at P0 then). Asserted: the
#: same 3 % on the mean as the central scheme, and a deviation below 2 % (about 2.5 times the largest
#: measured), which the central scheme's ringing does not meet.
RIEMANN_STD = 0.02


def test_riemann_settles_from_rest_without_ringing():
    sim = build("hydrostatic", dx=0.02, initial="rest", riemann=True, alpha=0.0, delta=0.0)
    sim.add(every=0.005)
    result = sim.run(2.0, progress=False)
    window = result.times >= 1.0
    late = result.times >= 1.5
    for name, y in PROBE_Y.items():
        exact = RHO0 * G * (DEPTH - y)
        mean = result[name][window].mean()
        assert abs(mean - exact) < 0.03 * exact, (name, mean, exact)
        assert result[name][late].std() < RIEMANN_STD * exact, (name, result[name][late].std(), exact)
    assert result.summary["escaped_particles"] == 0


def test_edac_keeps_still_water_within_the_settled_tolerances():
    """The EDAC pressure ([Ramachandran2019], alpha_edac = 0.5, no delta-SPH) with Adami walls from the hydrostatic
    start: measured largest deviation over 1.0-1.5 s 0.15 % (P0), 0.52 % (P1), 0.69 % (P2) of rho0 g (H - y),
    within the tolerances of the standard scheme above."""
    sim = build("hydrostatic", dx=0.02, initial="hydrostatic", pressure_model="edac", delta=0.0)
    sim.add(every=0.01)
    result = sim.run(1.5, progress=False)
    window = result.times >= 1.0
    for name, y in PROBE_Y.items():
        exact = RHO0 * G * (DEPTH - y)
        values = result[name][window]
        assert np.all(np.abs(values - exact) < SETTLED_TOLERANCE[name] * exact), (name, values.min(), values.max())
    assert result.summary["escaped_particles"] == 0
    mass = result["mass"]
    assert np.all(np.abs(mass - mass[0]) <= 1e-12 * mass[0])
