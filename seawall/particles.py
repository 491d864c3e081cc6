"""Structure-of-arrays particle storage. No physics here.

Every per-particle quantity is a contiguous numpy array whose first axis is
the particle. Reordering (for memory locality) and removal (particles that
left the domain) act on all arrays at once, so they never get out of step.
"""

import numpy as np

from .errors import ParameterError


def initial_velocity(velocity, n, dim):
    """(n, dim) velocities from ``velocity`` (None = at rest, one vector, or one row per particle), checked finite."""
    v = np.zeros((n, dim))
    if velocity is not None:
        try:
            v[:] = np.asarray(velocity, dtype=np.float64)
        except (TypeError, ValueError):
            raise ParameterError(f"velocity must be a vector of {dim} numbers or an (n, {dim}) array, "
                                 f"got {velocity!r}"[:200]) from None
        if not np.all(np.isfinite(v)):
            raise ParameterError("velocity must be finite (no NaN or infinity)")
    return v


class ParticleArrays:
    """Named per-particle arrays of equal length.

    >>> pa = ParticleArrays(2)
    >>> pa.add("x", np.zeros((3, 2)))
    >>> pa.n
    3
    """

    def __init__(self, dim):
        self.dim = int(dim)
        self._arrays = {}

    @property
    def n(self):
        for a in self._arrays.values():
            return a.shape[0]
        return 0

    def add(self, name, array):
        array = np.ascontiguousarray(array)
        if self._arrays and array.shape[0] != self.n:
            raise ValueError(f"array {name!r} has {array.shape[0]} rows, expected {self.n}")
        self._arrays[name] = array
        return array

    def __getitem__(self, name):
        return self._arrays[name]

    def __setitem__(self, name, array):
        self.add(name, array)

    def __contains__(self, name):
        return name in self._arrays

    def names(self):
        return list(self._arrays)

    def remove(self, name):
        """Drop the array ``name`` (if present)."""
        self._arrays.pop(name, None)

    def items(self):
        return self._arrays.items()

    def permute(self, order):
        """Reorder every array by the index array ``order`` (new[i] = old[order[i]])."""
        for name, a in self._arrays.items():
            self._arrays[name] = np.ascontiguousarray(a[order])

    def keep(self, mask):
        """Keep only the particles where ``mask`` is true; return how many were removed."""
        removed = int(mask.size - np.count_nonzero(mask))
        if removed:
            for name, a in self._arrays.items():
                self._arrays[name] = np.ascontiguousarray(a[mask])
        return removed

    def truncate(self, n):
        """Keep the first ``n`` particles (views of the present arrays, no copy)."""
        for name, a in self._arrays.items():
            self._arrays[name] = a[:int(n)]

    def append(self, count, **values):
        """Append ``count`` zero-filled rows to every array at once, then set those given as keywords.

        Returns the indices of the new rows.
        """
        n_old = self.n
        unknown = set(values) - set(self._arrays)
        if unknown:
            raise ValueError(f"no array named {sorted(unknown)[0]!r}")
        for name, a in self._arrays.items():
            new = np.zeros((int(count),) + a.shape[1:], dtype=a.dtype)
            if name in values:
                new[...] = values[name]
            self._arrays[name] = np.ascontiguousarray(np.concatenate([a, new]))
        return np.arange(n_old, n_old + int(count))

    def append_rows(self, source, **values):
        """Append copies of the rows ``source`` (index array) to every array at once.

        Keyword arrays overwrite the copied values of the new rows (one row per
        source index). Returns the indices of the new rows.
        """
        source = np.asarray(source, dtype=np.int64)
        n_old = self.n
        unknown = set(values) - set(self._arrays)
        if unknown:
            raise ValueError(f"no array named {sorted(unknown)[0]!r}")
        for name, a in self._arrays.items():
            new = a[source].copy()
            if name in values:
                new[...] = values[name]
            self._arrays[name] = np.ascontiguousarray(np.concatenate([a, new]))
        return np.arange(n_old, n_old + source.size)

    def as_dict(self):
        return dict(self._arrays)
