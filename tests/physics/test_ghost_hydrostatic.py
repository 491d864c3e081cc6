"""Hydrostatic tank with fixed ghost walls, each interpolation ([Huang2019] sec. 4.1, CI resolution).

dx = 0.025 m (the seed: 0.01 m), [Huang2019]'s fluid scheme (marrone2011), 1.5 s
of simulated time (a few seconds of wall time each). The wall probes P0-P3
must stay within a tolerance of rho g (H - y) over the second half of the
run. Measured maximum errors (docs/ghost.md): 2.0-2.1 % of rho g H for MLS
(linear, quadratic), SFDI and the improved Shepard method, 4.1 % for the
normalised method; the tolerances leave a margin of about 1.7x.
"""

import numpy as np
import pytest

from seawall.cases import build

T_END = 1.5
#: maximum |p - rho g (H - y)| / (rho g H) over t in [T_END/2, T_END], per method (measured x ~1.7)
TOLERANCE = {
    "ghost-mls1": 0.035,      # measured 0.0202 (0.0203 before the all-pairs viscosity)
    "ghost-mls2": 0.035,      # measured 0.0202 (0.0205)
    "ghost-sfdi": 0.035,      # measured 0.0210 (0.0214)
    "ghost-normalized": 0.07,  # measured 0.0414 (0.0411)
    "ghost-shepard": 0.035,   # measured 0.0195 (0.0195)
}


@pytest.mark.parametrize("method", list(TOLERANCE))
def test_hydrostatic_wall_pressure(method):
    sim = build("hydrostatic", boundary=method, dx=0.025, scheme="marrone2011")
    sim.add(every=0.01)
    res = sim.run(T_END, progress=False)
    rho_g = 1000.0 * 9.81
    depth = 0.3
    late = res.times >= 0.5 * T_END
    worst = 0.0
    for name, y in (("P0", 0.0), ("P1", 0.1), ("P2", 0.2), ("P3", 0.25)):
        p = res[name][late]
        assert np.all(np.isfinite(p))
        worst = max(worst, float(np.max(np.abs(p - rho_g * (depth - y)))) / (rho_g * depth))
    print(f"{method}: max late error {worst * 100:.2f} % of rho g H")
    assert worst < TOLERANCE[method], worst
    # the fluid stays at rest: no particle escapes, kinetic energy small
    assert res.summary["escaped_particles"] == 0
    assert res["kinetic_energy"][-1] < 0.05
    # the ghost pressures are the hydrostatic field continued below the floor
    wall = sim.walls[0]
    x = wall.particles["x"]
    floor = (x[:, 1] < 0) & (x[:, 0] > 0.2) & (x[:, 0] < 0.8)
    p_expected = rho_g * (depth - x[floor, 1])
    assert np.max(np.abs(wall.particles["p"][floor] - p_expected)) < 0.05 * rho_g * depth
