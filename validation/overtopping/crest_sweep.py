"""Water over a crest: the open dam break with every wall model that holds the closed tank.

    python validation/overtopping/crest_sweep.py --resolution 30            # every model, two at a time
    python validation/overtopping/crest_sweep.py --resolution 50 --models adami,dbc --jobs 1
    python validation/overtopping/crest_sweep.py --report-only              # tables from the stored results

Runs the ``dam-break`` case (H = 0.3 m, column 2H x H) in its tank opened (``lid=false``) and
lowered to ``tank_height=1.2`` (the crest 0.36 m above the floor, 1.2 H), at dx = H/N to
t sqrt(g/H) = 8, so the run-up jet on the downstream wall goes over its crest. Each model runs at
the setting with which it holds the *closed* tank: the first of its rows in the leak sweep
(``validation/leaks/results_H50.json``; plain model first, then its option variants) that
completed with no particle through a wall (none removed as ``wall`` or ``domain``; the density
guard's removals in the jet, ``unstable``, are allowed there). Each run is a ``seawall run``
process (``--no-vtk``) with a discharge section across the middle of the downstream wall's
crest, from one kernel support below the crest up past the domain's top (``--discharge``,
counted +x every step): what crossed it has left the tank over the wall's back, or stands on the crest's outer
half at the end. Per model it records the status and the
time reached, the removals per reason (``escaped_by_reason``) and their mass
(``escaped_mass_by_reason``), the mass balance (``mass_drift``: (mass now + removed - start) /
start), the overtopped volume per metre from the removals (mass / rho0), split by where they left
(past the downstream wall, ``x+``, or out through the domain's top, ``y+``: the run-up jet climbs
above the case's domain, twice the walls' height, at H/50 and finer), and the volume the
discharge section counted, with its relative difference from the removals past the wall.

What must hold (the crest is flow): every run completes, nothing is removed as ``wall`` or
``unstable`` beyond the stated transient, the mass balance holds to round-off, and the two
overtopped volumes agree.

Results: ``validation/overtopping/results_H<N>.json``; the table goes into docs/overtopping.md
between ``<!-- crest-table:begin -->`` and ``<!-- crest-table:end -->``. Run directories go to
``--out`` (default ``validation/overtopping/runs``, not kept in git).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DOC = os.path.join(ROOT, "docs", "overtopping.md")
BEGIN = "<!-- crest-table:begin -->"
END = "<!-- crest-table:end -->"
LEAKS = os.path.join(ROOT, "validation", "leaks", "results_H50.json")
H = 0.3
G = 9.81
RHO0 = 1000.0
TANK_HEIGHT = 1.2
T_END = 8.0 * math.sqrt(H / G)


def holding_settings():
    """{model: options} -- each registered model at the first closed-tank setting that held (module doc)."""
    with open(LEAKS) as fh:
        rows = json.load(fh)["models"]
    out = {}
    for key in sorted(rows, key=lambda k: (len(k.split(" ")), k)):
        rec = rows[key]
        model = key.split(" ")[0]
        # held: completed with nothing through a wall (a closed tank has no other way out than a leak)
        held = rec.get("status") == "completed" and not rec.get("escaped_wall") and not rec.get("escaped_domain")
        if held and model not in out:
            out[model] = dict(rec.get("params") or {})
    from seawall.boundary.registry import BOUNDARIES

    return {m: out[m] for m in BOUNDARIES if m in out}


def _key(model, options):
    return " ".join([model] + [f"{k}={v}" for k, v in sorted(options.items())])


def _case_geometry(dx, layout="layers"):
    """The downstream wall's inner face, the middle of its crest, the crest's height and one kernel
    support at this dx (seawall.cases.tanks: the open tank's side walls are 2 * layers thick; a
    repulsive model's wall is one row on the surface, which the hull follows at dx / 2, so the
    section stands dx / 4 behind the row)."""
    from seawall.cases.base import wall_layers
    from seawall.cases.tanks import snap
    from seawall.kernels import CubicSpline

    kernel, h = CubicSpline(), 1.3 * dx
    length = snap(5.366 * H, dx)
    crest = snap(TANK_HEIGHT * H, dx)
    middle = length + (wall_layers(kernel, h, dx) * dx if layout == "layers" else 0.25 * dx)
    return length, middle, crest, kernel.support(h)


def run_model(model, options, resolution, out, threads=1):
    from seawall.boundary.registry import boundary_by_name

    dx = H / resolution
    _, middle, crest, support = _case_geometry(dx, boundary_by_name(model, dict(options)).layout)
    # the section: across the middle of the downstream wall's crest, from one support below the crest
    # (water that runs along the crest a little inside its surface) up past the domain's top (the
    # run-up jet climbs far above the crest before it falls over it)
    bottom = crest - support
    ceiling = 100.0 * H
    run_dir = os.path.join(out, f"H{resolution}", _key(model, options).replace(" ", "_"))
    cmd = [sys.executable, "-m", "seawall", "run", "dam-break", "--boundary", model, "--dx", repr(dx),
           "--t-end", repr(T_END), "--out", run_dir, "--overwrite", "--no-vtk", "--no-progress",
           "--threads", str(threads), "--set", "lid=false", "--set", f"tank_height={TANK_HEIGHT}",
           "--discharge", f"{middle!r},{bottom!r}:{middle!r},{ceiling!r}:over_crest"]
    for k, v in sorted(options.items()):
        cmd += ["--set", f"{k}={v}"]
    env = {**os.environ, "PYTHONPATH": ROOT + os.pathsep + os.environ.get("PYTHONPATH", "")}
    started = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    rec = {"model": model, "params": options, "dx": dx, "exit_code": proc.returncode,
           "process_time_s": time.perf_counter() - started}
    rec.update(read_run(run_dir, proc.stderr))
    return rec


def read_run(run_dir, stderr=""):
    """A run's record from its summary.json and escaped.csv (``--refresh`` reads stored runs again)."""
    path = os.path.join(run_dir, "summary.json")
    if not os.path.exists(path):
        return {"status": "crashed", "error": (stderr.strip().splitlines() or [""])[-1]}
    with open(path) as fh:
        s = json.load(fh)
    mass = s.get("escaped_mass_by_reason") or {}
    # the overtopped removals by where they left: past the downstream wall (x+), which the section
    # counts, or out through the domain's top (y+: the run-up jet climbing higher than the domain)
    sides = {}
    escaped = os.path.join(run_dir, "escaped.csv")
    if os.path.exists(escaped):
        with open(escaped) as fh:
            rows = [line.rstrip("\n").split(",") for line in fh][1:]
        for row in rows:
            if row and row[-1] == "overtopped":
                sides[row[-2]] = sides.get(row[-2], 0) + 1
    over = (s.get("escaped_by_reason") or {}).get("overtopped", 0)
    # every fluid particle of the dam break has the same mass: the removed volume per side is its share
    over_removed = float(mass.get("overtopped", 0.0)) / RHO0
    over_crest = over_removed * sides.get("x+", 0) / over if over else 0.0
    section = (s.get("probes") or {}).get("over_crest") or {}
    over_section = section.get("final")
    return {
        "status": s.get("status"), "t_stop": s.get("t_end"), "t_end": T_END, "error": s.get("error") or "",
        "steps": s.get("steps"), "n_fluid_end": s.get("n_fluid"),
        "escaped_by_reason": s.get("escaped_by_reason"), "escaped_mass_by_reason": mass,
        "overtopped_by_side": sides, "mass_drift": s.get("mass_drift"),
        "overtopped_volume_removed": over_removed, "overtopped_volume_over_crest": over_crest,
        "overtopped_volume_section": over_section,
        "section_vs_removed": (None if over_section is None or over_crest == 0.0
                               else (over_section - over_crest) / over_crest),
        "wall_time_s": s.get("wall_time_s"),
    }


def results_path(resolution):
    return os.path.join(HERE, f"results_H{resolution}.json")


def load(resolution):
    path = results_path(resolution)
    if not os.path.exists(path):
        return {"H": H, "case": "dam-break", "tank_height": TANK_HEIGHT, "t_end": T_END, "models": {}}
    with open(path) as fh:
        return json.load(fh)


def save(resolution, data):
    with open(results_path(resolution), "w") as fh:
        json.dump(data, fh, indent=1, sort_keys=True)
        fh.write("\n")


def _stored_resolutions():
    found = []
    for name in os.listdir(HERE):
        if name.startswith("results_H") and name.endswith(".json"):
            found.append(int(name[len("results_H"):-len(".json")]))
    return sorted(found)


def table(resolution, data):
    lines = [f"**H/{resolution}** (dx = {H / resolution * 1000:.2f} mm), to t sqrt(g/H) = 8:", "",
             "| model (setting) | status | t [s] | removed: domain / wall / unstable / overtopped | "
             "overtopped: past the wall / out the top | overtopped volume [m^2/m] | discharge section vs past "
             "the wall | mass balance |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for key in sorted(data["models"], key=lambda k: list(holding_order()).index(k.split(" ")[0])
                      if k.split(" ")[0] in holding_order() else 99):
        r = data["models"][key]
        by = r.get("escaped_by_reason") or {}
        counts = " / ".join(str(by.get(k, "n/a")) for k in ("domain", "wall", "unstable", "overtopped"))
        rel = r.get("section_vs_removed")
        drift = r.get("mass_drift")
        sides = r.get("overtopped_by_side") or {}
        lines.append(f"| {key} | {r.get('status')} | {r.get('t_stop') or 0:.3f} | {counts} | "
                     f"{sides.get('x+', 0)} / {sides.get('y+', 0)} | "
                     f"{r.get('overtopped_volume_removed', 0.0):.3e} | "
                     f"{'n/a' if rel is None else f'{rel:+.1e}'} | {'n/a' if drift is None else f'{drift:.1e}'} |")
    return "\n".join(lines)


def holding_order():
    from seawall.boundary.registry import BOUNDARIES

    return list(BOUNDARIES)


def write_doc():
    parts = [table(n, load(n)) for n in _stored_resolutions()]
    with open(DOC) as fh:
        doc = fh.read()
    if BEGIN not in doc or END not in doc:
        raise SystemExit(f"{DOC} lacks the markers {BEGIN} / {END}")
    head, rest = doc.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(DOC, "w") as fh:
        fh.write(head + BEGIN + "\n" + "\n\n".join(parts) + "\n" + END + tail)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--resolution", type=int, default=30, help="N of dx = H/N (default 30)")
    ap.add_argument("--models", help="comma-separated model names (default: every model that holds the closed tank)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="an option for every model of this run, replacing its holding setting's value")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time, one thread each (default 2)")
    ap.add_argument("--out", default=os.path.join(HERE, "runs"))
    ap.add_argument("--report-only", action="store_true", help="rewrite the tables from the stored results")
    ap.add_argument("--refresh", action="store_true",
                    help="read the stored results' run directories in --out again (no run) and rewrite the tables")
    args = ap.parse_args(argv)
    if args.report_only:
        write_doc()
        return 0
    if args.refresh:
        data = load(args.resolution)
        for key, rec in data["models"].items():
            run_dir = os.path.join(args.out, f"H{args.resolution}", key.replace(" ", "_"))
            if os.path.exists(os.path.join(run_dir, "summary.json")):
                rec.update(read_run(run_dir))
        save(args.resolution, data)
        write_doc()
        return 0
    settings = holding_settings()
    models = args.models.split(",") if args.models else list(settings)
    unknown = [m for m in models if m not in settings]
    if unknown:
        raise SystemExit(f"--models: {unknown[0]!r} has no closed-tank setting that held; "
                         f"those that have: {', '.join(settings)}")
    from seawall.sweep import parse_set_items

    extra = parse_set_items(args.set)
    jobs = [(m, {**settings[m], **extra}) for m in models]
    data = load(args.resolution)
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for rec in pool.map(lambda job: run_model(job[0], job[1], args.resolution, args.out), jobs):
            key = _key(rec["model"], rec["params"])
            data["models"][key] = rec
            save(args.resolution, data)
            by = rec.get("escaped_by_reason") or {}
            print(f"{key}: {rec.get('status')} at {rec.get('t_stop')} s; removed {by}; "
                  f"mass balance {rec.get('mass_drift')}", flush=True)
    write_doc()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
