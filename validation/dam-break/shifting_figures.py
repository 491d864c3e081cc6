"""Particle shifting on the dam break (issue 17, item 6): figure and table from the stored entries.

    python validation/dam-break/shifting_figures.py

Reads the P1 series that the full runs of ``dam-break`` and ``dam-break-<kind>`` (kind: sun2017,
lind2012) keep in results/p1_series_<entry>.csv, and their rows in results/<entry>.json. Writes
img/shifting_p1.png (p* against t*, the 0.1 t* running mean of each run, with Buchner's P1 in both
digitisations) and prints the features of every stored run side by side as a markdown table.
Entries without a stored series are left out (they were not run).
"""

import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)

from seawall.validation._common import pyplot, rows_side_by_side  # noqa: E402

RUNS = [("dam-break", "no shifting (default)", "k-"), ("dam-break-sun2017", "shifting sun2017", "C3-"),
        ("dam-break-lind2012", "shifting lind2012", "C0--")]
FILES = [("buchner2002_P1_pysph.csv", "Buchner 2002 P1 (PySPH digitisation)", "o"),
         ("buchner2002_P1_jaxsph.csv", "Buchner 2002 P1 (jax-sph digitisation)", "s")]


def stored_runs():
    """(name, label, style, series or None, stored result) of every run whose result is stored."""
    out = []
    for name, label, style in RUNS:
        res = os.path.join(HERE, "results", f"{name}.json")
        if not os.path.isfile(res):
            continue
        ser = os.path.join(HERE, "results", f"p1_series_{name}.csv")
        series = np.loadtxt(ser, delimiter=",", skiprows=1) if os.path.isfile(ser) else None
        with open(res) as fh:
            out.append((name, label, style, series, json.load(fh)))
    return out


def figure(runs, path):
    plt = pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(7.5, 6.4), dpi=100, sharex=True,
                             gridspec_kw={"height_ratios": [3, 1.4]})
    ax, dif = axes
    for fname, label, mk in FILES:
        d = np.loadtxt(os.path.join(ROOT, "data", "buchner2002_dambreak2d_P1", fname), delimiter=",", skiprows=1)
        d = d[np.argsort(d[:, 0], kind="stable")]
        ax.plot(d[:, 0], d[:, 1], mk, ms=3, mfc="none", color="0.45", label=label)
    base = next((r[3] for r in runs if r[0] == "dam-break" and r[3] is not None), None)
    for name, label, style, series, _ in runs:
        if series is None:
            continue
        ax.plot(series[:, 0], series[:, 2], style, lw=1.2, label=f"seawall P1, {label}")
        if base is not None and name != "dam-break":
            # the shifted run minus the default, on the default's read-out times
            dif.plot(base[:, 0], np.interp(base[:, 0], series[:, 0], series[:, 2]) - base[:, 2], style, lw=1,
                     label=f"{label} minus default")
    ax.set_ylabel("p / (rho g H), 0.1 t* running mean")
    ax.set_ylim(-0.2, 1.3)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("dam break H = 0.6 m, sensor P1, dx = H/50: particle shifting")
    dif.axhline(0.0, color="0.6", lw=0.6)
    dif.set_xlabel("t sqrt(g/H)")
    dif.set_ylabel("difference")
    dif.set_xlim(0, 7.5)
    if dif.lines[1:]:
        dif.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main():
    runs = stored_runs()
    figure(runs, os.path.join(HERE, "img", "shifting_p1.png"))
    print(rows_side_by_side([r[4] for r in runs], [r[1] for r in runs]))
    for name, _, _, _, res in runs:
        print(f"{name}: {res['commit']}, {res['duration_s']} s; {res['settings']}; {' '.join(res['notes'][1:])}")


if __name__ == "__main__":
    main()
