"""Neighbour search against brute force: random sets, cell borders, periodic wrap."""

import numpy as np
import pytest
from numba import njit

from seawall.errors import ParameterError
from seawall.neighbors import (CellGrid, cell_index, cells_within_reach, neighbour_pairs, neighbour_range,
                               reach_plan, reach_range)


def brute(xa, xb, radius, period=None, same=False):
    d = xa[:, None, :] - xb[None, :, :]
    if period is not None:
        for k, L in enumerate(period):
            if L > 0:
                d[..., k] -= L * np.rint(d[..., k] / L)
    r2 = np.sum(d * d, axis=-1)
    mask = r2 < radius * radius
    if same:
        np.fill_diagonal(mask, False)
    i, j = np.nonzero(mask)
    return set(zip(i.tolist(), j.tolist()))


def found(grid, xa, xb=None, radius=None):
    i, j = neighbour_pairs(grid, xa, xb, radius)
    return set(zip(i.tolist(), j.tolist()))


@pytest.mark.parametrize("dim", [2, 3])
def test_random_sets_match_brute_force(dim):
    rng = np.random.default_rng(dim)
    radius = 0.13
    xa = rng.uniform(0, 1, size=(600, dim))
    xb = rng.uniform(0, 1, size=(500, dim))
    grid = CellGrid(np.zeros(dim), np.ones(dim), radius)
    assert found(grid, xa) == brute(xa, xa, radius, same=True)
    assert found(grid, xa, xb) == brute(xa, xb, radius)


@pytest.mark.parametrize("dim", [2, 3])
def test_particles_on_cell_borders(dim):
    radius = 0.1
    grid = CellGrid(np.zeros(dim), np.ones(dim), radius)
    # lattice with spacing equal to the cell width (radius/2): every particle sits on a border
    ticks = np.arange(0, 1.0 + 1e-12, grid.cell_size[0])
    ticks = ticks[ticks < 1.0]
    x = np.stack(np.meshgrid(*([ticks] * dim), indexing="ij"), axis=-1).reshape(-1, dim)
    # and pairs exactly at the radius must be excluded, just below it included
    assert found(grid, x) == brute(x, x, radius, same=True)
    # binary-exact coordinates: the first point is at exactly the radius 0.125
    grid = CellGrid(np.zeros(dim), np.ones(dim), 0.125)
    probe = np.array([[0.5] * dim])
    other = np.array([[0.625] + [0.5] * (dim - 1), [0.625 - 2 ** -40] + [0.5] * (dim - 1)])
    assert found(grid, probe, other) == {(0, 1)}


@pytest.mark.parametrize("dim", [2, 3])
def test_periodic_wrap(dim):
    rng = np.random.default_rng(10 + dim)
    radius = 0.15
    lo = np.zeros(dim)
    hi = np.full(dim, 0.8)
    periodic = [True] + [False] * (dim - 1)
    grid = CellGrid(lo, hi, radius, periodic=periodic)
    x = rng.uniform(0, 0.8, size=(400, dim))
    x[:20, 0] = rng.uniform(0, 0.02, 20)       # crowd both ends of the periodic axis
    x[20:40, 0] = rng.uniform(0.78, 0.8 - 1e-9, 20)
    period = [0.8] + [0.0] * (dim - 1)
    assert found(grid, x) == brute(x, x, radius, period=period, same=True)
    # pairs across the periodic boundary exist
    assert any(abs(x[i, 0] - x[j, 0]) > 0.5 for i, j in found(grid, x))


def test_fully_periodic_small_box():
    radius = 0.1
    grid = CellGrid([0, 0], [0.25, 0.3], radius, periodic=[True, True])
    rng = np.random.default_rng(3)
    x = rng.uniform(0, 1, size=(200, 2)) * [0.25, 0.3]
    assert found(grid, x) == brute(x, x, radius, period=[0.25, 0.3], same=True)


def test_periodic_axis_too_short():
    with pytest.raises(ParameterError, match="periodic axis 0"):
        CellGrid([0, 0], [0.2, 1], 0.1, periodic=[True, False])


def test_memory_is_linear_not_all_pairs():
    # 40k particles: an all-pairs array would need 12.8 GB; the search finds pairs only
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 1, size=(40_000, 2))
    grid = CellGrid([0, 0], [1, 1], 0.01)
    i, j = neighbour_pairs(grid, x)
    expected = 40_000 * 40_000 * np.pi * 0.01 ** 2  # ~ N^2 pi r^2 / area
    assert 0.8 * expected < i.size < 1.2 * expected


@njit
def _trimmed_candidates(points, x, start, order, lo, inv_cell, ncell, period, reach2, dim):
    """Per point: particles the trimmed rows hold within reach, all they hold, all the 5-cell rows hold,
    and how many trimmed rows reach outside their 5-cell row."""
    out = np.zeros((points.shape[0], 4), dtype=np.int64)
    for i in range(points.shape[0]):
        p0 = points[i, 0]
        p1 = points[i, 1]
        p2 = points[i, 2] if dim == 3 else 0.0
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        plan = reach_plan(p0, p1, p2, cx, cy, cz, lo, inv_cell)
        for row in range(25 if dim == 3 else 5):
            ka, kb = reach_range(row, cx, cy, cz, plan, ncell, start, reach2)
            out[i, 1] += kb - ka
            for k in range(ka, kb):
                j = order[k]
                r2 = (x[j, 0] - p0) ** 2 + (x[j, 1] - p1) ** 2 + ((x[j, 2] - p2) ** 2 if dim == 3 else 0.0)
                if r2 < reach2:
                    out[i, 0] += 1
            la, lb = neighbour_range(row, 0, cx, cy, cz, ncell, period, start)
            out[i, 2] += lb - la
            if ka < kb and (ka < la or kb > lb):
                out[i, 3] += 1
    return out


@pytest.mark.parametrize("dim", [2, 3])
def test_trimmed_rows_keep_every_neighbour_and_drop_candidates(dim):
    """reach_range (the fluid loop's cell walk) holds every particle within the radius -- also for
    points and particles outside the grid (clamped into its edge cells) and on cell borders --
    within the 5-cell rows of neighbour_range, and fewer candidates than they do."""
    rng = np.random.default_rng(10 + dim)
    radius = 0.13
    grid = CellGrid(np.zeros(dim), np.ones(dim), radius)
    x = np.concatenate([rng.uniform(-0.1, 1.1, size=(1500, dim)),
                        np.round(rng.uniform(0, 1, size=(300, dim)) / grid.cell_size[0]) * grid.cell_size[0]])
    cells = grid.build(x)
    points = np.concatenate([rng.uniform(-0.15, 1.15, size=(400, dim)), x[::7]])
    xp = np.zeros((x.shape[0], 3))
    xp[:, :dim] = x
    pp = np.zeros((points.shape[0], 3))
    pp[:, :dim] = points
    counts = _trimmed_candidates(pp, xp, cells.start, cells.order, grid.lo, grid.inv_cell, grid.ncell, grid.period,
                                 radius * radius, dim)
    d2 = np.sum((points[:, None, :] - x[None, :, :]) ** 2, axis=-1)
    assert np.array_equal(counts[:, 0], np.sum(d2 < radius * radius, axis=1))
    assert not np.any(counts[:, 3])
    assert np.sum(counts[:, 1]) < (0.8 if dim == 3 else 0.95) * np.sum(counts[:, 2])


def _reach_by_definition(counts, ncell, period):
    """Cell c is in reach when some cell within two cells along every axis (wrapped where periodic) is occupied."""
    nx, ny, nz = ncell
    occupied = counts.reshape(nz, ny, nx) > 0
    mask = np.zeros((nz, ny, nx), dtype=bool)
    rz = 2 if nz > 1 else 0
    for cz, cy, cx in np.argwhere(occupied):
        for oz in range(-rz, rz + 1):
            for oy in range(-2, 3):
                for ox in range(-2, 3):
                    z, y, x = cz + oz, cy + oy, cx + ox
                    if not (0 <= z < nz) and period[2] == 0.0 or not (0 <= y < ny) and period[1] == 0.0 \
                            or not (0 <= x < nx) and period[0] == 0.0:
                        continue
                    mask[z % nz, y % ny, x % nx] = True
    return mask.ravel()


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("periodic", [(0, 0, 0), (1, 0, 0), (0, 1, 1), (1, 1, 1)])
def test_reach_mask_is_the_five_cell_dilation(dim, periodic):
    rng = np.random.default_rng(7 + dim)
    ncell = np.array([9, 7, 6 if dim == 3 else 1], dtype=np.int64)
    period = np.array([float(p) for p in periodic])
    if dim == 2:
        period[2] = 0.0
    for fill in (0.0, 0.02, 0.1, 0.5):
        counts = (rng.random(int(ncell.prod())) < fill).astype(np.int64) * rng.integers(1, 4, int(ncell.prod()))
        start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        got = cells_within_reach(start, ncell, period).astype(bool)
        assert np.array_equal(got, _reach_by_definition(counts, tuple(ncell), period)), (fill, periodic)
