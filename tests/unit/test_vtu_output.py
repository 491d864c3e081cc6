"""VTU output: zlib compression, float32, metadata and FieldData, parallel frames (.pvtu); plot colour range,
probe units, --out."""

import json
import os

import numpy as np
import pytest

from seawall.cli import main
from seawall.io import PVDSeries, read_vtu, write_probes_csv, write_vtu
from seawall.io.vtk import read_vtu_metadata, write_pvtu


def _data(n, seed=0):
    rng = np.random.default_rng(seed)
    return rng.random((n, 2)), {"pressure": rng.normal(0, 1e3, n), "velocity": rng.random((n, 2)),
                                "id": np.arange(n, dtype=np.int64), "flag": rng.random(n) > 0.5}


@pytest.mark.parametrize("n", [0, 1, 5000, 70_000])   # 70 000 float64 = 560 KB: 18 zlib blocks of 32 KiB
def test_compressed_files_read_back_exactly(tmp_path, n):
    x, data = _data(n)
    path = write_vtu(tmp_path / "a.vtu", x, data, compress=True)
    assert 'compressor="vtkZLibDataCompressor"' in open(path).read(400)
    pos, back = read_vtu(path)
    np.testing.assert_array_equal(pos[:, :2], x)
    for name in ("pressure", "id"):
        np.testing.assert_array_equal(back[name], data[name])
    np.testing.assert_array_equal(back["velocity"][:, :2], data["velocity"])
    np.testing.assert_array_equal(back["flag"], data["flag"].astype(np.uint8))


def test_compression_and_float32_shrink_the_file(tmp_path):
    x, data = _data(5000)
    plain = os.path.getsize(write_vtu(tmp_path / "p.vtu", x, data))
    packed = os.path.getsize(write_vtu(tmp_path / "z.vtu", x, data, compress=True))
    single = os.path.getsize(write_vtu(tmp_path / "f.vtu", x, data, compress=True, float32=True))
    assert single < packed < plain
    pos, back = read_vtu(tmp_path / "f.vtu")
    assert back["pressure"].dtype == np.float32 and back["id"].dtype == np.int64
    np.testing.assert_array_equal(back["id"], data["id"])      # integers stay exact
    np.testing.assert_allclose(back["pressure"], data["pressure"], rtol=2 ** -23)
    np.testing.assert_allclose(pos[:, :2], x, rtol=2 ** -23)


def test_a_damaged_compressed_block_is_named(tmp_path):
    x, data = _data(100)
    path = write_vtu(tmp_path / "a.vtu", x, {"pressure": data["pressure"]}, compress=True)
    text = open(path).read()
    start = text.index('Name="pressure"')
    line_start = text.index("\n", start) + 1
    line_end = text.index("\n", line_start)
    payload = text[line_start:line_end].strip()
    broken = payload[:-8] + ("A" * 8 if payload[-8:] != "A" * 8 else "B" * 8)
    with open(path, "w") as fh:
        fh.write(text[:line_start] + "  " + broken + text[line_end:])
    with pytest.raises(ValueError, match="pressure"):
        read_vtu(path)


def test_metadata_and_field_data_round_trip(tmp_path):
    x, data = _data(10)
    md = {"case": "a--b", "model": "adami", "note": "-->"}
    path = write_vtu(tmp_path / "m.vtu", x, data, metadata=md, field_data={"TimeValue": 0.25, "wall_force": [1.5, -2]},
                     compress=True)
    meta = read_vtu_metadata(path)
    assert {k: meta[k] for k in md} == md
    assert meta["TimeValue"] == 0.25 and meta["wall_force"] == [1.5, -2.0]
    read_vtu(path)      # still a valid VTK XML file (the comment holds no '--')
    assert read_vtu_metadata(write_vtu(tmp_path / "n.vtu", x, data)) == {}


def test_a_pvtu_frame_reads_as_its_pieces_joined(tmp_path):
    x, data = _data(30)
    fields = {"TimeValue": 0.5, "h": 0.01}
    cut = [slice(0, 12), slice(12, 12), slice(12, 30)]          # the middle piece holds no particle
    names = [f"f_00003_p{r}.vtu" for r in range(3)]
    for name, part in zip(names, cut):
        write_vtu(tmp_path / name, x[part], {k: v[part] for k, v in data.items()}, field_data=fields,
                  metadata={"case": "c", "piece": 1}, compress=True, float32=True)
    path = write_pvtu(tmp_path / "f_00003.pvtu", names, x[:0], {k: v[:0] for k, v in data.items()},
                      metadata={"case": "c"}, compress=True, float32=True)
    text = open(path).read()
    assert '<PDataArray type="Float32" Name="velocity" NumberOfComponents="3"/>' in text
    assert '<PDataArray type="Int64" Name="id" NumberOfComponents="1"/>' in text
    assert '<PDataArray type="UInt8" Name="flag" NumberOfComponents="1"/>' in text
    assert '<PDataArray type="Float32" Name="Points" NumberOfComponents="3"/>' in text
    assert text.count("<Piece Source=") == 3
    pos, back = read_vtu(path)
    np.testing.assert_array_equal(back["id"], data["id"])
    np.testing.assert_allclose(pos[:, :2], x, rtol=2 ** -23)
    np.testing.assert_allclose(back["velocity"][:, :2], data["velocity"], rtol=2 ** -23)
    assert read_vtu_metadata(path) == {"case": "c", **fields}
    # a piece that does not hold what the frame declares is named
    write_vtu(tmp_path / names[1], x[:2], {"id": data["id"][:2]})
    with pytest.raises(ValueError, match="f_00003_p1.vtu holds arrays"):
        read_vtu(path)


def test_a_series_lists_pvtu_frames_and_resumes_after_them(tmp_path):
    series = PVDSeries(tmp_path, "fluid")
    assert series.next_index == 0
    series.add(0.0, "fluid_00000.pvtu")
    series.add(0.1, "fluid_00001.pvtu")
    again = PVDSeries(tmp_path, "fluid", resume=True, resume_after=0.05)
    assert again.files == [(0.0, "fluid_00000.pvtu")] and again.next_index == 1
    assert again.write(0.1, *_data(3)).endswith("fluid_00001.vtu")   # a serial restart goes on in .vtu


def test_colour_range_is_robust_unless_given():
    from seawall.plots import colour_range

    values = np.concatenate([np.linspace(0.0, 1000.0, 1000), [1e6, np.nan]])   # one impact outlier
    lo, hi = colour_range(values)
    assert lo == pytest.approx(np.percentile(values[:-1], 1)) and hi == pytest.approx(np.percentile(values[:-1], 99))
    assert hi < 2000.0
    assert colour_range(values, (-5.0, 5.0)) == (-5.0, 5.0)
    assert colour_range(np.full(4, 3.0)) == (2.5, 3.5)


def test_probe_units_are_per_metre_in_2d():
    from seawall import probes

    assert probes.probe_unit(probes.WallForce("F", "tank"), 2) == "N/m"
    assert probes.probe_unit(probes.WallForce("F", "tank"), 3) == "N"
    assert probes.probe_unit(probes.WallPressure("P", (0, 0)), 2) == "Pa"
    assert probes.probe_unit(probes.SurgeFront(), 2) == "m"


def test_plot_takes_clim_and_puts_the_probe_plot_beside_out(tmp_path, capsys):
    run = tmp_path / "run"
    x, data = _data(50)
    series = PVDSeries(str(run), "fluid")
    for t in (0.0, 0.1):
        series.write(t, x, {"pressure": data["pressure"], "mass": np.full(50, 0.1), "density": np.full(50, 1000.0)},
                     compress=True)
    wall = PVDSeries(str(run), "wall_tank")
    wall.write(0.0, x - 1.0, {"id": data["id"]})
    wall.write(0.1, x + 1.0, {"id": data["id"]})
    t = np.array([0.0, 0.1])
    write_probes_csv(str(run / "probes.csv"), t, {"P1": t * 10, "F": t, "front": t + 1})
    (run / "summary.json").write_text(json.dumps({"case": "c", "boundary": "adami",
                                                  "probe_units": {"P1": "Pa", "F": "N/m", "front": "m"}}))
    out = tmp_path / "pics" / "snap.png"
    assert main(["plot", str(run), "--out", str(out), "--probes", "--clim", "0,500"]) == 0
    printed = capsys.readouterr().out.split()
    assert printed == [str(out), str(tmp_path / "pics" / "snap_probes.png")]
    assert out.exists() and (tmp_path / "pics" / "snap_probes.png").exists() and not (run / "probes.png").exists()
    with pytest.raises(SystemExit) as stop:
        main(["plot", str(run), "--clim", "5,1"])
    assert stop.value.code == 2 and "--clim needs finite LO < HI" in capsys.readouterr().err
