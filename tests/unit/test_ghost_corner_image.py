"""Free-slip ghosts beyond a corner are the image under the reflections in both faces (seawall.boundary.ghost).

A flow that is symmetric about both faces of a 90-degree corner -- the corner stagnation
flow u = -k x, v = k y of the dam break's downstream corner -- continues across the wall
unchanged, so every ghost must carry the flow's own value at its position. Before the fix
the corner ghosts reflected the velocity in the plane normal to their diagonal, which swaps
the components (u_G = (v, u) on the 45-degree diagonal) instead of reversing them.
"""

import numpy as np
import pytest

from seawall import shapes
from seawall.boundary.ghost import corner_tangents, ghost_transfer, mirror_points

DX = 0.01


def test_corner_flags_2d_tank():
    lo, hi = np.zeros(2), np.array([0.2, 0.1])
    wall = shapes.tank(lo, hi, DX, layers=3, open_top=False)
    corner, tangent = corner_tangents(wall.positions, wall.surface_points, DX)
    outside = (wall.positions < lo) | (wall.positions > hi)
    assert np.array_equal(corner == 1, outside.sum(axis=1) == 2)
    assert corner.sum() == 4 * 9
    assert np.all(tangent == 0.0)


def test_corner_flags_3d_edges_and_vertices():
    lo, hi = np.zeros(3), np.array([0.06, 0.05, 0.04])
    wall = shapes.tank(lo, hi, DX, layers=2, open_top=False)
    corner, tangent = corner_tangents(wall.positions, wall.surface_points, DX)
    outside = (wall.positions < lo) | (wall.positions > hi)
    count = outside.sum(axis=1)
    assert np.array_equal(corner == 1, count >= 2)
    edge = count == 2
    # along an edge the tangent is the one axis the ghost is not outside of
    assert np.allclose(np.abs(tangent[edge]), (~outside[edge]).astype(float))
    assert np.all(tangent[count == 3] == 0.0)


def _physics():
    from seawall.cases import case_by_name

    sim = case_by_name("hydrostatic").build(boundary="ghost-mls1", dx=0.05, threads=1)
    return sim.physics, sim.grid.layout


@pytest.mark.parametrize("corner_xy", [(0.0, 0.0), (0.4, 0.0)])
def test_free_slip_ghosts_continue_a_corner_flow(corner_xy):
    """Every ghost of a closed 2D tank gets the corner flow's value at its own position."""
    prm, layout = _physics()
    lo, hi = np.zeros(2), np.array([0.4, 0.3])
    wall = shapes.tank(lo, hi, DX, layers=3, open_top=False)
    xg = wall.positions
    xm = mirror_points(wall.surface_points, xg)
    c = np.asarray(corner_xy)
    k = 2.0

    def flow(x):
        # stagnation flow into the corner c along the floor and up its wall: u = -k (x - cx), v = k (y - cy)
        return np.stack([-k * (x[:, 0] - c[0]), k * (x[:, 1] - c[1])], axis=1)

    near = np.linalg.norm(xg - c, axis=1) < 0.1   # the ghosts of the two faces and the corner at c
    n = xg.shape[0]
    interp = np.zeros((n, 3))
    interp[:, 0] = prm.p_background
    interp[:, 1:] = flow(xm)
    count = np.ones(n, dtype=np.int64)
    pg, rhog, vg = np.empty(n), np.empty(n), np.zeros((n, 2))
    corner, tangent = corner_tangents(xg, wall.surface_points, DX)
    ghost_transfer(layout, xg, xm, wall.normals, np.zeros((n, 2)), np.zeros((n, 2)), interp, count, prm, False,
                   pg, rhog, vg, corner, tangent)
    assert np.allclose(vg[near], flow(xg[near]), atol=1e-12)
