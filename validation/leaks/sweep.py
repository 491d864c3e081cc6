"""Leak sweep: the 2D dam break with every closed-tank wall model, to t sqrt(g/H) = 8.

    python validation/leaks/sweep.py                          # H/50, every model, 1 thread
    python validation/leaks/sweep.py --resolution 100 --models liu2012,ghost-sfdi
    python validation/leaks/sweep.py --report-only            # rewrite the tables from stored results

Runs the ``dam-break`` case (H = 0.3 m, the experiments' tank closed by its lid at
2 H) at dx = H/N for each wall model, one model after the other, each in a fresh
process (a model that crashes the interpreter cannot stop the sweep), with the
``min_wall_distance_dx`` probe of ``seawall compare`` (``seawall.compare.MinWallDistance``)
sampled at the case's probe interval. Per model it records:

* ``status`` -- ``completed`` or ``unstable``, with ``t_stop`` (the time reached)
  and ``error`` (why it stopped);
* ``escaped`` and ``escaped_domain`` / ``escaped_wall`` / ``escaped_unstable``
  (the removal guards of ``seawall.health``);
* ``min_wall_distance_dx`` -- smallest signed fluid-to-wall distance over the
  run in particle spacings (negative: behind the wall surface), and the time
  ``t_min_wall_distance`` at which it was sampled;
* ``wall_time_s`` -- time stepping only, without start-up and compilation;
  ``steps``;
* ``plateau`` -- the plateau profile on the downstream wall (issue 15, item 7): the probes of
  ``validation/dam-break/plateau_profiles.py`` are added to every run and their means over
  3 <= t sqrt(g/H) <= 5.5 kept here (that script tabulates them; the run directory also gets
  ``plateau_snapshots.npz``, the particles at t sqrt(g/H) = 3.5, 4, 4.5, 5).

Results are kept per resolution in ``validation/leaks/results_H<N>.json`` (a run of a
subset of models replaces only those models' entries) and ``.csv``; the markdown
table goes into docs/boundaries.md between the markers
``<!-- leaks-table:begin -->`` and ``<!-- leaks-table:end -->`` (one table per
stored resolution), written again from the stored results by ``--report-only``.
Run directories (probes.csv, summary.json) go to ``--out``
(default ``validation/leaks/runs``, not kept in git).
"""

import argparse
import csv
import json
import math
import multiprocessing
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DOC = os.path.join(ROOT, "docs", "boundaries.md")
BEGIN = "<!-- leaks-table:begin -->"
END = "<!-- leaks-table:end -->"
H = 0.3
G = 9.81
CASE = "dam-break"
#: the wall models meant for a closed tank: every registered model (each holds fluid in a tank)
FIELDS = ["key", "model", "status", "t_stop", "t_end", "error", "escaped", "escaped_domain", "escaped_wall",
          "escaped_unstable", "first_escape", "min_wall_distance_dx", "t_min_wall_distance", "reflections", "n_fluid",
          "steps", "wall_time_s", "params"]


def closed_tank_models():
    from seawall.boundary.registry import BOUNDARIES

    return list(BOUNDARIES)


def _worker(model, dx, t_end, params, out, threads, queue):
    """Run one model (in a fresh process) and put its record on ``queue``."""
    try:
        sys.path.insert(0, ROOT)
        import numpy as np

        from seawall.cases import case_by_name
        from seawall.compare import MinWallDistance
        from seawall.diagnostics import escaped_by_reason
        from seawall.errors import InstabilityError

        case = case_by_name(CASE)
        sim = case.build(boundary=model, threads=threads, dx=dx, **params)
        sim.add(MinWallDistance(), every=case.probe_every)
        run_dir = os.path.join(out, _key(model, params).replace(" ", "_"))
        os.makedirs(run_dir, exist_ok=True)
        plateau = _plateau_module()
        plateau.add_probes(sim, H, dx, snapshots=os.path.join(run_dir, "plateau_snapshots.npz"))
        started = time.perf_counter()
        error = ""
        try:
            result = sim.run(t_end, progress=False, probe_csv=os.path.join(run_dir, "probes.csv"))
            summary = result.summary
            status = "completed"
        except InstabilityError as exc:
            status = "unstable"
            error = str(exc)
            summary = sim.summary(wall_time=time.perf_counter() - started, loop_time=0.0, particle_steps=0,
                                  steps=sim.step, startup=0.0)
        res = sim.result(summary)
        times = np.asarray(res.times, dtype=float)
        dist = np.asarray(res.probes.get("min_wall_distance_dx", np.empty(0)), dtype=float)
        ok = np.isfinite(dist)
        by = escaped_by_reason(sim.escaped, sim.dim)
        first = min(sim.escaped, key=lambda rec: rec[0]) if sim.escaped else None
        reflections = sum(getattr(getattr(w, "model", None), "reflections", 0) for w in sim.walls)
        rec = {
            "model": model, "status": status, "t_stop": float(sim.time), "t_end": t_end, "error": error,
            "escaped": len(sim.escaped), "escaped_domain": by.get("domain", 0), "escaped_wall": by.get("wall", 0),
            "escaped_unstable": by.get("unstable", 0),
            "first_escape": None if first is None else {"t": first[0], "id": first[1],
                                                        "x": list(first[2:2 + sim.dim]), "reason": first[-1]},
            "min_wall_distance_dx": float(dist[ok].min()) if ok.any() else None,
            "t_min_wall_distance": float(times[ok][np.argmin(dist[ok])]) if ok.any() else None,
            "n_fluid": summary.get("n_fluid"), "steps": int(sim.step),
            "wall_time_s": (time.perf_counter() - started) if status != "completed"
            else summary.get("wall_time_s", 0.0) - summary.get("startup_s", 0.0),
            "reflections": int(reflections), "params": params,
            # the plateau profile on the downstream wall (validation/dam-break/plateau_profiles.py)
            "plateau": plateau.plateau_means(times, res.probes, H, rho0=float(sim.fluid.rho0)),
        }
        with open(os.path.join(run_dir, "summary.json"), "w") as fh:
            json.dump(summary, fh, indent=1, default=str)
    except Exception as exc:  # a crash is a result of the sweep, recorded with its reason
        rec = {"model": model, "status": "crashed", "t_stop": None, "t_end": t_end,
               "error": f"{type(exc).__name__}: {exc}", "params": params}
    queue.put(rec)


def _plateau_module():
    """validation/dam-break/plateau_profiles.py."""
    from seawall.validation import load_script

    return load_script(os.path.join(ROOT, "validation", "dam-break", "plateau_profiles.py"))


def _key(model, params):
    """Results are kept per model and options: ``ghost-sfdi`` and ``ghost-sfdi reflect=1`` are two rows."""
    return " ".join([model] + [f"{k}={v}" for k, v in sorted(params.items())])


def run_model(model, dx, t_end, params, out, threads):
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_worker, args=(model, dx, t_end, params, out, threads, queue))
    started = time.perf_counter()
    proc.start()
    rec = None
    while rec is None:
        try:
            rec = queue.get(timeout=5.0)
        except Exception:
            if not proc.is_alive():
                break
    proc.join()
    if rec is None:
        rec = {"model": model, "status": "crashed", "t_stop": None, "t_end": t_end,
               "error": f"worker exited with code {proc.exitcode}", "params": params}
    rec["process_time_s"] = time.perf_counter() - started
    return rec


def results_path(resolution):
    return os.path.join(HERE, f"results_H{resolution}.json")


def read_json(path):
    """A stored results file of the validation scripts, or {} when there is none yet."""
    if not os.path.exists(path):
        return {}
    with open(path) as fh:
        return json.load(fh)


def write_json(path, data):
    """Store a results file as every validation script here does: sorted keys, one space indent."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as fh:
        json.dump(data, fh, indent=1, sort_keys=True)
        fh.write("\n")


def load(resolution):
    return read_json(results_path(resolution))


def save(resolution, data):
    write_json(results_path(resolution), data)
    with open(os.path.join(HERE, f"results_H{resolution}.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(FIELDS)
        for key in _ordered(data["models"]):
            rec = {**data["models"][key], "key": key}
            w.writerow(["" if rec.get(f) is None else (json.dumps(rec[f]) if f in ("params", "first_escape")
                                                       else rec[f]) for f in FIELDS])


def _ordered(keys):
    """Keys in registry order of their model, plain model before its option variants."""
    try:
        order = closed_tank_models()
    except Exception:
        order = []
    rank = {m: k for k, m in enumerate(order)}
    return sorted(keys, key=lambda key: (rank.get(key.split(" ")[0], len(rank)), key))


def _num(value, fmt):
    return "n/a" if value is None or (isinstance(value, float) and not math.isfinite(value)) else format(value, fmt)


def table(resolution, data):
    """The markdown table of one stored resolution."""
    tstar = data.get("t_star")
    lines = [f"**H/{resolution}** (dx = {data['dx']:.4g} m, H = {H} m, to t sqrt(g/H) = {tstar:g} = "
             f"{data['t_end']:.3f} s, {data.get('threads', 1)} thread(s)). Escaped: removed by the guards of "
             "`seawall.health`, by reason; first escape: time, reason and position; distance: smallest signed "
             "fluid-to-wall distance sampled over the run, in dx (negative: behind the wall surface; the wall "
             "guard removes at -2.6 dx); a run stopped by the damage budget of `seawall.health` names the "
             "particle that stopped it under first escape (it is not counted among the escaped); reflections: particles sent back by the opt-in `reflect` safeguard; "
             "wall time: time stepping only (shared machine, indicative).", "",
             "| model | options | completed | escaped: domain / wall / unstable | first escape | "
             "min wall distance [dx] (at t [s]) | reflections | wall time [s] |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for key in _ordered(data["models"]):
        r = data["models"][key]
        if r["status"] == "completed":
            done = "yes"
        elif r["status"] == "unstable":
            done = f"no: unstable at t = {r['t_stop']:.3f} s"
        else:
            done = f"no: {r['status']} ({(r.get('error') or '')[:60]})"
        esc = ("n/a" if r.get("escaped") is None else
               f"{r['escaped_domain']} / {r['escaped_wall']} / {r['escaped_unstable']}")
        fe = r.get("first_escape")
        if not fe and r["status"] == "unstable":
            m = re.search(r"at \[([-0-9.ena]+), ([-0-9.ena]+)\].*?\(([^;)]*)", r.get("error") or "")
            if m:
                fe = {"t": r["t_stop"], "reason": m.group(3).strip(), "x": [float(m.group(1)), float(m.group(2))]}
        if fe:
            first = f"{fe['t']:.3f} s, {fe['reason']}, ({fe['x'][0]:.3f}, {fe['x'][1]:.3f}) m"
        else:
            first = "n/a" if "first_escape" not in r and r.get("escaped") else "-"
        d = r.get("min_wall_distance_dx")
        dist = _num(d, ".1e" if d is not None and abs(d) < 0.005 else ".2f")
        if r.get("t_min_wall_distance") is not None:
            dist += f" ({r['t_min_wall_distance']:.3f})"
        opts = ", ".join(f"{k}={v}" for k, v in sorted((r.get("params") or {}).items())) or "defaults"
        refl = r.get("reflections")
        lines.append(f"| `{r['model']}` | {opts} | {done} | {esc} | {first} | {dist} | "
                     f"{'-' if not refl else refl} | {_num(r.get('wall_time_s'), '.0f')} |")
    return "\n".join(lines)


def write_doc():
    """Replace the text between the markers in docs/boundaries.md by the tables of every stored resolution."""
    blocks = []
    import glob

    stored = sorted(int(os.path.basename(p)[9:-5]) for p in glob.glob(os.path.join(HERE, "results_H*.json")))
    for resolution in stored:
        data = load(resolution)
        if data.get("models"):
            blocks.append(table(resolution, data))
    body = "\n\n".join(blocks) if blocks else "(no stored results)"
    from seawall.validation import replace_block

    replace_block(DOC, BEGIN, END, body)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=50, help="N in dx = H/N: 50 or 100 (default 50; "
                        "other N, e.g. 15 for a quick look, are stored and tabulated the same way)")
    parser.add_argument("--models", default=None, help="comma-separated wall models (default: every closed-tank model)")
    parser.add_argument("--t-star", type=float, default=8.0, help="end time t sqrt(g/H) (default 8)")
    parser.add_argument("--threads", type=int, default=1, help="threads of each run (default 1)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="case or wall option for every model of this sweep (recorded with the result)")
    parser.add_argument("--out", default=os.path.join(HERE, "runs"),
                        help="run directories (default validation/leaks/runs, not kept in git)")
    parser.add_argument("--report-only", action="store_true", help="rewrite the tables from stored results only")
    args = parser.parse_args(argv)
    sys.path.insert(0, ROOT)
    if args.report_only:
        write_doc()
        return 0
    if args.resolution < 5:
        parser.error("--resolution must be at least 5")
    if args.t_star <= 0:
        parser.error("--t-star must be positive")
    if args.threads < 1:
        parser.error("--threads must be at least 1")
    all_models = closed_tank_models()
    models = all_models if args.models is None else [m.strip() for m in args.models.split(",") if m.strip()]
    unknown = [m for m in models if m not in all_models]
    if unknown:
        parser.error(f"unknown wall model {unknown[0]!r}; available: {', '.join(all_models)}")
    from seawall.errors import ParameterError
    from seawall.sweep import parse_set_items

    try:
        params = parse_set_items(args.set)
    except ParameterError as exc:
        parser.error(str(exc))
    dx = H / args.resolution
    t_end = args.t_star * math.sqrt(H / G)
    out = os.path.join(args.out, f"H{args.resolution}")
    data = load(args.resolution)
    if data.get("t_star") not in (None, args.t_star) or data.get("threads") not in (None, args.threads):
        # results of another end time or thread count are not mixed into one table, nor thrown away
        parser.error(f"{os.path.relpath(results_path(args.resolution), ROOT)} holds runs to t* = {data.get('t_star')} "
                     f"with {data.get('threads')} thread(s); this sweep asks --t-star {args.t_star:g} --threads "
                     f"{args.threads}: give those, or run the variant with plateau_diagnostics.py "
                     "(its own results file)")
    data.update({"case": CASE, "H": H, "dx": dx, "t_star": args.t_star, "t_end": t_end, "threads": args.threads})
    data.setdefault("models", {})
    for model in models:
        print(f"[leaks] {model}: dam break dx = {dx:.4g} m to t = {t_end:.4f} s ...", flush=True)
        rec = run_model(model, dx, t_end, params, out, args.threads)
        print(f"[leaks] {model}: {rec['status']} t = {rec.get('t_stop')} escaped = {rec.get('escaped')} "
              f"(wall {rec.get('escaped_wall')}) min distance = {rec.get('min_wall_distance_dx')} dx "
              f"{rec.get('error', '')}", flush=True)
        # read again before saving: another sweep process may have stored its models meanwhile
        fresh = load(args.resolution)
        if fresh.get("t_star") == data["t_star"] and fresh.get("threads") == data["threads"]:
            data["models"] = fresh.get("models", {})
        data["models"][_key(model, params)] = rec
        save(args.resolution, data)
        write_doc()
    return 0


if __name__ == "__main__":
    sys.exit(main())
