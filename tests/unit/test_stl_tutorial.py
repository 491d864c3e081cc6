"""docs/tutorials/stl-geometry.md stays true: its commands and code run, in order, in a copy of
docs/tutorials/stl_pillar/, and what it says they print is what they print."""

import os
import re
import shlex
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "tutorials" / "stl-geometry.md"
FOLDER = ROOT / "docs" / "tutorials" / "stl_pillar"


def _blocks():
    """(language, text) of every fenced block of the tutorial, in order."""
    return re.findall(r"```(\w*)\n(.*?)```", DOC.read_text(), flags=re.S)


def _seawall(line, cwd):
    args = shlex.split(line)
    assert args[0] == "seawall"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "seawall", *args[1:]], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)


def test_the_tutorial_runs_as_written(tmp_path, monkeypatch):
    work = tmp_path / "stl_pillar"
    shutil.copytree(FOLDER, work)
    blocks = _blocks()
    ran = {"bash": 0, "python": 0}
    monkeypatch.chdir(work)
    for k, (lang, text) in enumerate(blocks):
        if lang == "bash":
            outputs = []
            for line in text.strip().splitlines():
                done = _seawall(line, work)
                assert done.returncode == 0, f"{line}: {done.stderr}"
                outputs.append(done.stdout.strip())
            # a plain block right after says what the commands print
            if k + 1 < len(blocks) and blocks[k + 1][0] == "":
                assert "\n".join(outputs) == blocks[k + 1][1].strip()
            ran["bash"] += 1
        elif lang == "python":
            exec(compile(text, f"{DOC.name} block {k}", "exec"), {"__name__": "tutorial"})
            ran["python"] += 1
    assert ran == {"bash": 2, "python": 2}
    # the meshes the first python block wrote are those committed beside the case
    from seawall.meshes import load_mesh

    for name in ("tank.stl", "pillar.stl", "column.stl"):
        mine, committed = load_mesh(work / name), load_mesh(FOLDER / name)
        assert np.array_equal(mine.vertices, committed.vertices) and np.array_equal(mine.faces, committed.faces)
    summary = (work / "run-dbc" / "summary.json").read_text()
    assert '"boundary": "dbc"' in summary


def test_the_toml_shown_is_the_case_file():
    shown = tomllib.loads(next(text for lang, text in _blocks() if lang == "toml"))
    case = tomllib.loads((FOLDER / "pillar.toml").read_text())
    for table, value in shown.items():
        if isinstance(value, list):                 # [[wall]], [[water]], [[probe]]: the shown ones are there
            for item in value:
                assert any(item.items() <= full.items() for full in case[table]), (table, item)
        else:
            assert value.items() <= case[table].items(), table


def test_make_stl_writes_the_committed_files(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    script = tmp_path / "make_stl.py"
    shutil.copy(FOLDER / "make_stl.py", script)
    subprocess.run([sys.executable, str(script)], check=True, env=env, capture_output=True)
    for name in ("tank.stl", "pillar.stl", "column.stl"):
        assert (tmp_path / name).read_bytes() == (FOLDER / name).read_bytes()
        assert (FOLDER / name).stat().st_size < 4096       # small files


@pytest.mark.parametrize("problem, message", [
    ("inverted", "pillar.stl: inverted normals"),
    ("open", "column.stl: not watertight"),
    ("missing", "pillar.stl: no such file"),
    ("overlap", "the fluid fill overlaps wall pillar"),
    ("covered", "pillar.stl: 2 faces of wall pillar are covered by wall tank"),
])
def test_case_file_errors_name_the_mesh(tmp_path, problem, message):
    from seawall import meshes
    from seawall.cases import build
    from seawall.errors import ParameterError

    work = tmp_path / "case"
    shutil.copytree(FOLDER, work)
    if problem == "inverted":
        meshes.write_stl(work / "pillar.stl", meshes.box_mesh([0.5, 0.15, 0.0], [0.6, 0.25, 0.5], inward=True,
                                                              open_bottom=True))
    elif problem == "open":
        meshes.write_stl(work / "column.stl", meshes.box_mesh([0.0, 0.0, 0.0], [0.3, 0.4, 0.3], open_top=True))
    elif problem == "covered":      # a closed pillar: its foot stands on the floor
        meshes.write_stl(work / "pillar.stl", meshes.box_mesh([0.5, 0.15, 0.0], [0.6, 0.25, 0.5]))
    elif problem == "missing":
        (work / "pillar.stl").unlink()
    else:
        meshes.write_stl(work / "column.stl", meshes.box_mesh([0.0, 0.0, 0.0], [0.55, 0.4, 0.3]))
    with pytest.raises(ParameterError, match=re.escape(message)) as err:
        build(str(work / "pillar.toml"), dx=0.05, boundary="dbc")
    assert "\n" not in str(err.value)
