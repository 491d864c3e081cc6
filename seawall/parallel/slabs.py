"""Slabs: the domain cut across one axis at particle-count quantiles.

Rank r owns the fluid particles with ``cuts[r] <= x[axis] < cuts[r + 1]``
(``cuts[0] = -inf``, ``cuts[-1] = +inf``). The cuts come from a histogram of
the coordinate in bins of one neighbour cell (half a kernel support), summed
over the ranks, so finding them costs one reduction of a few thousand
integers whatever the particle count, and every rank computes the same cuts.
"""

from __future__ import annotations

import numpy as np


def longest_axis(lo, hi, periodic):
    """The longest non-periodic axis of the box (lo, hi); None if every axis is periodic."""
    lengths = [(hi[k] - lo[k], k) for k in range(len(lo)) if not periodic[k]]
    return max(lengths)[1] if lengths else None


def histogram(coord, lo, width, nbins):
    """Particle counts per bin of ``width`` from ``lo`` (values outside are put in the end bins)."""
    k = np.floor((coord - lo) / width).astype(np.int64)
    np.clip(k, 0, nbins - 1, out=k)
    return np.bincount(k, minlength=nbins).astype(np.int64)


def quantile_cuts(counts, lo, width, size):
    """Cut positions (size + 1 values, open ends) splitting the histogram ``counts`` into ``size``
    parts of nearly equal count, each cut on a bin edge."""
    total = int(counts.sum())
    cumulative = np.cumsum(counts)
    cuts = np.empty(size + 1)
    cuts[0] = -np.inf
    cuts[-1] = np.inf
    for r in range(1, size):
        # first bin edge at or past r / size of the particles
        b = int(np.searchsorted(cumulative, r * total / size, side="left"))
        cuts[r] = lo + (b + 1) * width
    return cuts


def owners(coord, cuts):
    """Rank owning each coordinate."""
    return np.searchsorted(cuts[1:-1], coord, side="right").astype(np.int64)


def halo_rows(coord, cuts, rank, width):
    """Per destination rank: the rows whose coordinate lies within ``width`` of that rank's slab
    (none for ``rank`` itself)."""
    rows = []
    for r in range(cuts.size - 1):
        if r == rank:
            rows.append(np.zeros(0, dtype=np.int64))
            continue
        near = (coord >= cuts[r] - width) & (coord < cuts[r + 1] + width)
        rows.append(np.flatnonzero(near))
    return rows
