"""seawall sweep and the executors of compare / validate / sweep (seawall.sweep, seawall.executors)."""

import csv
import json
import math
import os

import numpy as np
import pytest

from seawall.cases import case_by_name
from seawall.cli import main
from seawall.errors import ParameterError
from seawall.executors import (DaskCluster, InProcess, LocalProcesses, Task, executor_for, local_executor,
                               run_tasks)
from seawall.sweep import check_settings, combinations, parse_set_items, parse_sweep_sets, run_dir_name, sweep


def run_cli(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


# ---------------------------------------------------------------------------- --set values and their product

def test_sets_are_read_in_order_with_their_values():
    grid = parse_sweep_sets(["alpha=0.01, 0.02", "h-factor=1.3", "boundary=adami,dbc"])
    assert grid == {"alpha": ["0.01", "0.02"], "h_factor": ["1.3"], "boundary": ["adami", "dbc"]}
    assert list(grid) == ["alpha", "h_factor", "boundary"]


@pytest.mark.parametrize("item, names", [
    ("alpha", "KEY=VALUE"), ("=1,2", "KEY=VALUE"), ("alpha=", "alpha"), ("alpha=1,,2", "alpha"),
    ("alpha=1,1", "alpha")])
def test_bad_set_syntax_stops_naming_it(item, names):
    with pytest.raises(ParameterError, match=names):
        parse_sweep_sets([item])


def test_a_key_given_twice_is_refused():
    with pytest.raises(ParameterError, match="--set alpha is given twice"):
        parse_sweep_sets(["alpha=1", "alpha=2"])


def test_single_sets_are_read_as_seawall_run_reads_them():
    assert parse_set_items(["reflect= 1 ", "clip-negative=1", "c=48.5"]) == \
        {"reflect": "1", "clip_negative": "1", "c": "48.5"}
    assert parse_set_items(None) == {}
    for item in ("reflect", "=1"):
        with pytest.raises(ParameterError, match="KEY=VALUE"):
            parse_set_items([item])


def test_the_product_has_every_combination_first_key_outermost():
    runs = combinations({"a": ["1", "2"], "b": ["x", "y", "z"], "c": ["k"]})
    assert len(runs) == 6
    assert runs[0] == {"a": "1", "b": "x", "c": "k"} and runs[1] == {"a": "1", "b": "y", "c": "k"}
    assert runs[3] == {"a": "2", "b": "x", "c": "k"}
    assert len({tuple(r.values()) for r in runs}) == 6
    assert combinations({"a": ["1"]}) == [{"a": "1"}]


def test_run_directories_are_distinct_and_safe_names():
    assert run_dir_name(3, {"alpha": "0.01", "boundary": "ghost-mls1"}) == "003_alpha=0.01_boundary=ghost-mls1"
    a, b = run_dir_name(0, {"f": "a/b"}), run_dir_name(1, {"f": "a b"})
    assert "/" not in a and " " not in b and a != b


def test_settings_are_checked_as_seawall_run_checks_them():
    case = case_by_name("hydrostatic")
    check_settings(case, "adami", {"alpha": "0.01", "slip": "noslip", "dx": 0.03})   # case and model keys
    check_settings(case, "dbc", {"adhesion_coefficient": "0.1", "shifting": "sun2017"})
    with pytest.raises(ParameterError, match="no parameter 'alfa'"):
        check_settings(case, "adami", {"alfa": "0.01"})
    with pytest.raises(ParameterError, match="alpha .* must be float"):
        check_settings(case, "adami", {"alpha": "much"})
    with pytest.raises(ParameterError, match="no parameter 'slip'"):      # slip is an option of adami, not of dbc
        check_settings(case, "dbc", {"slip": "noslip"})
    with pytest.raises(ParameterError, match="unknown boundary 'nope'"):
        check_settings(case, "nope", {})


def test_sweep_with_an_unknown_key_stops_in_one_line_before_any_run(tmp_path, capsys):
    out = tmp_path / "sw"
    code, _, err = run_cli(["sweep", "hydrostatic", "--set", "alpha=0.01,0.02", "--set", "alfa=1",
                            "--out", str(out)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "'alfa'" in err
    assert not out.exists()
    code, _, err = run_cli(["sweep", "hydrostatic", "--set", "boundary=adami,teflon", "--out", str(out)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "unknown boundary 'teflon'" in err
    code, _, err = run_cli(["sweep", "hydrostatic", "--set", "boundary=adami,dbc", "--set", "slip=noslip",
                            "--out", str(out)], capsys)    # slip is an option of adami, not of dbc
    assert code == 2 and "no parameter 'slip'" in err and not out.exists()
    code, _, err = run_cli(["sweep", "hydrostatic", "--set", "alpha", "--out", str(out)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "--set expects KEY=VALUE" in err
    code, _, err = run_cli(["sweep", "hydrostatic", "--set", "alpha=1", "--workers", "2", "--out", str(out)],
                           capsys)
    assert code == 2 and "--workers" in err and not out.exists()


def test_a_run_that_fails_is_a_row_of_the_table_and_the_exit_code_says_so(tmp_path, capsys):
    # a regularisation value is checked when the run is built: here the run, not the sweep, fails
    out = tmp_path / "sw"
    code, stdout, err = run_cli(["sweep", "hydrostatic", "--set", "dx=0.05", "--set", "shifting=bogus",
                                 "--t-end", "0.02", "--jobs", "1", "--out", str(out)], capsys)
    assert code == 3 and "000_dx=0.05_shifting=bogus: failed: ParameterError: shifting must be one of" in err
    with open(out / "sweep.csv") as fh:
        (row,) = list(csv.DictReader(fh))
    assert row["status"].startswith("failed: ParameterError") and row["steps"] == "" and row["shifting"] == "bogus"
    assert "| failed: ParameterError" in stdout and "summary.json" not in (out / "sweep.md").read_text()


# ---------------------------------------------------------------------------- executors

def _sqrt_tasks():
    # math.sqrt pickles by reference and raises for -1: three runs, the middle one fails
    return [Task(math.sqrt, (4.0,), "four"), Task(math.sqrt, (-1.0,), "minus one"), Task(math.sqrt, (9.0,), "nine")]


@pytest.mark.parametrize("executor", [InProcess(1), LocalProcesses(2, 1)], ids=["in-process", "processes"])
def test_executor_returns_outcomes_in_order_and_records_a_failure(executor):
    seen = []
    outcomes = run_tasks(executor, _sqrt_tasks(), progress=False, on_done=lambda i, o: seen.append(i))
    assert [o.label for o in outcomes] == ["four", "minus one", "nine"]
    assert outcomes[0].ok and outcomes[0].value == 2.0 and outcomes[2].value == 3.0
    assert not outcomes[1].ok and outcomes[1].error == "ValueError: math domain error"
    assert "ValueError" in outcomes[1].details
    assert sorted(seen) == [0, 1, 2]


def test_executor_choice_from_the_options(monkeypatch):
    # a 2-core machine, whatever NUMBA_NUM_THREADS the tests run with
    monkeypatch.setattr("seawall.executors.usable_cores", lambda: 2)
    one = executor_for(jobs=1, n_tasks=4)
    assert isinstance(one, InProcess)
    assert isinstance(executor_for(n_tasks=3, default_in_process=True), InProcess)
    procs = local_executor(2, 5, threads_per_run=1)
    assert isinstance(procs, LocalProcesses) and procs.jobs <= 2 and procs.threads_per_run == 1
    cluster = executor_for(scheduler="local", workers=2, n_tasks=5)
    assert isinstance(cluster, DaskCluster) and cluster.local and cluster.workers == 2
    assert executor_for(scheduler="local", workers=4, n_tasks=2).workers == 2      # no idle workers
    remote = executor_for(scheduler="tcp://127.0.0.1:8786", n_tasks=2)
    assert not remote.local and remote.threads_per_run == 1
    with pytest.raises(ParameterError, match="--workers"):
        executor_for(workers=2, n_tasks=2)
    with pytest.raises(ParameterError, match="--jobs"):
        executor_for(scheduler="local", jobs=2, n_tasks=2)
    with pytest.raises(ParameterError, match="--workers"):
        executor_for(scheduler="tcp://127.0.0.1:8786", workers=2, n_tasks=2)


# ---------------------------------------------------------------------------- a sweep on a local dask cluster

TIMING = {"wall_time_s", "startup_s", "particle_steps_per_s"}


def _without_timing(summary):
    out = {k: v for k, v in summary.items() if k not in TIMING}
    out["metrics"] = {k: v for k, v in summary["metrics"].items() if k not in TIMING}
    return out


def _assert_same(a, b, where):
    """Equal, floats to 1e-9: the same run in two fresh processes; docs/architecture.md measured up to
    2.4e-12 between code compiled cold and loaded from the cache, which CI's first run may mix."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            _assert_same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b)):
            _assert_same(x, y, f"{where}[{k}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-9, abs=1e-12), where
    else:
        assert a == b, where


@pytest.fixture(scope="module")
def cluster():
    """The local dask cluster of 2 workers (one run at a time each) that ``--scheduler local --workers 2``
    starts; the tests reach it by its address, as ``--scheduler tcp://...`` reaches a remote one."""
    pytest.importorskip("distributed")
    local = DaskCluster("local", workers=2, threads_per_run=1)
    with local:
        yield local.cluster.scheduler_address
    assert local.cluster.status.name == "closed" and local.client.status == "closed"   # stopped with the command


def test_a_sweep_on_a_dask_cluster_equals_the_one_in_local_processes(cluster, tmp_path):
    grid = {"alpha": ["0.02", "0.05"], "dx": ["0.05"]}
    settings = dict(boundary="adami", t_end=0.02, progress=False)
    local_out, dask_out = tmp_path / "local", tmp_path / "dask"
    # both with one thread per run, so the two do the same arithmetic
    local_rows = sweep("hydrostatic", grid, executor=LocalProcesses(2, 1), out=str(local_out), **settings)
    on_dask = DaskCluster(cluster, threads_per_run=1)
    dask_rows = sweep("hydrostatic", grid, executor=on_dask, out=str(dask_out), **settings)
    assert on_dask.client.status == "closed"
    assert [r["status"] for r in dask_rows] == ["completed", "completed"]
    assert [r["alpha"] for r in dask_rows] == ["0.02", "0.05"]
    for rl, rd in zip(local_rows, dask_rows):
        _assert_same({k: v for k, v in rl.items() if k not in TIMING},
                     {k: v for k, v in rd.items() if k not in TIMING}, "row")
        assert rd["steps"] > 10 and rd["wall_time_s"] > 0
        sl = json.loads((local_out / rl["run_dir"] / "summary.json").read_text())
        sd = json.loads((dask_out / rd["run_dir"] / "summary.json").read_text())
        _assert_same(_without_timing(sl), _without_timing(sd), rd["run_dir"])
        assert sd["parameters"]["alpha"] == float(rd["alpha"])
        pl = np.loadtxt(local_out / rl["run_dir"] / "probes.csv", delimiter=",", skiprows=1)
        pd = np.loadtxt(dask_out / rd["run_dir"] / "probes.csv", delimiter=",", skiprows=1)
        assert pd.shape == pl.shape and pd.shape[0] > 5
        np.testing.assert_allclose(pd, pl, rtol=1e-9, atol=1e-15)
    # the two values of alpha gave two different runs
    assert dask_rows[0]["wall_pressure_error"] != dask_rows[1]["wall_pressure_error"]
    with open(dask_out / "sweep.csv") as fh:
        table = list(csv.DictReader(fh))
    assert [t["alpha"] for t in table] == ["0.02", "0.05"] and [t["dx"] for t in table] == ["0.05", "0.05"]
    assert table[0]["boundary"] == "adami" and table[0]["run_dir"] == dask_rows[0]["run_dir"]
    md = (dask_out / "sweep.md").read_text()
    assert md.startswith("# hydrostatic: sweep over alpha, dx") and md.count("| completed |") == 2
    assert os.path.isdir(dask_out / "000_alpha=0.02_dx=0.05")


def test_a_failed_task_on_the_dask_cluster_is_recorded_and_the_others_finish(cluster):
    outcomes = run_tasks(DaskCluster(cluster), _sqrt_tasks(), progress=False)
    assert [o.value for o in outcomes] == [2.0, None, 3.0]
    assert outcomes[1].error == "ValueError: math domain error"


STAND_IN = '''
from seawall.validation import Entry, row


def run(ctx):
    return {"rows": [row("none", "two", "arithmetic", 2.0, 1.0 + 1.0, tolerance=0.0)], "settings": "none"}


def broken(ctx):
    raise RuntimeError("no data")


ENTRIES = (Entry(name="stand-in", title="A stand-in entry", run=run, expected_s=1.0),
           Entry(name="broken-in", title="An entry that cannot run", run=broken, expected_s=1.0))
'''


def test_validate_runs_its_entries_on_the_dask_cluster(cluster, tmp_path, monkeypatch, capsys):
    import sys

    from seawall import validation

    case = tmp_path / "validation" / "stand-in"
    case.mkdir(parents=True)
    (case / "entry.py").write_text(STAND_IN)
    monkeypatch.setattr(validation, "VALIDATION_DIR", str(tmp_path / "validation"))
    try:
        doc = tmp_path / "docs" / "validation.md"
        code = main(["validate", "--doc", str(doc), "--scheduler", cluster])
        _, err = capsys.readouterr()
        assert code == 1 and "[broken-in] failed to run: RuntimeError: no data" in err   # recorded, not the end
        stored = json.loads((case / "results" / "stand-in.json").read_text())   # written by the worker
        assert stored["rows"][0]["pass"] and stored["threads"] == 1
        text = doc.read_text()
        assert "| [stand-in](#stand-in) |" in text and "| broken-in | | | | | | | | not run |" in text
    finally:
        sys.modules.pop("seawall.validation.entries.stand_in", None)
        vars(sys.modules["seawall.validation.entries"]).pop("stand_in", None)
