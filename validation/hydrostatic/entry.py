"""Hydrostatic tank: wall pressure at the probes against p = rho0 g (H - y).

Case ``hydrostatic`` (water 0.3 m deep in a 1 m tank, [Huang2019] sec. 4.1),
Adami wall, dx = 0.01 m, 2 s from the hydrostatic state. Quantity: the mean
of each wall probe over the second half of the run. Tolerance (chosen before
the run): 1 % of rho0 g H, the pressure scale of the tank -- a wall that holds
still water should give its hydrostatic pressure to a fraction of a percent
(docs/validation-notes.md measured <= 1.3 % of the local value at dx = 0.02).
Also: no particle may escape or enter a wall (smallest signed fluid-to-wall
distance > 0), and the wall-pressure noise is reported.
"""

from functools import partial

import numpy as np

from seawall import cases
from seawall.compare import MinWallDistance
from seawall.diagnostics import pressure_noise
from seawall.validation import Entry, row
from seawall.validation._common import pyplot

TOL = 0.01
#: the EDAC variant (entry hydrostatic-edac, [Ramachandran2019]): pressure by the EDAC equation, no delta-SPH
#: (refused with EDAC), everything else the case's default; fixed before the run
EDAC_SETTINGS = {"pressure_model": "edac", "delta": 0.0}


def run(ctx, settings=None, label="hydrostatic"):
    dx, t_end = (0.04, 0.3) if ctx.quick else (0.01, 2.0)
    settings = settings or {}
    sim = cases.build("hydrostatic", boundary="adami", dx=dx, threads=ctx.threads, **settings)
    sim.add(MinWallDistance(), every=2e-3)
    res = sim.run(t_end, progress=False)
    ref = sim.reference
    scale = ref["rho0"] * ref["g"] * ref["depth"]
    late = res.times >= 0.5 * res.times[-1]
    rows = []
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 3.6), dpi=100)
    for p in sim.probes:
        if p.name.startswith("P"):
            exact = ref["rho0"] * ref["g"] * (ref["depth"] - p.point[-1])
            mean = float(np.mean(res[p.name][late]))
            rows.append(row(label, f"wall pressure {p.name} (y = {p.point[-1]:g} m), mean over "
                            f"{0.5 * t_end:g}-{t_end:g} s", "rho0 g (H - y)", exact, mean,
                            error=(mean - exact) / scale, kind="% of rho0 g H", tolerance=TOL, unit="Pa", fmt="{:.1f}"))
            line, = ax.plot(res.times, res[p.name], lw=0.8, label=p.name)
            ax.axhline(exact, color=line.get_color(), ls="--", lw=0.8)
    rows.append(row(label, "escaped particles", "none", 0, res.summary["escaped_particles"],
                    kind="absolute", tolerance=0))
    dmin = float(np.nanmin(res["min_wall_distance_dx"]))
    rows.append(row(label, "smallest fluid-to-wall distance [dx]", "> 0 (no particle in a wall)", None, dmin,
                    error=None, tolerance="> 0", passed=dmin > 0, fmt="{:.3f}"))
    noise = [pressure_noise(res.times, res[p.name]) for p in sim.probes if p.name.startswith("P")]
    noise = [n for n in noise if n is not None]
    notes = ["Errors of the wall-pressure rows are relative to rho0 g H = "
             f"{scale:.0f} Pa. Wall-pressure noise (RMS of p minus its 0.05 s running mean, seawall.diagnostics) "
             f"over the probes: mean {np.mean(noise) / scale * 100:.2f} % of rho0 g H (reported, no tolerance)."
             if noise else "Run too short for the wall-pressure noise."]
    ax.set_xlabel("t [s]")
    ax.set_ylabel("wall pressure [Pa]")
    ax.set_title("hydrostatic tank, Adami wall (dashed: rho0 g (H - y))")
    ax.legend(fontsize=7, ncol=4)
    fig.tight_layout()
    fig.savefig(ctx.plot_path(label.replace(" (EDAC)", "_edac")))
    plt.close(fig)
    return {"rows": rows, "notes": notes,
            "settings": f"case hydrostatic, boundary adami, dx = {dx:g} m ({sim.fluid.n} fluid particles), "
                        f"t_end = {t_end:g} s, hydrostatic start"
                        + "".join(f", {k} = {v}" for k, v in settings.items())}


ENTRIES = (
    Entry(name="hydrostatic", title="Hydrostatic tank: wall pressure against rho0 g (H - y)", run=run,
          expected_s=150, quick_s=15, order=10, description=" ".join(__doc__.split("\n\n")[1].split())),
    Entry(name="hydrostatic-edac", title="Hydrostatic tank, EDAC pressure: wall pressure against rho0 g (H - y)",
          run=partial(run, settings=EDAC_SETTINGS, label="hydrostatic (EDAC)"), expected_s=300, quick_s=15, order=11,
          description="The hydrostatic entry with the pressure evolved by the entropically damped artificial "
                      "compressibility equation ([Ramachandran2019], --set pressure_model=edac, alpha_edac = 0.5) "
                      "and no delta-SPH; Adami wall, dx = 0.01 m, 2 s from the hydrostatic state; the same "
                      "quantities and tolerances. The case's default scheme is not changed by it."),
)
