"""The command line: contract files, JSON line, one-line errors without traceback."""

import json
import subprocess
import sys

import numpy as np
import pytest

from seawall.cli import main
from seawall.io import read_probes_csv


def run_cli(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


def test_cases_lists_every_case(capsys):
    code, out, _ = run_cli(["cases"], capsys)
    assert code == 0
    names = [line.split()[0] for line in out.strip().splitlines()]
    assert {"hydrostatic", "dam-break", "collapse", "dam-break-3d"} <= set(names)


def test_boundaries_lists_every_model_with_its_options(capsys):
    from seawall.boundary.registry import BOUNDARIES

    code, out, _ = run_cli(["boundaries"], capsys)
    assert code == 0
    lines = out.rstrip("\n").splitlines()
    # the existing lines stay: one per model, "name  description", in registry order
    heads = [line for line in lines if not line.startswith(" ")]
    assert [line.split()[0] for line in heads] == list(BOUNDARIES)
    assert all(line.split(None, 1)[1] == BOUNDARIES[line.split()[0]][1] for line in heads)
    # below each, indented: its --set keys with defaults and its class's options with the values it is built with
    blocks = {}
    for line in lines:
        if not line.startswith(" "):
            name = line.split()[0]
            blocks[name] = []
        else:
            blocks[name].append(line.strip())
    assert all(len(b) == 2 and b[0].startswith("--set: ") and b[1].startswith("options: ") for b in blocks.values())
    assert blocks["adami-noslip"][0] == "--set: slip=noslip wall_nu=(model) clip_negative=(model)"
    assert "density='summation'" in blocks["summation"][1] and "clip_negative_pressure=True" in blocks["summation"][1]
    assert blocks["idbc"][1].startswith("options: ImprovedDynamicBoundary(order=7, rectangular=True,")
    assert blocks["ghost-mls2"][1] == ("options: GhostParticles(interpolation=MLS(order=2, limit=True), slip='free', "
                                        "reflect=False)")
    assert blocks["liu2012"] == ["--set: beta=2.0 c=(model)", "options: Liu2012Force(beta=2.0, c=None)"]


def test_run_writes_contract_files(tmp_path, capsys):
    out_dir = tmp_path / "run"
    code, out, _ = run_cli(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.02", "--out", str(out_dir),
                            "--no-progress", "--set", "length=0.5", "--set", "depth=0.2",
                            "--set", "height=0.3"], capsys)
    assert code == 0
    summary = json.loads((out_dir / "summary.json").read_text())
    for key in ("case", "boundary", "dimension", "n_fluid", "n_wall", "steps", "t_end", "wall_time_s",
                "particle_steps_per_s", "escaped_particles", "mass_drift"):
        assert key in summary, key
    assert summary["case"] == "hydrostatic" and summary["boundary"] == "adami"
    assert summary["t_end"] == pytest.approx(0.02)
    t, cols = read_probes_csv(str(out_dir / "probes.csv"))
    header = (out_dir / "probes.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "t" and {"P0", "P1"} <= set(header)
    assert t[0] == 0.0 and t[-1] == pytest.approx(0.02)
    assert np.all(np.isfinite(cols["P0"]))
    assert (out_dir / "fluid.pvd").exists() and (out_dir / "wall_tank.pvd").exists()
    from seawall.io import read_vtu
    wx, wdata = read_vtu(str(out_dir / "wall_tank_00000.vtu"))
    assert {"normal", "mirror_point", "pressure"} <= set(wdata)
    # every mirror point of a particle facing the water lies inside the tank (0 < x < 0.5, y > 0); the
    # open tank's back faces mirror behind it
    mp = wdata["mirror_point"]
    n = wdata["normal"]
    sides = (np.abs(n[:, 0]) > 0.99) & (n[:, 0] * (0.25 - wx[:, 0]) > 0)          # facing into the tank
    floor = (n[:, 1] > 0.99) & (wx[:, 0] > 0) & (wx[:, 0] < 0.5) & (wx[:, 1] < 0)  # under the water
    face = sides | floor
    assert sides.any() and floor.any()
    assert mp[face, 0].min() > 0 and mp[face, 0].max() < 0.5 and mp[face, 1].min() > 0
    assert "M particle-steps/s" in out


def test_wall_force_adds_one_column_per_component(tmp_path, capsys):
    out_dir = tmp_path / "run"
    code, _, _ = run_cli(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.01", "--out", str(out_dir),
                          "--no-progress", "--no-vtk", "--wall-force", "tank", "--set", "length=0.5",
                          "--set", "depth=0.2", "--set", "height=0.3"], capsys)
    assert code == 0
    t, cols = read_probes_csv(str(out_dir / "probes.csv"))
    assert {"wall_force:tank:fx", "wall_force:tank:fy"} <= set(cols) and "wall_force:tank:fz" not in cols
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["probe_units"]["wall_force:tank:fy"] == "N/m"
    # water at rest presses on its tank with its weight (hydrostatic start: within a few per cent), pointing down
    weight = summary["probes"]["mass"]["final"] * 9.81
    assert cols["wall_force:tank:fy"][0] == pytest.approx(-weight, rel=0.03)
    assert abs(cols["wall_force:tank:fx"][0]) < 1e-9 * weight     # a symmetric tank: no net side force


def test_bench_prints_one_json_line(capsys):
    code, out, _ = run_cli(["bench", "hydrostatic", "--dx", "0.05", "--steps", "5"], capsys)
    assert code == 0
    lines = out.strip().splitlines()
    assert len(lines) == 1
    rec = json.loads(lines[0])
    for key in ("n_particles", "steps", "seconds", "particle_steps_per_s", "compile_seconds", "cpu_seconds"):
        assert key in rec
    assert rec["steps"] == 5 and rec["particle_steps_per_s"] > 0


@pytest.mark.parametrize("args,word", [
    (["run", "hydrostatic", "--dx", "0"], "--dx"),
    (["run", "hydrostatic", "--dx", "-0.1"], "--dx"),
    (["run", "hydrostatic", "--t-end", "0"], "--t-end"),
    (["run", "hydrostatic", "--set", "h_factor=0"], "h must be"),
    (["run", "hydrostatic", "--set", "c0=-3"], "c0"),
    (["run", "hydrostatic", "--set", "rho0=0"], "rho0"),
    (["run", "dam-break", "--set", "rho0=-1000"], "rho0"),
    (["run", "hydrostatic", "--set", "dx=-0.01"], "dx"),
    (["run", "hydrostatic", "--set", "depth=0.5"], "depth"),
    (["run", "no-such-case"], "unknown case"),
    (["run", "hydrostatic", "--boundary", "teflon"], "unknown boundary"),
    (["run", "hydrostatic", "--set", "colour=red"], "no parameter 'colour'"),
    (["run", "taylor-green", "--set", "shifting=sideways"], "shifting must be one of"),
    (["run", "taylor-green", "--set", "density=summed"], "density must be one of"),
    (["run", "taylor-green", "--set", "density=summation", "--set", "delta=0.1"], "delta: delta-SPH needs"),
    (["run", "taylor-green", "--set", "kernel=quartic"], "kernel must be one of"),
    (["run", "dam-break", "--set", "transport_velocity=true"], "needs its free-surface correction"),
    (["run", "hydrostatic", "--wall-force", "tnk"], "no wall named 'tnk'; its walls: tank"),
])
def test_bad_input_gives_one_line_without_traceback(args, word, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "seawall", *args, "--out", str(tmp_path / "x")]
                          if args[0] == "run" else [sys.executable, "-m", "seawall", *args],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1, proc.stderr
    assert word in err[0]
    assert "Traceback" not in proc.stderr


def test_rho0_zero_in_api_is_named():
    import seawall as sw
    from seawall.errors import ParameterError
    with pytest.raises(ParameterError, match="rho0"):
        sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.1, 0.1), 0.01), rho0=0, eos=sw.Tait(c0=1.0))


def test_flows_that_need_no_slip_run_with_their_own_default_wall(tmp_path):
    """`seawall run poiseuille` without --boundary picks the case's no-slip default instead of refusing."""
    from seawall.cases import case_by_name

    for name in ("poiseuille", "couette", "channel", "pipe-3d", "cavity"):
        assert case_by_name(name).default_boundary == "adami-noslip"
    out = tmp_path / "p"
    proc = subprocess.run([sys.executable, "-m", "seawall", "run", "poiseuille", "--t-end", "1e-4", "--out", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "summary.json").read_text())["boundary"] == "adami-noslip"


def test_regularisation_options_reach_summary_json(tmp_path, capsys):
    out_dir = tmp_path / "tgv"
    code, _, _ = run_cli(["run", "taylor-green", "--t-end", "0.002", "--out", str(out_dir), "--no-progress",
                          "--set", "n=16", "--set", "shifting=lind2012", "--set", "transport_velocity=true",
                          "--set", "tvf_background=2"], capsys)
    assert code == 0
    params = json.loads((out_dir / "summary.json").read_text())["parameters"]
    assert params["shifting"] == "lind2012" and params["transport_velocity"] is True
    assert params["tvf_background"] == 2.0 and params["tvf_free_surface"] is False
