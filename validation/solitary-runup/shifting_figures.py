"""Particle shifting on the solitary-wave run-up (issue 17, item 6): figure and table from the stored entries.

    python validation/solitary-runup/shifting_figures.py

Reads the rows of ``solitary-runup`` and ``solitary-runup-<kind>`` (kind: sun2017, lind2012) from
results/<entry>.json. Writes img/shifting_runup.png (R/d against H/d of each run with Chan & Street's
curve and experiment) and prints the rows side by side as a markdown table. Entries without a stored
result are left out (they were not run).
"""

import json
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)

from seawall.validation._common import pyplot, rows_side_by_side  # noqa: E402
from seawall.validation.entries import solitary_runup as entry  # noqa: E402  (validation/solitary-runup/entry.py)

RUNS = [("solitary-runup", "no shifting (default)", ("k", "-")),
        ("solitary-runup-sun2017", "shifting sun2017", ("C3", "-")),
        ("solitary-runup-lind2012", "shifting lind2012", ("C0", "--"))]
ROW = re.compile(r"R/d at H/d = ([0-9.]+), dx = d/([0-9]+)")


def load(folder, name):
    return np.loadtxt(os.path.join(ROOT, "data", folder, name), delimiter=",", skiprows=1)


def main():
    runs = []
    for name, label, style in RUNS:
        path = os.path.join(HERE, "results", f"{name}.json")
        if os.path.isfile(path):
            with open(path) as fh:
                runs.append((label, style, json.load(fh)))
    curve, exp = entry.reference(load)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.8, 4.2), dpi=100)
    ax.plot(curve[:, 0], curve[:, 1], "-", color="0.45", lw=1, label="Chan & Street 1970, curve")
    ax.plot(exp[:, 0], exp[:, 1], "o", color="0.45", ms=4, mfc="none", label="experiment")
    stopped = []
    for label, (colour, line), res in runs:
        pts = {}
        for r in res["rows"]:
            hd, n = ROW.match(r["quantity"]).groups()
            pts.setdefault(int(n), []).append((float(hd), r["value"]))
            if "stopped" in r["case"]:
                stopped.append((float(hd), r["value"]))
        for n, mk in zip(sorted(pts), "s^"):
            p = np.array(pts[n])
            ax.plot(p[:, 0], p[:, 1], mk + (line if len(p) > 2 else ""), color=colour, ms=4, mfc="none", lw=1,
                    label=f"seawall d/{n}, {label}")
    if stopped:
        p = np.array(stopped)
        ax.plot(p[:, 0], p[:, 1], "x", color="k", ms=7, label="run stopped by the instability guard")
    ax.set_xlabel("H/d")
    ax.set_ylabel("R/d")
    ax.legend(fontsize=7)
    ax.set_title("solitary-wave run-up: particle shifting")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "img", "shifting_runup.png"))
    plt.close(fig)
    print(rows_side_by_side([r for _, _, r in runs], [label for label, _, _ in runs]))
    for label, _, res in runs:
        print(f"{res['name']}: {res['commit']}, {res['duration_s']} s; {' '.join(res['notes'])}")


if __name__ == "__main__":
    main()
