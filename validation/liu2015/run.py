"""[Liu2015] sec. 4 per wall model: plates, cavity (Re = 1 and Re = 100) and the ETSIN dam break.

    python validation/liu2015/run.py [--quick] [--only plates,cavity1,cavity100,dam]

Writes docs/liu2015_results.md and validation/liu2015/img/liu2015_*.png. Runs single-threaded
(NUMBA_NUM_THREADS=1 recommended); the full set takes roughly 20-30 min.
"""

import argparse
import os
import re
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))   # the repository checkout
sys.path.insert(0, ROOT)

from seawall.cases import build  # noqa: E402
from seawall.cases.lid_cavity import centrelines  # noqa: E402
from seawall.errors import InstabilityError  # noqa: E402

DOC = os.path.join(ROOT, "docs", "liu2015_results.md")
IMG = os.path.join(HERE, "img")
SERIES = os.path.join(HERE, "runs")   # probe series (not committed)
#: width of the running mean of the ETSIN sensor pressures, in t* = t sqrt(g/H)
SMOOTH = 0.1
#: t* up to which the smoothed peak is sought
FIRST_IMPACT_END = 4.0


def _run(sim, t_end):
    """Run; on instability keep what was sampled. Returns (times, {probe: values}, status, wall time)."""
    start = time.perf_counter()
    status = "completed"
    try:
        sim.run(t_end, progress=False)
    except InstabilityError as exc:
        status = f"unstable at t = {exc.time:.4g} s"
    sampled = sim.result({})
    return sampled.times, sampled.probes, status, time.perf_counter() - start


def plates(lines, quick):
    lines += ["## Plates ([Liu2015] sec. 4.1)", "",
              "Block 0.04 x 0.04 m at 1 m/s, dx = 1 mm, h = 1.5 dx, no gravity; c_s = 10 m/s (Monaghan-Kajtar: "
              "1 m/s and K = 0.01 c_s^2, as the seed runs it). Deformation = largest distance of a particle from "
              "its rigid-translation position, over the particles still between the plates and over all.", "",
              "| model | status | wall time | deformation between plates (max) [dx] | deformation, all (max) [dx] | "
              "p range t = 4 ms [Pa] | p range t = 20 ms [Pa] | p range t = 48 ms [Pa] |",
              "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    dx = 1e-3
    for model in ("liu2015", "adami", "monaghan-kajtar", "liu2012"):
        sim = build("plates", boundary=model, threads=1)
        t, pr, status, wall = _run(sim, 0.048)
        ranges = []
        for tt in (4e-3, 2e-2, 4.8e-2):
            if t.size and t[-1] >= tt - 1e-4:
                k = int(np.argmin(np.abs(t - tt)))
                ranges.append(f"{pr['p_min'][k]:.3g} .. {pr['p_max'][k]:.3g}")
            else:
                ranges.append("-")
        lines.append(f"| {model} | {status} | {wall:.0f} s | {pr['deformation_between'].max() / dx:.3g} | "
                     f"{pr['deformation'].max() / dx:.3g} | " + " | ".join(ranges) + " |")
    lines.append("")


def _cavity_reference(reynolds):
    if reynolds == 1:
        ref = np.loadtxt(os.path.join(ROOT, "data", "lid_driven_cavity_stokes_computed", "cavity_Re1_centerlines.csv"),
                         delimiter=",", skiprows=1)
        return ref[:, 0], ref[:, 1], ref[:, 0], ref[:, 2], "computed Re = 1 reference"
    tu = np.loadtxt(os.path.join(ROOT, "data", "ghia1982_lid_driven_cavity", "ghia1982_u_vertical_centerline.csv"),
                    delimiter=",", skiprows=1)
    tv = np.loadtxt(os.path.join(ROOT, "data", "ghia1982_lid_driven_cavity", "ghia1982_v_horizontal_centerline.csv"),
                    delimiter=",", skiprows=1)
    col = {100: 2, 1000: 4}[reynolds]
    return tu[:, 1], tu[:, col], tv[:, 1], tv[:, col], f"Ghia et al. (1982), Re = {reynolds}"


#: measuring times of the cavity [s]: at Re = 1 the Stokes start-up transient decays as exp(-52.3 nu t / L^2)
#: (slowest Stokes mode of the square, the clamped-plate buckling eigenvalue), below 1e-4 by t = 0.2 s -- the
#: seed calls its run steady at 0.15 s; 0.5 s shows what the particle distribution does afterwards
CAVITY_TIMES = {1: (0.2, 0.5), 100: (30.0,)}


def cavity(lines, quick, reynolds):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = 20 if quick else 50
    times = tuple(t * (0.1 if quick else 1.0) for t in CAVITY_TIMES[reynolds])
    c0 = 0.05 if reynolds == 1 else 0.01
    s_u, u_ref, s_v, v_ref, label = _cavity_reference(reynolds)
    lines += [f"## Cavity, Re = {reynolds} ([Liu2015] sec. 4.2)", "",
              f"L = 1 mm, lid U = 1 mm/s, nu = U L / Re, dx = L/{n}, h = 1.2 dx, c_s = {c0:g} m/s, 4 wall layers, "
              f"[Liu2015] fluid without regularisation (`cavity --set fluid=liu2015 transport_velocity=false`; the case's "
              f"default adds the transport velocity). Reference: {label}. Error = largest |seawall - "
              "reference| / U over the reference stations at least dx from the walls (Shepard interpolation), "
              f"at t = {', '.join(f'{t:g}' for t in times)} s.", "",
              "| model | status | wall time | " + " | ".join(f"max err u (s), t = {t:g} s | max err v (s), t = {t:g} s"
                                                           for t in times) + " |",
              "| --- | --- | --- | " + " | ".join("--- | ---" for _ in times) + " |"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 4), dpi=100)
    a1.plot(u_ref, s_u, "ko", ms=3, mfc="none", label=label)
    a2.plot(s_v, v_ref, "ko", ms=3, mfc="none", label=label)
    fine = np.linspace(0.0, 1.0, 101)
    ku = (s_u >= 1.0 / n) & (s_u <= 1.0 - 1.0 / n)
    kv = (s_v >= 1.0 / n) & (s_v <= 1.0 - 1.0 / n)
    for model, colour in (("liu2015-noslip", "b"), ("adami-noslip", "r")):
        sim = build("cavity", boundary=model, fluid="liu2015", layers=4, dx=1e-3 / n, reynolds=float(reynolds),
                    c0=c0, threads=1, transport_velocity=False)
        cells, status, wall = [], "completed", 0.0
        for k, t_end in enumerate(times):
            t, _, status, took = _run(sim, t_end)
            wall += took
            if status != "completed":
                cells += ["-", "-"] * (len(times) - k)
                break
            u, _ = centrelines(sim, s_u[ku])
            _, v = centrelines(sim, s_v[kv])
            eu = np.abs(u - u_ref[ku])
            ev = np.abs(v - v_ref[kv])
            cells += [f"{100 * np.nanmax(eu):.1f} % ({s_u[ku][np.nanargmax(eu)]:.3f})",
                      f"{100 * np.nanmax(ev):.1f} % ({s_v[kv][np.nanargmax(ev)]:.3f})"]
            uf, vf = centrelines(sim, fine)
            style = "-" if k == 0 else ":"
            a1.plot(uf, fine, colour + style, lw=1.2, label=f"{model}, t = {t_end:g} s")
            a2.plot(fine, vf, colour + style, lw=1.2, label=f"{model}, t = {t_end:g} s")
        lines.append(f"| {model} | {status} | {wall:.0f} s | " + " | ".join(cells) + " |")
    a1.set_xlabel("u/U on x = L/2")
    a1.set_ylabel("y/L")
    a2.set_xlabel("x/L")
    a2.set_ylabel("v/U on y = L/2")
    a1.legend(fontsize=7)
    fig.suptitle(f"lid-driven cavity, Re = {reynolds}, dx = L/{n}", fontsize=9)
    fig.tight_layout()
    name = f"liu2015_cavity_re{reynolds}.png"
    fig.savefig(os.path.join(IMG, name))
    plt.close(fig)
    lines += ["", f"![cavity Re = {reynolds}](../validation/liu2015/img/{name})", ""]


def dam(lines, quick, reuse=False):
    """ETSIN dam break per wall model; ``reuse`` takes the probe series stored by an earlier run where present."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    H, g, rho0 = 0.3, 9.81, 1000.0
    t_end = 0.3 if quick else 1.45
    lines += ["## Dam break, ETSIN ([Liu2015] sec. 4.4)", "",
              "H = 0.3 m, column 0.6 m, tank 1.61 m, dx = 6 mm (5000 particles), h = 1.2 dx, c_s = 10 sqrt(2 g H) "
              "= 24.26 m/s, dt = 5e-5 s (the seed's), hydrostatic start, gate removed at t = 0 (last row: lifted at "
              "3.46 m/s as in the experiment), [Liu2015] fluid. t* = t sqrt(g/H), p* = p / (rho g H); "
              "S1 = 3 mm and S3 = 30 mm above the floor on the wall hit by the surge (the seed's monitoring points "
              "1 and 2). [Liu2015] (text of sec. 4.4): peaks of about 3 (point 1) and 1.8 (point 2) at t* ~ 2.5.", "",
              "Peak = largest sample (every 5e-4 s: the impact spike); smoothed peak = largest running mean over "
              f"dt* = {SMOOTH} ({SMOOTH * np.sqrt(H / g) * 1e3:.0f} ms) up to t* = {FIRST_IMPACT_END:g} (the first impact; "
              "the reflected wave returns at t* ~ 8); plateau = mean over t* = 3-5. "
              "Probe series: validation/liu2015/runs/.", "",
              "| model | status | wall time | front x/H at t* = 0.5, 1.0, 1.5, 2.0 | impact t* (front reaches the wall) | "
              "S1 peak p* (t*) | S1 smoothed peak | S1 plateau | S3 peak p* (t*) | S3 smoothed peak | S3 plateau |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), dpi=100)
    runs = (("liu2015", "b-", 0.0), ("adami", "r--", 0.0), ("liu2012", "g-.", 0.0), ("monaghan-kajtar", "m:", 0.0),
            ("liu2015", "c-", 3.46))
    for model, style, gate in runs:
        sim = build("dam-break-etsin", boundary=model, gate_speed=gate, threads=1)
        if gate:
            model = f"{model}, gate {gate:g} m/s"
        series = os.path.join(SERIES, "etsin_" + re.sub(r"[^A-Za-z0-9.-]+", "_", model) + ".csv")
        if reuse and os.path.exists(series):
            data = np.loadtxt(series, delimiter=",", skiprows=1, ndmin=2)
            t = data[:, 0]
            pr = dict(zip(("front", "S1", "S2", "S3", "S4"), data[:, 1:].T))
            status, wall = f"stored series to t = {t[-1]:.3g} s", float("nan")
        else:
            t, pr, status, wall = _run(sim, t_end)
        if not t.size:
            lines.append(f"| {model} | {status} | {wall:.0f} s |" + " - |" * 8)
            continue
        ts = t * np.sqrt(g / H)
        front = pr["front"] / H
        fr = []
        for tt in (0.5, 1.0, 1.5, 2.0):
            fr.append(f"{front[int(np.argmin(np.abs(ts - tt)))]:.2f}" if ts[-1] >= tt - 0.01 else "-")
        length = sim.reference["tank_length"]
        hit = np.flatnonzero(pr["front"] >= length - 0.01)
        impact = f"{ts[hit[0]]:.2f}" if hit.size else "-"
        peaks = []
        for nm in ("S1", "S3"):
            p = pr[nm] / (rho0 * g * H)
            k = int(np.argmax(p))
            width = max(1, int(round(SMOOTH / (ts[1] - ts[0]))))
            smooth = np.convolve(p, np.ones(width) / width, mode="valid")
            smooth[ts[width // 2:width // 2 + smooth.size] > FIRST_IMPACT_END] = -np.inf  # the first impact only
            ks = int(np.argmax(smooth))
            plateau = (ts >= 3.0) & (ts <= 5.0)
            peaks += [f"{p[k]:.2f} ({ts[k]:.2f})", f"{smooth[ks]:.2f} ({ts[ks + width // 2]:.2f})",
                      f"{p[plateau].mean():.2f}" if plateau.any() else "-"]
        os.makedirs(SERIES, exist_ok=True)
        np.savetxt(series, np.column_stack([t] + [pr[nm] for nm in ("front", "S1", "S2", "S3", "S4")]), delimiter=",",
                   header="t,front,S1,S2,S3,S4", comments="", fmt="%.6g")
        took = "-" if np.isnan(wall) else f"{wall:.0f} s"
        lines.append(f"| {model} | {status} | {took} | {', '.join(fr)} | {impact} | " + " | ".join(peaks) + " |")
        axes[0].plot(ts, front, style, lw=1.1, label=model)
        axes[1].plot(ts, pr["S1"] / (rho0 * g * H), style, lw=0.9, label=model)
        axes[2].plot(ts, pr["S3"] / (rho0 * g * H), style, lw=0.9, label=model)
    axes[0].set_ylabel("front x / H")
    axes[1].set_ylabel("S1 (3 mm) p / (rho g H)")
    axes[2].set_ylabel("S3 (30 mm) p / (rho g H)")
    for ax in axes:
        ax.set_xlabel("t sqrt(g/H)")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "liu2015_dam_break_etsin.png"))
    plt.close(fig)
    lines += ["", "![ETSIN dam break](../validation/liu2015/img/liu2015_dam_break_etsin.png)", ""]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="coarse and short (smoke test of the script)")
    ap.add_argument("--only", default="plates,cavity1,cavity100,dam")
    ap.add_argument("--reuse", action="store_true",
                    help="dam break: rebuild the table from the series in validation/liu2015/runs where present")
    args = ap.parse_args(argv)
    os.makedirs(IMG, exist_ok=True)
    lines = ["# Liu et al. (2015): measured figures", "",
             "Written by `python validation/liu2015/run.py`" + (" --quick" if args.quick else "") +
             "; see docs/liu2015.md for the model, the choices and the discussion.", ""]
    todo = args.only.split(",")
    if "plates" in todo:
        plates(lines, args.quick)
    if "cavity1" in todo:
        cavity(lines, args.quick, 1)
    if "cavity100" in todo:
        cavity(lines, args.quick, 100)
    if "dam" in todo:
        dam(lines, args.quick, args.reuse)
    text = _merge_sections(lines)
    with open(DOC, "w") as f:
        f.write(text)
    print(text)


def _sections(lines):
    """Split markdown lines into (header, lines) blocks at the '## ' headers; the preamble's header is ''."""
    blocks = [("", [])]
    for line in lines:
        if line.startswith("## "):
            blocks.append((line, []))
        blocks[-1][1].append(line)
    return blocks


def _merge_sections(lines):
    """The new sections replace their namesakes in the existing results file; the others are kept."""
    new = _sections(lines)
    if not os.path.exists(DOC):
        return "\n".join(lines) + "\n"
    with open(DOC) as f:
        old = _sections(f.read().splitlines())
    fresh = dict(new[1:])
    merged = [new[0]] + [(h, fresh.pop(h, body)) for h, body in old[1:]] + list(fresh.items())
    return "\n".join(line for _, body in merged for line in body).rstrip("\n") + "\n"


if __name__ == "__main__":
    main()
