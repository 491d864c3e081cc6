"""Unit tests for seawall.shapes: lattices, tank walls, polyline walls, binning."""

import dataclasses
import itertools
import math

import numpy as np
import pytest

from seawall import shapes
from seawall.errors import ParameterError
from seawall.shapes import Shape


def _pairwise_min(p, q=None):
    """Brute-force minimum distance (within one set if q is None)."""
    if q is None:
        d = np.sqrt(np.sum((p[:, None, :] - p[None, :, :]) ** 2, axis=-1))
        np.fill_diagonal(d, np.inf)
        return d.min()
    return np.sqrt(np.sum((p[:, None, :] - q[None, :, :]) ** 2, axis=-1)).min()


def _as_index_set(pos, lo, dx):
    """Integer lattice indices i with pos = lo + (i + 0.5) dx, as a set of tuples."""
    idx = (pos - lo) / dx - 0.5
    rounded = np.rint(idx)
    assert np.allclose(idx, rounded, atol=1e-9), "particle off the lattice"
    return set(map(tuple, rounded.astype(int)))


# ---------------------------------------------------------------- fluid blocks

def test_rectangle_count_and_cell_centres():
    r = shapes.rectangle((0.0, 0.0), (0.6, 0.3), 0.005)
    assert r.n == 7200 and r.dim == 2
    xs = np.unique(np.round(r.positions[:, 0], 12))
    ys = np.unique(np.round(r.positions[:, 1], 12))
    assert xs.size == 120 and ys.size == 60
    np.testing.assert_allclose(xs, 0.0025 + 0.005 * np.arange(120), atol=1e-12)
    np.testing.assert_allclose(ys, 0.0025 + 0.005 * np.arange(60), atol=1e-12)
    assert r.normals is None and r.surface_points is None and r.layer is None


def test_block_only_whole_cells_and_offset_lo():
    b = shapes.block((1.0, -0.5), (1.35, -0.1), 0.1)  # 3.5 x 4 cells -> 3 x 4
    assert b.n == 12
    assert b.positions[:, 0].min() == pytest.approx(1.05)
    assert b.positions[:, 0].max() == pytest.approx(1.25)
    assert b.positions[:, 1].max() == pytest.approx(-0.15)


def test_box_counts_3d():
    b = shapes.box((0, 0, 0), (0.4, 0.2, 0.3), 0.01)
    assert b.n == 40 * 20 * 30 and b.dim == 3
    assert np.all(b.positions > 0) and np.all(b.positions < [0.4, 0.2, 0.3])


@pytest.mark.parametrize("call, match", [
    (lambda: shapes.rectangle((0, 0), (1, 1), -0.1), "dx must be a positive finite number"),
    (lambda: shapes.rectangle((0, 0), (1, 1), float("nan")), "dx"),
    (lambda: shapes.rectangle((0, 0), (1, -1), 0.1), "hi must be greater than lo"),
    (lambda: shapes.rectangle((0, 0, 0), (1, 1, 1), 0.1), "lo must be a sequence of 2"),
    (lambda: shapes.box((0, 0), (1, 1), 0.1), "lo must be a sequence of 3"),
    (lambda: shapes.block((0, 0), (1, 1, 1), 0.1), "same length"),
    (lambda: shapes.block((0, 0), (0.05, 1), 0.1), "at least dx"),
    (lambda: shapes.circle((0, 0), 0.0, 0.1), "radius"),
    (lambda: shapes.tank((0, 0), (1.05, 1), 0.1), "whole multiple of dx"),
    (lambda: shapes.tank((0, 0), (1, 1), 0.1, layers=0), "layers must be a positive integer"),
    (lambda: shapes.polyline_wall([(0, 0), (1, 0)], 0.1, side="up"), "side must be"),
    (lambda: shapes.polyline_wall([(0, 0), (0, 0), (1, 0)], 0.1), "zero length"),
    (lambda: shapes.polyline_wall([(0, 0), (1, 0), (0, 0)], 0.1), "fold back"),
    (lambda: shapes.remove_overlap(shapes.rectangle((0, 0), (1, 1), 0.1),
                                   np.zeros((3, 2)), 0.0), "min_distance"),
])
def test_bad_parameters_raise(call, match):
    with pytest.raises(ParameterError, match=match):
        call()


# ------------------------------------------------------------- discs and balls

@pytest.mark.parametrize("make, center", [
    (shapes.circle, np.array([0.3, -0.7])),
    (shapes.sphere, np.array([0.1, 0.2, 0.3])),
])
def test_round_shapes_mirror_symmetric(make, center):
    dx = 0.01
    s = make(center, 0.137, dx)
    rel = s.positions - center
    assert np.all(np.linalg.norm(rel, axis=1) <= 0.137 * (1 + 1e-9))
    for axis in range(s.dim):
        mirrored = s.positions.copy()
        mirrored[:, axis] = 2 * center[axis] - mirrored[:, axis]
        # every mirrored particle coincides with an original one
        order_a = np.lexsort(np.round(s.positions / dx, 6).T)
        order_b = np.lexsort(np.round(mirrored / dx, 6).T)
        np.testing.assert_allclose(s.positions[order_a], mirrored[order_b], atol=1e-12)


def test_circle_and_sphere_counts_match_area_and_volume():
    dx = 0.002
    r = 50 * dx
    c = shapes.circle((0.5, 0.5), r, dx)
    assert abs(c.n - math.pi * r * r / dx**2) / (math.pi * r * r / dx**2) < 0.02
    s = shapes.sphere((0.0, 0.0, 0.0), 20 * dx, dx)
    vol = 4.0 / 3.0 * math.pi * (20 * dx) ** 3 / dx**3
    assert abs(s.n - vol) / vol < 0.02


# ------------------------------------------------------------------- tank walls

def _face_count(pos, lo, hi):
    """Number of axes along which each point lies outside [lo, hi]."""
    return np.sum((pos < lo) | (pos > hi), axis=1)


@pytest.mark.parametrize("lo, hi", [
    ((0.0, 0.0), (1.0, 0.6)),
    ((-0.2, 0.1, 0.0), (0.4, 0.5, 0.3)),
])
@pytest.mark.parametrize("open_top", [True, False])
def test_tank_geometry(lo, hi, open_top):
    lo, hi = np.array(lo), np.array(hi)
    dx, layers = 0.05, 3
    w = shapes.tank(lo, hi, dx, layers=layers, open_top=open_top)
    d = w.dim
    pos, sp, nrm, lay = w.positions, w.surface_points, w.normals, w.layer

    # nothing inside the interior box
    inside = np.all((pos > lo) & (pos < hi), axis=1)
    assert not np.any(inside)
    # unit normals that equal (surface - position) / distance
    np.testing.assert_allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-12)
    diff = sp - pos
    dist = np.linalg.norm(diff, axis=1)
    np.testing.assert_allclose(nrm, diff / dist[:, None], atol=1e-12)
    assert lay.min() == 0 and lay.max() == layers - 1

    # an open tank's side walls are 2 * layers thick; each of their particles takes the nearest of
    # the inner face, the crest (hi_last) and the back face, a tie the edge between them
    side_surface = np.zeros(w.n, dtype=bool)
    if open_top:
        thick = 2 * layers * dx
        # (the side walls down to the floor's underside: the back face runs down past the floor)
        beside = np.any((pos[:, :-1] < lo[:-1]) | (pos[:, :-1] > hi[:-1]), axis=1)
        inner = np.linalg.norm(pos - np.clip(pos, lo, hi), axis=1)
        crest = hi[-1] - pos[:, -1]
        back = np.min(np.concatenate([pos[:, :-1] - (lo[:-1] - thick), (hi[:-1] + thick) - pos[:, :-1]], axis=1),
                      axis=1)
        nearest = np.minimum(np.minimum(inner, crest), back)
        assert np.all(pos[:, :-1] > lo[:-1] - thick) and np.all(pos[:, :-1] < hi[:-1] + thick)
        np.testing.assert_allclose(dist[beside & (nearest == inner) & (crest > inner + 1e-9) & (back > inner + 1e-9)],
                                   inner[beside & (crest > inner + 1e-9) & (back > inner + 1e-9)], atol=1e-12)
        on_crest = beside & (crest < inner - 1e-9) & (crest < back - 1e-9)
        assert np.any(on_crest)
        np.testing.assert_allclose(sp[on_crest, -1], hi[-1], atol=1e-12)
        np.testing.assert_allclose(nrm[on_crest, -1], 1.0, atol=1e-12)
        on_back = beside & (back < inner - 1e-9) & (back < crest - 1e-9)
        assert np.any(on_back)
        np.testing.assert_allclose(dist[on_back], back[on_back], atol=1e-12)
        assert np.all(np.einsum("ij,ij->i", nrm[on_back, :-1], pos[on_back, :-1] - 0.5 * (lo[:-1] + hi[:-1])) > 0)
        # a particle as near to two faces takes the edge between them: farther than either face
        edge = beside & ~on_crest & ~on_back & ~((inner < crest - 1e-9) & (inner < back - 1e-9))
        assert np.any(edge)
        assert np.all(dist[edge] > nearest[edge] + 1e-9)
        assert np.all(lay[beside] <= np.floor(nearest[beside] / dx + 1e-9))
        side_surface = beside & ~((inner < crest - 1e-9) & (inner < back - 1e-9))
    crest = side_surface

    # face particles: distance (layer + 0.5) dx, normal along one axis
    nout = _face_count(pos, lo, hi)
    face = (nout == 1) & ~crest
    np.testing.assert_allclose(dist[face], (lay[face] + 0.5) * dx, rtol=1e-10)
    assert np.all(np.sum(np.abs(nrm[face]) > 1e-12, axis=1) == 1)

    # bottom-face particles point straight up
    bottom = face & (pos[:, -1] < lo[-1])
    up = np.zeros(d)
    up[-1] = 1.0
    assert np.any(bottom)
    np.testing.assert_allclose(nrm[bottom], np.broadcast_to(up, nrm[bottom].shape), atol=1e-12)

    # corner particles: diagonal normals pointing to the corner point
    corner = (nout >= 2) & ~crest
    assert np.any(corner)
    assert np.all(np.sum(np.abs(nrm[corner]) > 1e-12, axis=1) == nout[corner])
    k_out = (pos[corner] < lo) | (pos[corner] > hi)
    expected_sp = np.where(pos[corner] < lo, lo, np.where(pos[corner] > hi, hi, pos[corner]))
    np.testing.assert_allclose(sp[corner], expected_sp, atol=1e-12)
    assert np.all(np.sign(nrm[corner])[k_out] == np.sign(expected_sp - pos[corner])[k_out])
    # the layer of a corner particle is its largest per-axis layer index
    per_axis = np.where(pos[corner] < lo, (lo - pos[corner]) / dx - 0.5,
                        np.where(pos[corner] > hi, (pos[corner] - hi) / dx - 0.5, -1))
    np.testing.assert_allclose(lay[corner], per_axis.max(axis=1), atol=1e-9)

    # mirror points inside the closed interior box
    mirror = w.mirror_points
    np.testing.assert_allclose(mirror, 2 * sp - pos)
    assert np.all(mirror[~crest] >= lo - 1e-12) and np.all(mirror[~crest] <= hi + 1e-12)

    # no duplicates: closest pair is exactly one lattice spacing
    assert _pairwise_min(pos) == pytest.approx(dx, rel=1e-9)
    assert shapes.min_distance_between(pos[: w.n // 2], pos[w.n // 2:]) >= dx * (1 - 1e-9)

    # no holes: the wall is exactly the outer lattice minus the interior
    n = np.rint((hi - lo) / dx).astype(int)
    ranges = [range(-layers, n[k] + layers) for k in range(d)]
    if open_top:
        ranges = [range(-2 * layers, n[k] + 2 * layers) for k in range(d - 1)] + [range(-layers, n[-1])]
    expected = {i for i in itertools.product(*ranges)
                if any(i[k] < 0 or i[k] >= n[k] for k in range(d))}
    got = _as_index_set(pos, lo, dx)
    assert len(got) == w.n
    assert got == expected
    has_lid = np.any(pos[:, -1] > hi[-1])
    assert has_lid == (not open_top)


def test_tank_and_fluid_share_one_lattice():
    lo, hi, dx = np.array([0.0, 0.0]), np.array([1.0, 0.6]), 0.02
    wall = shapes.tank(lo, hi, dx)
    fluid = shapes.block(lo, (hi[0], 0.3), dx)
    assert shapes.min_distance_between(fluid.positions, wall.positions) == pytest.approx(
        dx, abs=1e-12)
    # first fluid particle 0.5 dx from the wall surfaces
    assert fluid.positions[:, 0].min() - lo[0] == pytest.approx(0.5 * dx, abs=1e-12)
    assert fluid.positions[:, 1].min() - lo[1] == pytest.approx(0.5 * dx, abs=1e-12)
    assert shapes.tank_interior_lattice(lo, hi, dx).n == 50 * 30

    lo3, hi3 = np.zeros(3), np.array([0.4, 0.3, 0.5])
    wall3 = shapes.tank(lo3, hi3, dx)
    fluid3 = shapes.box(lo3, (0.4, 0.3, 0.2), dx)
    assert shapes.min_distance_between(fluid3, wall3) == pytest.approx(dx, abs=1e-12)


def test_tank_open_top_non_multiple_height():
    # the open vertical axis need not be a whole number of cells
    w = shapes.tank((0.0, 0.0), (0.5, 0.33), 0.1, layers=2)
    assert w.positions[:, 1].max() == pytest.approx(0.25)
    # the crest is the top of the walls' upper cells, not the unfilled hi
    assert w.surface_points[:, 1].max() == pytest.approx(0.3)
    assert not np.any(np.all((w.positions > 0) & (w.positions < [0.5, 0.33]), axis=1))


def test_tank_3d_bottom_normal():
    w = shapes.tank((0, 0, 0), (0.3, 0.2, 0.2), 0.05, layers=2)
    below = (w.positions[:, 2] < 0) & np.all(
        (w.positions[:, :2] > 0) & (w.positions[:, :2] < [0.3, 0.2]), axis=1)
    assert np.sum(below) == 6 * 4 * 2
    np.testing.assert_allclose(w.normals[below], [[0, 0, 1]] * int(np.sum(below)))


# --------------------------------------------------------------- polyline walls

def test_polyline_straight_line_matches_layered_wall():
    dx = 0.1
    w = shapes.polyline_wall([(0.0, 0.0), (1.0, 0.0)], dx, layers=3, side="right")
    ref = shapes.block((0.0, -0.3), (1.0, 0.0), dx)
    order_a = np.lexsort(w.positions.T)
    order_b = np.lexsort(ref.positions.T)
    np.testing.assert_allclose(w.positions[order_a], ref.positions[order_b], atol=1e-12)
    np.testing.assert_allclose(w.normals, [[0.0, 1.0]] * w.n, atol=1e-12)
    np.testing.assert_allclose(w.surface_points[:, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(w.surface_points[:, 0], w.positions[:, 0], atol=1e-12)
    np.testing.assert_allclose(-w.positions[:, 1], (w.layer + 0.5) * dx, atol=1e-12)

    # a collinear middle vertex and the opposite direction give the same wall
    w2 = shapes.polyline_wall([(1.0, 0.0), (0.5, 0.0), (0.0, 0.0)], dx, side="left")
    order_c = np.lexsort(w2.positions.T)
    np.testing.assert_allclose(w2.positions[order_c], ref.positions[order_b], atol=1e-12)


V_CASES = [
    # (vertices, wall side, fluid-region predicate)
    ([(-1.0, 1.0), (0.0, 0.0), (1.0, 1.0)], "right",
     lambda p: p[:, 1] > np.abs(p[:, 0])),                 # fluid in a V: gap + arc
    ([(-1.0, 0.0), (0.0, 1.0), (1.0, 0.0)], "right",
     lambda p: p[:, 1] > 1.0 - np.abs(p[:, 0])),           # fluid over a ridge: overlap
    ([(-1.0, 1.0), (0.0, 0.0), (1.0, 1.0)], "left",
     lambda p: p[:, 1] < np.abs(p[:, 0])),                 # wall inside the V: overlap
    ([(-1.0, -0.5), (0.0, 0.0), (1.0, -0.5)], "right",
     lambda p: p[:, 1] > -0.5 * np.abs(p[:, 0])),          # obtuse overlap
    ([(-0.5, 0.75), (0.0, 0.0), (0.5, 0.75)], "left",
     lambda p: p[:, 1] < 1.5 * np.abs(p[:, 0])),           # wall in an acute V: overlap
    # bottom then a side wall leaning at 120 degrees (fluid angle 120): gap
    ([(-1.0, 0.0), (0.0, 0.0), (0.5, math.sqrt(3) / 2)], "right",
     lambda p: (p[:, 1] > 0) & (math.sqrt(3) * p[:, 0] - p[:, 1] < 0)),
]


@pytest.mark.parametrize("layers", [3, 6])
@pytest.mark.parametrize("pts, side, in_fluid", V_CASES)
def test_polyline_corners(pts, side, in_fluid, layers):
    dx = 0.05
    pts = np.array(pts)
    w = shapes.polyline_wall(pts, dx, layers=layers, side=side)
    pos = w.positions
    assert _pairwise_min(pos) >= 0.5 * dx * (1 - 1e-9)
    np.testing.assert_allclose(np.linalg.norm(w.normals, axis=1), 1.0, atol=1e-12)
    # wall particles in the wall material, mirror points in the fluid
    assert not np.any(in_fluid(pos))
    assert np.all(in_fluid(w.mirror_points))
    # normals point to the fluid: a short step along them reaches the surface
    dist = np.linalg.norm(w.surface_points - pos, axis=1)
    np.testing.assert_allclose(pos + dist[:, None] * w.normals, w.surface_points, atol=1e-12)
    assert np.all(dist >= 0.5 * dx * (1 - 1e-9)) and np.all(dist <= layers * dx + 1e-12)
    assert set(np.unique(w.layer)) == set(range(layers))

    # no holes: every point of the band of particle centres (0.5 .. layers - 0.5
    # dx behind the line) near the vertex has a particle close by
    rng = np.random.default_rng(1)
    q = pts[1] + rng.uniform(-0.4, 0.4, size=(6000, 2))
    _, qdist = shapes._closest_on_polyline(q, pts)
    band = ~in_fluid(q) & (qdist >= 0.5 * dx) & (qdist < (layers - 0.5) * dx)
    nearest = np.array([np.min(np.linalg.norm(pos - x, axis=1)) for x in q[band]])
    assert nearest.max() < 0.95 * dx


def test_polyline_concave_vertex_drops_duplicates():
    # a right-angle corner with the wall inside: the two strips coincide in
    # the corner square and must not be doubled
    dx = 0.1
    w = shapes.polyline_wall([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)], dx, layers=3, side="left")
    ref = shapes.block((0.7, 0.0), (1.0, 1.0), dx) + shapes.block((0.0, 0.0), (0.7, 0.3), dx)
    assert w.n == ref.n
    assert _as_index_set(w.positions, np.zeros(2), dx) == _as_index_set(
        ref.positions, np.zeros(2), dx)


# ------------------------------------------------------- Shape and binning tools

def test_shape_add_and_validation():
    a = shapes.rectangle((0, 0), (1, 1), 0.1)
    b = shapes.rectangle((2, 0), (3, 1), 0.1)
    c = a + b
    assert c.n == a.n + b.n and c.normals is None
    assert sum([a, b]).n == c.n
    w = shapes.tank((0, 0), (1, 1), 0.1)
    ww = w + w
    assert ww.n == 2 * w.n and ww.layer.shape == (2 * w.n,)
    with pytest.raises(ParameterError, match="normals"):
        a + w
    with pytest.raises(ParameterError, match="spacing"):
        a + shapes.rectangle((0, 0), (1, 1), 0.05)
    with pytest.raises(ParameterError, match="dimension"):
        a + shapes.box((0, 0, 0), (1, 1, 1), 0.1)
    with pytest.raises(ParameterError, match="normals must have shape"):
        Shape(np.zeros((3, 2)), 0.1, normals=np.zeros((2, 2)))
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.spacing = 1.0


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_binning_matches_brute_force(dim, seed):
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.0, 1.0, size=(300, dim))
    b = rng.uniform(0.3, 1.7, size=(200, dim))
    assert shapes.min_distance_between(a, b) == pytest.approx(_pairwise_min(a, b), rel=1e-12)

    fluid = Shape(a, 0.05)
    for md in (0.02, 0.1, 0.35):
        kept = shapes.remove_overlap(fluid, b, md)
        dmin = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1)).min(axis=1)
        np.testing.assert_array_equal(kept.positions, a[dmin >= md])


def test_min_distance_far_apart_and_degenerate():
    a = np.array([[0.0, 0.0], [0.001, 0.0]])
    b = np.array([[100.0, 50.0], [200.0, 0.0], [100.0, 49.0]])
    assert shapes.min_distance_between(a, b) == pytest.approx(_pairwise_min(a, b))
    assert shapes.min_distance_between(a, a) == 0.0
    assert shapes.min_distance_between(np.zeros((0, 2)), b) == math.inf
    # huge coordinate range with a tiny cut-off must not overflow the cell keys
    big = np.array([[0.0, 0.0], [1e9, 1e9]])
    kept = shapes.remove_overlap(Shape(np.array([[1e9 + 1e-7, 1e9], [5.0, 5.0]]), 1e-6), big, 1e-6)
    np.testing.assert_array_equal(kept.positions, [[5.0, 5.0]])


def test_remove_overlap_keeps_wall_data_and_lattice_case():
    dx = 0.05
    wall = shapes.tank((0, 0), (1, 1), dx)
    # a fluid block poking through the wall: the overlapping part is removed
    fluid = shapes.block((-0.2, 0.0), (0.5, 0.5), dx)
    kept = shapes.remove_overlap(fluid, wall, 0.5 * dx)
    assert kept.n < fluid.n
    assert shapes.min_distance_between(kept, wall) >= 0.5 * dx
    # particles exactly on wall particle sites are gone, everything else stays
    dmin = np.array([np.min(np.linalg.norm(wall.positions - p, axis=1)) for p in fluid.positions])
    assert kept.n == int(np.sum(dmin >= 0.5 * dx))
