"""Walls and fluid from triangle meshes (STL, OBJ) in 3D and closed polygons in 2D.

A mesh's faces are oriented by their vertex order (right-hand rule); the facet
normals an STL file also stores are ignored, as most mesh tools do. The
convention is that of :class:`seawall.shapes.Shape`: **a wall's face normals
point into the fluid**, so the wall material lies behind the faces. A closed
obstacle (a pillar) therefore has outward normals, a container (a tank) inward
ones; ``fluid="outside"`` / ``fluid="inside"`` says which is meant, and a mesh
wound the other way is refused as having inverted normals.

Wall particles (``layout = "layers"``) sit on the fluid's lattice
``origin + (i + 1/2) dx`` (the lattice of :func:`seawall.shapes.block` and
:func:`seawall.shapes.tank`): every lattice point behind the surface whose
distance d to it is below ``layers * dx`` is a wall particle of layer
``floor(d / dx)``, with the closest surface point and the normal towards it.
On a face aligned with the lattice this is exactly the tank's layering (layer L
at (L + 1/2) dx); at edges and corners the normals are diagonal, as the tank's.
Repulsive models (``layout = "surface"``) get one row on the surface: the
first layer of a lattice of spacing dx / beta behind the surface projected onto
it, plus a row along convex edges and corners.

Inside/behind is decided exactly from the closest surface feature with the
angle-weighted pseudonormal [Baerentzen2005]; closest points on triangles
follow [Ericson2005] sec. 5.1.5. Reading files needs the optional package
trimesh (``pip install seawall[geometry]``); everything else is numpy and
Numba, so meshes built from arrays (:func:`box_mesh`) work without it.

Every problem is one :class:`~seawall.errors.ParameterError` line naming the
file (or "mesh" for arrays) and the problem.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from .errors import ParameterError, require_positive
from .resources import require_memory
from .polygons import inside_polygon
from .shapes import Shape, _closest_on_polyline, _nearest_distances, _require_layers

__all__ = [
    "TriangleMesh",
    "load_mesh",
    "box_mesh",
    "write_stl",
    "mesh_wall",
    "mesh_wall_for_model",
    "fill_mesh",
    "fill_polygon",
    "check_fill_against_walls",
    "check_wall_junctions",
    "default_clearance",
    "EXTRA_HINT",
]

#: what to install when trimesh is missing
EXTRA_HINT = "pip install seawall[geometry]"
MESH_SUFFIXES = (".stl", ".obj")

# feature codes of a closest point on a triangle (a, b, c)
_FACE, _VA, _VB, _VC, _EAB, _EBC, _ECA = range(7)


# --------------------------------------------------------------------------
# Compiled geometry
# --------------------------------------------------------------------------

@njit(cache=True)
def _closest_point_triangle(p, a, b, c, out):
    """Closest point of triangle abc to p written to ``out``; returns its feature code.

    The Voronoi-region walk of [Ericson2005] sec. 5.1.5 (ClosestPtPointTriangle).
    """
    ab0, ab1, ab2 = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    ac0, ac1, ac2 = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    ap0, ap1, ap2 = p[0] - a[0], p[1] - a[1], p[2] - a[2]
    d1 = ab0 * ap0 + ab1 * ap1 + ab2 * ap2
    d2 = ac0 * ap0 + ac1 * ap1 + ac2 * ap2
    if d1 <= 0.0 and d2 <= 0.0:
        out[0], out[1], out[2] = a[0], a[1], a[2]
        return _VA
    bp0, bp1, bp2 = p[0] - b[0], p[1] - b[1], p[2] - b[2]
    d3 = ab0 * bp0 + ab1 * bp1 + ab2 * bp2
    d4 = ac0 * bp0 + ac1 * bp1 + ac2 * bp2
    if d3 >= 0.0 and d4 <= d3:
        out[0], out[1], out[2] = b[0], b[1], b[2]
        return _VB
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = d1 / (d1 - d3)
        out[0], out[1], out[2] = a[0] + v * ab0, a[1] + v * ab1, a[2] + v * ab2
        return _EAB
    cp0, cp1, cp2 = p[0] - c[0], p[1] - c[1], p[2] - c[2]
    d5 = ab0 * cp0 + ab1 * cp1 + ab2 * cp2
    d6 = ac0 * cp0 + ac1 * cp1 + ac2 * cp2
    if d6 >= 0.0 and d5 <= d6:
        out[0], out[1], out[2] = c[0], c[1], c[2]
        return _VC
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        out[0], out[1], out[2] = a[0] + w * ac0, a[1] + w * ac1, a[2] + w * ac2
        return _ECA
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        out[0] = b[0] + w * (c[0] - b[0])
        out[1] = b[1] + w * (c[1] - b[1])
        out[2] = b[2] + w * (c[2] - b[2])
        return _EBC
    denom = 1.0 / (va + vb + vc)
    v = vb * denom
    w = vc * denom
    out[0] = a[0] + ab0 * v + ac0 * w
    out[1] = a[1] + ab1 * v + ac1 * w
    out[2] = a[2] + ab2 * v + ac2 * w
    return _FACE


@njit(cache=True)
def _band_pairs(vertices, faces, origin, dx, band, fill, idx, tri, dist, feat, foot):
    """(lattice point, triangle) pairs closer than ``band``: count them, or write them when ``fill``.

    The lattice is ``origin + (i + 1/2) dx``; each triangle visits the lattice
    points of its bounding box grown by ``band``, so the cost is linear in the
    number of points near the surface.
    """
    n = 0
    p = np.empty(3)
    q = np.empty(3)
    lo = np.empty(3, dtype=np.int64)
    hi = np.empty(3, dtype=np.int64)
    for t in range(faces.shape[0]):
        a = vertices[faces[t, 0]]
        b = vertices[faces[t, 1]]
        c = vertices[faces[t, 2]]
        for k in range(3):
            mn = min(a[k], b[k], c[k]) - band
            mx = max(a[k], b[k], c[k]) + band
            lo[k] = int(math.ceil((mn - origin[k]) / dx - 0.5))
            hi[k] = int(math.floor((mx - origin[k]) / dx - 0.5))
        for i in range(lo[0], hi[0] + 1):
            p[0] = origin[0] + (i + 0.5) * dx
            for j in range(lo[1], hi[1] + 1):
                p[1] = origin[1] + (j + 0.5) * dx
                for k in range(lo[2], hi[2] + 1):
                    p[2] = origin[2] + (k + 0.5) * dx
                    f = _closest_point_triangle(p, a, b, c, q)
                    d = math.sqrt((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 + (p[2] - q[2]) ** 2)
                    if d < band:
                        if fill:
                            idx[n, 0], idx[n, 1], idx[n, 2] = i, j, k
                            tri[n] = t
                            dist[n] = d
                            feat[n] = f
                            foot[n, 0], foot[n, 1], foot[n, 2] = q[0], q[1], q[2]
                        n += 1
    return n


@njit(cache=True)
def _column_crossings(vertices, faces, normals, origin, dx, shift, i0, j0, ni, nj, fill, col, z, sign):
    """Crossings of the vertical lines through the lattice columns with the faces.

    Column (i, j) is the line x = origin + (i + 1/2) dx + shift (same in y);
    ``shift`` is a tiny irrational offset so that no line passes exactly
    through an edge or vertex of a mesh built on round numbers (such a line
    would be counted twice or never). Returns the number of crossings and,
    when ``fill``, writes the column number, the height and the sign of the
    face normal's z component.
    """
    n = 0
    for t in range(faces.shape[0]):
        nz = normals[t, 2]
        if nz == 0.0:
            continue   # a vertical face is never crossed by a vertical line
        a = vertices[faces[t, 0]]
        b = vertices[faces[t, 1]]
        c = vertices[faces[t, 2]]
        ilo = max(i0, int(math.ceil((min(a[0], b[0], c[0]) - origin[0] - shift[0]) / dx - 0.5)))
        ihi = min(i0 + ni - 1, int(math.floor((max(a[0], b[0], c[0]) - origin[0] - shift[0]) / dx - 0.5)))
        jlo = max(j0, int(math.ceil((min(a[1], b[1], c[1]) - origin[1] - shift[1]) / dx - 0.5)))
        jhi = min(j0 + nj - 1, int(math.floor((max(a[1], b[1], c[1]) - origin[1] - shift[1]) / dx - 0.5)))
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if det == 0.0:
            continue
        for i in range(ilo, ihi + 1):
            x = origin[0] + (i + 0.5) * dx + shift[0]
            for j in range(jlo, jhi + 1):
                y = origin[1] + (j + 0.5) * dx + shift[1]
                # barycentric coordinates of (x, y) in the projected triangle
                l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det
                l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det
                l0 = 1.0 - l1 - l2
                if l0 < 0.0 or l1 < 0.0 or l2 < 0.0:
                    continue
                if fill:
                    col[n] = (i - i0) * nj + (j - j0)
                    z[n] = l0 * a[2] + l1 * b[2] + l2 * c[2]
                    sign[n] = 1 if nz > 0.0 else -1
                n += 1
    return n


@njit(cache=True)
def _winding_numbers(start, z, sign, ncol, z0, dx, nk):
    """Winding number of every lattice point of every column: the sum of the signs of the
    crossings above it (a closed surface wound outwards gives 1 inside, 0 outside)."""
    w = np.zeros((ncol, nk), dtype=np.int32)
    for c in range(ncol):
        for m in range(start[c], start[c + 1]):
            top = int(math.floor((z[m] - z0) / dx - 0.5))   # lattice points below crossing m
            for k in range(min(top, nk - 1), -1, -1):
                w[c, k] += sign[m]
    return w


# --------------------------------------------------------------------------
# The mesh and its checks
# --------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class TriangleMesh:
    """A triangle surface in 3D: ``vertices`` (V, 3) [m], ``faces`` (F, 3) vertex indices.

    ``label`` names it in messages ("mesh file tank.stl"). Faces of zero area
    are dropped. The constructor checks the surface: every edge shared by at
    most two faces, and consistently oriented (each shared edge run once in
    each direction); :attr:`watertight` says whether every edge is shared.
    """

    vertices: np.ndarray
    faces: np.ndarray
    label: str = "mesh"
    _edges: dict = field(default=None, repr=False)

    def __post_init__(self):
        label = self.label
        try:
            v = np.array(self.vertices, dtype=np.float64)
            f = np.array(self.faces, dtype=np.int64)
        except (TypeError, ValueError):
            raise ParameterError(f"{label}: vertices and faces must be numeric arrays") from None
        if v.ndim != 2 or v.shape[1] != 3 or not np.all(np.isfinite(v)):
            raise ParameterError(f"{label}: vertices must be an (V, 3) array of finite numbers, got shape {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3 or f.shape[0] == 0:
            raise ParameterError(f"{label}: has no triangles (faces must be an (F, 3) array, got shape {f.shape})")
        if f.min() < 0 or f.max() >= v.shape[0]:
            raise ParameterError(f"{label}: a face refers to a vertex that does not exist")
        area2 = np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
        scale = float(np.ptp(v, axis=0).max()) if v.shape[0] else 0.0
        keep = area2 > 1e-14 * scale ** 2
        if not np.any(keep):
            raise ParameterError(f"{label}: every triangle has zero area")
        f = f[keep]
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "faces", f)
        object.__setattr__(self, "_edges", self._edge_structure())

    # -- topology ---------------------------------------------------------
    def _edge_structure(self):
        f = self.faces
        directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])   # edge k of face t at k*F + t
        und = np.sort(directed, axis=1)
        keys, inverse, counts = np.unique(und, axis=0, return_inverse=True, return_counts=True)
        inverse = inverse.reshape(-1)
        if np.any(counts > 2):
            e = keys[np.argmax(counts)]
            raise ParameterError(f"{self.label}: not a surface: an edge (vertices {e[0]}, {e[1]}) is shared by "
                                 f"{counts.max()} faces (at most 2 allowed)")
        # consistent winding: a shared edge is run a->b by one face and b->a by the other
        forward = directed[:, 0] < directed[:, 1]
        fwd_count = np.bincount(inverse, weights=forward.astype(float), minlength=keys.shape[0])
        shared = counts == 2
        bad = shared & (fwd_count != 1)
        if np.any(bad):
            raise ParameterError(f"{self.label}: faces are not consistently oriented: {int(bad.sum())} shared edges "
                                 "are run in the same direction by both faces (fix the winding, e.g. "
                                 "trimesh's fix_normals)")
        return {"inverse": inverse, "counts": counts, "keys": keys}

    @property
    def watertight(self) -> bool:
        """Every edge shared by exactly two faces (the surface encloses a volume)."""
        return bool(np.all(self._edges["counts"] == 2))

    @property
    def n_open_edges(self) -> int:
        return int(np.sum(self._edges["counts"] == 1))

    @property
    def face_normals(self) -> np.ndarray:
        v, f = self.vertices, self.faces
        n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
        return n / np.linalg.norm(n, axis=1)[:, None]

    @property
    def signed_volume(self) -> float:
        """Sum of the signed volumes of the cones from the bounding-box centre to the faces [m^3].

        For a closed mesh this is its volume, positive when the normals point
        out; for an open one (a tank without its lid) its sign still tells the
        orientation when the surface is seen from inside around that centre.
        """
        v, f = self.vertices, self.faces
        centre = 0.5 * (v.min(axis=0) + v.max(axis=0))
        a, b, c = v[f[:, 0]] - centre, v[f[:, 1]] - centre, v[f[:, 2]] - centre
        return float(np.sum(np.einsum("ij,ij->i", a, np.cross(b, c))) / 6.0)

    @property
    def bounds(self):
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def require_closed(self, purpose):
        """ParameterError unless watertight; ``purpose`` says what needed it."""
        if not self.watertight:
            raise ParameterError(f"{self.label}: not watertight ({self.n_open_edges} open edges); {purpose} "
                                 "needs a closed surface")

    def require_orientation(self, fluid):
        """ParameterError (inverted normals) unless the faces point into the fluid side."""
        vol = self.signed_volume
        want = 1.0 if fluid == "outside" else -1.0
        if vol * want <= 0.0:
            into = "into the solid" if fluid == "outside" else "out of the container"
            should = ("out of the obstacle" if fluid == "outside" else "into the container")
            raise ParameterError(f"{self.label}: inverted normals: the faces' vertex order makes the normals point "
                                 f"{into} (signed volume {vol:.4g} m^3); with fluid = '{fluid}' they must point "
                                 f"{should}, towards the fluid")

    # -- pseudonormals for the inside test ----------------------------------
    def _feature_normals(self):
        """Per face the normals of its 7 features (face, 3 vertices, 3 edges) and whether each
        lies on the open rim: the angle-weighted pseudonormals of [Baerentzen2005] eq. 3-4."""
        v, f = self.vertices, self.faces
        nf = self.face_normals
        nface = f.shape[0]
        vert_n = np.zeros_like(v)
        for k in range(3):
            e1 = v[f[:, (k + 1) % 3]] - v[f[:, k]]
            e2 = v[f[:, (k + 2) % 3]] - v[f[:, k]]
            cosang = np.einsum("ij,ij->i", e1, e2) / (np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1))
            angle = np.arccos(np.clip(cosang, -1.0, 1.0))
            np.add.at(vert_n, f[:, k], angle[:, None] * nf)
        inv = self._edges["inverse"]
        edge_n = np.zeros((self._edges["keys"].shape[0], 3))
        np.add.at(edge_n, inv, np.tile(nf, (3, 1)))
        open_edge = self._edges["counts"] == 1
        open_vertex = np.zeros(v.shape[0], dtype=bool)
        open_vertex[self._edges["keys"][open_edge].ravel()] = True
        normals = np.empty((nface, 7, 3))
        rim = np.zeros((nface, 7), dtype=bool)
        normals[:, _FACE] = nf
        for k, code in enumerate((_VA, _VB, _VC)):
            normals[:, code] = vert_n[f[:, k]]
            rim[:, code] = open_vertex[f[:, k]]
        # directed edge k of face t (ab, bc, ca) is row k * F + t of the edge list
        for k, code in enumerate((_EAB, _EBC, _ECA)):
            rows = inv[k * nface:(k + 1) * nface]
            normals[:, code] = edge_n[rows]
            rim[:, code] = open_edge[rows]
        return normals, rim

    def nearest_in_band(self, dx, band, origin, *, ties=False):
        """For every lattice point closer than ``band`` to the surface: its lattice index (n, 3),
        position, closest surface point, distance, the signed side (> 0 in front of the faces,
        < 0 behind them, 0 beyond the open rim) and the closest feature's code (face, vertex or
        edge). One compiled pass, cost linear in the band. ``ties``: every closest point of a
        lattice point equidistant from several faces (one row per point otherwise)."""
        origin = np.asarray(origin, dtype=np.float64)
        fill_args = (np.empty((0, 3), np.int64), np.empty(0, np.int64), np.empty(0), np.empty(0, np.int64),
                     np.empty((0, 3)))
        count = _band_pairs(self.vertices, self.faces, origin, dx, band, False, *fill_args)
        require_memory(f"the wall band of {self.label} at dx = {dx:g} m", count)
        idx = np.empty((count, 3), np.int64)
        tri = np.empty(count, np.int64)
        dist = np.empty(count)
        feat = np.empty(count, np.int64)
        foot = np.empty((count, 3))
        _band_pairs(self.vertices, self.faces, origin, dx, band, True, idx, tri, dist, feat, foot)
        # the nearest triangle of every lattice point (ties: any of them, the pseudonormal agrees)
        order = np.lexsort((dist, idx[:, 2], idx[:, 1], idx[:, 0]))
        idx, tri, dist, feat, foot = idx[order], tri[order], dist[order], feat[order], foot[order]
        first = np.ones(count, dtype=bool)
        first[1:] = np.any(idx[1:] != idx[:-1], axis=1)
        if ties:
            group = np.cumsum(first) - 1
            keep = dist <= dist[first][group] + 1e-9 * dx
        else:
            keep = first
        idx, tri, dist, feat, foot = idx[keep], tri[keep], dist[keep], feat[keep], foot[keep]
        pos = origin + (idx + 0.5) * dx
        normals, rim = self._feature_normals()
        side = np.einsum("ij,ij->i", pos - foot, normals[tri, feat]) if count else np.empty(0)
        side[rim[tri, feat]] = 0.0     # beyond an open edge: neither in front nor behind
        return idx, pos, foot, dist, side, feat


def _require_trimesh(label):
    try:
        import trimesh   # noqa: F401
    except ImportError:
        raise ParameterError(f"{label}: reading STL/OBJ files needs the optional package trimesh: "
                             f"{EXTRA_HINT}") from None
    return trimesh


def load_mesh(path, *, scale=1.0, offset=None) -> TriangleMesh:
    """Read an STL or OBJ file (through trimesh) into a checked :class:`TriangleMesh`.

    ``scale`` multiplies the coordinates (e.g. 0.001 for a file in mm), then
    ``offset`` [m] is added. Duplicate vertices are merged (an STL stores each
    triangle's corners separately), nothing else is repaired.
    """
    path = os.fspath(path)
    label = f"mesh file {path}"
    if not path.lower().endswith(MESH_SUFFIXES):
        raise ParameterError(f"{label}: must be an .stl or .obj file")
    if not os.path.isfile(path):
        raise ParameterError(f"{label}: no such file")
    trimesh = _require_trimesh(label)
    scale = require_positive("scale", scale)
    try:
        mesh = trimesh.load(path, force="mesh", process=True)
    except Exception as exc:   # trimesh raises many kinds on a bad file
        raise ParameterError(f"{label}: cannot be read as a mesh ({type(exc).__name__}: {exc})") from None
    vertices = np.asarray(getattr(mesh, "vertices", np.empty((0, 3))), dtype=np.float64)
    faces = np.asarray(getattr(mesh, "faces", np.empty((0, 3))), dtype=np.int64)
    if faces.size == 0:
        raise ParameterError(f"{label}: has no triangles")
    vertices = vertices * scale
    if offset is not None:
        off = np.asarray(offset, dtype=np.float64)
        if off.shape != (3,) or not np.all(np.isfinite(off)):
            raise ParameterError(f"offset must be 3 finite numbers, got {offset!r}")
        vertices = vertices + off
    return TriangleMesh(vertices, faces, label)


def _as_mesh(mesh) -> TriangleMesh:
    if isinstance(mesh, TriangleMesh):
        return mesh
    if isinstance(mesh, (str, os.PathLike)):
        return load_mesh(mesh)
    raise ParameterError(f"mesh must be a file path or a seawall.meshes.TriangleMesh, got {type(mesh).__name__}")


# --------------------------------------------------------------------------
# Building meshes (tests, examples) and writing STL without trimesh
# --------------------------------------------------------------------------

def box_mesh(lo, hi, *, inward=False, open_top=False, open_bottom=False, label="mesh") -> TriangleMesh:
    """The 12 triangles of the box [lo, hi] (2 fewer for each of ``open_top``, ``open_bottom``);
    normals outward, or inward."""
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    if lo.shape != (3,) or hi.shape != (3,) or not np.all(hi > lo):
        raise ParameterError(f"box_mesh needs 3D corners with hi > lo, got lo={lo.tolist()}, hi={hi.tolist()}")
    corners = np.array([[hi[k] if (n >> k) & 1 else lo[k] for k in range(3)] for n in range(8)])
    # each face as a quad of corner numbers (bit k set = hi along axis k), counter-clockwise from outside
    quads = {"x-": (0, 4, 6, 2), "x+": (1, 3, 7, 5), "y-": (0, 1, 5, 4), "y+": (2, 6, 7, 3),
             "z-": (0, 2, 3, 1), "z+": (4, 5, 7, 6)}
    faces = []
    for name, (a, b, c, d) in quads.items():
        if (open_top and name == "z+") or (open_bottom and name == "z-"):
            continue
        faces += [(a, b, c), (a, c, d)]
    faces = np.array(faces)
    if inward:
        faces = faces[:, ::-1]
    return TriangleMesh(corners, faces, label)


def write_stl(path, mesh: TriangleMesh, name="seawall"):
    """Write ``mesh`` as an ASCII STL file (facet normals from the winding)."""
    v, f = mesh.vertices, mesh.faces
    normals = mesh.face_normals
    lines = [f"solid {name}"]
    for t in range(f.shape[0]):
        lines.append("  facet normal {:.9g} {:.9g} {:.9g}".format(*normals[t]))
        lines.append("    outer loop")
        for k in range(3):
            lines.append("      vertex {:.9g} {:.9g} {:.9g}".format(*v[f[t, k]]))
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    with open(path, "w", encoding="ascii") as fh:
        fh.write("\n".join(lines) + "\n")
    return os.fspath(path)


# --------------------------------------------------------------------------
# Walls
# --------------------------------------------------------------------------

def _require_fluid_side(fluid):
    if fluid not in ("outside", "inside"):
        raise ParameterError(f"fluid must be 'outside' (an obstacle) or 'inside' (a container), got {fluid!r}")
    return fluid


def _origin(origin, dim):
    if origin is None:
        return np.zeros(dim)
    o = np.asarray(origin, dtype=np.float64)
    if o.shape != (dim,) or not np.all(np.isfinite(o)):
        raise ParameterError(f"origin must be {dim} finite numbers, got {origin!r}")
    return o


def mesh_wall(mesh, dx, layers=3, *, fluid="outside", origin=None, layout="layers", beta=1.0) -> Shape:
    """Wall particles of a mesh (a path to an STL/OBJ file or a :class:`TriangleMesh`).

    Parameters
    ----------
    mesh : path or TriangleMesh
    dx : float
        The fluid's particle spacing [m].
    layers : int
        Wall layers for ``layout = "layers"``: every lattice point behind the
        surface closer than ``layers * dx`` to it (layer ``floor(d / dx)``).
    fluid : "outside" or "inside"
        An obstacle (normals point out of it) or a container (normals point
        into it); a mesh wound the other way is refused (inverted normals).
    origin : 3 floats, optional
        The lattice is ``origin + (i + 1/2) dx`` (default 0, the lattice of
        :func:`seawall.shapes.block` for blocks starting at whole multiples of dx).
    layout : "layers" or "surface"
        ``"surface"``: one row on the surface at spacing dx / beta (repulsive models).
    beta : float
        Ratio dx / wall spacing of the surface row.

    Returns
    -------
    Shape
        Particles sorted by layer, with ``surface_points`` (closest surface
        point), ``normals`` (unit, from the particle towards that point, into
        the fluid; for the surface row the direction of its lattice point's
        offset) and ``layer``.
    """
    mesh = _as_mesh(mesh)
    dx = require_positive("dx", dx)
    layers = _require_layers(layers)
    _require_fluid_side(fluid)
    mesh.require_orientation(fluid)
    origin = _origin(origin, 3)
    if layout == "surface":
        spacing = dx / require_positive("beta", beta)
        # the first layer of a lattice of spacing dx / beta, projected onto the surface (onto every
        # face a point is equally near to); at convex edges and corners, where that layer thins out,
        # the lattice points in front whose closest point is the edge or corner add its row
        _, pos, foot, dist, side, feat = mesh.nearest_in_band(spacing, spacing, origin, ties=True)
        tol = 1e-9 * spacing
        behind = (side < 0.0) & (dist > tol)
        edge_row = (side > 0.0) & (feat != _FACE) & (dist > tol)
        keep = behind | edge_row
        pos, foot, dist, behind = pos[keep], foot[keep], dist[keep], behind[keep]
        normals = np.where(behind[:, None], foot - pos, pos - foot) / dist[:, None]
        # one particle per surface point (a corner is reached from several lattice points)
        _, first = np.unique(np.round(foot / (1e-6 * spacing)).astype(np.int64), axis=0, return_index=True)
        first = np.sort(first)
        foot, normals = foot[first], normals[first]
        shape = Shape(foot, spacing, normals=normals, surface_points=foot.copy(),
                      layer=np.zeros(foot.shape[0], dtype=np.int64))
    elif layout == "layers":
        idx, pos, foot, dist, side, _ = mesh.nearest_in_band(dx, layers * dx, origin, ties=True)
        pos, foot, dist, side = _merge_ties(idx, pos, foot, dist, side)
        keep = (side < 0.0) & (dist > 1e-9 * dx)
        pos, foot, dist = pos[keep], foot[keep], dist[keep]
        layer = np.minimum(np.floor(dist / dx + 1e-9).astype(np.int64), layers - 1)
        order = np.argsort(layer, kind="stable")
        pos, foot, dist, layer = pos[order], foot[order], dist[order], layer[order]
        shape = Shape(pos, dx, normals=(foot - pos) / dist[:, None], surface_points=foot, layer=layer)
    else:
        raise ParameterError(f"layout must be 'layers' or 'surface', got {layout!r}")
    if shape.n == 0:
        raise ParameterError(f"{mesh.label}: no wall particle at dx = {dx:g} m (the mesh is smaller than the spacing)")
    return shape


def _merge_ties(idx, pos, foot, dist, side):
    """One closest point per lattice point. A point as near to several faces (inside a convex
    obstacle, on its medial planes: the edge row of a pillar) gets the normal that bisects theirs
    and, as surface point, the edge or corner they meet at: with m the mean of the distinct unit
    vectors u_k towards the closest points, n = m / |m| and s = x + d m / |m|^2, at distance
    d / cos(theta / 2) from x for two faces at angle theta (d sqrt(2) at a right-angled edge,
    d sqrt(3) at a cube's corner). Each face's own choice would put the fluid in front of the
    other face behind this particle's surface (negative signed wall distance near a convex edge).
    Faces at more than 120 degrees (opposite sides of a thin plate) keep the first face's point.
    Behind only if behind every tied face."""
    n = idx.shape[0]
    if n == 0:
        return pos, foot, dist, side
    first = np.ones(n, dtype=bool)
    first[1:] = np.any(idx[1:] != idx[:-1], axis=1)
    if np.all(first):
        return pos, foot, dist, side
    group = np.cumsum(first) - 1
    starts = np.flatnonzero(first)
    unit = (foot - pos) / np.maximum(dist, 1e-300)[:, None]
    # distinct directions only (two triangles of one face give the same closest point)
    key = np.concatenate([group[:, None], np.round(unit * 1e6).astype(np.int64)], axis=1)
    _, distinct = np.unique(key, axis=0, return_index=True)
    use = np.zeros(n, dtype=bool)
    use[distinct] = True
    count = np.bincount(group, weights=use, minlength=starts.size)
    m = np.stack([np.bincount(group, weights=unit[:, k] * use, minlength=starts.size) for k in range(3)], axis=1)
    m /= count[:, None]
    d = dist[starts]
    m2 = np.einsum("ij,ij->i", m, m)
    # faces that nearly face each other (a point midway in a thin plate, theta > 120 degrees) meet
    # at no nearby edge: keep the first face's closest point there
    bisect = m2 >= 0.25
    surface = foot[starts].copy()
    surface[bisect] = pos[starts][bisect] + (d[bisect] / m2[bisect])[:, None] * m[bisect]
    merged_side = np.maximum.reduceat(side, starts)
    return pos[starts], surface, np.linalg.norm(surface - pos[starts], axis=1), merged_side


def mesh_wall_for_model(model, mesh, dx, kernel, h, *, fluid="outside", origin=None) -> Shape:
    """:func:`mesh_wall` in the layout ``model`` declares: ceil(support / dx) layers
    (:func:`seawall.cases.base.wall_layers`), or one surface row at dx / beta."""
    from .cases.base import wall_layers

    if model.layout == "surface":
        return mesh_wall(mesh, dx, fluid=fluid, origin=origin, layout="surface", beta=model.beta)
    return mesh_wall(mesh, dx, wall_layers(kernel, h, dx), fluid=fluid, origin=origin)


# --------------------------------------------------------------------------
# Fluid fills
# --------------------------------------------------------------------------

def default_clearance(dx):
    """The default fluid-wall clearance: dx / 2.

    A fluid particle stands for the cell of side dx around it
    (:mod:`seawall.shapes`), so a fill whose cells reach the surface has its
    particles dx / 2 from it: the fluid of :func:`seawall.shapes.block` in
    :func:`seawall.shapes.tank`. Layered walls have their first layer dx / 2
    behind the surface, so fluid and wall are one lattice with gap dx; surface
    rows (repulsive models) sit on the surface, dx / 2 from the fluid, as in the
    built-in tanks with those models.
    """
    return 0.5 * require_positive("dx", dx)


def _clearance(clearance, dx):
    if clearance is None:
        return default_clearance(dx)
    try:
        c = float(clearance)
    except (TypeError, ValueError):
        raise ParameterError(f"clearance must be a number >= 0 [m], got {clearance!r}") from None
    if not (c >= 0.0 and math.isfinite(c)):
        raise ParameterError(f"clearance must be a number >= 0 [m], got {clearance!r}")
    return c


# an irrational, tiny offset of the test lines, in units of dx (see _column_crossings)
_SHIFT = np.array([math.sqrt(2.0) - 1.0, math.sqrt(3.0) - 1.0]) * 1e-6


def fill_mesh(mesh, dx, *, clearance=None, origin=None, walls=()) -> Shape:
    """Fluid particles filling a closed mesh (3D) at spacing dx.

    Lattice points ``origin + (i + 1/2) dx`` inside the surface (non-zero
    winding number, counted along vertical lines) and at least ``clearance``
    (default :func:`default_clearance`, dx / 2) from it. Either orientation is
    accepted. ``walls``: Shapes (or (name, Shape) pairs) the fill must not
    overlap (:func:`check_fill_against_walls`).
    """
    mesh = _as_mesh(mesh)
    dx = require_positive("dx", dx)
    c = _clearance(clearance, dx)
    origin = _origin(origin, 3)
    mesh.require_closed("a fluid fill")
    lo, hi = mesh.bounds
    ilo = np.ceil((lo - origin) / dx - 0.5).astype(np.int64)
    ihi = np.floor((hi - origin) / dx - 0.5).astype(np.int64)
    counts = ihi - ilo + 1
    if np.any(counts < 1):
        raise ParameterError(f"{mesh.label}: holds no lattice point at dx = {dx:g} m")
    require_memory(f"the fill of {mesh.label} at dx = {dx:g} m", int(np.prod(counts)))
    ni, nj, nk = (int(n) for n in counts)
    args = (mesh.vertices, mesh.faces, mesh.face_normals, origin, dx, _SHIFT * dx, int(ilo[0]), int(ilo[1]), ni, nj)
    n = _column_crossings(*args, False, np.empty(0, np.int64), np.empty(0), np.empty(0, np.int64))
    col = np.empty(n, np.int64)
    z = np.empty(n)
    sign = np.empty(n, np.int64)
    _column_crossings(*args, True, col, z, sign)
    order = np.argsort(col, kind="stable")
    col, z, sign = col[order], z[order], sign[order]
    start = np.searchsorted(col, np.arange(ni * nj + 1))
    z0 = origin[2] + ilo[2] * dx
    wind = _winding_numbers(start, z, sign, ni * nj, z0, dx, nk)
    ii, jj, kk = np.nonzero(wind.reshape(ni, nj, nk) != 0)
    idx = np.stack([ii, jj, kk], axis=1) + ilo
    pos = origin + (idx + 0.5) * dx
    if c > 0.0 and pos.shape[0]:
        near_idx, _, _, near_d, _, _ = mesh.nearest_in_band(dx, c, origin)
        close = near_idx[near_d < c * (1.0 - 1e-9)]
        close = close[np.all((close >= ilo) & (close <= ihi), axis=1)]   # the others are no fill point
        if close.shape[0]:
            def key(a):
                return np.ravel_multi_index((a - ilo).T, counts)
            pos = pos[~np.isin(key(idx), key(close))]
    if pos.shape[0] == 0:
        raise ParameterError(f"{mesh.label}: the fill holds no particle at dx = {dx:g} m with clearance {c:g} m")
    fill = Shape(pos, dx)
    check_fill_against_walls(fill, walls, c, mesh.label)
    return fill


def fill_polygon(points, dx, *, clearance=None, origin=None, walls=(), label="polygon") -> Shape:
    """Fluid particles filling a closed 2D polygon (vertices (M, 2), M >= 3, closed implicitly).

    Lattice points inside (non-zero winding number) and at least ``clearance``
    (default dx / 2) from every edge; ``walls`` as in :func:`fill_mesh`.
    """
    try:
        pts = np.array(points, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{label}: points must be an (M, 2) array of numbers") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 3 or not np.all(np.isfinite(pts)):
        raise ParameterError(f"{label}: points must be an (M, 2) array of finite numbers with M >= 3, "
                             f"got shape {pts.shape}")
    if np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    dx = require_positive("dx", dx)
    c = _clearance(clearance, dx)
    origin = _origin(origin, 2)
    closed = np.vstack([pts, pts[:1]])
    area = 0.5 * np.sum(closed[:-1, 0] * closed[1:, 1] - closed[1:, 0] * closed[:-1, 1])
    if abs(area) <= 1e-12 * float(np.ptp(pts, axis=0).max()) ** 2:
        raise ParameterError(f"{label}: the polygon encloses no area")
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    ilo = np.ceil((lo - origin) / dx - 0.5).astype(np.int64)
    ihi = np.floor((hi - origin) / dx - 0.5).astype(np.int64)
    if np.any(ihi < ilo):
        raise ParameterError(f"{label}: holds no lattice point at dx = {dx:g} m")
    require_memory(f"the fill of {label} at dx = {dx:g} m", int(np.prod(ihi - ilo + 1)))
    axes = [origin[k] + (np.arange(ilo[k], ihi[k] + 1) + 0.5) * dx for k in range(2)]
    gx, gy = np.meshgrid(*axes, indexing="ij")
    pos = np.stack([gx.ravel(), gy.ravel()], axis=1)
    pos = pos[inside_polygon(pos, closed, dx)]
    if c > 0.0 and pos.shape[0]:
        _, d = _closest_on_polyline(pos, closed)
        pos = pos[d >= c * (1.0 - 1e-9)]
    if pos.shape[0] == 0:
        raise ParameterError(f"{label}: the fill holds no particle at dx = {dx:g} m with clearance {c:g} m")
    fill = Shape(pos, dx)
    check_fill_against_walls(fill, walls, c, label)
    return fill


def check_fill_against_walls(fill, walls, clearance, label="fill"):
    """Refuse (ParameterError) a fill that overlaps a wall.

    ``walls``: Shapes, or (name, Shape) pairs. A fill overlaps a wall when one
    of its particles is closer than ``clearance`` to a wall particle (a fill
    clear of the surface by ``clearance`` never is: the segment to a wall
    particle, on or behind the surface, crosses it), or lies inside the wall's
    material between its particles (:func:`_behind`).
    """
    items = list(walls.items()) if isinstance(walls, dict) else list(walls or ())
    for k, item in enumerate(items, start=1):
        name, wall = item if isinstance(item, tuple) else (f"number {k}", item)
        if not isinstance(wall, Shape):
            raise ParameterError(f"walls must be seawall Shapes, got {type(wall).__name__}")
        if wall.dim != fill.dim:
            raise ParameterError(f"wall {name} has dimension {wall.dim}, the fill {fill.dim}")
        tol = 1e-9 * fill.spacing
        if clearance > 0.0:
            near = _nearest_distances(fill.positions, wall.positions, clearance)
            bad = np.nonzero(near < clearance - tol)[0]
            if bad.size:
                p = fill.positions[bad[0]]
                raise ParameterError(f"{label}: the fluid fill overlaps wall {name}: {bad.size} particles closer "
                                     f"than the clearance {clearance:g} m to it (first at {np.round(p, 6).tolist()})")
        if wall.normals is None or wall.surface_points is None:
            continue
        behind = _behind(fill.positions, wall, tol)
        if behind.size:
            p = fill.positions[behind[0]]
            raise ParameterError(f"{label}: the fluid fill overlaps wall {name}: {behind.size} particles lie inside "
                                 f"the wall (first at {np.round(p, 6).tolist()})")


def _behind(points, wall, tol):
    """Indices of the points inside a wall's material, judged from its particles: within
    sqrt(d) / 2 spacings of a wall particle (the farthest a point of a region tiled by the
    particles' cells can be from them) and behind the surface point of the nearest one,
    (x - s) . n < -tol. The distance gate keeps a point in front of a convex edge, whose nearest
    particle may belong to the other face, from being taken as behind it."""
    reach = 0.5 * math.sqrt(wall.dim) * wall.spacing * (1.0 + 1e-9)
    near = _nearest_distances(points, wall.positions, reach)
    cand = np.nonzero(near < reach)[0]
    if cand.size == 0:
        return cand
    nearest = _nearest_index(points[cand], wall.positions, near[cand])
    side = np.einsum("ij,ij->i", points[cand] - wall.surface_points[nearest], wall.normals[nearest])
    return cand[side < -tol]


def check_wall_junctions(meshes_and_walls):
    """Refuse a mesh with a face covered by another wall (ParameterError, one line).

    ``meshes_and_walls``: (TriangleMesh, name, Shape) triples, the mesh None
    for walls not made from one (a ``shapes.tank``). A face is covered when
    its centroid and points near its corners, moved dx / 2 along its normal
    (towards the fluid), all lie inside another wall: a pillar's foot standing
    on the floor. Its wall particles would point into the floor: a ghost model
    mirrors fluid states there, and every model sees a wall surface where there
    is none. Such faces must be left out of the mesh (a pillar open at its foot).
    """
    items = list(meshes_and_walls)
    for mesh, name, wall in items:
        if mesh is None:
            continue
        v, f = mesh.vertices, mesh.faces
        centroid = v[f].mean(axis=1)
        samples = [centroid] + [centroid + 0.8 * (v[f[:, k]] - centroid) for k in range(3)]
        step = 0.5 * wall.spacing * mesh.face_normals
        covered_by = [None] * f.shape[0]
        for _, other_name, other in items:
            if other is wall or other.normals is None or other.surface_points is None:
                continue
            inside = np.ones(f.shape[0], dtype=bool)
            for pts in samples:
                hit = np.zeros(f.shape[0], dtype=bool)
                hit[_behind(pts + step, other, 1e-9 * wall.spacing)] = True
                inside &= hit
            for t in np.nonzero(inside)[0]:
                covered_by[t] = covered_by[t] or other_name
        bad = [t for t, c in enumerate(covered_by) if c is not None]
        if bad:
            c = np.round(centroid[bad[0]], 6).tolist()
            raise ParameterError(f"{mesh.label}: {len(bad)} faces of wall {name} are covered by wall "
                                 f"{covered_by[bad[0]]} (first with centre {c}); leave covered faces out "
                                 "of the mesh (e.g. a pillar open at its foot)")


def _nearest_index(query, ref, dist):
    """Index of the nearest ref point of each query point, whose distance ``dist`` is known finite:
    the ref points are sorted into cells of side max(dist), each query scans its 3^d cells."""
    cell = float(dist.max()) * (1.0 + 1e-6) + 1e-300
    lo = np.minimum(ref.min(axis=0), query.min(axis=0))
    rc = np.floor((ref - lo) / cell).astype(np.int64)
    qc = np.floor((query - lo) / cell).astype(np.int64)
    nb = np.maximum(rc.max(axis=0), qc.max(axis=0)) + 3
    rkey = np.ravel_multi_index((rc + 1).T, nb)
    order = np.argsort(rkey, kind="stable")
    return _nearest_index_loop(query, ref, order, rkey[order], qc + 1, nb)


@njit(cache=True)
def _nearest_index_loop(query, ref, order, sorted_key, qcell, nb):
    d = query.shape[1]
    out = np.full(query.shape[0], -1, dtype=np.int64)
    for q in range(query.shape[0]):
        best = np.inf
        for off in range(3 ** d):
            key = 0
            rem = off
            for k in range(d):
                c = qcell[q, k] + rem % 3 - 1
                rem //= 3
                key = key * nb[k] + c
            s = np.searchsorted(sorted_key, key)
            while s < sorted_key.shape[0] and sorted_key[s] == key:
                i = order[s]
                dd = 0.0
                for k in range(d):
                    dd += (ref[i, k] - query[q, k]) ** 2
                if dd < best:
                    best = dd
                    out[q] = i
                s += 1
    return out
