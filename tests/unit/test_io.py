"""Tests of seawall.io: VTU/PVD output, HDF5 checkpoints and probe CSV files."""

import base64
import os
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

from seawall.io import (PVDSeries, ProbeCSVWriter, load_checkpoint, read_probes_csv,
                        read_vtu, save_checkpoint, write_probes_csv, write_vtu)


def _rng():
    return np.random.default_rng(1234)


def _pvd_entries(path):
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return [(float(ds.get("timestep")), ds.get("file")) for ds in root.iter("DataSet")]


def _no_temp_files(directory):
    return not [f for f in os.listdir(directory) if f.endswith(".tmp")]


# ---------------------------------------------------------------- VTU


def test_vtu_round_trip_2d(tmp_path):
    rng = _rng()
    n = 37
    x = rng.random((n, 2))
    data = {
        "pressure": rng.standard_normal(n),
        "velocity": rng.standard_normal((n, 2)),
        "id": np.arange(n, dtype=np.int64) * 7 - 3,
        "tag": np.arange(n, dtype=np.int32),
        "free_surface": rng.random(n) > 0.5,
    }
    path = write_vtu(tmp_path / "a.vtu", x, data)
    assert os.fspath(path) == os.fspath(tmp_path / "a.vtu")
    pos, back = read_vtu(tmp_path / "a.vtu")

    assert pos.shape == (n, 3) and pos.dtype == np.float64
    np.testing.assert_array_equal(pos[:, :2], x)
    np.testing.assert_array_equal(pos[:, 2], 0.0)
    assert list(back) == list(data)
    np.testing.assert_array_equal(back["pressure"], data["pressure"])
    assert back["pressure"].dtype == np.float64 and back["pressure"].shape == (n,)
    assert back["velocity"].shape == (n, 3)
    np.testing.assert_array_equal(back["velocity"][:, :2], data["velocity"])
    np.testing.assert_array_equal(back["velocity"][:, 2], 0.0)
    assert back["id"].dtype == np.int64
    np.testing.assert_array_equal(back["id"], data["id"])
    assert back["tag"].dtype == np.int32
    np.testing.assert_array_equal(back["tag"], data["tag"])
    assert back["free_surface"].dtype == np.uint8
    np.testing.assert_array_equal(back["free_surface"].astype(bool), data["free_surface"])
    assert _no_temp_files(tmp_path)


def test_vtu_round_trip_3d_and_float32(tmp_path):
    rng = _rng()
    n = 11
    x = rng.standard_normal((n, 3)) * 1e6
    data = {"v": rng.standard_normal((n, 3)).astype(np.float32),
            "rho": rng.random(n).astype(np.float32),
            "tiny": np.array([5e-324, -0.0, np.inf, -np.inf] + [1.0] * (n - 4))}
    write_vtu(tmp_path / "b.vtu", x, data)
    pos, back = read_vtu(tmp_path / "b.vtu")
    np.testing.assert_array_equal(pos, x)
    assert back["v"].dtype == np.float32 and back["v"].shape == (n, 3)
    np.testing.assert_array_equal(back["v"], data["v"])
    assert back["rho"].dtype == np.float32
    np.testing.assert_array_equal(back["rho"], data["rho"])
    # Bit-level equality, including the sign of zero.
    assert back["tiny"].tobytes() == data["tiny"].tobytes()


def test_vtu_empty(tmp_path):
    write_vtu(tmp_path / "e.vtu", np.zeros((0, 2)),
              {"p": np.zeros(0), "v": np.zeros((0, 2)), "id": np.zeros(0, dtype=np.int64)})
    root = ET.parse(tmp_path / "e.vtu").getroot()
    piece = root.find("./UnstructuredGrid/Piece")
    assert piece.get("NumberOfPoints") == "0" and piece.get("NumberOfCells") == "0"
    pos, back = read_vtu(tmp_path / "e.vtu")
    assert pos.shape == (0, 3)
    assert back["p"].shape == (0,)
    assert back["v"].shape == (0, 3)
    assert back["id"].shape == (0,) and back["id"].dtype == np.int64


def test_vtu_structure_is_valid_vtk(tmp_path):
    """Check the layout ParaView relies on: vertex cells and the byte-count header."""
    n = 5
    write_vtu(tmp_path / "c.vtu", np.ones((n, 2)), {"p": np.arange(n, dtype=float)})
    root = ET.parse(tmp_path / "c.vtu").getroot()
    assert root.get("type") == "UnstructuredGrid"
    assert root.get("byte_order") == "LittleEndian"
    assert root.get("header_type") == "UInt64"
    cells = {da.get("Name"): da for da in root.find("./UnstructuredGrid/Piece/Cells")}

    def decode(da, dtype):
        blob = base64.b64decode("".join(da.text.split()))
        nbytes = int(np.frombuffer(blob[:8], "<u8")[0])
        assert nbytes == len(blob) - 8
        return np.frombuffer(blob[8:], dtype)

    np.testing.assert_array_equal(decode(cells["connectivity"], "<i8"), np.arange(n))
    np.testing.assert_array_equal(decode(cells["offsets"], "<i8"), np.arange(1, n + 1))
    np.testing.assert_array_equal(decode(cells["types"], "u1"), np.ones(n))
    for da in root.iter("DataArray"):
        assert da.get("format") == "binary"


def test_vtu_special_names_and_bad_input(tmp_path):
    name = 'p<"&>\' x'
    write_vtu(tmp_path / "d.vtu", np.zeros((2, 3)), {name: np.array([1.0, 2.0])})
    _, back = read_vtu(tmp_path / "d.vtu")
    np.testing.assert_array_equal(back[name], [1.0, 2.0])

    with pytest.raises(ValueError, match="shape"):
        write_vtu(tmp_path / "bad.vtu", np.zeros((3, 4)))
    with pytest.raises(ValueError, match="'p'"):
        write_vtu(tmp_path / "bad.vtu", np.zeros((3, 2)), {"p": np.zeros(4)})
    with pytest.raises(TypeError):
        write_vtu(tmp_path / "bad.vtu", np.zeros((2, 2)), {"s": np.array(["a", "b"])})
    assert not (tmp_path / "bad.vtu").exists()
    assert _no_temp_files(tmp_path)


def test_read_vtu_uint32_header_and_separate_encoding(tmp_path):
    """The reader accepts VTK's UInt32 headers and a separately encoded header."""
    pts = np.array([[1.0, 2.0, 3.0]])
    flags = np.array([1], dtype=np.uint8)

    def together(arr, htype):
        raw = arr.tobytes()
        return base64.b64encode(np.array([len(raw)], htype).tobytes() + raw).decode()

    def separate(arr, htype):
        raw = arr.tobytes()
        return (base64.b64encode(np.array([len(raw)], htype).tobytes()).decode()
                + base64.b64encode(raw).decode())

    for htype, name, enc in (("<u4", "UInt32", together), ("<u4", "UInt32", separate),
                             ("<u8", "UInt64", separate)):
        text = f"""<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="{name}">
<UnstructuredGrid><Piece NumberOfPoints="1" NumberOfCells="1">
<PointData><DataArray type="UInt8" Name="b" format="binary">{enc(flags, htype)}</DataArray>
</PointData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">
{enc(pts, htype)}</DataArray></Points>
</Piece></UnstructuredGrid></VTKFile>
"""
        (tmp_path / "v.vtu").write_text(text)
        pos, data = read_vtu(tmp_path / "v.vtu")
        np.testing.assert_array_equal(pos, pts)
        np.testing.assert_array_equal(data["b"], flags)


def test_vtu_failed_write_keeps_previous_file(tmp_path, monkeypatch):
    path = tmp_path / "keep.vtu"
    write_vtu(path, np.zeros((3, 2)), {"p": np.array([1.0, 2.0, 3.0])})
    before = path.read_bytes()

    import seawall.io.vtk as vtk_mod

    def boom(*args, **kwargs):
        raise RuntimeError("simulated crash while writing")

    monkeypatch.setattr(vtk_mod, "_encode", boom)
    with pytest.raises(RuntimeError):
        write_vtu(path, np.zeros((4, 2)), {"p": np.zeros(4)})
    assert path.read_bytes() == before
    assert _no_temp_files(tmp_path)


# ---------------------------------------------------------------- PVD


def test_pvd_lists_every_file_after_each_write(tmp_path):
    out = tmp_path / "out"
    series = PVDSeries(out, "fluid")
    pvd = out / "fluid.pvd"
    assert pvd.exists() and _pvd_entries(pvd) == []
    times = [0.0, 0.1, 0.30000000000000004, 1.0 / 3.0]
    for k, t in enumerate(times):
        x = np.full((k + 1, 2), float(k))
        path = series.write(t, x, {"p": np.arange(k + 1, dtype=float)})
        assert os.path.basename(path) == f"fluid_{k:05d}.vtu"
        entries = _pvd_entries(pvd)
        assert entries == [(tt, f"fluid_{i:05d}.vtu") for i, tt in enumerate(times[:k + 1])]
        assert series.files == entries
        for _, f in entries:
            # Filenames are relative to the .pvd's directory.
            assert (out / f).exists()
        pos, data = read_vtu(out / entries[-1][1])
        np.testing.assert_array_equal(pos[:, 0], float(k))
        np.testing.assert_array_equal(data["p"], np.arange(k + 1))
    assert _no_temp_files(out)


def test_pvd_resume_continues_numbering(tmp_path):
    series = PVDSeries(tmp_path, "fluid")
    for k in range(5):
        series.write(0.1 * k, np.zeros((2, 2)))

    again = PVDSeries(tmp_path, "fluid", resume=True)
    assert [f for _, f in again.files] == [f"fluid_{k:05d}.vtu" for k in range(5)]
    again.write(0.5, np.zeros((2, 2)))
    assert again.files[-1] == (0.5, "fluid_00005.vtu")
    assert _pvd_entries(tmp_path / "fluid.pvd") == again.files

    # Restart from a checkpoint at t = 0.2: later entries go, numbering follows the kept ones.
    restarted = PVDSeries(tmp_path, "fluid", resume=True, resume_after=0.2)
    assert restarted.files == [(0.0, "fluid_00000.vtu"), (0.1, "fluid_00001.vtu"),
                               (0.2, "fluid_00002.vtu")]
    assert _pvd_entries(tmp_path / "fluid.pvd") == restarted.files
    path = restarted.write(0.25, np.ones((3, 2)))
    assert os.path.basename(path) == "fluid_00003.vtu"
    assert _pvd_entries(tmp_path / "fluid.pvd")[-1] == (0.25, "fluid_00003.vtu")
    pos, _ = read_vtu(path)
    assert pos.shape == (3, 3)


def test_pvd_resume_without_existing_file_and_fresh_start(tmp_path):
    series = PVDSeries(tmp_path / "new", "wall_left", resume=True, resume_after=1.0)
    assert series.files == []
    series.write(0.0, np.zeros((1, 2)))
    # A new series without resume starts again from an empty collection.
    fresh = PVDSeries(tmp_path / "new", "wall_left")
    assert fresh.files == [] and _pvd_entries(tmp_path / "new" / "wall_left.pvd") == []
    assert os.path.basename(fresh.write(0.0, np.zeros((1, 2)))) == "wall_left_00000.vtu"


# ---------------------------------------------------------------- checkpoints


def _sample_arrays():
    rng = _rng()
    return {
        "fluid": {
            "x": rng.standard_normal((50, 2)),
            "v": rng.standard_normal((50, 2)).astype(np.float32),
            "id": np.arange(50, dtype=np.int64),
            "flag": rng.random(50) > 0.3,
            "big_endian": np.arange(6, dtype=">f8") / 3.0,
            "scalar": np.array(2.5),
            "empty": np.zeros((0, 3)),
            "special": np.array([np.nan, np.inf, -np.inf, -0.0, 5e-324]),
        },
        "wall": {
            "x": rng.random((20_000, 2)),  # large enough to be compressed
            "inner": {"normal": rng.standard_normal((4, 2)), "u8": np.arange(4, dtype=np.uint8)},
        },
        "empty_group": {},
    }


def _assert_same_tree(a, b):
    assert list(a) == list(b)
    for key in a:
        if isinstance(a[key], dict):
            assert isinstance(b[key], dict)
            _assert_same_tree(a[key], b[key])
        else:
            assert isinstance(b[key], np.ndarray)
            assert b[key].dtype == a[key].dtype, key
            assert b[key].shape == a[key].shape, key
            assert b[key].tobytes() == a[key].tobytes(), key


def test_checkpoint_round_trip_bit_for_bit(tmp_path):
    arrays = _sample_arrays()
    attrs = {
        "time": 0.1 + 0.2,
        "step": 12345,
        "name": "dam break",
        "unicode": "Δt → 0",
        "looks_like_json": "json:not really",
        "restart": True,
        "done": False,
        "last_error": None,
        "box": [0.0, 1.0, 0.1, 1e-300],
        "params": {"c0": 20.0, "kernel": "wendland", "walls": ["left", "bottom"],
                   "nested": {"a": None}},
        "np_float": np.float64(1.5),
        "np_vec": np.array([1, 2, 3], dtype=np.int32),
    }
    path = tmp_path / "ck.h5"
    assert os.fspath(save_checkpoint(path, arrays, attrs)) == os.fspath(path)
    assert not os.path.exists(os.fspath(path) + ".tmp")
    back, back_attrs = load_checkpoint(path)
    _assert_same_tree(arrays, back)

    assert set(back_attrs) == set(attrs)
    for key in ("time", "step", "name", "unicode", "looks_like_json", "restart", "done",
                "box", "params", "np_float"):
        assert back_attrs[key] == attrs[key], key
        assert type(back_attrs[key]) is type(attrs[key]) or key == "np_float"
    assert back_attrs["time"] == 0.30000000000000004
    assert back_attrs["last_error"] is None
    assert back_attrs["restart"] is True and back_attrs["done"] is False
    np.testing.assert_array_equal(back_attrs["np_vec"], [1, 2, 3])

    with h5py.File(path, "r") as f:
        assert f.attrs["format"] == "seawall-checkpoint"
        assert int(f.attrs["format_version"]) == 1
        assert f["wall/x"].compression in (None, "gzip")
        assert isinstance(f.attrs["last_error"], str) and f.attrs["last_error"].startswith("json:")


def test_checkpoint_replaces_previous_and_survives_failed_write(tmp_path):
    path = tmp_path / "ck.h5"
    save_checkpoint(path, {"fluid": {"x": np.zeros(3)}}, {"time": 1.0})
    save_checkpoint(path, {"fluid": {"x": np.ones(4)}}, {"time": 2.0})
    arrays, attrs = load_checkpoint(path)
    assert attrs == {"time": 2.0}
    np.testing.assert_array_equal(arrays["fluid"]["x"], np.ones(4))

    with pytest.raises(TypeError):
        save_checkpoint(path, {"fluid": {"x": np.zeros(2), "bad": np.array([object()])}},
                        {"time": 3.0})
    arrays, attrs = load_checkpoint(path)
    assert attrs == {"time": 2.0}
    assert not os.path.exists(os.fspath(path) + ".tmp")


def test_checkpoint_missing_file(tmp_path):
    path = tmp_path / "nope.h5"
    with pytest.raises(FileNotFoundError, match="nope.h5"):
        load_checkpoint(path)


def test_checkpoint_wrong_files(tmp_path):
    text = tmp_path / "notes.txt"
    text.write_text("hello")
    with pytest.raises(ValueError, match="notes.txt"):
        load_checkpoint(text)

    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = np.zeros(3)
    with pytest.raises(ValueError, match="other.h5.*not a seawall checkpoint"):
        load_checkpoint(other)

    newer = tmp_path / "newer.h5"
    with h5py.File(newer, "w") as f:
        f.attrs["format"] = "seawall-checkpoint"
        f.attrs["format_version"] = 99
    with pytest.raises(ValueError, match="newer.h5.*99"):
        load_checkpoint(newer)


def test_checkpoint_rejects_reserved_attr(tmp_path):
    with pytest.raises(ValueError, match="reserved"):
        save_checkpoint(tmp_path / "ck.h5", {}, {"format": "mine"})
    assert not (tmp_path / "ck.h5").exists()


# ---------------------------------------------------------------- CSV


def test_csv_round_trip_exact(tmp_path):
    rng = _rng()
    n = 25
    times = np.cumsum(rng.random(n))
    p = rng.standard_normal(n) * 1e5
    p[[3, 7]] = np.nan
    p[8] = np.inf
    p[9] = -0.0
    front = rng.standard_normal((n, 2))
    force = rng.standard_normal((n, 1))
    columns = {"p_gauge": p, "front": front, "energy": rng.random(n) / 3.0, "force": force}
    path = write_probes_csv(tmp_path / "probes.csv", times, columns)
    assert os.fspath(path) == os.fspath(tmp_path / "probes.csv")
    header = (tmp_path / "probes.csv").read_text().splitlines()[0]
    assert header == "t,p_gauge,front_0,front_1,energy,force_0"
    assert "nan" in (tmp_path / "probes.csv").read_text()

    t_back, back = read_probes_csv(tmp_path / "probes.csv")
    assert t_back.tobytes() == times.tobytes()
    assert list(back) == ["p_gauge", "front", "energy", "force_0"]
    assert back["p_gauge"].tobytes() == p.tobytes()  # NaN, inf and -0.0 bit-exact
    assert back["front"].shape == (n, 2)
    assert back["front"].tobytes() == front.tobytes()
    assert back["energy"].tobytes() == columns["energy"].tobytes()
    np.testing.assert_array_equal(back["force_0"], force[:, 0])

    _, flat = read_probes_csv(tmp_path / "probes.csv", merge_vectors=False)
    assert list(flat) == ["p_gauge", "front_0", "front_1", "energy", "force_0"]


def test_csv_empty_and_errors(tmp_path):
    write_probes_csv(tmp_path / "e.csv", np.zeros(0), {"a": np.zeros(0)})
    t, data = read_probes_csv(tmp_path / "e.csv")
    assert t.shape == (0,) and data["a"].shape == (0,)
    with pytest.raises(ValueError, match="'b'"):
        write_probes_csv(tmp_path / "x.csv", np.zeros(3), {"b": np.zeros(4)})
    with pytest.raises(ValueError, match="comma"):
        write_probes_csv(tmp_path / "x.csv", np.zeros(1), {"a,b": np.zeros(1)})
    with pytest.raises(FileNotFoundError, match="missing.csv"):
        read_probes_csv(tmp_path / "missing.csv")
    assert not (tmp_path / "x.csv").exists()


def test_probe_writer_rows_survive_without_close(tmp_path):
    path = tmp_path / "run.csv"
    w = ProbeCSVWriter(path, ["p1", "p2"])
    assert path.read_text() == "t,p1,p2\n"
    w.append(0.0, [1.0, np.nan])
    w.append(0.1, {"p2": 4.0, "p1": 3.0})
    w.append(0.2, np.array([1.0 / 3.0, -2.0]))
    # No close(): another reader must already see every row.
    t, data = read_probes_csv(path)
    np.testing.assert_array_equal(t, [0.0, 0.1, 0.2])
    assert np.isnan(data["p2"][0])
    assert data["p1"][2] == 1.0 / 3.0
    assert data["p2"][1] == 4.0
    with pytest.raises(ValueError, match="3 values"):
        w.append(0.3, [1.0, 2.0, 3.0])
    w.close()
    w.close()
    with pytest.raises(ValueError, match="closed"):
        w.append(0.4, [0.0, 0.0])


def test_probe_writer_resume_drops_later_rows(tmp_path):
    path = tmp_path / "run.csv"
    with ProbeCSVWriter(path, ["h"]) as w:
        for k in range(6):
            w.append(0.1 * k, [float(k)])
    original_lines = path.read_text().splitlines()
    # Simulate a crash that cut the last row in half.
    with open(path, "a") as fh:
        fh.write("0.6000000000000")

    with ProbeCSVWriter(path, ["h"], resume=True, resume_after=0.30000000000000004) as w:
        # Kept rows are the original text, untouched.
        assert path.read_text().splitlines() == original_lines[:5]
        w.append(0.35, [99.0])
    t, data = read_probes_csv(path)
    np.testing.assert_array_equal(t, [0.0, 0.1, 0.2, 0.30000000000000004, 0.35])
    np.testing.assert_array_equal(data["h"], [0, 1, 2, 3, 99])

    # Resume without a cut-off time keeps everything; other columns are refused.
    with ProbeCSVWriter(path, ["h"], resume=True) as w:
        w.append(0.4, [100.0])
    assert len(read_probes_csv(path)[0]) == 6
    with pytest.raises(ValueError, match="columns"):
        ProbeCSVWriter(path, ["h", "u"], resume=True)
    # resume=True on a missing file starts a new one.
    with ProbeCSVWriter(tmp_path / "new.csv", ["h"], resume=True, resume_after=1.0) as w:
        w.append(0.0, [1.0])
    assert (tmp_path / "new.csv").read_text() == "t,h\n0,1\n"
