"""Fluid fields at arbitrary points: Shepard-normalised kernel interpolation, lines and grids.

For a point p and a fluid field f (velocity, pressure, density, ...)

    f(p) = sum_j f_j V_j W(p - x_j, h) / sum_j V_j W(p - x_j, h),   V_j = m_j / rho_j,

the zeroth-order-consistent (Shepard 1968) form of the SPH interpolant
(Monaghan 2005, Rep. Prog. Phys. 68, eq. 2.3 normalised by the same sum of
V_j W). It reproduces a constant exactly wherever a fluid particle lies within
the support. A linear field f = a + b . x is reproduced as a + b . x_c, where
x_c = sum_j x_j V_j W / sum_j V_j W is the kernel-weighted centroid of the
neighbours: exactly at points whose neighbourhood is symmetric (for instance
lattice nodes and cell centres inside a regular lattice), to first order
elsewhere, and with a bias towards the fluid next to a free surface or a wall,
where the neighbourhood is one-sided (tests/unit/test_line_interpolation.py).

Walls are not included: the value is an average of the fluid only, as for the
pressure probes (seawall.probes), so the same line means the same thing for
every wall model. Points with no fluid particle within the kernel support get
NaN and a zero Shepard weight.

Python: :func:`interpolate` (any points), :func:`line_points`, :func:`grid_points`;
during a run: :class:`LineSampler` (``seawall run CASE --line x0,y0:x1,y1:n``),
which writes one CSV row per point and sample time.
"""

import os

import numpy as np
from numba import njit, prange

from .errors import ParameterError
from .kernels import kernel_shape
from .neighbors import cell_index, neighbour_range, separation, tag_dim, tag_periodic
from .probes import Probe


@njit(cache=True, parallel=True, fastmath=True, error_model="numpy")
def shepard_interpolate(layout, points, xf, values, volume, start, order, lo, inv_cell, ncell, period, prm,
                        out, weight):
    """out[k, :] = sum_j values[j, :] V_j W / sum_j V_j W at points[k]; weight[k] = sum_j V_j W.

    ``points`` has three columns (z = 0 in 2D). Points with no fluid neighbour get NaN.
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    nval = values.shape[1]
    for k in prange(points.shape[0]):
        p0 = points[k, 0]
        p1 = points[k, 1]
        p2 = points[k, 2]
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        acc = np.zeros(nval)
        sw = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for kk in range(ka, kb):
                    j = order[kk]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xf, j, dim, periodic, period)
                    if r2 >= prm.support2:
                        continue
                    w = volume[j] * kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                    sw += w
                    for c in range(nval):
                        acc[c] += values[j, c] * w
        weight[k] = sw * prm.sigma
        for c in range(nval):
            out[k, c] = acc[c] / sw if sw > 0.0 else np.nan


#: field name -> (particle array, gauge?) ; "p" is reported as gauge pressure (minus the background pressure)
FIELD_ALIASES = {"velocity": "v", "pressure": "p", "density": "rho"}


def _columns(sim, fields):
    """(names of the output columns, (N, k) array of the fluid values) for the requested fields."""
    fp = sim.fluid.particles
    names = []
    cols = []
    for field in fields:
        key = FIELD_ALIASES.get(field, field)
        if key not in fp:
            raise ParameterError(f"fields: the fluid has no field {field!r}; available: "
                                 f"{', '.join(sorted(set(fp.names()) | set(FIELD_ALIASES)))}")
        a = fp[key]
        if key == "p":
            a = a - sim.physics.p_background
        if a.ndim == 1:
            names.append(key)
            cols.append(a.astype(np.float64))
        else:
            axes = "xyz"
            for c in range(a.shape[1]):
                names.append(f"{key}_{axes[c]}" if key != "v" else "uvw"[c])
                cols.append(a[:, c].astype(np.float64))
    return names, np.ascontiguousarray(np.stack(cols, axis=1)) if cols else np.zeros((fp.n, 0))


def interpolate(sim, points, fields=("v", "p")):
    """Shepard-interpolated fluid fields at ``points`` (an (M, d) array) of a built simulation.

    Returns a dict: one array of length M per scalar column (``u``, ``v``
    [, ``w``] for the velocity, ``p`` gauge pressure, ``rho``, or any other
    fluid array by its name) and ``weight``, the kernel sum sum_j V_j W
    (about 1 inside the fluid, lower near a free surface or wall, 0 where
    there is no fluid).
    """
    from .fluid.rates import equation_of_state

    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim == 1:
        pts = pts[None, :]
    if pts.ndim != 2 or pts.shape[1] != sim.dim or not np.all(np.isfinite(pts)):
        raise ParameterError(f"points must be an (M, {sim.dim}) array of finite coordinates, got shape {pts.shape}")
    fp = sim.fluid.particles
    # pressures and volumes consistent with the current densities (cheap; also done before probes)
    equation_of_state(fp["rho"], fp["m"], sim.physics, fp["p"], fp["c"], fp["p_over_rho2"], fp["volume"])
    names, values = _columns(sim, fields)
    p3 = np.zeros((pts.shape[0], 3))
    p3[:, :sim.dim] = pts
    g = sim.grid
    cells = g.build(fp["x"])
    out = np.empty((pts.shape[0], values.shape[1]))
    weight = np.empty(pts.shape[0])
    if fp.n == 0:
        out[:] = np.nan
        weight[:] = 0.0
    else:
        shepard_interpolate(g.layout, p3, fp["x"], values, fp["volume"], cells.start, cells.order, g.lo,
                            g.inv_cell, g.ncell, g.period, sim.physics, out, weight)
    result = {name: out[:, c].copy() for c, name in enumerate(names)}
    result["weight"] = weight
    return result


def line_points(start, end, n):
    """``n`` points evenly spaced from ``start`` to ``end`` (both included; n = 1 gives ``start``)."""
    a = np.asarray(start, dtype=np.float64)
    b = np.asarray(end, dtype=np.float64)
    n = int(n)
    if a.shape != b.shape or a.ndim != 1 or a.size not in (2, 3):
        raise ParameterError(f"line ends must both have 2 or 3 coordinates, got {start!r} and {end!r}")
    if n < 1:
        raise ParameterError(f"a line needs at least 1 point, got n = {n}")
    s = np.linspace(0.0, 1.0, n) if n > 1 else np.zeros(1)
    return a[None, :] + s[:, None] * (b - a)[None, :]


def grid_points(lo, hi, shape):
    """Points of a regular grid from corner ``lo`` to ``hi`` (both included), ``shape`` points per axis.

    Returned as an (prod(shape), d) array, x fastest (reshape to ``shape[::-1]``).
    """
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    shape = [int(s) for s in shape]
    if lo.shape != hi.shape or lo.size not in (2, 3) or len(shape) != lo.size or min(shape) < 1:
        raise ParameterError("grid_points needs lo, hi with 2 or 3 coordinates and one positive count per axis")
    axes = [np.linspace(lo[k], hi[k], shape[k]) if shape[k] > 1 else np.array([lo[k]]) for k in range(lo.size)]
    mesh = np.meshgrid(*axes[::-1], indexing="ij")[::-1]
    return np.stack([m.ravel() for m in mesh], axis=1)


def parse_line(text, option="--line"):
    """``"x0,y0:x1,y1:n"`` (or with z) -> (start, end, n); errors name the option."""
    parts = str(text).split(":")
    if len(parts) != 3:
        raise ParameterError(f"{option} expects x0,y0:x1,y1:n (start:end:number of points), got {text!r}")
    ends = []
    for label, part in zip(("start", "end"), parts[:2]):
        try:
            coords = [float(c) for c in part.split(",")]
        except ValueError:
            raise ParameterError(f"{option}: the {label} point must be comma-separated numbers, got {part!r}") from None
        if len(coords) not in (2, 3) or not all(np.isfinite(coords)):
            raise ParameterError(f"{option}: the {label} point must have 2 or 3 finite coordinates, got {part!r}")
        ends.append(coords)
    if len(ends[0]) != len(ends[1]):
        raise ParameterError(f"{option}: start and end must have the same number of coordinates, got {text!r}")
    try:
        n = int(parts[2])
    except ValueError:
        raise ParameterError(f"{option}: the number of points must be a whole number, got {parts[2]!r}") from None
    if n < 2:
        raise ParameterError(f"{option}: the number of points must be at least 2, got {n}")
    return tuple(ends[0]), tuple(ends[1]), n


class LineSampler:
    """Output callback: interpolated fluid fields along a line (or any point set) every ``every`` seconds.

    Writes ``DIR/<name>.csv`` with columns ``time, point, s, x, y[, z], u, v[, w], p, rho, weight``
    (``s`` = distance from the first point [m]), one row per point and sample,
    flushed at every sample. Add it with ``sim.add(LineSampler(...))``.
    """

    def __init__(self, directory, start, end, n, *, every=0.02, name="line", fields=("v", "p", "rho")):
        from .errors import require_positive

        self.directory = str(directory)
        self.points = line_points(start, end, n)
        self.every = require_positive("every", every)
        self.name = str(name)
        self.fields = tuple(fields)
        self.path = os.path.join(self.directory, f"{self.name}.csv")
        self.next_time = 0.0
        self._fh = None
        self.s = np.linalg.norm(self.points - self.points[0], axis=1)

    def open(self, sim, resume_after=None):
        if self.points.shape[1] != sim.dim:
            raise ParameterError(f"line {self.name!r}: points have {self.points.shape[1]} coordinates, the case is "
                                 f"{sim.dim}D")
        os.makedirs(self.directory, exist_ok=True)
        if resume_after is not None and os.path.exists(self.path):
            # keep the rows up to the restart time, as the probe CSV does
            with open(self.path) as fh:
                lines = fh.readlines()
            keep = [lines[0]] + [ln for ln in lines[1:] if float(ln.split(",", 1)[0]) <= resume_after + 1e-12]
            self._fh = open(self.path, "w")
            self._fh.writelines(keep)
            self.next_time = (int(np.floor(resume_after / self.every + 1e-9)) + 1) * self.every
        else:
            self._fh = open(self.path, "w")
            names, _ = _columns(sim, self.fields)
            coords = ["x", "y", "z"][:sim.dim]
            self._fh.write(",".join(["time", "point", "s", *coords, *names, "weight"]) + "\n")
        self._fh.flush()

    def due(self, t):
        return t >= self.next_time - 1e-12

    def write(self, sim):
        res = interpolate(sim, self.points, self.fields)
        names = [k for k in res if k != "weight"]
        for k in range(self.points.shape[0]):
            vals = [f"{sim.time:.9g}", str(k), f"{self.s[k]:.9g}", *(f"{c:.9g}" for c in self.points[k]),
                    *(f"{res[nm][k]:.9g}" for nm in names), f"{res['weight'][k]:.6g}"]
            self._fh.write(",".join(vals) + "\n")
        self._fh.flush()
        while self.next_time <= sim.time + 1e-12:
            self.next_time += self.every

    def close(self):
        if self._fh is not None:
            self._fh.close()
            self._fh = None


def read_line_csv(path):
    """Read a LineSampler CSV: (times, dict column -> (n_times, n_points) array)."""
    import csv

    with open(path) as fh:
        reader = csv.reader(fh)
        header = next(reader)
        rows = np.array([[float(v) if v != "nan" else np.nan for v in r] for r in reader], dtype=np.float64)
    if rows.size == 0:
        return np.zeros(0), {h: np.zeros((0, 0)) for h in header}
    n_points = int(rows[:, 1].max()) + 1
    rows = rows[: (rows.shape[0] // n_points) * n_points]
    times = rows[::n_points, 0]
    return times, {h: rows[:, c].reshape(-1, n_points) for c, h in enumerate(header)}



class FieldProbe(Probe):
    """Probe: one interpolated fluid field at a fixed point, e.g. ``FieldProbe("u_c", (0.5, 0.5), "u")``.

    ``field`` is a column name of :func:`interpolate`: ``u``, ``v``, ``w``,
    ``p`` (gauge), ``rho`` or another scalar fluid array. NaN where no fluid is near.
    """

    def __init__(self, name, point, field):
        super().__init__(name)
        self.point = np.asarray(point, dtype=np.float64)
        if self.point.ndim != 1 or self.point.size not in (2, 3):
            raise ParameterError(f"probe {name!r}: point must have 2 or 3 coordinates, got {point!r}")
        self.field = str(field)
        key = {"u": "v", "v": "v", "w": "v"}.get(self.field, FIELD_ALIASES.get(self.field, self.field))
        self._request = (key,)

    def sample(self, sim):
        res = interpolate(sim, self.point[None, :], self._request)
        if self.field not in res:
            raise ParameterError(f"probe {self.name!r}: no interpolated field {self.field!r}; "
                                 f"available: {', '.join(k for k in res if k != 'weight')}")
        return float(res[self.field][0])
