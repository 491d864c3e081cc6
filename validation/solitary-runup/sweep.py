"""Solitary-wave run-up on a vertical wall against Chan & Street (1970), Fig. 11.

    python validation/solitary-runup/sweep.py                     # adami, dx = d/15, H/d = 0.1 ... 0.6
    python validation/solitary-runup/sweep.py --models adami dbc ghost-shepard --n 15

Case ``solitary-runup``: constant depth d = 0.25 m, a Goring piston, a vertical
wall 10 d from the piston's start (the set-up of the SolitaryWave study that
digitised the reference, 2.5 m flume). The run-up R is the highest fluid on the
wall (``RunUp`` probe: top face of the highest particle within 2 dx of the
wall) above the still level, over the run until the crest has reached the wall
and come back (crest arrival + 4 / (k c)). R/d is compared with the solid curve
of Chan & Street (interpolated) and the nearest experimental points
(|Delta H/d| <= 0.02); ``seawall validate solitary-runup`` runs the same
(adami, d/15) against a stated tolerance. Writes validation/solitary-runup/runs/solitary_runup.csv (not committed),
the table in docs/waves_runup.md and validation/solitary-runup/img/solitary_runup.png.
"""

import argparse
import csv
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)

from seawall.validation.entries import solitary_runup as entry  # noqa: E402  (validation/solitary-runup/entry.py)

OUT = os.path.join(HERE, "runs")
DOCS = os.path.join(ROOT, "docs")


def reference():
    def load(folder, name):
        return np.loadtxt(os.path.join(ROOT, "data", folder, name), delimiter=",", skiprows=1)

    return entry.reference(load)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=["adami"])
    parser.add_argument("--n", type=int, default=15, help="particles per depth, d/dx")
    parser.add_argument("--hd", type=float, nargs="+", default=[0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    parser.add_argument("--threads", type=int, default=None)
    args = parser.parse_args(argv)
    os.makedirs(OUT, exist_ok=True)
    curve, exp = reference()
    rows = []
    path = os.path.join(OUT, "solitary_runup.csv")
    for model in args.models:
        for hd in args.hd:
            r = entry.run_one(model, hd, args.n, args.threads)
            r["R_curve"] = float(np.interp(hd, curve[:, 0], curve[:, 1]))
            near = exp[np.abs(exp[:, 0] - hd) <= 0.02 + 1e-9, 1]
            r["R_exp"] = float(near.mean()) if near.size else float("nan")
            r["err_curve"] = r["R_over_d"] / r["R_curve"] - 1.0
            r["err_exp"] = r["R_over_d"] / r["R_exp"] - 1.0 if near.size else float("nan")
            rows.append(r)
            print(f"{model:14s} H/d={hd:.2f} R/d={r['R_over_d']:.3f} curve={r['R_curve']:.3f} "
                  f"({100 * r['err_curve']:+.1f} %) exp={r['R_exp']:.3f} ({100 * r['err_exp']:+.1f} %) "
                  f"{r['wall_s']:.0f} s", flush=True)
            with open(path, "w", newline="") as fh:
                w = csv.DictWriter(fh, fieldnames=list(rows[0]))
                w.writeheader()
                w.writerows(rows)
    write_docs(rows, curve, exp, args.n)


def write_docs(rows, curve, exp, n):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.plot(curve[:, 0], curve[:, 1], "k-", lw=1, label="Chan & Street 1970, curve")
    ax.plot(exp[:, 0], exp[:, 1], "ko", ms=4, mfc="none", label="experiment")
    for model in dict.fromkeys(r["model"] for r in rows):
        rr = [r for r in rows if r["model"] == model]
        ax.plot([r["H_over_d"] for r in rr], [r["R_over_d"] for r in rr], "s-", ms=4, label=f"seawall {model}")
    ax.set_xlabel("H/d")
    ax.set_ylabel("R/d")
    ax.set_title(f"solitary-wave run-up on a vertical wall, dx = d/{n}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.join(HERE, "img"), exist_ok=True)
    fig.savefig(os.path.join(HERE, "img", "solitary_runup.png"), dpi=110)
    lines = ["# Solitary-wave run-up on a vertical wall (Chan & Street 1970)", "",
             "Written by `python validation/solitary-runup/sweep.py` (case `solitary-runup`, d = 0.25 m, "
             f"dx = d/{n}, wall 10 d from the piston). Errors relative to the interpolated solid curve and to "
             "the mean of the experimental points within 0.02 in H/d.", "",
             "| model | H/d | R/d | curve | error | experiment | error | wall time [s] |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['model']} | {r['H_over_d']:.2f} | {r['R_over_d']:.3f} | {r['R_curve']:.3f} | "
                     f"{100 * r['err_curve']:+.1f} % | {r['R_exp']:.3f} | {100 * r['err_exp']:+.1f} % | "
                     f"{r['wall_s']:.0f} |")
    lines += ["", "![run-up](../validation/solitary-runup/img/solitary_runup.png)", ""]
    with open(os.path.join(DOCS, "waves_runup.md"), "w") as fh:
        fh.write("\n".join(lines))


if __name__ == "__main__":
    main()
