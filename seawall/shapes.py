"""Geometry to particles: fluid blocks, discs/balls, tank walls and polyline walls.

Everything here is plain numpy and works in 2D and 3D (the last axis is the
vertical one).  Fluid shapes sit on a cell-centred lattice: a particle stands
for the square/cube of side ``dx`` around it, so a block ``[lo, hi]`` holds
particles at ``lo + (i + 0.5) dx``.  Tank walls continue that same lattice
outwards, which puts the first fluid particle 0.5 dx inside a wall surface and
the first wall layer 0.5 dx outside it.

Wall shapes carry, per particle, the closest point of the wall surface
(``surface_points``), the unit normal at that point oriented INTO the fluid
(``normals``, equal to ``(surface_point - position) / distance``) and the layer
index (0 next to the fluid).  The ghost/mirror point of a wall particle is
``2 * surface_points - positions``.

All lengths are in metres.  Bad input raises `seawall.errors.ParameterError`.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from seawall.errors import ParameterError, require_positive
from seawall.resources import require_memory

__all__ = [
    "Shape",
    "block",
    "rectangle",
    "box",
    "ball",
    "circle",
    "sphere",
    "tank",
    "tank_interior_lattice",
    "polyline_wall",
    "remove_overlap",
    "min_distance_between",
]

# Tolerance (in units of one lattice cell) used when counting cells in a
# length, so that 0.6 / 0.005 = 119.99999999999999 still gives 120 cells.
_CELL_TOL = 1e-9


# --------------------------------------------------------------------------
# Shape container
# --------------------------------------------------------------------------

def _optional_array(name, value, n, dim, dtype):
    """Convert an optional per-particle array and check its shape."""
    if value is None:
        return None
    arr = np.array(value, dtype=dtype)  # copy: the Shape owns its data
    want = (n,) if dim is None else (n, dim)
    if arr.shape != want:
        raise ParameterError(f"{name} must have shape {want}, got {arr.shape}")
    return arr


@dataclass(frozen=True, eq=False)
class Shape:
    """A set of particles produced from a geometry.

    Attributes
    ----------
    positions : ndarray (N, d) float64
        Particle positions [m], d = 2 or 3.
    spacing : float
        Lattice spacing dx [m] the particles were generated with.
    normals : ndarray (N, d) float64 or None
        Wall particles only: unit normal of the wall surface at the closest
        surface point, oriented into the fluid.
    surface_points : ndarray (N, d) float64 or None
        Wall particles only: closest point of the wall surface [m].  The
        mirror (ghost) point is ``2 * surface_points - positions``.
    layer : ndarray (N,) int64 or None
        Wall particles only: layer index, 0 next to the fluid.

    The constructor copies the arrays.  ``a + b`` concatenates two shapes of
    equal spacing and dimension; wall data must be present in both or none.
    """

    positions: np.ndarray
    spacing: float
    normals: np.ndarray | None = None
    surface_points: np.ndarray | None = None
    layer: np.ndarray | None = None

    def __post_init__(self):
        pos = np.array(self.positions, dtype=np.float64)
        if pos.ndim != 2 or pos.shape[1] not in (2, 3):
            raise ParameterError(
                f"positions must be an (N, 2) or (N, 3) array, got shape {pos.shape}")
        if not np.all(np.isfinite(pos)):
            raise ParameterError("positions must be finite numbers")
        n, dim = pos.shape
        spacing = require_positive("spacing", self.spacing)
        normals = _optional_array("normals", self.normals, n, dim, np.float64)
        surface = _optional_array("surface_points", self.surface_points, n, dim, np.float64)
        layer = _optional_array("layer", self.layer, n, None, np.int64)
        # frozen dataclass: assign the normalised copies through object.__setattr__
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "spacing", spacing)
        object.__setattr__(self, "normals", normals)
        object.__setattr__(self, "surface_points", surface)
        object.__setattr__(self, "layer", layer)

    @property
    def n(self) -> int:
        """Number of particles."""
        return int(self.positions.shape[0])

    @property
    def dim(self) -> int:
        """Spatial dimension (2 or 3)."""
        return int(self.positions.shape[1])

    @property
    def mirror_points(self) -> np.ndarray | None:
        """Mirror points ``2 * surface_points - positions`` [m], or None for fluid."""
        if self.surface_points is None:
            return None
        return 2.0 * self.surface_points - self.positions

    def __len__(self) -> int:
        return self.n

    def __add__(self, other):
        """Concatenate two shapes of equal spacing and dimension.

        Raises ParameterError when spacing or dimension differ, or when one
        shape has wall data (normals, surface_points, layer) and the other not.
        """
        if not isinstance(other, Shape):
            return NotImplemented
        if other.dim != self.dim:
            raise ParameterError(
                f"cannot add shapes of dimension {self.dim} and {other.dim}")
        if not math.isclose(self.spacing, other.spacing, rel_tol=1e-12, abs_tol=0.0):
            raise ParameterError(
                f"cannot add shapes of spacing {self.spacing} and {other.spacing}: "
                "spacing must be equal")
        merged = {}
        for name in ("normals", "surface_points", "layer"):
            a, b = getattr(self, name), getattr(other, name)
            if (a is None) != (b is None):
                raise ParameterError(
                    f"cannot add a shape with {name} to a shape without {name}")
            merged[name] = None if a is None else np.concatenate([a, b])
        return Shape(np.concatenate([self.positions, other.positions]),
                     self.spacing, **merged)

    def __radd__(self, other):
        # lets sum([s1, s2, ...]) work: sum starts from the integer 0
        if isinstance(other, int) and other == 0:
            return self
        return NotImplemented

    def subset(self, mask) -> "Shape":
        """Return a new Shape keeping only the particles selected by ``mask``.

        Parameters
        ----------
        mask : boolean array (N,) or integer index array
        """
        def pick(a):
            return None if a is None else a[mask]
        return Shape(self.positions[mask], self.spacing, pick(self.normals),
                     pick(self.surface_points), pick(self.layer))


# --------------------------------------------------------------------------
# Validation helpers
# --------------------------------------------------------------------------

def _vector(name, value, dims=(2, 3)):
    """Return ``value`` as a finite float64 vector whose length is in ``dims``."""
    allowed = " or ".join(str(d) for d in dims)
    try:
        v = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{name} must be a sequence of {allowed} finite numbers, got {value!r}") from None
    if v.ndim != 1 or v.shape[0] not in dims or not np.all(np.isfinite(v)):
        raise ParameterError(
            f"{name} must be a sequence of {allowed} finite numbers, got {value!r}")
    return v


def _box_corners(lo, hi, dims=(2, 3)):
    """Validate a box given by its lower and upper corners."""
    lo = _vector("lo", lo, dims)
    hi = _vector("hi", hi, dims)
    if lo.shape != hi.shape:
        raise ParameterError(
            f"lo and hi must have the same length, got {lo.shape[0]} and {hi.shape[0]}")
    if not np.all(hi > lo):
        raise ParameterError(f"hi must be greater than lo in every axis, got lo={lo.tolist()}, "
                             f"hi={hi.tolist()}")
    return lo, hi


def _require_layers(layers):
    """Validate the number of wall layers (a positive integer)."""
    if isinstance(layers, bool) or not isinstance(layers, (int, np.integer)) or layers < 1:
        raise ParameterError(f"layers must be a positive integer, got {layers!r}")
    return int(layers)


def _as_positions(name, value):
    """Accept a Shape or an (N, d) array and return an (N, d) float64 array."""
    if isinstance(value, Shape):
        return value.positions
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an (N, 2) or (N, 3) array of numbers") from None
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise ParameterError(
            f"{name} must be an (N, 2) or (N, 3) array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must contain finite numbers only")
    return arr


def _cell_count(length, dx):
    """Number of whole cells of size dx in ``length`` (robust to rounding)."""
    return int(math.floor(length / dx + _CELL_TOL))


# --------------------------------------------------------------------------
# Fluid shapes
# --------------------------------------------------------------------------

def block(lo, hi, dx) -> Shape:
    """Fill the box [lo, hi] with particles at the cell centres of a dx lattice.

    Parameters
    ----------
    lo, hi : sequence of 2 or 3 floats
        Lower and upper corner [m]; hi > lo in every axis.
    dx : float
        Particle spacing [m].

    Returns
    -------
    Shape
        Particles at ``lo + (i + 0.5) dx`` for i = 0 .. n_k - 1 in each axis k,
        with ``n_k = floor((hi_k - lo_k) / dx + 1e-9)`` (only whole cells fit,
        so a 0.6 x 0.3 box at dx = 0.005 has 120 x 60 particles).  The last
        axis varies fastest in the particle order.
    """
    lo, hi = _box_corners(lo, hi)
    dx = require_positive("dx", dx)
    counts = [_cell_count(h - l, dx) for l, h in zip(lo, hi)]
    for k, c in enumerate(counts):
        if c < 1:
            raise ParameterError(
                f"hi - lo must be at least dx in every axis, got {hi[k] - lo[k]!r} "
                f"along axis {k} with dx={dx!r}")
    require_memory(f"a block of particles at dx = {dx:g} m", math.prod(counts))
    axes = [l + (np.arange(c) + 0.5) * dx for l, c in zip(lo, counts)]
    grids = np.meshgrid(*axes, indexing="ij")
    return Shape(np.stack([g.ravel() for g in grids], axis=1), dx)


def rectangle(lo, hi, dx) -> Shape:
    """2D `block`: lo, hi are (x, y) corners [m], dx the spacing [m]."""
    _vector("lo", lo, (2,))
    _vector("hi", hi, (2,))
    return block(lo, hi, dx)


def box(lo, hi, dx) -> Shape:
    """3D `block`: lo, hi are (x, y, z) corners [m], dx the spacing [m]."""
    _vector("lo", lo, (3,))
    _vector("hi", hi, (3,))
    return block(lo, hi, dx)


def ball(center, radius, dx) -> Shape:
    """Particles of a lattice inside a disc (2D) or ball (3D).

    Parameters
    ----------
    center : sequence of 2 or 3 floats
        Centre [m].
    radius : float
        Radius [m].
    dx : float
        Particle spacing [m].

    Returns
    -------
    Shape
        Points ``center + (i + 0.5) dx`` (i integer in each axis) with
        distance to the centre <= radius.  The offsets from the centre are
        exactly antisymmetric, so the set is mirror symmetric about the
        centre in every axis (the lattice coincides with one aligned to
        ``center - radius + dx/2`` when radius is a multiple of dx).
    """
    center = _vector("center", center)
    radius = require_positive("radius", radius)
    dx = require_positive("dx", dx)
    m = int(math.ceil(radius / dx))
    require_memory(f"a ball of particles at dx = {dx:g} m", float(2 * m + 2) ** center.shape[0])
    # half-integer multiples of dx: negating them is exact in floating point,
    # and the inside test is done on the offsets, so symmetry is exact
    offs = (np.arange(-m - 1, m + 1) + 0.5) * dx
    grids = np.meshgrid(*([offs] * center.shape[0]), indexing="ij")
    rel = np.stack([g.ravel() for g in grids], axis=1)
    r2 = np.sum(rel * rel, axis=1)
    inside = r2 <= (radius * (1.0 + _CELL_TOL)) ** 2
    if not np.any(inside):
        raise ParameterError(
            f"radius must be large enough for at least one particle at dx={dx!r}, got {radius!r}")
    return Shape(center + rel[inside], dx)


def circle(center, radius, dx) -> Shape:
    """2D `ball`: center (x, y) [m], radius [m], spacing dx [m]."""
    _vector("center", center, (2,))
    return ball(center, radius, dx)


def sphere(center, radius, dx) -> Shape:
    """3D `ball`: center (x, y, z) [m], radius [m], spacing dx [m]."""
    _vector("center", center, (3,))
    return ball(center, radius, dx)


# --------------------------------------------------------------------------
# Tank walls
# --------------------------------------------------------------------------

def tank(lo, hi, dx, layers=3, open_top=True) -> Shape:
    """Wall particles around the interior box [lo, hi] (2D or 3D).

    The wall surfaces are the planes x_k = lo_k and x_k = hi_k of every axis
    k, except the top plane (last axis = vertical, x_last = hi_last) when
    ``open_top``.  Wall particles continue the fluid lattice
    ``lo + (i + 0.5) dx`` outwards; layer L lies (L + 0.5) dx outside a face.
    Corner/edge regions outside two or three faces are filled completely.
    With an open top the side walls span the interior's vertical cell centres
    (plus the bottom corner layers) and stop at the last whole cell below
    hi_last; they are ``2 * layers`` thick, and their top face (the **crest**)
    and back face are wall surfaces like the inner face
    (:func:`_open_tank_surfaces`): water that lands on the crest, goes over it
    and runs down the back of the wall meets a surface, not the far side of
    the inner face.

    Parameters
    ----------
    lo, hi : sequence of 2 or 3 floats
        Corners of the interior (fluid) box [m].  hi - lo must be a whole
        multiple of dx along every axis that has walls at both ends (all
        axes, or all but the vertical one when the top is open).
    dx : float
        Particle spacing [m].
    layers : int
        Number of wall layers (>= 1); an open tank's side walls get twice as many.
    open_top : bool
        If False a lid is added at x_last = hi_last.

    Returns
    -------
    Shape
        Wall particles, sorted by layer (layer 0 first), with
        ``surface_points`` = closest point of the existing wall surface
        (a face point, or the corner edge/vertex in corner regions),
        ``normals`` = (surface_point - position) / distance (into the tank;
        diagonal in corner regions) and ``layer`` = max over axes of the
        outward layer index.
    """
    lo, hi = _box_corners(lo, hi)
    dx = require_positive("dx", dx)
    layers = _require_layers(layers)
    if not isinstance(open_top, (bool, np.bool_)):
        raise ParameterError(f"open_top must be True or False, got {open_top!r}")
    d = lo.shape[0]

    # Per axis: lattice indices of the whole outer grid, their coordinate,
    # which side they are on (-1 below lo, 0 interior, +1 above hi), the
    # layer index outside the face (-1 inside) and the clamped surface coord.
    idx_axes, n_int = [], []
    for k in range(d):
        ratio = (hi[k] - lo[k]) / dx
        n = _cell_count(hi[k] - lo[k], dx)
        if n < 1:
            raise ParameterError(
                f"hi - lo must be at least dx in every axis, got {hi[k] - lo[k]!r} "
                f"along axis {k} with dx={dx!r}")
        open_axis = bool(open_top) and k == d - 1
        if not open_axis and abs(ratio - n) > _CELL_TOL:
            raise ParameterError(
                f"hi - lo must be a whole multiple of dx along axis {k} so that wall and "
                f"fluid share one lattice, got {ratio!r} cells")
        # an open tank's side walls are twice as thick: their back face is a surface too
        side = 2 * layers if open_top and k < d - 1 else layers
        top = n if open_axis else n + side
        idx_axes.append(range(-side, top))
        n_int.append(n)

    outer = math.prod(len(r) for r in idx_axes)
    require_memory(f"a tank wall at dx = {dx:g} m", outer - math.prod(n_int))
    idx_axes = [np.arange(r.start, r.stop) for r in idx_axes]

    # Enumerate the shell without building the (possibly huge) interior:
    # the piece where axis k is the FIRST axis outside the interior has
    # interior indices on axes < k, outside indices on axis k, anything after.
    pieces = []
    for k in range(d):
        parts = []
        for j in range(d):
            ij = idx_axes[j]
            if j < k:
                ij = ij[(ij >= 0) & (ij < n_int[j])]
            elif j == k:
                ij = ij[(ij < 0) | (ij >= n_int[j])]
            parts.append(ij)
        if any(p.size == 0 for p in parts):
            continue
        grids = np.meshgrid(*parts, indexing="ij")
        pieces.append(np.stack([g.ravel() for g in grids], axis=1))
    idx = np.concatenate(pieces, axis=0)

    pos = lo + (idx + 0.5) * dx
    n_arr = np.array(n_int)
    below = idx < 0
    above = idx >= n_arr
    # closest point of the closed box = clamp; with an open top no particle
    # lies above the top face, so the clamp never lands on the missing lid
    surface = np.where(below, lo, np.where(above, hi, pos))
    lay_axis = np.where(below, -idx - 1, np.where(above, idx - n_arr, -1))
    layer = lay_axis.max(axis=1)
    if open_top:
        _open_tank_surfaces(pos, surface, layer, below, lo, hi, n_int, layers, dx)
    diff = surface - pos
    dist = np.linalg.norm(diff, axis=1)
    normals = diff / dist[:, None]
    order = np.argsort(layer, kind="stable")
    return Shape(pos[order], dx, normals[order], surface[order], layer[order])


def _open_tank_surfaces(pos, surface, layer, below, lo, hi, n_int, layers, dx):
    """Surface points (in place) of an open tank's side walls: the inner face, the crest and the back face.

    Water that goes over an open tank's side wall lands on its top, the **crest** (the top of the
    walls' upper cells), and runs down its **back face**. Both are wall surfaces: a side-wall
    particle takes the nearest of inner face, crest and back face; one as near to two of them
    (on a convex edge's bisector) takes the edge, with the bisecting normal, as mesh walls do
    (seawall.meshes), so fluid in front of either face is never behind it. The walls are
    ``2 * layers`` thick, so each face has its ``layers`` and a particle that goes through a
    wall is still one support deep behind the face it entered by (seawall.health). The back
    face runs down past the floor to its underside; the particles under the interior keep the
    floor's surface.
    """
    d = pos.shape[1]
    side = np.any((pos[:, :-1] < lo[:-1]) | (pos[:, :-1] > hi[:-1]), axis=1)
    if not side.any():
        return
    p = pos[side]
    thick = 2 * layers * dx
    crest_level = lo[-1] + n_int[-1] * dx
    cands = [surface[side].copy()]                       # the inner face (or its vertical edge)
    crest = p.copy()
    crest[:, -1] = crest_level
    cands.append(crest)
    back = p.copy()                                      # the nearest face of the outer box, across gravity
    best = np.full(p.shape[0], np.inf)
    for k in range(d - 1):
        for level in (lo[k] - thick, hi[k] + thick):
            dist = np.abs(p[:, k] - level)
            nearer = dist < best
            back[nearer] = p[nearer]
            back[nearer, k] = level
            best = np.minimum(best, dist)
    cands.append(back)
    dists = np.stack([np.linalg.norm(c - p, axis=1) for c in cands])
    dmin = dists.min(axis=0)
    tie = dists <= dmin + _CELL_TOL * dx
    m = np.zeros_like(p)
    for c, t in zip(cands, tie):
        m[t] += (c[t] - p[t]) / dmin[t, None]
    m /= tie.sum(axis=0)[:, None]
    chosen = np.argmin(dists, axis=0)
    out = np.stack(cands)[chosen, np.arange(p.shape[0])]
    two = tie.sum(axis=0) > 1
    m2 = np.einsum("ij,ij->i", m[two], m[two])
    out[two] = p[two] + (dmin[two] / m2)[:, None] * m[two]
    surface[side] = out
    layer[side] = np.minimum(layer[side], np.floor(dmin / dx + 1e-9).astype(layer.dtype))


def tank_surface(lo, hi, spacing, open_top=True) -> Shape:
    """One layer of wall particles *on* the surface of the box [lo, hi] (2D or 3D).

    For repulsive-particle walls (Monaghan & Kajtar 2009; [TrixiBoundary]), whose
    particles sit on the wall line at a spacing ``spacing`` = dx / beta,
    smaller than the fluid's. Faces are the planes x_k = lo_k, hi_k except the
    top (last axis) when ``open_top``; each face is sampled with
    round(length / spacing) intervals, corners and edges once. ``normals``
    point into the box (diagonal at corners and edges) and ``surface_points``
    are the positions themselves.

    Parameters
    ----------
    lo, hi : sequence of 2 or 3 floats
        Corners of the interior box [m].
    spacing : float
        Distance between neighbouring wall particles [m].
    open_top : bool
        Leave out the top face.
    """
    lo, hi = _box_corners(lo, hi)
    spacing = require_positive("spacing", spacing)
    dim = lo.size
    counts = [max(1, int(round((hi[k] - lo[k]) / spacing))) + 1 for k in range(dim)]
    # the full grid is built and its faces kept
    require_memory(f"a wall surface at spacing {spacing:g} m", math.prod(counts))
    axes = [np.linspace(lo[k], hi[k], counts[k]) for k in range(dim)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    tol = 1e-9 * spacing
    on_face = np.zeros((grid.shape[0], dim, 2), dtype=bool)
    for k in range(dim):
        on_face[:, k, 0] = np.abs(grid[:, k] - lo[k]) < tol
        on_face[:, k, 1] = np.abs(grid[:, k] - hi[k]) < tol
    if open_top:
        on_face[:, dim - 1, 1] = False
    keep = on_face.reshape(grid.shape[0], -1).any(axis=1)
    pos = grid[keep]
    faces = on_face[keep]
    normals = np.zeros_like(pos)
    for k in range(dim):
        normals[:, k] += faces[:, k, 0].astype(float) - faces[:, k, 1].astype(float)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    return Shape(pos, spacing, normals=normals, surface_points=pos.copy(), layer=np.zeros(pos.shape[0], dtype=int))


def tank_interior_lattice(lo, hi, dx) -> Shape:
    """Fluid lattice filling [lo, hi]; same as `block`, shares the `tank` lattice.

    Parameters are the interior corners lo, hi [m] and spacing dx [m].
    """
    return block(lo, hi, dx)


# --------------------------------------------------------------------------
# Polyline walls (2D)
# --------------------------------------------------------------------------

def _closest_on_polyline(pos, pts):
    """Closest point on the polyline ``pts`` for each row of ``pos``.

    Loops over segments (few) to keep memory O(N).  Returns (points, dist).
    """
    best = np.empty_like(pos)
    best_d2 = np.full(pos.shape[0], np.inf)
    for a, b in zip(pts[:-1], pts[1:]):
        seg = b - a
        length2 = float(seg @ seg)
        t = np.clip(((pos - a) @ seg) / length2, 0.0, 1.0)
        foot = a + t[:, None] * seg
        d2 = np.sum((pos - foot) ** 2, axis=1)
        better = d2 < best_d2  # strict: the earlier segment wins ties
        best[better] = foot[better]
        best_d2[better] = d2[better]
    return best, np.sqrt(best_d2)


def polyline_wall(points, dx, layers=3, side="left") -> Shape:
    """Layered wall particles along an open 2D polyline.

    Parameters
    ----------
    points : array (M, 2), M >= 2
        Polyline vertices [m]; consecutive vertices must differ and the line
        must not fold back on itself (a 180 degree turn).
    dx : float
        Particle spacing [m].
    layers : int
        Number of wall layers (>= 1).
    side : "left" or "right"
        Side of the direction of travel where the wall material is; the fluid
        is on the other side.

    Returns
    -------
    Shape
        Per segment, particles at along-positions ``(j + 0.5) ds`` with
        ``ds = length / max(1, round(length / dx))`` (dx adjusted so the
        segment holds whole cells) and offsets ``(L + 0.5) dx`` on the wall
        side.  Where the wall is on the outside of a turn the wedge-shaped gap
        is filled with arcs of particles around the vertex (radius
        (L + 0.5) dx); where it is on the inside, each segment keeps only its
        side of the corner bisector and particles closer than 0.5 dx to an
        already placed one are dropped.  ``surface_points`` are the closest
        points on the polyline, ``normals`` point from the particle to them
        (into the fluid), ``layer`` is L.
    """
    try:
        pts = np.array(points, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError("points must be an (M, 2) array of numbers, M >= 2") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
        raise ParameterError(
            f"points must be an (M, 2) array with M >= 2, got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ParameterError("points must contain finite numbers only")
    dx = require_positive("dx", dx)
    layers = _require_layers(layers)
    if side not in ("left", "right"):
        raise ParameterError(f'side must be "left" or "right", got {side!r}')

    seg = np.diff(pts, axis=0)
    seg_len = np.linalg.norm(seg, axis=1)
    if np.any(seg_len <= 0.0):
        k = int(np.argmin(seg_len))
        raise ParameterError(
            f"points must not repeat consecutive vertices (segment {k} has zero length)")
    tang = seg / seg_len[:, None]
    sgn = 1.0 if side == "left" else -1.0
    wall_dir = sgn * np.stack([-tang[:, 1], tang[:, 0]], axis=1)  # into the wall material

    # classify interior vertices by the turn relative to the wall side
    n_vert = pts.shape[0]
    kind = [None] * n_vert
    turn = np.zeros(n_vert)
    for i in range(1, n_vert - 1):
        t0, t1 = tang[i - 1], tang[i]
        cross = t0[0] * t1[1] - t0[1] * t1[0]
        dot = float(t0 @ t1)
        turn[i] = math.atan2(cross, dot)
        if abs(turn[i]) > math.pi - 1e-6:
            raise ParameterError(
                f"points must not fold back on themselves (180 degree turn at vertex {i})")
        if cross * sgn < -1e-12:
            kind[i] = "gap"        # wall on the outside of the turn
        elif cross * sgn > 1e-12:
            kind[i] = "overlap"    # wall on the inside of the turn
        else:
            kind[i] = "straight"

    eps = 1e-9 * dx
    offsets = (np.arange(layers) + 0.5) * dx
    lay_ids = np.arange(layers)
    placed_pos = np.empty((0, 2))
    placed_lay = np.empty(0, dtype=np.int64)

    def add(batch_pos, batch_lay):
        nonlocal placed_pos, placed_lay
        if batch_pos.shape[0] == 0:
            return
        if placed_pos.shape[0] > 0:
            # drop particles that would crowd an already placed one
            near = _nearest_distances(batch_pos, placed_pos, 0.5 * dx)
            keep = near >= 0.5 * dx - eps
            batch_pos, batch_lay = batch_pos[keep], batch_lay[keep]
        placed_pos = np.concatenate([placed_pos, batch_pos])
        placed_lay = np.concatenate([placed_lay, batch_lay])

    for k in range(n_vert - 1):
        count = max(1, int(round(seg_len[k] / dx)))
        along = (np.arange(count) + 0.5) * (seg_len[k] / count)
        pos = (pts[k] + along[:, None, None] * tang[k]
               + offsets[None, :, None] * wall_dir[k]).reshape(-1, 2)
        lay = np.broadcast_to(lay_ids, (count, layers)).reshape(-1)
        keep = np.ones(pos.shape[0], dtype=bool)
        # inside a turn, split the overlapping corner along the bisector:
        # t_prev + t_next is the normal of the bisector line through the vertex
        if k > 0 and kind[k] == "overlap":
            keep &= (pos - pts[k]) @ (tang[k - 1] + tang[k]) >= -eps
        if k < n_vert - 2 and kind[k + 1] == "overlap":
            keep &= (pos - pts[k + 1]) @ (tang[k] + tang[k + 1]) <= eps
        add(pos[keep], lay[keep])

        v = k + 1
        if v < n_vert - 1 and kind[v] == "gap":
            # fill the wedge between the two segments' end normals with arcs
            theta = turn[v]
            w0 = wall_dir[k]
            arc_pos, arc_lay = [], []
            for L in range(layers):
                r = (L + 0.5) * dx
                m = int(round(r * abs(theta) / dx))
                if m == 0:
                    continue
                phi = (np.arange(m) + 0.5) / m * theta
                c, s = np.cos(phi), np.sin(phi)
                rot = np.stack([c * w0[0] - s * w0[1], s * w0[0] + c * w0[1]], axis=1)
                arc_pos.append(pts[v] + r * rot)
                arc_lay.append(np.full(m, L, dtype=np.int64))
            if arc_pos:
                add(np.concatenate(arc_pos), np.concatenate(arc_lay))

    surface, dist = _closest_on_polyline(placed_pos, pts)
    # a particle nearer to the line than the first layer sits in a place
    # another part of the wall claims (e.g. a narrow U): leave it out
    ok = dist >= 0.5 * dx - eps
    placed_pos, placed_lay, surface, dist = (
        placed_pos[ok], placed_lay[ok], surface[ok], dist[ok])
    normals = (surface - placed_pos) / dist[:, None]
    return Shape(placed_pos, dx, normals, surface, placed_lay)


# --------------------------------------------------------------------------
# Cell binning: overlap removal and minimum distance
# --------------------------------------------------------------------------

# Upper bound on candidate pairs materialised at once (memory ~ 40 B / pair).
_MAX_PAIRS = 2_000_000


def _nearest_distances(query, ref, cell):
    """Distance from each query point to its nearest ref point among neighbour cells.

    Ref points are sorted into square/cubic cells of side >= ``cell``; each
    query point looks at the 3^d cells around its own.  Every ref point
    closer than ``cell`` is therefore seen, so the result is exact wherever
    it is < ``cell``; larger values are upper bounds and ``inf`` means no ref
    point in the neighbour cells.  Memory stays O(N + M + _MAX_PAIRS).

    Parameters
    ----------
    query : (N, d) float array [m]
    ref : (M, d) float array [m]
    cell : float, cell side [m], > 0

    Returns
    -------
    (N,) float64 array of distances [m]
    """
    n, d = query.shape
    out = np.full(n, np.inf)
    if n == 0 or ref.shape[0] == 0:
        return out
    ref_min = ref.min(axis=0)
    extent = ref.max(axis=0) - ref_min
    # a little larger than asked so rounding in floor() cannot hide a pair;
    # coarser still if needed to keep the cell key inside int64
    h = float(cell) * (1.0 + 1e-8)
    max_cells = 2 ** (60 // d) - 4
    h = max(h, float(extent.max()) / max_cells)
    nb = (np.floor(extent / h).astype(np.int64) + 1)
    ref_cell = np.floor((ref - ref_min) / h).astype(np.int64)
    ref_cell = np.minimum(ref_cell, nb - 1)
    ref_key = np.ravel_multi_index(ref_cell.T, nb)
    order = np.argsort(ref_key, kind="stable")
    sorted_key = ref_key[order]
    # clip before the int cast so far-away query points cannot overflow
    q_cell = np.floor(np.clip((query - ref_min) / h, -2.0, nb + 1.0)).astype(np.int64)

    for off in itertools.product((-1, 0, 1), repeat=d):
        c = q_cell + np.array(off)
        valid = np.all((c >= 0) & (c < nb), axis=1)
        if not np.any(valid):
            continue
        qi = np.nonzero(valid)[0]
        key = np.ravel_multi_index(c[qi].T, nb)
        start = np.searchsorted(sorted_key, key, side="left")
        count = np.searchsorted(sorted_key, key, side="right") - start
        has = count > 0
        qi, start, count = qi[has], start[has], count[has]
        if qi.size == 0:
            continue
        # expand (query, ref) candidate pairs in chunks of bounded size
        csum = np.cumsum(count)
        lo_i = 0
        while lo_i < qi.size:
            base = csum[lo_i - 1] if lo_i > 0 else 0
            hi_i = int(np.searchsorted(csum, base + _MAX_PAIRS, side="right"))
            hi_i = max(hi_i, lo_i + 1)
            cnt = count[lo_i:hi_i]
            total = int(cnt.sum())
            pair_q = np.repeat(qi[lo_i:hi_i], cnt)
            first = np.repeat(start[lo_i:hi_i], cnt)
            run_start = np.repeat(np.cumsum(cnt) - cnt, cnt)
            pair_r = order[first + (np.arange(total) - run_start)]
            dist = np.sqrt(np.sum((query[pair_q] - ref[pair_r]) ** 2, axis=1))
            np.minimum.at(out, pair_q, dist)
            lo_i = hi_i
    return out


def remove_overlap(fluid, wall, min_distance) -> Shape:
    """Drop fluid particles closer than ``min_distance`` to any wall particle.

    Parameters
    ----------
    fluid : Shape
        Fluid particles.
    wall : Shape or array (M, d)
        Wall particles (positions) [m], same dimension as the fluid.
    min_distance : float
        Minimum allowed fluid-wall distance [m]; particles at exactly this
        distance are kept.

    Returns
    -------
    Shape
        The fluid shape without the overlapping particles (other per-particle
        arrays filtered alike).
    """
    if not isinstance(fluid, Shape):
        raise ParameterError(f"fluid must be a Shape, got {type(fluid).__name__}")
    wall_pos = _as_positions("wall", wall)
    min_distance = require_positive("min_distance", min_distance)
    if wall_pos.shape[0] and wall_pos.shape[1] != fluid.dim:
        raise ParameterError(
            f"wall must have the fluid's dimension {fluid.dim}, got {wall_pos.shape[1]}")
    near = _nearest_distances(fluid.positions, wall_pos, min_distance)
    return fluid.subset(near >= min_distance)


def min_distance_between(a_positions, b_positions) -> float:
    """Smallest distance between any point of a and any point of b.

    Uses cell binning with a growing cell size (no N x M arrays).

    Parameters
    ----------
    a_positions, b_positions : Shape or array (N, d), (M, d) [m]

    Returns
    -------
    float
        Minimum distance [m]; ``inf`` if either set is empty.
    """
    a = _as_positions("a_positions", a_positions)
    b = _as_positions("b_positions", b_positions)
    if a.shape[0] == 0 or b.shape[0] == 0:
        return math.inf
    if a.shape[1] != b.shape[1]:
        raise ParameterError(
            f"a_positions and b_positions must have the same dimension, "
            f"got {a.shape[1]} and {b.shape[1]}")
    # query the smaller set against the binned larger one
    if a.shape[0] > b.shape[0]:
        a, b = b, a
    d = a.shape[1]
    # upper bound: the nearest b to one a point; a cell of this size is
    # guaranteed to contain the closest pair
    upper = float(np.sqrt(np.min(np.sum((b - a[0]) ** 2, axis=1))))
    if upper == 0.0:
        return 0.0
    both_min = np.minimum(a.min(axis=0), b.min(axis=0))
    both_max = np.maximum(a.max(axis=0), b.max(axis=0))
    # start from the typical spacing of the combined set: few pairs per cell
    guess = float((both_max - both_min).max()) / (a.shape[0] + b.shape[0]) ** (1.0 / d)
    h = min(upper, guess) if guess > 0.0 else upper
    while True:
        best = float(np.min(_nearest_distances(a, b, h)))
        if best <= h:
            return best  # every pair closer than h was examined
        if h >= upper:
            return min(best, upper)  # cannot happen in exact arithmetic; never loop
        # the true minimum is <= best and <= upper: retry with that cell size
        h = min(best, upper) if math.isfinite(best) else min(4.0 * h, upper)
