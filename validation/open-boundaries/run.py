"""Open boundaries: channel profile against Poiseuille, and the S-cavity filling ([Liu2015] sec. 4.3).

    python validation/open-boundaries/run.py                 # channel at H/20, H/30, cavity at dx = 2 mm, duct (~6 min)
    python validation/open-boundaries/run.py --cavity-dx 1e-3   # the seed's resolution (~1 h on one core)
    python validation/open-boundaries/run.py --only channel  # or --only cavity, --only pipe

Writes validation/open-boundaries/img/open_channel_profile.png, open_s_cavity.png,
open_s_cavity_series.png and the numbers to
docs/open-boundaries-results.md.
"""

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)
IMG = os.path.join(HERE, "img")
RESULTS = os.path.join(ROOT, "docs", "open-boundaries-results.md")


def run_channel(dx_fraction):
    from seawall.cases import build
    from seawall.cases.channels import channel_profile, poiseuille_velocity

    sim = build("channel", boundary="adami-noslip", dx=0.1 / dx_fraction)
    ref = sim.reference
    T = ref["viscous_time"]
    sim.add(every=T / 50)
    start = time.perf_counter()
    sim.run(0.4 * T, progress=False)
    ob = sim.open_boundary
    m_in0, m_out0 = ob.net_inflow(0), -ob.net_inflow(1)
    profiles = []
    for k in range(10):
        result = sim.run(0.4 * T + (k + 1) * 0.02 * T, progress=False)
        y, u, _ = channel_profile(sim)
        profiles.append(u)
    u = np.mean(profiles, axis=0)
    exact = poiseuille_velocity(y, ref["height"], ref["u_max"])
    flux_in = ob.net_inflow(0) - m_in0
    flux_out = -ob.net_inflow(1) - m_out0
    p_in, p_out = result["p_inlet"][-25:].mean(), result["p_outlet"][-25:].mean()
    dx = sim.fluid.spacing
    return {"dx_fraction": dx_fraction, "y": y, "u": u, "exact": exact, "u_max": ref["u_max"],
            "height": ref["height"],
            "max_error": float(np.abs(u - exact).max() / ref["u_max"]),
            "centre": float(u.max() / ref["u_max"]),
            "flux_in": flux_in, "flux_out": flux_out,
            "flux_mismatch": float((flux_in - flux_out) / flux_in),
            "gradient": float((p_in - p_out) / (ref["length"] - 4 * dx)), "gradient_exact": ref["gradient"],
            "escaped": result.summary["escaped_particles"],
            "lost": result.summary["couplings"]["open_boundary"]["particles_left_zone_wrongly"],
            "wall_s": time.perf_counter() - start, "steps": sim.step}


def channel_part(lines):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [run_channel(n) for n in (20, 30)]
    fig, ax = plt.subplots(figsize=(5.5, 4))
    yy = np.linspace(0, runs[0]["height"], 200)
    from seawall.cases.channels import poiseuille_velocity
    ax.plot(poiseuille_velocity(yy, runs[0]["height"], runs[0]["u_max"]), yy * 1e3, "k-", label="Poiseuille")
    for r, mk in zip(runs, ("o", "s")):
        ax.plot(r["u"], r["y"] * 1e3, mk, ms=4, mfc="none", label=f"SPH, dx = H/{r['dx_fraction']}")
    ax.set_xlabel("u [m/s]")
    ax.set_ylabel("y [mm]")
    ax.set_title("channel: lane-averaged u, x = L/4..3L/4, t = 0.4-0.6 H^2/nu")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "open_channel_profile.png"), dpi=110)
    lines += ["## channel (Re = 10, H = 0.1 m, L = 2H, adami-noslip plates)", "",
              "| dx | max abs(u - u_exact) / U | centre u / U | mass in vs out | -dp/dx SPH / exact | "
              "escaped | left a zone wrongly | steps | wall time |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in runs:
        lines.append(f"| H/{r['dx_fraction']} | {100 * r['max_error']:.2f} % | {r['centre']:.4f} | "
                     f"{100 * r['flux_mismatch']:+.2f} % ({r['flux_in']:.2f} / {r['flux_out']:.2f} kg/m) | "
                     f"{r['gradient'] / r['gradient_exact']:.3f} | {r['escaped']} | {r['lost']} | {r['steps']} | "
                     f"{r['wall_s']:.0f} s |")
    lines.append("")


def cavity_part(lines, dx, times):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from seawall.cases import build

    sim = build("s-cavity", dx=dx)
    ref = sim.reference
    sim.add(every=2.5e-4)
    snaps = []
    start = time.perf_counter()
    result = None
    for t in times:
        result = sim.run(t, progress=False)
        fp = sim.fluid.particles
        snaps.append((sim.time, fp["x"].copy(), np.linalg.norm(fp["v"], axis=1), fp["zone"].copy()))
    wall_s = time.perf_counter() - start
    walls = sim.walls[0].x
    ncol = 3
    nrow = int(np.ceil(len(snaps) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4 * ncol, 3.6 * nrow))
    for ax, (t, x, speed, zone) in zip(axes.ravel(), snaps):
        ax.scatter(walls[:, 0] * 1e3, walls[:, 1] * 1e3, s=0.3, c="0.4")
        fl = zone < 0
        sc = ax.scatter(x[fl, 0] * 1e3, x[fl, 1] * 1e3, s=0.5, c=speed[fl] / ref["v_in"], cmap="jet",
                        vmin=0, vmax=3)
        ax.scatter(x[~fl, 0] * 1e3, x[~fl, 1] * 1e3, s=0.5, c="m")
        ax.set_title(f"t = {1e3 * t:.0f} ms")
        ax.set_aspect("equal")
        ax.set_xticks([0, 90, 180])
        ax.set_yticks([0, 75, 150])
    for ax in axes.ravel()[len(snaps):]:
        ax.axis("off")
    fig.colorbar(sc, ax=axes, shrink=0.6, label="|v| / v_in")
    fig.savefig(os.path.join(IMG, "open_s_cavity.png"), dpi=100)

    t = result.times
    mass = result["mass_in"]
    rate = np.gradient(mass, t)
    u_in = rate / (ref["rho0"] * ref["width"])
    fig, ax = plt.subplots(1, 3, figsize=(12, 3.3))
    ax[0].plot(t * 1e3, result["front"] * 1e3, label="water front")
    ax[0].plot(t * 1e3, result["spray_front"] * 1e3, ":", label="foremost particle")
    ax[0].set_ylabel("distance along the centre line [mm]")
    ax[0].legend(fontsize=8)
    ax[1].plot(t * 1e3, result["fill"])
    ax[1].set_ylabel("filled fraction")
    ax[2].plot(t * 1e3, result["max_speed"] / ref["v_in"], lw=0.7, label="max |v| / v_in")
    ax[2].plot(t * 1e3, result["speed_p99"] / ref["v_in"], label="99th percentile |v| / v_in")
    ax[2].plot(t * 1e3, u_in / ref["v_in"], label="inflow velocity / v_in")
    ax[2].legend(fontsize=8)
    for a in ax:
        a.set_xlabel("t [ms]")
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "open_s_cavity_series.png"), dpi=110)
    summary = result.summary
    ob = summary["couplings"]["open_boundary"]
    lines += [f"## s-cavity (dx = {1e3 * dx:g} mm, h = 1.2 dx, c0 = 174 m/s, adami walls, free slip)", "",
              f"fluid particles at the end: {ob['n_fluid_proper']} (+ {ob['zones']['gate']['particles']} in the "
              f"inflow zone), wall particles: {summary['n_wall']}, steps: {summary['steps']}, "
              f"wall time {wall_s:.0f} s, escaped: {summary['escaped_particles']}, "
              f"left the zone wrongly: {ob['particles_left_zone_wrongly']}", "",
              "| t [ms] | water front along centre line [mm] | foremost particle [mm] | filled fraction | "
              "max abs(v) / v_in | 99th percentile abs(v) / v_in | inflow velocity / v_in (1 ms mean) |",
              "| --- | --- | --- | --- | --- | --- | --- |"]
    for tt in times:
        k = int(np.argmin(np.abs(t - tt)))
        window = (t > tt - 1e-3) & (t <= tt)
        lines.append(f"| {1e3 * t[k]:.0f} | {1e3 * result['front'][k]:.0f} | {1e3 * result['spray_front'][k]:.0f} | "
                     f"{result['fill'][k]:.3f} | {result['max_speed'][k] / ref['v_in']:.2f} | "
                     f"{result['speed_p99'][k] / ref['v_in']:.2f} | {u_in[window].mean() / ref['v_in']:.3f} |")
    lines.append("")


def pipe_part(lines):
    from seawall.cases import build
    from seawall.cases.channels import duct_profile_error

    sim = build("pipe-3d", boundary="adami-noslip")
    ref = sim.reference
    T = ref["viscous_time"]
    sim.add(every=T / 50)
    start = time.perf_counter()
    sim.run(0.4 * T, progress=False)
    ob = sim.open_boundary
    m_in0, m_out0 = ob.net_inflow(0), -ob.net_inflow(1)
    errors = []
    means = []
    for k in range(10):
        result = sim.run(0.4 * T + (k + 1) * 0.02 * T, progress=False)
        err, u, count = duct_profile_error(sim)
        errors.append(err)
        means.append(u)
    flux_in = ob.net_inflow(0) - m_in0
    flux_out = -ob.net_inflow(1) - m_out0
    from seawall.cases.channels import duct_velocity
    n = means[0].shape[0]
    dx = sim.fluid.spacing
    yc = (np.arange(n) + 0.5) * dx - ref["a"]
    exact = duct_velocity(yc[:, None], yc[None, :], ref["a"], ref["a"], u_max=ref["u_max"])
    mean_err = float(np.abs(np.mean(means, axis=0) - exact).max() / ref["u_max"])
    lines += ["## pipe-3d (square duct, Re = 10, H = 0.1 m, dx = H/10, adami-noslip walls)", "",
              f"- largest lane error of the time-mean velocity (lanes dx x dx of the cross-section, "
              f"x = L/4..3L/4, 10 snapshots in 0.4-0.6 H^2/nu; compared at lane centres): "
              f"{100 * mean_err:.2f} % of U",
              f"- largest lane error per snapshot (particle-wise against the exact value at each particle): "
              f"{100 * min(errors):.2f}-{100 * max(errors):.2f} % of U",
              f"- mass in vs out over the window: {flux_in:.3f} / {flux_out:.3f} kg "
              f"({100 * (flux_in - flux_out) / flux_in:+.2f} %)",
              f"- escaped {result.summary['escaped_particles']}, left a zone wrongly "
              f"{result.summary['couplings']['open_boundary']['particles_left_zone_wrongly']}, "
              f"{sim.step} steps, {time.perf_counter() - start:.0f} s", ""]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=("channel", "cavity", "pipe"))
    parser.add_argument("--cavity-dx", type=float, default=2e-3)
    args = parser.parse_args(argv)
    os.makedirs(IMG, exist_ok=True)
    sections = _read_sections()
    if args.only in (None, "channel"):
        lines = []
        channel_part(lines)
        sections["channel"] = lines
    if args.only in (None, "cavity"):
        lines = []
        cavity_part(lines, args.cavity_dx, [0.01, 0.02, 0.03, 0.04, 0.05, 0.06])
        sections["s-cavity"] = lines
    if args.only in (None, "pipe"):
        lines = []
        pipe_part(lines)
        sections["pipe-3d"] = lines
    text = ["# Open boundaries: measured results", "",
            "Written by `python validation/open-boundaries/run.py` (see docs/open-boundaries.md); "
            "`--only channel|cavity|pipe` rewrites one section.", ""]
    for key in ("channel", "s-cavity", "pipe-3d"):
        text += sections.get(key, [])
    with open(RESULTS, "w") as fh:
        fh.write("\n".join(text) + "\n")
    print("\n".join(text))


def _read_sections():
    """The sections (## channel ..., ## s-cavity ...) of the existing results file."""
    sections = {}
    if not os.path.exists(RESULTS):
        return sections
    key = None
    for line in open(RESULTS).read().splitlines():
        if line.startswith("## "):
            key = line[3:].split()[0]
            sections[key] = []
        if key is not None:
            sections[key].append(line)
    return sections


if __name__ == "__main__":
    main()
