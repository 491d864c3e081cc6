"""Figures and numbers of docs/waves.md: the sloped seawall and the spring-mounted seawall, three wall models.

    python validation/waves/run.py                    # coarse: dx = 0.025 m / 0.02 m, ~20 min on 2 cores
    python validation/waves/run.py --seawall-dx 0.01 --movable-dx 0.008   # the seed's resolutions (hours)

``solitary-seawall`` ([Huang2019] sec. 4.3: 10 m flume, d = 0.25 m, H = 0.15 m, wall at 120 deg,
probes P0/P1 at y = 0.05/0.15 m) and ``movable-seawall`` (sec. 4.4: wall at 2.5 m on a
spring, d = 0.2 m, m = 250 kg/m, k = 10 N/m, H = 0.1 m our choice) with adami, dbc and
ghost-shepard. Writes validation/waves/runs/waves_<case>_<model>.csv (not committed),
validation/waves/img/waves_*.png and docs/waves_results.md.
"""

import argparse
import csv
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)
OUT = os.path.join(HERE, "runs")
DOCS = os.path.join(ROOT, "docs")
MODELS = ["adami", "dbc", "ghost-shepard"]


def run(case, model, dx, t_end, threads):
    from seawall.cases import build

    sim = build(case, boundary=model, dx=dx, threads=threads)
    sim.add(every=0.01)
    t0 = time.perf_counter()
    try:
        res = sim.run(t_end, progress=False)
        status = "ok"
    except Exception as exc:  # an unstable run is a result too: keep what was sampled
        res = sim.result({})
        status = f"{type(exc).__name__}: {str(exc)[:120]}"
    path = os.path.join(OUT, f"waves_{case}_{model}.csv")
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time"] + list(res.probes))
        for k in range(res.times.size):
            w.writerow([res.times[k]] + [res.probes[p][k] for p in res.probes])
    return sim, res, status, time.perf_counter() - t0


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", nargs="+", default=MODELS)
    parser.add_argument("--seawall-dx", type=float, default=0.025)
    parser.add_argument("--movable-dx", type=float, default=0.02)
    parser.add_argument("--cases", nargs="+", default=["movable-seawall", "solitary-seawall"])
    parser.add_argument("--threads", type=int, default=None)
    args = parser.parse_args(argv)
    os.makedirs(OUT, exist_ok=True)
    os.makedirs(os.path.join(HERE, "img"), exist_ok=True)
    lines = ["# Wave cases: measured numbers", "", "Written by `python validation/waves/run.py`.", ""]
    if "solitary-seawall" in args.cases:
        results = {}
        lines += [f"## solitary-seawall, dx = {args.seawall_dx} m", "",
                  "| model | status | max eta at 2/4/6/8 m [m] | max P0 [Pa] | max P1 [Pa] | max F* pairwise | "
                  "max F* pressure | max run-up [m] | wall time [s] |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for model in args.models:
            sim, res, status, wall = run("solitary-seawall", model, args.seawall_dx, 7.0, args.threads)
            results[model] = (sim, res)
            fs = sim.reference["static_force"]
            etas = "/".join(f"{np.nanmax(res[f'eta_{x}']):.3f}" for x in (2, 4, 6, 8))
            lines.append(f"| {model} | {status} | {etas} | {np.nanmax(res['P0']):.0f} | {np.nanmax(res['P1']):.0f} | "
                         f"{np.nanmax(res['Fx_wall']) / fs:.2f} | {np.nanmax(res['Fx_wall_p']) / fs:.2f} | "
                         f"{np.nanmax(res['runup']):.3f} | {wall:.0f} |")
            print(lines[-1], flush=True)
        fig, axes = plt.subplots(2, 2, figsize=(10, 7))
        for model, (sim, res) in results.items():
            t = res.times
            fs = sim.reference["static_force"]
            for x, ls in zip((2, 4, 6, 8), ("-", "--", "-.", ":")):
                axes[0, 0].plot(t, res[f"eta_{x}"], ls, lw=0.8, label=f"{model} x={x} m" if x in (2, 8) else None)
            axes[0, 1].plot(t, res["P0"], lw=0.8, label=f"{model} P0 (y=0.05)")
            axes[0, 1].plot(t, res["P1"], "--", lw=0.8, label=f"{model} P1 (y=0.15)")
            axes[1, 0].plot(t, res["Fx_wall"] / fs, lw=0.8, label=f"{model} pairwise (eq. 29)")
            axes[1, 0].plot(t, res["Fx_wall_p"] / fs, "--", lw=0.8, label=f"{model} integrated pressure")
            axes[1, 1].plot(t, res["runup"], lw=0.8, label=model)
        for ax, title in zip(axes.flat, ("surface gauges eta [m]", "wall pressure [Pa]",
                                         "F* = Fx / F_static", "run-up on the wall [m]")):
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("t [s]")
            ax.legend(fontsize=6)
        fig.suptitle(f"solitary-seawall (H 0.15 m, d 0.25 m, wall 120 deg), dx = {args.seawall_dx} m")
        fig.tight_layout()
        fig.savefig(os.path.join(HERE, "img", "waves_solitary_seawall.png"), dpi=100)
        lines.append("")
    if "movable-seawall" in args.cases:
        results = {}
        lines += [f"## movable-seawall, dx = {args.movable_dx} m", "",
                  "| model | status | onset [s] | wall x at 4 s [m] | max x* | max F* pairwise | max F* pressure | "
                  "max run-up [m] | wall time [s] |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for model in args.models:
            sim, res, status, wall = run("movable-seawall", model, args.movable_dx, 4.0, args.threads)
            results[model] = (sim, res)
            spring = sim.couplings[0]
            fs = sim.reference["static_force"]
            onset = f"{spring.onset_time:.2f}" if spring.onset_time is not None else "-"
            lines.append(f"| {model} | {status} | {onset} | {res['wall_x'][-1]:.3f} | {np.nanmax(res['x_star']):.2f} | "
                         f"{np.nanmax(res['F_star']):.2f} | {np.nanmax(res['Fx_wall_p']) / fs:.2f} | "
                         f"{np.nanmax(res['runup']):.3f} | {wall:.0f} |")
            print(lines[-1], flush=True)
        fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
        for model, (sim, res) in results.items():
            t = res.times
            fs = sim.reference["static_force"]
            axes[0].plot(t, res["F_star"], lw=0.8, label=f"{model} pairwise (eq. 29)")
            axes[0].plot(t, res["Fx_wall_p"] / fs, "--", lw=0.8, label=f"{model} integrated pressure")
            axes[1].plot(t, res["x_star"], lw=0.8, label=model)
            axes[2].plot(t, res["runup"], lw=0.8, label=model)
        axes[0].axhline(1.10, color="k", lw=0.5)
        for ax, title in zip(axes, ("F* = F / F_static (line: threshold 1.10)", "x* = X / d", "run-up [m]")):
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("t [s]")
            ax.legend(fontsize=6)
        fig.suptitle(f"movable-seawall (d 0.2 m, H 0.1 m, m 250 kg/m, k 10 N/m), dx = {args.movable_dx} m")
        fig.tight_layout()
        fig.savefig(os.path.join(HERE, "img", "waves_movable_seawall.png"), dpi=100)
        lines.append("")
    with open(os.path.join(DOCS, "waves_results.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
