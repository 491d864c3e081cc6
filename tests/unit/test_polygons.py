"""2D walls from outlines (seawall.polygons): layout, surfaces, junctions, refusals; outlines in case files."""

import numpy as np
import pytest

from seawall import shapes
from seawall.errors import ParameterError
from seawall.polygons import polygon_overlap, polygon_wall

DX = 0.02


def _edges_distance(points, pos, skip=()):
    """Distance of each point to the outline's edges other than those in ``skip`` (by index)."""
    pts = np.asarray(points, dtype=float)
    loop = np.vstack([pts, pts[:1]])
    best = np.full(pos.shape[0], np.inf)
    for k, (a, b) in enumerate(zip(loop[:-1], loop[1:])):
        if k in skip:
            continue
        seg = b - a
        t = np.clip(((pos - a) @ seg) / (seg @ seg), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(pos - (a + t[:, None] * seg), axis=1))
    return best


def test_a_container_outline_is_the_closed_tank():
    # a rectangle holding the fluid is a closed tank: the same particles, surface points and normals
    lo, hi = (0.0, 0.0), (0.4, 0.3)
    tank = shapes.tank(lo, hi, DX, layers=3, open_top=False)
    # the tank fills its corner squares; the outline keeps what lies within 3 dx of its surface,
    # which leaves out each corner's farthest point (3.5 sqrt(2) dx, beyond any fluid's support)
    near = np.linalg.norm(tank.surface_points - tank.positions, axis=1) < 3 * DX
    assert np.count_nonzero(~near) == 4
    tank = tank.subset(near)
    outline = polygon_wall([[0, 0], [0.4, 0], [0.4, 0.3], [0, 0.3]], DX, 3, fluid="inside")
    a = np.lexsort(tank.positions.T)
    b = np.lexsort(outline.positions.T)
    assert outline.n == tank.n
    np.testing.assert_allclose(outline.positions[b], tank.positions[a], atol=1e-12)
    np.testing.assert_allclose(outline.surface_points[b], tank.surface_points[a], atol=1e-12)
    np.testing.assert_allclose(outline.normals[b], tank.normals[a], atol=1e-12)
    # layers: floor(distance / dx), as mesh walls count them; the tank counts a corner particle by its
    # largest per-axis index, so the two agree off the corners
    face = np.min(np.abs(tank.normals[a]), axis=1) < 1e-12
    np.testing.assert_array_equal(outline.layer[b][face], tank.layer[a][face])


def test_a_block_has_every_face_and_bisecting_normals_at_its_corners():
    pts = [[0.1, 0.1], [0.3, 0.1], [0.3, 0.22], [0.1, 0.22]]
    w = polygon_wall(pts, DX, 3, fluid="outside")
    pos, sp, nrm = w.positions, w.surface_points, w.normals
    # lattice points inside the block within 3 dx of its outline, nothing else
    inside = np.all((pos > [0.1, 0.1]) & (pos < [0.3, 0.22]), axis=1)
    assert inside.all()
    assert np.all(_edges_distance(pts, pos) < 3 * DX)
    np.testing.assert_allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(nrm, (sp - pos) / np.linalg.norm(sp - pos, axis=1)[:, None], atol=1e-12)
    # normals point out of the block (into the fluid); the particle on a corner's bisector takes the corner
    centre = np.array([0.2, 0.16])
    assert np.all(np.einsum("ij,ij->i", nrm, sp - centre) > 0)
    corner = np.isclose(np.abs(nrm[:, 0]), np.sqrt(0.5)) & np.isclose(np.abs(nrm[:, 1]), np.sqrt(0.5))
    assert corner.sum() == 4 * 3                   # three layers on each corner's bisector
    for c in pts:
        at = np.all(np.isclose(sp[corner], c), axis=1)
        assert at.sum() == 3
    # elsewhere the surface point is the foot on the nearest edge, at the particle's own distance
    d = np.linalg.norm(sp - pos, axis=1)
    np.testing.assert_allclose(d[~corner], _edges_distance(pts, pos[~corner]), atol=1e-12)
    np.testing.assert_array_equal(w.layer, np.minimum(np.floor(_edges_distance(pts, pos) / DX + 1e-9), 2))


def test_an_open_outline_has_no_surface_on_its_closing_segment():
    # a sloped seawall on a floor: toe, crest, back; the material closed along the floor
    pts = [[1.0, 0.0], [1.36, 0.36], [1.5, 0.36], [1.5, 0.0]]
    w = polygon_wall(pts, DX, 3, fluid="left")
    assert np.all(w.surface_points[:, 1] > 1e-9)        # never on the floor segment
    assert np.all(w.positions[:, 1] > 0.0)
    # the crest's particles point up, the slope's up the slope's normal, the back's landwards
    crest = np.isclose(w.surface_points[:, 1], 0.36) & (w.surface_points[:, 0] > 1.37) & (w.surface_points[:, 0] < 1.49)
    np.testing.assert_allclose(w.normals[crest], [[0.0, 1.0]] * int(crest.sum()), atol=1e-12)
    slope = _edges_distance(pts, w.positions, skip=(1, 2, 3)) < _edges_distance(pts, w.positions, skip=(0, 3)) - 1e-9
    np.testing.assert_allclose(w.normals[slope], [[-np.sqrt(0.5), np.sqrt(0.5)]] * int(slope.sum()), atol=1e-12)
    back = np.isclose(w.surface_points[:, 0], 1.5) & (w.surface_points[:, 1] < 0.35)
    assert back.any()
    np.testing.assert_allclose(w.normals[back], [[1.0, 0.0]] * int(back.sum()), atol=1e-12)
    # the same outline with fluid on the right would hold the water in its material: refused
    with pytest.raises(ParameterError, match="reverse the points") as info:
        polygon_wall(pts, DX, 3, fluid="right")
    assert "\n" not in str(info.value)
    # the reversed outline with fluid on the right is the same wall
    r = polygon_wall(pts[::-1], DX, 3, fluid="right")
    assert r.n == w.n


def test_edges_on_a_tank_face_meet_its_walls():
    # a seawall against the tank's end wall: its back edge and foot lie on the tank's faces
    pts = [[1.6, 0.0], [2.32, 0.36], [2.4, 0.36], [2.4, 0.0]]
    free = polygon_wall(pts, DX, 3, fluid="left")
    met = polygon_wall(pts, DX, 3, fluid="left", junction=((0.0, 0.0), (2.4, np.inf)))
    assert np.any(free.normals[:, 0] > 0.99)              # the back faces +x when free
    assert not np.any(met.normals[:, 0] > 0.99)           # ... not when it stands against the tank
    # against the tank the back's own layers are the tank's wall: only the slope's and crest's remain
    assert met.n < free.n
    assert {tuple(p) for p in np.round(met.positions / DX, 6)} <= {tuple(p) for p in np.round(free.positions / DX, 6)}
    np.testing.assert_array_less(_edges_distance(pts, met.positions, skip=(2, 3)), 3 * DX)
    with pytest.raises(ParameterError, match="no edge"):
        polygon_wall([[0, 0], [1, 0], [1, 1], [0, 1]], DX, 3, fluid="outside", junction=((0, 0), (1, 1)))


def test_surface_row_for_repulsive_models():
    pts = [[0.1, 0.1], [0.3, 0.1], [0.3, 0.2], [0.1, 0.2]]
    w = polygon_wall(pts, DX, fluid="outside", layout="surface", beta=2.0)
    # every particle on an edge, spacing dx / 2 along it, each corner once with the bisecting normal
    assert np.all(_edges_distance(pts, w.positions) < 1e-12)
    assert w.n == 2 * (20 + 10)
    corner = np.all(np.isclose(w.positions, [0.3, 0.2]), axis=1)
    assert corner.sum() == 1
    np.testing.assert_allclose(w.normals[corner][0], [np.sqrt(0.5), np.sqrt(0.5)], atol=1e-12)
    # an open outline's closing segment gets no row
    s = polygon_wall([[1.0, 0.0], [1.36, 0.36], [1.5, 0.36], [1.5, 0.0]], DX, fluid="left", layout="surface")
    assert not np.any((s.positions[:, 1] < 1e-12) & (s.positions[:, 0] > 1.0 + 1e-9) & (s.positions[:, 0] < 1.5))


@pytest.mark.parametrize("points, kwargs, match", [
    ([[0, 0], [1, 0]], {}, "at least 3"),
    ([[0, 0], [1, 0], [2, 0]], {}, "crosses itself|encloses|area"),
    ([[0, 0], [1, 1], [1, 0], [0, 1]], {}, "crosses itself"),
    ([[0, 0], [1, 0], [1, 0], [0, 1]], {}, "coincide"),
    ([[0, 0], [1, 0], [0, "a"]], {}, "points"),
    ([[0, 0], [1, 0], [0, float("nan")]], {}, "finite"),
    ([[0, 0], [1, 0], [0, 1]], {"fluid": "above"}, "fluid"),
    ([[0, 0], [1, 0], [0, 1]], {"layout": "dots"}, "layout"),
    ([[0, 0], [1, 0], [0, 1]], {"dx": -1.0}, "dx"),
])
def test_bad_outlines_are_one_line(points, kwargs, match):
    args = {"dx": DX, **kwargs}
    with pytest.raises(ParameterError, match=match) as info:
        polygon_wall(points, **args)
    assert "\n" not in str(info.value)


def test_overlap_is_the_material_and_the_clearance():
    pts = [[1.0, 0.0], [1.36, 0.36], [1.5, 0.36], [1.5, 0.0]]
    fluid = shapes.block((0.0, 0.0), (2.0, 0.3), DX).positions
    covered = polygon_overlap(fluid, pts, fluid="left", clearance=0.5 * DX)
    wall = polygon_wall(pts, DX, 3, fluid="left")
    kept = fluid[~covered]
    # the water kept lies in front of the wall, at least dx / 2 from its surface
    assert shapes.min_distance_between(kept, wall.positions) >= 0.5 * DX
    assert np.all(_edges_distance(pts, kept, skip=(3,)) >= 0.5 * DX * (1 - 1e-9))
    # and the water behind the seawall (landward of its back face) is kept
    assert np.any(kept[:, 0] > 1.5)
    assert not np.any((kept[:, 0] > 1.01) & (kept[:, 0] < 1.49) & (kept[:, 1] < 0.005))


# ------------------------------------------------------------------ outlines in case files

SEAWALL_TOML = """
[case]
name = "seawall"
t_end = 0.02

[parameters]
dx = {default = 0.02, unit = "m"}
crest = {default = 0.36, unit = "m"}

[tank]
lo = [0, 0]
hi = [2.4, "crest"]
open_top = true

[[water]]
lo = [0, 0]
hi = [2.4, 0.2]

[[wall]]
name = "seawall"
points = [[1.6, 0], ["1.6 + 2 * crest", "crest"], [2.4, "crest"], [2.4, 0]]
fluid = "left"
%s

[[probe]]
kind = "wall_force"
name = "seawall_fx"
wall = "seawall"
"""


def _case(tmp_path, extra="", text=None):
    from seawall.cases.toml_case import case_from_toml

    path = tmp_path / "seawall.toml"
    path.write_text(text if text is not None else SEAWALL_TOML % extra)
    return case_from_toml(str(path))


def test_a_seawall_in_a_case_file_is_the_python_outline(tmp_path):
    from seawall.cases import outline_wall
    from seawall.kernels import CubicSpline

    sim = _case(tmp_path).build(boundary="adami")
    names = [w.name for w in sim.walls]
    assert names == ["tank", "seawall"]
    wall = sim.walls[1]
    pts = [[1.6, 0.0], [1.6 + 2 * 0.36, 0.36], [2.4, 0.36], [2.4, 0.0]]   # as the file's expressions
    want = outline_wall(sim.walls[0].model, pts, 0.02, CubicSpline(), 0.026, fluid="left", origin=(0.0, 0.0),
                        inside=((0.0, 0.0), (2.4, np.inf)))
    a, b = np.lexsort(wall.x.T), np.lexsort(want.positions.T)
    np.testing.assert_array_equal(wall.x[a], want.positions[b])
    np.testing.assert_array_equal(wall.particles["normal"][a], want.normals[b])
    # the water is displaced by the seawall: none in its material, none within dx/2 of its surface
    x = sim.fluid.particles["x"]
    assert not polygon_overlap(x, pts, fluid="left", clearance=0.01 * (1 - 1e-9),
                               junction=((0.0, 0.0), (2.4, np.inf))).any()
    assert np.any(x[:, 0] > 1.7)               # in front of the slope's toe the water stays


def test_repulsive_models_get_the_outline_as_a_surface_row(tmp_path):
    sim = _case(tmp_path).build(boundary="monaghan-kajtar")
    wall = sim.walls[1]
    assert np.allclose(wall.x, wall.particles["surface"])


@pytest.mark.parametrize("extra, match", [
    ('layers = 2', "layers must be a whole number >= 3"),
    ('layers = "three"', "layers must be a whole number"),
    ('file = "x.stl"', "not both"),
])
def test_bad_outline_keys_name_the_key(tmp_path, extra, match):
    with pytest.raises(ParameterError, match=match) as info:
        _case(tmp_path, extra).build(boundary="adami")
    assert "\n" not in str(info.value) and "seawall.toml" in str(info.value)


@pytest.mark.parametrize("old, new, match", [
    ('fluid = "left"', 'fluid = "behind"', "fluid must be one of"),
    ('fluid = "left"', 'fluid = "right"', "reverse the points"),
    ('points = [[1.6, 0], ["1.6 + 2 * crest", "crest"], [2.4, "crest"], [2.4, 0]]', 'points = [[1.6, 0], [2, 0]]',
     "at least 3"),
    ('points = [[1.6, 0], ["1.6 + 2 * crest", "crest"], [2.4, "crest"], [2.4, 0]]',
     'points = [[1.6, 0], ["1.6 + 2 * ridge", "crest"], [2.4, "crest"], [2.4, 0]]', "unknown name 'ridge'"),
    ('lo = [0, 0]\nhi = [2.4, "crest"]', 'lo = [0, 0, 0]\nhi = [2.4, 1, "crest"]', "2D outline"),
])
def test_bad_outlines_in_case_files_are_one_line(tmp_path, old, new, match):
    text = SEAWALL_TOML % ""
    assert old in text
    with pytest.raises(ParameterError, match=match) as info:
        _case(tmp_path, text=text.replace(old, new, 1)).build(boundary="adami")
    assert "\n" not in str(info.value)
