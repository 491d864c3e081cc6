"""seawall forces / seawall sample: post-processing of a run directory's VTU series."""

import numpy as np
import pytest

from seawall.cli import main
from seawall.io import PVDSeries
from seawall.kernels import CubicSpline


def _lattice(dx, n):
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    return np.stack([(i.ravel() + 0.5) * dx, (j.ravel() + 0.5) * dx], axis=1)


def _run_dir(tmp_path, pressure_of):
    dx, h = 0.01, 0.013
    x = _lattice(dx, 20)
    run = tmp_path / "run"
    fluid = PVDSeries(str(run), "fluid")
    wall = PVDSeries(str(run), "wall_tank")
    for k, t in enumerate((0.0, 0.5)):
        meta = {"h": h, "dx": dx, "kernel": "CubicSpline", "dimension": 2}
        fluid.write(t, x, {"pressure": pressure_of(x) * (k + 1), "density": np.full(len(x), 1000.0),
                           "mass": np.full(len(x), 1000.0 * dx * dx), "velocity": np.tile([1.0, -2.0], (len(x), 1))},
                    metadata=meta, field_data={"TimeValue": t, "h": h}, compress=True)
        wall.write(t, x[:3] - 1.0, {"id": np.arange(3)}, metadata=meta,
                   field_data={"TimeValue": t, "wall_force": [10.0 * k, -5.0 - k]})
    return run, dx


def test_sample_reproduces_constant_and_symmetric_linear_fields(tmp_path):
    from seawall.postprocess import sample_series

    run, dx = _run_dir(tmp_path, lambda x: 3.0 * x[:, 0] - 7.0 * x[:, 1] + 100.0)
    # lattice points well inside the block (symmetric neighbourhoods), a point between them, one far outside
    points = np.array([[0.105, 0.095], [0.055, 0.145], [0.1, 0.1], [1.0, 1.0]])
    times, out = sample_series(str(run), points, ("pressure", "u", "v", "speed"))
    np.testing.assert_array_equal(times, [0.0, 0.5])
    exact = 3.0 * points[:2, 0] - 7.0 * points[:2, 1] + 100.0
    np.testing.assert_allclose(out["pressure"][0, :2], exact, rtol=1e-12)
    np.testing.assert_allclose(out["pressure"][1, :2], 2 * exact, rtol=1e-12)
    np.testing.assert_allclose(out["u"][:, :3], 1.0, rtol=1e-12)          # a constant field: exact anywhere
    np.testing.assert_allclose(out["speed"][:, :3], np.sqrt(5.0), rtol=1e-12)
    assert np.isnan(out["pressure"][:, 3]).all()
    # the between-lattice point: the Shepard sum by hand
    x = _lattice(dx, 20)
    r = np.linalg.norm(x - points[2], axis=1)
    w = CubicSpline().value(r, 0.013, 2)
    p = 3.0 * x[:, 0] - 7.0 * x[:, 1] + 100.0
    assert out["pressure"][0, 2] == pytest.approx(np.sum(w * p) / np.sum(w), rel=1e-12)


def test_sample_and_forces_commands_write_their_csv(tmp_path, capsys):
    run, _ = _run_dir(tmp_path, lambda x: np.full(len(x), 50.0))
    assert main(["forces", str(run)]) == 0
    lines = (run / "forces.csv").read_text().splitlines()
    assert lines == ["time,wall,fx,fy", "0,tank,0,-5", "0.5,tank,10,-6"]
    assert "largest |F| = 11.662 at t = 0.5 s" in capsys.readouterr().out
    assert main(["sample", str(run), "--line", "0.05,0.05:0.15,0.05:3", "--time", "0.4",
                 "--quantities", "pressure", "--out", str(tmp_path / "s.csv")]) == 0
    rows = (tmp_path / "s.csv").read_text().splitlines()
    assert rows[0] == "time,s,x,y,pressure" and len(rows) == 4
    assert [float(r.split(",")[-1]) for r in rows[1:]] == pytest.approx([100.0] * 3, rel=1e-12)   # frame 0.5: x2
    assert main(["sample", str(run), "--line", "0,0:1,1:3", "--quantities", "w"]) == 2
    assert "needs a 3D run" in capsys.readouterr().err
