"""Diagnostics usable in any run: where particles escaped, wall-pressure noise, wall distance.

* :func:`signed_wall_distance` -- per fluid particle, the signed distance to
  the wall surface (negative = inside the wall). The probe
  :class:`seawall.compare.MinWallDistance` (``seawall run --diagnostics``)
  reports its minimum; the simulation's wall guard removes particles deeper
  than ``wall_removal_depth`` (``seawall.health``).
* :func:`escaped_where` -- the removed particles grouped by the face of the
  domain box they crossed (``x-``, ``x+``, ``y-``, ``y+``, ``z-``, ``z+``: the
  axis along which the recorded position lies farthest outside the box), with
  the time of the first and last escape. Records are kept by the simulation as
  (time, id, position at removal, reason); ``seawall run`` writes them to
  escaped.csv. A particle removed for leaving the walls' hull is given the
  hull face it crossed; one removed inside both (a wall crossing, a density
  or non-finite guard) gets ``inside``.
* :func:`escaped_by_reason` -- the records counted per removal reason
  (``domain``, ``wall``, ``unstable``; see ``seawall.health``).
* :func:`pressure_noise` -- the high-frequency part of a pressure series: the
  RMS of p minus its centred running mean over ``window`` seconds (the same
  definition as the ``pressure_noise`` metric of ``seawall compare``).
* :func:`running_mean`, :func:`interval_mean` -- smoothing of a probe series:
  a centred running mean, and the mean over consecutive output intervals of a
  series sampled every step (what a transducer of finite bandwidth reports).
* :func:`impact_features` -- arrival, first peak, plateau, secondary peak (value
  and time) and the pre-impact level of a dimensionless wall-pressure history
  p/(rho g H) against t sqrt(g/H): the features the Buchner (2002) dam-break
  validation compares (seawall validate dam-break).
"""

import math

import numpy as np
from numba import njit, prange

from .jit import particle_loop

AXES = "xyz"

#: why a fluid particle was removed (the ``reason`` of escaped records, in this order in summaries)
REASONS = ("domain", "wall", "unstable", "overtopped")


@njit(cache=True)
def _walk_wall_cells(p0, p1, p2, dim, xw, nw, sw, start, order, lo, inv_cell, ncell, radius2, limit2):
    """One walk over the wall particles in the 5^d cells around the point (p0, p1, p2): the index of
    the nearest within sqrt(radius2) (-1 if none) and, when ``limit2`` >= 0, the largest surface-plane
    distance (x - s_b) . n_b of those within sqrt(limit2) (-inf if none; ``nw``, ``sw`` unread else)."""
    c0 = min(max(int((p0 - lo[0]) * inv_cell[0]), 0), ncell[0] - 1)
    c1 = min(max(int((p1 - lo[1]) * inv_cell[1]), 0), ncell[1] - 1)
    c2 = min(max(int((p2 - lo[2]) * inv_cell[2]), 0), ncell[2] - 1)
    best = radius2
    b_best = -1
    plane = -np.inf
    zr = 2 if dim == 3 else 0
    for oz in range(-zr, zr + 1):
        cz = c2 + oz
        if cz < 0 or cz >= ncell[2]:
            continue
        for oy in range(-2, 3):
            cy = c1 + oy
            if cy < 0 or cy >= ncell[1]:
                continue
            for ox in range(-2, 3):
                cx = c0 + ox
                if cx < 0 or cx >= ncell[0]:
                    continue
                cell = cx + ncell[0] * (cy + ncell[1] * cz)
                for kk in range(start[cell], start[cell + 1]):
                    b = order[kk]
                    d0 = p0 - xw[b, 0]
                    d1 = p1 - xw[b, 1]
                    r2 = d0 * d0 + d1 * d1
                    if dim == 3:
                        d2 = p2 - xw[b, 2]
                        r2 += d2 * d2
                    if r2 < best:
                        best = r2
                        b_best = b
                    if r2 <= limit2:
                        s = (p0 - sw[b, 0]) * nw[b, 0] + (p1 - sw[b, 1]) * nw[b, 1]
                        if dim == 3:
                            s += (p2 - sw[b, 2]) * nw[b, 2]
                        if s > plane:
                            plane = s
    return b_best, plane


@njit(cache=True)
def nearest_wall_particle(p0, p1, p2, dim, xw, start, order, reach, lo, inv_cell, ncell, radius2):
    """Index of the wall particle nearest to the point (p0, p1, p2) within sqrt(radius2), else -1.

    The search visits the 5^d cells around the point's cell (cells at least
    radius / 2 wide). ``reach`` (uint8 per cell, ``CellList.reach_mask``)
    marks the cells with a wall particle in their 5^d neighbourhood; a point
    elsewhere returns -1 without a search, which keeps the cost to the fluid
    near walls.
    """
    c0 = min(max(int((p0 - lo[0]) * inv_cell[0]), 0), ncell[0] - 1)
    c1 = min(max(int((p1 - lo[1]) * inv_cell[1]), 0), ncell[1] - 1)
    c2 = min(max(int((p2 - lo[2]) * inv_cell[2]), 0), ncell[2] - 1)
    if reach.size and reach[c0 + ncell[0] * (c1 + ncell[1] * c2)] == 0:
        return -1
    b_best, _ = _walk_wall_cells(p0, p1, p2, dim, xw, xw, xw, start, order, lo, inv_cell, ncell, radius2, -1.0)
    return b_best


@njit(cache=True)
def wall_surface_distance(p0, p1, p2, dim, xw, nw, sw, start, order, reach, lo, inv_cell, ncell, radius2, slack):
    """Signed distance of the point (p0, p1, p2) from a wall's surface (negative inside), +inf when no
    wall particle lies within sqrt(radius2).

    Each wall particle b carries the plane of its closest surface point s_b and normal n_b
    (``seawall.shapes``); the value is the largest (x - s_b) . n_b over the wall particles within
    ``slack`` (one wall spacing) of the nearest one's distance. Near a face every such plane is the
    face's. Inside a convex edge of the material (a crest's edges, a block's corners) the material
    is the intersection of its faces' half-planes, whose signed distance is the largest of theirs:
    the set then holds particles of both faces, while the nearest particle alone may be one on the
    edge's bisector, whose plane gives up to sqrt(2) times the depth at a right angle. Inside a
    concave corner the nearest particles are the corner's own, whose planes are the distance to
    the corner.
    """
    b_near = nearest_wall_particle(p0, p1, p2, dim, xw, start, order, reach, lo, inv_cell, ncell, radius2)
    if b_near < 0:
        return np.inf
    d0 = p0 - xw[b_near, 0]
    d1 = p1 - xw[b_near, 1]
    r2 = d0 * d0 + d1 * d1
    if dim == 3:
        d2 = p2 - xw[b_near, 2]
        r2 += d2 * d2
    limit = np.sqrt(r2) + slack
    _, plane = _walk_wall_cells(p0, p1, p2, dim, xw, nw, sw, start, order, lo, inv_cell, ncell, radius2,
                                limit * limit)
    return plane


@particle_loop(fastmath=False)
def signed_wall_distance(xf, xw, nw, sw, start, order, reach, lo, inv_cell, ncell, radius2, slack, out):
    """Per fluid particle: its signed distance from the wall's surface (:func:`wall_surface_distance`),
    +inf away from the wall.

    Negative inside the wall. Particles away from every wall get +inf without a search
    (:func:`nearest_wall_particle`'s reach mask).
    """
    from_dim = xf.shape[1]
    for i in prange(xf.shape[0]):
        # scalars, not small arrays: an allocation per particle cost more than the search
        p0 = xf[i, 0]
        p1 = xf[i, 1]
        p2 = xf[i, 2] if from_dim == 3 else 0.0
        out[i] = wall_surface_distance(p0, p1, p2, from_dim, xw, nw, sw, start, order, reach, lo, inv_cell, ncell,
                                       radius2, slack)


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


def record_reason(record, dim):
    """Reason of an escaped record; records without one (older checkpoints) left the domain."""
    return record[2 + dim] if len(record) > 2 + dim else "domain"


def _side(record, dim, lo, hi, hull):
    side = escape_side(record[2:2 + dim], lo, hi)
    if side == "inside" and hull is not None and record_reason(record, dim) in ("domain", "overtopped"):
        side = escape_side(record[2:2 + dim], hull[0], hull[1])
    return side


def escaped_where(records, grid, hull=None):
    """Summary of escaped-particle records ``(time, id, x, y[, z], reason)``: count per face, first/last time.

    ``hull``: the (lo, hi) box of the walls' hull (``Simulation.hull_box()``)
    that gives the face of particles removed inside the domain box.
    """
    by_side = {}
    times = []
    dim = grid.dim
    lo = grid.lo[:dim]
    hi = grid.hi[:dim]
    for rec in records:
        side = _side(rec, dim, lo, hi, hull)
        by_side[side] = by_side.get(side, 0) + 1
        times.append(float(rec[0]))
    return {"by_side": by_side, "first_time": min(times) if times else None,
            "last_time": max(times) if times else None}


def escape_sides(records, grid, hull=None):
    """The face crossed by each record (list of str, same order); see :func:`escaped_where`."""
    dim = grid.dim
    return [_side(rec, dim, grid.lo[:dim], grid.hi[:dim], hull) for rec in records]


def escaped_by_reason(records, dim):
    """Number of records per removal reason, every reason of :data:`REASONS` present (0 if none)."""
    counts = dict.fromkeys(REASONS, 0)
    for rec in records:
        reason = record_reason(rec, dim)
        counts[reason] = counts.get(reason, 0) + 1
    return counts


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


def running_mean(t, p, width):
    """Centred running mean of ``p`` over ``width`` (units of ``t``); samples assumed evenly spaced.

    The window spans round(width / median dt) samples, made odd; the ends use
    the zero-padded convolution (the mean is biased over the first and last
    half window).
    """
    t = np.asarray(t, dtype=float)
    p = np.asarray(p, dtype=float)
    dt = float(np.median(np.diff(t)))
    n = max(1, int(round(width / dt)) | 1)
    if n <= 1 or p.size <= n:
        return p.copy()
    return np.convolve(p, np.ones(n) / n, mode="same")


def interval_mean(t, p, every):
    """Time-weighted mean of a step-sampled series over consecutive intervals of ``every`` seconds.

    A sample at t_k stands for the step (t_{k-1}, t_k] (the first for a step as long as the
    second sample's); each interval
    [k every, (k + 1) every) reports the mean of the samples whose step ends in it,
    weighted by their step length, at its end time. Returns (times, means) of the
    non-empty intervals. This is a box filter of width ``every``: a transducer
    read out at 1/every whose response averages over its sampling interval
    (first zero of the transfer function at 1/every Hz, -3 dB at about 0.44/every).
    """
    t = np.asarray(t, dtype=float)
    p = np.asarray(p, dtype=float)
    if t.size < 2:
        return t.copy(), p.copy()
    w = np.diff(t, prepend=t[0] - (t[1] - t[0]))
    k = np.floor(t / every - 1e-9).astype(np.int64)
    kk, first = np.unique(k, return_index=True)
    sw = np.add.reduceat(w, first)
    sp = np.add.reduceat(w * p, first)
    return (kk + 1) * every, sp / sw


#: names of :func:`impact_features`' values, in order
IMPACT_FEATURES = ("arrival", "first_peak", "plateau", "secondary_peak", "pre_impact", "secondary_time")


def impact_features(t, p):
    """Features of a wall-pressure history p* = p/(rho g H) against t* = t sqrt(g/H) (dam break, sensor P1).

    Returns a tuple in the order of :data:`IMPACT_FEATURES`:

    * arrival: first t* > 2 where p* reaches 0.2;
    * first (impact) peak: largest p* over 2.3 < t* < 3.3;
    * plateau: mean p* over 3.5 < t* < 5.2 (linear interpolation on 200 points);
    * secondary (returning plunging wave) peak: largest p* over 5.4 < t* < 6.4;
    * pre-impact: largest |p*| over 0.5 < t* < 2.3 (the sensor is dry);
    * secondary-peak time: the t* of that largest p*.

    NaN for a feature whose window the series does not cover. ``t`` must be sorted.
    """
    t = np.asarray(t, dtype=float)
    p = np.asarray(p, dtype=float)

    def window(a, b):
        return (t > a) & (t < b)

    def peak(a, b):
        m = window(a, b)
        if not m.any() or t[-1] < b:
            return math.nan, math.nan
        k = int(np.argmax(np.where(m, p, -np.inf)))
        return float(p[k]), float(t[k])
    after = (t > 2.0) & (p >= 0.2)
    arrival = float(t[np.argmax(after)]) if after.any() else math.nan
    grid = np.linspace(3.5, 5.2, 200)
    plateau = float(np.mean(np.interp(grid, t, p))) if t[-1] >= 5.2 else math.nan
    pre = p[window(0.5, 2.3)]
    first, _ = peak(2.3, 3.3)
    second, second_t = peak(5.4, 6.4)
    return (arrival, first, plateau, second, float(np.abs(pre).max()) if pre.size else math.nan, second_t)
