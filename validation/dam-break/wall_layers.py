"""What the wall particles hold near the downstream corner of the dam break (issue 15, item 7).

    python validation/dam-break/wall_layers.py RUN_DIR [RUN_DIR ...]

For each snapshot of a run (t sqrt(g/H) = 3.5, 4, 4.5, 5; ``plateau_snapshots.npz`` of the leak
sweep or of plateau_diagnostics.py) and each height y/H of the plateau profile, prints

* ``gap``: the mean distance from the downstream wall's surface of the two fluid particles nearest
  to it within y +- dx, in dx -- how far the wall keeps its fluid off;
* ``wall1``: the median pressure of the wall's first particle layer within y +- 2 dx, in rho g H
  -- what the wall particles hold, against the fluid's ~0.4-1 rho g H there;

and, for the floor's first layer within 0.5 H of the downstream wall (the part the snapshots
keep), the median pressure and the fraction below zero; and the fluid particle deepest behind any
wall surface (signed distance in dx, position, velocity). dx and the wall's surface are
read as :func:`geometry` says.
"""

import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))
from seawall.validation import load_script  # noqa: E402  (this checkout's seawall, put on the path above)

plateau_profiles = load_script(os.path.join(HERE, "plateau_profiles.py"))

#: the sweep's dam break and the plateau profile's heights
H = plateau_profiles.sweep_module().H
G = plateau_profiles.G
RHO_G_H = plateau_profiles.RHO0 * G * H
HEIGHTS = plateau_profiles.HEIGHTS


def geometry(snapshots, k, run_dir=None):
    """(dx, x of the downstream wall's surface, offset of the wall's first row behind it) of snapshot
    ``k`` of the loaded ``plateau_snapshots.npz``.

    Snapshots written since the file stores ``dx`` and ``surface_x`` carry both. For older ones they
    are read from the wall particles: a layered wall's columns are dx apart with the first dx/2
    behind the surface; a one-row wall (``monaghan-kajtar``, ``liu2012``) sits on the surface at a
    finer spacing, so dx comes from the run's ``summary.json`` in ``run_dir``.
    """
    wall_x = snapshots[f"w{k}_x"]
    side = (wall_x[:, 1] > 0.05 * H) & (wall_x[:, 1] < 1.5 * H)
    columns = np.unique(np.round(wall_x[side, 0], 9))
    if "dx" in snapshots.files and "surface_x" in snapshots.files:
        dx, surface = float(snapshots["dx"]), float(snapshots["surface_x"])
        return dx, surface, float(columns[0] - surface)
    if len(columns) > 1:
        spacing = float(columns[1] - columns[0])
        return spacing, float(columns[0]) - 0.5 * spacing, 0.5 * spacing
    summary = os.path.join(run_dir or "", "summary.json")
    if not os.path.exists(summary):
        raise ValueError(f"RUN_DIR {run_dir!r}: a one-row wall's snapshots need the run's summary.json for dx")
    with open(summary) as fh:
        return float(json.load(fh)["dx"]), float(columns[0]), 0.0


def snapshot_rows(path):
    """One dict per snapshot of the run directory ``path`` (see the module docstring)."""
    d = np.load(os.path.join(path, "plateau_snapshots.npz"))
    rows = []
    k = 0
    while f"t{k}" in d.files:
        x, v, wx = d[f"f{k}_x"], d[f"f{k}_v"], d[f"w{k}_x"]
        # repulsive-force walls (monaghan-kajtar) carry no pressure: their wall columns read nan
        wp = d[f"w{k}_p"] if f"w{k}_p" in d.files else np.full(len(wx), np.nan)
        dx, length, first_offset = geometry(d, k, path)
        s = length - x[:, 0]                       # distance from the downstream wall's surface
        row = {"t_star": float(d[f"t{k}"]) * np.sqrt(G / H), "dx": dx, "heights": {}}
        for frac in HEIGHTS:
            y = frac * H
            band = np.abs(x[:, 1] - y) < dx
            gap = float(np.sort(s[band])[:2].mean() / dx) if band.sum() >= 2 else float("nan")
            first = (np.abs(wx[:, 0] - (length + first_offset)) < 1e-6) & (np.abs(wx[:, 1] - y) < 2 * dx)
            wall1 = float(np.median(wp[first]) / RHO_G_H) if first.any() else float("nan")
            row["heights"][frac] = (gap, wall1)
        floor = (np.abs(wx[:, 1] + first_offset) < 1e-6) & (wx[:, 0] < length)
        row["floor_median"] = float(np.median(wp[floor]) / RHO_G_H)
        row["floor_negative"] = (float((wp[floor] < 0).mean()) if np.isfinite(wp[floor]).all()
                                 else float("nan"))
        depth = np.minimum(np.minimum(x[:, 0], s), x[:, 1]) / dx   # left wall at x = 0, floor at y = 0
        i = int(np.argmin(depth))
        row["deepest"] = (float(depth[i]), tuple(x[i]), tuple(v[i]))
        rows.append(row)
        k += 1
    return rows


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    for path in argv:
        if not os.path.exists(os.path.join(path, "plateau_snapshots.npz")):
            print(f"wall_layers.py: RUN_DIR {path!r} has no plateau_snapshots.npz (a run directory of the leak "
                  "sweep or of plateau_diagnostics.py)", file=sys.stderr)
            return 2
        print(f"## {path}")
        print("t*   | " + " | ".join(f"y/H {f:g}: gap, wall1" for f in HEIGHTS)
              + " | floor1 median, <0 | deepest (dx; x, y; u, v)")
        for r in snapshot_rows(path):
            cells = " | ".join(f"{g:.2f}, {w:.1f}" for g, w in r["heights"].values())
            dist, pos, vel = r["deepest"]
            print(f"{r['t_star']:.2f} | {cells} | {r['floor_median']:.2f}, {r['floor_negative']:.2f} | "
                  f"{dist:.2f}; {pos[0]:.4f}, {pos[1]:.4f}; {vel[0]:.3f}, {vel[1]:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
