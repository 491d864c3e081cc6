"""Figures of docs/idbc.md: ``python validation/idbc/figures.py [fields|box|drop|sweep|all] [--out DIR]``
(default DIR: validation/idbc/img).

* fields -- dimensionless force and potential per order ([Li2022] Fig. 1-2)
  and the force field of a row of six wall particles (Fig. 4 a-d);
* box    -- particle-in-box trajectory and kinetic energy, DBC vs IDBC vs LUST (Fig. 8);
* drop   -- f_sym(t) of the drop on the symmetric and shifted walls (Fig. 11);
* sweep  -- break-through speed of each model (sec. 4.2).

``--models dbc,idbc,lust`` (the default) chooses the wall models. Every part prints the numbers it
measured as JSON lines.
"""

import argparse
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))   # this checkout's seawall


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def fields(out):
    from seawall.boundary.dbc_field import pair_force, pair_potential, potential_energy, row_force_field

    plt = _plt()
    q = np.linspace(0.0, 2.0, 401)
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.5))
    for n in range(1, 8):
        ax[0].plot(q, pair_force(q, n), label=f"order {n}")
        ax[1].plot(q, pair_potential(q, n), label=f"order {n}")
    ax[0].set(xlabel="q = r/h", ylabel="F* = |dv/dt| h / c²", title="force of one wall particle (eq. 23)")
    ax[1].set(xlabel="q = r/h", ylabel="U*(q) = ∫_q^2 F* dq", title="potential")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "idbc_force_orders.png"), dpi=90)
    plt.close(fig)
    energies = {n: potential_energy(n) for n in range(1, 8)}
    print(json.dumps({"part": "fields", "potential": energies, "ratio_7_to_1": energies[7] / energies[1],
                      "peak_q": {n: float(q[np.argmax(pair_force(q, n))]) for n in (1, 7)}}))

    x, y = np.meshgrid(np.linspace(-4, 4, 161), np.linspace(-0.5, 3.0, 71))
    fig, axes = plt.subplots(2, 2, figsize=(9, 5.5), sharex=True, sharey=True)
    variants = [("a) DBC", dict(order=1)), ("b) DBC, order 7", dict(order=7)),
                ("c) DBC, rectangular + α_DB", dict(order=1, rectangular=True, correction=True)),
                ("d) IDBC (order 7, rectangular, α_DB)", dict(order=7, rectangular=True, correction=True))]
    for a, (title, kw) in zip(axes.ravel(), variants):
        fx, fy = row_force_field(x, y, **kw)
        mag = np.hypot(fx, fy)
        cs = a.contourf(x, y, mag, levels=20, cmap="viridis")
        a.plot(np.arange(6) - 2.5, np.zeros(6), "wo", ms=4)
        a.set_title(title, fontsize=9)
        fig.colorbar(cs, ax=a)
    for a in axes[1]:
        a.set_xlabel("x / dx")
    for a in axes[:, 0]:
        a.set_ylabel("y / dx")
    fig.suptitle("|F*| of six wall particles in a row (h = 1.3 dx)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "idbc_force_field.png"), dpi=80)
    plt.close(fig)


def _closing(times, x, y, x0, y0, period):
    """Distance from the start point to the path after half a period, and the KE drift."""
    m = times > 0.5 * period
    px, py = x[m], y[m]
    ax_, ay = px[:-1], py[:-1]
    bx, by = px[1:], py[1:]
    dx, dy = bx - ax_, by - ay
    L2 = dx * dx + dy * dy
    t = np.clip(((x0 - ax_) * dx + (y0 - ay) * dy) / np.where(L2 > 0, L2, 1.0), 0.0, 1.0)
    d = np.hypot(ax_ + t * dx - x0, ay + t * dy - y0)
    return float(d.min())


MODELS = ("dbc", "idbc", "lust")
COLOURS = {"dbc": "r", "idbc": "b", "lust": "g"}


def _options(boundary, case):
    """Wall options of the figures: IDBC with the wall density integrated across the rectangle's edges
    (docs/idbc.md, choice 3); LUST with no artificial viscosity across the wall in the drop, as the
    seed's fluid-wall alpha = 0 ([Li2022] sec. 4.2; its box has no viscosity at all)."""
    if boundary == "idbc" and case == "box":
        return {"wall_density": "consistent"}
    if boundary == "lust":
        return {"alpha_wall": 0.0}
    return {}


def box(out, models=MODELS, t_end=6.5):
    from seawall.cases import build

    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    for b in models:
        style = COLOURS.get(b, "k") + "-"
        sim = build("particle-in-box", boundary=b, threads=1, **_options(b, "box"))
        sim.add(every=1e-3)
        r = sim.run(t_end, progress=False)
        x, y, ke = r["x"], r["y"], r["kinetic_energy"]
        period = sim.reference["period"]
        err = _closing(r.times, x, y, 30.0, 36.0, period)
        post = r.times > 0.95 * t_end
        v = sim.fluid.particles["v"][0]
        # the first bounce (on the right wall, at t = 1.475 s for a specular path): where the wall starts
        # to act (kinetic energy 0.1 % below its start) and where the particle turns, as distances from
        # the nearest wall-particle line (x, y = 0 or L) in h
        h = sim.h
        L = sim.reference["L"]
        dist = np.minimum.reduce([x, y, L - x, L - y]) / h
        first = r.times < 0.27 * sim.reference["period"]
        onset = int(np.argmax(ke[first] < 0.999 * ke[0]))
        turn = int(np.argmin(dist[first]))
        print(json.dumps({"part": "box", "boundary": b, "closing_error_m": err,
                          "ke_drift_end": float(ke[-1] / ke[0] - 1.0),
                          "ke_min_during_contact": float(ke.min() / ke[0] - 1.0),
                          "direction_error_deg_end": float(np.degrees(np.arctan2(abs(v[1]), abs(v[0])) - np.pi / 4)),
                          "steps": r.summary["steps"], "ke_end_window_mean": float(ke[post].mean() / ke[0] - 1),
                          "first_bounce": {"onset_t": float(r.times[onset]), "onset_distance_h": float(dist[onset]),
                                           "turn_t": float(r.times[turn]), "turn_distance_h": float(dist[turn])}}))
        ax[0].plot(x, y, style, lw=0.8, label=f"{b} (closing error {err:.3g} m)")
        ax[1].plot(r.times, ke / ke[0], style, lw=0.8, label=b)
    ax[0].plot([30], [36], "ko")
    ax[0].set(xlim=(0, 60), ylim=(0, 60), aspect="equal", xlabel="x [m]", ylabel="y [m]",
              title="particle in a box: trajectory")
    ax[0].legend(fontsize=8)
    ax[1].set(xlabel="t [s]", ylabel="KE / KE(0)", title="kinetic energy")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "idbc_particle_in_box.png"), dpi=80)
    plt.close(fig)


def drop(out, models=MODELS):
    from seawall.cases.idbc_tests import drop_run

    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    for b in models:
        col = COLOURS.get(b, "k")
        for shift, ls in ((0.0, "--"), (0.3, "-")):
            res = drop_run(b, threads=1, shift=shift, **_options(b, "drop"))
            t = res["times"]
            fs = res["f_sym"]
            late = t >= 1.0e-3
            print(json.dumps({"part": "drop", "boundary": b, "shift": shift, "status": res["status"],
                              "f_sym_end": float(fs[-1]), "f_sym_mean_1_2ms": float(fs[late].mean()),
                              "through": res["final_through"]}))
            ax[0].plot(t * 1e3, fs, col + ls, lw=0.9, label=f"{b}, shift {shift}")
            if shift == 0.3:
                p = res["positions"] / 2e-4
                ax[1].plot(p[:, 0], p[:, 1], col + ".", ms=3, label=f"{b}, shift 0.3")
                ax[1].plot(-p[:, 0], p[:, 1], col + "o", mfc="none", ms=5, alpha=0.4)
    ax[0].set(xlabel="t [ms]", ylabel="f_sym (eq. 29, x, y in dx)", yscale="symlog", title="drop impact: f_sym")
    ax[0].legend(fontsize=7)
    ax[1].set(xlabel="x / dx", ylabel="y / dx", title="t = 2 ms, shifted wall (dots) and mirror (circles)",
              aspect="equal")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "idbc_drop_fsym.png"), dpi=80)
    plt.close(fig)


def sweep(out, models=MODELS, speeds=(5, 10, 16, 20, 30, 40, 50, 65, 80, 100)):
    from seawall.cases.idbc_tests import breakthrough_speed

    for layers in (1, 3):
        for b in models:
            first, rows = breakthrough_speed(b, list(speeds), threads=1, layers=layers, **_options(b, "drop"))
            print(json.dumps({"part": "sweep", "boundary": b, "layers": layers, "first_escape_speed": first,
                              "rows": rows}))


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python validation/idbc/figures.py", description=__doc__.splitlines()[0])
    parser.add_argument("what", nargs="?", default="all", choices=("fields", "box", "drop", "sweep", "all"))
    parser.add_argument("--out", default=os.path.join(HERE, "img"))
    parser.add_argument("--models", default=",".join(MODELS), help="wall models of box, drop and sweep")
    args = parser.parse_args(argv)
    models = tuple(m.strip() for m in args.models.split(",") if m.strip())
    os.makedirs(args.out, exist_ok=True)
    for name, fn in (("fields", fields), ("drop", drop), ("sweep", sweep), ("box", box)):
        if args.what in (name, "all"):
            fn(args.out) if name == "fields" else fn(args.out, models)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
