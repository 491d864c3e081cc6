"""seawall compare: one row per wall model, no missing cell where the case has something to measure."""

import csv

from seawall.cli import main

MODELS = ["adami", "dbc", "ghost-shepard"]
ALWAYS = ["escaped", "min_wall_distance_dx", "wall_pressure_error", "pressure_noise", "particle_steps_per_s",
          "relative_time", "steps"]


def test_compare_hydrostatic_table(tmp_path, capsys):
    out = tmp_path / "cmp"
    code = main(["compare", "hydrostatic", "--boundaries", ",".join(MODELS), "--dx", "0.04", "--t-end", "0.3",
                 "--out", str(out), "--jobs", "1"])
    printed = capsys.readouterr().out
    assert code == 0
    rows = list(csv.DictReader(open(out / "compare.csv")))
    assert [r["boundary"] for r in rows] == MODELS
    for row in rows:
        assert row["status"] == "completed"
        for key in ALWAYS:
            assert row[key] != "", (row["boundary"], key)
        assert int(row["escaped"]) == 0
        assert sum(int(row[f"escaped_{r}"]) for r in ("domain", "wall", "unstable")) == int(row["escaped"])
        assert float(row["min_wall_distance_dx"]) > 0.0        # nothing inside a wall
        assert float(row["wall_pressure_error"]) < 0.2
    assert min(float(r["relative_time"]) for r in rows) == 1.0
    md = (out / "compare.md").read_text()
    for model in MODELS:
        assert f"| {model} |" in md
    assert "of which domain / wall / unstable / overtopped" in md and "| 0 / 0 / 0 / 0 |" in md
    assert (out / "probe_P0.png").exists()
    assert "wall models compared" in printed
    for model in MODELS:
        assert (out / model / "probes.csv").exists() and (out / model / "summary.json").exists()


def test_compare_every_wall_model_fills_every_cell(tmp_path):
    """Every registered wall model (new ones included automatically) gets a complete row."""
    from seawall.boundary.registry import BOUNDARIES

    out = tmp_path / "all"
    code = main(["compare", "hydrostatic", "--boundaries", ",".join(BOUNDARIES), "--dx", "0.04", "--t-end", "0.3",
                 "--out", str(out)])
    assert code == 0
    rows = list(csv.DictReader(open(out / "compare.csv")))
    assert [r["boundary"] for r in rows] == list(BOUNDARIES)
    for row in rows:
        assert row["status"] == "completed", row["boundary"]
        for key in ALWAYS:
            assert row[key] != "", (row["boundary"], key)
