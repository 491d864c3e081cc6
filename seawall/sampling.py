"""Fluid fields at arbitrary points: lines and grids (pressure along a wall, velocity on a centreline).

A field f is interpolated at a point x by the Shepard-normalised SPH sum
([Huang2019], sec. 3.3, eq. 14-16 -- the "normalised" interpolation that ghost
walls use at their mirror points, whose compiled gather this module reuses):

    f(x) = sum_j f_j W(x - x_j) V_j / sum_j W(x - x_j) V_j,    V_j = m_j / rho_j,

over the fluid particles within the kernel support. It reproduces a
constant field exactly wherever x has a fluid neighbour, and a linear
field exactly at points whose neighbourhood is symmetric (lattice points
inside the fluid); near a free surface or a wall it is first-order
accurate. Points with no fluid neighbour get NaN.

``LineSampler`` writes a line's values every ``every`` seconds to
``DIR/line_<name>.csv``; on the command line, ``seawall run CASE --line
x0,y0:x1,y1:n`` (repeatable).
"""

import csv
import math
import os

import numpy as np

from .boundary.interpolation import NORMALISED, interpolate_points
from .errors import ParameterError, require_positive
from .probes import Probe
from .resources import require_memory
from .schedule import first_due_after, next_due

#: memory one line point takes while sampled: coordinates, the gathered values and their text row
BYTES_PER_LINE_POINT = 200

#: quantities that can be sampled: name -> how to get it from the fluid's arrays
QUANTITIES = ("pressure", "density", "u", "v", "w", "speed")


def interpolate(sim, points, quantities=("pressure", "u", "v")):
    """Fluid ``quantities`` (see :data:`QUANTITIES`) at ``points`` (M, d); returns {name: (M,) array}."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != sim.dim:
        raise ParameterError(f"points must be an (M, {sim.dim}) array, got shape {pts.shape}")
    unknown = [q for q in quantities if q not in QUANTITIES or (q == "w" and sim.dim == 2)]
    if unknown:
        raise ParameterError(f"unknown quantity {unknown[0]!r}; available: {', '.join(QUANTITIES)}")
    fp = sim.fluid.particles
    cols = []
    for q in quantities:
        if q == "pressure":
            cols.append(fp["p"] - sim.physics.p_background)
        elif q == "density":
            cols.append(fp["rho"])
        elif q == "speed":
            cols.append(np.linalg.norm(fp["v"], axis=1))
        else:
            cols.append(fp["v"][:, "uvw".index(q)])
    values = np.ascontiguousarray(np.stack(cols, axis=1))
    g = sim.grid
    inside = g.inside(pts)
    out = np.full((pts.shape[0], len(quantities)), np.nan)
    if inside.any():
        cells = g.build(fp["x"])
        sub = np.ascontiguousarray(pts[inside])
        res = np.empty((sub.shape[0], len(quantities)))
        count = np.zeros(sub.shape[0], dtype=np.int64)
        # the same gather as the ghost walls' normalised interpolation ([Huang2019] eq. 14-16)
        interpolate_points(g.layout, NORMALISED, 0.0, 0.0, 0, sub, fp["x"], values, fp["m"] / fp["rho"],
                           cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period, sim.physics, res, count)
        res[count == 0] = np.nan
        out[inside] = res
    return {q: out[:, k].copy() for k, q in enumerate(quantities)}


def line_points(start, end, n):
    """n points from ``start`` to ``end`` inclusive."""
    start = np.asarray(start, dtype=np.float64)
    end = np.asarray(end, dtype=np.float64)
    if start.shape != end.shape or start.ndim != 1 or start.size not in (2, 3):
        raise ParameterError("a line's start and end must both have 2 or 3 coordinates")
    n = int(n)
    if n < 2:
        raise ParameterError(f"a line needs at least 2 points, got {n}")
    if not (np.all(np.isfinite(start)) and np.all(np.isfinite(end))):
        raise ParameterError("a line's start and end must be finite")
    require_memory("a line", n, BYTES_PER_LINE_POINT)
    return start[None, :] + np.linspace(0.0, 1.0, n)[:, None] * (end - start)[None, :]


def grid_points(lo, hi, shape):
    """Points of a regular grid over the box [lo, hi] with ``shape`` points per axis (row-major)."""
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    if lo.shape != hi.shape or len(shape) != lo.size:
        raise ParameterError("grid: lo, hi and shape must have one entry per axis")
    axes = [np.linspace(a, b, int(k)) for a, b, k in zip(lo, hi, shape, strict=True)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, lo.size)


def parse_line(text, dim=None):
    """Parse ``x0,y0:x1,y1:n`` (or with z) as given to ``--line``; errors name ``--line``."""
    parts = str(text).split(":")
    try:
        if len(parts) != 3:
            raise ValueError
        start = [float(c) for c in parts[0].split(",")]
        end = [float(c) for c in parts[1].split(",")]
        n = int(parts[2])
    except ValueError:
        raise ParameterError(f"--line must look like x0,y0:x1,y1:n (or x0,y0,z0:x1,y1,z1:n), got {text!r}") from None
    if len(start) != len(end) or len(start) not in (2, 3) or (dim is not None and len(start) != dim):
        raise ParameterError(f"--line {text!r}: start and end need {dim or '2 or 3'} coordinates each")
    if n < 2:
        raise ParameterError(f"--line {text!r}: needs at least 2 points, got n = {n}")
    if not all(math.isfinite(c) for c in start + end):
        raise ParameterError(f"--line {text!r}: coordinates must be finite numbers")
    require_memory(f"--line {text!r}", n, BYTES_PER_LINE_POINT)
    return start, end, n


class LineSampler:
    """Fluid fields along a line every ``every`` seconds, appended to ``DIR/line_<name>.csv``.

    Columns: time, s (distance from the start), the point's coordinates, then
    the quantities. Rows are flushed as written, so an interrupted run keeps them.
    """

    def __init__(self, directory, start, end, n, *, every, name="line", quantities=None):
        self.directory = str(directory)
        self.name = str(name)
        self.every = require_positive("every", every)
        self.points = line_points(start, end, n)
        dim = self.points.shape[1]
        self.quantities = tuple(quantities) if quantities else (("pressure", "u", "v") if dim == 2
                                                                else ("pressure", "u", "v", "w"))
        self.path = os.path.join(self.directory, f"line_{self.name}.csv")
        self.next_time = 0.0
        self._fh = None

    def open(self, sim, resume_after=None):
        if self.points.shape[1] != sim.dim:
            raise ParameterError(f"line {self.name!r} has {self.points.shape[1]} coordinates, the run is {sim.dim}D")
        os.makedirs(self.directory, exist_ok=True)
        header = ["time", "s", *"xyz"[:sim.dim], *self.quantities]
        resume = resume_after is not None and os.path.exists(self.path)
        if resume:
            self._drop_rows_after(resume_after, header)
        self._fh = open(self.path, "a" if resume else "w", newline="")  # noqa: SIM115 (kept open for the run)
        self._writer = csv.writer(self._fh)
        if not resume:
            self._writer.writerow(header)
        else:
            self.next_time = first_due_after(resume_after, self.every)

    def _drop_rows_after(self, resume_after, header):
        """On a restart keep the rows up to the checkpoint's time; the run writes the later ones again."""
        from .io.vtk import _atomic_write

        with open(self.path, newline="") as fh:
            rows = list(csv.reader(fh))
        if not rows or rows[0] != header:
            raise ParameterError(f"{self.path}: cannot continue it, its columns {rows[0] if rows else []} "
                                 f"differ from {header}")
        kept = []
        for row in rows[1:]:
            try:
                if len(row) == len(header) and float(row[0]) <= resume_after:
                    kept.append(row)
            except ValueError:
                pass   # a row cut off by a crash
        with _atomic_write(self.path, "w", newline="") as fh:
            csv.writer(fh).writerows([header, *kept])

    def due(self, t):
        return t >= self.next_time - 1e-12

    def write(self, sim):
        values = interpolate(sim, self.points, self.quantities)
        s = np.linalg.norm(self.points - self.points[0], axis=1)
        for i in range(self.points.shape[0]):
            self._writer.writerow([f"{sim.time:.9g}", f"{s[i]:.9g}", *(f"{c:.9g}" for c in self.points[i]),
                                   *(f"{values[q][i]:.9g}" for q in self.quantities)])
        self._fh.flush()
        self.next_time = next_due(self.next_time, self.every, sim.time)

    def close(self):
        if self._fh is not None:
            self._fh.close()
            self._fh = None


class FieldProbe(Probe):
    """Probe: one interpolated fluid quantity at a fixed point, e.g. ``FieldProbe("u_c", (0.5, 0.5), "u")``.

    ``quantity`` is one of :data:`QUANTITIES`; NaN where no fluid is near.
    """

    def __init__(self, name, point, quantity):
        super().__init__(name)
        self.point = np.asarray(point, dtype=np.float64)
        if self.point.ndim != 1 or self.point.size not in (2, 3):
            raise ParameterError(f"probe {name!r}: point must have 2 or 3 coordinates, got {point!r}")
        if quantity not in QUANTITIES:
            raise ParameterError(f"probe {name!r}: unknown quantity {quantity!r}; available: {', '.join(QUANTITIES)}")
        self.quantity = quantity

    def sample(self, sim):
        return float(interpolate(sim, self.point[None, :], (self.quantity,))[self.quantity][0])


def face_points(center, normal, diameter, spacing):
    """Quadrature of a sensor face: (points (M, d), weights (M,)) with sum(weights) = the face's size.

    2D: the segment of length ``diameter`` through ``center`` perpendicular to
    ``normal``, cut into equal parts no longer than ``spacing``, one point at
    the middle of each (midpoint rule). 3D: the disc of that diameter in the
    plane perpendicular to ``normal``, cut into rings no wider than
    ``spacing``; a ring [r0, r1] gets m >= 4 equally spaced points on the
    radius sqrt((r0^2 + r1^2) / 2), m = ceil(2 pi r / spacing), each weighing
    the ring's area / m. Both rules are exact for fields linear on the face;
    the disc's rule also gives the exact second moment (pi D^4 / 64 about a
    diameter), the segment's misses D^3 / 12 by the factor 1 - 1/m^2 of the
    midpoint rule. A kernel-interpolated field varies on the scale h > spacing.
    """
    c = np.asarray(center, dtype=np.float64)
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    D = require_positive("diameter", diameter)
    spacing = require_positive("spacing", spacing)
    if c.size == 2:
        t = np.array([-n[1], n[0]])
        m = max(1, int(np.ceil(D / spacing - 1e-9)))
        s = ((np.arange(m) + 0.5) / m - 0.5) * D
        return c[None, :] + s[:, None] * t[None, :], np.full(m, D / m)
    # two unit vectors spanning the face: t1 perpendicular to n, t2 = n x t1
    helper = np.eye(3)[int(np.argmin(np.abs(n)))]
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    R = 0.5 * D
    rings = max(1, int(np.ceil(R / spacing - 1e-9)))
    points = []
    weights = []
    for j in range(rings):
        r0 = j * R / rings
        r1 = (j + 1) * R / rings
        r = np.sqrt(0.5 * (r0 * r0 + r1 * r1))
        m = max(4, int(np.ceil(2.0 * np.pi * r / spacing - 1e-9)))
        phi = (np.arange(m) + 0.5 * (j % 2)) * 2.0 * np.pi / m
        points.append(c[None, :] + r * (np.cos(phi)[:, None] * t1[None, :] + np.sin(phi)[:, None] * t2[None, :]))
        weights.append(np.full(m, np.pi * (r1 * r1 - r0 * r0) / m))
    return np.concatenate(points), np.concatenate(weights)


def parse_sensor(text, dim=None):
    """Parse ``x,y[,z][:diameter]`` as given to ``--sensor``; returns (point, diameter or None)."""
    parts = str(text).split(":")
    try:
        if len(parts) not in (1, 2):
            raise ValueError
        point = [float(c) for c in parts[0].split(",")]
        diameter = float(parts[1]) if len(parts) == 2 else None
    except ValueError:
        raise ParameterError(f"--sensor must look like x,y:diameter or x,y,z:diameter (diameter optional), "
                             f"got {text!r}") from None
    if len(point) not in (2, 3) or (dim is not None and len(point) != dim):
        raise ParameterError(f"--sensor {text!r}: the point needs {dim or '2 or 3'} coordinates")
    if not all(np.isfinite(point)):
        raise ParameterError(f"--sensor {text!r}: the point's coordinates must be finite")
    if diameter is not None and not (diameter > 0 and np.isfinite(diameter)):
        raise ParameterError(f"--sensor {text!r}: diameter must be a positive number, got {parts[1]!r}")
    return point, diameter
