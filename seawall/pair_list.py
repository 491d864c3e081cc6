"""The fluid's neighbour pairs kept over several steps: a Verlet list with a skin.

The cell walk (:func:`seawall.neighbors.reach_range`) tests every particle of the cells a
particle's support touches: in the 3D dam break 156 candidates for 71 neighbours, and the walk
with its distance tests alone took 14.9-18.5 ms per pass, of the fluid loop's 48 (one thread,
stand-alone loops; docs/performance.md, "Pairs kept over steps"). Reading the same pairs from a
list took 4.7 ms.

So the fluid loop may read its pairs from a list, built by the same cell walk with the radius
enlarged by a *skin*: every pair closer than support + skin, for each particle in the order the
walk meets them. The list stays valid while no particle has moved more than half the skin from
where it was at the build: two particles then approach by at most one skin, so every pair
within the support is in it (Verlet 1967; the neighbour-list criterion of molecular dynamics).
The fluid loop still skips the listed pairs beyond the support, so it sums the pairs the walk
would, in the order of the build's cells (a particle that changed cell since is met where it
was then: the sums may differ from the walk's in the last bits).

:class:`PairList` decides when to rebuild: when the particles are not the same ones in the same
order as at the build (reordering, removals, additions: compared by id), or when one moved more
than half the skin. Memory: room for ``stride`` int32 pairs and a count per particle, linear in
the particle count (3D dam break, skin 0.1: room for 116, 81 listed on average; 12.5 MB).

The build walks up to three cells each way (cells are half a support wide, so the skin may be
at most half a support) and trims every row of cells to the sphere it must cover, as
:func:`~seawall.neighbors.reach_range` does for one support. Non-periodic grids only: periodic
ones keep the cell walk.
"""

import math

import numpy as np
from numba import prange

from .errors import ParameterError
from .jit import loop_helper, particle_loop
from .neighbors import cell_fractions, cell_gap, cell_index, point_of, tag_dim

#: the skin may be at most this fraction of the support (the build's walk reaches three cells)
MAX_SKIN = 0.5


def check_skin(skin):
    """``neighbour_skin`` as a float in [0, MAX_SKIN] (0: no pair list), or a ParameterError naming it."""
    try:
        value = float(skin)
    except (TypeError, ValueError):
        value = math.nan
    if not 0.0 <= value <= MAX_SKIN:
        raise ParameterError(f"neighbour_skin must be in [0, {MAX_SKIN:g}] (a fraction of the kernel support; "
                             f"0: no pair list), got {skin!r}")
    return value


@loop_helper
def _gap2(offset, frac, width):
    """The square of :func:`seawall.neighbors.cell_gap` (a lower bound of the distance to that cell)."""
    g = cell_gap(offset, frac, width)
    return g * g


@loop_helper
def _walk_pairs(i, x, dim, start, order, lo, inv_cell, ncell, radius2, out, at, room):
    """The pairs (i, j), j != i, closer than sqrt(``radius2``), in cell-walk order: counted, and the
    first ``room`` of them written to ``out[at:]``. Returns the count.

    Rows of cells (along x) at y and z offsets -3 ... 3 (0 in 2D), each trimmed to the cells the
    sphere touches as :func:`seawall.neighbors.reach_range` trims its rows, so the cells come in
    the same order. The row's ends are found by stepping outwards while the next cell is within
    reach: in a stand-alone build of the 3D dam break's list (skin 0.1, one thread) 25.1 ms per
    pass, against 26.9 ms with reach_range's counted comparisons and 33.2 ms with the candidates
    also written without a branch (every one to the next free slot).
    """
    p0, p1, p2 = point_of(x, i, dim)
    cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
    fx, fy, fz = cell_fractions(p0, p1, p2, cx, cy, cz, lo, inv_cell)
    wx = 1.0 / inv_cell[0]
    wy = 1.0 / inv_cell[1]
    wz = 1.0 / inv_cell[2]
    reach_z = 3 if ncell[2] > 1 else 0
    count = 0
    for oz in range(-reach_z, reach_z + 1):
        nz = cz + oz
        if nz < 0 or nz >= ncell[2]:
            continue
        gz = _gap2(oz, fz, wz)
        for oy in range(-3, 4):
            ny = cy + oy
            if ny < 0 or ny >= ncell[1]:
                continue
            left = radius2 - _gap2(oy, fy, wy) - gz
            if left <= 0.0:
                continue
            xl = cx
            while xl > 0 and xl > cx - 3 and _gap2(xl - 1 - cx, fx, wx) < left:
                xl -= 1
            xr = cx
            while xr < ncell[0] - 1 and xr < cx + 3 and _gap2(xr + 1 - cx, fx, wx) < left:
                xr += 1
            base = ncell[0] * (ny + ncell[1] * nz)
            for k in range(start[base + xl], start[base + xr + 1]):
                j = order[k]
                q0, q1, q2 = point_of(x, j, dim)
                d0 = p0 - q0
                d1 = p1 - q1
                d2 = p2 - q2
                if d0 * d0 + d1 * d1 + d2 * d2 < radius2 and j != i:
                    if count < room:
                        out[at + count] = j
                    count += 1
    return count


@particle_loop()
def fill_pairs(layout, x, start, order, lo, inv_cell, ncell, radius2, stride, counts, index):
    """counts[i] = the number of particles within sqrt(``radius2``) of particle i (itself excluded);
    the first ``stride`` of them go to index[i * stride:], in cell-walk order."""
    for i in prange(x.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        counts[i] = _walk_pairs(i, x, dim, start, order, lo, inv_cell, ncell, radius2, index, i * stride, stride)


@particle_loop()
def largest_displacement(x, x_ref, out):
    """out[0] = max_i |x_i - x_ref_i|^2."""
    n = x.shape[0]
    dim = x.shape[1]
    largest = 0.0
    for i in prange(n):
        d2 = 0.0
        for a in range(dim):
            d = x[i, a] - x_ref[i, a]
            d2 += d * d
        largest = max(largest, d2)
    out[0] = largest


class PairList:
    """The fluid's pairs within support + skin, rebuilt when a particle has moved half the skin.

    Particle i's pairs are ``index[i * stride:i * stride + counts[i]]``: one walk fills them, in
    room for ``stride`` per particle (a quarter more than the most any particle had at the last
    build; a particle with more than that makes the build walk again with more room).

    Parameters
    ----------
    skin : float
        The skin as a fraction of the kernel support, in (0, 0.5] (:func:`check_skin`).
    support : float
        The kernel support [m].
    """

    def __init__(self, skin, support):
        skin = check_skin(skin)
        if skin == 0.0:
            raise ParameterError("neighbour_skin = 0 means no pair list: make none")
        self.skin = skin
        self.radius2 = (support * (1.0 + skin)) ** 2
        # moved more than half the skin: a pair may have come within the support unlisted
        self.limit2 = (0.5 * skin * support) ** 2
        self.stride = 0
        self.counts = np.zeros(0, dtype=np.int64)
        self.index = np.zeros(0, dtype=np.int32)
        self._x_ref = None
        self._ids_ref = None
        self._moved = np.zeros(1)
        #: evaluations served and builds made (``summary.json``: how often the list was rebuilt)
        self.evaluations = 0
        self.builds = 0

    def describe(self):
        """The skin and how often the list was rebuilt (``summary.json``, key ``pair_list``)."""
        return {"skin": self.skin, "builds": self.builds, "evaluations": self.evaluations,
                "pairs_per_particle": float(self.counts.mean()) if self.counts.shape[0] else 0.0}

    def current(self, grid, cells, x, ids):
        """(stride, counts, index) valid for positions ``x`` of the particles ``ids``; ``cells`` is
        their cell list in ``grid``, walked when the list is rebuilt."""
        self.evaluations += 1
        if self.stale(x, ids):
            self._build(grid, cells, x, ids)
            self.builds += 1
        return self.stride, self.counts, self.index

    def stale(self, x, ids):
        """Whether the particles are not those of the build, in its order, or one moved half the skin."""
        if self._x_ref is None or self._x_ref.shape != x.shape or not np.array_equal(ids, self._ids_ref):
            return True
        self._moved[0] = np.inf   # stays so where the loop is not run (a compile helper's rehearsal)
        largest_displacement(x, self._x_ref, self._moved)
        return not self._moved[0] <= self.limit2

    def state(self):
        """What a checkpoint keeps: the positions and ids of the last build (empty before one)."""
        if self._x_ref is None:
            return {}
        return {"x_ref": self._x_ref, "ids_ref": self._ids_ref}

    def set_state(self, grid, state):
        """Rebuild the list a checkpoint's :meth:`state` had: the same positions give the same pairs in
        the same order, so a restarted run continues exactly as the uninterrupted one."""
        if "x_ref" in state:
            x = np.ascontiguousarray(state["x_ref"])
            self._build(grid, grid.build(x), x, np.asarray(state["ids_ref"]))

    def _build(self, grid, cells, x, ids):
        n = x.shape[0]
        if self.counts.shape[0] != n:
            self.counts = np.zeros(n, dtype=np.int64)
        args = (grid.layout, x, cells.start, cells.order, grid.lo, grid.inv_cell, grid.ncell, self.radius2)
        while True:
            if self.index.shape[0] != n * self.stride:
                self.index = np.zeros(n * self.stride, dtype=np.int32)
            fill_pairs(*args, self.stride, self.counts, self.index)
            most = int(self.counts.max()) if n else 0
            if most <= self.stride:
                break
            self.stride = most + most // 4 + 1
        self._x_ref = x.copy()
        self._ids_ref = ids.copy()
