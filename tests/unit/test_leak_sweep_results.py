"""validation/leaks/sweep.py keeps what it stored: a sweep of another end time stops instead of
throwing the stored table away."""

import json
import os

import pytest

from seawall.validation import ROOT, load_script

sweep = load_script(os.path.join(ROOT, "validation", "leaks", "sweep.py"))


def test_a_sweep_of_another_end_time_stops_and_keeps_the_stored_rows(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sweep, "HERE", str(tmp_path))
    stored = {"t_star": 8.0, "threads": 1, "models": {"adami": {"model": "adami", "status": "completed"}}}
    path = tmp_path / "results_H7.json"
    path.write_text(json.dumps(stored))
    with pytest.raises(SystemExit) as exc:
        sweep.main(["--resolution", "7", "--t-star", "5.5", "--models", "adami", "--out", str(tmp_path / "runs")])
    assert exc.value.code == 2
    assert "t* = 8.0" in capsys.readouterr().err
    assert json.loads(path.read_text()) == stored
    assert not (tmp_path / "runs").exists()
