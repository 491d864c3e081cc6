"""Removal guards: which fluid particles leave the run, and when a run is lost.

After every step the simulation sorts out the fluid particles that can no
longer take part in the flow, removes them, records them (time, id,
position, reason) and goes on:

* ``overtopped`` -- outside the domain box or the hull (below) over the top
  of the walls beside it, or down the back face of an open wall: water that
  went over a crest or out through an open top (:func:`overtopped_mask`).
  Flow, not damage.
* ``domain`` -- outside the domain box, or outside the walls' **hull**: the
  region the walls enclose across gravity (below), any other way: through
  the bottom, out of a flume's open end, or out through a wall's outer face.
  A particle that went over the side of a tank is counted as soon as it is
  outside the tank, not when it has slid down the outside to the edge of the
  domain.
* ``wall`` -- deeper than ``wall_removal_depth`` behind a wall surface, the
  depth measured by :func:`seawall.diagnostics.signed_wall_distance` (the
  same signed distance as the ``min_wall_distance_dx`` probe).
* ``unstable`` -- a non-finite position, velocity or density, or a density
  outside the band [lo, hi] x rho0.

Reasons are tested in the order non-finite, domain, wall, density: a
particle that went through a wall and expanded there counts as ``wall``.
The wall guard applies below the walls' top (the highest wall particle +
dx/2 along gravity's upward direction): a particle above it cannot be in a
wall, and the nearest wall particle's normal says nothing about it (a jet
passing over the rim of an open tank). Between the wall depth and the
walls' outer face (the hull's edge) a particle that goes *through* a wall is
seen as ``wall``: for the default walls this band is 0.4 dx wide (2.6 to 3 dx
with 3 layers), and with CFL 0.2 and h = 1.3 dx a particle moves less than
0.26 dx per step, so it cannot jump over the band; with thinner bands
(other kernels) such a particle may be counted as ``domain``.

**Wall depth.** The default depth is one kernel support (2.6 dx for the
cubic spline with h = 1.3 dx): a particle that deep behind the surface has
no neighbour on the fluid side, the wall models' pressure and repulsion act
over the support, so nothing returns it to the fluid; in a layered wall
(ceil(support / dx) layers) it is in the last layer. A fraction of dx
would remove particles of runs that are healthy by their wall model's
standard: at rest in the hydrostatic tank pressure zeroing holds particles
2.06 dx and IDBC 0.61 dx behind the surface, and the MLS ghost wall lets
the collapse reach 1.38 dx (docs/boundaries.md, measured).

**Hull.** Derived from the walls unless the case gives one: with gravity
along an axis, the box spanned by the wall particles, grown by dx/2 to the
walls' outer faces, across gravity (every non-periodic axis but gravity's;
where the outermost particles are a back face, whose normals point outwards,
as an open tank's, the hull ends at their centres: water that has gone over
the crest and reached the back of the wall is out, before a wall model that
pulls water, as Adami's extrapolation of a negative pressure does, can hold
it to the outside of the wall),
bounded below along gravity by the lowest wall particle's outer face and
open above, so a splash rising above an open tank
and falling back in is kept. No gravity, gravity off the axes, or no walls:
no hull (domain box only). Walls that move are followed (the hull is taken
from their current positions at every check).

**When the run is lost.** Removals for ``wall`` and ``unstable`` are damage;
leaving the domain (``domain``, ``overtopped``) is not. The run stops with :class:`InstabilityError`
when the damage removals within the last ``unstable_window`` seconds exceed
``unstable_fraction`` of the fluid particles, or when the state cannot be
repaired particle by particle (a non-finite time step after the removals).
Both are settings of every case (``--set unstable_fraction=...``, ``[case]``
keys of a TOML file; ``seawall.cases.base.GUARD_KEYS``), recorded in
summary.json's ``damage_budget``.
"""

import math

import numpy as np
from numba import njit, prange

from .diagnostics import REASONS, wall_surface_distance
from .errors import ParameterError, require_positive
from .jit import particle_loop

KEEP = 0
DOMAIN = 1
WALL = 2
UNSTABLE = 3
OVERTOPPED = 4
#: density out of band: ``unstable`` unless the particle is also inside a wall
_DENSITY = 5

#: reasons that count as damage towards ``unstable_fraction``
DAMAGE = ("wall", "unstable")


@njit(cache=True)
def classify_particles(x, v, rho, rho_lo, rho_hi, box_lo, box_hi, out):
    """Per particle: 0 keep, 1 outside [box_lo, box_hi), 3 non-finite, 4 density outside [rho_lo, rho_hi].

    Returns the number of particles not kept. Infinite box bounds leave an
    axis open (periodic axes, the hull's upper side).
    """
    n_bad = 0
    dim = x.shape[1]
    for i in range(x.shape[0]):
        code = KEEP
        r = rho[i]
        if not np.isfinite(r):
            code = UNSTABLE
        for k in range(dim):
            if not (np.isfinite(x[i, k]) and np.isfinite(v[i, k])):
                code = UNSTABLE
        if code == KEEP:
            for k in range(dim):
                if x[i, k] < box_lo[k] or x[i, k] >= box_hi[k]:
                    code = DOMAIN
            if code == KEEP and not (r >= rho_lo and r <= rho_hi):
                code = _DENSITY
        out[i] = code
        if code != KEEP:
            n_bad += 1
    return n_bad


def derive_hull(walls, gravity, periodic, dx):
    """(lo, hi) of the walls' hull across gravity, with +-inf on open sides; None when there is none."""
    gravity = np.asarray(gravity, dtype=np.float64)
    dim = gravity.size
    if not walls or not np.any(gravity != 0.0):
        return None
    axis = int(np.argmax(np.abs(gravity)))
    if np.count_nonzero(gravity) != 1:
        return None   # gravity off the axes: "across gravity" is not a box
    pos = [w.x for w in walls if w.n]
    if not pos:
        return None
    lo = np.min([p.min(axis=0) for p in pos], axis=0) - 0.5 * dx
    hi = np.max([p.max(axis=0) for p in pos], axis=0) + 0.5 * dx
    for k in range(dim):
        if k == axis:
            continue
        for side, bound in ((-1.0, lo), (1.0, hi)):
            if _back_face(walls, k, side, bound[k] - side * 0.5 * dx, dx):
                bound[k] -= side * 0.5 * dx
    for k in range(dim):
        if periodic[k]:
            lo[k], hi[k] = -math.inf, math.inf
    if gravity[axis] < 0:
        hi[axis] = math.inf
    else:
        lo[axis] = -math.inf
    return lo, hi


def _back_face(walls, k, side, level, dx):
    """Whether the outermost wall particles along axis ``k`` on ``side`` (at ``level``) face outwards:
    a back face (an open tank's, seawall.shapes.tank), whose particles' normals point away from
    the walls' interior."""
    facing = total = 0
    for w in walls:
        if not w.n or "normal" not in w.particles:
            continue
        at = np.abs(w.x[:, k] - level) <= 1e-6 * dx
        total += int(np.count_nonzero(at))
        facing += int(np.count_nonzero(side * w.particles["normal"][at, k] > 0.5))
    return total > 0 and facing == total


def parse_hull(hull, dim):
    """Validate the ``hull`` argument of Simulation: "walls", None or a box (lo, hi) (None entries = open)."""
    if hull is None or (isinstance(hull, str) and hull == "walls"):
        return hull
    if isinstance(hull, str):
        raise ParameterError(f"hull must be 'walls', None or a box (lo, hi), got {hull!r}")
    try:
        lo, hi = hull
        lo = np.array([-math.inf if c is None else float(c) for c in lo])
        hi = np.array([math.inf if c is None else float(c) for c in hi])
    except (TypeError, ValueError):
        raise ParameterError(f"hull must be 'walls', None or a box (lo, hi) of {dim} coordinates each, "
                             f"got {hull!r}") from None
    if lo.shape != (dim,) or hi.shape != (dim,) or not np.all(hi > lo):
        raise ParameterError(f"hull must be a box (lo, hi) of {dim} coordinates each with hi > lo, got {hull!r}")
    return lo, hi


def parse_guard_settings(wall_removal_depth, unstable_fraction, unstable_window):
    """Validate the guard parameters of Simulation; return them as floats (depth None = no wall guard)."""
    if wall_removal_depth is not None and not (isinstance(wall_removal_depth, str)
                                               and wall_removal_depth == "support"):
        if isinstance(wall_removal_depth, str):
            raise ParameterError(f"wall_removal_depth must be 'support', None or a number of dx > 0, "
                                 f"got {wall_removal_depth!r}")
        wall_removal_depth = require_positive("wall_removal_depth", wall_removal_depth)
    try:
        fraction = float(unstable_fraction)
    except (TypeError, ValueError):
        raise ParameterError(f"unstable_fraction must be a number in (0, 1), got {unstable_fraction!r}") from None
    if not 0.0 < fraction < 1.0:
        raise ParameterError(f"unstable_fraction must be in (0, 1), got {unstable_fraction!r}")
    window = require_positive("unstable_window", unstable_window)
    return wall_removal_depth, fraction, window


def walls_top(walls, gravity, dx):
    """(axis, coordinate) of the walls' top along gravity's upward direction, or None (no or oblique gravity)."""
    gravity = np.asarray(gravity, dtype=np.float64)
    if np.count_nonzero(gravity) != 1 or not any(w.n for w in walls):
        return None
    axis = int(np.flatnonzero(gravity)[0])
    up = -np.sign(gravity[axis])
    top = max(float((up * w.x[:, axis]).max()) for w in walls if w.n) + 0.5 * dx
    return axis, up, top


@particle_loop(fastmath=False)
def deepest_wall_distance(x, codes, axis, up, level, xw, nw, sw, start, order, reach, deep_cells, lo, inv_cell, ncell,
                          radius2, slack, deepest):
    """deepest[i] = min(deepest[i], signed distance of particle i from this wall's surface) for the
    particles the wall guard tests (kept or density-flagged, below ``level`` along ``axis`` when
    axis >= 0) whose cell is marked in ``deep_cells`` (:func:`cells_maybe_deep`: elsewhere no
    distance can fall below the guard's depth, so the search is skipped). The distance is
    :func:`seawall.diagnostics.wall_surface_distance`'s (``slack``: the wall's spacing); one
    parallel pass without temporary arrays (the masks and copies it replaced took ~1 ms a step
    at 80k)."""
    dim = x.shape[1]
    for i in prange(x.shape[0]):
        c = codes[i]
        if c != KEEP and c != _DENSITY:
            continue
        if axis >= 0 and up * x[i, axis] >= level:
            continue
        p0 = x[i, 0]
        p1 = x[i, 1]
        p2 = x[i, 2] if dim == 3 else 0.0
        # the cell test before the call: most particles cannot be deep in this wall, and the call costs more
        c0 = min(max(int((p0 - lo[0]) * inv_cell[0]), 0), ncell[0] - 1)
        c1 = min(max(int((p1 - lo[1]) * inv_cell[1]), 0), ncell[1] - 1)
        c2 = min(max(int((p2 - lo[2]) * inv_cell[2]), 0), ncell[2] - 1)
        if deep_cells[c0 + ncell[0] * (c1 + ncell[1] * c2)] == 0:
            continue
        s = wall_surface_distance(p0, p1, p2, dim, xw, nw, sw, start, order, reach, lo, inv_cell, ncell, radius2,
                                  slack)
        if s < deepest[i]:
            deepest[i] = s


@njit(cache=True)   # serial: once per wall cell list (static walls: once per run)
def cells_maybe_deep(xw, nw, sw, cell, lo, cell_size, ncell, depth):
    """Mask of the cells where a point may lie more than ``depth`` behind this wall's surface.

    The guard's distance of a point in cell C is the largest (x - s_b) . n_b over some wall
    particles b in the 5^d cells around C (:func:`seawall.diagnostics.wall_surface_distance`),
    so it is at least the minimum over those b and over the cell's box of that linear function, reached at the
    box corner opposite to n_b. Cells whose minimum is above -depth cannot hold a particle the
    guard removes and are not searched: the test decides exactly as the search would, and most
    fluid particles near a wall are in such cells. The box is widened by 1e-6 of a cell (the
    cell index is a rounded product) and open on the grid's outer faces (positions beyond are
    clamped into the edge cells); the threshold keeps a margin of 1e-6 of a cell over the
    round-off of the distance.
    """
    nx, ny, nz = ncell[0], ncell[1], ncell[2]
    dim = xw.shape[1]
    floor = np.full(nx * ny * nz, np.inf)
    zr = 2 if dim == 3 else 0
    smallest = cell_size[0]
    for k in range(1, cell_size.shape[0]):   # not cell_size.min(): Numba's generic min took 0.9 s to compile
        smallest = min(smallest, cell_size[k])
    slack = 1e-6 * smallest
    for b in range(xw.shape[0]):
        cb = cell[b]
        bx = cb % nx
        by = (cb // nx) % ny
        bz = cb // (nx * ny)
        for oz in range(-zr, zr + 1):
            cz = bz + oz
            if cz < 0 or cz >= nz:
                continue
            for oy in range(-2, 3):
                cy = by + oy
                if cy < 0 or cy >= ny:
                    continue
                for ox in range(-2, 3):
                    cx = bx + ox
                    if cx < 0 or cx >= nx:
                        continue
                    m = 0.0
                    for k in range(dim):
                        n = nw[b, k]
                        if n == 0.0:
                            continue
                        ck = cx if k == 0 else (cy if k == 1 else cz)
                        if n > 0.0:   # the box's low face minimises n . x
                            corner = -np.inf if ck == 0 else lo[k] + ck * cell_size[k] - slack
                        else:
                            corner = np.inf if ck == ncell[k] - 1 else lo[k] + (ck + 1) * cell_size[k] + slack
                        m += n * (corner - sw[b, k])
                    c = cx + nx * (cy + ny * cz)
                    if m < floor[c]:
                        floor[c] = m
    out = np.zeros(nx * ny * nz, dtype=np.uint8)
    threshold = -depth + slack
    for c in range(nx * ny * nz):
        if floor[c] < threshold:
            out[c] = 1
    return out


def _deep_cells(wall, grid, depth):
    """:func:`cells_maybe_deep` of a static wall, kept while its cell list and the depth are the same.

    A moving wall gets its reach mask instead (every cell a search can find a wall particle
    from, the test before this filter): the filter visits 5^d cells per wall particle, which
    pays once per run but not at every step of a large moving wall.
    """
    if wall.movement is not None:
        return wall.cells.reach_mask(grid)
    cached = getattr(wall, "_deep_cells_cache", None)
    if cached is not None and cached[0] is wall.cells and cached[1] == depth:
        return cached[2]
    pa = wall.particles
    mask = cells_maybe_deep(pa["x"], pa["normal"], pa["surface"], wall.cells.cell, grid.lo, grid.cell_size,
                            grid.ncell, float(depth))
    wall._deep_cells_cache = (wall.cells, depth, mask)
    return mask


def wall_depth_codes(sim, depth, codes, top=None):
    """Set ``codes`` to WALL where a fluid particle lies more than ``depth`` [m] behind a wall surface.

    ``top``: (axis, up, coordinate) from :func:`walls_top`; particles above it are not tested.
    """
    fp = sim.fluid.particles
    g = sim.grid
    axis, up, level = (int(top[0]), float(top[1]), float(top[2])) if top is not None else (-1, 1.0, 0.0)
    deepest = None
    for wall in sim.walls:
        pa = wall.particles
        if wall.n == 0 or "normal" not in pa or "surface" not in pa:
            continue
        if deepest is None:
            deepest = np.full(fp.n, np.inf)
        deepest_wall_distance(fp["x"], codes, axis, up, level, pa["x"], pa["normal"], pa["surface"], wall.cells.start,
                              wall.cells.order, wall.cells.reach_mask(g), _deep_cells(wall, g, depth), g.lo,
                              g.inv_cell, g.ncell, sim.physics.support2, wall.spacing, deepest)
    if deepest is not None:
        codes[deepest < -depth] = WALL


def column_tops(walls, axis, up, cell):
    """The walls' top along gravity per horizontal column of width ``cell``: (lo, tops), with
    ``tops`` an array over the columns (one axis in 2D, two in 3D) of the highest wall particle's
    coordinate along ``up`` plus cell / 2 (its outer face), -inf where a column holds none."""
    pos = np.concatenate([w.x for w in walls if w.n])
    horizontal = [k for k in range(pos.shape[1]) if k != axis]
    hx = pos[:, horizontal]
    lo = hx.min(axis=0)
    idx = np.floor((hx - lo) / cell).astype(np.int64)
    shape = tuple(int(i) + 1 for i in idx.max(axis=0))
    tops = np.full(shape, -np.inf)
    np.maximum.at(tops, tuple(idx.T), up * pos[:, axis] + 0.5 * cell)
    return lo, tops


def overtopped_mask(x, walls, gravity, cell, reach):
    """Which of the points ``x`` (fluid particles leaving the domain or the hull) left over the walls.

    A point is overtopped when it left

    * over the top: it is not below the top of the walls within ``reach`` (one kernel support)
      of it across gravity (:func:`column_tops`) by more than ``reach`` (water that passed over a
      crest cannot be deeper below it without the wall guard removing it as ``wall`` first), or
      upwards where no wall stands beside it (out of an open top, above every wall); or
    * down the back of a wall: the wall particle nearest to it within ``reach`` faces away from
      the walls' interior, towards the way it left (its normal points out of the hull along the
      axis it crossed: an open tank's back face, ``seawall.shapes.tank``). Such walls are thick
      enough that water going *through* them is removed as ``wall`` before it reaches their back.

    Otherwise it went through or under a wall (``domain``). No gravity along one axis, or no
    walls: none is.
    """
    gravity = np.asarray(gravity, dtype=np.float64)
    out = np.zeros(x.shape[0], dtype=bool)
    if x.shape[0] == 0 or np.count_nonzero(gravity) != 1 or not any(w.n for w in walls):
        return out
    axis = int(np.flatnonzero(gravity)[0])
    up = -np.sign(gravity[axis])
    lo, tops = column_tops(walls, axis, up, cell)
    overall = float(tops.max())
    horizontal = [k for k in range(x.shape[1]) if k != axis]
    span = int(math.ceil(reach / cell))
    faced = [w for w in walls if w.n and "normal" in w.particles]
    centre = 0.5 * (np.min([w.x.min(axis=0) for w in walls if w.n], axis=0)
                    + np.max([w.x.max(axis=0) for w in walls if w.n], axis=0))
    for i in range(x.shape[0]):
        height = up * x[i, axis]
        c = np.floor((x[i, horizontal] - lo) / cell).astype(np.int64)
        window = tuple(slice(max(int(ck) - span, 0), max(int(ck) + span + 1, 0)) for ck in c)
        near = tops[window]
        local = float(near.max()) if near.size else -np.inf
        if np.isfinite(local):
            out[i] = height >= local - reach
        else:
            out[i] = height >= overall
        if out[i] or not faced:
            continue
        # the nearest wall particle: does it face out of the walls' interior, the way the point left?
        best, normal, where = np.inf, None, None
        for w in faced:
            r2 = np.sum((w.x - x[i]) ** 2, axis=1)
            b = int(np.argmin(r2))
            if r2[b] < best:
                best, normal, where = float(r2[b]), w.particles["normal"][b], w.x[b]
        if best <= reach * reach:
            outward = where - centre
            outward[axis] = 0.0
            out[i] = float(np.dot(normal, outward)) > 0.0
    return out


def reason_name(code):
    return REASONS[code - 1]
