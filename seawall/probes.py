"""Probes: quantities sampled during a run, returned as arrays and written as CSV.

Every probe has a ``name`` (its CSV column) and ``sample(sim)`` returning a
float. Pressure probes read only the fluid particles, so the same probe
means the same thing whatever wall model is used:

* :class:`WallPressure` -- the fluid pressure extrapolated to a point on a
  wall with the hydrostatic/acceleration term (the Adami et al. 2012 form,
  [TrixiBoundary]: p = sum_f (p_f + rho_f (g - a) . (x - x_f)) W / sum_f W). It is
  exact for still water, so the probe has no bias from the kernel's
  truncation at the wall, as a plain Shepard average would.
* :class:`PressureSensor` -- the same wall pressure averaged over a sensor's
  face: a disc of given diameter (a segment in 2D) on the wall surface, as a
  real transducer integrates the pressure over its membrane.
* :class:`Pressure` -- Shepard average sum_f p_f W / sum_f W at an interior point.
* :class:`FreeSurfaceGauge` -- a wave gauge: the elevation of the free surface
  above a horizontal position [m], by the definition of ``seawall sample
  --gauge`` (:func:`seawall.postprocess.gauge_series`), so the run-time and the
  post-processed gauge agree on the same frame; over a dry bed it reads the
  bed's elevation (water depth 0).
* :class:`SurgeFront` -- largest coordinate of any fluid particle along an axis.
* :class:`KineticEnergy`, :class:`TotalMass`.
* :class:`Discharge` -- the fluid volume that has crossed a section, a
  segment from ``start`` to ``end`` (2D) or a rectangle normal to an axis
  with opposite corners ``start`` and ``end`` (3D), counted at every step, and
  its companion column ``<name>_rate``, the discharge over the last probe
  interval. Positive flow crosses towards the side obtained by rotating
  end - start clockwise by 90 degrees (a section drawn bottom to top counts
  flow in +x as positive). A fluid particle whose side of the section's
  line changes during a step, at a point of its path (straight from its
  position before the step to its position after it) within the segment,
  adds +-m / rho0 (its mass-based volume, so the count conserves volume
  exactly). Columns: the cumulative volume [m^2 per metre in 2D] and the
  discharge q [m^2/s], the mean over the last probe interval (NaN at the
  first sample, which has no interval before it).
  :meth:`Discharge.over_crest` places a vertical section on a wall's crest.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from .errors import ParameterError
from .kernels import kernel_shape
from .neighbors import cell_index, neighbour_range, tag_dim, tag_periodic, separation

if TYPE_CHECKING:
    from .simulation import Simulation


@njit(cache=True)
def interpolate_pressure(layout, points, accel, xf, pf, rhof, start, order, lo, inv_cell, ncell, period, prm,
                         hydrostatic, out, weight):
    """Kernel-weighted fluid pressure at points; with ``hydrostatic`` the Adami extrapolation.

    ``out[k]`` is 0 (gauge) where no fluid particle lies within the support;
    ``weight[k]`` receives the Shepard sum sum_f V_f W (1 inside full fluid).
    """
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    for k in range(points.shape[0]):
        p0 = points[k, 0]
        p1 = points[k, 1]
        p2 = points[k, 2] if dim == 3 else 0.0
        g0 = prm.gx - accel[0]
        g1 = prm.gy - accel[1]
        g2 = prm.gz - accel[2]
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        sw = 0.0
        sp = 0.0
        sv = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for kk in range(ka, kb):
                    f = order[kk]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xf, f, dim, periodic, period)
                    if r2 >= prm.support2:
                        continue
                    w = kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
                    sw += w
                    val = pf[f]
                    if hydrostatic:
                        val += rhof[f] * (g0 * d0 + g1 * d1 + g2 * d2)
                    sp += val * w
                    sv += prm.sigma * w
        # a dry sensor (no fluid within the support) reads zero gauge pressure, as a real one does
        out[k] = sp / sw if sw > 0.0 else 0.0
        weight[k] = sv


class Probe:
    """Base class: a named scalar sampled during the run.

    ``unit``: the unit of the sampled value ("" if none); a force, energy or
    mass of a 2D run is per metre of depth (:func:`probe_unit`).
    docs/tutorials/your-own-probe.md writes one.
    """

    unit: str = ""

    def __init__(self, name: str) -> None:
        if not isinstance(name, str) or not name or "," in name:
            raise ParameterError(f"probe name must be a non-empty string without commas, got {name!r}")
        self.name = name

    def sample(self, sim: Simulation) -> float:
        """The value now, from ``sim``'s current state."""
        raise NotImplementedError

    def companions(self) -> Sequence[Probe]:
        """Probes added with this one, right after it (their own columns; :class:`Discharge`'s rate)."""
        return ()


#: units that are per metre of depth in a 2D run
PER_DEPTH = ("N", "J", "kg")


def probe_unit(probe: Probe, dim: int) -> str:
    """The unit of ``probe``'s values in a ``dim``-D run: "N/m" for a 2D force (per metre of depth), ...

    A probe whose 2D unit is not its unit per metre (a volume m^3 becomes m^2 per metre) gives it as ``unit_2d``.
    """
    if dim == 2 and getattr(probe, "unit_2d", None):
        return probe.unit_2d
    unit = getattr(probe, "unit", "") or ""
    return f"{unit}/m" if dim == 2 and unit in PER_DEPTH else unit


class _PointPressure(Probe):
    hydrostatic = False
    unit = "Pa"

    def __init__(self, name: str, point: Sequence[float]) -> None:
        super().__init__(name)
        self.point = np.asarray(point, dtype=np.float64)
        if self.point.ndim != 1 or self.point.size not in (2, 3):
            raise ParameterError(f"probe {name!r}: point must have 2 or 3 coordinates, got {point!r}")

    def sample(self, sim):
        fp = sim.fluid.particles
        cells = sim.fluid_cells
        if cells is None or fp.n == 0:
            return float("nan")
        g = sim.grid
        out = np.empty(1)
        weight = np.empty(1)
        pts = np.zeros((1, 3))
        pts[0, :self.point.size] = self.point
        interpolate_pressure(g.layout, pts, np.zeros(3), fp["x"], fp["p"] - sim.physics.p_background, fp["rho"],
                             cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period, sim.physics,
                             self.hydrostatic, out, weight)
        return float(out[0])


class WallPressure(_PointPressure):
    """Gauge pressure at a point on a wall [Pa], extrapolated from the fluid (Adami 2012 form).

    Parameters
    ----------
    name : str
        Column name.
    point : sequence of float
        The sensor's position on the wall surface [m].
    """

    hydrostatic = True


class PressureSensor(Probe):
    """Gauge pressure averaged over a sensor's face on a wall [Pa].

    The face is the disc of ``diameter`` (3D; a segment of that length in 2D)
    in the wall surface around ``point``: the wall's normal and surface come
    from the wall particle nearest to the point (``seawall.shapes`` normals
    and surface points), and the face is centred on the point's projection
    onto that surface. The value is (1/A) int_face p dA of the field that
    :class:`WallPressure` samples at one point (the Adami et al. 2012
    extrapolation, [TrixiBoundary]), integrated by :func:`seawall.sampling.face_points`
    with points no farther apart than dx / 2. For still water (p linear) the
    sensor reads the point probe's value at its centre; where the pressure
    varies on the face's scale (an impact) it reads the mean, and noise of
    wavelength below the diameter is averaged out.

    Parameters
    ----------
    name : str
        Column name.
    point : sequence of float
        Centre of the face, on (within dx/2 of) a wall surface [m].
    diameter : float, optional
        Face diameter (segment length in 2D) [m]; default one kernel support.
    """

    unit = "Pa"

    def __init__(self, name: str, point: Sequence[float], diameter: float | None = None) -> None:
        super().__init__(name)
        self.point = np.asarray(point, dtype=np.float64)
        if self.point.ndim != 1 or self.point.size not in (2, 3) or not np.all(np.isfinite(self.point)):
            raise ParameterError(f"sensor {name!r}: point must have 2 or 3 finite coordinates, got {point!r}")
        if diameter is not None:
            try:
                d = float(diameter)
            except (TypeError, ValueError):
                d = float("nan")
            if not (d > 0 and np.isfinite(d)):
                raise ParameterError(f"sensor {name!r}: diameter must be a positive number, got {diameter!r}")
            diameter = d
        self.diameter = diameter
        self.normal = None
        self.center = None
        self._points = None
        self._weights = None

    def attach(self, sim: Simulation) -> None:
        """Place the face on the wall surface nearest to the point (called by ``Simulation.add``)."""
        from .sampling import face_points

        if self.point.size != sim.dim:
            raise ParameterError(f"sensor {self.name!r}: point has {self.point.size} coordinates, the run is {sim.dim}D")
        dx = sim.fluid.spacing
        best = None
        for wall in sim.walls:
            pa = wall.particles
            if wall.n == 0 or "normal" not in pa or "surface" not in pa:
                continue
            r2 = np.sum((pa["x"] - self.point) ** 2, axis=1)
            b = int(np.argmin(r2))
            if best is None or r2[b] < best[0]:
                best = (r2[b], pa["normal"][b], pa["surface"][b])
        off = None
        if best is not None:
            normal = best[1] / np.linalg.norm(best[1])
            off = float(np.dot(self.point - best[2], normal))
            # on the surface: within half a spacing of it, next to a wall particle
            if abs(off) <= 0.5 * dx and best[0] <= sim.kernel.support(sim.h) ** 2:
                self.normal = normal
                self.center = self.point - off * normal
                if self.diameter is None:
                    self.diameter = sim.kernel.support(sim.h)
                self._points, self._weights = face_points(self.center, normal, self.diameter, 0.5 * dx)
                return
        raise ParameterError(
            f"sensor {self.name!r}: point {self.point.tolist()} is not on a wall surface"
            + ("" if off is None else f" (nearest surface {abs(off):.3g} m away along its normal"
               f"{'' if best[0] <= sim.kernel.support(sim.h) ** 2 else ', nearest wall particle beyond a kernel support'})")
            + "; put it on a wall")

    def describe(self):
        return {"point": self.point.tolist(), "center": None if self.center is None else self.center.tolist(),
                "normal": None if self.normal is None else self.normal.tolist(), "diameter": self.diameter,
                "quadrature_points": 0 if self._points is None else int(self._points.shape[0])}

    def sample(self, sim):
        fp = sim.fluid.particles
        cells = sim.fluid_cells
        if cells is None or fp.n == 0:
            return float("nan")
        if self._points is None:
            self.attach(sim)
        g = sim.grid
        m = self._points.shape[0]
        pts = np.zeros((m, 3))
        pts[:, :sim.dim] = self._points
        out = np.empty(m)
        weight = np.empty(m)
        interpolate_pressure(g.layout, pts, np.zeros(3), fp["x"], fp["p"] - sim.physics.p_background, fp["rho"],
                             cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period, sim.physics,
                             True, out, weight)
        return float(np.dot(self._weights, out) / np.sum(self._weights))


class Pressure(_PointPressure):
    """Gauge pressure at an interior point [Pa], Shepard-interpolated from the fluid."""

    hydrostatic = False


class SurgeFront(Probe):
    """Position of the foremost fluid particle along ``axis`` [m] (max, or min if direction < 0)."""

    unit = "m"

    def __init__(self, name: str = "front", axis: int = 0, direction: int = 1) -> None:
        super().__init__(name)
        self.axis = int(axis)
        self.direction = 1 if direction >= 0 else -1

    def sample(self, sim):
        x = sim.fluid.particles["x"]
        if x.shape[0] == 0:
            return float("nan")
        col = x[:, self.axis]
        return float(col.max() if self.direction > 0 else col.min())


class WallForce(Probe):
    """Force of the fluid on the wall system ``wall`` along ``axis`` [N, per metre in 2D].

    The sum over fluid particles of -m_i times the wall's contribution to
    their acceleration, at the last evaluation of the rates (the pairwise form
    of [Huang2019] eq. 29 for a momentum-conserving wall model).

    ``part`` = (lo, hi), a box: only the force on the wall particles inside it (e.g. the right
    side of a tank, whose corners belong to the box that holds them). It is the same sum with
    the wall model acting through those particles alone, one extra pass of the model over
    them per evaluation; it needs a model whose push is a sum of pair forces
    (``pairwise_momentum``, as the per-particle forces of
    :mod:`seawall.boundary.particle_forces`): boxes that split a wall's particles then give
    forces that add up to the wall's.
    """

    unit = "N"

    def __init__(self, name: str, wall: str, axis: int = 0, part: Sequence[Sequence[float]] | None = None) -> None:
        super().__init__(name)
        self.wall = str(wall)
        self.axis = int(axis)
        self.part = None
        if part is not None:
            try:
                lo, hi = (np.asarray(c, dtype=np.float64) for c in part)
            except (TypeError, ValueError):
                lo = hi = np.zeros(0)
            if (lo.ndim != 1 or lo.shape != hi.shape or lo.size not in (2, 3) or not np.all(np.isfinite(lo))
                    or not np.all(np.isfinite(hi)) or not np.all(hi > lo)):
                raise ParameterError(f"wall force {name!r}: part must be a box [lo, hi] of 2 or 3 finite "
                                     f"coordinates each with hi > lo, got {part!r}")
            self.part = (tuple(lo.tolist()), tuple(hi.tolist()))
        # a part's force is summed over the fluid each rank owns (the wall's total is already global)
        self.mpi_reduction = "sum" if self.part is not None else None

    def attach(self, sim: Simulation) -> None:
        """Check the axis and the part against the run; register the part (called by ``Simulation.add``)."""
        if not 0 <= self.axis < sim.dim:
            raise ParameterError(f"wall force {self.name!r}: axis must be 0 .. {sim.dim - 1}, got {self.axis}")
        if self.part is None:
            return
        wall = next(w for w in sim.walls if w.name == self.wall)
        lo, hi = (np.asarray(c) for c in self.part)
        if lo.size != sim.dim:
            raise ParameterError(f"wall force {self.name!r}: part has {lo.size} coordinates, the run is {sim.dim}D")
        if not getattr(type(wall.model), "pairwise_momentum", False):
            raise ParameterError(f"wall force {self.name!r}: part needs a wall model whose push is a sum of pair "
                                 f"forces (pairwise_momentum); {type(wall.model).__name__} of wall {wall.name!r} "
                                 f"is not one (the whole wall's force needs no part)")
        if not np.any(np.all((wall.x >= lo) & (wall.x <= hi), axis=1)):
            raise ParameterError(f"wall force {self.name!r}: no particle of wall {wall.name!r} lies in part "
                                 f"{lo.tolist()} - {hi.tolist()}")
        sim.wall_part_forces.setdefault(self.wall, {})[self.part] = np.zeros(sim.dim)

    def sample(self, sim):
        if self.part is not None:
            return float(sim.wall_part_forces[self.wall][self.part][self.axis])
        return float(sim.wall_forces[self.wall][self.axis])


class KineticEnergy(Probe):
    """Total kinetic energy of the fluid, sum m |v|^2 / 2 [J] (per metre of depth in 2D)."""

    unit = "J"

    def __init__(self, name: str = "kinetic_energy") -> None:
        super().__init__(name)

    def sample(self, sim):
        fp = sim.fluid.particles
        return float(0.5 * np.sum(fp["m"] * np.sum(fp["v"] ** 2, axis=1)))


class TotalMass(Probe):
    """Total mass of the fluid particles still in the domain [kg] (per metre in 2D)."""

    unit = "kg"

    def __init__(self, name: str = "mass") -> None:
        super().__init__(name)

    def sample(self, sim):
        return float(np.sum(sim.fluid.particles["m"]))


#: the vertical step of a free-surface gauge's line of points, in dx (seawall sample --gauge's too)
GAUGE_RESOLUTION = 0.25


@njit(cache=True)
def gauge_column(layout, points, xf, volume, start, order, lo, inv_cell, ncell, period, prm, full):
    """The Shepard sum sum_f V_f W at ``points`` (a vertical line, ordered upwards), from the last point
    down, stopping at the first where it reaches 0.5; returns that index (-1: none). ``full[k]`` is set
    for the points visited (the one above the crossing included), so only the line's dry part and one
    wet point are evaluated."""
    dim = tag_dim(layout)
    periodic = tag_periodic(layout)
    inv_h = 1.0 / prm.h
    nrows = 25 if dim == 3 else 5
    for k in range(points.shape[0] - 1, -1, -1):
        p0 = points[k, 0]
        p1 = points[k, 1]
        p2 = points[k, 2] if dim == 3 else 0.0
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        sv = 0.0
        for row in range(nrows):
            for part in range(2):
                ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                for kk in range(ka, kb):
                    f = order[kk]
                    d0, d1, d2, r2 = separation(p0, p1, p2, xf, f, dim, periodic, period)
                    if r2 >= prm.support2:
                        continue
                    sv += volume[f] * prm.sigma * kernel_shape(prm.kernel, np.sqrt(r2) * inv_h)
        full[k] = sv
        if sv >= 0.5:
            return k
    return -1


def gauge_vertical(gravity, dim):
    """(up axis, horizontal axes) of a free-surface gauge; ParameterError without gravity along one axis."""
    g = np.asarray(gravity, dtype=np.float64)[:dim]
    if not np.any(g):
        raise ParameterError("a free-surface gauge needs gravity; the run has none")
    if np.count_nonzero(g) != 1:
        raise ParameterError(f"a free-surface gauge needs gravity along one axis, got {g.tolist()}")
    up = int(np.argmax(np.abs(g)))
    return up, [a for a in range(dim) if a != up]


def gauge_heights(x_up, gravity_up, support, dx, resolution=GAUGE_RESOLUTION):
    """The heights of a gauge's vertical line: every ``resolution`` dx from one support below the lowest
    fluid particle to one above the highest (``x_up``: the fluid's vertical coordinates), ordered upwards
    (against gravity, whose vertical component is ``gravity_up``)."""
    lo, hi = x_up.min() - support, x_up.max() + support
    heights = np.arange(lo, hi + resolution * dx, resolution * dx)
    return heights[::-1] if gravity_up > 0 else heights


def surface_crossing(heights, full, top):
    """Elevation where the Shepard sum ``full`` along ``heights`` falls through 0.5 above index ``top``
    (the highest wet point), interpolated linearly."""
    if top + 1 < heights.size:
        a, b = full[top], full[top + 1]
        return float(heights[top] + (a - 0.5) / (a - b) * (heights[top + 1] - heights[top]))
    return float(heights[top])


def bed_level(wall_x, normals, surfaces, position, up, horizontal, gravity_up, dx):
    """Elevation of the bed under a dry gauge: the highest surface point (along the upward direction)
    of the wall particles within dx/2 of the gauge's vertical line (each horizontal coordinate) whose
    normal points upwards; NaN if there is none (no wall under the gauge)."""
    if wall_x is None or wall_x.shape[0] == 0:
        return float("nan")
    sign = -1.0 if gravity_up > 0 else 1.0
    near = sign * normals[:, up] > 0.0
    for a, c in zip(horizontal, position):
        near &= np.abs(wall_x[:, a] - c) <= 0.5 * dx + 1e-12 * max(1.0, abs(c))
    if not near.any():
        return float("nan")
    return float(sign * np.max(sign * surfaces[near, up]))


class FreeSurfaceGauge(Probe):
    """Elevation of the free surface above a horizontal position [m] (a wave gauge).

    Along the vertical line through ``x`` (gravity gives the vertical) the Shepard sum of the
    fluid, sum_f V_f W ([Huang2019] eq. 16's denominator: 1 inside the fluid, 0 outside), is
    evaluated every dx/4 from one kernel support below the lowest fluid particle to one above
    the highest, and the value is the highest height where it crosses 0.5, interpolated
    linearly: the definition of ``seawall sample --gauge``
    (:func:`seawall.postprocess.gauge_series`), so both read the same on the same frame. The
    line is evaluated from the top down to the crossing, through the compiled cell search.
    Where the line meets no fluid (a dry bed, or a film thinner than about a kernel's
    half-support) the gauge reads the elevation of the bed under it, :func:`bed_level`: the
    water depth, gauge minus bed, is then 0; NaN only where there is no wall under the line.

    Parameters
    ----------
    name : str
        Column name.
    x : float or (float, float)
        The horizontal position: x in 2D, the two horizontal coordinates (in axis order) in 3D [m].
    """

    unit = "m"

    def __init__(self, name: str, x: float | Sequence[float]) -> None:
        super().__init__(name)
        try:
            pos = np.atleast_1d(np.asarray(x, dtype=np.float64))
        except (TypeError, ValueError):
            pos = np.zeros(0)
        if pos.ndim != 1 or pos.size not in (1, 2) or not np.all(np.isfinite(pos)):
            raise ParameterError(f"gauge {name!r}: x must be 1 finite number (2D) or 2 (3D), got {x!r}")
        self.position = pos

    def attach(self, sim: Simulation) -> None:
        """Check the position's coordinates against the run (called by ``Simulation.add``)."""
        up, horizontal = gauge_vertical(sim.gravity, sim.dim)
        if self.position.size != len(horizontal):
            raise ParameterError(f"gauge {self.name!r}: needs {len(horizontal)} horizontal coordinate(s) in a "
                                 f"{sim.dim}D run, got {self.position.tolist()}")

    def sample(self, sim):
        fp = sim.fluid.particles
        cells = sim.fluid_cells
        up, horizontal = gauge_vertical(sim.gravity, sim.dim)
        gravity_up = float(np.asarray(sim.gravity)[up])
        dx = sim.fluid.spacing
        if cells is None and fp.n > 0:      # before the run's first step: the cells of the state as it is
            cells = sim.grid.build(fp["x"])
        if fp.n > 0:
            heights = gauge_heights(fp["x"][:, up], gravity_up, sim.kernel.support(sim.h), dx)
            pts = np.zeros((heights.size, 3))
            pts[:, horizontal] = self.position
            pts[:, up] = heights
            full = np.zeros(heights.size)
            g = sim.grid
            top = gauge_column(g.layout, pts, fp["x"], fp["m"] / fp["rho"], cells.start, cells.order, g.lo,
                               g.inv_cell, g.ncell, g.period, sim.physics, full)
            if top >= 0:
                return surface_crossing(heights, full, top)
        walls = [w.particles for w in sim.walls if w.n and "normal" in w.particles and "surface" in w.particles]
        if not walls:
            return float("nan")
        return bed_level(np.concatenate([w["x"] for w in walls]), np.concatenate([w["normal"] for w in walls]),
                         np.concatenate([w["surface"] for w in walls]), self.position, up, horizontal,
                         gravity_up, dx)


@njit(cache=True)
def crossed_mass(x_before, x_after, m, x0, y0, ex, ey):
    """Signed mass of the particles whose path crossed the section (x0, y0) + u (ex, ey), 0 <= u <= 1, in a step.

    A particle is on the positive side where s = (x - x0) ey - (y - y0) ex > 0 (the section's
    direction rotated clockwise by 90 degrees); it counts +m (-m) when its side changes to
    positive (negative) and the point where its straight path meets the line lies within the segment.
    """
    inv_len2 = 1.0 / (ex * ex + ey * ey)
    total = 0.0
    for i in range(x_after.shape[0]):
        s0 = (x_before[i, 0] - x0) * ey - (x_before[i, 1] - y0) * ex
        s1 = (x_after[i, 0] - x0) * ey - (x_after[i, 1] - y0) * ex
        before = s0 > 0.0
        after = s1 > 0.0
        if before == after:
            continue
        t = s0 / (s0 - s1)      # s0 != s1: the sides differ
        px = x_before[i, 0] + t * (x_after[i, 0] - x_before[i, 0])
        py = x_before[i, 1] + t * (x_after[i, 1] - x_before[i, 1])
        u = ((px - x0) * ex + (py - y0) * ey) * inv_len2
        if u < 0.0 or u > 1.0:
            continue
        total += m[i] if after else -m[i]
    return total


@njit(cache=True)
def crossed_mass_rectangle(x_before, x_after, m, axis, level, lo, hi):
    """Signed mass of the particles whose path crossed the rectangle x[axis] = level, lo <= x <= hi on
    the two other axes, in a step (3D): +m where the particle ends on the side x[axis] > level, -m on
    the other, counted when its side changes where its straight path meets the plane within the
    rectangle."""
    a = (axis + 1) % 3
    b = (axis + 2) % 3
    total = 0.0
    for i in range(x_after.shape[0]):
        s0 = x_before[i, axis] - level
        s1 = x_after[i, axis] - level
        before = s0 > 0.0
        after = s1 > 0.0
        if before == after:
            continue
        t = s0 / (s0 - s1)      # s0 != s1: the sides differ
        pa = x_before[i, a] + t * (x_after[i, a] - x_before[i, a])
        pb = x_before[i, b] + t * (x_after[i, b] - x_before[i, b])
        if pa < lo[a] or pa > hi[a] or pb < lo[b] or pb > hi[b]:
            continue
        total += m[i] if after else -m[i]
    return total


def _section_point(name, what, value):
    try:
        p = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        p = np.zeros(0)
    if p.shape not in ((2,), (3,)) or not np.all(np.isfinite(p)):
        raise ParameterError(f"discharge {name!r}: {what} must be 2 (x, y) or 3 (x, y, z) finite coordinates, "
                             f"got {value!r}")
    return p


def _rectangle_axis(name, start, end):
    """The axis a 3D section is normal to: the one coordinate its two corners share."""
    same = [k for k in range(3) if start[k] == end[k]]
    if len(same) != 1:
        raise ParameterError(f"discharge {name!r}: a 3D section is a rectangle normal to an axis: its corners "
                             f"{start.tolist()} and {end.tolist()} must share exactly one coordinate")
    return same[0]


class Discharge(Probe):
    """Fluid volume that has crossed a section since the start [m^3; m^2 per metre in 2D], counted every step.

    In 2D the section is the segment from ``start`` to ``end``: positive flow crosses towards the
    side obtained by rotating end - start clockwise by 90 degrees, so a section drawn bottom to
    top counts flow in +x as positive. In 3D it is the rectangle with opposite corners ``start``
    and ``end``, which share one coordinate (the axis it is normal to): x = 1 m, 0 <= y <= 0.5 m,
    0 <= z <= 0.4 m is ``start=(1, 0, 0), end=(1, 0.5, 0.4)``; positive flow goes along + that
    axis. At every step a
    fluid particle whose side of the section's line changes, where its straight path from its
    position before the step to the one after it meets the line within the segment, adds
    +-m / rho0 (rho0 the fluid's reference density): the count is of mass, so volume is conserved
    exactly. Particles are counted before the step's removals, so one that crosses and leaves the
    domain in the same step is counted; particles added by couplings (open boundaries) have not
    crossed. The count needs no per-particle state across steps: the positions are taken after
    the step's reordering and periodic wrap and compared after the integration, before any
    removal, so reordering, removal and wrapping never count as crossings.

    Adds the companion column ``<name>_rate`` (:class:`DischargeRate`): the discharge q
    [m^3/s; m^2/s per metre in 2D], the mean over the last probe interval. The cumulative
    count is part of checkpoints, so a restart continues bit for bit. Not decomposed (MPI runs
    refuse it).

    Parameters
    ----------
    name : str
        Column name (the rate is ``name + "_rate"``).
    start, end : sequence of float
        The section's end points (x, y) in 2D, its opposite corners (x, y, z) in 3D [m].
    crest, direction
        Instead of start and end: the section over the crest of this wall (:meth:`over_crest`).
    """

    unit = "m^3"
    unit_2d = "m^2"

    def __init__(self, name: str, start: Sequence[float] | None = None, end: Sequence[float] | None = None, *,
                 crest: str | None = None, direction: int = 1) -> None:
        super().__init__(name)
        self.crest = None
        self.direction = 1
        if crest is not None:
            if start is not None or end is not None:
                raise ParameterError(f"discharge {name!r}: give start and end, or a crest, not both")
            if not isinstance(crest, str) or not crest:
                raise ParameterError(f"discharge {name!r}: crest must be a wall name, got {crest!r}")
            if direction not in (1, -1) or isinstance(direction, bool):
                raise ParameterError(f"discharge {name!r}: direction must be 1 or -1, got {direction!r}")
            self.crest = crest
            self.direction = int(direction)
            self.start = self.end = None
            self.axis = None
        else:
            if start is None or end is None:
                raise ParameterError(f"discharge {name!r}: needs start and end (or a crest)")
            self._set_section(_section_point(name, "start", start), _section_point(name, "end", end))
        self.mass = 0.0          # signed mass that has crossed [kg (per metre in 2D)]
        self.rho0 = None
        self._before = None
        self._rate = DischargeRate(self)

    @classmethod
    def over_crest(cls, name: str, wall: str, direction: int = 1) -> Discharge:
        """A vertical section over the crest of wall system ``wall``, from its highest point up to the domain top.

        The section starts at the height of the wall's highest particles (fluid passes above
        them) and stands at the middle of that top row. Where the top row has separate parts (an
        open tank's two sides) it stands on the last part the flow meets going the positive way:
        the one farthest in +x for ``direction=1`` (default; positive flow in +x), the one
        farthest in -x for ``direction=-1`` (positive flow in -x).
        """
        return cls(name, crest=wall, direction=direction)

    def _set_section(self, start, end):
        if start.shape != end.shape:
            raise ParameterError(f"discharge {self.name!r}: start and end must have the same number of "
                                 f"coordinates, got {start.tolist()} and {end.tolist()}")
        if np.array_equal(start, end):
            raise ParameterError(f"discharge {self.name!r}: start and end are the same point {start.tolist()}")
        self.axis = _rectangle_axis(self.name, start, end) if start.shape == (3,) else None
        self.start = start
        self.end = end

    def companions(self):
        return (self._rate,)

    def attach(self, sim: Simulation) -> None:
        """Check the run and place a crest section (called by ``Simulation.add``)."""
        if not hasattr(sim, "fluid"):
            raise ParameterError(f"discharge {self.name!r}: the run has no fluid")
        if self.crest is not None and sim.dim != 2:
            raise ParameterError(f"discharge {self.name!r}: a crest section is a 2D segment; the run is {sim.dim}D "
                                 f"(give the corners of a rectangle, start and end)")
        self.rho0 = float(sim.fluid.rho0)
        if self.crest is None:
            if self.start.shape[0] != sim.dim:
                raise ParameterError(f"discharge {self.name!r}: the section has {self.start.shape[0]} coordinates, "
                                     f"the run is {sim.dim}D")
            return
        walls = {w.name: w for w in sim.walls}
        if self.crest not in walls:
            raise ParameterError(f"discharge {self.name!r}: no wall named {self.crest!r}; the walls: "
                                 + (", ".join(walls) or "none"))
        wall = walls[self.crest]
        x = wall.particles["x"]
        dx = wall.spacing
        top = float(x[:, 1].max())
        # the particles of the highest level (to a small fraction of the spacing), in runs along x
        level = np.sort(x[x[:, 1] >= top - 1e-6 * dx, 0])
        runs = np.split(level, np.flatnonzero(np.diff(level) > 1.5 * dx) + 1)
        # separate parts (an open tank's two sides): the last the flow meets, going the positive way
        run = runs[-1] if self.direction > 0 else runs[0]
        xc = 0.5 * float(run[0] + run[-1])
        ceiling = float(sim.grid.hi[1])
        if not ceiling > top:
            raise ParameterError(f"discharge {self.name!r}: wall {self.crest!r}'s crest y = {top:g} m is at the "
                                 f"domain top")
        ends = (np.array([xc, top]), np.array([xc, ceiling]))
        self._set_section(*(ends if self.direction > 0 else ends[::-1]))

    def describe(self):
        return {"start": self.start.tolist(), "end": self.end.tolist(), "crest": self.crest,
                "positive": "towards the side of (end - start) rotated clockwise by 90 degrees"}

    def before_step(self, sim):
        """Keep the positions the step starts from (after reordering and periodic wrap)."""
        if self.rho0 is None:       # added to a runner that does not attach probes: check it now
            self.attach(sim)
        x = sim.fluid.particles["x"]
        if self._before is None or self._before.shape != x.shape:
            self._before = np.empty_like(x)
        np.copyto(self._before, x)

    def after_step(self, sim):
        """Count the crossings of the step just integrated (before removals)."""
        fp = sim.fluid.particles
        x = fp["x"]
        if self._before is None or self._before.shape != x.shape:
            raise RuntimeError(f"discharge {self.name!r}: the fluid changed size within a step")
        if self.axis is not None:
            lo, hi = np.minimum(self.start, self.end), np.maximum(self.start, self.end)
            self.mass += crossed_mass_rectangle(self._before, x, fp["m"], self.axis, float(self.start[self.axis]),
                                                lo, hi)
            return
        (x0, y0), (x1, y1) = self.start, self.end
        self.mass += crossed_mass(self._before, x, fp["m"], x0, y0, x1 - x0, y1 - y0)

    def sample(self, sim):
        return self.mass / self.rho0

    def state(self):
        """The probe's part of a checkpoint."""
        return {"mass": self.mass}

    def set_state(self, state):
        self.mass = float(state["mass"])


class DischargeRate(Probe):
    """Discharge through a :class:`Discharge` section [m^3/s; m^2/s per metre in 2D], column ``<name>_rate``.

    The mean over the last probe interval, (V(t_k) - V(t_k-1)) / (t_k - t_k-1) from the
    cumulative volume's samples; NaN at the first sample (no interval before it). Added with
    its :class:`Discharge`; its values come from the probe history, which checkpoints keep.
    """

    unit = "m^3/s"
    unit_2d = "m^2/s"

    def __init__(self, parent: Discharge) -> None:
        super().__init__(parent.name + "_rate")
        self.parent = parent

    def sample(self, sim):
        if not sim.probe_times:
            return float("nan")
        k = sim.probes.index(self.parent)
        elapsed = sim.time - sim.probe_times[-1]
        if not elapsed > 0:
            return float("nan")
        return (self.parent.sample(sim) - sim.probe_values[-1][k]) / elapsed
