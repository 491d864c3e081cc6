"""Post-processing of a run directory from its VTU series: ``seawall forces`` and ``seawall sample``.

Both read only the files ``seawall run`` wrote, so they work after the run
(and on a copy of its directory) without the case or a checkpoint.

* :func:`wall_force_series` -- the fluid's force on each wall system at every
  output time, from the ``wall_force`` FieldData of the wall files (the sum
  over the fluid of minus what the wall adds to m_i dv_i at the last
  evaluation of the rates: the pairwise form of [Huang2019] eq. 29, as the
  ``WallForce`` probe). Output times only: for an impact peak sample the
  ``WallForce`` probe at a finer ``--probe-every``.
* :func:`sample_series` -- fluid fields at points (a line) in stored frames,
  by the Shepard-normalised SPH sum of :mod:`seawall.sampling` ([Huang2019]
  sec. 3.3, eq. 14-16), f(x) = sum_j f_j W_j V_j / sum_j W_j V_j with
  V_j = m_j / rho_j, over particles within the kernel support; NaN where no
  particle is within it. The kernel and h come from the file's metadata.
"""

import os

import numpy as np

from .errors import ParameterError
from .plots import _series

#: fields :func:`sample_series` can give
SAMPLE_QUANTITIES = ("pressure", "density", "u", "v", "w", "speed")


def _wall_names(run_dir):
    if not os.path.isdir(run_dir):
        raise ParameterError(f"run directory {run_dir} not found")
    return sorted(f[len("wall_"):-len(".pvd")] for f in os.listdir(run_dir)
                  if f.startswith("wall_") and f.endswith(".pvd"))


def wall_force_series(run_dir):
    """{wall name: (times (n,), forces (n, d))} from the wall files' ``wall_force`` FieldData."""
    from .io.vtk import read_vtu_metadata

    names = _wall_names(run_dir)
    if not names:
        raise ParameterError(f"{run_dir} holds no wall series (wall_<name>.pvd): was it run with --no-vtk?")
    out = {}
    for name in names:
        times, forces = [], []
        for t, path in _series(run_dir, f"wall_{name}"):
            force = read_vtu_metadata(path).get("wall_force")
            if force is None:
                raise ParameterError(f"{path} holds no wall_force: it was written before seawall recorded wall "
                                     f"forces in the VTU files (or by a DEM run); run the case again")
            times.append(t)
            forces.append(np.atleast_1d(force))
        out[name] = (np.asarray(times), np.asarray(forces, dtype=np.float64))
    return out


def write_forces_csv(path, series):
    """forces.csv: time, wall, fx, fy[, fz] -- one row per wall and output time."""
    from .io.vtk import _atomic_write

    dim = max((f.shape[1] for _, f in series.values() if f.size), default=2)
    with _atomic_write(path, "w") as fh:
        fh.write(",".join(["time", "wall", *("fx", "fy", "fz")[:dim]]) + "\n")
        rows = sorted((t, name, f) for name, (ts, fs) in series.items() for t, f in zip(ts, fs))
        for t, name, f in rows:
            fh.write(",".join([f"{t:.9g}", name, *(f"{v:.9g}" for v in f)]) + "\n")
    return path


def _shepard(points, x, values, volume, kernel, h):
    """Shepard-normalised SPH sum of ``values`` (N, k) at ``points`` (M, d), NaN where no particle is near."""
    support = kernel.support(h)
    dim = points.shape[1]
    out = np.full((points.shape[0], values.shape[1]), np.nan)
    if x.shape[0] == 0:
        return out
    # bin the particles in cells of the support size; each point reads its 3^d neighbouring cells
    lo = x.min(axis=0) - support
    cell = np.floor((x - lo) / support).astype(np.int64)
    order = np.lexsort(cell.T[::-1])
    keys = [tuple(c) for c in cell[order]]
    starts = {}
    for k, key in enumerate(keys):
        starts.setdefault(key, [k, k])[1] = k + 1
    offsets = np.array(np.meshgrid(*[[-1, 0, 1]] * dim, indexing="ij")).reshape(dim, -1).T
    for m, p in enumerate(points):
        base = np.floor((p - lo) / support).astype(np.int64)
        idx = [order[slice(*starts[tuple(base + off)])] for off in offsets if tuple(base + off) in starts]
        if not idx:
            continue
        j = np.concatenate(idx)
        r = np.linalg.norm(x[j] - p, axis=1)
        near = r < support
        if not near.any():
            continue
        w = kernel.value(r[near], h, dim) * volume[j[near]]
        if w.sum() > 0:
            out[m] = (w[:, None] * values[j[near]]).sum(axis=0) / w.sum()
    return out


def sample_series(run_dir, points, quantities=("pressure", "u", "v"), times=None):
    """Fluid ``quantities`` at ``points`` (M, d) in the stored frames (all, or those nearest to ``times``).

    Returns (frame times (F,), {quantity: (F, M) array}).
    """
    from .io.vtk import read_vtu, read_vtu_metadata
    from .kernels import KERNELS

    frames = _series(run_dir)
    if not frames:
        raise ParameterError(f"{run_dir}: the fluid series is empty")
    if times is not None:
        chosen = sorted({int(np.argmin([abs(ft - t) for ft, _ in frames])) for t in times})
        frames = [frames[k] for k in chosen]
    points = np.asarray(points, dtype=np.float64)
    unknown = [q for q in quantities if q not in SAMPLE_QUANTITIES]
    if unknown:
        raise ParameterError(f"unknown quantity {unknown[0]!r}; available: {', '.join(SAMPLE_QUANTITIES)}")
    by_class = {type(k()).__name__: k for k in KERNELS.values()}
    result = {q: [] for q in quantities}
    for t, path in frames:
        meta = read_vtu_metadata(path)
        if "h" not in meta:
            raise ParameterError(f"{path} does not record h: it was written before seawall stored metadata "
                                 f"in the VTU files; run the case again")
        kernel = by_class.get(meta.get("kernel", "CubicSpline"))
        if kernel is None:
            raise ParameterError(f"{path}: unknown kernel {meta.get('kernel')!r}")
        dim = int(meta.get("dimension", points.shape[1]))
        if points.shape[1] != dim:
            raise ParameterError(f"points have {points.shape[1]} coordinates, the run is {dim}D")
        x, data = read_vtu(path)
        x = x[:, :dim]
        if "w" in quantities and dim == 2:
            raise ParameterError("quantity 'w' needs a 3D run")
        cols = []
        for q in quantities:
            if q == "pressure":
                cols.append(data["pressure"])
            elif q == "density":
                cols.append(data["density"])
            elif q == "speed":
                cols.append(np.linalg.norm(data["velocity"], axis=1))
            else:
                cols.append(data["velocity"][:, "uvw".index(q)])
        values = np.stack(cols, axis=1).astype(np.float64)
        volume = data["mass"].astype(np.float64) / data["density"].astype(np.float64)
        sampled = _shepard(points, x.astype(np.float64), values, volume, kernel(), float(meta["h"]))
        for k, q in enumerate(quantities):
            result[q].append(sampled[:, k])
    return np.array([t for t, _ in frames]), {q: np.array(v) for q, v in result.items()}


def write_sample_csv(path, times, points, result):
    """sample.csv: time, s (distance along the points from the first), the coordinates, then the quantities."""
    from .io.vtk import _atomic_write

    dim = points.shape[1]
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    names = list(result)
    with _atomic_write(path, "w") as fh:
        fh.write(",".join(["time", "s", *"xyz"[:dim], *names]) + "\n")
        for f, t in enumerate(times):
            for m, p in enumerate(points):
                fh.write(",".join([f"{t:.9g}", f"{s[m]:.9g}", *(f"{c:.9g}" for c in p),
                                   *(f"{result[q][f, m]:.9g}" for q in names)]) + "\n")
    return path
