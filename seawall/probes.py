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
* :class:`SurgeFront` -- largest coordinate of any fluid particle along an axis.
* :class:`KineticEnergy`, :class:`TotalMass`.
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


#: units that are per metre of depth in a 2D run
PER_DEPTH = ("N", "J", "kg")


def probe_unit(probe: Probe, dim: int) -> str:
    """The unit of ``probe``'s values in a ``dim``-D run: "N/m" for a 2D force (per metre of depth), ..."""
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
    """

    unit = "N"

    def __init__(self, name: str, wall: str, axis: int = 0) -> None:
        super().__init__(name)
        self.wall = str(wall)
        self.axis = int(axis)

    def sample(self, sim):
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
