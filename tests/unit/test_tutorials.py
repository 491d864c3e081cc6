"""docs/tutorials/ stays true: every file and command of each tutorial runs, at a tiny resolution.

The runs are short (dx = 0.05 m, a few hundredths of a second) so each tutorial takes seconds once
the compiled loops are cached; what they print is checked for the quantities the text promises.
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from seawall.io import read_probes_csv
from tests.tutorial_blocks import DOCS, run_tutorial

REPO = Path(__file__).resolve().parents[2]
SMALL = {"run": ["--dx", "0.05", "--t-end", "0.02", "--no-progress"],
         "compare": ["--dx", "0.05", "--t-end", "0.02", "--jobs", "1"],
         "bench": ["--dx", "0.05", "--steps", "3"]}


def test_index_lists_every_tutorial():
    index = (DOCS / "README.md").read_text()
    linked = set(re.findall(r"\]\(([\w-]+\.md)\)", index))
    present = {p.name for p in DOCS.glob("*.md")} - {"README.md"}
    assert present <= linked, f"tutorials missing from docs/tutorials/README.md: {sorted(present - linked)}"
    assert linked <= present, f"links to missing tutorials: {sorted(linked - present)}"


def test_first_case(tmp_path):
    steps = run_tutorial("first-case.md", tmp_path, SMALL)
    said = dict(steps)
    # seawall cases lists the file's parameters with units
    assert re.search(r"U\b.*0\.3.*m/s", said["seawall cases slosh.py"])
    assert re.search(r"L\b.*0\.8.*\bm\b", said["seawall cases two_columns.toml"])
    # both runs wrote their probes; the dbc run took U = 0.5 m/s: kinetic energy m U^2 / 2 at t = 0
    for run, speed in (("slosh", 0.3), ("slosh-dbc", 0.5)):
        t, probes = read_probes_csv(str(tmp_path / "runs" / run / "probes.csv"))
        summary = json.loads((tmp_path / "runs" / run / "summary.json").read_text())
        assert summary["status"] == "completed" and summary["boundary"] == ("dbc" if speed == 0.5 else "adami")
        mass = summary["n_fluid"] * 1000.0 * 0.05 ** 2
        assert probes["kinetic_energy"][0] == pytest.approx(0.5 * mass * speed ** 2, rel=1e-9)
        assert {"p_left", "p_right"} <= set(probes) and np.all(np.isfinite(probes["p_right"]))
    printed = [out for what, out in steps if "read_probes_csv" in what][0]
    assert printed.count("largest pressure on the right wall") == 2
    assert (tmp_path / "runs" / "slosh" / "probes.png").exists()
    t, probes = read_probes_csv(str(tmp_path / "runs" / "two-columns" / "probes.csv"))
    assert probes["F_down"][0] < 0.0                       # the water presses the tank down
    compare_md = (tmp_path / "runs" / "compare-two-columns" / "compare.md").read_text()
    assert "adami" in compare_md and "dbc" in compare_md


def test_your_own_probe(tmp_path):
    steps = run_tutorial("your-own-probe.md", tmp_path, SMALL, replace={"sim.run(0.4,": "sim.run(0.02,"})
    t, probes = read_probes_csv(str(tmp_path / "runs" / "gauges" / "probes.csv"))
    summary = json.loads((tmp_path / "runs" / "gauges" / "summary.json").read_text())
    assert summary["probe_units"]["level_column"] == "m"
    # at t = 0 the column stands H = 0.2 m high (4 particles of dx 0.05: tops at 0.2 m); the far gauge is dry
    assert probes["level_column"][0] == pytest.approx(0.2, abs=1e-12)
    assert probes["level_far"][0] == 0.0
    printed = "".join(out for what, out in steps)
    assert "level in the column: 0.200 m at t = 0" in printed
    assert "samples; water level at x = 1 m" in printed and (tmp_path / "levels.csv").exists()
    # the built-in probes from the command line
    t, probes = read_probes_csv(str(tmp_path / "runs" / "dam-break-probes" / "probes.csv"))
    assert {"sensor:1", "wall_force:tank:fx", "wall_force:tank:fy"} <= set(probes)
    assert probes["wall_force:tank:fy"][0] < 0.0


def test_overtopping_a_seawall(tmp_path):
    # long enough at dx = 0.05 m for the bore to reach the seawall and load it (its front is at the
    # toe, 1.6 m, at about 0.3 s), so the TOML and Python builds are compared on a force, not on zeros
    settings = {**SMALL, "run": ["--dx", "0.05", "--t-end", "0.6", "--no-progress"]}
    steps = run_tutorial("overtopping-a-seawall.md", tmp_path, settings)
    said = dict(steps)
    assert re.search(r"crest\b.*0\.2.*\bm\b", said["seawall cases seawall.toml"])
    for model in ("adami", "dbc", "mdbc"):
        summary = json.loads((tmp_path / "runs" / model / "summary.json").read_text())
        assert summary["status"] == "completed" and summary["walls"].keys() == {"tank", "seawall"}
        assert summary["probe_units"]["q_crest"] == "m^2" and summary["probe_units"]["q_crest_rate"] == "m^2/s"
        assert abs(summary["mass_drift"]) < 1e-12
        t, probes = read_probes_csv(str(tmp_path / "runs" / model / "probes.csv"))
        assert probes["F_seawall"].max() > 1.0              # the bore pushes the seawall landwards [N/m]
    printed = "".join(out for what, out in steps)
    assert printed.count("peak force on the seawall") == 3
    assert (tmp_path / "runs" / "dbc" / "discharge.csv").exists()
    # the seawall of the case file and of the Python module: one simulation, the same force to round-off
    t_toml, toml = read_probes_csv(str(tmp_path / "runs" / "dbc" / "probes.csv"))
    t_py, py = read_probes_csv(str(tmp_path / "runs" / "dbc-python" / "probes.csv"))
    np.testing.assert_array_equal(t_toml, t_py)
    assert np.abs(toml["F_seawall"]).max() > 1.0
    np.testing.assert_allclose(py["F_seawall"], toml["F_seawall"], rtol=0, atol=1e-9 * np.abs(toml["F_seawall"]).max())
    assert "largest difference of the force on the seawall, TOML against Python" in printed


def test_api_reference_builds_without_warnings(tmp_path):
    """python docs/build_api.py: every public module renders and pdoc raises no warning."""
    pytest.importorskip("pdoc", reason="pdoc not installed (pip install -e '.[test]' or '.[docs]')")
    from seawall.validation import load_script

    build_api = load_script(str(REPO / "docs" / "build_api.py"))
    problems = build_api.build(tmp_path / "api")
    assert problems == []
    for module in build_api.PUBLIC_MODULES:
        page = tmp_path / "api" / (module.replace(".", "/") + ".html")
        assert page.exists(), module
    simulation = (tmp_path / "api" / "seawall" / "simulation.html").read_text()
    assert "Simulation" in simulation and "unstable_fraction" in simulation   # the docstring's parameters
