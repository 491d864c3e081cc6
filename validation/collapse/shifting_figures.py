"""Particle shifting on the column collapse (issue 17, item 6): figure and tables from the stored entries.

    python validation/collapse/shifting_figures.py

Reads the front series that the full runs of ``collapse`` and ``collapse-<kind>`` (kind: sun2017,
lind2012) keep in results/front_series_<entry>.csv. Writes img/shifting_front.png (Z = x_front / a
against T = t sqrt(2 g / a) of each run with the four references) and prints, as markdown, the front
of each run at the Martin & Moyce (a = 2.25 in) points with its error, and the largest error against
each reference over the entry's window (T > 0.5, Z < 3.95: the entry's rows, recomputed from the
series for every run alike). Entries without a stored series are left out (they were not run).
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)

from seawall.validation._common import pyplot  # noqa: E402
from seawall.validation.entries import collapse as entry  # noqa: E402  (validation/collapse/entry.py)

RUNS = [("collapse", "no shifting (default)", "k-"), ("collapse-sun2017", "shifting sun2017", "C3-"),
        ("collapse-lind2012", "shifting lind2012", "C0--")]


def load(folder, name):
    return np.loadtxt(os.path.join(ROOT, "data", folder, name), delimiter=",", skiprows=1)


def main():
    runs = [(name, label, style, np.loadtxt(path, delimiter=",", skiprows=1))
            for name, label, style in RUNS
            for path in [os.path.join(HERE, "results", f"front_series_{name}.csv")] if os.path.isfile(path)]
    refs = [(label, load(folder, fname)) for folder, fname, label in entry.REFERENCES]
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=100)
    for (label, ref), mk in zip(refs, "osd^"):
        ax.plot(ref[:, 0], ref[:, 1], mk, ms=4, mfc="none", color="0.45", label=label)
    for _, label, style, s in runs:
        ax.plot(s[:, 0], s[:, 1], style, lw=1.3, label=f"seawall a/40, {label}")
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("Z = x_front / a")
    ax.set_xlim(0, 3.5)
    ax.set_ylim(1, 4.2)
    ax.legend(fontsize=7)
    ax.set_title("column collapse: surge front with and without particle shifting")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "img", "shifting_front.png"))
    plt.close(fig)

    mm = refs[0][1]
    labels = [label for _, label, _, _ in runs]
    print("| T | Martin & Moyce (a = 2.25 in) | " + " | ".join(labels) + " |")
    print("| --- " * (len(runs) + 2) + "|")
    for t, z in mm[(mm[:, 0] > 0.5) & (mm[:, 1] < 3.95)]:    # the entry's window: before the far wall
        cells = [f"{np.interp(t, s[:, 0], s[:, 1]):.3f} ({100 * (np.interp(t, s[:, 0], s[:, 1]) / z - 1):+.1f} %)"
                 for _, _, _, s in runs]
        print(f"| {t:.2f} | {z:.3f} | " + " | ".join(cells) + " |")
    print()
    print("| largest error against | " + " | ".join(labels) + " |")
    print("| --- " * (len(runs) + 1) + "|")
    for label, ref in refs:
        cells = []
        for _, _, _, s in runs:
            T, Z = s[:, 0], s[:, 1]
            t_wall = T[np.argmax(Z >= 3.95)] if np.any(Z >= 3.95) else T[-1]
            pts = ref[(ref[:, 0] > 0.5) & (ref[:, 0] < t_wall) & (ref[:, 1] < 3.95)]
            err = np.interp(pts[:, 0], T, Z) / pts[:, 1] - 1
            k = int(np.argmax(np.abs(err)))
            cells.append(f"{100 * err[k]:+.1f} % (T = {pts[k, 0]:.2f}, {len(pts)} points)")
        print(f"| {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
