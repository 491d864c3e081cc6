"""2D walls outlined by polygons: seawalls, dikes, breakwater blocks, obstacles.

A 2D structure is given by its outline, a list of vertices (x, y):

* ``fluid="outside"`` -- a closed polygon (closed implicitly; a repeated first
  vertex at the end is dropped) whose inside is wall material: a block, a
  caisson, a breakwater. Every edge is a wall surface.
* ``fluid="inside"`` -- a closed polygon that holds the fluid: a container.
* ``fluid="left"`` / ``"right"`` -- an open polyline that traces the wall's
  exposed surface with the fluid on that side of the direction of travel: a
  seawall from its seaward toe up the slope, over the crest and down its back.
  The material is the polygon closed by the segment from the last vertex back
  to the first; that closing segment is no wall surface (it is where the wall
  stands on a floor or meets another wall), so no particle takes its surface
  point or normal there. An outline whose closing segment leaves the material
  on the fluid side is refused (reverse the points, or name the other side).

An edge that lies on a face of a given box (``junction``: a tank's interior)
is where the structure meets the tank's walls (a back face against the tank's
end wall, a foot on its floor): it is no wall surface either.

Particles follow the convention of :mod:`seawall.shapes` and
:func:`seawall.meshes.mesh_wall`, the 3D twin of this module: the fluid's
lattice ``origin + (i + 1/2) dx`` continued into the material, every lattice
point of the material closer than ``layers * dx`` to a wall surface is a wall
particle of layer ``floor(d / dx)``, with the closest surface point and the
unit normal from the particle towards it (into the fluid). A point as near to
two edges (on the bisector of a convex corner: the crest's edges) takes the
corner and the bisecting normal, as mesh walls do, so fluid in front of either
edge is never behind it. Near a concave corner (the toe, seen from the fluid)
the closest point is the vertex and the normal diagonal, as in a tank's
corners. Repulsive models (``layout = "surface"``) get one row on the exposed
edges at spacing dx / beta, vertices included, with the edge normals (their
bisector at a vertex).

A 2D outline is thus declared by its surface, crest and end faces included:
water landing on a crest or falling down the back of a wall meets a surface.
:func:`polygon_overlap` tells which fluid points a structure displaces.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import ParameterError, require_positive
from .resources import require_memory
from .shapes import Shape, _require_layers

__all__ = ["FLUID_SIDES", "polygon_wall", "polygon_overlap", "inside_polygon"]

#: what ``fluid`` may say of an outline (module doc)
FLUID_SIDES = ("outside", "inside", "left", "right")

# an irrational, tiny offset of the test lines (in units of the spacing), so that no lattice
# point's horizontal line passes through a vertex
_SHIFT = math.sqrt(3.0) - 1.0


def inside_polygon(positions, loop, scale):
    """Mask of the points inside the closed polygon ``loop`` ((M + 1, 2), first vertex repeated),
    by the non-zero winding number counted along horizontal lines shifted by 1e-6 ``scale``."""
    pos = np.asarray(positions, dtype=np.float64)
    y = pos[:, 1] + _SHIFT * 1e-6 * scale
    wind = np.zeros(pos.shape[0], dtype=np.int64)
    for a, b in zip(loop[:-1], loop[1:]):
        if a[1] == b[1]:
            continue
        up = a[1] < b[1]
        ylo, yhi = (a[1], b[1]) if up else (b[1], a[1])
        spans = np.flatnonzero((y >= ylo) & (y < yhi))
        xc = a[0] + (y[spans] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        right = xc > pos[spans, 0]
        wind[spans[right]] += 1 if up else -1
    return wind != 0


def _segments_cross(p, q, r, s):
    """Whether the closed segments pq and rs share a point (orientation test)."""
    def orient(a, b, c):
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return 0 if abs(v) <= 1e-12 * max(1.0, abs(b[0] - a[0]) + abs(b[1] - a[1])) ** 2 else (1 if v > 0 else -1)

    def on(a, b, c):
        return min(a[0], b[0]) - 1e-12 <= c[0] <= max(a[0], b[0]) + 1e-12 and \
            min(a[1], b[1]) - 1e-12 <= c[1] <= max(a[1], b[1]) + 1e-12

    o1, o2, o3, o4 = orient(p, q, r), orient(p, q, s), orient(r, s, p), orient(r, s, q)
    if o1 != o2 and o3 != o4:
        return True
    return ((o1 == 0 and on(p, q, r)) or (o2 == 0 and on(p, q, s)) or (o3 == 0 and on(r, s, p))
            or (o4 == 0 and on(r, s, q)))


class _Outline:
    """The checked outline: its loop, which edges are surfaces, and on which side the material is."""

    def __init__(self, points, fluid, label, junction=None):
        if fluid not in FLUID_SIDES:
            raise ParameterError(f"{label}: fluid must be one of {', '.join(FLUID_SIDES)}, got {fluid!r}")
        try:
            pts = np.array(points, dtype=np.float64)
        except (TypeError, ValueError):
            raise ParameterError(f"{label}: points must be a list of [x, y] pairs of numbers") from None
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
            raise ParameterError(f"{label}: points must be a list of at least 3 [x, y] pairs, got shape "
                                 f"{pts.shape}")
        if not np.all(np.isfinite(pts)):
            raise ParameterError(f"{label}: points must be finite numbers")
        if pts.shape[0] > 2 and np.all(pts[0] == pts[-1]):
            pts = pts[:-1]
        if pts.shape[0] < 3:
            raise ParameterError(f"{label}: points must outline an area: give at least 3 distinct vertices "
                                 "(a wall has a thickness: trace its front, crest and back)")
        seg = np.roll(pts, -1, axis=0) - pts
        length = np.linalg.norm(seg, axis=1)
        size = float(np.ptp(pts, axis=0).max())
        if np.any(length <= 1e-12 * size):
            k = int(np.argmin(length))
            raise ParameterError(f"{label}: points {k} and {(k + 1) % pts.shape[0]} coincide")
        m = pts.shape[0]
        for i in range(m):
            for j in range(i + 1, m):
                if j == i + 1 or (i == 0 and j == m - 1):
                    continue   # neighbours share a vertex
                if _segments_cross(pts[i], pts[(i + 1) % m], pts[j], pts[(j + 1) % m]):
                    raise ParameterError(f"{label}: the outline crosses itself (edges {i} and {j})")
        area = 0.5 * float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
        if abs(area) <= 1e-12 * size * size:
            raise ParameterError(f"{label}: the outline encloses no area (its points lie on one line)")
        if fluid in ("left", "right") and (area < 0.0) != (fluid == "left"):
            other = "right" if fluid == "left" else "left"
            raise ParameterError(
                f"{label}: with fluid = {fluid!r} the polygon closed from the last point back to the first "
                f"holds the fluid, not the wall: reverse the points or give fluid = {other!r}")
        self.points = pts
        self.loop = np.vstack([pts, pts[:1]])
        self.exposed = np.ones(m, dtype=bool)
        if fluid in ("left", "right"):
            self.exposed[-1] = False      # the closing segment
        if junction is not None:
            # an edge on a face of the box where other walls stand (a tank's floor or side) meets them
            jlo, jhi = (np.asarray(c, dtype=np.float64) for c in junction)
            tol = 1e-9 * max(size, 1e-300)
            for k in range(m):
                a, b = pts[k], pts[(k + 1) % m]
                for axis in range(2):
                    for level in (jlo[axis], jhi[axis]):
                        if np.isfinite(level) and abs(a[axis] - level) <= tol and abs(b[axis] - level) <= tol:
                            self.exposed[k] = False
        if not self.exposed.any():
            raise ParameterError(f"{label}: no edge of the outline is a wall surface (all meet other walls)")
        self.material_inside = fluid != "inside"
        # unit normal of each edge, out of the polygon (right of travel for a counter-clockwise loop)
        tang = seg / length[:, None]
        out = np.stack([tang[:, 1], -tang[:, 0]], axis=1) * (1.0 if area > 0 else -1.0)
        self.edge_normal = out if self.material_inside else -out   # into the fluid
        self.label = label
        self.size = size

    def material(self, pos, scale):
        inside = inside_polygon(pos, self.loop, scale)
        return inside if self.material_inside else ~inside

    def distance(self, pos):
        """Per point: distance to the nearest wall surface."""
        dmin = np.full(pos.shape[0], np.inf)
        for k in np.flatnonzero(self.exposed):
            a, b = self.loop[k], self.loop[k + 1]
            seg = b - a
            t = np.clip(((pos - a) @ seg) / float(seg @ seg), 0.0, 1.0)
            np.minimum(dmin, np.linalg.norm(pos - (a + t[:, None] * seg), axis=1), out=dmin)
        return dmin

    def closest(self, pos, tol):
        """Per point: distance to the nearest wall surface, its surface point (corners merged) and
        whether the point is closest to a vertex shared by two exposed edges."""
        n = pos.shape[0]
        dmin = np.full(n, np.inf)
        feet = []
        for k in np.flatnonzero(self.exposed):
            a, b = self.loop[k], self.loop[k + 1]
            seg = b - a
            t = np.clip(((pos - a) @ seg) / float(seg @ seg), 0.0, 1.0)
            foot = a + t[:, None] * seg
            d = np.linalg.norm(pos - foot, axis=1)
            feet.append((foot, d))
            np.minimum(dmin, d, out=dmin)
        first_u = np.zeros((n, 2))
        first_foot = np.zeros((n, 2))
        m_sum = np.zeros((n, 2))
        count = np.zeros(n, dtype=np.int64)
        for foot, d in feet:
            tie = d <= dmin + tol
            u = np.zeros_like(pos)
            u[tie] = (foot[tie] - pos[tie]) / np.maximum(dmin[tie], 1e-300)[:, None]
            new = tie & (count == 0)
            first_u[new] = u[new]
            first_foot[new] = foot[new]
            m_sum[new] = u[new]
            count[new] = 1
            other = tie & ~new & (np.linalg.norm(u - first_u, axis=1) > 1e-6)
            m_sum[other] += u[other]
            count[other] += 1
        m = m_sum / np.maximum(count, 1)[:, None]
        m2 = np.einsum("ij,ij->i", m, m)
        # a point as near to two edges (a convex corner's bisector) takes the corner: with m the
        # mean of the unit vectors towards the closest points, s = x + d m / |m|^2 (seawall.meshes);
        # edges nearly facing each other (a thin plate's midplane) keep the first edge's point
        bisect = (count > 1) & (m2 >= 0.25)
        surface = first_foot.copy()
        surface[bisect] = pos[bisect] + (dmin[bisect] / m2[bisect])[:, None] * m[bisect]
        return dmin, surface


def _lattice(lo, hi, dx, origin):
    """Index range (ilo, ihi) of the lattice points in [lo, hi], or None when it holds none."""
    ilo = np.ceil((lo - origin) / dx - 0.5).astype(np.int64)
    ihi = np.floor((hi - origin) / dx - 0.5).astype(np.int64)
    return None if np.any(ihi < ilo) else (ilo, ihi)


def _origin(origin):
    if origin is None:
        return np.zeros(2)
    o = np.asarray(origin, dtype=np.float64)
    if o.shape != (2,) or not np.all(np.isfinite(o)):
        raise ParameterError(f"origin must be 2 finite numbers, got {origin!r}")
    return o


def polygon_wall(points, dx, layers=3, *, fluid="outside", origin=None, layout="layers", beta=1.0,
                 junction=None, label="outline") -> Shape:
    """Wall particles of a 2D structure given by its outline (module doc).

    Parameters
    ----------
    points : sequence of [x, y]
        The outline's vertices [m] (at least 3; it must not cross itself).
    dx : float
        The fluid's particle spacing [m].
    layers : int
        Wall layers (``layout = "layers"``): every lattice point of the
        material closer than ``layers * dx`` to a wall surface.
    fluid : "outside", "inside", "left" or "right"
        Where the fluid is (module doc).
    origin : 2 floats, optional
        The lattice is ``origin + (i + 1/2) dx`` (default 0; a tank's ``lo``
        puts the structure on the tank's lattice).
    layout : "layers" or "surface"
        ``"surface"``: one row on the exposed edges at spacing dx / beta.
    beta : float
        Ratio dx / wall spacing of the surface row.
    junction : (lo, hi), optional
        A box (a tank's interior; +-inf for an open side) on whose faces the
        outline meets other walls: an edge lying on one of them is no wall
        surface, as the closing segment of an open outline is not.
    label : str
        Names the outline in error messages.

    Returns
    -------
    Shape
        Particles sorted by layer, with ``surface_points``, ``normals`` (into
        the fluid) and ``layer``.
    """
    dx = require_positive("dx", dx)
    outline = _Outline(points, fluid, label, junction)
    origin = _origin(origin)
    if layout == "surface":
        return _surface_row(outline, dx / require_positive("beta", beta))
    if layout != "layers":
        raise ParameterError(f"layout must be 'layers' or 'surface', got {layout!r}")
    layers = _require_layers(layers)
    band = layers * dx
    grow = band if not outline.material_inside else 0.0
    lattice = _lattice(outline.points.min(axis=0) - grow, outline.points.max(axis=0) + grow, dx, origin)
    if lattice is None:
        raise ParameterError(f"{label}: holds no lattice point at dx = {dx:g} m")
    ilo, ihi = lattice
    require_memory(f"the wall of {label} at dx = {dx:g} m", int(np.prod(ihi - ilo + 1)))
    axes = [origin[k] + (np.arange(ilo[k], ihi[k] + 1) + 0.5) * dx for k in range(2)]
    gx, gy = np.meshgrid(*axes, indexing="ij")
    pos = np.stack([gx.ravel(), gy.ravel()], axis=1)
    pos = pos[outline.material(pos, dx)]
    tol = 1e-9 * dx
    dist, surface = outline.closest(pos, tol)
    keep = (dist < band - tol) & (dist > tol)
    pos, surface, dist = pos[keep], surface[keep], dist[keep]
    if pos.shape[0] == 0:
        raise ParameterError(f"{label}: no wall particle at dx = {dx:g} m (the outline is thinner than the spacing)")
    layer = np.minimum(np.floor(dist / dx + 1e-9).astype(np.int64), layers - 1)
    order = np.argsort(layer, kind="stable")
    pos, surface, layer = pos[order], surface[order], layer[order]
    normals = surface - pos
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    return Shape(pos, dx, normals=normals, surface_points=surface, layer=layer)


def _surface_row(outline, spacing):
    pts, normals = [], []
    for k in np.flatnonzero(outline.exposed):
        a, b = outline.loop[k], outline.loop[k + 1]
        count = max(1, int(round(float(np.linalg.norm(b - a)) / spacing)))
        t = np.arange(count + 1) / count
        pts.append(a + t[:, None] * (b - a))
        normals.append(np.broadcast_to(outline.edge_normal[k], (count + 1, 2)))
    pos = np.concatenate(pts)
    nrm = np.concatenate(normals)
    # a vertex shared by two exposed edges is one particle with the bisecting normal
    keys = np.round(pos / (1e-6 * spacing)).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    summed = np.zeros((first.size, 2))
    np.add.at(summed, inverse, nrm)
    summed /= np.linalg.norm(summed, axis=1)[:, None]
    order = np.sort(first)
    pos = pos[order]
    nrm = summed[inverse[order]]
    return Shape(pos, spacing, normals=nrm, surface_points=pos.copy(), layer=np.zeros(pos.shape[0], dtype=np.int64))


def polygon_overlap(positions, points, *, fluid="outside", clearance=0.0, junction=None, label="outline"):
    """Mask of the points a structure displaces: inside its material, or closer than
    ``clearance`` [m] to one of its wall surfaces (the fluid's lattice keeps dx / 2 from a
    surface, as :func:`seawall.meshes.default_clearance` argues); ``junction`` as in :func:`polygon_wall`."""
    outline = _Outline(points, fluid, label, junction)
    pos = np.asarray(positions, dtype=np.float64)
    if pos.ndim != 2 or pos.shape[1] != 2:
        raise ParameterError(f"positions must be an (N, 2) array, got shape {pos.shape}")
    scale = max(outline.size, 1e-300)
    covered = outline.material(pos, scale)
    if clearance > 0.0 and pos.shape[0]:
        covered |= outline.distance(pos) < clearance * (1.0 - 1e-9)
    return covered
