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
    said = capsys.readouterr().out
    assert "largest |F| = 11.662 at t = 0.5 s (10, -6) N/m" in said
    # trapezoid over the two frames: 0.5 s x ((0, -5) + (10, -6)) / 2
    assert "impulse over 0-0.5 s: (2.5, -2.75) N/m s" in said
    assert main(["forces", str(run), "--wall", "tank", "--out", str(tmp_path / "f.csv")]) == 0
    assert (tmp_path / "f.csv").read_text().splitlines() == lines
    assert main(["forces", str(run), "--wall", "lid"]) == 2
    assert "--wall: " in capsys.readouterr().err
    assert main(["sample", str(run), "--line", "0.05,0.05:0.15,0.05:3", "--time", "0.4",
                 "--quantities", "pressure", "--out", str(tmp_path / "s.csv")]) == 0
    rows = (tmp_path / "s.csv").read_text().splitlines()
    assert rows[0] == "time,s,x,y,pressure" and len(rows) == 4
    assert [float(r.split(",")[-1]) for r in rows[1:]] == pytest.approx([100.0] * 3, rel=1e-12)   # frame 0.5: x2
    assert main(["sample", str(run), "--line", "0,0:1,1:3", "--quantities", "w"]) == 2
    assert "needs a 3D run" in capsys.readouterr().err


def _tank_dir(tmp_path, gravity=(0.0, -9.81)):
    """A still 0.2 m deep lattice over a floor row (surface y = 0, normal +y): hydrostatic p = rho g (H - y)."""
    dx, h, depth, rho = 0.01, 0.013, 0.2, 1000.0
    x = _lattice(dx, 20)
    floor = np.stack([(np.arange(-3, 23) + 0.5) * dx, np.full(26, -0.5 * dx)], axis=1)
    run = tmp_path / "tank"
    fluid = PVDSeries(str(run), "fluid")
    wall = PVDSeries(str(run), "wall_floor")
    meta = {"h": h, "dx": dx, "kernel": "CubicSpline", "dimension": 2}
    if gravity is not None:
        meta["gravity"] = list(gravity)
    for t in (0.0, 0.1):
        fluid.write(t, x, {"pressure": rho * 9.81 * (depth - x[:, 1]), "density": np.full(len(x), rho),
                           "mass": np.full(len(x), rho * dx * dx), "velocity": np.zeros((len(x), 2))},
                    metadata=meta, field_data={"TimeValue": t, "h": h})
        mirror = floor * [1.0, -1.0]          # 2 s - x with the surface point s = (x, 0)
        wall.write(t, floor, {"id": np.arange(len(floor)), "normal": np.tile([0.0, 1.0], (len(floor), 1)),
                              "mirror_point": mirror}, metadata=meta, field_data={"TimeValue": t})
    return run, dx, depth, rho


def test_sensor_and_gauge_from_stored_frames_read_still_water(tmp_path):
    from seawall.postprocess import gauge_series, sensor_series

    run, dx, depth, rho = _tank_dir(tmp_path)
    # the extrapolation of [Adami2012] eq. 27 continues a hydrostatic field exactly: a point sensor and a
    # face (constant pressure along the floor) both read rho g H, whatever the face's diameter
    times, p = sensor_series(str(run), [((0.1, 0.0), None), ((0.1, 0.002), 0.05)])
    np.testing.assert_array_equal(times, [0.0, 0.1])
    np.testing.assert_allclose(p, rho * 9.81 * depth, rtol=1e-12)
    # the half-filled kernel sits on the surface of a lattice block: measured +8.7e-6 m (0.001 dx)
    _, eta = gauge_series(str(run), [0.1, 0.05])
    np.testing.assert_allclose(eta, depth, atol=2e-5)
    _, dry = gauge_series(str(run), [5.0])
    assert np.isnan(dry).all()


def test_sensor_off_the_wall_and_files_without_gravity_are_refused(tmp_path):
    from seawall.errors import ParameterError
    from seawall.postprocess import gauge_series, sensor_series

    run, dx, _, _ = _tank_dir(tmp_path)
    with pytest.raises(ParameterError, match="not on a wall surface"):
        sensor_series(str(run), [((0.1, 0.05), None)])
    old, _, _, _ = _tank_dir(tmp_path / "old", gravity=None)
    with pytest.raises(ParameterError, match="does not record gravity"):
        gauge_series(str(old), [0.1])


def test_sample_command_writes_sensors_and_points(tmp_path, capsys):
    run, _, depth, rho = _tank_dir(tmp_path)
    assert main(["sample", str(run), "--sensor", "0.1,0:0.03", "--gauge", "0.1", "--point", "0.1,0.1"]) == 0
    lines = (run / "sensors.csv").read_text().splitlines()
    assert lines[0] == "time,sensor:1,gauge:1"
    t, p, eta = (float(v) for v in lines[1].split(","))
    assert t == 0.0 and abs(p - rho * 9.81 * depth) < 1e-6 and abs(eta - depth) < 1e-4
    assert (run / "sample.csv").exists()
    assert main(["sample", str(run)]) == 2
    assert "at least one of --line, --point, --sensor, --gauge" in capsys.readouterr().err
    assert main(["sample", str(run), "--gauge", "0.1,nope"]) == 2
    assert "--gauge must be" in capsys.readouterr().err
