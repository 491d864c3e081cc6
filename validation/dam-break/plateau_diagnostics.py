"""Diagnostic runs for the plateau profiles (issue 15, item 7): one choice changed at a time.

    python validation/dam-break/plateau_diagnostics.py NAME [NAME ...]     # run variants
    python validation/dam-break/plateau_diagnostics.py --list               # the variants

Each variant is a wall model with options at a resolution, run like a row of the leak sweep
(``validation/leaks/sweep.py``: same case, probes and plateau read-outs of
``plateau_profiles.py``, its own process) but only to t sqrt(g/H) = 5.5, the end of the
plateau window. Results go to ``validation/dam-break/results/plateau_diagnostics.json``
(a variant replaces only its own entry); run directories with the corner snapshots to
``validation/leaks/runs/diag`` (not kept in git).
"""

import argparse
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "validation", "leaks"))
sys.path.insert(0, ROOT)

import sweep  # noqa: E402  (validation/leaks/sweep.py: its worker is spawned by module name)

OUT = os.path.join(HERE, "results", "plateau_diagnostics.json")
RUNS = os.path.join(ROOT, "validation", "leaks", "runs", "diag")
T_STAR = 5.5
#: water at 20 C [m^2/s]
NU_WATER = 1.0e-6

#: name -> (model, options, N in dx = H/N, what it isolates)
VARIANTS = {
    "adami-h50": ("adami", {}, 50, "the read-outs (with the force read-out)"),
    "dbc-h50": ("dbc", {}, 50, "the read-outs of a wall that keeps a gap"),
    "adami-h30": ("adami", {}, 30, "resolution"),
    "adami-h100": ("adami", {}, 100, "resolution"),
    "ghost-mls1-h30": ("ghost-mls1", {}, 30, "the ghost walls' first fluid column"),
    "ghost-normalized-h30": ("ghost-normalized", {}, 30, "the ghost walls' first fluid column"),
    "ghost-mls1-h50": ("ghost-mls1", {}, 50, "the ghost walls' first fluid column"),
    "ghost-mls1-h30-fixed": ("ghost-mls1", {}, 30, "the corner ghosts' free-slip image, after the fix"),
    "ghost-normalized-h30-fixed": ("ghost-normalized", {}, 30, "the corner ghosts' free-slip image, after the fix"),
    "adami-noslip-h100": ("adami-noslip", {}, 100, "resolution"),
    "adami-noslip-h30": ("adami-noslip", {}, 30, "resolution"),
    "adami-noslip-nu-water": ("adami-noslip", {"wall_nu": NU_WATER}, 50,
                              "no slip with water's viscosity at the wall instead of alpha h c0 / 8"),
    "adami-noslip-nu-quarter": ("adami-noslip", {"wall_nu": "quarter"}, 50,
                                "no slip with a quarter of the default wall viscosity alpha h c0 / 8"),
    "liu2015-noslip-wall-normal": ("liu2015-noslip", {"normal_velocity": "wall"}, 50,
                                   "eq. 21 with the wall's normal velocity instead of eq. 29's mirror"),
    "liu2015-noslip-wall-normal-h100": ("liu2015-noslip", {"normal_velocity": "wall"}, 100,
                                        "eq. 21 with the wall's normal velocity instead of eq. 29's mirror"),
    "idbc-h50": ("idbc", {}, 50, "IDBC's wall densities under [Li2022]'s continuity rule (wall_layers.py)"),
    "idbc-consistent-h50": ("idbc", {"wall_density": "consistent"}, 50,
                            "IDBC with the exact integral of eq. 8 instead (wall_layers.py)"),
}


def _options(params, dx):
    """Resolve symbolic options (``quarter``: a quarter of alpha h c0 / 8 of the case)."""
    out = {}
    for k, v in params.items():
        if v == "quarter":
            from seawall.cases import case_by_name

            sim = case_by_name("dam-break").build(boundary="adami", dx=dx, threads=1)
            prm = sim.physics
            v = 0.25 * prm.alpha * prm.h * prm.c0 / 8.0
        out[k] = v
    return out


def table(readouts=("wall", "force", "int1.6", "layer")):
    """Markdown table of the stored variants: plateau p / (rho g H) per height and read-out."""
    with open(OUT) as fh:
        data = json.load(fh)
    heights = ("0.01", "0.05", "0.1", "0.2", "0.27")
    lines = ["| variant | model, options | H/N | run (t*) | read-out | " + " | ".join(f"y/H = {h}" for h in heights) + " |",
             "| --- | --- | --- | --- | --- | " + " | ".join("---" for _ in heights) + " |"]
    for name, r in data.items():
        pl = r.get("plateau") or {}
        opts = ", ".join(f"{k}={v:.3g}" if isinstance(v, float) else f"{k}={v}"
                         for k, v in sorted((r.get("params") or {}).items())) or "defaults"
        run = f"{r['status']} ({r.get('t_stop', 0) * math.sqrt(sweep.G / sweep.H):.2f})"
        for k, ro in enumerate(readouts):
            vals = pl.get(ro) or {}
            cells = ["n/a" if vals.get(h) is None else f"{vals[h]:.2f}" for h in heights]
            head = f"| {name} | `{r['model']}` {opts} | {r['resolution']} | {run} |" if k == 0 else "| | | | |"
            lines.append(f"{head} {ro} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def write_doc():
    doc = os.path.join(ROOT, "docs", "validation-notes.md")
    from seawall.validation import replace_block

    replace_block(doc, "<!-- plateau-diagnostics:begin -->", "<!-- plateau-diagnostics:end -->", table())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--table", action="store_true", help="print the markdown table of the stored variants")
    parser.add_argument("--write-doc", action="store_true",
                        help="write the table into docs/validation-notes.md between its markers")
    parser.add_argument("--t-star", type=float, default=T_STAR, help=f"end time t sqrt(g/H) (default {T_STAR})")
    args = parser.parse_args(argv)
    if args.table:
        print(table())
        return 0
    if args.write_doc:
        write_doc()
        return 0
    if args.list or not args.names:
        for k, (m, p, n, what) in VARIANTS.items():
            print(f"{k:28s} {m} {p} H/{n}: {what}")
        return 0
    for name in args.names:
        if name not in VARIANTS:
            parser.error(f"unknown variant {name!r}; --list shows them")
    for name in args.names:
        model, params, n, what = VARIANTS[name]
        dx = sweep.H / n
        opts = _options(params, dx)
        t_end = args.t_star * math.sqrt(sweep.H / sweep.G)
        print(f"[diag] {name}: {model} {opts} dx = {dx:.4g} m to t* = {args.t_star}", flush=True)
        rec = sweep.run_model(model, dx, t_end, opts, os.path.join(RUNS, name), 1)
        rec.update({"variant": name, "resolution": n, "what": what, "t_star": args.t_star})
        print(f"[diag] {name}: {rec['status']} escaped {rec.get('escaped')}", flush=True)
        data = sweep.read_json(OUT)
        data[name] = rec
        sweep.write_json(OUT, data)
    return 0


if __name__ == "__main__":
    sys.exit(main())
