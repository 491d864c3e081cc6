"""Plateau pressure profile on the downstream wall of the dam break, every wall model (issue 15, item 7).

    python validation/dam-break/plateau_profiles.py --resolution 50                # every model at H/50
    python validation/dam-break/plateau_profiles.py --resolution 100 --models adami,dbc
    python validation/dam-break/plateau_profiles.py --report-only                  # table + plot from stored results

The runs are those of the leak sweep (``validation/leaks/sweep.py``): the ``dam-break`` case
(H = 0.3 m, closed tank) to t sqrt(g/H) = 8, each model in its own process. The sweep
adds the probes of :func:`add_probes` to every run and stores, next to the leak row, the
plateau means of :func:`plateau_means`, so one run per model gives both the leak row
(docs/boundaries.md) and the plateau profile (docs/validation-notes.md). This script runs
the sweep for the chosen models and resolution, copies the plateau part into
``validation/dam-break/results/plateau_H<N>.json``, and writes the table and the plot
(``validation/dam-break/img/plateau_profiles.png``) into docs/validation-notes.md between
``<!-- plateau-table:begin -->`` and ``<!-- plateau-table:end -->``.

Plateau: mean of p / (rho0 g H) over 3 <= t sqrt(g/H) <= 5.5 on the downstream wall
(x = L) at y/H = 0.01, 0.05, 0.1, 0.2, 0.27, by four read-outs:

* ``wall``   -- :class:`seawall.probes.WallPressure` at the wall surface (the case's S1-S4/P1
  probes: fluid pressure extrapolated with the hydrostatic term);
* ``int1.6`` -- :class:`seawall.probes.Pressure` (plain Shepard mean of the fluid) at
  x = L - 1.6 dx, inside the fluid (the read-out of the issue's first measurement);
* ``face``   -- :class:`seawall.probes.PressureSensor`, face of one kernel support;
* ``layer``  -- the wall's own first particle layer (linear in y between the two nearest), for
  the models whose wall particles carry a pressure (n/a otherwise);
* ``force``  -- the force the wall exerts on the fluid, per unit wall area: minus the sum of
  m_i times the wall's contribution to the x-acceleration of the fluid particles i within 3 h of
  the wall and with y in [y - dx, y + dx] (clipped at the floor), divided by that band's height.
  It reads the momentum each model actually exchanges, whatever its wall particles' pressure
  means (a DBC wall's particle pressure is not the fluid's; its fluid keeps a gap).
"""

import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RESULTS = os.path.join(HERE, "results")
IMG = os.path.join(HERE, "img")
DOC = os.path.join(ROOT, "docs", "validation-notes.md")
BEGIN = "<!-- plateau-table:begin -->"
END = "<!-- plateau-table:end -->"
HEIGHTS = (0.01, 0.05, 0.1, 0.2, 0.27)
READOUTS = ("wall", "int1.6", "face", "layer", "force")
WINDOW = (3.0, 5.5)
G = 9.81
RHO0 = 1000.0


def sweep_module():
    """validation/leaks/sweep.py: the dam break the profiles are taken on, and its results."""
    from seawall.validation import load_script

    return load_script(os.path.join(ROOT, "validation", "leaks", "sweep.py"))


def probe_name(readout, frac):
    return f"plateau_{readout}_{frac:g}"


def _layer_probe_class():
    from seawall import probes

    class _WallLayerPressure(probes.Probe):
        unit = "Pa"

        def __init__(self, name, x_wall, y, dx):
            super().__init__(name)
            self.x_wall, self.y, self.dx = x_wall, y, dx
            self.pair = None

        def sample(self, sim):
            pa = sim.walls[0].particles
            if "p" not in pa:
                return float("nan")
            x = pa["x"]
            if self.pair is None:
                # the first layer: wall particles nearest to the surface behind it (dx/2 for layered
                # walls, on it for one-row walls)
                beyond = x[:, 0] >= self.x_wall - 1e-9
                if not beyond.any():
                    return float("nan")
                first_x = x[beyond, 0].min()
                idx = np.nonzero(np.abs(x[:, 0] - first_x) < 0.25 * self.dx)[0]
                order = idx[np.argsort(np.abs(x[idx, 1] - self.y))][:2]
                self.pair = order[np.argsort(x[order, 1])]
            a, b = self.pair
            ya, yb = x[a, 1], x[b, 1]
            s = (self.y - ya) / (yb - ya) if yb != ya else 0.0
            pb = sim.physics.p_background
            return float((1 - s) * (pa["p"][a] - pb) + s * (pa["p"][b] - pb))

    return _WallLayerPressure


#: times t sqrt(g/H) of the snapshots of the corner region kept for the diagnosis (within the window)
SNAPSHOT_T_STAR = (3.5, 4.0, 4.5, 5.0)


def _snapshot_probe_class():
    from seawall import probes

    class _CornerSnapshots(probes.Probe):
        """Saves every fluid particle and the wall particles within 0.5 H of the downstream wall at
        the times of :data:`SNAPSHOT_T_STAR` to an npz file, with ``dx`` and the wall's surface
        ``surface_x``; samples the number saved so far."""

        def __init__(self, path, length, H):
            super().__init__("plateau_snapshots")
            self.path, self.length, self.H = path, length, H
            self.saved = {}

        def sample(self, sim):
            ts = sim.time * math.sqrt(G / self.H)
            for k, target in enumerate(SNAPSHOT_T_STAR):
                if k in self.saved or ts < target:
                    continue
                pb = sim.physics.p_background
                fp = sim.fluid.particles
                near = np.ones(fp.n, dtype=bool)
                snap = {f"f{k}_{n}": np.array(fp[n][near]) for n in ("x", "v", "rho", "p") if n in fp}
                snap[f"f{k}_p"] = snap[f"f{k}_p"] - pb
                wp = sim.walls[0].particles
                wnear = wp["x"][:, 0] > self.length - 0.5 * self.H
                for n in ("x", "v", "rho", "p"):
                    if n in wp:
                        snap[f"w{k}_{n}"] = np.array(wp[n][wnear]) - (pb if n == "p" else 0.0)
                snap[f"t{k}"] = np.array(sim.time)
                self.saved[k] = snap
                # dx and the downstream wall's surface, so that readers need not infer them from
                # the wall particles (a one-row wall's spacing is not dx)
                merged = {"dx": np.array(sim.fluid.spacing), "surface_x": np.array(self.length)}
                for d in self.saved.values():
                    merged.update(d)
                np.savez_compressed(self.path, **merged)
            return float(len(self.saved))

    return _CornerSnapshots


def _force_probe_class():
    from seawall import probes

    class _BandForce(probes.Probe):
        """Horizontal force per unit area that the fluid in a band of heights exerts on the wall x = length
        (see the module doc, read-out ``force``)."""

        unit = "Pa"

        def __init__(self, name, length, y, dx):
            super().__init__(name)
            self.wall = "tank"          # asks the simulation to keep this wall's force and accelerations
            self.length, self.y, self.dx = length, y, dx

        def sample(self, sim):
            dvw = sim.wall_accelerations.get(self.wall)
            fp = sim.fluid.particles
            if dvw is None or dvw.shape[0] != fp.n:
                return float("nan")
            x = fp["x"]
            lo = max(0.0, self.y - self.dx)
            hi = self.y + self.dx
            sel = (x[:, 0] > self.length - 3.0 * sim.h) & (x[:, 1] >= lo) & (x[:, 1] < hi)
            # force of the fluid on the wall along +x = minus the wall's force on the fluid
            return float(-np.sum(fp["m"][sel] * dvw[sel, 0]) / (hi - lo))

    return _BandForce


def add_probes(sim, H, dx, snapshots=None):
    """Add the plateau read-outs at every height of :data:`HEIGHTS` to a dam-break simulation
    (and, with ``snapshots`` a file path, the corner snapshots of :data:`SNAPSHOT_T_STAR`)."""
    from seawall import probes

    length = sim.probes[[p.name for p in sim.probes].index("P1")].point[0]
    layer = _layer_probe_class()
    force = _force_probe_class()
    added = []
    for frac in HEIGHTS:
        y = frac * H
        added += [probes.WallPressure(probe_name("wall", frac), (length, y)),
                  probes.Pressure(probe_name("int1.6", frac), (length - 1.6 * dx, y)),
                  probes.PressureSensor(probe_name("face", frac), (length, y)),
                  layer(probe_name("layer", frac), length, y, dx),
                  force(probe_name("force", frac), length, y, dx)]
    if snapshots is not None:
        added.append(_snapshot_probe_class()(snapshots, length, H))
    sim.add(*added)
    return length


def plateau_means(times, series, H, rho0=RHO0):
    """{readout: {frac: mean p/(rho0 g H) over the window}} from probe series (NaN-free samples only);
    with the window's standard deviation under ``readout + "_std"``."""
    t = np.asarray(times, dtype=float) * math.sqrt(G / H)
    sel = (t >= WINDOW[0]) & (t <= WINDOW[1])
    out = {}
    for readout in READOUTS:
        means, stds = {}, {}
        for frac in HEIGHTS:
            p = np.asarray(series.get(probe_name(readout, frac), np.empty(0)), dtype=float)
            if p.size != t.size:
                continue
            v = p[sel][np.isfinite(p[sel])] / (rho0 * G * H)
            # a sample can be NaN (the force read-out right after a particle was removed); the mean
            # needs 90 % of the window's samples finite
            ok = v.size > 0 and v.size >= 0.9 * sel.sum()
            means[f"{frac:g}"] = float(v.mean()) if ok else None
            stds[f"{frac:g}"] = float(v.std()) if ok else None
        out[readout] = means
        out[readout + "_std"] = stds
    out["window_t_star"] = list(WINDOW)
    out["samples"] = int(sel.sum())
    return out


# ----------------------------------------------------------------------------- report
def results_path(resolution):
    return os.path.join(RESULTS, f"plateau_H{resolution}.json")


def collect(resolution):
    """Copy the plateau part of the sweep's stored records into results/plateau_H<N>.json."""
    sweep = sweep_module()
    data = sweep.load(resolution)
    path = results_path(resolution)
    stored = {}
    if os.path.exists(path):
        with open(path) as fh:
            stored = json.load(fh)
    stored.update({"case": "dam-break", "H": data.get("H"), "dx": data.get("dx"), "resolution": resolution})
    stored.setdefault("models", {})
    runs = os.path.join(ROOT, "validation", "leaks", "runs", f"H{resolution}")
    for key, rec in (data.get("models") or {}).items():
        probes_csv = os.path.join(runs, key.replace(" ", "_"), "probes.csv")
        if key in stored["models"] and not os.path.exists(probes_csv):
            # no run directory here (a fresh checkout): the stored profile is the full one; the
            # sweep's record may predate read-outs added later (e.g. force)
            continue
        if rec.get("plateau") and os.path.exists(probes_csv):
            # the run directory is still here: the means again from its probes (same numbers unless
            # this module's averaging changed)
            series = _read_csv(probes_csv)
            rec["plateau"] = plateau_means(series["t"], series, data.get("H") or 0.3)
        if rec.get("plateau"):
            stored["models"][key] = {"model": rec["model"], "params": rec.get("params", {}),
                                     "status": rec["status"], "t_stop": rec.get("t_stop"),
                                     "plateau": rec["plateau"]}
    if stored["models"]:
        os.makedirs(RESULTS, exist_ok=True)
        with open(path, "w") as fh:
            json.dump(stored, fh, indent=1, sort_keys=True)
            fh.write("\n")
    return stored


def _read_csv(path):
    import csv

    with open(path) as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].startswith("#")]
    head, body = rows[0], rows[1:]
    data = np.array([[float(v) if v not in ("", "nan") else np.nan for v in r] for r in body])
    return {name: data[:, k] for k, name in enumerate(head)}


def _stored():
    import glob

    out = {}
    for p in sorted(glob.glob(os.path.join(RESULTS, "plateau_H*.json"))):
        with open(p) as fh:
            d = json.load(fh)
        if d.get("models"):
            out[int(d["resolution"])] = d
    return out


def _fmt(v):
    return "n/a" if v is None else f"{v:.2f}"


#: the read-outs shown in the doc's table (every read-out is in the JSON)
TABLE_READOUTS = ("wall", "force", "layer")


def table(resolution, data, order):
    lines = [f"**H/{resolution}** (dx = {data['dx']:.4g} m). Plateau mean p/(rho0 g H) over "
             f"{WINDOW[0]:g} <= t sqrt(g/H) <= {WINDOW[1]:g} on the downstream wall, per read-out: wall "
             "(fluid pressure extrapolated to the surface, the case's S1-S4 probes), force (the wall's force on "
             "the fluid in a band of +-dx per unit area), layer (the wall's first particle layer); int1.6 and face "
             f"are in `validation/dam-break/results/plateau_H{resolution}.json`.", "",
             "| model | options | run | read-out | " + " | ".join(f"y/H = {f:g}" for f in HEIGHTS) + " |",
             "| --- | --- | --- | --- | " + " | ".join("---" for _ in HEIGHTS) + " |"]
    for key in order(data["models"]):
        r = data["models"][key]
        pl = r["plateau"]
        opts = ", ".join(f"{k}={v}" for k, v in sorted((r.get("params") or {}).items())) or "defaults"
        if r["status"] == "completed":
            run = "completed"
        else:
            reached = r["t_stop"] * math.sqrt(G / data["H"])
            run = f"{r['status']} at {r['t_stop']:.3f} s (t* {reached:.2f}" + (
                "; window not reached)" if reached < WINDOW[0] else f"; window cut at {reached:.2f})")
        for k, ro in enumerate(TABLE_READOUTS):
            vals = pl.get(ro) or {}
            if not vals:
                continue
            head = f"| `{r['model']}` | {opts} | {run} |" if k == 0 else "| | | |"
            lines.append(f"{head} {ro} | " + " | ".join(_fmt(vals.get(f"{f:g}")) for f in HEIGHTS) + " |")
    return "\n".join(lines)


def slip_group(record):
    """``"free slip"`` or ``"no slip"``: how the wall treats the fluid's tangential velocity.

    The run's ``slip`` option, else the model's default one (``boundary_option_defaults``), else the
    name (``-noslip``). Every value but ``free`` is a no-slip wall: ``noslip`` mirrors the velocity,
    and ``vel0`` (`mdbc`, the original mDBC) gives the wall particles the wall's own velocity, so the
    fluid's viscosity acts across the wall against a still wall (docs/boundaries.md, "mDBC"); its
    plateau reads with the no-slip walls at every resolution (docs/validation-notes.md). A model
    without a ``slip`` option (`dbc`, `idbc`, the repulsive-force walls) has no viscosity across
    the wall and is free slip.
    """
    from seawall.boundary.registry import boundary_option_defaults
    from seawall.errors import ParameterError

    slip = (record.get("params") or {}).get("slip")
    if slip is None:
        try:
            slip = boundary_option_defaults(record["model"]).get("slip")
        except ParameterError:        # a name the registry does not know (a test's, or a retired model)
            slip = None
    if slip is None:
        return "no slip" if record["model"].endswith("-noslip") else "free slip"
    return "free slip" if str(slip) == "free" else "no slip"


#: the read-outs compared within a slip group (issue 15, item 7)
AGREEMENT_READOUTS = ("wall", "force")


def agreement(stored, order):
    """Spread of the plateau means within each slip group, per resolution, read-out and height.

    The spread is the largest minus the smallest mean over the group's completed runs that have the
    read-out at every height; "farthest" names the run whose mean distance from the group's median
    profile is largest (the one that widens the spread most; not named for two runs).
    """
    lines = ["Agreement within a slip group (completed runs only): largest minus smallest plateau mean, "
             "in rho0 g H. Item 7 of issue 15 asks for at most 0.05 at every height at H/200.", "",
             "| H/N | group | read-out | runs | " + " | ".join(f"y/H = {f:g}" for f in HEIGHTS) + " | farthest from the median |",
             "| --- | --- | --- | --- | " + " | ".join("---" for _ in HEIGHTS) + " | --- |"]
    for n in sorted(stored):
        models = stored[n]["models"]
        for group in ("free slip", "no slip"):
            keys = [k for k in order(models) if models[k]["status"] == "completed" and slip_group(models[k]) == group]
            for ro in AGREEMENT_READOUTS:
                profiles = {}
                for k in keys:
                    vals = [(models[k]["plateau"].get(ro) or {}).get(f"{f:g}") for f in HEIGHTS]
                    if all(v is not None for v in vals):
                        profiles[k] = vals
                if len(profiles) < 2:
                    continue
                columns = list(zip(*profiles.values()))
                spread = [max(c) - min(c) for c in columns]
                median = [float(np.median(c)) for c in columns]
                # with two runs both are equally far from their median: no run to name
                farthest = "--" if len(profiles) < 3 else "`{}`".format(
                    max(profiles, key=lambda k: sum(abs(v - m) for v, m in zip(profiles[k], median))))
                lines.append(f"| H/{n} | {group} | {ro} | {len(profiles)} | " + " | ".join(_fmt(v) for v in spread)
                             + f" | {farthest} |")
    return "\n".join(lines)


def plot(stored, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = sorted(stored)
    keys = sorted({k for n in res for k in stored[n]["models"]})
    # tab20 has 20 colours and the tables more runs: the next 20 come from tab20b with another marker
    palette = [plt.get_cmap("tab20")(i) for i in range(20)] + [plt.get_cmap("tab20b")(i) for i in range(20)]
    colour = {k: palette[i % 40] for i, k in enumerate(keys)}
    marker = {k: "os^"[(i // 20) % 3] for i, k in enumerate(keys)}
    fig, axes = plt.subplots(len(res), 2, figsize=(10.4, 4.6 * len(res)), squeeze=False)
    for row, n in enumerate(res):
        for ax, ro in zip(axes[row], ("wall", "force")):
            for key, r in sorted(stored[n]["models"].items()):
                vals = [(r["plateau"].get(ro) or {}).get(f"{f:g}") for f in HEIGHTS]
                if any(v is None for v in vals):
                    continue
                # a run stopped inside the window averages over its part only: drawn dotted
                cut = r["status"] != "completed"
                style = ":" if cut else ("--" if "noslip" in key else "-")
                ax.plot(vals, HEIGHTS, style, marker=marker[key], ms=3, color=colour[key],
                        label=key + (" (stopped)" if cut else ""))
            ax.set_xlabel(f"plateau p / (rho g H), read-out: {ro}")
            ax.set_ylabel("y / H")
            ax.set_title(f"downstream wall, H/{n}, t* {WINDOW[0]:g}-{WINDOW[1]:g}", fontsize=9)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_doc():
    stored = _stored()
    sweep = sweep_module()
    blocks = [table(n, stored[n], sweep._ordered) for n in sorted(stored)]
    if stored:
        blocks.append(agreement(stored, sweep._ordered))
        plot(stored, os.path.join(IMG, "plateau_profiles.png"))
        blocks.append("![plateau profiles](../validation/dam-break/img/plateau_profiles.png)")
    body = "\n\n".join(blocks) if blocks else "(no stored results)"
    from seawall.validation import replace_block

    replace_block(DOC, BEGIN, END, body)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=50, help="N in dx = H/N (50, 100, 200; default 50)")
    parser.add_argument("--models", default=None, help="comma-separated wall models (default: every model)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="case or wall option for every model (passed to the sweep)")
    parser.add_argument("--report-only", action="store_true", help="table and plot from stored results only")
    args = parser.parse_args(argv)
    sys.path.insert(0, ROOT)
    if not args.report_only:
        sweep = sweep_module()
        models = sweep.closed_tank_models() if args.models is None else \
            [m.strip() for m in args.models.split(",") if m.strip()]
        for model in models:     # one sweep call per model: the table grows as the runs finish
            sweep_args = ["--resolution", str(args.resolution), "--models", model]
            for item in args.set:
                sweep_args += ["--set", item]
            # the sweep as its own program: its workers are spawned from its own module
            rc = subprocess.run([sys.executable, os.path.join(ROOT, "validation", "leaks", "sweep.py")]
                                + sweep_args).returncode
            if rc:
                return rc
            collect(args.resolution)
            write_doc()
    else:
        for n in (50, 100, 200):
            if os.path.exists(sweep_module().results_path(n)):
                collect(n)
    write_doc()
    return 0


if __name__ == "__main__":
    sys.exit(main())
