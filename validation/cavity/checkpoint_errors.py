"""Centreline errors of a cavity run's checkpoints against Ghia et al., as the entries measure them.

    python validation/cavity/checkpoint_errors.py RUN_DIR [--set KEY=VALUE ...] [--dx DX]

RUN_DIR is the output of ``seawall run cavity ... --checkpoint-every T``; give the same
``--set`` and ``--dx`` as that run (the checkpoint is loaded into an identically built case).
For each checkpoint: its time, the worst u/U on x = L/2 and v/U on y = L/2 over the 15
interior reference points (error in % of U, its s) -- the rows of ``run_cavity`` in
``entry.py``, read at every checkpoint instead of only at the end, so a long run can be
followed while it runs.
"""

import argparse
import glob
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, ROOT)

from seawall import cases  # noqa: E402
from seawall.cases.lid_cavity import centrelines  # noqa: E402
from seawall.sweep import split_set_item  # noqa: E402


def ghia(reynolds):
    col = {100: 2, 400: 3, 1000: 4}[int(reynolds)]
    tu = np.loadtxt(os.path.join(ROOT, "data", "ghia1982_lid_driven_cavity", "ghia1982_u_vertical_centerline.csv"),
                    delimiter=",", skiprows=1)
    tv = np.loadtxt(os.path.join(ROOT, "data", "ghia1982_lid_driven_cavity", "ghia1982_v_horizontal_centerline.csv"),
                    delimiter=",", skiprows=1)
    return tu[:, 1], tu[:, col], tv[:, 1], tv[:, col]


def worst(s, got, want):
    inside = (s > 0.0) & (s < 1.0)
    err = np.where(inside, got - want, 0.0)
    k = int(np.nanargmax(np.abs(err)))
    return err[k], s[k]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--dx", type=float, default=None)
    args = parser.parse_args(argv)
    params = dict(split_set_item(item) for item in args.set)
    files = sorted(glob.glob(os.path.join(args.run_dir, "**", "*.h5"), recursive=True), key=os.path.getmtime)
    if not files:
        sys.exit(f"run_dir: no checkpoint (*.h5) under {args.run_dir}")
    print("t [s] | u/U worst [% of U] (s) | v/U worst [% of U] (s)")
    for path in files:
        sim = cases.build("cavity", boundary="adami-noslip", dx=args.dx, threads=1, **params)
        sim.restart(path)
        s_u, u_ref, s_v, v_ref = ghia(sim.reference["reynolds"])
        u, v = centrelines(sim, s_u, s_v)
        eu, su = worst(s_u, u, u_ref)
        ev, sv = worst(s_v, v, v_ref)
        print(f"{sim.time:.3f} | {100 * eu:+.2f} ({su:.3f}) | {100 * ev:+.2f} ({sv:.3f})", flush=True)


if __name__ == "__main__":
    main()
