"""Shared run of the start-up channel flows (entries ``poiseuille`` and ``couette``)."""

import numpy as np

from .. import cases
from ..analytic import couette_startup, poiseuille_startup
from . import row
from ._common import pyplot

TAUS = (0.02, 0.1, 0.2, 1.0)
TOL = 0.02
FILES = {"poiseuille": "poiseuille_startup_u_over_umax.csv", "couette": "couette_startup_u_over_U.csv"}


def run_channel(ctx, name):
    L = 1e-3
    nu = 1e-6
    dx = L / 10 if ctx.quick else L / 40
    taus = (0.02, 0.1) if ctx.quick else TAUS
    sim = cases.build(name, boundary="adami-noslip", dx=dx, threads=ctx.threads)
    ref = sim.reference
    if name == "poiseuille":
        scale = ref["force"] * L * L / (8 * nu)

        def exact(y, t):
            return poiseuille_startup(y, t, L=L, F=ref["force"], nu=nu)
    else:
        scale = ref["wall_speed"]

        def exact(y, t):
            return couette_startup(y, t, L=L, U=scale, nu=nu)
    data = ctx.data("poiseuille_couette_analytic", FILES[name])
    with open(f"{ctx.data_dir}/poiseuille_couette_analytic/{FILES[name]}") as fh:
        header = fh.readline().strip().split(",")
    rows = []
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    eta_fine = np.linspace(0, 1, 201)
    sim.add(every=0.005)
    for tau in taus:
        t = tau * L * L / nu
        sim.run(t, progress=False)
        fp = sim.fluid.particles
        y = fp["x"][:, 1]
        u = fp["v"][:, 0]
        err = (u - exact(y, sim.time)) / scale
        k = int(np.argmax(np.abs(err)))
        rows.append(row(name, f"u / u_ref at tau = {tau:g}, worst particle (eta = {y[k] / L:.3f})",
                        "Morris et al. 1997 series", float(exact(y[k], sim.time) / scale), float(u[k] / scale),
                        error=float(err[k]), kind="% of u_ref", tolerance=TOL, fmt="{:.4f}"))
        # layer means for the plot
        layers = np.round(y / dx - 0.5).astype(int)
        ym = np.array([y[layers == j].mean() for j in np.unique(layers)])
        um = np.array([u[layers == j].mean() for j in np.unique(layers)])
        line, = ax.plot(exact(eta_fine * L, sim.time) / scale, eta_fine, lw=1)
        ax.plot(um / scale, ym / L, "o", ms=3, color=line.get_color(), label=f"tau = {tau:g}")
    # the series used above against the tabulated data (independent evaluation)
    col_err = 0.0
    for c, head in enumerate(header[1:], start=1):
        if head.startswith("tau_"):
            tau = float(head[4:])
            if name == "couette" and tau < 0.01:
                continue  # README: slow convergence near eta = 1 at the smallest tau
            col_err = max(col_err, float(np.max(np.abs(exact(data[:, 0] * L, tau * L * L / nu) / scale - data[:, c]))))
    rows.append(row(name, "series (seawall.analytic) vs tabulated data, tau >= 0.01, max difference",
                    f"data/poiseuille_couette_analytic/{FILES[name]}", 0.0, col_err, error=col_err,
                    kind="absolute", tolerance=1e-6, fmt="{:.2g}"))
    ax.set_xlabel("u / u_max" if name == "poiseuille" else "u / U")
    ax.set_ylabel("y / L")
    ax.set_title(f"{name} start-up, adami-noslip, dx = L/{L / dx:.0f} (lines: series; dots: layer means)")
    ax.title.set_fontsize(8)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(ctx.plot_path(name))
    plt.close(fig)
    what = ("body force F = 2e-4 m/s^2, u_max = F L^2 / (8 nu) = 2.5e-5 m/s" if name == "poiseuille"
            else "upper plate U = 2.5e-5 m/s")
    return {"rows": rows,
            "settings": f"case {name}, boundary adami-noslip, L = 1 mm, nu = 1e-6 m^2/s, {what}, dx = L/{L / dx:.0f} "
                        f"({sim.fluid.n} fluid particles, periodic length {sim.grid.period[0]:g} m), "
                        f"tau = nu t / L^2 up to {taus[-1]:g}",
            "notes": [f"Error = (u_SPH - u_series) / u_ref at the particle with the largest deviation, over all "
                      f"{sim.fluid.n} particles; tolerance (chosen before the run) 2 % of u_ref. "
                      f"Escaped particles: {len(sim.escaped)}."]}
