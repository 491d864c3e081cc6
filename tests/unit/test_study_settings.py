"""A seawall study from case files and the CLI: the damage budget as a setting, the exports of seawall.cases."""

import json

import numpy as np
import pytest

from seawall.cases import build, case_by_name
from seawall.cli import main
from seawall.errors import InstabilityError, ParameterError
from seawall.sweep import check_settings

TOML = """[case]
t_end = 0.004
{case_extra}
[parameters]
dx = {{default = 0.05, unit = "m"}}
[tank]
lo = [0, 0]
hi = [1, 0.5]
[[water]]
lo = [0, 0]
hi = [0.5, 0.2]
"""


def toml_file(tmp_path, case_extra="", tail="", name="study.toml"):
    path = tmp_path / name
    path.write_text(TOML.format(case_extra=case_extra) + tail)
    return str(path)


def run_cli(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


def test_wall_layers_and_tank_wall_are_exported_by_seawall_cases():
    import seawall.cases as cases
    from seawall.cases import tank_wall, wall_layers
    from seawall.cases.base import tank_wall as base_tank_wall, wall_layers as base_wall_layers
    from seawall.kernels import CubicSpline

    assert wall_layers is base_wall_layers and tank_wall is base_tank_wall
    assert {"wall_layers", "tank_wall"} <= set(cases.__all__)
    assert wall_layers(CubicSpline(), 1.3 * 0.01, 0.01) == 3     # support 2.6 dx


# ----------------------------------------------------------------------------- the damage budget

def test_set_damage_budget_reaches_the_simulation_and_summary():
    sim = build("hydrostatic", dx=0.05, unstable_fraction="0.25", unstable_window="0.1")
    assert sim.unstable_fraction == 0.25 and sim.unstable_window == 0.1
    assert "unstable_fraction" not in sim.metadata["parameters"]      # not a case parameter: no restart check
    summary = sim.summary(wall_time=0.0, loop_time=0.0, particle_steps=0, steps=0, startup=0.0)
    assert summary["damage_budget"] == {"unstable_fraction": 0.25, "unstable_window": 0.1}
    default = build("hydrostatic", dx=0.05)
    assert (default.unstable_fraction, default.unstable_window) == (1e-3, 0.05)


@pytest.mark.parametrize("item,key", [
    ("unstable_fraction=2", "unstable_fraction"), ("unstable_fraction=0", "unstable_fraction"),
    ("unstable_fraction=lots", "unstable_fraction"), ("unstable_window=0", "unstable_window"),
    ("unstable_window=-1", "unstable_window"), ("unstable_window=inf", "unstable_window"),
])
def test_bad_damage_budget_on_the_command_line_is_one_line_naming_the_key(tmp_path, capsys, item, key):
    out = tmp_path / "run"
    code, _, err = run_cli(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.002", "--no-progress",
                            "--out", str(out), "--set", item], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], lines
    assert not out.exists()
    with pytest.raises(ParameterError, match=key):      # a sweep refuses it before any run
        check_settings(case_by_name("hydrostatic"), "adami", dict([item.split("=")]))


def test_damage_budget_on_a_case_without_fluid_is_refused():
    with pytest.raises(ParameterError, match="unstable_window"):
        build("dem-box", unstable_window=0.1)


def test_a_larger_budget_keeps_a_run_going_that_the_default_stops():
    def damaged(**budget):
        # 25 x 10 particles; six of them corrupted within 0.01 s
        sim = build("hydrostatic", dx=0.02, length=0.5, depth=0.2, height=0.3, **budget)
        sim.run(0.005, progress=False)
        sim.fluid.particles["rho"][3:9] = 5000.0
        return sim

    with pytest.raises(InstabilityError, match="unstable_fraction = 0.001"):
        damaged().run(0.01, progress=False)
    sim = damaged(unstable_fraction="0.5")
    sim.run(0.01, progress=False)
    assert len(sim.escaped) == 6 and {rec[-1] for rec in sim.escaped} == {"unstable"}
    # 6 of 250 is 2.4 %: a budget of 2 % stops it, the window given as a string too
    with pytest.raises(InstabilityError, match="within 0.02 s"):
        damaged(unstable_fraction="0.02", unstable_window="0.02").run(0.01, progress=False)


@pytest.mark.parametrize("extra,key", [
    ("unstable_fraction = 1.5", "unstable_fraction"), ("unstable_fraction = true", "unstable_fraction"),
    ("unstable_fraction = \"half\"", "unstable_fraction"), ("unstable_window = 0", "unstable_window"),
    ("unstable_window = -0.1", "unstable_window"),
])
def test_bad_damage_budget_in_a_case_file_is_one_line_naming_the_key(tmp_path, capsys, extra, key):
    path = toml_file(tmp_path, extra)
    code, _, err = run_cli(["run", path, "--no-progress", "--out", str(tmp_path / "out")], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and path in lines[0] and f"[case] {key}" in lines[0], lines


def test_case_file_budget_is_the_default_and_set_overrides_it(tmp_path):
    case = case_by_name(toml_file(tmp_path, "unstable_fraction = 0.02\nunstable_window = 0.2"))
    assert case.guards == {"unstable_fraction": 0.02, "unstable_window": 0.2}
    sim = case.build()
    assert (sim.unstable_fraction, sim.unstable_window) == (0.02, 0.2)
    sim = case.build(unstable_fraction="0.3")
    assert (sim.unstable_fraction, sim.unstable_window) == (0.3, 0.2)


def test_run_records_the_budget_and_a_restart_may_change_it(tmp_path, capsys):
    out = tmp_path / "run"
    base = ["run", "hydrostatic", "--dx", "0.05", "--no-progress", "--no-vtk", "--out", str(out),
            "--checkpoint-every", "0.002"]
    code, stdout, err = run_cli(base + ["--t-end", "0.004", "--set", "unstable_fraction=0.2"], capsys)
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["damage_budget"] == {"unstable_fraction": 0.2, "unstable_window": 0.05}
    # like the end time, the budget decides when a run stops, not how its particles move: a restart takes a new one
    code, _, err = run_cli(base + ["--t-end", "0.006", "--restart", str(out / "checkpoint.h5"),
                                   "--set", "unstable_fraction=0.4", "--set", "unstable_window=0.01"], capsys)
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["damage_budget"] == {"unstable_fraction": 0.4, "unstable_window": 0.01}
    assert np.isclose(summary["t_end"], 0.006)


def test_cases_name_shows_the_damage_budget(tmp_path, capsys):
    code, out, _ = run_cli(["cases", toml_file(tmp_path, "unstable_fraction = 0.02")], capsys)
    assert code == 0
    assert "--set unstable_fraction=0.02  --set unstable_window=0.05" in out
