"""Figures of the plateau diagnosis (issue 15, item 7) from the runs' directories.

    python validation/dam-break/plateau_figures.py fields OUT.png LABEL=RUN_DIR [LABEL=RUN_DIR ...] [--snapshot K]
    python validation/dam-break/plateau_figures.py series OUT.png FRAC LABEL=RUN_DIR [...]

``fields``: the fluid near the downstream wall at snapshot K (t sqrt(g/H) = 3.5, 4, 4.5, 5 for
K = 0..3) of each run, coloured by p / (rho g H), with the velocity as arrows.
``series``: p / (rho g H) at height FRAC (y/H) on the downstream wall (the ``wall`` read-out, or
the one named by RUN_DIR@READOUT), 0.05 s running mean, against t sqrt(g/H).
RUN_DIR: a run directory of the leak sweep or of plateau_diagnostics.py (probes.csv,
plateau_snapshots.npz). Figures go to validation/dam-break/img/.
"""

import csv
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))
from seawall.validation import load_script  # noqa: E402  (this checkout's seawall, put on the path above)

# wall_layers.py beside this script: where a snapshot's downstream wall surface is, and the sweep's
# dam break
wall_layers = load_script(os.path.join(HERE, "wall_layers.py"))

H, G, RHO_G_H = wall_layers.H, wall_layers.G, wall_layers.RHO_G_H


def _fields(out, runs, k):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(runs), figsize=(3.6 * len(runs), 4.4), squeeze=False, sharey=True)
    sc = None
    for ax, (label, run) in zip(axes[0], runs):
        with np.load(os.path.join(run, "plateau_snapshots.npz")) as d:
            x, v, p = d[f"f{k}_x"], d[f"f{k}_v"], d[f"f{k}_p"] / RHO_G_H
            _, length, _ = wall_layers.geometry(d, k, run)
            t_k = float(d[f"t{k}"])
        near = x[:, 0] > length - 0.5 * H
        sc = ax.scatter(x[near, 0] / H, x[near, 1] / H, c=p[near], s=4, cmap="viridis", vmin=-0.1, vmax=1.2)
        sub = np.nonzero(near)[0][::3]
        ax.quiver(x[sub, 0] / H, x[sub, 1] / H, v[sub, 0], v[sub, 1], scale=40, width=0.004, color="k", alpha=0.6)
        ax.axvline(length / H, color="0.4", lw=1)
        ax.set_title(f"{label}, t* = {t_k * math.sqrt(G / H):.1f}", fontsize=9)
        ax.set_xlabel("x / H")
        ax.set_aspect("equal")
        ax.set_ylim(0, 1.0)
        ax.set_xlim(length / H - 0.5, length / H + 0.05)
    axes[0][0].set_ylabel("y / H")
    fig.colorbar(sc, ax=axes[0].tolist(), label="p / (rho g H)", shrink=0.8)
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)


def _read_probes(run):
    with open(os.path.join(run, "probes.csv")) as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    body = [r for r in rows[1:] if r and not r[0].startswith("#")]
    data = np.array([[float(v) if v not in ("", "nan") else np.nan for v in r] for r in body])
    return {name: data[:, k] for k, name in enumerate(head)}


def _series(out, frac, runs):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.8))
    for label, run in runs:
        readout = "wall"
        if "@" in run:
            run, readout = run.split("@", 1)
        d = _read_probes(run)
        tkey = next(k for k in d if k.startswith("t"))
        t = d[tkey]
        p = d[f"plateau_{readout}_{frac:g}"] / RHO_G_H
        ok = np.isfinite(p)
        t, p = t[ok], p[ok]
        width = max(1, int(round(0.05 / np.median(np.diff(t)))))
        pm = np.convolve(p, np.ones(width) / width, mode="same")
        ax.plot(t * math.sqrt(G / H), pm, lw=1, label=label)
    ax.axvspan(3.0, 5.5, color="0.9")
    ax.set_xlabel("t sqrt(g/H)")
    ax.set_ylabel(f"p / (rho g H) at y/H = {frac:g} (0.05 s mean)")
    ax.set_title(f"downstream wall, y/H = {frac:g}; grey: the plateau window", fontsize=9)
    ax.set_xlim(2, 8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv):
    kind, out = argv[0], argv[1]
    rest = argv[2:]
    k = 2
    if "--snapshot" in rest:
        i = rest.index("--snapshot")
        k = int(rest[i + 1])
        rest = rest[:i] + rest[i + 2:]
    if kind == "fields":
        runs = [tuple(a.split("=", 1)) for a in rest]
        for _, run in runs:
            with np.load(os.path.join(run, "plateau_snapshots.npz")) as d:
                if f"t{k}" not in d.files:
                    print(f"plateau_figures.py: --snapshot {k}: RUN_DIR {run!r} has snapshots "
                          f"0..{sum(1 for f in d.files if f[0] == 't' and f[1:].isdigit()) - 1}", file=sys.stderr)
                    return 2
        _fields(out, runs, k)
    else:
        _series(out, float(rest[0]), [tuple(a.split("=", 1)) for a in rest[1:]])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
