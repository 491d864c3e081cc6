"""Solitary waves from the Goring wave maker, and the spring-mounted seawall ([Huang2019] sec. 4.4).

Solitary wave (Adami walls, d = 0.1 m, H/d = 0.4, dx = d/14, flume 20 d, cubic
spline h = 1.3 dx, alpha = 0.01 (the wave cases' default), delta-SPH 0.1, c0 = 10 sqrt(g (d + H))):
the crest height is measured by surface gauges at 4 d and 14 d (10 depths of travel).
Measured while writing this test: see docs/waves.md (crest ratio and both heights);
at d/10 the same wave loses 10-13 % over 10 d and at d/20 0.5 %, so the resolution,
not the wave maker, sets the loss.

Spring wall: still water 0.1 m deep in front of a spring-mounted wall (m = 250 kg/m,
k = 10 N/m), dx = 0.01 m. The pairwise force of the water on it stays within
0.93-0.98 F_static, so with the seed's threshold 1.10 F_static it never moves; with
the threshold lowered to 0.8 F_static the same load passes it and the wall moves
forward from the first step, as the seed's update integrates the recorded force.
"""

import numpy as np
import pytest

from seawall.cases import build

D, HD, N = 0.1, 0.4, 14


@pytest.fixture(scope="module")
def solitary():
    sim = build("solitary-wave", boundary="adami", depth=D, height=HD * D, dx=D / N, length=20 * D,
                wall_height=2 * D, gauges=f"{4 * D},{14 * D}")
    sim.add(every=0.01)
    paddle = sim.reference["paddle"]
    result = sim.run(paddle.crest_arrival(14 * D) + 1.0 / (paddle.k * paddle.c), progress=False)
    return sim, result


# slow: one run of a 20 d flume (~7.5 min on a loaded 2-core machine); the wave maker's motion is
# guarded by tests/unit/test_wave_makers.py and prescribed wall motion by test_moving_wall.py
@pytest.mark.slow
def test_solitary_wave_keeps_its_height_over_ten_depths(solitary):
    sim, result = solitary
    h1 = np.nanmax(result[f"eta_{4 * D:g}"])
    h2 = np.nanmax(result[f"eta_{14 * D:g}"])
    H = HD * D
    assert abs(h1 - H) < 0.10 * H, (h1, H)   # the wave maker makes the asked-for wave
    assert abs(h2 / h1 - 1.0) < 0.05, (h1, h2)
    assert result.summary["escaped_particles"] == 0


@pytest.mark.slow
def test_solitary_wave_travels_at_its_celerity(solitary):
    sim, result = solitary
    t = result.times
    t1 = t[np.nanargmax(result[f"eta_{4 * D:g}"])]
    t2 = t[np.nanargmax(result[f"eta_{14 * D:g}"])]
    c = np.sqrt(9.81 * (D + HD * D))
    assert (10 * D) / (t2 - t1) == pytest.approx(c, rel=0.05)


def _spring_tank(boundary, ratio):
    sim = build("movable-seawall", boundary=boundary, dx=0.01, depth=0.1, height=0.03, wall_x=0.4,
                wall_height=0.2, floor_extra=0.2, wave=False, threshold_ratio=ratio)
    sim.add(every=0.01)
    return sim


@pytest.mark.parametrize("boundary", ["adami", "dbc", "ghost-shepard"])
def test_spring_wall_does_not_move_under_hydrostatic_load(boundary):
    sim = _spring_tank(boundary, 1.10)
    result = sim.run(0.5, progress=False)
    spring = sim.couplings[0]
    assert not spring.started and spring.displacement == 0.0
    assert np.all(result["wall_x"] == 0.4)
    assert np.nanmax(result["F_star"]) < 1.10


def test_spring_wall_moves_once_the_threshold_is_passed():
    sim = _spring_tank("adami", 0.8)
    result = sim.run(0.5, progress=False)
    spring = sim.couplings[0]
    assert spring.started and spring.onset_time < 0.01
    x = result["wall_x"] - 0.4
    assert np.all(x >= 0.0) and np.all(np.diff(x) >= 0.0) and x[-1] > 1e-3
    # the seed's update with the sampled force: x'' = (F - 0.8 F_s - k x) / m
    t, f = result.times, result["F_star"] * spring.static_force
    xs, v = 0.0, 0.0
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        a = (0.5 * (f[k] + f[k - 1]) - spring.threshold - spring.stiffness * xs) / spring.mass
        v += a * dt
        xs += v * dt
    assert x[-1] == pytest.approx(xs, rel=0.1)
