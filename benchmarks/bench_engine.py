"""Speed of the core engine against a plain compiled WCSPH step, measured side by side.

The yardstick is the plain step of issue 19 (``plain_step.py``: cell list, continuity,
momentum, Tait, artificial viscosity; no walls, no delta-SPH), run in the same session
as seawall and interleaved with it, because the project's machines are shared and
their speed drifts by 2x within minutes: only ratios measured side by side mean
anything. Every configuration runs in a fresh process (``seawall bench``), so the
thread count is set before Numba starts; compilation is excluded from the timing.

    python benchmarks/bench_engine.py                       # every part (side by side, models, start-up, versus-commit)
    python benchmarks/bench_engine.py --only side-by-side --rounds 3
    python benchmarks/bench_engine.py --write-doc           # also rewrite docs/performance.md's tables
    python benchmarks/bench_engine.py --only versus-commit --reference f56cb9a

Parts:

* ``side-by-side``: per round, the plain step (100k and 400k particles) then seawall's 2D dam
  break with Adami walls and delta-SPH (80k and 320k), 2 threads; the ratio of particle-steps
  per second within each round, median over the rounds (targets of issue 19: >= 1.0 at 80k
  and 320k; time per step 80k -> 320k at most 4.2x). The plain step runs with the same
  ``OMP_WAIT_POLICY=PASSIVE`` seawall sets on import (without it, on a loaded machine its
  spinning threads lose 2-5x and the ratio flatters seawall).
* ``models``: every registered wall model on the same dam break, 1 thread, CPU time per step
  (steadier than wall time under load) over ``adami``'s measured in the same round; median
  over the rounds (target: at most 1.25).
* ``startup``: the default ``seawall bench dam-break`` with an empty Numba cache (a fresh
  ``NUMBA_CACHE_DIR``) and again with the cache it filled: seconds to compile and take the
  first two steps (target 3 of issue 19 for compilation: at most 15 s).
* ``versus-commit``: the 3D dam break of issue 2's table (dx = 0.01 m: 27,000 fluid + 76,041
  wall particles, open tank) with 2 threads, in this tree and in an older commit (``--reference``,
  default f56cb9a, issue 19's baseline) checked out into a temporary git worktree that is
  removed afterwards; the same driver (``DRIVER``, run by ``python -c`` in each tree) times the
  steps by wall clock and by the CPU time of the process. One untimed run in each tree first (it
  compiles and fills that tree's Numba cache), then per round both trees one after the other, the
  order alternating between rounds; the speed-up is the reference's time per step over this
  tree's within a round, median over the rounds (target 2 of issue 19: at least 1.4).
  ``--flow-3d T`` first runs T seconds of the flow untimed in every run (from rest the fluid's
  pair list is hardly ever rebuilt; once the fluid moves, every few steps), and writes its own
  block (``versus-commit-flow``).

The machine (CPU, cores, load), the commit and Numba's version are printed and written
with the tables.
"""

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# the in-process parts (the model list, the doc's blocks) import this checkout's package, installed or not:
# run as a script, only benchmarks/ would be on the path
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)
# dx of the 2D dam break (H = 0.3 m) for about 80k and 320k fluid particles
SIZES = {"80k": 0.0015, "320k": 0.00075}
# the plain step's sizes compared with them
PLAIN = {"80k": 100000, "320k": 400000}
DOC = os.path.join(ROOT, "docs", "performance.md")
# the 3D dam break of issue 2's table: 27,000 fluid + 76,041 wall particles (103,041)
DX_3D = 0.01
# older trees close no lid over the tank; this tree's tank does by default
SETS_3D = ["lid=false"]
REFERENCE = "f56cb9a"


def seawall_bench(case, dx=None, threads=2, steps=60, boundary=None, env=None, root=ROOT, sets=()):
    cmd = [sys.executable, "-m", "seawall", "bench", case, "--steps", str(steps), "--threads", str(threads)]
    if dx is not None:
        cmd += ["--dx", str(dx)]
    if boundary:
        cmd += ["--boundary", boundary]
    for item in sets:
        cmd += ["--set", item]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, cwd=root, env=env)
    return json.loads(out.stdout.strip().splitlines()[-1])



def plain_step(path, n, threads=2):
    env = dict(os.environ, NUMBA_NUM_THREADS=str(threads), OMP_WAIT_POLICY="PASSIVE")
    out = subprocess.run([sys.executable, path, str(n), "f64", "20"], capture_output=True, text=True, check=True,
                         env=env)
    return json.loads(out.stdout.strip().splitlines()[-1])


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                cwd=ROOT).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], capture_output=True,
                               text=True, cwd=ROOT).stdout.strip()
        commit += "+changes" if dirty else ""
    except OSError:
        commit = "unknown"
    import numba

    return {"cpu": cpu, "cores": os.cpu_count(), "load": os.getloadavg()[0], "commit": commit,
            "numba": numba.__version__, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}


def side_by_side(args):
    rows = {label: [] for label in SIZES}
    for r in range(args.rounds):
        for label, dx in SIZES.items():
            plain = plain_step(args.plain, PLAIN[label])
            sw = seawall_bench("dam-break", dx, 2, args.steps if label == "80k" else max(20, args.steps // 4))
            rec = {"plain_psps": plain["psps"], "seawall_psps": sw["particle_steps_per_s"],
                   "ms_per_step": sw["seconds"] / sw["steps"] * 1e3, "n": sw["n_particles"]}
            rec["ratio"] = rec["seawall_psps"] / rec["plain_psps"]
            rows[label].append(rec)
            print(f"round {r + 1} {label}: plain {plain['psps'] / 1e6:.2f} M, seawall {rec['seawall_psps'] / 1e6:.2f} M "
                  f"({rec['ms_per_step']:.1f} ms/step), ratio {rec['ratio']:.2f}", flush=True)
    return rows


def models(args):
    from seawall.boundary.registry import BOUNDARIES

    names = [m for m in BOUNDARIES if m != "adami"]
    cpu = {m: [] for m in ["adami", *names]}
    ratio = {m: [] for m in names}
    for r in range(args.rounds):
        for m in names:
            base = seawall_bench("dam-break", args.model_dx, 1, args.model_steps, "adami")
            rec = seawall_bench("dam-break", args.model_dx, 1, args.model_steps, m)
            a = base["cpu_seconds"] / base["steps"]
            b = rec["cpu_seconds"] / rec["steps"]
            cpu["adami"].append(a)
            cpu[m].append(b)
            ratio[m].append(b / a)
            print(f"round {r + 1} {m}: {b * 1e3:.1f} ms CPU/step, adami {a * 1e3:.1f}, ratio {b / a:.2f}", flush=True)
    return cpu, ratio


def startup(args):
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        cold = seawall_bench("dam-break", threads=2, steps=5, env=env)["compile_seconds"]
        warm = seawall_bench("dam-break", threads=2, steps=5, env=env)["compile_seconds"]
    print(f"start-up (compile + 2 steps of the default dam break): cold {cold:.1f} s, warm {warm:.2f} s", flush=True)
    return cold, warm


def imported_from(root):
    """The directory the package ``seawall`` is imported from when ``python -m`` runs in ``root``."""
    out = subprocess.run([sys.executable, "-c", "import seawall, os; print(os.path.dirname(seawall.__file__))"],
                         capture_output=True, text=True, check=True, cwd=root)
    return os.path.realpath(out.stdout.strip())


# Run in each tree by `python -c` (its own package first on the path): the same build and timing
# code for both, so that the older tree's `seawall bench` (which reported no CPU time) does not matter.
DRIVER = """
import json, sys, time
from seawall.cases import case_by_name
dx, steps, sets, flow = float(sys.argv[1]), int(sys.argv[2]), json.loads(sys.argv[3]), float(sys.argv[4])
sim = case_by_name("dam-break-3d").build(boundary="adami", threads=2, dx=dx, **sets)
if flow > 0:
    sim.run(flow, progress=False)
sim.run_steps(2)
w0, c0 = time.perf_counter(), time.process_time()
sim.run_steps(steps)
w, c = time.perf_counter() - w0, time.process_time() - c0
n = sim.fluid.n + sum(w.n for w in sim.walls)
print(json.dumps({"n_particles": n, "steps": steps, "seconds": w, "cpu_seconds": c}))
"""


def drive_3d(root, steps, sets, env, flow=0.0):
    """The 3D dam break in the tree ``root``: time and CPU time (all threads) of ``steps`` steps after two,
    from rest or after ``flow`` seconds of the flow."""
    out = subprocess.run([sys.executable, "-c", DRIVER, str(DX_3D), str(steps), json.dumps(sets), str(flow)],
                         capture_output=True, text=True, check=True, cwd=root, env=env)
    return json.loads(out.stdout.strip().splitlines()[-1])


def versus_commit(args):
    """This tree against ``args.reference`` on the 3D dam break, 2 threads, interleaved rounds."""
    tmp = tempfile.mkdtemp(prefix="seawall-reference-")
    tree = os.path.join(tmp, "tree")
    subprocess.run(["git", "worktree", "add", "--detach", tree, args.reference], cwd=ROOT, check=True,
                   capture_output=True, text=True)
    try:
        # `python -c` must import each tree's own package, not the installed one
        for root in (ROOT, tree):
            where = imported_from(root)
            if where != os.path.realpath(os.path.join(root, "seawall")):
                raise SystemExit(f"python -c in {root} imports seawall from {where}")
        env = dict(os.environ, NUMBA_NUM_THREADS="2", OMP_WAIT_POLICY="PASSIVE")
        sets = dict(item.split("=", 1) for item in SETS_3D)
        sets = {key: value.lower() == "true" if value.lower() in ("true", "false") else value
                for key, value in sets.items()}
        runs = {"this": lambda: drive_3d(ROOT, args.steps_3d, sets, env, args.flow_3d),
                "reference": lambda: drive_3d(tree, args.steps_3d, {}, env, args.flow_3d)}
        for name, run in runs.items():   # compiles; fills each tree's Numba cache
            t0 = time.perf_counter()
            rec = run()
            print(f"warm-up {name}: {time.perf_counter() - t0:.0f} s with compilation, {rec['n_particles']:,} particles",
                  flush=True)
        rounds = []
        for r in range(args.rounds):
            order = ("reference", "this") if r % 2 == 0 else ("this", "reference")
            rec = {name: runs[name]() for name in order}
            ms = {name: rec[name]["seconds"] / rec[name]["steps"] * 1e3 for name in rec}
            cpu = {name: rec[name]["cpu_seconds"] / rec[name]["steps"] * 1e3 for name in rec}
            row = {"ms_this": ms["this"], "ms_reference": ms["reference"], "speedup": ms["reference"] / ms["this"],
                   "cpu_this": cpu["this"], "cpu_reference": cpu["reference"],
                   "cpu_speedup": cpu["reference"] / cpu["this"],
                   "n_this": rec["this"]["n_particles"], "n_reference": rec["reference"]["n_particles"],
                   "load": os.getloadavg()[0]}
            rounds.append(row)
            print(f"round {r + 1}: reference {ms['reference']:.1f} ms/step ({cpu['reference']:.1f} CPU), this "
                  f"{ms['this']:.1f} ms/step ({cpu['this']:.1f} CPU), speed-up {row['speedup']:.2f} "
                  f"(CPU {row['cpu_speedup']:.2f}; load {row['load']:.1f})", flush=True)
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", tree], cwd=ROOT, capture_output=True)
        subprocess.run(["git", "worktree", "prune"], cwd=ROOT, capture_output=True)
        shutil.rmtree(tmp, ignore_errors=True)
    return {"reference": args.reference, "rounds": rounds}


def versus_commit_table(head, vs, args):
    """The ``versus-commit`` block: time and CPU time per step in both trees, the speed-ups per round."""
    med = statistics.median
    rs = vs["rounds"]
    loads = [r["load"] for r in rs]
    return "\n".join([
        head, "",
        f"| 3D dam break, dx = {DX_3D} m, Adami, 2 threads, {args.steps_3d} timed steps per run"
        f"{f' after {args.flow_3d:g} s of the flow' if args.flow_3d else ''} | particles | "
        f"{vs['reference']} ms/step | this tree ms/step | speed-up (median of rounds) | per round | "
        f"CPU ms/step {vs['reference']} / this tree | CPU speed-up (median) | per round |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        f"| wall time and CPU time of the process | {rs[0]['n_this']:,} (reference: {rs[0]['n_reference']:,}) | "
        f"{med(r['ms_reference'] for r in rs):.1f} | {med(r['ms_this'] for r in rs):.1f} | "
        f"**{med(r['speedup'] for r in rs):.2f}** | " + ", ".join(f"{r['speedup']:.2f}" for r in rs) + " | "
        f"{med(r['cpu_reference'] for r in rs):.1f} / {med(r['cpu_this'] for r in rs):.1f} | "
        f"**{med(r['cpu_speedup'] for r in rs):.2f}** | " + ", ".join(f"{r['cpu_speedup']:.2f}" for r in rs) + " |",
        "", f"Load average after each round: {', '.join(f'{x:.1f}' for x in loads)} "
        "(target 2 of issue 19: at least 1.4x in time per step)."])


def command_line(args):
    """The options a measurement was made with, as they would be typed (parts, rounds, steps)."""
    words = [f"--only {part}" for part in args.only or ()] + [f"--rounds {args.rounds}"]
    if not args.only or "versus-commit" in args.only:
        words.append(f"--steps-3d {args.steps_3d}")
        if args.flow_3d:
            words.append(f"--flow-3d {args.flow_3d:g}")
    return " ".join(words)


def tables(info, sbs, mods, start, args, vs=None):
    """Markdown per part measured: {part: text}, each headed by the machine line."""
    med = statistics.median
    head = (f"Measured {info['date']} on {info['cpu']} ({info['cores']} cores, shared: load average "
            f"{info['load']:.1f} at the start), commit {info['commit']}, Numba {info['numba']}; "
            f"`python benchmarks/bench_engine.py {command_line(args)}`.")
    parts = {}
    if sbs:
        lines = [head, "", "| dam break, Adami + delta-SPH, 2 threads | particles | plain step M p-steps/s | "
                 "seawall M p-steps/s | seawall ms/step | ratio (median of rounds) | ratios per round |",
                 "| --- | --- | --- | --- | --- | --- | --- |"]
        for label, recs in sbs.items():
            lines.append(f"| {label} | {recs[0]['n']:,} (plain: {PLAIN[label]:,}) | "
                         f"{med(r['plain_psps'] for r in recs) / 1e6:.2f} | {med(r['seawall_psps'] for r in recs) / 1e6:.2f} | "
                         f"{med(r['ms_per_step'] for r in recs):.1f} | **{med(r['ratio'] for r in recs):.2f}** | "
                         + ", ".join(f"{r['ratio']:.2f}" for r in recs) + " |")
        if "80k" in sbs and "320k" in sbs:
            g = med(b["ms_per_step"] / a["ms_per_step"] for a, b in zip(sbs["80k"], sbs["320k"]))
            n = sbs["320k"][0]["n"] / sbs["80k"][0]["n"]
            lines += ["", f"Time per step from 80k to 320k: {g:.2f}x for {n:.2f}x the particles (limit 4.2x)."]
        parts["side-by-side"] = "\n".join(lines)
    if mods:
        cpu, ratio = mods
        lines = [head, "", f"Wall models on the same dam break (dx = {args.model_dx} m), 1 thread, CPU time per step "
                 f"(median of {args.rounds} rounds, each model interleaved with `adami`):", "",
                 "| model | ms CPU / step | x adami (median) | per round |", "| --- | --- | --- | --- |",
                 f"| adami | {med(cpu['adami']) * 1e3:.1f} | 1.00 | |"]
        for m, rs in ratio.items():
            lines.append(f"| {m} | {med(cpu[m]) * 1e3:.1f} | {'**' if med(rs) > 1.25 else ''}{med(rs):.2f}"
                         f"{'**' if med(rs) > 1.25 else ''} | " + ", ".join(f"{x:.2f}" for x in rs) + " |")
        parts["models"] = "\n".join(lines)
    if start:
        parts["startup"] = "\n".join([head, "", "Start-up of `seawall bench dam-break` (default resolution; compile + "
                                      f"first two steps): {start[0]:.1f} s from an empty Numba cache, {start[1]:.2f} s "
                                      "with the cache filled."])
    if vs:
        # from rest and after some flow are two blocks of the doc
        parts["versus-commit-flow" if args.flow_3d else "versus-commit"] = versus_commit_table(head, vs, args)
    return parts


def write_doc(parts):
    """Replace each measured part's block in docs/performance.md (appended if missing); others stay."""
    from seawall.validation import replace_block

    for part, text in parts.items():
        replace_block(DOC, f"<!-- bench_engine:{part}:begin -->", f"<!-- bench_engine:{part}:end -->", text,
                      append=True)


PARTS = ("side-by-side", "models", "startup", "versus-commit")


def build_parser():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=100, help="timed steps at 80k (a quarter of them at 320k)")
    parser.add_argument("--only", choices=PARTS, action="append")
    parser.add_argument("--plain", default=os.path.join(ROOT, "..", "shared", "bench", "plain_step.py"),
                        help="the plain step of issue 19 (default ../shared/bench/plain_step.py beside the checkout)")
    parser.add_argument("--model-dx", type=float, default=0.0015)
    parser.add_argument("--model-steps", type=int, default=40)
    parser.add_argument("--reference", default=REFERENCE, help="the older commit of the versus-commit part")
    parser.add_argument("--steps-3d", type=int, default=60, help="timed steps of each 3D dam break run")
    parser.add_argument("--flow-3d", type=float, default=0.0,
                        help="seconds of the 3D dam break's flow run untimed before the timed steps (default 0: "
                             "from rest; the fluid's pair list is rebuilt more often once the fluid moves)")
    parser.add_argument("--write-doc", action="store_true", help="rewrite the tables in docs/performance.md")
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    parts = args.only or list(PARTS)
    info = machine()
    print(json.dumps(info), flush=True)
    sbs = side_by_side(args) if "side-by-side" in parts else None
    mods = models(args) if "models" in parts else None
    start = startup(args) if "startup" in parts else None
    vs = versus_commit(args) if "versus-commit" in parts else None
    parts = tables(info, sbs, mods, start, args, vs)
    print("\n\n".join(parts.values()))
    if args.write_doc:
        write_doc(parts)


if __name__ == "__main__":
    main()
