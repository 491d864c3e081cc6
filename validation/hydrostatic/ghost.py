"""Hydrostatic tank ([Huang2019] sec. 4.1) with the five ghost-wall interpolations.

Runs ``hydrostatic`` with the seed's fluid scheme (marrone2011: linear EOS,
Gaussian kernel cut at 3h, delta-SPH, alpha = 0.02, h = 1.3 dx) for each of
ghost-mls1, ghost-mls2, ghost-sfdi, ghost-normalized, ghost-shepard, one
after the other, and writes

* ``validation/hydrostatic/results/ghost_hydrostatic.csv`` -- probe histories,
* ``validation/hydrostatic/results/ghost_hydrostatic.json`` -- errors per method and probe,
* ``validation/hydrostatic/img/ghost_hydrostatic.png`` -- P0-P3 histories against rho g (H - y).

Usage: python validation/hydrostatic/ghost.py [--dx 0.02] [--t-end 5] [--dt 0]
(the seed's own settings are --dx 0.01 --dt 1e-4 --t-end 35: about 2 h per method
on 2 cores).
"""

import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)

from seawall.cases import build  # noqa: E402

METHODS = ["ghost-mls1", "ghost-mls2", "ghost-sfdi", "ghost-normalized", "ghost-shepard"]
PROBES = {"P0": 0.0, "P1": 0.1, "P2": 0.2, "P3": 0.25}

def run(method, dx, t_end, dt, scheme):
    sim = build("hydrostatic", boundary=method, dx=dx, scheme=scheme, dt=dt)
    sim.add(every=max(0.01, t_end / 500))
    start = time.perf_counter()
    res = sim.run(t_end, progress=False)
    wall = time.perf_counter() - start
    depth = sim.reference["depth"]
    rho_g = sim.reference["rho0"] * sim.reference["g"]
    errors = {}
    late = res.times >= 0.5 * t_end
    for name, y in PROBES.items():
        exact = rho_g * (depth - y)
        p = res[name]
        errors[name] = {
            "exact_Pa": exact,
            "mean_late_Pa": float(p[late].mean()),
            "rel_err_mean_late": float(abs(p[late].mean() - exact) / exact),
            "rel_err_max_late": float(np.max(np.abs(p[late] - exact)) / exact),
            "rel_err_max_all_over_rhogH": float(np.max(np.abs(p - exact)) / (rho_g * depth)),
        }
    return res, {"wall_time_s": wall, "steps": res.summary["steps"], "n_fluid": res.summary["n_fluid"],
                 "n_wall": res.summary["n_wall"], "ke_final": float(res["kinetic_energy"][-1]),
                 "probes": errors}


def plot(results, depth, rho_g, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(9, 6), sharex=True)
    for ax, (name, y) in zip(axes.ravel(), PROBES.items()):
        for method, res in results.items():
            ax.plot(res.times, res[name] / 1000.0, lw=0.9, label=method.replace("ghost-", ""))
        ax.axhline(rho_g * (depth - y) / 1000.0, color="k", ls="--", lw=1.0, label="rho g (H - y)")
        ax.set_title(f"{name} (y = {y} m)", fontsize=10)
        ax.set_ylabel("p [kPa]")
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    axes[0, 0].legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=64)
    plt.close(fig)


class _Saved:
    def __init__(self, times, cols):
        self.times = times
        self.cols = cols

    def __getitem__(self, name):
        return self.cols[name]


def replot():
    path = os.path.join(HERE, "results", "ghost_hydrostatic.csv")
    data = np.genfromtxt(path, delimiter=",", names=True, deletechars="")
    header = open(path).readline().strip().split(",")[1:]
    methods = sorted({c.split(":")[0] for c in header}, key=METHODS.index)
    results = {m: _Saved(data["time"], {p: data[f"{m}:{p}"] for p in PROBES}) for m in methods}
    plot(results, 0.3, 1000.0 * 9.81, os.path.join(HERE, "img", "ghost_hydrostatic.png"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dx", type=float, default=0.02)
    ap.add_argument("--t-end", type=float, default=5.0)
    ap.add_argument("--dt", type=float, default=0.0)
    ap.add_argument("--scheme", default="marrone2011")
    ap.add_argument("--methods", nargs="*", default=METHODS)
    ap.add_argument("--plot-only", action="store_true", help="redraw the figure from the saved CSV")
    args = ap.parse_args()
    if args.plot_only:
        replot()
        return
    out_dir = os.path.join(HERE, "results")
    os.makedirs(out_dir, exist_ok=True)
    results, report = {}, {"dx": args.dx, "t_end": args.t_end, "dt": args.dt, "scheme": args.scheme,
                           "methods": {}}
    for method in args.methods:
        res, summary = run(method, args.dx, args.t_end, args.dt, args.scheme)
        results[method] = res
        report["methods"][method] = summary
        errs = ", ".join(f"{k} {v['rel_err_mean_late'] * 100:.2f}%" for k, v in summary["probes"].items())
        print(f"{method:18s} {summary['wall_time_s']:6.1f} s wall  mean late error: {errs}", flush=True)
    with open(os.path.join(out_dir, "ghost_hydrostatic.json"), "w") as fh:
        json.dump(report, fh, indent=2)
    first = next(iter(results.values()))
    with open(os.path.join(out_dir, "ghost_hydrostatic.csv"), "w") as fh:
        cols = [f"{m}:{p}" for m in results for p in PROBES]
        fh.write("time," + ",".join(cols) + "\n")
        n = min(len(r.times) for r in results.values())
        for k in range(n):
            row = [f"{first.times[k]:.4f}"] + [f"{results[m][p][k]:.2f}" for m in results for p in PROBES]
            fh.write(",".join(row) + "\n")
    plot(results, 0.3, 1000.0 * 9.81, os.path.join(HERE, "img", "ghost_hydrostatic.png"))


if __name__ == "__main__":
    main()
