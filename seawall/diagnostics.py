"""Diagnostics usable in any run: where particles escaped, wall-pressure noise.

(The third, the smallest fluid-to-wall distance, is the probe
:class:`seawall.compare.MinWallDistance`; ``seawall run --diagnostics`` adds it.)

* :func:`escaped_where` -- the removed particles grouped by the face of the
  domain box they crossed (``x-``, ``x+``, ``y-``, ``y+``, ``z-``, ``z+``: the
  axis along which the recorded position lies farthest outside the box), with
  the time of the first and last escape. Records are kept by the simulation as
  (time, id, position at removal); ``seawall run`` writes them to escaped.csv.
* :func:`pressure_noise` -- the high-frequency part of a pressure series: the
  RMS of p minus its centred running mean over ``window`` seconds (the same
  definition as the ``pressure_noise`` metric of ``seawall compare``).
"""

import numpy as np

AXES = "xyz"


def escape_side(position, lo, hi):
    """Face of the box [lo, hi) that a point outside it crossed, e.g. ``"y-"``; ``"inside"`` if it is inside.

    The face along whose axis the point lies farthest outside (a particle
    removed after one step is just past the face it crossed).
    """
    best = -1.0
    side = "inside"
    for k, c in enumerate(position):
        for dist, label in ((lo[k] - c, "-"), (c - hi[k], "+")):
            if (dist > 0 or (label == "+" and dist == 0)) and dist > best:
                best, side = dist, f"{AXES[k]}{label}"
    return side


def escaped_where(records, grid):
    """Summary of escaped-particle records ``(time, id, x, y[, z])``: count per domain face, first/last time."""
    by_side = {}
    times = []
    dim = grid.dim
    lo = grid.lo[:dim]
    hi = grid.hi[:dim]
    for rec in records:
        side = escape_side(rec[2:2 + dim], lo, hi)
        by_side[side] = by_side.get(side, 0) + 1
        times.append(float(rec[0]))
    return {"by_side": by_side, "first_time": min(times) if times else None,
            "last_time": max(times) if times else None}


def escape_sides(records, grid):
    """The face crossed by each record (list of str, same order)."""
    dim = grid.dim
    return [escape_side(rec[2:2 + dim], grid.lo[:dim], grid.hi[:dim]) for rec in records]


def pressure_noise(times, p, window=0.05):
    """RMS of ``p`` minus its centred running mean over ``window`` seconds [units of p].

    None when the series is shorter than the window. Samples are assumed
    (nearly) evenly spaced; the running mean spans round(window / median dt)
    samples, made odd and at least 3.
    """
    times = np.asarray(times, dtype=float)
    p = np.asarray(p, dtype=float)
    if times.size < 5:
        return None
    dt = float(np.median(np.diff(times)))
    if not dt > 0:
        return None
    n = max(3, int(round(window / dt)) | 1)
    if p.size <= n:
        return None
    running = np.convolve(p, np.ones(n) / n, mode="same")
    half = n // 2
    core = slice(half, p.size - half)
    d = p[core] - running[core]
    d = d[np.isfinite(d)]
    return float(np.sqrt(np.mean(d * d))) if d.size else None
