"""Typed bundles the compiled loops read: neighbour search, fluid, wall, rates.

Named tuples of arrays and scalars instead of 20-29 positional arguments.
Numba types a named tuple by its fields' types, so a loop taking one is
compiled once per combination of field types, exactly as with separate
arguments (the ``layout`` tag keeps dim and periodicity compile-time
constants, see :func:`seawall.neighbors.layout_tag`); field access is free.

Build them with :func:`cell_view`, :func:`fluid_view`, :func:`fluid_rates_view`
and :func:`wall_view` right before a compiled call: they hold references to
the particle arrays, which are replaced when particles are added, removed
or reordered.
"""

from typing import NamedTuple

import numpy as np


class CellView(NamedTuple):
    """Search over one system's particles sorted into the grid (:class:`seawall.neighbors.CellList`)."""

    layout: np.ndarray   # zero-size array, its number of axes encodes (dim, periodic)
    lo: np.ndarray
    inv_cell: np.ndarray
    ncell: np.ndarray
    period: np.ndarray
    start: np.ndarray    # particles order[start[c]:start[c+1]] are in cell c
    order: np.ndarray
    reach: np.ndarray    # 1 for cells within reach of some particle (empty: not computed)


class PairView(NamedTuple):
    """The fluid's listed pairs (:class:`seawall.pair_list.PairList`): the neighbours of particle i are
    ``index[i * stride:i * stride + counts[i]]``. ``listed`` is a zero-size array whose number of axes
    says whether there is a list (2) or the loop walks the cells (1): a compile-time switch."""

    listed: np.ndarray
    stride: int
    counts: np.ndarray
    index: np.ndarray


class FluidView(NamedTuple):
    """The fluid's state at one evaluation."""

    x: np.ndarray
    v: np.ndarray
    rho: np.ndarray
    p: np.ndarray
    c: np.ndarray
    m: np.ndarray
    p_over_rho2: np.ndarray
    volume: np.ndarray


class Rates(NamedTuple):
    """What an evaluation writes for the fluid: walls add to these (and only these)."""

    dv: np.ndarray       # acceleration
    drho: np.ndarray     # density rate
    xsph: np.ndarray     # XSPH velocity correction ([Li2022] eq. 10)
    mu_max: np.ndarray   # max_j |mu_ij| for the time-step rule ([Li2022] eq. 11)


class WallView(NamedTuple):
    """A wall's particles as the fluid sees them.

    ``v`` is the velocity in the continuity and pressure terms (the wall's
    own, or a mirrored one), ``v_visc`` the velocity in the viscous term,
    ``normal`` the unit normals into the fluid (zero rows if the wall has none).
    """

    x: np.ndarray
    v: np.ndarray
    v_visc: np.ndarray
    rho: np.ndarray
    p: np.ndarray
    m: np.ndarray
    normal: np.ndarray


_NO_REACH = np.zeros(0, dtype=np.uint8)


def cell_view(grid, cells, reach=False):
    """The :class:`CellView` of ``cells`` in ``grid``; ``reach`` adds the reach mask (wall cells)."""
    mask = cells.reach_mask(grid) if reach else _NO_REACH
    return CellView(grid.layout, grid.lo, grid.inv_cell, grid.ncell, grid.period, cells.start, cells.order, mask)


_NO_PAIRS = PairView(np.empty((0,)), 0, np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int32))


def pair_view(stride=None, counts=None, index=None):
    """The :class:`PairView` of a pair list's arrays, or (no arguments) of none: the loop walks the cells."""
    if stride is None:
        return _NO_PAIRS
    return PairView(np.empty((0, 0)), int(stride), counts, index)


def fluid_view(particles):
    """The :class:`FluidView` of a fluid's particle arrays (after the equation of state)."""
    return FluidView(particles["x"], particles["v"], particles["rho"], particles["p"], particles["c"],
                     particles["m"], particles["p_over_rho2"], particles["volume"])


def fluid_rates_view(particles):
    """The :class:`Rates` arrays of a fluid's particles."""
    return Rates(particles["dv"], particles["drho"], particles["xsph"], particles["mu_max"])


def wall_view(particles, *, v="v", v_visc=None, rho="rho", p="p"):
    """The :class:`WallView` of a wall's particle arrays, with the named velocity / state arrays.

    A wall without density, pressure or normals (repulsive rows) gets empty arrays for them.
    """
    x = particles["x"]

    def array(name, shape):
        return particles[name] if name in particles else np.zeros(shape)

    return WallView(x, particles[v], particles[v_visc or v], array(rho, 0), array(p, 0), particles["m"],
                    array("normal", (0, x.shape[1])))
