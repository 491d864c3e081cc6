"""Ghost-wall geometry ([Huang2019] sec. 2.2): mirror points of corner-rich walls lie in the fluid,
the pressure transfer is exact for still water, and the dam-break initial field meets its boundary conditions."""

import numpy as np
import pytest

from seawall import shapes
from seawall.boundary.ghost import export_ghost_vtu, mirror_diagnostics, mirror_points
from seawall.cases.tanks import dam_break_pressure

DX = 0.01


def inside_box(p, lo, hi, tol=1e-12):
    return np.all((p > np.asarray(lo) + tol) & (p < np.asarray(hi) - tol), axis=1)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("open_top", [True, False])
def test_tank_mirror_points_inside_fluid(dim, open_top):
    """Concave corners and (3D) edges/vertices: every mirror point is inside the tank, >= 0.5 dx from the wall."""
    lo = np.zeros(dim)
    hi = np.array([0.2, 0.1, 0.15][:dim])
    wall = shapes.tank(lo, hi, DX, layers=4, open_top=open_top)
    m, near = mirror_diagnostics(wall.positions, wall.surface_points, DX)
    top = hi.copy()
    inner = np.ones(wall.n, dtype=bool)
    if open_top:
        top[-1] = 10.0
        # an open tank's crest and back face are surfaces too (seawall.shapes.tank): their particles
        # mirror above the crest or behind the tank; the others into it
        inner = np.all((wall.surface_points[:, :-1] >= lo[:-1] - 1e-12)
                       & (wall.surface_points[:, :-1] <= hi[:-1] + 1e-12), axis=1)
        inner &= wall.surface_points[:, -1] < hi[-1] - 1e-12
        assert not np.any(inside_box(m[~inner], lo, hi))
    assert np.all(inside_box(m[inner], lo, top))
    assert near.min() >= 0.999  # first-layer mirror points are 1 dx from the wall lattice
    # the mirror point is the reflection along the normal: x_M - x_G = 2 d n
    d = np.linalg.norm(wall.surface_points - wall.positions, axis=1)
    assert np.allclose(m - wall.positions, 2.0 * d[:, None] * wall.normals)
    # corner particles mirror through the corner point itself (diagonal normals)
    corner = np.all(wall.positions < lo, axis=1) & inner  # the vertex region at lo
    assert corner.any()
    assert np.allclose(m[corner], -wall.positions[corner])


def test_polyline_convex_and_concave_corners():
    """A step profile: floor, up a step (convex corner for the fluid at its top edge), along, and a wedge."""
    pts = np.array([[0.0, 0.3], [0.0, 0.0], [0.3, 0.0], [0.3, 0.1], [0.6, 0.1], [0.8, 0.25]])
    wall = shapes.polyline_wall(pts, DX, layers=4, side="right")
    m, near = mirror_diagnostics(wall.positions, wall.surface_points, DX)
    assert near.min() > 0.5, near.min()
    # every mirror point lies in the fluid region: the polygon above the profile, whose
    # first and last segments are extended along their directions
    from matplotlib.path import Path

    fluid = Path(np.vstack([[0.0, 3.0], pts[0] + [0.0, 0.0], pts[1:], pts[-1] + 8.0 * (pts[-1] - pts[-2]),
                            [4.0, 3.0]]))
    assert fluid.contains_points(m).all()
    # ... and not on the wall line: at least 0.3 dx away from it (the fluid lattice's first
    # particles are 0.5 dx away; arc particles of a concave corner mirror through the vertex,
    # so the first-layer arc particle on the bisector, 0.5 dx from the vertex, has its mirror
    # point 0.5 dx / sqrt(2) = 0.35 dx from both segments)
    from seawall.shapes import _closest_on_polyline
    _, dm = _closest_on_polyline(m, pts)
    assert dm.min() > 0.3 * DX, dm.min() / DX


def test_mirror_points_formula():
    x = np.array([[-0.005, 0.05], [-0.015, -0.015]])
    s = np.array([[0.0, 0.05], [0.0, 0.0]])
    assert np.allclose(mirror_points(s, x), [[0.005, 0.05], [0.015, 0.015]])


def test_export_vtu(tmp_path):
    from seawall.boundary.base import WallSystem
    from seawall.boundary.ghost import GhostParticles
    from seawall.io.vtk import read_vtu

    wall = WallSystem(shapes.tank((0, 0), (0.1, 0.05), DX, layers=3), model=GhostParticles("shepard"))
    g, m = export_ghost_vtu(wall, tmp_path)
    positions, data = read_vtu(g)
    x = wall.particles["x"]
    assert positions.shape == (wall.n, 3)
    assert np.allclose(positions[:, :2], x)
    # the glyph vector points from each ghost to its mirror point across the wall surface
    mirror = mirror_points(wall.particles["surface"], x)
    assert np.allclose(data["to_mirror"][:, :2], mirror - x)
    assert np.allclose(data["distance_to_wall"], np.linalg.norm(wall.particles["surface"] - x, axis=1))
    mirror_positions, mirror_data = read_vtu(m)
    assert np.allclose(mirror_positions[:, :2], mirror)
    assert np.array_equal(mirror_data["id"], wall.particles["id"])


def test_dam_break_initial_pressure_boundary_conditions():
    """[Huang2019] eq. 22-24: P = 0 on the free surfaces, dP/dx = 0 at x = 0, dP/dy = -g (rho0 + P/c0^2) at y = 0."""
    H, L = 0.6, 1.2
    c0 = 20.0 * np.sqrt(9.81 * H)
    y = np.linspace(0.05, 0.55, 6)
    x = np.linspace(0.05, 1.15, 6)
    assert np.allclose(dam_break_pressure(L, y, L, H, c0=c0), 0.0, atol=1e-6)
    assert np.allclose(dam_break_pressure(x, H, L, H, c0=c0), 0.0, atol=1e-6)
    e = 1e-6
    dpdx = (dam_break_pressure(e, y, L, H, c0=c0) - dam_break_pressure(-e, y, L, H, c0=c0)) / (2 * e)
    assert np.allclose(dpdx, 0.0, atol=1e-3)
    p0 = dam_break_pressure(x, 0.0, L, H, c0=c0)
    dpdy = (dam_break_pressure(x, e, L, H, c0=c0) - p0) / e
    assert np.allclose(dpdy, -9.81 * (1000.0 + p0 / c0 ** 2), rtol=1e-2)
    # below hydrostatic everywhere in the column, close to it far from the released face
    assert np.all(p0 < 1000 * 9.81 * H)
    assert dam_break_pressure(0.0, 0.0, L, H, c0=c0) > 0.9 * 1000 * 9.81 * H
