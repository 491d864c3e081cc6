"""Impact pressure at Buchner's sensor P1: what makes it quiet and right (issue 15, item 6).

Runs the H = 0.6 m dam break (case ``dam-break``, Adami wall, free slip) to
t sqrt(g/H) = 7.5 once per *variant* -- one choice changed at a time from the
case's defaults -- and tabulates, for each, the features that
``seawall validate dam-break`` checks against Buchner (2002) (arrival, first
peak, plateau mean, secondary peak and its time, from
:func:`seawall.diagnostics.impact_features`) and the noise: RMS of p about
its 0.05 s running mean (:func:`seawall.diagnostics.pressure_noise`), in
rho g H.

Every run samples its probes at every time step. From that one series the
study derives the *read-out* choices without another run:

* ``point``        -- the point probe (WallPressure, Adami extrapolation from the fluid)
  read every 2.5e-4 s (the validation entry's sampling so far);
* ``point-avg``    -- the same probe averaged over each 2.5e-4 s interval (box filter, what a
  transducer read out at 4 kHz with a response that integrates over its interval reports);
* ``point-avg1ms`` -- averaged over 1e-3 s (1 kHz);
* ``face-avg``     -- the PressureSensor (face of one kernel support) averaged over 2.5e-4 s;
* ``wall-avg``     -- the pressure of the Adami wall particles (first layer, linear between the two
  nearest to the sensor's height) averaged over 2.5e-4 s.

Command (single thread, one run after another; results in
validation/dam-break/results/pressure_study_h<N>.json, step series in validation/dam-break/runs/pressure_study/)::

    NUMBA_NUM_THREADS=1 python validation/dam-break/pressure_study.py [--n 50] [--only NAME ...] [--table]

``--table`` prints the markdown table of the stored results without running.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)

from seawall import cases, probes  # noqa: E402
from seawall.diagnostics import IMPACT_FEATURES, impact_features, interval_mean, pressure_noise, running_mean  # noqa: E402

H = 0.6
G = 9.81
RHO0 = 1000.0
T_STAR_END = 7.5
EVERY = 2.5e-4
DATA = os.path.join(ROOT, "data", "buchner2002_dambreak2d_P1")
OUT = os.path.join(ROOT, "validation", "dam-break", "results")
RUNS = os.path.join(ROOT, "validation", "dam-break", "runs", "pressure_study")

#: the variants: name -> (case parameters changed from the defaults, what the change is)
VARIANTS = {
    "default": ({}, "case defaults: c0 = 10 sqrt(2gH), CFL 0.2, delta-SPH (renormalised) delta = 0.1, alpha = 0.02"),
    "cfl0.1": ({"cfl": 0.1}, "CFL 0.1 (half the time step)"),
    "c0-10": ({"c0": 10.0 * math.sqrt(G * H)}, "c0 = 10 sqrt(gH) (Mach <= 0.14)"),
    "c0-20": ({"c0": 20.0 * math.sqrt(G * H)}, "c0 = 20 sqrt(gH)"),
    "delta0.2": ({"delta": 0.2}, "delta-SPH delta = 0.2"),
    "molteni": ({"diffusion": "molteni"}, "Molteni-Colagrossi diffusion (no renormalised gradient), delta = 0.1"),
    "alpha0.05": ({"alpha": 0.05}, "artificial viscosity alpha = 0.05"),
    "analytic": ({"initial": "analytic"}, "initial pressure from the Laplace problem instead of rest"),
    "riemann": ({"riemann": True, "alpha": 0.0, "delta": 0.0},
                "Riemann continuity and momentum, low-dissipation limiter eta = 3 ([Zhang2017]); no alpha, no delta"),
    "riemann-c0-10": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": 10.0 * math.sqrt(G * H)},
                      "Riemann formulation (as riemann) with c0 = 10 sqrt(gH)"),
    "riemann-c0-10-eta1": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": 10.0 * math.sqrt(G * H),
                            "riemann_eta": 1.0},
                           "as riemann-c0-10 with the limiter's eta = 1 (less dissipation)"),
}


class WallParticlePressure(probes.Probe):
    """Pressure of the wall's first particle layer at a height on the right wall, linear between the two
    wall particles nearest in height (the Adami wall pressure, not an interpolation from the fluid)."""

    def __init__(self, name, x_wall, y, dx):
        super().__init__(name)
        self.x_wall = x_wall
        self.y = y
        self.dx = dx
        self.pair = None

    def sample(self, sim):
        wall = sim.walls[0]
        pa = wall.particles
        if self.pair is None:
            x = pa["x"]
            first = np.abs(x[:, 0] - (self.x_wall + 0.5 * self.dx)) < 0.25 * self.dx
            idx = np.nonzero(first)[0]
            order = idx[np.argsort(np.abs(x[idx, 1] - self.y))][:2]
            self.pair = order[np.argsort(x[order, 1])]
        a, b = self.pair
        ya, yb = pa["x"][a, 1], pa["x"][b, 1]
        s = (self.y - ya) / (yb - ya)
        pb = sim.physics.p_background
        return float((1 - s) * (pa["p"][a] - pb) + s * (pa["p"][b] - pb))


def references():
    """Buchner's P1 (two digitisations) and the mean of their features."""
    refs = []
    for name in ("buchner2002_P1_pysph.csv", "buchner2002_P1_jaxsph.csv"):
        d = np.loadtxt(os.path.join(DATA, name), delimiter=",", skiprows=1)
        refs.append(d[np.argsort(d[:, 0], kind="stable")])
    feats = np.array([impact_features(d[:, 0], d[:, 1]) for d in refs])
    return refs, np.nanmean(feats, axis=0)


def run_variant(name, n):
    overrides, _ = VARIANTS[name]
    dx = H / n
    sim = cases.build("dam-break", boundary="adami", H=H, dx=dx, threads=1, **overrides)
    length = sim.probes[[p.name for p in sim.probes].index("P1")].point[0]
    sim.add(probes.PressureSensor("P1face", (length, 0.2 * H)), WallParticlePressure("P1wall", length, 0.2 * H, dx))
    sim.add(every=1e-9)          # every step
    started = time.time()
    res = sim.run(T_STAR_END / math.sqrt(G / H), progress=False)
    wall = time.time() - started
    os.makedirs(RUNS, exist_ok=True)
    np.savez_compressed(os.path.join(RUNS, f"h{n}_{name}.npz"), t=res.times, P1=res["P1"], P1face=res["P1face"],
                        P1wall=res["P1wall"])
    return {"wall_time_s": wall, "steps": res.summary["steps"], "n_fluid": res.summary["n_fluid"],
            "escaped": res.summary["escaped_particles"], "status": res.summary.get("status", "completed")}


def readouts(t, series):
    """The read-out choices: name -> (times, p [Pa]) from step-sampled probes."""
    p1 = series["P1"]
    # point read every EVERY: the first step at or after each multiple
    k = np.floor(t / EVERY + 1e-9).astype(np.int64)
    first = np.r_[True, k[1:] != k[:-1]]
    out = {"point": (t[first], p1[first])}
    out["point-avg"] = interval_mean(t, p1, EVERY)
    out["point-avg1ms"] = interval_mean(t, p1, 1e-3)
    out["face-avg"] = interval_mean(t, series["P1face"], EVERY)
    out["wall-avg"] = interval_mean(t, series["P1wall"], EVERY)
    return out


def evaluate(t, p):
    ts = t * math.sqrt(G / H)
    ps = p / (RHO0 * G * H)
    feats = impact_features(ts, running_mean(ts, ps, 0.1))
    noise = pressure_noise(t, p)
    return dict(zip(IMPACT_FEATURES, feats), noise=None if noise is None else noise / (RHO0 * G * H))


def analyse(name, n, info):
    d = np.load(os.path.join(RUNS, f"h{n}_{name}.npz"))
    t = d["t"]
    rows = {}
    for readout, (tt, pp) in readouts(t, {k: d[k] for k in ("P1", "P1face", "P1wall")}).items():
        rows[readout] = evaluate(tt, pp)
    return {**info, "readouts": rows}


def results_path(n):
    return os.path.join(OUT, f"pressure_study_h{n}.json")


def load(n):
    path = results_path(n)
    if os.path.exists(path):
        with open(path) as fh:
            return json.load(fh)
    return {}


def table(n, readout_rows=("point", "point-avg")):
    _, ref = references()
    res = load(n)
    ref_d = dict(zip(IMPACT_FEATURES, ref))
    lines = [f"H/{n}: Buchner (mean of the two digitisations): arrival {ref_d['arrival']:.3f}, first peak "
             f"{ref_d['first_peak']:.3f}, plateau {ref_d['plateau']:.3f}, secondary peak "
             f"{ref_d['secondary_peak']:.3f} at t* {ref_d['secondary_time']:.3f}. Variants:", ""]
    lines += [f"* `{k}` -- {res[k].get('change', VARIANTS.get(k, ('', ''))[1])}" for k in
              [k for k in VARIANTS if k in res] + [k for k in res if k not in VARIANTS]]
    lines += ["",
             "| variant | read-out | arrival t* (±0.1) | first peak p* (±20 %) | plateau p* (±10 %) | "
             "secondary p* | secondary t* (±0.15) | noise / rho g H (<= 0.10) | run [s] |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]

    def fmt(v, r=None, rel=False):
        if v is None or not math.isfinite(v):
            return "n/a"
        if r is None:
            return f"{v:.3f}"
        return f"{v:.3f} ({100 * (v - r) / r:+.0f} %)" if rel else f"{v:.3f} ({v - r:+.3f})"
    # stored results of variants no longer in VARIANTS (an earlier form of a choice) are listed last
    for name in [k for k in VARIANTS if k in res] + [k for k in res if k not in VARIANTS]:
        info = res[name]
        for readout, f in info["readouts"].items():
            if name != "default" and readout not in readout_rows:
                continue
            lines.append(f"| {name} | {readout} | {fmt(f['arrival'], ref_d['arrival'])} | "
                         f"{fmt(f['first_peak'], ref_d['first_peak'], True)} | {fmt(f['plateau'], ref_d['plateau'], True)} | "
                         f"{fmt(f['secondary_peak'], ref_d['secondary_peak'], True)} | "
                         f"{fmt(f['secondary_time'], ref_d['secondary_time'])} | {fmt(f['noise'])} | "
                         f"{info['wall_time_s']:.0f} |")
    names = [k for k in VARIANTS if k in res] + [k for k in res if k not in VARIANTS]
    readout_names = list(res[names[0]]["readouts"]) if names else []
    lines += ["", "Noise / (rho g H) of every read-out:", "",
              "| variant | steps | " + " | ".join(readout_names) + " |",
              "| --- | --- | " + " | ".join("---" for _ in readout_names) + " |"]
    for name in names:
        r = res[name]["readouts"]
        lines.append(f"| {name} | {res[name]['steps']} | " + " | ".join(fmt(r[k]["noise"]) for k in readout_names) + " |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=50, help="particles per H (dx = H/n), default 50")
    ap.add_argument("--only", nargs="*", help="variants to run (default: all not yet stored)")
    ap.add_argument("--rerun", action="store_true", help="run variants even if stored")
    ap.add_argument("--table", action="store_true", help="print the table of stored results only")
    args = ap.parse_args(argv)
    if not args.table:
        names = args.only or list(VARIANTS)
        unknown = [x for x in names if x not in VARIANTS]
        if unknown:
            ap.error(f"unknown variant {unknown[0]!r}; variants: {', '.join(VARIANTS)}")
        for name in names:
            res = load(args.n)
            if name in res and not args.rerun:
                continue
            print(f"running {name} at H/{args.n} ...", flush=True)
            info = run_variant(name, args.n)
            res = load(args.n)
            res[name] = {"change": VARIANTS[name][1], **analyse(name, args.n, info)}
            os.makedirs(OUT, exist_ok=True)
            with open(results_path(args.n), "w") as fh:
                json.dump(res, fh, indent=1)
            print(f"  done in {info['wall_time_s']:.0f} s, {info['steps']} steps", flush=True)
    print(table(args.n))


if __name__ == "__main__":
    main()
