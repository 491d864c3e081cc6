"""Solitary-wave run-up on a vertical wall against Chan & Street (1970), Fig. 11.

Case ``solitary-runup`` (constant depth d = 0.25 m, Goring piston, vertical wall
10 d from the piston's start; Adami wall, free slip), dx = d/15, H/d = 0.1 ...
0.6, and the two smallest waves again at dx = d/24 (a wave of H/d = 0.1 is
1.5 particles high at d/15). Quantity: maximum run-up R/d (``RunUp`` probe: top face of the highest
particle within 2 dx of the wall, above the still level) until the crest has
reached the wall and come back. Reference: the solid curve of Chan & Street,
interpolated at H/d. Tolerance: 10 % (fixed before the run; the curve itself
is a computation that the experimental points scatter around by several %).
"""

import time
from functools import partial

import numpy as np

from seawall import cases
from seawall.validation import Entry, row
from seawall.validation._common import pyplot, run_to_the_end_or_the_stop

D = 0.25
TOL = 0.10
FOLDER = "chan_street1970_solitary_runup_wall"


def run_one(model, hd, n, threads=None, progress=False, shifting=None):
    """Maximum run-up of one solitary wave of height ``hd * d`` at dx = d/n (with particle shifting
    ``shifting`` if given); returns a dict of figures."""
    extra = {"shifting": shifting} if shifting else {}
    sim = cases.build("solitary-runup", boundary=model, depth=D, height=hd * D, dx=D / n, length=10 * D,
                      wall_height=3 * D, gauges="", threads=threads, **extra)
    sim.add(every=0.005)
    paddle = sim.reference["paddle"]
    t_end = paddle.crest_arrival(10 * D) + 4.0 / (paddle.k * paddle.c)
    t0 = time.perf_counter()
    # an unstable run keeps what it sampled: its run-up up to the stop, the stop named in its row
    res, exc = run_to_the_end_or_the_stop(sim, t_end, progress)
    stopped = exc.time if exc is not None else None
    if exc is not None:
        print(f"solitary-runup H/d = {hd:g}, dx = d/{n}: {exc}", flush=True)    # the guard's reason, in the log
    runup = res["runup"]
    return {"model": model, "H_over_d": hd, "n": n, "R_over_d": float(np.nanmax(runup)) / D,
            "t_max": float(res.times[int(np.nanargmax(runup))]), "wall_s": time.perf_counter() - t0,
            "escaped": res.summary["escaped_particles"], "fluid_particles": sim.fluid.n, "t_end": t_end,
            "stopped": stopped}


def reference(load):
    """(curve sorted by H/d, experimental points) from the data folder, via ``load(folder, file)``."""
    curve = load(FOLDER, "chan_street1970_numerical_curve.csv")
    exp = load(FOLDER, "chan_street1970_experiment.csv")
    return curve[np.argsort(curve[:, 0])], exp


def run(ctx, shifting=None):
    """The entry; ``shifting`` (sun2017 | lind2012) adds particle shifting, everything else unchanged."""
    n, heights = (8, (0.3,)) if ctx.quick else (15, (0.1, 0.2, 0.3, 0.4, 0.5, 0.6))
    n_fine, fine_heights = (12, (0.3,)) if ctx.quick else (24, (0.1, 0.2))
    curve, exp = reference(ctx.data)
    rows, found, fine = [], [], []
    for resolution, hds, runs in ((n, heights, found), (n_fine, fine_heights, fine)):
        for hd in hds:
            r = run_one("adami", hd, resolution, ctx.threads, shifting=shifting)
            runs.append(r)
            ref = float(np.interp(hd, curve[:, 0], curve[:, 1]))
            case = "solitary-runup" + ("" if r["stopped"] is None else
                                       f", run stopped (unstable) at t = {r['stopped']:.2f} of {r['t_end']:.2f} s")
            rows.append(row(case, f"R/d at H/d = {hd:g}, dx = d/{resolution}", "Chan & Street 1970, curve",
                            ref, r["R_over_d"], tolerance=TOL, fmt="{:.3f}"))
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4), dpi=100)
    ax.plot(curve[:, 0], curve[:, 1], "k-", lw=1, label="Chan & Street 1970, curve")
    ax.plot(exp[:, 0], exp[:, 1], "ko", ms=4, mfc="none", label="experiment")
    ax.plot([r["H_over_d"] for r in found], [r["R_over_d"] for r in found], "s-", ms=4,
            label=f"seawall adami, dx = d/{n}")
    ax.plot([r["H_over_d"] for r in fine], [r["R_over_d"] for r in fine], "^", ms=5,
            label=f"seawall adami, dx = d/{n_fine}")
    ax.set_xlabel("H/d")
    ax.set_ylabel("R/d")
    ax.legend(fontsize=8)
    ax.set_title("solitary-wave run-up on a vertical wall" + (f", shifting {shifting}" if shifting else ""))
    fig.tight_layout()
    fig.savefig(ctx.plot_path("solitary_runup" + (f"_{shifting}" if shifting else "")))
    plt.close(fig)
    near = []
    for r in found + fine:
        pts = exp[np.abs(exp[:, 0] - r["H_over_d"]) <= 0.02 + 1e-9, 1]
        if pts.size:
            near.append(f"H/d = {r['H_over_d']:g} (d/{r['n']}): {100 * (r['R_over_d'] / pts.mean() - 1):+.1f} %")
    return {"rows": rows,
            "settings": f"case solitary-runup, boundary adami (free slip), d = {D} m, dx = d/{n} "
                        f"({found[0]['fluid_particles']} fluid particles)"
                        + (f", particle shifting {shifting}" if shifting else "") + ", wall 10 d from the piston",
            "notes": ["Against the mean of the experimental points within 0.02 in H/d: " + "; ".join(near) + "."
                      if near else "No experimental point near the heights run.",
                      f"Escaped particles per run: {', '.join(str(r['escaped']) for r in found + fine)}."]}


ENTRIES = (
    Entry(name="solitary-runup", title="Solitary-wave run-up on a vertical wall (Chan & Street 1970)", run=run,
          expected_s=1000, quick_s=40, order=50, description=" ".join(__doc__.split("\n\n")[1].split())),
    *(Entry(name=f"solitary-runup-{kind}", title=f"Solitary-wave run-up on a vertical wall, particle shifting {kind} "
            "(Chan & Street 1970)", run=partial(run, shifting=kind), expected_s=1500, quick_s=60, order=51 + i,
            description=f"The solitary-runup entry with particle shifting {kind} after each step "
                        f"({'[Sun2017]' if kind == 'sun2017' else '[Lind2012]'}, --set shifting={kind}, with the "
                        "free-surface correction), everything else as solitary-runup; the same heights, resolutions, "
                        "reference and tolerance. Issue 17, item 6 (docs/validation-notes.md, particle shifting on "
                        "free-surface cases).")
      for i, kind in enumerate(("sun2017", "lind2012"))),
)
