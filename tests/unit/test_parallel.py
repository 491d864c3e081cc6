"""Decomposed runs (seawall.parallel): the slab arithmetic, and a case on 2 MPI ranks against one process."""

import csv
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from seawall.parallel import slabs
from seawall.parallel.distributed import _columns, _pack, _unpack, refusal
from seawall.particles import ParticleArrays

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# ---------------------------------------------------------------------------- slabs and row packing
def test_quantile_cuts_split_the_counts_evenly():
    rng = np.random.default_rng(3)
    coord = np.concatenate([rng.uniform(0.0, 1.0, 3000), rng.uniform(1.0, 4.0, 1000)])  # dense on the left
    width = 0.01
    counts = slabs.histogram(coord, 0.0, width, 400)
    for size in (2, 3, 4):
        cuts = slabs.quantile_cuts(counts, 0.0, width, size)
        per_rank = np.bincount(slabs.owners(coord, cuts), minlength=size)
        # each cut sits on a bin edge: a rank is off its share by at most one bin's count
        assert np.all(np.abs(per_rank - coord.size / size) <= counts.max())
        assert np.all(np.diff(cuts) > 0)


def test_halo_rows_are_the_particles_near_each_other_slab():
    coord = np.linspace(0.0, 10.0, 101)
    cuts = np.array([-np.inf, 4.0, 7.0, np.inf])
    rows = slabs.halo_rows(coord, cuts, 1, 0.55)      # rank 1 owns [4, 7)
    assert rows[1].size == 0
    assert np.array_equal(coord[rows[0]], coord[coord < 4.55])
    assert np.array_equal(coord[rows[2]], coord[coord >= 6.45])


def test_rows_travel_bit_for_bit():
    pa = ParticleArrays(2)
    rng = np.random.default_rng(0)
    pa.add("x", rng.normal(size=(7, 2)))
    pa.add("rho", rng.normal(size=7))
    pa.add("id", np.array([0, 5, 2**62 + 3, 7, -4, 9, 11], dtype=np.int64))
    pa.add("zone", np.arange(7, dtype=np.int8))
    columns = _columns(pa)
    rows = np.array([6, 2, 0])
    back = _unpack(_pack(pa, rows, columns), columns)
    for name, a in pa.items():
        assert back[name].dtype == a.dtype
        assert np.array_equal(back[name], a[rows])


def test_couplings_and_unverified_models_are_refused_by_name():
    from seawall.cases import case_by_name
    from seawall.coupling import Coupling

    sim = case_by_name("dam-break").build(boundary="adami", H=0.1, dx=0.01)
    assert refusal(sim) is None

    class Anchor(Coupling):
        name = "anchor"

    other = case_by_name("dam-break").build(boundary="adami", H=0.1, dx=0.01)
    other.walls[0].model.name = "my-model"          # a model of one's own, never compared on several ranks
    assert refusal(other).startswith("MPI: wall tank (my-model): this wall model has not been compared")

    # prescribed motion is a function of time, replicated on every rank: decomposed (docs/parallel.md)
    assert refusal(case_by_name("moving-wall").build(boundary="adami", dx=0.05)) is None

    sim.couplings.append(Anchor())
    assert refusal(sim) == ("MPI: coupling anchor (Anchor) acts on the whole fluid and is not decomposed; "
                            "run it in one process")


def test_shifting_and_the_transport_velocity_are_decomposed():
    from seawall.cases import case_by_name

    for setting in ({"shifting": "sun2017"}, {"shifting": "lind2012"}, {"transport_velocity": True}):
        sim = case_by_name("dam-break").build(boundary="adami", H=0.1, dx=0.01)
        sim.set_regularisation(**setting)
        assert refusal(sim) is None, setting
    # the cavity's centre probe interpolates at a point: sampled by the rank whose slab holds it
    cavity = case_by_name("cavity").build(boundary="adami-noslip", dx=1e-4)
    cavity.set_regularisation(transport_velocity=True)
    assert refusal(cavity) is None


def test_the_shift_speed_is_the_largest_of_the_owned_rows_over_ranks():
    from types import SimpleNamespace

    from seawall.parallel.distributed import DistributedSimulation

    # [Sun2017]'s shift scales with max |v|; a halo row (the last, advanced with discarded rates) must not count
    rank = SimpleNamespace(fluid=SimpleNamespace(particles={"v": np.array([[1.0, 0.0], [0.0, -2.0], [30.0, 0.0]])}),
                           _owned_rows=lambda: 2, _allreduce=lambda value, op: (value, op))
    assert DistributedSimulation._largest_speed(rank) == (2.0, "max")


# ---------------------------------------------------------------------------- 2 ranks against 1 process
def _mpiexec():
    """mpiexec on PATH, else the one MPICH's wheel installed beside this Python."""
    beside = os.path.join(os.path.dirname(sys.executable), "mpiexec")
    return shutil.which("mpiexec") or (beside if os.access(beside, os.X_OK) else None)


def _mpi_ready():
    try:
        import mpi4py  # noqa: F401
    except ImportError:
        return "mpi4py is not installed (pip install seawall[mpi])"
    if _mpiexec() is None:
        return "no mpiexec on PATH or beside the Python executable"
    return None


needs_mpi = pytest.mark.skipif(_mpi_ready() is not None, reason=str(_mpi_ready()))

RUN = ["-m", "seawall", "run", "dam-break", "--set", "H=0.1", "--dx", "0.005", "--no-progress"]


def _env():
    return {**os.environ, "NUMBA_NUM_THREADS": "1", "PYTHONPATH": ROOT}


def _seawall(args, ranks=1, **kwargs):
    cmd = [sys.executable, "-m", "seawall", *args]
    if ranks > 1:
        cmd = [_mpiexec(), "-n", str(ranks), *cmd]
    return subprocess.run(cmd, cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=900, **kwargs)


def _probes(out):
    with open(os.path.join(out, "probes.csv")) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def _summary(out):
    with open(os.path.join(out, "summary.json")) as fh:
        return json.load(fh)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The same dam break (800 particles, t = 0.045 s, ~480 steps) in one process and on 2 ranks."""
    if _mpi_ready():
        pytest.skip(_mpi_ready())
    base = tmp_path_factory.mktemp("mpi")
    out = {}
    for ranks in (1, 2):
        out[ranks] = str(base / f"r{ranks}")
        done = _seawall([*RUN[2:], "--t-end", "0.045", "--checkpoint-every", "0.02", "--out", out[ranks]], ranks)
        assert done.returncode == 0, done.stderr[-3000:]
    return out


@needs_mpi
def test_two_ranks_give_the_serial_probes(runs):
    head1, p1 = _probes(runs[1])
    head2, p2 = _probes(runs[2])
    assert head1 == head2 and p1.shape == p2.shape
    s1, s2 = _summary(runs[1]), _summary(runs[2])
    assert s2["steps"] == s1["steps"] > 300
    assert s2["n_fluid"] == s1["n_fluid"] and s2["escaped_particles"] == s1["escaped_particles"]
    assert s2["mpi"]["ranks"] == 2 and 0 < s2["mpi"]["halo_fraction"] < 1
    # sums over neighbours are taken in another order: round-off, grown over the steps (measured
    # 9.5e-16 relative after these 494 steps, 2.7e-11 after 3382 with the impact; docs/parallel.md),
    # far below any change of the physics. 1e-11 is the regression series' tolerance: a cold compile
    # against cached machine code moves a serial run by up to 2.4e-12 (docs/architecture.md)
    scale = np.maximum(np.abs(p1).max(axis=0), 1e-300)
    assert np.max(np.abs(p2 - p1) / scale) < 1e-11
    assert s2["mass_drift"] == pytest.approx(s1["mass_drift"], abs=1e-14)


def _frames(out):
    from seawall.plots import _series

    return _series(out)


@needs_mpi
def test_two_ranks_write_pvtu_frames_that_read_as_the_serial_frames(runs, tmp_path):
    """Each rank writes its piece; the .pvtu frames, read by seawall's readers, are the serial frames."""
    from seawall.io.vtk import pvtu_pieces, read_vtu, read_vtu_metadata
    from seawall.postprocess import sample_series

    serial, split = _frames(runs[1]), _frames(runs[2])
    assert len(split) == len(serial) >= 3
    assert all(path.endswith(".pvtu") for _, path in split) and all(path.endswith(".vtu") for _, path in serial)
    for (t1, p1), (t2, p2) in zip(serial, split):
        assert t2 == pytest.approx(t1, rel=1e-12)
        assert len(pvtu_pieces(p2)[0]) == 2
        x1, d1 = read_vtu(p1)
        x2, d2 = read_vtu(p2)
        o1, o2 = np.argsort(d1["id"]), np.argsort(d2["id"])
        assert np.array_equal(d1["id"][o1], d2["id"][o2])          # the same particles, each once
        assert set(d1) == set(d2)
        for name, a, b in [("x", x1, x2), *((k, d1[k], d2[k]) for k in d1)]:
            scale = max(float(np.abs(a).max()), 1e-300)
            assert np.max(np.abs(a[o1] - b[o2])) / scale < 1e-11, name
        m1, m2 = read_vtu_metadata(p1), read_vtu_metadata(p2)
        assert m2["pieces"] == 2 and m2["h"] == m1["h"] and m2["TimeValue"] == pytest.approx(m1["TimeValue"])
    # what `seawall sample` reads, the same from either run
    points = np.array([[0.05, 0.02], [0.2, 0.01], [0.5, 0.005]])
    tt1, s1 = sample_series(runs[1], points, ("pressure", "u", "v"))
    tt2, s2 = sample_series(runs[2], points, ("pressure", "u", "v"))
    np.testing.assert_allclose(tt2, tt1, rtol=1e-12)
    for q in s1:
        assert np.nanmax(np.abs(s2[q] - s1[q])) <= 1e-11 * np.nanmax(np.abs(s1[q]))
    meshio = pytest.importorskip("meshio")     # does not read .pvtu (5.3); each piece is a plain .vtu
    piece = meshio.read(pvtu_pieces(split[-1][1])[0][1])
    assert set(piece.point_data) == set(d2) and len(piece.points) < len(x2)


@needs_mpi
def test_vtk_reads_the_pvtu_frames(runs):
    """VTK's own parallel reader (ParaView's) takes the frame: every particle once, the declared arrays."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    from seawall.io.vtk import read_vtu

    path = _frames(runs[2])[-1][1]
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    x, data = read_vtu(path)
    assert grid.GetNumberOfPoints() == grid.GetNumberOfCells() == len(x)
    points = grid.GetPointData()
    assert {points.GetArrayName(k) for k in range(points.GetNumberOfArrays())} == set(data)
    assert np.array_equal(np.sort(vtk_to_numpy(points.GetArray("id"))), np.sort(data["id"]))
    assert grid.GetFieldData().GetArray("TimeValue") is not None


@needs_mpi
def test_checkpoint_of_two_ranks_restarts_in_one_process(runs, tmp_path):
    """One checkpoint for the whole run, independent of the rank count: a serial restart continues it."""
    out = str(tmp_path / "restart")
    shutil.copytree(runs[2], out)
    done = _seawall([*RUN[2:], "--t-end", "0.055", "--out", out, "--restart", os.path.join(out, "checkpoint.h5")])
    assert done.returncode == 0, done.stderr[-3000:]
    s = _summary(out)
    assert s["t_end"] == pytest.approx(0.055) and s["n_fluid"] == _summary(runs[1])["n_fluid"]
    _, p = _probes(out)
    _, p1 = _probes(runs[1])
    assert p[-1, 0] == pytest.approx(0.055)
    # the rows before the checkpoint's time are the 2-rank run's own
    kept, serial = p[:p1.shape[0] - 1], p1[:-1]
    assert np.max(np.abs(kept - serial) / np.maximum(np.abs(serial).max(axis=0), 1e-300)) < 1e-11
    # the series goes on: the 2-rank .pvtu frames up to the checkpoint, then the serial .vtu frames
    from seawall.io.vtk import read_vtu
    from seawall.plots import snapshot

    frames = _frames(out)
    kinds = [os.path.splitext(path)[1] for _, path in frames]
    assert kinds[0] == ".pvtu" and kinds[-1] == ".vtu" and kinds == sorted(kinds, key=lambda k: k == ".vtu")
    assert all(read_vtu(path)[0].shape[0] == s["n_fluid"] for _, path in frames)
    snapshot(out, str(tmp_path / "snap.png"), time=0.02)       # `seawall plot` of a .pvtu frame
    assert os.path.getsize(tmp_path / "snap.png") > 0


@needs_mpi
def test_refusals_stop_every_rank_with_one_line(tmp_path):
    done = _seawall([*RUN[2:], "--t-end", "0.01", "--line", "0,0.01:0.5,0.01:10", "--out", str(tmp_path / "a")], 2)
    assert done.returncode != 0
    lines = [line for line in done.stderr.splitlines() if line.startswith("seawall:")]
    assert lines == ["seawall: error: --line: the line sampler is not decomposed; run it in one process"]
    assert not (tmp_path / "a").exists()


@needs_mpi
def test_ranks_that_disagree_on_the_input_stop(tmp_path):
    one = [sys.executable, "-m", "seawall", *RUN[2:], "--t-end", "0.01", "--out", str(tmp_path / "b")]
    other = [*one[:-2], "--set", "c0=20", *one[-2:]]
    done = subprocess.run([_mpiexec(), "-n", "1", *one, ":", "-n", "1", *other], cwd=ROOT, env=_env(),
                          capture_output=True, text=True, timeout=900)
    assert done.returncode != 0
    lines = [line for line in done.stderr.splitlines() if line.startswith("seawall:")]
    assert len(lines) == 1 and "the ranks disagree on the input (ranks [1] differ from rank 0" in lines[0]
    assert not (tmp_path / "b").exists()


@needs_mpi
def test_more_ranks_than_the_fluid_allows_stop_with_the_usable_count(tmp_path):
    # 8 particles in 4 columns fall into 3 cells along x: a third rank would own nothing
    done = _seawall(["run", "dam-break", "--set", "H=0.1", "--dx", "0.05", "--t-end", "0.01", "--no-progress",
                     "--out", str(tmp_path / "c")], 3)
    assert done.returncode != 0
    lines = [line for line in done.stderr.splitlines() if line.startswith("seawall:")]
    assert len(lines) == 1 and "3 ranks are more than the fluid allows" in lines[0]
    assert lines[0].endswith("use at most 2 ranks")
    assert not (tmp_path / "c").exists()
