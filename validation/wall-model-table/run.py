"""Accuracy and cost of the wall models on two cases, as one table.

    python validation/wall-model-table/run.py            # about 10 minutes on 2 cores
    python validation/wall-model-table/run.py --quick    # three models

Runs ``seawall compare`` on
* ``hydrostatic`` (dx = 0.02 m, 1.5 s): wall-pressure error against rho g (H - y);
* ``collapse`` (dx = a/40, 0.3 s): surge-front error against Martin & Moyce
  (n^2 = 2, a = 2.25 in) and against Koshizuka & Oka's MPS computation, largest
  relative error over the reference points before the front reaches the far wall;
and writes validation/wall-model-table/results/wall_model_table.md (+ .csv) with escaped particles,
the smallest fluid-to-wall distance and the cost relative to ``adami``.
"""

import argparse
import csv
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)
DATA = os.path.join(ROOT, "data")
OUT = os.path.join(HERE, "results")
RUNS = os.path.join(HERE, "runs")   # the compare runs (not committed)
A = 0.146

MODELS = ["adami", "adami-noslip", "summation", "continuity", "zeroing", "mirroring", "monaghan-kajtar",
          "dbc", "idbc", "ghost-mls1", "ghost-sfdi", "ghost-normalized", "ghost-shepard", "mdbc", "mdbc-noslip"]


def front_error(run_dir, ref_file, folder):
    from seawall.io import read_probes_csv

    t, cols = read_probes_csv(os.path.join(run_dir, "probes.csv"))
    if len(t) < 2:
        return None
    T = t * np.sqrt(2 * 9.81 / A)
    Z = cols["front"] / A
    ref = np.loadtxt(os.path.join(DATA, folder, ref_file), delimiter=",", skiprows=1)
    t_wall = T[np.argmax(Z >= 3.95)] if np.any(Z >= 3.95) else T[-1]
    ref = ref[(ref[:, 0] > 0.5) & (ref[:, 0] < min(t_wall, T[-1])) & (ref[:, 1] < 3.95)]
    if not len(ref):
        return None
    sph = np.interp(ref[:, 0], T, Z)
    worst = np.argmax(np.abs(sph - ref[:, 1]))
    return float((sph[worst] - ref[worst, 1]) / ref[worst, 1])


def _parse(value):
    """A stored CSV cell back to a number, None or text."""
    if value in ("", "None"):
        return None
    try:
        number = float(value)
    except ValueError:
        return value
    return int(number) if number.is_integer() and "." not in value and "e" not in value.lower() else number


def main(argv=None):
    from seawall.compare import compare

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--models", help="comma-separated subset (adami first for the cost column); their rows "
                        "replace or join the stored table's, the other rows are kept")
    args = parser.parse_args(argv)
    models = ["adami", "dbc", "ghost-shepard"] if args.quick else MODELS
    if args.models:
        models = [m.strip() for m in args.models.split(",") if m.strip()]
    os.makedirs(OUT, exist_ok=True)
    hydro = compare("hydrostatic", models, out=os.path.join(RUNS, "table_hydrostatic"), dx=0.02, t_end=1.5)
    coll = compare("collapse", models, out=os.path.join(RUNS, "table_collapse"), dx=A / 40, t_end=0.3)
    by_h = {r["boundary"]: r for r in hydro}
    by_c = {r["boundary"]: r for r in coll}
    base = by_c["adami"]["particle_steps_per_s"] if "adami" in by_c else None

    rows = []
    for m in models:
        h, c = by_h[m], by_c[m]
        run_dir = os.path.join(RUNS, "table_collapse", m)
        rows.append({
            "model": m,
            "hydrostatic_status": h["status"], "wall_pressure_error": h["wall_pressure_error"],
            "hydrostatic_min_wall_distance_dx": h["min_wall_distance_dx"], "hydrostatic_escaped": h["escaped"],
            "collapse_status": c["status"],
            "front_error_vs_martin_moyce": front_error(run_dir, "mm1952_n2_2_a2.25in_front_pysph.csv",
                                                       "martin_moyce1952_collapse"),
            "front_error_vs_ko_mps": front_error(run_dir, "ko1996_mps_front_pysph.csv", "koshizuka_oka1996_collapse"),
            "collapse_escaped": c["escaped"], "collapse_min_wall_distance_dx": c["min_wall_distance_dx"],
            "cost_relative_to_adami": (base / c["particle_steps_per_s"]) if base and c["particle_steps_per_s"] else None,
        })
    csv_path = os.path.join(OUT, "wall_model_table.csv")
    if args.models and os.path.exists(csv_path):
        # a subset updates the stored table: its rows replace (or join) the stored ones, in the stored order
        with open(csv_path, newline="") as fh:
            stored = list(csv.DictReader(fh))
        new = {r["model"]: r for r in rows}
        merged = [new.pop(r["model"], None) or {k: _parse(v) for k, v in r.items()} for r in stored]
        rows = merged + [r for r in rows if r["model"] in new]
    with open(csv_path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    def pct(v):
        return "n/a" if v is None else f"{100 * v:+.1f} %"

    def num(v, fmt="{:.2f}"):
        return "n/a" if v is None else fmt.format(v)

    lines = ["# Wall models on the hydrostatic tank and the column collapse", "",
             "Produced by `python validation/wall-model-table/run.py` (hydrostatic dx = 0.02 m, 1.5 s; "
             "collapse dx = a/40, 0.3 s; cubic spline h = 1.3 dx, delta-SPH, symplectic). Wall-pressure error: "
             "mean over probes of |mean p - rho g (H - y)| / (rho g H) over the second half. Front error: the "
             "largest relative error of x_front/a before the far wall (signed). Cost: time per particle-step "
             "relative to adami on the collapse.", "",
             "| model | hydrostatic wall-pressure error | min wall distance [dx] | front vs Martin & Moyce | "
             "front vs K&O MPS | escaped (hydrostatic / collapse) | cost vs adami |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        status = "" if r["collapse_status"] == "completed" else f" ({r['collapse_status']})"
        hstatus = "" if r["hydrostatic_status"] == "completed" else f" ({r['hydrostatic_status']})"
        lines.append(f"| {r['model']} | {pct(r['wall_pressure_error'])}{hstatus} | "
                     f"{num(r['hydrostatic_min_wall_distance_dx'])} / {num(r['collapse_min_wall_distance_dx'])} | "
                     f"{pct(r['front_error_vs_martin_moyce'])}{status} | {pct(r['front_error_vs_ko_mps'])} | "
                     f"{r['hydrostatic_escaped']} / {r['collapse_escaped']} | {num(r['cost_relative_to_adami'])} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(OUT, "wall_model_table.md"), "w") as fh:
        fh.write(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
