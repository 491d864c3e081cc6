"""How far the plateau profile moves between runs that differ only in round-off (issue 15, item 7).

    python validation/dam-break/plateau_ensemble.py --resolution 50 --models adami,dbc
    python validation/dam-break/plateau_ensemble.py --models ghost-mls2 --set reflect=1   # with an option
    python validation/dam-break/plateau_ensemble.py --table          # print the stored spreads
    python validation/dam-break/plateau_ensemble.py --write-doc      # and put them into docs/validation-notes.md

After the impact the dam break is chaotic: a CFL number changed by 1e-5 of its value changes the
time steps in their last digits, and the run that follows is another realisation of the same
flow, as valid as the first. The members of an ensemble run the leak sweep's dam break (its
worker, same case, probes and read-outs; ``validation/leaks/sweep.py``) to t sqrt(g/H) = 5.5, the
end of the plateau window, with cfl = 0.2 (1 + e) for e in :data:`MEMBERS`. Their plateau means
go to ``validation/dam-break/results/plateau_ensemble.json`` (per resolution and model; a member
run again replaces its entry), run directories to ``validation/leaks/runs/ensemble`` (not kept).

The table gives, per read-out and height, the members' standard deviation and range (largest
minus smallest): the spread the agreement table of ``plateau_profiles.py`` would show for one
model run several times, against which a spread between models has to be read.
"""

import argparse
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "validation", "leaks"))
sys.path.insert(0, ROOT)

import sweep  # noqa: E402  (validation/leaks/sweep.py: its worker is spawned by module name)
from seawall.errors import ParameterError  # noqa: E402
from seawall.sweep import parse_set_items  # noqa: E402

OUT = os.path.join(HERE, "results", "plateau_ensemble.json")
RUNS = os.path.join(ROOT, "validation", "leaks", "runs", "ensemble")
DOC = os.path.join(ROOT, "docs", "validation-notes.md")
BEGIN = "<!-- plateau-ensemble:begin -->"
END = "<!-- plateau-ensemble:end -->"
T_STAR = 5.5
#: the case's CFL number, and the relative changes of it that make the members
CFL = 0.2
MEMBERS = (0.0, -1e-5, 1e-5, -1e-4, 1e-4)
#: the profile's heights as the plateau records key them ("0.01", ...)
HEIGHTS = tuple(f"{f:g}" for f in sweep._plateau_module().HEIGHTS)
TABLE_READOUTS = ("force", "wall")


def member_cfl(e):
    """The CFL number of member ``e`` as the option string the sweep records (0.199998, ...)."""
    return f"{CFL * (1.0 + e):.8g}"


def spread(records, readout):
    """{height: (n, standard deviation, range)} over the completed members' plateau means."""
    out = {}
    for h in HEIGHTS:
        vals = [r["plateau"][readout][h] for r in records
                if r.get("status") == "completed" and (r.get("plateau") or {}).get(readout, {}).get(h) is not None]
        v = np.array(vals, dtype=float)
        out[h] = (v.size, float(v.std(ddof=1)) if v.size > 1 else None, float(np.ptp(v)) if v.size else None)
    return out


def load():
    return sweep.read_json(OUT)


def table(data=None):
    data = load() if data is None else data
    lines = ["| H/N | model | members | read-out | " + " | ".join(f"y/H = {h}: sd, range" for h in HEIGHTS) + " |",
             "| --- | --- | --- | --- | " + " | ".join("---" for _ in HEIGHTS) + " |"]
    for res in sorted(data, key=lambda k: int(k[1:])):
        for model in sweep._ordered(data[res]):
            records = list(data[res][model].values())
            for ro in TABLE_READOUTS:
                s = spread(records, ro)
                n = max(c[0] for c in s.values())
                cells = ["n/a" if c[1] is None else f"{c[1]:.3f}, {c[2]:.3f}" for c in s.values()]
                lines.append(f"| {res[1:]} | `{model}` | {n} | {ro} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def write_doc():
    from seawall.validation import replace_block

    replace_block(DOC, BEGIN, END, table())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=50, help="N in dx = H/N (default 50)")
    parser.add_argument("--models", default="adami", help="comma-separated wall models (default adami)")
    parser.add_argument("--members", type=int, default=len(MEMBERS),
                        help=f"how many of the {len(MEMBERS)} CFL changes to run (default all)")
    parser.add_argument("--threads", type=int, default=1, help="threads of each run (default 1)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="case or wall option for every member (the row is then 'MODEL KEY=VALUE', "
                             "as in the sweep's tables)")
    parser.add_argument("--table", action="store_true", help="print the table of the stored ensembles")
    parser.add_argument("--write-doc", action="store_true", help="write the table into docs/validation-notes.md")
    args = parser.parse_args(argv)
    if args.table:
        print(table())
        return 0
    if args.write_doc:
        write_doc()
        return 0
    if args.resolution < 5:
        parser.error("--resolution must be at least 5")
    if not 1 <= args.members <= len(MEMBERS):
        parser.error(f"--members must be 1..{len(MEMBERS)}")
    if args.threads < 1:
        parser.error("--threads must be at least 1")
    known = sweep.closed_tank_models()
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    for m in models:
        if m not in known:
            parser.error(f"unknown wall model {m!r}; available: {', '.join(known)}")
    try:
        options = parse_set_items(args.set)
    except ParameterError as exc:
        parser.error(str(exc))
    if "cfl" in options:
        parser.error("--set cfl=...: the members are made by changing the CFL number; it cannot be set")
    dx = sweep.H / args.resolution
    t_end = T_STAR * math.sqrt(sweep.H / sweep.G)
    res = f"H{args.resolution}"
    for model in models:
        row = sweep._key(model, options)
        for e in MEMBERS[:args.members]:
            cfl = member_cfl(e)
            print(f"[ensemble] {row} H/{args.resolution} cfl = {cfl} to t* = {T_STAR}", flush=True)
            rec = sweep.run_model(model, dx, t_end, {**options, "cfl": cfl}, os.path.join(RUNS, res), args.threads)
            print(f"[ensemble] {row} cfl = {cfl}: {rec['status']} escaped {rec.get('escaped')}", flush=True)
            data = load()     # read again: another process may have stored members meanwhile
            data.setdefault(res, {}).setdefault(row, {})[cfl] = {
                k: rec.get(k) for k in ("status", "t_stop", "escaped", "min_wall_distance_dx", "steps", "plateau")}
            sweep.write_json(OUT, data)
    return 0


if __name__ == "__main__":
    sys.exit(main())
