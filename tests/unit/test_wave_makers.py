"""Wave-maker trajectories, the spring-mounted wall's update ([Huang2019] sec. 4.4) and the wave probes' geometry."""

import math

import numpy as np
import pytest

from seawall.errors import ParameterError
from seawall.spring_wall import SpringWall
from seawall.waves import GoringPaddle, RegularPaddle, piston_height_to_stroke, wave_number


def test_goring_paddle_follows_the_depth_averaged_wave_velocity():
    H, d = 0.075, 0.25
    p = GoringPaddle(H, d)
    k, c = math.sqrt(3 * H / (4 * d ** 3)), math.sqrt(9.81 * (d + H))
    assert p.k == pytest.approx(k) and p.c == pytest.approx(c)
    for t in np.linspace(0.05, p.t_end - 0.05, 17):
        X = p.displacement(t)[0]
        eta = H / math.cosh(k * (c * t - X) - p.kL) ** 2
        assert p.velocity(t)[0] == pytest.approx(c * eta / (d + eta), rel=1e-12)
        e = 1e-5
        fd_v = (p.displacement(t + e)[0] - p.displacement(t - e)[0]) / (2 * e)
        fd_a = (p.velocity(t + e)[0] - p.velocity(t - e)[0]) / (2 * e)
        assert fd_v == pytest.approx(p.velocity(t)[0], rel=1e-6, abs=1e-9)
        assert fd_a == pytest.approx(p.acceleration(t)[0], rel=1e-5, abs=1e-7)
    # total stroke: the wave's volume int eta dx = 2 H / k pushed by the paddle, S ~ 2 H / (k d) (Goring 1978)
    assert p.stroke == pytest.approx(2 * H / (k * d), rel=1e-2)
    assert p.displacement(-1.0)[0] == 0.0 and p.displacement(10 * p.t_end)[0] == p.stroke


def test_regular_paddle_matches_linear_wavemaker_theory():
    T, d = 1.0, 0.5
    k = wave_number(T, d)
    assert (2 * math.pi / T) ** 2 == pytest.approx(9.81 * k * math.tanh(k * d), rel=1e-12)
    # shallow-water limit of the piston transfer function: H/S -> kd
    assert piston_height_to_stroke(1e-3, 1.0) == pytest.approx(1e-3, rel=1e-3)
    p = RegularPaddle(0.02, T, d, ramp=2.0)
    assert p.stroke == pytest.approx(0.02 / piston_height_to_stroke(k, d))
    t = 5.25  # after the ramp: X = S/2 sin(omega t)
    assert p.displacement(t)[0] == pytest.approx(0.5 * p.stroke * math.sin(2 * math.pi * t / T))
    e = 1e-5
    for t in (0.3, 1.7, 3.1):
        assert (p.displacement(t + e)[0] - p.displacement(t - e)[0]) / (2 * e) == pytest.approx(p.velocity(t)[0], rel=1e-6)
        assert (p.velocity(t + e)[0] - p.velocity(t - e)[0]) / (2 * e) == pytest.approx(p.acceleration(t)[0], rel=1e-6)


def test_solitary_wave_rejects_breaking_heights():
    with pytest.raises(ParameterError, match="height"):
        GoringPaddle(0.2, 0.25)
    with pytest.raises(ParameterError, match="depth"):
        GoringPaddle(0.1, -1.0)


def _spring(**kw):
    args = dict(mass=250.0, stiffness=10.0, static_force=100.0, threshold_ratio=1.10)
    args.update(kw)
    return SpringWall("seawall", **args)


def test_spring_wall_stays_put_at_or_below_the_threshold():
    s = _spring()
    for force in (0.0, 100.0, 109.9, 110.0):
        assert s.step_motion(force, 1e-3) == (0.0, 0.0, 0.0)


def test_spring_wall_update_is_the_seed_scheme():
    s = _spring()
    dt = 1e-3
    x, v, a = s.step_motion(130.0, dt)          # 20 N/m above the threshold
    assert a == pytest.approx(20.0 / 250.0)
    assert v == pytest.approx(a * dt) and x == pytest.approx(v * dt)
    x1, v1, a1 = s.step_motion(100.0, dt)       # below: only the spring acts, -k x / m
    assert a1 == pytest.approx(-10.0 * x / 250.0)
    assert v1 == pytest.approx(v + a1 * dt) and x1 == pytest.approx(x + v1 * dt)


def test_spring_wall_never_goes_behind_its_start_and_oscillates_like_a_spring():
    s = _spring(stiffness=1000.0)
    dt = 1e-3
    xs = []
    for n in range(4000):   # a push for 0.2 s, then the spring pulls it back
        x, v, _ = s.step_motion(200.0 if n < 200 else 0.0, dt)
        xs.append(x)
    xs = np.array(xs)
    assert xs.min() >= 0.0 and xs.max() > 0.0
    assert xs[-1] == 0.0 and s.velocity == 0.0  # came back to its stop and rests there
    # while pushed: x'' = (F - F_th - k x)/m, x(0) = 0 -> x = (F_e/k)(1 - cos(w t))
    w = math.sqrt(1000.0 / 250.0)
    t = 0.2
    assert xs[199] == pytest.approx(90.0 / 1000.0 * (1 - math.cos(w * t)), rel=2e-2)


def test_spring_wall_parameters_are_checked():
    with pytest.raises(ParameterError, match="mass"):
        _spring(mass=0.0)
    with pytest.raises(ParameterError, match="stiffness"):
        _spring(stiffness=-1.0)
    with pytest.raises(ParameterError, match="static_force"):
        _spring(static_force=0.0)
