"""Shepard interpolation of fluid fields at points, lines and grids; --line parsing; diagnostics.

What Shepard interpolation promises (seawall/interpolate.py): a constant is
reproduced exactly wherever fluid is near; a linear field a + b.x is
reproduced as a + b.x_c, x_c the kernel-weighted centroid of the neighbours,
hence exactly where the neighbourhood is symmetric (lattice nodes and cell
centres inside a regular lattice) and with a one-sided bias near a free surface.
"""

import json

import numpy as np
import pytest

import seawall as sw
from seawall.cli import main
from seawall.diagnostics import escape_side, pressure_noise
from seawall.errors import ParameterError
from seawall.interpolate import grid_points, interpolate, line_points, parse_line, read_line_csv

DX = 0.05
A0, B = 2.0, np.array([3.0, -1.5])


@pytest.fixture(scope="module")
def sim():
    fluid = sw.FluidSystem(sw.shapes.rectangle((0.0, 0.0), (1.0, 1.0), DX), eos=sw.Tait(c0=10.0))
    s = sw.Simulation([fluid], h=1.3 * DX, gravity=(0.0, 0.0), domain=((-0.5, -0.5), (1.5, 1.5)))
    fp = s.fluid.particles
    fp["f"] = A0 + fp["x"] @ B
    fp["one"] = np.ones(fp.n)
    return s


def brute_centroid(sim, pts):
    """sum_j x_j V_j W / sum_j V_j W by direct summation over all particles (cubic spline, h = 1.3 dx)."""
    fp = sim.fluid.particles
    h = 1.3 * DX
    out = []
    for p in pts:
        q = np.linalg.norm(fp["x"] - p, axis=1) / h
        w = np.where(q < 1, 1 - 1.5 * q ** 2 + 0.75 * q ** 3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0))
        vol = fp["m"] / fp["rho"]
        out.append((fp["x"] * (vol * w)[:, None]).sum(axis=0) / (vol * w).sum())
    return np.array(out)


def test_linear_field_exact_at_symmetric_interior_points(sim):
    nodes = np.array([[0.475, 0.525], [0.325, 0.675], [0.5, 0.5], [0.45, 0.6]])   # lattice nodes and cell centres
    res = interpolate(sim, nodes, ("f",))
    assert np.allclose(res["f"], A0 + nodes @ B, rtol=0, atol=1e-10)
    assert np.allclose(res["weight"], 1.0, atol=0.02)


def test_linear_field_is_evaluated_at_the_kernel_centroid(sim):
    rng = np.random.default_rng(3)
    pts = np.vstack([rng.uniform(0.3, 0.7, size=(20, 2)),     # interior: tiny centroid shift
                     [[0.5, 0.99], [0.02, 0.5], [0.5, 1.04]]])  # at and beyond the free surface: one-sided
    res = interpolate(sim, pts, ("f", "one"))
    centroid = brute_centroid(sim, pts)
    assert np.allclose(res["f"], A0 + centroid @ B, rtol=0, atol=1e-9)
    assert np.allclose(res["one"], 1.0, atol=1e-12)      # constants: exact everywhere with a neighbour
    exact = A0 + pts @ B
    assert np.max(np.abs(res["f"][:20] - exact[:20])) < 1e-3 * np.abs(B).sum() * DX * 20
    # near the surface the neighbours lie on one side: the error is of order dx, not round-off
    assert abs(res["f"][21] - exact[21]) > 0.01 * np.abs(B).sum() * DX


def test_points_without_fluid_give_nan_and_zero_weight(sim):
    res = interpolate(sim, np.array([[1.4, 1.4]]), ("v", "p"))
    assert np.isnan(res["u"][0]) and np.isnan(res["p"][0]) and res["weight"][0] == 0.0


def test_unknown_field_and_bad_points_name_the_parameter(sim):
    with pytest.raises(ParameterError, match="fields"):
        interpolate(sim, np.zeros((1, 2)), ("vorticity",))
    with pytest.raises(ParameterError, match="points"):
        interpolate(sim, np.zeros((1, 3)), ("p",))


def test_line_and_grid_points():
    pts = line_points((0, 0), (1, 2), 3)
    assert np.allclose(pts, [[0, 0], [0.5, 1], [1, 2]])
    g = grid_points((0, 0), (1, 1), (3, 2))
    assert g.shape == (6, 2) and np.allclose(g[:3, 0], [0, 0.5, 1]) and np.allclose(g[:3, 1], 0)


@pytest.mark.parametrize("text, fragment", [
    ("0,0:1,1", "x0,y0:x1,y1:n"),
    ("0,0:1,a:5", "end point"),
    ("0:1,1:5", "start point"),
    ("0,0:1,1,1:5", "same number of coordinates"),
    ("0,0:1,1:many", "whole number"),
    ("0,0:1,1:1", "at least 2"),
])
def test_parse_line_errors_name_the_option(text, fragment):
    with pytest.raises(ParameterError, match="--line") as info:
        parse_line(text)
    assert fragment in str(info.value)


def test_parse_line():
    assert parse_line("0,0.1:1,0.2:11") == ((0.0, 0.1), (1.0, 0.2), 11)


def test_cli_line_errors(capsys):
    assert main(["run", "hydrostatic", "--line", "0,0:1"]) == 2
    assert "--line" in capsys.readouterr().err
    assert main(["run", "hydrostatic", "--dx", "0.05", "--line", "0,0,0:1,1,1:4"]) == 2
    assert "--line" in capsys.readouterr().err


def test_run_writes_line_csv_escaped_csv_and_diagnostics(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.02", "--out", str(out), "--no-progress",
                 "--no-vtk", "--set", "length=0.5", "--set", "depth=0.2", "--set", "height=0.3",
                 "--line", "0.25,0:0.25,0.2:5", "--line-every", "0.01", "--diagnostics"])
    capsys.readouterr()
    assert code == 0
    times, cols = read_line_csv(str(out / "line.csv"))
    assert list(cols)[:5] == ["time", "point", "s", "x", "y"] and {"u", "v", "p", "rho", "weight"} <= set(cols)
    assert len(times) >= 2 and cols["p"].shape[1] == 5
    # hydrostatic start: pressure at mid-depth within a few % of rho g (H - y)
    assert cols["p"][-1, 2] == pytest.approx(1000 * 9.81 * 0.1, rel=0.05)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["files"]["lines"] == ["line.csv"] and summary["files"]["escaped"] == "escaped.csv"
    assert summary["escaped_where"]["by_side"] == {}
    assert summary["diagnostics"]["min_wall_distance_dx"] > 0
    assert set(summary["diagnostics"]["wall_pressure_noise_pa"]) == {"P0", "P1", "P2"}
    assert (out / "escaped.csv").read_text().splitlines() == ["time,id,x,y,side"]


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
