"""The fluid next to the downstream wall over the plateau window, column by column (issue 15, item 7).

    python validation/dam-break/near_wall_columns.py NAME MODEL [--resolution 50] [--set KEY=VALUE ...]
    python validation/dam-break/near_wall_columns.py --table

Runs the leak sweep's dam break (``dam-break``, H = 0.3 m) with one wall model to
t sqrt(g/H) = 5.5 and, at every evaluation of the rates inside the plateau window
3 <= t sqrt(g/H) <= 5.5, sampled every 2 ms, in a band of heights y +- dx at
y/H = 0.05, 0.1, 0.2, 0.27:

* ``p_col`` -- mean pressure of the fluid particles in the columns 0-1, 1-2, 2-3, 3-4 dx from
  the wall surface (x = length), and ``n_col`` their mean number in the band;
* ``p_layer`` -- mean pressure of the wall's first and second particle layers (models whose
  wall particles carry one);
* ``force`` and ``force_col`` -- the wall's force on the fluid per unit area (the ``force``
  read-out of ``plateau_profiles.py``), in all and per column.

All pressures in rho0 g H. It tells whether a point probe's reading (which extrapolates from
the first columns) and the wall's load differ because of one over- or under-pressed column.
Results: ``validation/dam-break/results/near_wall_columns.json`` (a name replaces its own entry).
"""

import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, ROOT)

OUT = os.path.join(HERE, "results", "near_wall_columns.json")
H = 0.3
G = 9.81
RHO0 = 1000.0
HEIGHTS = (0.05, 0.1, 0.2, 0.27)
T_STAR = (3.0, 5.5)
COLUMNS = 4
EVERY = 0.002


def run(model, resolution, params):
    """One run; returns {height: {quantity: window mean}} and the run's escaped count."""
    from seawall.cases import case_by_name
    from seawall.probes import Probe

    dx = H / resolution
    sim = case_by_name("dam-break").build(boundary=model, threads=1, dx=dx, **params)
    tank = next(w for w in sim.walls if w.name == "tank")
    length = sim.probes[[p.name for p in sim.probes].index("P1")].point[0]
    h = sim.h
    rhogh = RHO0 * G * H
    t0, t1 = (t / math.sqrt(G / H) for t in T_STAR)
    samples = {y: [] for y in HEIGHTS}

    class Columns(Probe):
        unit = "-"
        wall = "tank"   # asks the simulation to keep the tank's accelerations of the fluid

        def sample(self, s):
            dv = s.wall_accelerations.get(self.wall)
            if not t0 <= s.time <= t1 or dv is None or dv.shape[0] != s.fluid.particles.n:
                return float("nan")
            fp = s.fluid.particles
            x, p, m = fp["x"], fp["p"], fp["m"]
            xw = tank.particles["x"]
            pw = tank.particles["p"] if "p" in tank.particles else None
            for y in HEIGHTS:
                lo, hi = max(0.0, y * H - dx), y * H + dx
                band = (x[:, 1] >= lo) & (x[:, 1] < hi)
                fx = m * dv[:, 0]
                row = {"force": float(-np.sum(fx[band & (x[:, 0] > length - 3.0 * h)]) / (hi - lo) / rhogh)}
                for k in range(COLUMNS):
                    col = band & (x[:, 0] < length - k * dx) & (x[:, 0] >= length - (k + 1) * dx)
                    row[f"n_col{k}"] = int(col.sum())
                    row[f"p_col{k}"] = float(np.mean(p[col]) / rhogh) if col.any() else float("nan")
                    row[f"force_col{k}"] = float(-np.sum(fx[col]) / (hi - lo) / rhogh)
                    if pw is not None and k < 2:
                        lay = ((xw[:, 0] > length + k * dx) & (xw[:, 0] < length + (k + 1) * dx)
                               & (xw[:, 1] >= lo) & (xw[:, 1] < hi))
                        row[f"p_layer{k}"] = float(np.mean(pw[lay]) / rhogh) if lay.any() else float("nan")
                samples[y].append(row)
            return 0.0

    sim.add(Columns("near_wall_columns"), every=EVERY)
    sim.run(t1, progress=False)
    out = {}
    for y, rows in samples.items():
        out[f"{y:g}"] = {k: float(np.nanmean([r[k] for r in rows])) for k in rows[0]}
        out[f"{y:g}"]["samples"] = len(rows)
    return out, len(sim.escaped)


def table():
    """Markdown table of the stored runs at every height: column pressures, layers, force."""
    with open(OUT) as fh:
        data = json.load(fh)
    lines = ["| run | model, options | H/N | y/H | fluid p, columns 0-1 / 1-2 / 2-3 / 3-4 dx | particles per column "
             "| wall layers 1 / 2 | force (first column) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name, rec in data.items():
        opts = ", ".join(f"{k}={v}" for k, v in sorted(rec["params"].items())) or "defaults"
        for y, r in rec["heights"].items():
            cols = " / ".join(f"{r[f'p_col{k}']:.2f}" for k in range(COLUMNS))
            counts = " / ".join(f"{r[f'n_col{k}']:.1f}" for k in range(COLUMNS))
            layers = " / ".join(f"{r[f'p_layer{k}']:.2f}" for k in range(2)) if "p_layer0" in r else "n/a"
            lines.append(f"| {name} | `{rec['model']}` {opts} | {rec['resolution']} | {y} | {cols} | {counts} | "
                         f"{layers} | {r['force']:.2f} ({r['force_col0']:.2f}) |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("name", nargs="?")
    parser.add_argument("model", nargs="?")
    parser.add_argument("--resolution", type=int, default=50, help="N in dx = H/N (default 50)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="case or wall option (repeatable)")
    parser.add_argument("--table", action="store_true", help="print the stored runs as a markdown table")
    args = parser.parse_args(argv)
    if args.table:
        print(table())
        return 0
    if not args.name or not args.model:
        parser.error("give a NAME for the run and a wall MODEL (or --table)")
    from seawall.errors import ParameterError
    from seawall.sweep import parse_set_items

    try:
        # text, as `seawall run --set` passes it: the case and model parse it
        params = parse_set_items(args.set)
    except ParameterError as exc:
        parser.error(str(exc))
    heights, escaped = run(args.model, args.resolution, params)
    data = {}
    if os.path.exists(OUT):
        with open(OUT) as fh:
            data = json.load(fh)
    data[args.name] = {"model": args.model, "params": params, "resolution": args.resolution,
                       "t_star": list(T_STAR), "escaped": escaped, "heights": heights}
    with open(OUT, "w") as fh:
        json.dump(data, fh, indent=1, sort_keys=True)
        fh.write("\n")
    print(table())
    return 0


if __name__ == "__main__":
    sys.exit(main())
