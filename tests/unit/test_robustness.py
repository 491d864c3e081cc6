"""Runs and files that never lie: bad input, reused directories, restarts, full disks, signals.

Every run here is the tiny hydrostatic tank (40 fluid particles), so each test takes seconds.
"""

import errno
import json
import os
import resource
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import seawall as sw
from seawall.cli import EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_IO_ERROR, EXIT_TERMINATED, main
from seawall.errors import OutputError, ParameterError
from seawall.io import load_checkpoint, read_probes_csv, save_checkpoint
from seawall.schedule import first_due_after, next_due

TANK = ["--dx", "0.05", "--no-progress", "--no-vtk", "--set", "length=0.5", "--set", "depth=0.2",
        "--set", "height=0.3"]
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run(capsys, *args):
    code = main(["run", "hydrostatic", *TANK, *args])
    out, err = capsys.readouterr()
    return code, out, err


def one_line(err):
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def summary_of(directory):
    return json.loads((directory / "summary.json").read_text())


def no_temp_files(directory):
    return [n for n in os.listdir(directory) if n.endswith(".tmp")] == []


def subprocess_env():
    env = dict(os.environ)
    env["PYTHONPATH"] = ROOT + os.pathsep + env.get("PYTHONPATH", "")
    return env


# ------------------------------------------------------------------ 1. one run per directory

def test_existing_run_directory_is_refused_unless_overwrite(tmp_path, capsys):
    out = tmp_path / "run"
    assert run(capsys, "--t-end", "0.01", "--out", str(out), "--line", "0.25,0.05:0.25,0.15:3")[0] == 0
    (out / "notes.txt").write_text("mine")
    before = summary_of(out)

    code, _, err = run(capsys, "--t-end", "0.005", "--out", str(out))
    assert code == EXIT_BAD_INPUT
    assert "--overwrite" in one_line(err) and str(out) in err
    assert summary_of(out) == before            # nothing of the first run was touched

    code, _, _ = run(capsys, "--t-end", "0.005", "--out", str(out), "--overwrite")
    assert code == 0
    assert summary_of(out)["t_end"] == pytest.approx(0.005)
    assert not (out / "line_1.csv").exists()    # the old run's line file is gone ...
    assert (out / "notes.txt").read_text() == "mine"   # ... the user's own file is not


def test_overwrite_refuses_to_delete_the_checkpoint_it_restarts_from(tmp_path, capsys):
    out = tmp_path / "run"
    assert run(capsys, "--t-end", "0.01", "--out", str(out), "--checkpoint-every", "0.005")[0] == 0
    code, _, err = run(capsys, "--t-end", "0.02", "--out", str(out), "--restart", str(out / "checkpoint.h5"),
                       "--overwrite")
    assert code == EXIT_BAD_INPUT and "--overwrite" in one_line(err)


# ------------------------------------------------------------------ 2. restart continues the same run only

@pytest.mark.parametrize("change,word", [
    (["--boundary", "summation"], "boundary"),
    (["--set", "c0=50"], "c0"),
    (["--set", "alpha=0.05"], "alpha"),
])
def test_restart_refuses_another_setup(tmp_path, capsys, change, word):
    out = tmp_path / "run"
    assert run(capsys, "--t-end", "0.01", "--out", str(out), "--checkpoint-every", "0.005")[0] == 0
    before = (out / "summary.json").read_text()
    code, _, err = run(capsys, "--t-end", "0.02", "--out", str(out), "--restart", str(out / "checkpoint.h5"),
                       *change)
    line = one_line(err)
    assert code == EXIT_BAD_INPUT and "--restart" in line and word in line and "does not match" in line
    assert (out / "summary.json").read_text() == before


def test_restart_continues_and_line_files_have_no_duplicate_rows(tmp_path, capsys):
    out = tmp_path / "run"
    line = ["--line", "0.25,0.05:0.25,0.15:3", "--output-every", "0.004"]
    assert run(capsys, "--t-end", "0.02", "--out", str(out), "--checkpoint-every", "0.007", *line)[0] == 0
    t_ck = load_checkpoint(out / "checkpoint.h5")[1]["time"]
    assert t_ck < 0.02
    # the first run wrote rows after the checkpoint's time; the restart writes them again
    code, _, _ = run(capsys, "--t-end", "0.03", "--out", str(out), "--restart", str(out / "checkpoint.h5"), *line)
    assert code == 0
    rows = [r.split(",") for r in (out / "line_1.csv").read_text().splitlines()[1:]]
    keys = [(r[0], r[1]) for r in rows]
    assert len(keys) == len(set(keys))
    times = [float(r[0]) for r in rows]
    assert times == sorted(times) and times[-1] == pytest.approx(0.03)
    t, _ = read_probes_csv(str(out / "probes.csv"))
    assert np.all(np.diff(t) > 0)
    summary = summary_of(out)
    assert summary["restarted_from"]["time"] == pytest.approx(t_ck)


# ------------------------------------------------------------------ 3. a full disk

def _full_disk_on_checkpoint(monkeypatch, fail_from):
    """Writes of an HDF5 image fail with ENOSPC (after writing part of it) from the fail_from-th on."""
    real_fdopen = os.fdopen
    seen = {"n": 0}

    class FullDisk:
        def __init__(self, fh):
            self._fh = fh

        def write(self, data):
            if not isinstance(data, str) and bytes(memoryview(data)[:4]) == b"\x89HDF":
                seen["n"] += 1
                if seen["n"] >= fail_from:
                    self._fh.write(memoryview(data)[:100])
                    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            return self._fh.write(data)

        def __getattr__(self, name):
            return getattr(self._fh, name)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return self._fh.__exit__(*exc)

    monkeypatch.setattr(os, "fdopen", lambda fd, *a, **k: FullDisk(real_fdopen(fd, *a, **k)))


def test_full_disk_during_checkpoint_keeps_the_last_one(tmp_path, capsys, monkeypatch):
    out = tmp_path / "run"
    _full_disk_on_checkpoint(monkeypatch, fail_from=2)
    code, _, err = run(capsys, "--t-end", "0.02", "--out", str(out), "--checkpoint-every", "0.005")
    line = one_line(err)
    assert code == EXIT_IO_ERROR
    assert "checkpoint.h5" in line and "No space left" in line and "MB free" in line
    assert no_temp_files(out)
    summary = summary_of(out)
    assert summary["status"] == "io-error" and "checkpoint.h5" in summary["error"]
    _, attrs = load_checkpoint(out / "checkpoint.h5")     # the first checkpoint, intact
    assert 0.005 <= attrs["time"] < 0.01
    assert summary["probes"]["P0"]["max"] is not None


def test_file_size_limit_is_an_io_error_not_a_crash(tmp_path):
    # a real failing write(2): RLIMIT_FSIZE makes writes past 16 kB fail (EFBIG); the checkpoint is larger.
    # HDF5 writing to such a file itself used to crash the process (segmentation fault, exit 139).
    out = tmp_path / "run"

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (16_000, 16_000))

    proc = subprocess.run([sys.executable, "-m", "seawall", "run", "hydrostatic", *TANK, "--t-end", "0.01",
                           "--out", str(out), "--checkpoint-every", "0.005"], capture_output=True, text=True,
                          timeout=300, preexec_fn=limit, env=subprocess_env())
    assert proc.returncode == EXIT_IO_ERROR, proc.stderr
    assert "checkpoint.h5" in one_line(proc.stderr)
    assert not (out / "checkpoint.h5").exists() and no_temp_files(out)
    assert summary_of(out)["status"] == "io-error"


# ------------------------------------------------------------------ 4. signals

def _wait_for_rows(path, rows, proc, limit=240):
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise AssertionError(f"run ended early: {proc.returncode} {proc.stderr.read()}")
        if path.exists() and len(path.read_text().splitlines()) > rows:
            return
        time.sleep(0.2)
    raise AssertionError("the run did not start sampling in time")


def _terminate_once_sampling(cmd, out):
    """Start ``seawall run`` ``cmd``, send SIGTERM once probes.csv has rows; (exit code, stderr)."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=subprocess_env())
    try:
        _wait_for_rows(out / "probes.csv", 3, proc)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    return proc.returncode, err


def test_sigterm_stops_like_ctrl_c_and_the_run_can_continue(tmp_path):
    out = tmp_path / "run"
    code, err = _terminate_once_sampling([sys.executable, "-m", "seawall", "run", "hydrostatic", *TANK, "--t-end",
                                          "50", "--out", str(out), "--probe-every", "0.001"], out)
    assert code == EXIT_TERMINATED, err
    assert "SIGTERM" in one_line(err) and "Traceback" not in err
    summary = summary_of(out)
    assert summary["status"] == "interrupted" and "SIGTERM" in summary["error"]
    # the summary of a stopped run is as complete as that of a finished one
    assert summary["probes"]["P0"]["min"] is not None and summary["particle_steps_per_s"] > 0
    assert summary["startup_s"] > 0
    assert (out / "escaped.csv").exists() and no_temp_files(out)
    _, attrs = load_checkpoint(out / "checkpoint.h5")   # written at the step the signal ended
    assert attrs["time"] == pytest.approx(summary["t_end"])
    t, _ = read_probes_csv(str(out / "probes.csv"))
    assert t[-1] <= summary["t_end"] + 1e-12

    proc = subprocess.run([sys.executable, "-m", "seawall", "run", "hydrostatic", *TANK,
                           "--t-end", str(attrs["time"] + 0.005), "--out", str(out),
                           "--restart", str(out / "checkpoint.h5")],
                          capture_output=True, text=True, timeout=300, env=subprocess_env())
    assert proc.returncode == 0, proc.stderr
    assert summary_of(out)["status"] == "completed"


def test_interrupt_during_start_up_is_one_line_and_writes_nothing(tmp_path, capsys, monkeypatch):
    import seawall.cli as cli

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "_build", interrupted)
    code, _, err = run(capsys, "--out", str(tmp_path / "run"))
    assert code == EXIT_INTERRUPTED and "interrupted" in one_line(err)
    assert not (tmp_path / "run").exists()


# ------------------------------------------------------------------ 5. tiny intervals

@pytest.mark.parametrize("flag", ["--probe-every", "--output-every", "--checkpoint-every"])
def test_interval_below_the_time_step_is_refused(tmp_path, capsys, flag):
    code, _, err = run(capsys, "--out", str(tmp_path / "run"), flag, "1e-300")
    assert code == EXIT_BAD_INPUT and flag in one_line(err) and "time step" in err
    assert not (tmp_path / "run").exists()


def test_catch_up_always_moves_forward():
    assert next_due(0.0, 0.1, 0.05) == 0.1
    assert next_due(0.1, 0.1, 0.35) == pytest.approx(0.4)
    for every in (1e-300, 1e-11, 1e-20):
        nxt = next_due(0.0, every, 0.01)
        assert nxt > 0.01
    assert first_due_after(0.01, 1e-300) > 0.01
    assert first_due_after(0.25, 0.1) == pytest.approx(0.3)


def test_api_run_with_a_tiny_interval_finishes(tmp_path):
    sim = sw.cases.build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3)
    sim.add(sw.output.Checkpoint(str(tmp_path), every=1e-300), every=1e-300)
    res = sim.run(1.0, progress=False, max_steps=3)   # the catch-up loop used to never return here
    assert sim.step == 3 and len(res.times) == 4     # a sample at t = 0 and after every step


# ------------------------------------------------------------------ 6, 7, 10. bad input is one line, exit 2

def _files(tmp_path):
    text = tmp_path / "notes.txt"
    text.write_text("not a checkpoint\n")
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = np.zeros(3)
    return {"FILE": str(text), "OTHER": str(other), "DIR": str(tmp_path)}


@pytest.mark.parametrize("args,word", [
    (["--out", "FILE"], "--out"),
    (["--out", "FILE/sub"], "--out"),
    (["--out", ""], "--out"),
    (["--restart", "DIR/missing.h5"], "not found"),
    (["--restart", "FILE"], "not an HDF5"),
    (["--restart", "OTHER"], "not a seawall checkpoint"),
    (["--restart", "DIR"], "directory"),
    (["--boundary", "ghost-shepard", "--set", "shepard_mu=abc"], "shepard_mu"),
    (["--boundary", "monaghan-kajtar", "--set", "K=abc"], "K"),
    (["--boundary", "monaghan-kajtar", "--set", "beta=abc"], "beta"),
    (["--set", "wall_nu=abc"], "wall_nu"),
    (["--dx", "1e-6"], "GiB"),
    (["--line", "0.1,0.1:0.2,0.2:100000000000000"], "GiB"),
    (["--line", "nan,0.1:0.2,0.2:5"], "finite"),
    (["--set", "c0=0"], "c0"),
    (["--set", "alpha=-0.1"], "alpha"),
    (["--set", "delta=-0.1"], "delta"),
    (["--boundary", "../../x"], "unknown boundary"),
])
def test_bad_run_input_is_one_line(tmp_path, capsys, args, word):
    files = _files(tmp_path)
    args = [next((a.replace(k, v) for k, v in files.items() if a.startswith(k)), a) for a in args]
    if "--out" not in args:
        args += ["--out", str(tmp_path / "run")]
    code, _, err = run(capsys, "--t-end", "0.01", *args)
    assert code == EXIT_BAD_INPUT
    assert word in one_line(err)
    assert not (tmp_path / "run").exists()   # refused before the run directory was made


@pytest.mark.parametrize("args,word", [
    (["drop-impact", "--set", "layers=0"], "layers"),
    (["drop-impact", "--set", "rho_min=3"], "rho_min"),
    (["dem-box", "--set", "seed=-1"], "seed"),
    (["poiseuille", "--boundary", "adami"], "no-slip"),   # free slip named explicitly
    (["couette", "--boundary", "ghost-mls1"], "no-slip"),
    (["taylor-green", "--boundary", "../../x"], "unknown boundary"),
    (["s-cavity", "--set", "nu=-1"], "nu"),
])
def test_impossible_case_parameters_are_refused(tmp_path, capsys, args, word):
    code = main(["run", *args, "--out", str(tmp_path / "run"), "--no-progress"])
    _, err = capsys.readouterr()
    assert code == EXIT_BAD_INPUT and word in one_line(err)
    assert not (tmp_path / "run").exists()


def test_read_only_out_is_refused(tmp_path, capsys):
    if os.geteuid() == 0:
        pytest.skip("root writes into read-only directories")
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        code, _, err = run(capsys, "--out", str(ro / "run"))
        assert code == EXIT_BAD_INPUT and "--out" in one_line(err)
    finally:
        ro.chmod(0o755)


def _checkpoint(tmp_path, capsys):
    out = tmp_path / "run"
    assert run(capsys, "--t-end", "0.01", "--out", str(out), "--checkpoint-every", "0.005")[0] == 0
    return out, out / "checkpoint.h5"


def _restart_refused(capsys, out, path, word):
    before = (out / "summary.json").read_text()
    code, _, err = run(capsys, "--t-end", "0.02", "--out", str(out), "--restart", str(path))
    assert code == EXIT_BAD_INPUT and word in one_line(err) and "--restart" in err
    assert (out / "summary.json").read_text() == before


def test_damaged_and_crafted_checkpoints_are_refused(tmp_path, capsys):
    out, path = _checkpoint(tmp_path, capsys)
    arrays, attrs = load_checkpoint(path)
    good = path.read_bytes()

    path.write_bytes(good[: len(good) // 2])
    _restart_refused(capsys, out, path, "truncated")

    for name, change in (("x", lambda a: np.concatenate([a, np.zeros((a.shape[0], 1))], axis=1)),
                         ("x", lambda a: a.astype(np.int32))):
        bad = {g: dict(v) for g, v in arrays.items()}
        bad["fluid"][name] = change(arrays["fluid"][name])
        save_checkpoint(path, bad, attrs)
        _restart_refused(capsys, out, path, "'x'")

    for key, value in (("next_dt", -1e-4), ("time", float("nan")), ("step", -3)):
        save_checkpoint(path, arrays, {**attrs, key: value})
        _restart_refused(capsys, out, path, key)


def test_restart_with_a_probes_csv_of_other_columns_is_refused(tmp_path, capsys):
    out, path = _checkpoint(tmp_path, capsys)
    (out / "probes.csv").write_text("t,other\n0,1\n")
    _restart_refused(capsys, out, path, "columns")


def test_api_refuses_impossible_values():
    block = sw.shapes.rectangle((0, 0), (0.2, 0.1), 0.02)
    with pytest.raises(ParameterError, match="velocity"):
        sw.FluidSystem(block, eos=sw.Tait(c0=10.0), velocity=(float("nan"), 0.0))
    fluid = sw.FluidSystem(block, eos=sw.Tait(c0=10.0))
    with pytest.raises(ParameterError, match="gravity"):
        sw.Simulation([fluid], h=0.026, gravity=(0.0, float("nan")))
    with pytest.raises(ParameterError, match="density_band"):
        sw.Simulation([fluid], h=0.026, density_band=(2.0, 0.5))
    sim = sw.Simulation([fluid], h=0.026)
    with pytest.raises(ParameterError, match="3 coordinates"):
        sim.add(sw.probes.WallPressure("P", (0.1, 0.0, 0.0)))


# ------------------------------------------------------------------ 9. files written whole, or not at all

def test_vanished_output_directory_stops_the_run(tmp_path):
    out = tmp_path / "run"

    class Vandal(sw.probes.Probe):
        def sample(self, sim):
            if sim.time > 0.004 and out.exists():
                for name in os.listdir(out):
                    os.remove(out / name)
                out.rmdir()
            return 0.0

    sim = sw.cases.build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3)
    sim.add(Vandal("vandal"), every=0.001)
    with pytest.raises(OutputError, match="removed during the run"):
        sim.run(0.02, progress=False, probe_csv=str(out / "probes.csv"))
    assert not out.exists()     # not silently recreated


def test_summary_is_replaced_whole_or_not_at_all(tmp_path, monkeypatch):
    from seawall import rundir

    path = tmp_path / "summary.json"
    rundir.write_json(path, {"status": "completed"})

    def broken(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(json, "dump", broken)
    with pytest.raises(OSError):
        rundir.write_json(path, {"status": "other"})
    assert json.loads(path.read_text()) == {"status": "completed"}
    assert no_temp_files(tmp_path)


# ------------------------------------------------------------------ 10. smaller items; provenance

def test_tiny_t_end_still_steps(tmp_path, capsys):
    code, _, _ = run(capsys, "--t-end", "1e-300", "--out", str(tmp_path / "run"))
    summary = summary_of(tmp_path / "run")
    assert code == 0 and summary["status"] == "completed" and summary["steps"] >= 1
    assert summary["t_end"] == 1e-300


@pytest.mark.parametrize("value", ["-5", "nan", "inf"])
def test_plot_time_must_be_a_time(tmp_path, capsys, value):
    with pytest.raises(SystemExit) as info:    # argparse's refusal, one line (cli._OneLineParser)
        main(["plot", str(tmp_path), "--time", value])
    _, err = capsys.readouterr()
    assert info.value.code == EXIT_BAD_INPUT and "--time" in one_line(err)


def test_run_directory_records_what_produced_it(tmp_path, capsys):
    out = tmp_path / "run"
    assert run(capsys, "--t-end", "0.01", "--out", str(out), "--checkpoint-every", "0.005")[0] == 0
    record = summary_of(out)["provenance"]
    assert record["seawall_version"] == sw.__version__
    assert record["command_line"][:2] == ["seawall", "run"] and str(out) in record["command_line"]
    for key in ("git_commit", "threads", "python", "numba", "numpy", "started"):
        assert key in record
    assert record["threads"] >= 1
    _, attrs = load_checkpoint(out / "checkpoint.h5")
    assert attrs["metadata"]["provenance"]["started"] == record["started"]
    proc = subprocess.run([sys.executable, "-m", "seawall", "--version"], capture_output=True, text=True,
                          timeout=120, env=subprocess_env())
    assert proc.returncode == 0 and proc.stdout.startswith(f"seawall {sw.__version__}")
