"""Case files (case.py, case.toml): loading, parameters, one-line errors, run / restart / compare / bench."""

import json
import os

import numpy as np
import pytest

from seawall.cases import case_by_name
from seawall.cases.templates import write_template
from seawall.cli import main
from seawall.errors import ParameterError
from seawall.io import read_vtu
from seawall.io.vtk import read_vtu_metadata
from seawall.restart_checks import setup_differences


def run_cli(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def py_case(tmp_path):
    return write_template(str(tmp_path / "my_case"))


@pytest.fixture
def toml_case(tmp_path):
    return write_template(str(tmp_path / "my_case"), toml=True)


def test_python_template_loads_with_its_parameters_and_units(py_case):
    case = case_by_name(py_case)
    assert case.name == "my_case" and case.dimension == 2 and case.default_boundary == "adami"
    assert set(case.parameters) == {"dx", "H", "length", "alpha"}
    assert case.parameters["H"].units == "m" and case.parameters["alpha"].units == ""
    assert case.source["sha256"] and os.path.isabs(case.source["path"])


def test_python_case_builds_with_set_values_and_records_the_file(py_case):
    sim = case_by_name(py_case).build(boundary="dbc", dx="0.04", H="0.12")
    assert sim.fluid.n == 9          # a 0.12 m square column at dx = 0.04: 3 x 3 particles
    assert sim.metadata["case"] == "my_case" and sim.metadata["parameters"]["H"] == 0.12
    assert sim.metadata["case_file"] == os.path.abspath(py_case) and len(sim.metadata["case_sha256"]) == 64
    assert [p.name for p in sim.probes] == ["p_right", "front", "kinetic_energy"]


def test_toml_template_builds_the_blocks_and_probes_it_declares(toml_case):
    case = case_by_name(toml_case)
    assert {"dx", "H", "length", "rho0", "alpha", "delta", "c0", "cfl", "h_factor"} == set(case.parameters)
    sim = case.build(dx=0.05, H=0.2, alpha=0.05)
    assert sim.fluid.n == 8 * 4     # column 2H x H = 0.4 x 0.2 at dx = 0.05
    assert sim.physics.alpha == pytest.approx(0.05)
    # hydrostatic: the lowest row (y = dx / 2) starts at rho(p = rho0 g (H - dx / 2))
    assert sim.fluid.particles["rho"].max() == pytest.approx(float(sim.fluid.eos.density(1000.0 * 9.81 * 0.175,
                                                                                           1000.0)), rel=1e-12)
    assert sim.fluid.particles["rho"].max() > 1000.0
    assert [p.name for p in sim.probes] == ["p_right", "front"]
    np.testing.assert_allclose(sim.probes[0].point, [0.8, 0.04])   # "length", "0.2 * H"
    with pytest.raises(ParameterError, match="has no parameter 'depth'"):
        case.build(depth=0.1)


def test_cases_name_prints_parameters_with_defaults_and_units(toml_case, capsys):
    code, out, _ = run_cli(["cases", toml_case], capsys)
    assert code == 0
    rows = {line.split()[0]: line.split() for line in out.splitlines() if line.startswith("    ")}
    assert rows["dx"][1:3] == ["0.01", "m"] and rows["rho0"][1:3] == ["1000.0", "kg/m^3"]
    assert rows["c0"][1] == "(case)"
    code, out, _ = run_cli(["cases", "dam-break"], capsys)
    assert code == 0 and any(line.split()[:3] == ["H", "0.3", "m"] for line in out.splitlines())


def test_new_case_refuses_to_overwrite(tmp_path, capsys):
    path = str(tmp_path / "c.py")
    assert run_cli(["new-case", path], capsys)[0] == 0
    code, _, err = run_cli(["new-case", path], capsys)
    assert code == 2 and "exists" in err and len(err.strip().splitlines()) == 1


TOML_HEAD = '[parameters]\ndx = {default = 0.05, unit = "m"}\n[tank]\nlo = [0, 0]\nhi = [1, 0.5]\n'


@pytest.mark.parametrize("suffix,text,problem", [
    (".toml", "[case\nname = 1\n", "invalid TOML"),
    (".toml", TOML_HEAD + "[[water]]\nlo = [0, 0]\nhi = [0.5, 0.2]\n[wind]\nspeed = 1\n", "unknown table [wind]"),
    (".toml", TOML_HEAD.replace('dx = {default = 0.05, unit = "m"}', "H = 1.0") +
     "[[water]]\nlo = [0, 0]\nhi = [0.5, 0.2]\n", "must declare dx"),
    (".toml", TOML_HEAD + "[[water]]\nlo = [0, 0]\nhi = [1.5, 0.2]\n", "must lie inside the tank"),
    (".toml", TOML_HEAD + "[[water]]\nlo = [0, 0]\nhi = [\"2 * width\", 0.2]\n", "unknown name 'width'"),
    (".toml", TOML_HEAD + "[[water]]\nlo = [0, 0]\nhi = [\"__import__('os')\", 0.2]\n", "not an arithmetic"),
    (".toml", TOML_HEAD + "[[water]]\nlo = [0, 0]\nhi = [0.5, 0.2]\n[[probe]]\nkind = \"speed\"\n", "kind must be"),
    (".toml", TOML_HEAD + "[[water]]\nlo = [0, 0]\nhi = [0.5, 0.2]\n[[water]]\nlo = [0.2, 0]\nhi = [0.6, 0.1]\n",
     "overlaps"),
    (".py", "def build(:\n", "syntax error at line 1"),
    (".py", "PARAMETERS = {}\n", "defines no function build"),
    (".py", "import no_such_module_xyz\n", "ModuleNotFoundError while loading (line 1)"),
    (".py", "from seawall.cases import Parameter\nPARAMETERS = {'H': Parameter(1.0, 'h')}\n"
            "def build(boundary, H):\n    pass\n", "must declare dx"),
    (".py", "from seawall.cases import Parameter\nPARAMETERS = {'dx': Parameter(0.05, 'dx')}\n"
            "def build(dx, boundary):\n    return 3\n", "returned int, not a seawall.Simulation"),
    (".py", "from seawall.cases import Parameter\nPARAMETERS = {'dx': Parameter(0.05, 'dx')}\n"
            "def build(dx, boundary):\n    return undefined_name\n", "NameError in build() (line 4)"),
    (".txt", "", "ends in .py or .toml"),
])
def test_a_malformed_case_file_stops_with_one_line_naming_file_and_problem(tmp_path, capsys, suffix, text, problem):
    path = tmp_path / f"bad{suffix}"
    path.write_text(text)
    code, _, err = run_cli(["run", str(path), "--out", str(tmp_path / "out"), "--no-progress"], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and problem in lines[0], lines
    assert not (tmp_path / "out").exists()


def test_restart_refuses_a_changed_case_file(toml_case):
    case = case_by_name(toml_case)
    before = case.build(dx=0.05).metadata
    with open(toml_case, "a") as fh:
        fh.write("\n# edited\n")
    after = case_by_name(toml_case).build(dx=0.05).metadata
    diffs = setup_differences(before, after)
    assert len(diffs) == 1 and diffs[0].startswith("case file changed since the checkpoint")
    assert setup_differences(before, before) == []


def test_file_case_runs_restarts_and_writes_walls_every_frame(toml_case, tmp_path, capsys):
    out = tmp_path / "run"
    base = ["run", toml_case, "--dx", "0.05", "--out", str(out), "--no-progress", "--boundary", "dbc",
            "--output-every", "0.004", "--checkpoint-every", "0.004"]
    code, stdout, err = run_cli(base + ["--t-end", "0.008"], capsys)
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["case"] == "my_case" and summary["boundary"] == "dbc" and summary["status"] == "completed"
    assert summary["probe_units"] == {"p_right": "Pa", "front": "m"}
    assert summary["files"]["wall_series"] == ["wall_tank.pvd"]
    fluid = sorted(f for f in os.listdir(out) if f.startswith("fluid_"))
    walls = sorted(f for f in os.listdir(out) if f.startswith("wall_tank_"))
    assert len(fluid) == len(walls) == 3       # t = 0, 0.004, 0.008: the fixed wall at every frame too
    meta = read_vtu_metadata(out / walls[-1])
    assert meta["case"] == "my_case" and meta["pressure_convention"].startswith("gauge")
    assert meta["TimeValue"] == pytest.approx(0.008, abs=1e-3) and meta["dx"] == 0.05 and len(meta["wall_force"]) == 2
    _, data = read_vtu(out / walls[-1])
    np.testing.assert_array_equal(data["pressure"], data["pressure_absolute"] - meta["p_background"])
    # the same file continues; an edited file does not
    code, _, err = run_cli(base + ["--t-end", "0.012", "--restart", str(out / "checkpoint.h5")], capsys)
    assert code == 0, err
    with open(toml_case, "a") as fh:
        fh.write("\n# edited\n")
    code, _, err = run_cli(base + ["--t-end", "0.016", "--restart", str(out / "checkpoint.h5")], capsys)
    assert code == 2 and "case file changed since the checkpoint" in err and len(err.strip().splitlines()) == 1


def test_file_case_in_bench_and_compare(py_case, tmp_path, capsys):
    code, out, err = run_cli(["bench", py_case, "--dx", "0.04", "--steps", "2", "--chunks", "1"], capsys)
    assert code == 0, err
    line = json.loads(out.strip().splitlines()[-1])
    assert line["case"] == "my_case" and line["n_fluid"] == 25    # the 0.2 m column at dx = 0.04
    cmp_out = tmp_path / "cmp"
    code, out, err = run_cli(["compare", py_case, "--boundaries", "adami,dbc", "--dx", "0.04", "--t-end", "0.004",
                              "--jobs", "1", "--out", str(cmp_out)], capsys)
    assert code == 0, err
    rows = {r.split(",")[0]: r.split(",") for r in (cmp_out / "compare.csv").read_text().splitlines()}
    header = rows.pop("boundary")
    rate = {b: float(r[header.index("particle_steps_per_s")]) for b, r in rows.items()}
    rel = {b: float(r[header.index("relative_time")]) for b, r in rows.items()}
    fastest = max(rate, key=rate.get)
    assert rel[fastest] == 1.0
    for b in rel:
        assert rel[b] == pytest.approx(rate[fastest] / rate[b])


def test_toml_case_in_3d(tmp_path):
    path = tmp_path / "box.toml"
    path.write_text('[parameters]\ndx = {default = 0.05, unit = "m"}\nW = 0.2\n'
                    '[tank]\nlo = [0, 0, 0]\nhi = [0.6, "W", 0.4]\nopen_top = false\n'
                    '[[water]]\nlo = [0, 0, 0]\nhi = [0.2, "W", 0.2]\n'
                    '[[water]]\nlo = [0.4, 0, 0]\nhi = [0.6, "W", 0.1]\npressure = "rest"\n'
                    '[[probe]]\nkind = "wall_pressure"\nname = "p"\npoint = [0.6, "W / 2", 0.05]\n'
                    '[[probe]]\nkind = "wall_force"\nname = "F"\naxis = 2\n')
    case = case_by_name(str(path))
    assert case.dimension == 3 and case.parameters["W"].default == 0.2
    sim = case.build(boundary="dbc")
    assert sim.dim == 3 and sim.fluid.n == 4 * 4 * 4 + 4 * 4 * 2
    rho = sim.fluid.particles["rho"]
    x = sim.fluid.particles["x"]
    assert np.all(rho[x[:, 0] > 0.3] == 1000.0) and np.all(rho[x[:, 0] < 0.3] > 1000.0)   # rest / hydrostatic
    assert [p.name for p in sim.probes] == ["p", "F"] and sim.probes[1].axis == 2
