"""Run diagnostics: where particles escaped, wall-pressure noise, smallest wall distance (seawall.diagnostics)."""

import json

import numpy as np
import pytest

from seawall.cli import main
from seawall.diagnostics import escape_side, pressure_noise


def test_run_writes_escaped_csv_and_diagnostics(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.02", "--out", str(out), "--no-progress",
                 "--no-vtk", "--set", "length=0.5", "--set", "depth=0.2", "--set", "height=0.3", "--diagnostics"])
    capsys.readouterr()
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["files"]["escaped"] == "escaped.csv"
    assert summary["escaped_where"]["by_side"] == {}
    assert summary["diagnostics"]["min_wall_distance_dx"] > 0
    assert set(summary["diagnostics"]["wall_pressure_noise_pa"]) == {"P0", "P1", "P2"}
    assert (out / "escaped.csv").read_text().splitlines() == ["time,id,x,y,side,reason"]


def test_escape_side_and_pressure_noise():
    assert escape_side([0.5, -0.1], [0, 0], [1, 1]) == "y-"
    assert escape_side([1.0, 0.5], [0, 0], [1, 1]) == "x+"
    assert escape_side([1.2, 1.5], [0, 0], [1, 1]) == "y+"
    assert escape_side([0.5, 0.5], [0, 0], [1, 1]) == "inside"
    t = np.arange(0, 2, 1e-3)
    rng = np.random.default_rng(0)
    p = 100 * np.sin(2 * np.pi * t) + rng.normal(0, 5.0, t.size)
    assert pressure_noise(t, p) == pytest.approx(5.0, rel=0.1)    # the slow signal is not noise
    assert pressure_noise(t[:3], p[:3]) is None


def test_impact_features_of_a_known_curve():
    from seawall.diagnostics import IMPACT_FEATURES, impact_features

    t = np.linspace(0.0, 7.5, 7501)
    # dry until 2.5, a step to 0.5 with a bump of 0.3 centred at 5.8
    p = np.where(t >= 2.5, 0.5, 0.0) + 0.3 * np.exp(-((t - 5.8) / 0.1) ** 2)
    f = dict(zip(IMPACT_FEATURES, impact_features(t, p)))
    assert f["arrival"] == pytest.approx(2.5, abs=1e-3)
    assert f["first_peak"] == pytest.approx(0.5, abs=1e-9)
    assert f["plateau"] == pytest.approx(0.5, abs=1e-6)
    assert f["secondary_peak"] == pytest.approx(0.8, abs=1e-6)
    assert f["secondary_time"] == pytest.approx(5.8, abs=1e-3)
    assert f["pre_impact"] == 0.0
    # a series that stops before a window gives NaN for it
    short = impact_features(t[t < 4.0], p[t < 4.0])
    assert np.isnan(short[2]) and np.isnan(short[3]) and np.isnan(short[5])


def test_interval_mean_is_the_step_weighted_mean():
    from seawall.diagnostics import interval_mean

    # steps of 0.3 ms and 0.1 ms alternating; p = step index; intervals of 1 ms
    dts = np.tile([3e-4, 1e-4], 10)
    t = np.cumsum(dts)
    p = np.arange(t.size, dtype=float)
    times, means = interval_mean(t, p, 1e-3)
    dts[0] = t[1] - t[0]          # the first sample stands for a step as long as the second's
    k = np.floor(t / 1e-3 - 1e-9).astype(int)
    for tt, m in zip(times, means):
        sel = k == round(tt / 1e-3) - 1
        assert m == pytest.approx(np.sum(dts[sel] * p[sel]) / np.sum(dts[sel]), rel=1e-12)
    # a constant stays constant
    assert np.allclose(interval_mean(t, np.full(t.size, 3.0), 1e-3)[1], 3.0)
