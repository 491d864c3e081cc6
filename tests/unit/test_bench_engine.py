"""benchmarks/bench_engine.py without running a benchmark: its arguments and the versus-commit block it writes."""

import os

from seawall.validation import ROOT, load_script

bench_engine = load_script(os.path.join(ROOT, "benchmarks", "bench_engine.py"))


def test_versus_commit_is_a_part_with_its_reference_and_steps():
    args = bench_engine.build_parser().parse_args(["--only", "versus-commit", "--reference", "abc1234",
                                                    "--steps-3d", "7", "--rounds", "2"])
    assert args.only == ["versus-commit"] and args.reference == "abc1234" and args.steps_3d == 7
    assert bench_engine.command_line(args) == "--only versus-commit --rounds 2 --steps-3d 7"
    defaults = bench_engine.build_parser().parse_args([])
    assert defaults.reference == "f56cb9a" and defaults.only is None
    assert bench_engine.command_line(defaults) == "--rounds 3 --steps-3d 60"
    assert "versus-commit" in bench_engine.PARTS
    flow = bench_engine.build_parser().parse_args(["--only", "versus-commit", "--flow-3d", "0.3"])
    assert flow.flow_3d == 0.3 and defaults.flow_3d == 0.0
    assert bench_engine.command_line(flow) == "--only versus-commit --rounds 3 --steps-3d 60 --flow-3d 0.3"


def test_versus_commit_block_gives_the_median_speedup_and_every_round(tmp_path, monkeypatch):
    args = bench_engine.build_parser().parse_args(["--steps-3d", "30"])
    rounds = [{"ms_this": 50.0, "ms_reference": 80.0, "n_this": 103041, "n_reference": 103041, "load": 2.0},
              {"ms_this": 60.0, "ms_reference": 72.0, "n_this": 103041, "n_reference": 103041, "load": 3.0},
              {"ms_this": 40.0, "ms_reference": 60.0, "n_this": 103041, "n_reference": 103041, "load": 4.0}]
    for r in rounds:
        r["speedup"] = r["ms_reference"] / r["ms_this"]
        r["cpu_this"], r["cpu_reference"] = 2 * r["ms_this"], 3 * r["ms_reference"]
        r["cpu_speedup"] = r["cpu_reference"] / r["cpu_this"]
    text = bench_engine.versus_commit_table("HEAD LINE", {"reference": "f56cb9a", "rounds": rounds}, args)
    assert text.startswith("HEAD LINE\n")
    # medians: reference 72.0, this 50.0, speed-up median of 1.60, 1.20, 1.50 = 1.50
    assert ("| 103,041 (reference: 103,041) | 72.0 | 50.0 | **1.50** | 1.60, 1.20, 1.50 | 216.0 / 100.0 | **2.25** | "
            "2.40, 1.80, 2.25 |") in text
    assert "30 timed steps per run" in text
    doc = tmp_path / "performance.md"
    doc.write_text("prose\n<!-- bench_engine:versus-commit:begin -->\nold\n<!-- bench_engine:versus-commit:end -->\nmore\n")
    monkeypatch.setattr(bench_engine, "DOC", str(doc))
    bench_engine.write_doc({"versus-commit": text})
    written = doc.read_text()
    assert written.startswith("prose\n<!-- bench_engine:versus-commit:begin -->\nHEAD LINE\n")
    assert "old" not in written and written.endswith("<!-- bench_engine:versus-commit:end -->\nmore\n")
