"""Why the impact at Buchner's P1 arrives late and peaks low (issue 15, item 6).

Runs the H = 0.6 m dam break (case ``dam-break``, Adami wall, free slip) with the
validation entry's settings (or a variant) and samples at every step:

* ``front``  -- the x of the foremost fluid particle (when does the water reach the wall?);
* ``S1``, ``S3``, ``P1`` -- the point probes at y = 0.010, 0.100 and 0.2 H on the downstream wall;
* ``P1face`` -- the sensor face of one kernel support (the default face), ``P1dx`` -- a face of one
  particle spacing, ``P1half`` -- half a support;
* ``wet``    -- the number of fluid particles within one support of P1 (when is the sensor wet?);
* ``run_up`` -- the height of the highest fluid particle within 2 dx of the downstream wall.

Derived per run: when the front passes 3, 4 and 5 H and reaches the wall, when P1 gets wet and the
run-up passes 0.2 H, the features of :func:`seawall.diagnostics.impact_features` on the 0.25 ms means
(raw and on the entry's 0.1 t* running mean) for every read-out and for S1 and S3, and the mean p* over
the early impact (``EARLY``). The step series go to validation/dam-break/runs/arrival_study/ and the
derived figures to validation/dam-break/results/arrival_study.json. Command::

    NUMBA_NUM_THREADS=1 python validation/dam-break/arrival_study.py --n 50 --variant entry [--t-star 3.5]
    python validation/dam-break/arrival_study.py --table
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
from seawall.diagnostics import impact_features, interval_mean, pressure_noise, running_mean  # noqa: E402

H = 0.6
G = 9.81
RHO0 = 1000.0
EVERY = 2.5e-4
OUT = os.path.join(ROOT, "validation", "dam-break", "results", "arrival_study.json")
RUNS = os.path.join(ROOT, "validation", "dam-break", "runs", "arrival_study")
C10 = 10.0 * math.sqrt(G * H)
#: the early impact: t* window over which the mean pressure is compared (Buchner's P1 rises to ~0.6 in it)
EARLY = (2.55, 2.85)
DATA = os.path.join(ROOT, "data", "buchner2002_dambreak2d_P1")

#: variants: name -> (case parameters beyond the defaults, what they are)
VARIANTS = {
    "entry": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": C10},
              "the validation entry: Riemann formulation, eta = 3, c0 = 10 sqrt(gH)"),
    "default": ({}, "case defaults: c0 = 10 sqrt(2gH), delta-SPH delta = 0.1, alpha = 0.02"),
    "entry-analytic": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": C10, "initial": "analytic"},
                       "as entry, initial pressure from the Laplace problem instead of p = 0"),
    "entry-cfl0.1": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": C10, "cfl": 0.1},
                     "as entry, CFL 0.1"),
    "entry-noslip": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": C10, "boundary": "adami",
                      "slip": "noslip", "wall_nu": 1.0e-6},
                     "as entry, no-slip walls with water's viscosity nu = 1e-6 m^2/s (Adami wall velocity)"),
    "alpha0.05": ({"alpha": 0.05}, "case defaults with artificial viscosity alpha = 0.05"),
    "entry-open3": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": C10, "lid": False, "tank_height": 3.0},
                    "as entry, no lid and walls 3 H high (the case closes the tank at 2 H)"),
    "entry-h2": ({"riemann": True, "alpha": 0.0, "delta": 0.0, "c0": C10, "h_factor": 2.0},
                 "as entry, h = 2 dx instead of 1.3 dx (cubic spline support 4 dx instead of 2.6 dx)"),
    "huang2019": ({"scheme": "marrone2011", "c0": C10, "initial": "analytic"},
                  "[Huang2019]'s fluid for this case: delta-SPH of Marrone et al. (linear EOS, Gaussian cut at 3 h, "
                  "alpha = 0.02 on all pairs, delta = 0.1), c0 = 10 sqrt(gH), initial pressure from the Laplace problem"),
}


class Wet(probes.Probe):
    """Number of fluid particles within ``radius`` of ``point``."""

    def __init__(self, name, point, radius):
        super().__init__(name)
        self.point = np.asarray(point, dtype=float)
        self.radius = radius

    def sample(self, sim):
        x = sim.fluid.particles["x"]
        return float(np.count_nonzero(np.sum((x - self.point) ** 2, axis=1) < self.radius ** 2))


class RunUp(probes.Probe):
    """Height of the highest fluid particle within ``band`` of the wall at ``x_wall`` (0 if none)."""

    def __init__(self, name, x_wall, band):
        super().__init__(name)
        self.x_wall = x_wall
        self.band = band

    def sample(self, sim):
        x = sim.fluid.particles["x"]
        near = x[:, 0] > self.x_wall - self.band
        return float(x[near, 1].max()) if near.any() else 0.0


def run(name, n, t_star):
    overrides, _ = VARIANTS[name]
    overrides = dict(overrides)
    boundary = overrides.pop("boundary", "adami")
    dx = H / n
    sim = cases.build("dam-break", boundary=boundary, H=H, dx=dx, threads=1, **overrides)
    keep = {"S1", "S3", "P1", "front"}
    sim.probes[:] = [p for p in sim.probes if p.name in keep]
    length = sim.probes[[p.name for p in sim.probes].index("P1")].point[0]
    support = sim.kernel.support(sim.h)
    sim.add(probes.PressureSensor("P1face", (length, 0.2 * H)),
            probes.PressureSensor("P1half", (length, 0.2 * H), diameter=0.5 * support),
            probes.PressureSensor("P1dx", (length, 0.2 * H), diameter=dx),
            Wet("wet", (length, 0.2 * H), support), RunUp("run_up", length, 2 * dx))
    sim.add(every=1e-9)
    started = time.time()
    res = sim.run(t_star / math.sqrt(G / H), progress=False)
    wall = time.time() - started
    os.makedirs(RUNS, exist_ok=True)
    cols = ["front", "S1", "S3", "P1", "P1face", "P1half", "P1dx", "wet", "run_up"]
    np.savez_compressed(os.path.join(RUNS, f"h{n}_{name}.npz"), t=res.times, **{c: res[c] for c in cols})
    fx = sim.fluid.particles["x"]
    return {"wall_time_s": wall, "steps": res.summary["steps"], "n_fluid": int(fx.shape[0]), "length": float(length),
            "dx": dx, "support": float(support)}


def first_time(ts, mask):
    return float(ts[np.argmax(mask)]) if mask.any() else math.nan


def analyse(name, n, info):
    d = np.load(os.path.join(RUNS, f"h{n}_{name}.npz"))
    t = d["t"]
    ts = t * math.sqrt(G / H)
    length, dx = info["length"], info["dx"]
    out = dict(info)
    # the front reaches the wall: foremost particle within dx/2 (its centre) of the wall surface
    out["front_at_wall"] = first_time(ts, d["front"] >= length - 0.5 * dx - 1e-12)
    out["front_at"] = {f"{x:g}": first_time(ts, d["front"] >= x * H) for x in (3.0, 4.0, 5.0)}
    out["wet_P1"] = first_time(ts, d["wet"] > 0)
    out["run_up_P1"] = first_time(ts, d["run_up"] >= 0.2 * H)
    out["run_up_2H"] = first_time(ts, d["run_up"] >= 2.0 * H - 0.5 * dx)
    out["run_up_max"] = float(d["run_up"].max() / H)
    noise = pressure_noise(*interval_mean(t, d["P1"], EVERY))     # as the entry: on the 0.25 ms means
    out["noise"] = None if noise is None else noise / (RHO0 * G * H)
    rho_g_h = RHO0 * G * H
    feats = {}
    for col in ("P1", "P1face", "P1half", "P1dx", "S1", "S3"):
        tt, pp = interval_mean(t, d[col], EVERY)
        tts = tt * math.sqrt(G / H)
        ps = pp / rho_g_h
        smooth = running_mean(tts, ps, 0.1)
        f = impact_features(tts, smooth)
        raw = impact_features(tts, ps)
        feats[col] = {"arrival": f[0], "first_peak": f[1], "arrival_raw": raw[0], "first_peak_raw": raw[1],
                      "first_nonzero": first_time(tts, (tts > 1.0) & (ps > 0.02)),
                      "p_raw_max": float(np.nanmax(np.where((tts > 2.0) & (tts < 3.3), ps, -np.inf))),
                      "t_raw_max": float(tts[np.argmax(np.where((tts > 2.0) & (tts < 3.3), ps, -np.inf))]),
                      "early_mean": float(np.mean(ps[(tts > EARLY[0]) & (tts < EARLY[1])])),
                      "plateau": f[2], "secondary_peak": f[3], "secondary_time": f[5]}
    out["features"] = feats
    return out


def buchner_early():
    """Mean p* of each digitisation of Buchner's P1 over the EARLY window (linear between the points)."""
    out = []
    for name in ("buchner2002_P1_pysph.csv", "buchner2002_P1_jaxsph.csv"):
        d = np.loadtxt(os.path.join(DATA, name), delimiter=",", skiprows=1)
        d = d[np.argsort(d[:, 0], kind="stable")]
        grid = np.linspace(EARLY[0], EARLY[1], 200)
        out.append(float(np.mean(np.interp(grid, d[:, 0], d[:, 1]))))
    return out


def load():
    if os.path.exists(OUT):
        with open(OUT) as fh:
            return json.load(fh)
    return {}


def table():
    res = load()
    lines = ["| run | front at x = 3/4/5 H | front at the wall | P1 wet | run-up reaches P1 | P1 > 0.02 | "
             "arrival (0.1 t* mean) | arrival (raw 0.25 ms) | first peak (0.1 t* mean) | largest p* 2-3.3 (raw) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for key, r in res.items():
        f = r["features"]["P1"]
        fa = r["front_at"]
        lines.append(f"| {key} | {fa['3']:.3f} / {fa['4']:.3f} / {fa['5']:.3f} | {r['front_at_wall']:.3f} | "
                     f"{r['wet_P1']:.3f} | {r['run_up_P1']:.3f} | {f['first_nonzero']:.3f} | {f['arrival']:.3f} | "
                     f"{f['arrival_raw']:.3f} | {f['first_peak']:.3f} | {f['p_raw_max']:.3f} at {f['t_raw_max']:.3f} |")
    early = buchner_early()
    lines += ["", f"Mean p* over {EARLY[0]:g} < t* < {EARLY[1]:g} (Buchner P1: {early[0]:.3f} / {early[1]:.3f}, "
              "the two digitisations):", "", "| run | S1 (0.01 H) | S3 (0.1 H) | P1 (0.2 H) |", "| --- | --- | --- | --- |"]
    for key, r in res.items():
        f = r["features"]
        lines.append(f"| {key} | {f['S1']['early_mean']:.3f} | {f['S3']['early_mean']:.3f} | {f['P1']['early_mean']:.3f} |")
    lines += ["", "| run | read-out | arrival | first peak (0.1 t* mean) | largest p* 2-3.3 (raw) |",
              "| --- | --- | --- | --- | --- |"]
    for key, r in res.items():
        for col in ("P1", "P1face", "P1half", "P1dx"):
            f = r["features"][col]
            lines.append(f"| {key} | {col} | {f['arrival']:.3f} | {f['first_peak']:.3f} | "
                         f"{f['p_raw_max']:.3f} at {f['t_raw_max']:.3f} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=50)
    ap.add_argument("--variant", default="entry", choices=list(VARIANTS))
    ap.add_argument("--t-star", type=float, default=3.5)
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--analyse-only", action="store_true")
    args = ap.parse_args(argv)
    if not args.table:
        key = f"h{args.n}_{args.variant}"
        res = load()
        info = res.get(key, {}) if args.analyse_only else run(args.variant, args.n, args.t_star)
        if not info:
            ap.error(f"{key} is not stored; run it first")
        info = {k: info[k] for k in ("wall_time_s", "steps", "n_fluid", "length", "dx", "support")}
        res = load()
        res[key] = analyse(args.variant, args.n, info)
        os.makedirs(os.path.dirname(OUT), exist_ok=True)
        with open(OUT, "w") as fh:
            json.dump(res, fh, indent=1)
    print(table())


if __name__ == "__main__":
    main()
