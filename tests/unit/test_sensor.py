"""PressureSensor: wall pressure averaged over a finite face (seawall.probes, seawall.sampling.face_points)."""

import csv

import numpy as np
import pytest

from seawall import probes
from seawall.cases import build
from seawall.cli import main
from seawall.errors import ParameterError
from seawall.sampling import face_points, parse_sensor


@pytest.mark.parametrize("diameter,spacing", [(0.026, 0.005), (0.01, 0.02), (0.031, 0.0049)])
def test_face_quadrature_is_exact_to_second_moments_2d(diameter, spacing):
    c = np.array([1.0, 0.2])
    n = np.array([-1.0, 0.0])
    pts, w = face_points(c, n, diameter, spacing)
    assert w.sum() == pytest.approx(diameter)
    assert np.allclose(pts[:, 0], 1.0)                           # on the wall plane
    s = pts[:, 1] - c[1]
    assert np.dot(w, s) == pytest.approx(0.0, abs=1e-15)
    if pts.shape[0] > 1:
        # the midpoint rule integrates s^2 with error -D h^2 / 12 (h = D / m): within the cell-size term
        m = pts.shape[0]
        assert np.dot(w, s * s) == pytest.approx(diameter ** 3 / 12 * (1 - 1 / m ** 2))


@pytest.mark.parametrize("normal", [(0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (1.0, 2.0, -0.5)])
def test_face_quadrature_is_exact_to_second_moments_3d(normal):
    D = 0.03
    c = np.array([0.3, 0.1, 0.05])
    pts, w = face_points(c, normal, D, 0.004)
    n = np.asarray(normal) / np.linalg.norm(normal)
    r = pts - c
    assert np.allclose(r @ n, 0.0, atol=1e-15)
    assert w.sum() == pytest.approx(np.pi * D * D / 4)
    assert np.allclose(w @ r, 0.0, atol=1e-15)
    # second moment of a disc about a diameter: pi D^4 / 64 along any in-plane direction
    t = np.cross(n, [0.3, -0.7, 0.2])
    t /= np.linalg.norm(t)
    assert np.dot(w, (r @ t) ** 2) == pytest.approx(np.pi * D ** 4 / 64, rel=1e-12)


def test_sensor_equals_point_probe_in_still_water():
    # a linear (hydrostatic) field: the face mean is the value at the face's centre
    sim = build("hydrostatic", dx=0.02, length=0.5, depth=0.2, height=0.3)
    sensor = probes.PressureSensor("sensor", (0.0, 0.1))
    wide = probes.PressureSensor("wide", (0.0, 0.1), diameter=0.08)
    point = probes.WallPressure("point", (0.0, 0.1))
    sim.add(sensor, wide, point, every=0.05)
    result = sim.run(0.1, progress=False)
    assert sensor.diameter == pytest.approx(sim.kernel.support(sim.h))
    assert np.allclose(sensor.normal, (1.0, 0.0)) and np.allclose(sensor.center, (0.0, 0.1))
    p = result["point"]
    assert np.all(p > 500)
    assert np.allclose(result["sensor"], p, rtol=2e-3)
    assert np.allclose(result["wide"], p, rtol=5e-3)
    assert result.summary["sensors"]["sensor"]["diameter"] == pytest.approx(sensor.diameter)


def test_sensor_is_projected_onto_the_surface():
    sim = build("hydrostatic", dx=0.02, length=0.5, depth=0.2, height=0.3)
    s = probes.PressureSensor("s", (0.004, 0.1))   # 0.2 dx in front of the left wall
    sim.add(s)
    assert np.allclose(s.center, (0.0, 0.1))


@pytest.mark.parametrize("make,match", [
    (lambda: probes.PressureSensor("s", (0.0, 0.1), diameter=0.0), "diameter"),
    (lambda: probes.PressureSensor("s", (0.0, 0.1), diameter=-0.01), "diameter"),
    (lambda: probes.PressureSensor("s", (0.25, 0.1)), "not on a wall"),      # in the middle of the tank
    (lambda: probes.PressureSensor("s", (0.0, 0.1, 0.0)), "coordinates"),
])
def test_bad_sensors(make, match):
    sim = build("hydrostatic", dx=0.02, length=0.5, depth=0.2, height=0.3)
    with pytest.raises(ParameterError, match=match) as info:
        sim.add(make())
    assert "\n" not in str(info.value)


def test_parse_sensor():
    assert parse_sensor("1.61,0.06:0.01", 2) == ([1.61, 0.06], 0.01)
    assert parse_sensor("1.61,0.06", 2) == ([1.61, 0.06], None)
    for text, match in (("1.61,0.06:0", "diameter"), ("1.61,0.06:-1", "diameter"), ("1.61:0.01", "coordinates"),
                        ("a,b:1", "--sensor"), ("1,2:3:4", "--sensor")):
        with pytest.raises(ParameterError, match=match):
            parse_sensor(text, 2)


def test_cli_sensor_columns(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.01", "--out", str(out), "--no-progress",
                 "--no-vtk", "--set", "length=0.5", "--set", "depth=0.2", "--set", "height=0.3",
                 "--sensor", "0,0.1", "--sensor", "0.5,0.05:0.02"])
    capsys.readouterr()
    assert code == 0
    with open(out / "probes.csv") as fh:
        header = next(csv.reader(fh))
    assert header[-2:] == ["sensor:1", "sensor:2"] and header[:2] == ["t", "P0"]


@pytest.mark.parametrize("sensor,match", [("0,0.1:0", "diameter"), ("0.25,0.1", "not on a wall"),
                                          ("0,0.1,0:0.01", "coordinates")])
def test_cli_bad_sensor(tmp_path, capsys, sensor, match):
    code = main(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.01", "--out", str(tmp_path / "r"),
                 "--no-progress", "--no-vtk", "--sensor", sensor])
    err = capsys.readouterr().err
    assert code == 2 and match in err and len(err.strip().splitlines()) == 1
