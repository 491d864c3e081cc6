"""validation/dam-break/plateau_ensemble.py without a run: the members' options and their spread."""

import os

import pytest

from seawall.validation import ROOT, load_script

plateau_ensemble = load_script(os.path.join(ROOT, "validation", "dam-break", "plateau_ensemble.py"))


def _member(values, status="completed"):
    return {"status": status, "plateau": {"force": dict(zip(plateau_ensemble.HEIGHTS, values)),
                                          "wall": dict(zip(plateau_ensemble.HEIGHTS, values))}}


def test_members_change_the_cfl_number_in_its_last_digits():
    assert [plateau_ensemble.member_cfl(e) for e in plateau_ensemble.MEMBERS] == \
        ["0.2", "0.199998", "0.200002", "0.19998", "0.20002"]


def test_spread_is_over_completed_members_only():
    records = [_member([1.0, 0.9, 0.8, 0.5, 0.3]), _member([1.2, 0.9, 0.8, 0.5, 0.3]),
               _member([1.1, 0.9, 0.8, 0.5, 0.3]), _member([9.0] * 5, status="unstable")]
    s = plateau_ensemble.spread(records, "force")
    n, sd, rng = s["0.01"]
    assert n == 3
    assert abs(sd - 0.1) < 1e-12 and abs(rng - 0.2) < 1e-12
    assert s["0.27"][1] == 0.0 and s["0.27"][2] == 0.0


def test_table_has_a_row_per_model_and_readout():
    data = {"H50": {"adami": {"0.2": _member([1.0] * 5), "0.199998": _member([1.1] * 5)}}}
    lines = plateau_ensemble.table(data).splitlines()
    assert len(lines) == 2 + len(plateau_ensemble.TABLE_READOUTS)
    assert lines[2].startswith("| 50 | `adami` | 2 | force | 0.071, 0.100 |")


def test_table_keeps_a_model_run_with_an_option_apart():
    data = {"H50": {"ghost-mls2 reflect=1": {"0.2": _member([1.0] * 5), "0.199998": _member([1.1] * 5)},
                    "adami": {"0.2": _member([1.0] * 5)}}}
    rows = [line.split(" | ")[1] for line in plateau_ensemble.table(data).splitlines()[2:]]
    assert set(rows) == {"`adami`", "`ghost-mls2 reflect=1`"}


@pytest.mark.parametrize("item, named", [("cfl=0.3", "--set cfl"), ("reflect", "--set expects KEY=VALUE")])
def test_a_bad_option_is_refused_in_one_line_before_any_run(item, named, capsys):
    with pytest.raises(SystemExit) as stop:
        plateau_ensemble.main(["--models", "adami", "--set", item])
    assert stop.value.code == 2
    assert named in capsys.readouterr().err
