"""dem-box through the shared run loop (seawall.runner): bench, checkpoint/restart, signals.

Small boxes (6 discs dropped onto the floor, so contacts happen within the first steps).
"""

import json
import subprocess
import sys

import numpy as np
import pytest

import seawall as sw
from seawall.cases import build
from seawall.cli import EXIT_BAD_INPUT, EXIT_TERMINATED, main
from seawall.errors import ParameterError
from seawall.io import load_checkpoint, read_probes_csv, read_vtu
from seawall.io.vtk import PVDSeries

from test_robustness import _terminate_once_sampling, no_temp_files, one_line, subprocess_env, summary_of

SMALL = {"columns": 3, "layers": 2, "drop_height": 0.0}
SMALL_ARGS = [arg for key, value in SMALL.items() for arg in ("--set", f"{key}={value}")]


def small_box():
    return build("dem-box", **SMALL)


def test_bench_prints_its_json_line(capsys):
    assert main(["bench", "dem-box", "--steps", "6", "--chunks", "2", *SMALL_ARGS]) == 0
    line = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert line["case"] == "dem-box" and line["steps"] == 6
    assert line["n_particles"] == line["n_dem"] == 6 and line["n_fluid"] == 0 and line["n_wall"] > 0
    assert line["particle_steps_per_s"] > 0 and line["seconds"] > 0 and line["compile_seconds"] >= 0


def test_checkpoint_restart_reproduces_the_uninterrupted_run(tmp_path):
    # the checkpoint written during an uninterrupted run (at the first step after 0.01 s)
    reference = small_box()
    reference.add(sw.output.Checkpoint(str(tmp_path), every=0.01), every=0.001)
    ref_result = reference.run(0.015, progress=False)
    assert ref_result["max_overlap"].max() > 0        # the discs did touch the floor and each other
    path = tmp_path / "checkpoint.h5"

    second = small_box()
    second.add(every=0.001)
    second.restart(str(path))
    assert 0.01 <= second.time < 0.011 and 0 < second.step < reference.step
    result = second.run(0.015, progress=False)

    assert second.step == reference.step and second.time == reference.time
    for name in ("x", "v", "a", "overlap", "id"):
        assert np.array_equal(second.dem.particles[name], reference.dem.particles[name]), name
    assert np.array_equal(result.times, ref_result.times)     # the probe history is part of the checkpoint
    for name in ref_result.probes:
        assert np.array_equal(result.probes[name], ref_result.probes[name]), name


def test_restart_refuses_another_dem_setup(tmp_path):
    first = small_box()
    first.add(sw.output.Checkpoint(str(tmp_path), every=0.001))
    first.run(0.0015, progress=False)
    other = build("dem-box", **{**SMALL, "restitution": 0.6})
    with pytest.raises(ParameterError, match="restitution"):
        other.restart(str(tmp_path / "checkpoint.h5"))


@pytest.mark.parametrize("flag", [["--line", "0,0:0.1,0.1:3"], ["--diagnostics"]])
def test_fluid_outputs_are_refused_before_the_run_directory_is_made(tmp_path, capsys, flag):
    out = tmp_path / "run"
    code = main(["run", "dem-box", *SMALL_ARGS, "--out", str(out), "--no-progress", *flag])
    assert code == EXIT_BAD_INPUT and flag[0] in one_line(capsys.readouterr().err)
    assert not out.exists()


def _run(out, *args):
    return [sys.executable, "-m", "seawall", "run", "dem-box", *SMALL_ARGS, "--no-progress",
            "--probe-every", "0.0005", "--output-every", "0.002", "--out", str(out), *args]


def _last_snapshot(directory):
    series = PVDSeries(str(directory), "dem", resume=True)
    t, name = series.files[-1]
    x, data = read_vtu(directory / name)
    return t, x, data


def test_sigterm_ends_a_whole_step_and_the_restart_is_bit_for_bit(tmp_path):
    out = tmp_path / "stopped"
    code, err = _terminate_once_sampling(_run(out, "--t-end", "50"), out)
    assert code == EXIT_TERMINATED, err
    assert "SIGTERM" in one_line(err)
    summary = summary_of(out)
    assert summary["status"] == "interrupted" and "SIGTERM" in summary["error"]
    assert summary["probes"]["kinetic_energy"]["min"] is not None and summary["particle_steps_per_s"] > 0
    assert no_temp_files(out)
    # the checkpoint holds the state at the end of the step the signal interrupted
    _, attrs = load_checkpoint(out / "checkpoint.h5")
    assert attrs["step"] == summary["steps"] and attrs["time"] == summary["t_end"]
    assert attrs["time"] == pytest.approx(attrs["step"] * attrs["next_dt"], rel=1e-9)   # whole steps only
    t, _ = read_probes_csv(str(out / "probes.csv"))
    assert t[-1] <= summary["t_end"]

    t_end = repr(attrs["time"] + 0.003)
    restarted = subprocess.run(_run(out, "--t-end", t_end, "--restart", str(out / "checkpoint.h5")),
                               capture_output=True, text=True, timeout=300, env=subprocess_env())
    assert restarted.returncode == 0, restarted.stderr
    straight = tmp_path / "straight"
    uninterrupted = subprocess.run(_run(straight, "--t-end", t_end), capture_output=True, text=True, timeout=300,
                                   env=subprocess_env())
    assert uninterrupted.returncode == 0, uninterrupted.stderr

    assert summary_of(out)["status"] == "completed"
    assert summary_of(out)["steps"] == summary_of(straight)["steps"]
    t_a, p_a = read_probes_csv(str(out / "probes.csv"))
    t_b, p_b = read_probes_csv(str(straight / "probes.csv"))
    assert np.array_equal(t_a, t_b)
    for name in p_b:
        assert np.array_equal(p_a[name], p_b[name]), name
    t_a, x_a, d_a = _last_snapshot(out)
    t_b, x_b, d_b = _last_snapshot(straight)
    assert t_a == t_b and t_a == pytest.approx(summary_of(straight)["t_end"], rel=1e-12)
    assert np.array_equal(x_a, x_b) and np.array_equal(d_a["velocity"], d_b["velocity"])
