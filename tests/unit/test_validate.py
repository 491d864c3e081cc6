"""``seawall validate``: one folder per validated case (validation/<case>/), its stored results, the markdown.

No simulation runs here: the entry of the end-to-end test is a stand-in written to a temporary folder.
"""

import json
import os
import sys
import textwrap

import pytest

import seawall.validation as validation
from seawall.cli import main
from seawall.validation import ROOT, all_entries, case_folders, load_results


def test_every_case_folder_has_entries_with_their_stored_result_and_figures():
    folders = case_folders()
    registry = all_entries()
    assert set(folders) >= {"hydrostatic", "collapse", "dam-break", "poiseuille", "couette", "solitary-runup",
                            "taylor-green", "elliptical-drop", "cavity"}
    assert {os.path.basename(e.folder) for e in registry.values()} == set(folders)
    stored = load_results(None, registry)
    assert set(stored) <= set(registry)
    doc = open(os.path.join(ROOT, "docs", "validation.md")).read()
    for name in set(registry) - set(stored):
        # an entry not run yet (a long one) says so in the summary table, never a number
        assert f"| {name} | | | | | | | | not run |" in doc, name
    for name, entry in registry.items():
        if name not in stored:
            continue
        assert os.path.isfile(os.path.join(entry.folder, "results", f"{name}.json"))
        for plot in stored[name]["plots"]:
            # figures live in the entry's own folder and exist
            assert plot.startswith(f"validation/{os.path.basename(entry.folder)}/img/"), plot
            assert os.path.isfile(os.path.join(ROOT, plot)), plot


def test_doc_only_rebuilds_the_committed_markdown_from_the_stored_results(tmp_path, capsys):
    doc = tmp_path / "validation.md"
    assert main(["validate", "--doc-only", "--doc", str(doc)]) == 0
    committed = open(os.path.join(ROOT, "docs", "validation.md")).read()
    # the only difference is where the figures are seen from
    rel = os.path.relpath(os.path.join(ROOT, "validation"), tmp_path)
    assert doc.read_text() == committed.replace("](../validation/", f"]({rel}/")
    assert main(["validate", "--doc-only", "hydrostatic", "--doc", str(doc)]) == 2
    assert "--doc-only" in capsys.readouterr().err


def test_without_the_validation_folder_validate_stops_with_one_line(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(validation, "VALIDATION_DIR", str(tmp_path / "validation"))
    assert main(["validate", "--list"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "validation folder is not there" in err


def test_old_module_names_still_import():
    import seawall.plots_idbc
    import seawall.validation.entries.dam_break as dam_break
    from seawall.validation.entries import solitary_runup

    assert dam_break.ENTRIES[0] is all_entries()["dam-break"]
    assert os.path.dirname(solitary_runup.__file__) == os.path.join(ROOT, "validation", "solitary-runup")
    assert callable(seawall.plots_idbc.main) and callable(seawall.plots_idbc.sweep)


STAND_IN = '''
from seawall.validation import Entry, row


def run(ctx):
    path = ctx.plot_path("stand_in")
    open(path, "wb").close()
    return {"rows": [row("none", "two", "arithmetic", 2.0, 1.0 + 1.0, tolerance=0.0)], "settings": "none"}


ENTRY = Entry(name="stand-in", title="A stand-in entry", run=run, expected_s=1.0)
'''


def test_a_new_folder_is_discovered_and_keeps_its_result_and_figure(tmp_path, monkeypatch, capsys):
    case = tmp_path / "validation" / "stand-in"
    case.mkdir(parents=True)
    (case / "entry.py").write_text(textwrap.dedent(STAND_IN))
    (tmp_path / "validation" / "no-entry").mkdir()          # a folder without entry.py is not a case
    monkeypatch.setattr(validation, "VALIDATION_DIR", str(tmp_path / "validation"))
    monkeypatch.delitem(sys.modules, "seawall.validation.entries.stand_in", raising=False)
    try:
        assert list(case_folders()) == ["stand-in"]
        doc = tmp_path / "docs" / "validation.md"
        assert main(["validate", "--doc", str(doc)]) == 0
        stored = json.loads((case / "results" / "stand-in.json").read_text())
        assert stored["rows"][0]["pass"] and stored["command"] == "seawall validate stand-in"
        assert (case / "img" / "validation_stand_in.png").exists()
        assert "![stand-in](../validation/stand-in/img/validation_stand_in.png)" in doc.read_text()
    finally:
        sys.modules.pop("seawall.validation.entries.stand_in", None)
        vars(sys.modules["seawall.validation.entries"]).pop("stand_in", None)


def test_replace_block_keeps_the_prose_and_refuses_a_file_without_markers(tmp_path):
    doc = tmp_path / "notes.md"
    doc.write_text("intro\n<!-- t:begin -->\nold\n<!-- t:end -->\noutro\n")
    validation.replace_block(str(doc), "<!-- t:begin -->", "<!-- t:end -->", "new | table")
    assert doc.read_text() == "intro\n<!-- t:begin -->\nnew | table\n<!-- t:end -->\noutro\n"
    with pytest.raises(SystemExit, match="lacks the markers"):
        validation.replace_block(str(doc), "<!-- u:begin -->", "<!-- u:end -->", "x")
    validation.replace_block(str(doc), "<!-- u:begin -->", "<!-- u:end -->", "x", append=True)
    assert doc.read_text().endswith("outro\n\n<!-- u:begin -->\nx\n<!-- u:end -->\n")


def test_an_entry_gets_the_results_directory_for_the_files_it_keeps(tmp_path):
    # `seawall validate --results DIR`: what an entry keeps beside its JSON (a series for figures) goes to DIR,
    # not into the checkout's validation/<case>/results
    seen = []

    def run(ctx):
        seen.append(ctx.results_dir)
        open(ctx.result_path("series.csv"), "w").close()
        return {"rows": [], "settings": "none"}

    entry = validation.Entry(name="kept-files", title="", run=run, expected_s=1.0)
    out = tmp_path / "results"
    validation.run_entry(entry, quick=True, results=str(out), img_dir=str(tmp_path / "img"))
    assert seen == [str(out)] and (out / "kept-files.json").exists() and (out / "series.csv").exists()


def test_load_script_imports_a_study_script_once_by_its_path(tmp_path):
    folder = tmp_path / "validation" / "some-case"
    folder.mkdir(parents=True)
    script = folder / "study.py"
    script.write_text("LOADS = []\nLOADS.append(1)\n")
    first = validation.load_script(str(script))
    assert validation.load_script(str(script)) is first and first.LOADS == [1]
    # the same name from another checkout is that checkout's file, not the one held
    other = tmp_path / "other" / "validation" / "some-case"
    other.mkdir(parents=True)
    (other / "study.py").write_text("LOADS = [2]\n")
    assert validation.load_script(str(other / "study.py")).LOADS == [2]
    with pytest.raises(validation.ParameterError, match="no script at"):
        validation.load_script(str(folder / "missing.py"))
