"""validation/dam-break/plateau_profiles.py without a run: the slip groups and their spread table (issue 15, item 7)."""

import os

from seawall.validation import ROOT, load_script

plateau_profiles = load_script(os.path.join(ROOT, "validation", "dam-break", "plateau_profiles.py"))


def _record(model, values, params=None, status="completed", readout="wall"):
    return {"model": model, "params": params or {}, "status": status,
            "plateau": {readout: {f"{f:g}": v for f, v in zip(plateau_profiles.HEIGHTS, values)}}}


def test_slip_group_follows_the_name_unless_an_option_says():
    group = plateau_profiles.slip_group
    assert group(_record("adami", [0] * 5)) == "free slip"
    assert group(_record("adami-noslip", [0] * 5)) == "no slip"
    assert group(_record("adami", [0] * 5, {"slip": "noslip"})) == "no slip"
    assert group(_record("liu2015-noslip", [0] * 5, {"slip": "free"})) == "free slip"


def test_slip_group_reads_the_model_default_slip():
    group = plateau_profiles.slip_group
    # mdbc keeps the wall's own velocity (vel0): the fluid's viscosity acts across a still wall
    assert group(_record("mdbc", [0] * 5)) == "no slip"
    assert group(_record("mdbc", [0] * 5, {"clip_negative": "1"})) == "no slip"
    assert group(_record("mdbc-noslip", [0] * 5)) == "no slip"
    # no slip option at all: no viscosity across the wall
    for model in ("dbc", "idbc", "liu2012", "monaghan-kajtar"):
        assert group(_record(model, [0] * 5)) == "free slip"
    assert group(_record("ghost-mls1", [0] * 5, {"reflect": "1"})) == "free slip"
    assert group(_record("lust", [0] * 5)) == "free slip"


def test_spread_per_height_within_each_group_and_the_farthest_run():
    models = {
        "a": _record("a", [1.0, 0.9, 0.8, 0.5, 0.3]),
        "b": _record("b", [0.9, 0.9, 0.8, 0.5, 0.3]),
        "c": _record("c", [0.5, 0.6, 0.5, 0.3, 0.2]),
        "d": _record("d", [9.0, 9.0, 9.0, 9.0, 9.0], status="unstable"),     # not compared
        "e-noslip": _record("e-noslip", [0.6, 0.5, 0.5, 0.5, 0.4]),
        "f-noslip": _record("f-noslip", [0.5, 0.5, 0.5, 0.5, 0.4]),
    }
    text = plateau_profiles.agreement({50: {"models": models}}, lambda m: sorted(m))
    rows = [line for line in text.splitlines() if line.startswith("| H/50")]
    assert rows == ["| H/50 | free slip | wall | 3 | 0.50 | 0.30 | 0.30 | 0.20 | 0.10 | `c` |",
                    "| H/50 | no slip | wall | 2 | 0.10 | 0.00 | 0.00 | 0.00 | 0.00 | -- |"]


def test_a_run_without_the_read_out_at_every_height_is_left_out():
    models = {"a": _record("a", [1.0, 0.9, 0.8, 0.5, 0.3]), "b": _record("b", [0.9, 0.9, 0.8, 0.5, 0.3])}
    models["b"]["plateau"]["wall"].pop("0.27")
    assert "| H/100 |" not in plateau_profiles.agreement({100: {"models": models}}, lambda m: sorted(m))
