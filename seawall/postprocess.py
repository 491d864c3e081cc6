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
* :func:`sensor_series` -- the face-averaged wall pressure of a pressure sensor
  (the read-out of the run-time ``PressureSensor``, ``--sensor``) from stored frames.
* :func:`gauge_series` -- the free-surface elevation above given horizontal
  positions (wave gauges) from stored frames; the bed's elevation where dry (the
  read-out of the run-time ``FreeSurfaceGauge``, ``--gauge``).
  positions (wave gauges) from stored frames.
* :func:`discharge_series` -- the fluid volume that has passed a section, from
  stored frames and ``escaped.csv`` (``seawall discharge``): a check of the
  run-time :class:`~seawall.probes.Discharge` probe, exact only for a section
  spanning the whole fluid depth.
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


def impulse(times, forces):
    """The time integral of a force series, int F dt by the trapezoidal rule over the output times
    [N s, per metre of depth in 2D]; as coarse as the output interval (an impact peak between two
    frames is missed: integrate the ``WallForce`` probe at a fine ``--probe-every`` for that)."""
    t = np.asarray(times, dtype=np.float64)
    f = np.asarray(forces, dtype=np.float64)
    if t.size < 2:
        return np.zeros(f.shape[-1])
    return (0.5 * (f[1:] + f[:-1]) * np.diff(t)[:, None]).sum(axis=0)


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


def _fluid_frames(run_dir, times, dim=None):
    """The stored fluid frames (all, or those nearest to ``times``) as (t, path, x, data, meta, kernel, h)."""
    from .io.vtk import read_vtu, read_vtu_metadata
    from .kernels import KERNELS

    frames = _series(run_dir)
    if not frames:
        raise ParameterError(f"{run_dir}: the fluid series is empty")
    if times is not None:
        chosen = sorted({int(np.argmin([abs(ft - t) for ft, _ in frames])) for t in times})
        frames = [frames[k] for k in chosen]
    by_class = {type(k()).__name__: k for k in KERNELS.values()}
    for t, path in frames:
        meta = read_vtu_metadata(path)
        if "h" not in meta:
            raise ParameterError(f"{path} does not record h: it was written before seawall stored metadata "
                                 f"in the VTU files; run the case again")
        kernel = by_class.get(meta.get("kernel", "CubicSpline"))
        if kernel is None:
            raise ParameterError(f"{path}: unknown kernel {meta.get('kernel')!r}")
        run_dim = int(meta.get("dimension", dim or 2))
        if dim is not None and dim != run_dim:
            raise ParameterError(f"points have {dim} coordinates, the run is {run_dim}D")
        x, data = read_vtu(path)
        yield t, path, x[:, :run_dim].astype(np.float64), data, meta, kernel(), float(meta["h"])


def _volume(data):
    return data["mass"].astype(np.float64) / data["density"].astype(np.float64)


def sample_series(run_dir, points, quantities=("pressure", "u", "v"), times=None):
    """Fluid ``quantities`` at ``points`` (M, d) in the stored frames (all, or those nearest to ``times``).

    Returns (frame times (F,), {quantity: (F, M) array}).
    """
    points = np.asarray(points, dtype=np.float64)
    unknown = [q for q in quantities if q not in SAMPLE_QUANTITIES]
    if unknown:
        raise ParameterError(f"unknown quantity {unknown[0]!r}; available: {', '.join(SAMPLE_QUANTITIES)}")
    result = {q: [] for q in quantities}
    frame_times = []
    for t, _, x, data, meta, kernel, h in _fluid_frames(run_dir, times, points.shape[1]):
        if "w" in quantities and x.shape[1] == 2:
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
        sampled = _shepard(points, x, values, _volume(data), kernel, h)
        frame_times.append(t)
        for k, q in enumerate(quantities):
            result[q].append(sampled[:, k])
    return np.array(frame_times), {q: np.array(v) for q, v in result.items()}


def _gravity(meta, path, what):
    g = meta.get("gravity")
    if g is None:
        raise ParameterError(f"{path} does not record gravity, which {what} needs: it was written before "
                             f"seawall stored it in the VTU files; run the case again")
    return np.asarray(g, dtype=np.float64)


def _wall_surface_frames(run_dir, count, dim):
    """Per fluid frame index: (x, normal, surface) of all wall particles that record normals."""
    from .io.vtk import read_vtu

    series = [_series(run_dir, f"wall_{name}") for name in _wall_names(run_dir)]
    out = []
    for k in range(count):
        xs, ns, ss = [], [], []
        for frames in series:
            if not frames:
                continue
            x, data = read_vtu(frames[min(k, len(frames) - 1)][1])
            if "normal" not in data or "mirror_point" not in data:
                continue
            xs.append(x[:, :dim])
            ns.append(data["normal"][:, :dim])
            # the files store the mirror point 2 s - x of each particle's surface point s
            ss.append(0.5 * (data["mirror_point"][:, :dim] + x[:, :dim]))
        out.append(None if not xs else tuple(np.concatenate(a).astype(np.float64) for a in (xs, ns, ss)))
    return out


def sensor_series(run_dir, sensors, times=None):
    """Face-averaged wall pressure of ``sensors`` [(point, diameter or None), ...] in the stored frames [Pa].

    The same read-out as the run-time :class:`seawall.probes.PressureSensor`: the face is
    centred on the point's projection onto the surface of the nearest wall particle (whose
    normal and surface point the wall files store), its diameter defaults to one kernel support,
    and the pressure at each quadrature point of :func:`seawall.sampling.face_points` is the
    extrapolation of [Adami2012] eq. 27 used by the wall probes,
    p = sum_f (p_f + rho_f g . (x - x_f)) W_f / sum_f W_f over the fluid within the support
    (0 where none: a dry sensor). Returns (frame times (F,), (F, S) array).
    """
    from .sampling import face_points

    frames = list(_fluid_frames(run_dir, times))
    all_frames = _series(run_dir)
    index = {path: k for k, (_, path) in enumerate(all_frames)}
    dim = frames[0][2].shape[1] if frames else 2
    walls = _wall_surface_frames(run_dir, len(all_frames), dim)
    values = np.full((len(frames), len(sensors)), np.nan)
    for f, (t, path, x, data, meta, kernel, h) in enumerate(frames):
        dim = x.shape[1]
        g = _gravity(meta, path, "a pressure sensor")
        surface = walls[index[path]]
        if surface is None:
            raise ParameterError(f"{run_dir} holds no wall files with normals: a sensor needs them")
        wx, wn, ws = surface
        support = kernel.support(h)
        dx = float(meta.get("dx", h))
        for k, (point, diameter) in enumerate(sensors):
            point = np.asarray(point, dtype=np.float64)
            if point.size != dim:
                raise ParameterError(f"sensor {k + 1}: point has {point.size} coordinates, the run is {dim}D")
            r2 = np.sum((wx - point) ** 2, axis=1)
            b = int(np.argmin(r2))
            normal = wn[b] / np.linalg.norm(wn[b])
            off = float(np.dot(point - ws[b], normal))
            if abs(off) > 0.5 * dx or r2[b] > support ** 2:
                raise ParameterError(f"sensor {k + 1}: point {point.tolist()} is not on a wall surface at "
                                     f"t = {t:g} s (nearest surface {abs(off):.3g} m away along its normal); "
                                     f"put it on a wall")
            pts, weights = face_points(point - off * normal, normal, diameter or support, 0.5 * dx)
            values[f, k] = np.dot(weights, _extrapolated_pressure(pts, x, data, kernel, h, g)) / weights.sum()
    return np.array([fr[0] for fr in frames]), values


def _extrapolated_pressure(points, x, data, kernel, h, g):
    """p at ``points`` by [Adami2012] eq. 27 from the fluid (0 where no fluid is within the support)."""
    p = data["pressure"].astype(np.float64)
    rho = data["density"].astype(np.float64)
    out = np.zeros(points.shape[0])
    for m, d, w, near in _kernel_weights(points, x, kernel, h):
        if w.sum() > 0:
            out[m] = np.dot(w, p[near] + rho[near] * (d[near] @ g)) / w.sum()
    return out


def _kernel_weights(points, x, kernel, h):
    """Per point m with fluid within the support: (m, q_m - x, W of the near particles, near mask)."""
    support = kernel.support(h)
    dim = x.shape[1]
    for m, q in enumerate(points):
        d = q - x
        r = np.sqrt(np.einsum("ij,ij->i", d, d))
        near = r < support
        if near.any():
            yield m, d, kernel.value(r[near], h, dim), near


def gauge_series(run_dir, positions, times=None, resolution=None):
    """Free-surface elevation [m] above the given horizontal positions in the stored frames.

    The vertical is the axis of gravity (stored in the files). Along the vertical line through
    each position the Shepard sum of the fluid, sum_f V_f W_f ([Huang2019] eq. 16's
    denominator: 1 inside the fluid, 0 outside), is evaluated every ``resolution`` dx (default
    :data:`seawall.probes.GAUGE_RESOLUTION`, 1/4), and the elevation is the highest height
    where it crosses 0.5, interpolated linearly (the half-filled kernel of a flat surface sits
    on the surface). The run-time :class:`seawall.probes.FreeSurfaceGauge` (``seawall run
    --gauge``) is this definition, evaluated during the run. Where the line meets no fluid
    (a dry bed) the value is the bed's elevation from the wall files
    (:func:`seawall.probes.bed_level`: water depth 0), NaN where no wall lies under the line.
    ``positions``: the horizontal coordinates (x in 2D; the two horizontal axes in 3D,
    in axis order). Returns (frame times (F,), (F, G) array). On a lattice block the
    half-filled kernel lies 0.001 dx above the surface; within one kernel support of a side wall
    or of the fluid's edge the kernel is cut sideways too and the gauge reads low (on a 0.3 m
    still tank at dx = 0.05 m: 0.2965 m at one dx from the wall, 0.3000 m mid-tank).
    """
    from .probes import GAUGE_RESOLUTION, bed_level, gauge_heights, gauge_vertical, surface_crossing

    resolution = GAUGE_RESOLUTION if resolution is None else resolution
    frames = list(_fluid_frames(run_dir, times))
    values = np.full((len(frames), len(positions)), np.nan)
    walls = None          # read only when a gauge is dry
    for f, (t, path, x, data, meta, kernel, h) in enumerate(frames):
        dim = x.shape[1]
        g = _gravity(meta, path, "a free-surface gauge")
        up, horizontal = gauge_vertical(g, dim)
        dx = float(meta.get("dx", h))
        heights = gauge_heights(x[:, up], g[up], kernel.support(h), dx, resolution)
        volume = _volume(data)
        for k, pos in enumerate(positions):
            pos = np.atleast_1d(np.asarray(pos, dtype=np.float64))
            if pos.size != len(horizontal):
                raise ParameterError(f"gauge {k + 1}: needs {len(horizontal)} horizontal coordinate(s), "
                                     f"got {pos.tolist()}")
            pts = np.zeros((heights.size, dim))
            pts[:, horizontal] = pos
            pts[:, up] = heights
            full = _filled(pts, x, volume, kernel, h)
            wet = np.nonzero(full >= 0.5)[0]
            if wet.size:
                values[f, k] = surface_crossing(heights, full, wet[-1])
                continue
            if walls is None:
                all_frames = _series(run_dir)
                walls = (_wall_surface_frames(run_dir, len(all_frames), dim),
                         {p: n for n, (_, p) in enumerate(all_frames)})
            surface = walls[0][walls[1][path]]
            if surface is not None:
                values[f, k] = bed_level(*surface, pos, up, horizontal, g[up], dx)
    return np.array([fr[0] for fr in frames]), values


def _filled(points, x, volume, kernel, h):
    """The Shepard sum sum_f V_f W_f at ``points`` (0 where no fluid is near)."""
    out = np.zeros(points.shape[0])
    for m, _, w, near in _kernel_weights(points, x, kernel, h):
        out[m] = np.dot(w, volume[near])
    return out


def _write_time_columns(path, times, columns, digits):
    """A CSV of ``time`` and the named columns, one row per time, ``digits`` significant digits."""
    from .io.vtk import _atomic_write

    names = list(columns)
    with _atomic_write(path, "w") as fh:
        fh.write(",".join(["time", *names]) + "\n")
        for f, t in enumerate(times):
            fh.write(",".join([f"{t:.{digits}g}", *(f"{columns[n][f]:.{digits}g}" for n in names)]) + "\n")
    return path


def write_sensor_csv(path, times, columns):
    """sensors.csv: time, then one column per sensor (``sensor:<k>``, Pa) and gauge (``gauge:<k>``, m)."""
    return _write_time_columns(path, times, columns, 9)


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


def _read_escaped(run_dir, dim):
    """(times (n,), ids (n,), positions (n, dim)) of the removed particles in RUN_DIR/escaped.csv."""
    import csv

    path = os.path.join(run_dir, "escaped.csv")
    if not os.path.exists(path):
        raise ParameterError(f"{path} not found: the removed particles are needed (was the run stopped before "
                             f"writing it?)")
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    coords = ["x", "y", "z"][:dim]
    header = rows[0] if rows else []
    if not all(c in header for c in ["time", "id", *coords]):
        raise ParameterError(f"{path}: expected the columns time, id, {', '.join(coords)}; got {header}")
    cols = [header.index(c) for c in coords]
    body = rows[1:]
    times = np.array([float(r[header.index("time")]) for r in body])
    ids = np.array([int(r[header.index("id")]) for r in body], dtype=np.int64)
    x = np.array([[float(r[c]) for c in cols] for r in body]).reshape(len(body), dim)
    return times, ids, x


def _positive_side(x, start, end):
    """True where a point is on the positive side of the line through ``start``, ``end`` (the probe's test)."""
    (x0, y0), (x1, y1) = start, end
    return (x[:, 0] - x0) * (y1 - y0) - (x[:, 1] - y0) * (x1 - x0) > 0.0


def discharge_series(run_dir, start, end):
    """Fluid volume that has passed a section since the first stored frame, per frame [m^2 per metre in 2D].

    The check of the run-time :class:`seawall.probes.Discharge` probe from the files of a
    run: V(t) = (volume on the section's positive side now) + (volume removed on that side
    since the first frame) - (volume on that side in the first frame), with volume m / rho0
    (rho0 from the frames' metadata) and the positive side as the probe takes it (end - start
    rotated clockwise by 90 degrees). The side is that of the section's whole line, so V(t)
    equals the probe's count only for a section that spans the whole fluid depth (no particle
    passes beside it); the probe, which counts every step within the segment, is the primary
    measure. The removed particles are read from ``escaped.csv`` (positions at removal, with 9
    significant digits; masses from the last frame holding them, or the common mass of the
    fluid if none did). Frames written in single precision (``--vtk-float32``) agree to that
    precision only. Returns (frame times (F,), {"volume", "fluid_beyond", "removed_beyond": (F,)}).
    """
    start = np.asarray(start, dtype=np.float64)
    end = np.asarray(end, dtype=np.float64)
    if start.shape != (2,) or end.shape != (2,) or np.array_equal(start, end):
        raise ParameterError(f"--section must be two different 2D points, got {start.tolist()} and {end.tolist()}")
    frames = list(_fluid_frames(run_dir, None))
    if frames[0][2].shape[1] != 2:
        raise ParameterError(f"{run_dir}: the discharge check takes 2D runs, this one is {frames[0][2].shape[1]}D")
    esc_t, esc_id, esc_x = _read_escaped(run_dir, 2)
    esc_beyond = _positive_side(esc_x, start, end)
    known = np.full(0, np.nan)        # mass by particle id, from the frames read so far
    times, fluid, removed = [], [], []
    t0 = frames[0][0]
    counted = np.zeros(esc_t.size, dtype=bool)
    removed_mass = 0.0
    rho0 = None
    for t, path, x, data, meta, _, _ in frames:
        if meta.get("rho0") is None:
            raise ParameterError(f"{path} does not record rho0, which the discharge check needs: it was written "
                                 f"before seawall stored it in the VTU files; run the case again")
        rho0 = float(meta["rho0"])
        m = data["mass"].astype(np.float64)
        ids = data["id"].astype(np.int64)
        # removals after the first frame up to this one (times in escaped.csv have 9 digits)
        due = (~counted & (esc_t > t0 + 1e-8 * abs(t0)) & (esc_t <= t + 1e-8 * abs(t)))
        for k in np.flatnonzero(due & esc_beyond):
            pid = esc_id[k]
            mass = known[pid] if pid < known.size else np.nan
            if mass != mass:
                if not (m.size and m.min() == m.max()):
                    raise ParameterError(f"particle id {pid}, removed at t = {esc_t[k]:g} s, is in no frame before; "
                                         f"its mass is unknown")
                mass = m[0]
            removed_mass += mass
        counted |= due
        if ids.size:
            if ids.max() >= known.size:
                known = np.concatenate([known, np.full(ids.max() + 1 - known.size, np.nan)])
            known[ids] = m
        times.append(t)
        fluid.append(m[_positive_side(x, start, end)].sum() / rho0)
        removed.append(removed_mass / rho0)
    fluid = np.array(fluid)
    removed = np.array(removed)
    return np.array(times), {"volume": fluid + removed - fluid[0], "fluid_beyond": fluid, "removed_beyond": removed}


def write_discharge_csv(path, times, columns):
    """discharge.csv: time, volume (passed since the first frame), fluid_beyond, removed_beyond [m^2 in 2D]."""
    return _write_time_columns(path, times, columns, 17)
