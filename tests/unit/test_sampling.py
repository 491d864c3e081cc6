"""Interpolation of fluid fields at points, lines (``--line``) and grids (seawall.sampling)."""

import csv
import json

import numpy as np
import pytest

from seawall.cases import build
from seawall.cli import main
from seawall.errors import ParameterError
from seawall.sampling import grid_points, interpolate, line_points, parse_line


@pytest.fixture(scope="module")
def tank():
    # 0.5 x 0.2 m of water at dx = 0.02 m; fields are set by hand below
    sim = build("hydrostatic", dx=0.02, length=0.5, depth=0.2, height=0.3, initial="rest")
    return sim


def test_constant_field_is_exact_wherever_there_is_fluid(tank):
    fp = tank.fluid.particles
    fp["p"][:] = 1234.5
    rng = np.random.default_rng(0)
    pts = rng.uniform((0.0, 0.0), (0.5, 0.2), size=(200, 2))
    out = interpolate(tank, pts, ("pressure",))["pressure"]
    np.testing.assert_allclose(out, 1234.5, rtol=1e-12)
    far = interpolate(tank, np.array([[0.25, 0.28], [5.0, 5.0]]), ("pressure",))["pressure"]
    assert np.isnan(far).all()      # no fluid neighbour (above the water; outside the domain)


def test_linear_field_is_exact_at_interior_lattice_points(tank):
    fp = tank.fluid.particles
    x = fp["x"]
    fp["p"][:] = 100.0 + 3000.0 * x[:, 0] - 5000.0 * x[:, 1]
    fp["v"][:, 0] = 0.5 - 2.0 * x[:, 1]
    fp["v"][:, 1] = 0.1 * x[:, 0]
    support = tank.kernel.support(tank.h)
    interior = (x[:, 0] > support) & (x[:, 0] < 0.5 - support) & (x[:, 1] > support) & (x[:, 1] < 0.2 - support)
    assert interior.sum() > 10
    out = interpolate(tank, x[interior], ("pressure", "u", "v"))
    np.testing.assert_allclose(out["pressure"], fp["p"][interior], rtol=1e-10, atol=1e-10 * np.abs(fp["p"]).max())
    np.testing.assert_allclose(out["u"], fp["v"][interior, 0], rtol=1e-10)
    np.testing.assert_allclose(out["v"], fp["v"][interior, 1], rtol=1e-10, atol=1e-14)


def test_lines_grids_and_their_errors():
    pts = line_points((0.0, 0.0), (1.0, 2.0), 5)
    np.testing.assert_allclose(pts[2], (0.5, 1.0))
    assert grid_points((0, 0), (1, 1), (3, 4)).shape == (12, 2)
    assert parse_line("0.1,0:0.1,0.3:7", 2) == ([0.1, 0.0], [0.1, 0.3], 7)
    for bad in ("0.1,0:0.1", "a,b:c,d:3", "0,0:1,1:1", "0,0,0:1,1,1:4"):
        with pytest.raises(ParameterError, match="--line"):
            parse_line(bad, 2)


def test_run_with_line_writes_the_profile(tmp_path):
    out = tmp_path / "run"
    code = main(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.02", "--output-every", "0.01", "--no-vtk",
                 "--no-progress", "--set", "length=0.5", "--set", "depth=0.2", "--set", "height=0.3",
                 "--line", "0.25,0.025:0.25,0.175:4", "--out", str(out)])
    assert code == 0
    rows = list(csv.DictReader(open(out / "line_1.csv")))
    assert list(rows[0]) == ["time", "s", "x", "y", "pressure", "u", "v"]
    times = sorted({float(r["time"]) for r in rows})
    assert times[0] == 0.0 and times[-1] == pytest.approx(0.02) and len(rows) == 4 * len(times)
    # still water from a hydrostatic start: pressure falls with height along the vertical line
    last = [float(r["pressure"]) for r in rows if float(r["time"]) == times[-1]]
    assert all(a > b for a, b in zip(last, last[1:]))
    summary = json.load(open(out / "summary.json"))
    assert summary["files"]["lines"] == ["line_1.csv"]
