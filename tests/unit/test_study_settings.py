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


# ----------------------------------------------------------------------------- free-surface gauges

def test_run_time_gauge_reads_what_seawall_sample_reads_on_the_same_frames(tmp_path, capsys):
    from seawall.postprocess import gauge_series

    path = toml_file(tmp_path, tail="[[probe]]\nkind = \"gauge\"\nname = \"eta_mid\"\npoint = [\"0.5 * 0.5\"]\n")
    out = tmp_path / "run"
    code, _, err = run_cli(["run", path, "--no-progress", "--out", str(out), "--t-end", "0.02",
                            "--output-every", "0.01", "--probe-every", "0.01",
                            "--gauge", "0.1", "--gauge", "0.8:dry", "--gauge", "0.45"], capsys)
    assert code == 0, err
    rows = [line.split(",") for line in (out / "probes.csv").read_text().splitlines()]
    header, values = rows[0], np.array(rows[1:], dtype=float)
    assert header[-4:] == ["eta_mid", "gauge:1", "gauge:dry", "gauge:3"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["probe_units"]["gauge:1"] == "m" and summary["probe_units"]["eta_mid"] == "m"
    times, eta = gauge_series(str(out), [0.25, 0.1, 0.8, 0.45])
    assert len(times) == 3
    for f, t in enumerate(times):
        row = values[np.argmin(np.abs(values[:, 0] - t))]
        assert row[0] == pytest.approx(t, abs=1e-12)      # probes and frames at the same times
        np.testing.assert_allclose(row[-4:], eta[f], rtol=0, atol=1e-9)
    # still water 0.2 m deep over the floor (y = 0); over the dry floor: the bed, depth 0, not NaN
    np.testing.assert_allclose(eta[0, [0, 1, 3]], 0.2, atol=0.01)
    assert eta[0, 2] == 0.0 and values[0, header.index("gauge:dry")] == 0.0
    # seawall sample --gauge writes the same numbers into sensors.csv
    assert main(["sample", str(out), "--gauge", "0.8", "--gauge", "0.1"]) == 0
    sensors = np.loadtxt(out / "sensors.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(sensors[:, 1:], eta[:, [2, 1]], atol=1e-8)


def test_gauge_without_a_wall_under_it_reads_nan_and_in_3d_takes_two_coordinates():
    from seawall.probes import FreeSurfaceGauge

    sim = build("hydrostatic", dx=0.05)
    far = FreeSurfaceGauge("far", 50.0)           # beyond the tank: no fluid, no bed
    mid = FreeSurfaceGauge("mid", [0.5])
    sim.add(far, mid)
    assert np.isnan(far.sample(sim)) and mid.sample(sim) > 0
    with pytest.raises(ParameterError, match="needs 1 horizontal coordinate"):
        sim.add(FreeSurfaceGauge("xy", (0.5, 0.5)))
    with pytest.raises(ParameterError, match="gauge 'bad'"):
        FreeSurfaceGauge("bad", [0.1, 0.2, 0.3])


@pytest.mark.parametrize("gauge,problem", [
    ("abc", "--gauge must be 1 or 2 finite"), ("0.1,0.2", "--gauge: gauge 'gauge:1': needs 1 horizontal"),
    ("0.1:", "--gauge: NAME"), ("0.1:a,b", "--gauge: NAME"), ("nan", "--gauge must be"),
])
def test_bad_gauge_on_the_command_line_is_one_line(tmp_path, capsys, gauge, problem):
    out = tmp_path / "run"
    code, _, err = run_cli(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.002", "--no-progress",
                            "--out", str(out), "--gauge", gauge], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and problem in lines[0], lines
    assert not out.exists()


def test_gauge_names_from_the_command_line():
    from seawall.cli import parse_gauge

    assert parse_gauge("0.25", 1) == ("gauge:1", [0.25])
    assert parse_gauge(" 0.25 , 0.5:toe", 3) == ("gauge:toe", [0.25, 0.5])


# ----------------------------------------------------------------------------- TOML probes

WALL_FORCES = """[[probe]]
kind = "wall_force"
name = "tank_fx"
[[probe]]
kind = "wall_force"
name = "left_fx"
wall = "tank"
part = [[-1, -1], [0.51, 1]]
[[probe]]
kind = "wall_force"
name = "right_fx"
part = [[0.51, -1], [2, 1]]
[[probe]]
kind = "wall_force"
name = "right_side"
part = [["length", 0], [2, 1]]
"""


def test_wall_force_parts_add_up_to_the_wall_and_the_right_side_holds_the_water(tmp_path):
    path = toml_file(tmp_path, tail=WALL_FORCES).replace("study", "study")
    text = open(path).read().replace('[parameters]\n', '[parameters]\nlength = 1.0\n')
    open(path, "w").write(text.replace("dx = {default = 0.05", "dx = {default = 0.025"))
    sim = case_by_name(path).build(boundary="adami")
    assert [p.name for p in sim.probes] == ["tank_fx", "left_fx", "right_fx", "right_side"]
    assert all(p.wall == "tank" for p in sim.probes)                 # the default: the first wall, the tank
    result = sim.run(0.01, progress=False)
    final = {k: v[-1] for k, v in result.probes.items()}
    # the two boxes split the tank's particles: their forces add up to the wall's, to rounding
    assert final["left_fx"] + final["right_fx"] == pytest.approx(final["tank_fx"], abs=1e-9)
    assert final["left_fx"] < 0 < final["right_fx"]
    assert final["right_side"] == 0.0                     # the water (0 - 0.5 m) does not reach x = 1 m


def test_wall_force_probes_name_every_wall_of_a_case():
    import seawall as sw
    from seawall.probes import WallForce

    tank = sw.WallSystem(sw.shapes.tank((0, 0), (0.6, 0.3), 0.02, layers=3), name="tank")
    block = sw.WallSystem(sw.shapes.rectangle((0.3, 0.0), (0.4, 0.08), 0.02), name="block")
    fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.3, 0.1), 0.02), eos=sw.Tait(c0=15.0))
    sim = sw.Simulation([fluid, tank, block], h=0.026, gravity=(0, -9.81))
    sim.add(WallForce("tank_fy", "tank", 1), WallForce("block_fx", "block", 0),
            WallForce("block_part", "block", 0, part=[[0.3, 0.0], [0.33, 0.1]]), every=0.002)
    result = sim.run(0.004, progress=False)
    assert result.probes["tank_fy"][-1] < 0 and result.probes["block_fx"][-1] > 0
    assert 0 < result.probes["block_part"][-1] <= result.probes["block_fx"][-1] + 1e-9
    with pytest.raises(ParameterError, match="axis must be 0 .. 1"):
        sim.add(WallForce("bad_axis", "block", 2))
    with pytest.raises(ParameterError, match="no particle of wall 'block' lies in part"):
        sim.add(WallForce("empty", "block", 0, part=[[2, 2], [3, 3]]))


@pytest.mark.parametrize("probe,problem", [
    ('kind = "gauge"', "(gauge) needs a point"),
    ('kind = "gauge"\npoint = [0.2, 0.1]', "number 1 point of a gauge is its horizontal position"),
    ('kind = "gauge"\npoint = ["2 * width"]', "unknown name 'width'"),
    ('kind = "wall_force"\naxis = 2', "axis must be 0 .. 1, got 2"),
    ('kind = "wall_force"\naxis = 0.5', "axis must be 0 .. 1, got 0.5"),
    ('kind = "wall_force"\nwall = "lid"', "no wall named 'lid'"),
    ('kind = "wall_force"\npart = [0, 1]', "part[0] must be a list of 2 or 3 numbers"),
    ('kind = "wall_force"\npart = [[0, 0], [1, 1, 1]]', "part[1] has 3 coordinates, the tank has 2"),
    ('kind = "wall_force"\npart = [[5, 5], [6, 6]]', "no particle of wall 'tank' lies in part"),
    ('kind = "wall_force"\npart = [[1, 1], [0, 0]]', "part must be a box"),
    ('kind = "front"\npart = [[0, 0], [1, 1]]', "part is a key of wall_force probes"),
])
def test_bad_probe_keys_in_a_case_file_are_one_line(tmp_path, capsys, probe, problem):
    path = toml_file(tmp_path, tail=f"[[probe]]\n{probe}\n")
    code, _, err = run_cli(["run", path, "--no-progress", "--out", str(tmp_path / "out")], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and path in lines[0] and problem in lines[0], lines


def test_compare_and_sweep_refuse_a_bad_budget_before_any_run(tmp_path, capsys):
    for args in (["compare", "hydrostatic", "--boundaries", "adami,dbc", "--jobs", "1"],
                 ["sweep", "hydrostatic", "--set", "dx=0.05", "--jobs", "1"]):
        code, _, err = run_cli(args + ["--out", str(tmp_path / args[0]), "--set", "unstable_window=0"], capsys)
        assert code == 2
        lines = err.strip().splitlines()
        assert len(lines) == 1 and "unstable_window" in lines[0], lines
