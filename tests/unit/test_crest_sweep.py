"""validation/overtopping/crest_sweep.py: which settings it runs, how it reads a run, and what its stored
results say (the open dam break holds with every model that holds the closed tank)."""

import json
import os

from seawall.validation import ROOT, load_script

sweep = load_script(os.path.join(ROOT, "validation", "overtopping", "crest_sweep.py"))


def test_every_model_runs_at_its_first_closed_tank_setting_that_held():
    settings = sweep.holding_settings()
    from seawall.boundary.registry import BOUNDARIES

    # zeroing never held the closed tank; every other model has a setting that did
    assert set(settings) == set(BOUNDARIES) - {"zeroing"}
    assert settings["adami"] == {} and settings["ghost-mls1"] == {"reflect": "1"}
    assert settings["liu2012"] == {"c": "48.5"} and settings["mdbc"] == {"clip_negative": "1"}


def test_a_run_is_read_from_its_summary_and_escaped_records(tmp_path):
    summary = {"status": "completed", "t_end": 1.4, "steps": 10, "n_fluid": 7, "mass_drift": 0.0,
               "escaped_by_reason": {"domain": 0, "wall": 0, "unstable": 0, "overtopped": 3},
               "escaped_mass_by_reason": {"overtopped": 0.3}, "probes": {"over_crest": {"final": 2e-4}}}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    (tmp_path / "escaped.csv").write_text("time,id,x,y,side,reason\n0.5,1,1.7,0.4,x+,overtopped\n"
                                          "0.6,2,1.7,0.4,x+,overtopped\n0.7,3,1.0,0.8,y+,overtopped\n")
    rec = sweep.read_run(str(tmp_path))
    assert rec["overtopped_by_side"] == {"x+": 2, "y+": 1}
    # 0.3 kg/m removed, two thirds of it past the wall: 2e-4 m^2/m of rho0 = 1000
    assert abs(rec["overtopped_volume_over_crest"] - 2e-4) < 1e-18 and abs(rec["section_vs_removed"]) < 1e-12
    assert sweep.read_run(str(tmp_path / "nothing"), "boom\n")["status"] == "crashed"


def test_the_stored_sweeps_hold_the_open_tank():
    for n in (30, 50):
        models = sweep.load(n)["models"]
        assert len(models) == 19
        for key, rec in models.items():
            by = rec["escaped_by_reason"]
            assert rec["status"] == "completed" and by["wall"] == 0 and by["domain"] == 0, (n, key)
            assert abs(rec["mass_drift"]) < 1e-12, (n, key)
            if rec["section_vs_removed"] is not None:
                assert abs(rec["section_vs_removed"]) < 1e-12, (n, key)
