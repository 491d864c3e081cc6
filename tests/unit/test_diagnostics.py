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
