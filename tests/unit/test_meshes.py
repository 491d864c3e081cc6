"""seawall.meshes: walls and fills from STL/OBJ meshes and 2D polygons, and their checks."""

import math
import re
import sys

import numpy as np
import pytest

from seawall import meshes, shapes
from seawall.errors import ParameterError
from seawall.meshes import TriangleMesh, box_mesh, fill_mesh, fill_polygon, mesh_wall, write_stl

DX = 0.1


def _box_distance(points, lo, hi):
    """Signed distance to the box [lo, hi] (negative inside)."""
    lo, hi = np.asarray(lo), np.asarray(hi)
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    q = np.abs(points - centre) - half
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    return outside + np.minimum(q.max(axis=1), 0.0)


def _rotated_box(lo, hi, angle, label="mesh"):
    box = box_mesh(lo, hi, label=label)
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    centre = 0.5 * (np.asarray(lo) + np.asarray(hi))
    return TriangleMesh((box.vertices - centre) @ rot.T + centre, box.faces, label), rot, centre


# -- walls ---------------------------------------------------------------------------------------

def test_layers_on_a_lattice_face_are_at_half_dx_steps_and_dx_apart():
    lo, hi = [0.0, 0.0, 0.0], [1.0, 0.8, 0.9]
    wall = mesh_wall(box_mesh(lo, hi), DX, layers=3, fluid="outside")
    depth = -_box_distance(wall.positions, lo, hi)          # inside the obstacle
    assert np.all(depth > 0.0) and depth.max() < 3 * DX
    # on the face x = 0: layer L at (L + 1/2) dx behind it, neighbours dx apart
    face = np.abs(wall.normals[:, 0] + 1.0) < 1e-12
    assert set(np.round(wall.positions[face, 0] / DX, 9)) == {0.5, 1.5, 2.5}
    assert np.array_equal(np.round(wall.positions[face, 0] / DX - 0.5).astype(int), wall.layer[face])
    first = wall.positions[face & (wall.layer == 0)]
    # the face's 8 x 9 cells; those as near to another face (the obstacle's medial planes) may go to it
    assert 6 * 7 <= first.shape[0] <= 8 * 9
    others = np.array([np.sort(np.linalg.norm(first - p, axis=1))[1] for p in first])
    assert np.allclose(others, DX)
    assert np.allclose(np.linalg.norm(wall.normals, axis=1), 1.0)


def test_a_mesh_tank_is_the_tank_of_shapes_where_it_has_particles():
    lo, hi = [0.0, 0.0, 0.0], [1.0, 0.6, 0.5]
    mesh = box_mesh(lo, hi, inward=True, open_top=True)
    wall = mesh_wall(mesh, DX, layers=3, fluid="inside")
    # the closed tank below its lid: the mesh's open rim is no crest (an open shapes.tank's side walls
    # are thicker, with a crest and a back face of their own)
    tank = shapes.tank(lo, hi, DX, layers=3, open_top=False)
    tank = tank.subset(tank.positions[:, 2] < hi[2])
    key = {tuple(k): i for i, k in enumerate(np.round(tank.positions / DX * 2).astype(int))}
    rows = [key[tuple(k)] for k in np.round(wall.positions / DX * 2).astype(int)]   # KeyError: not in the tank
    assert np.allclose(wall.surface_points, tank.surface_points[rows], atol=1e-12)
    assert np.allclose(wall.normals, tank.normals[rows], atol=1e-12)
    # the tank's particles the mesh wall leaves out are its outer corners, beyond layers * dx
    missing = np.setdiff1d(np.arange(tank.n), rows)
    dist = np.linalg.norm(tank.positions[missing] - tank.surface_points[missing], axis=1)
    assert dist.min() >= 3 * DX
    # nothing above the open top's rim (the side walls stop at the last fluid row, as the tank's)
    assert wall.positions[:, 2].max() == pytest.approx(0.45)


def test_normals_point_into_the_fluid_for_obstacles_and_containers():
    lo, hi = [0.0, 0.0, 0.0], [0.4, 0.3, 0.5]
    for fluid, mesh, sign in (("outside", box_mesh(lo, hi), 1.0),
                              ("inside", box_mesh(lo, hi, inward=True), -1.0)):
        wall = mesh_wall(mesh, DX, layers=2, fluid=fluid)
        ahead = wall.surface_points + 0.01 * DX * wall.normals
        # a step along the normal from the surface goes into the fluid: outside the box for the obstacle
        assert np.all(sign * _box_distance(ahead, lo, hi) > 0.0)
        assert np.all(sign * _box_distance(wall.positions, lo, hi) < 0.0)   # particles in the material


def test_layer_depth_on_a_tilted_obstacle():
    mesh, rot, centre = _rotated_box([0.0, 0.0, 0.0], [0.8, 0.6, 0.5], math.radians(30.0))
    for layers in (1, 2, 3):
        wall = mesh_wall(mesh, DX, layers=layers, origin=[0.013, 0.029, 0.0])
        local = (wall.positions - centre) @ rot               # back into the box frame
        depth = -_box_distance(local + [0.4, 0.3, 0.25], [0.0, 0.0, 0.0], [0.8, 0.6, 0.5])
        d = np.linalg.norm(wall.positions - wall.surface_points, axis=1)
        # the closest surface point is exact; a particle as near to 2 or 3 faces (the box's medial
        # planes) takes the edge or corner they meet at: d = depth sqrt(2) or sqrt(3)
        ratio = d / depth
        tied = ~np.isclose(ratio, 1.0, rtol=1e-9)     # (a point midway between opposite faces keeps one)
        assert np.allclose(ratio[tied], np.sqrt(np.round(ratio[tied] ** 2)), rtol=1e-9)
        assert set(np.round(ratio[tied] ** 2)) <= {2.0, 3.0} and tied.mean() < 0.3
        assert depth.max() < layers * DX
        assert np.array_equal(np.minimum(np.floor(d / DX + 1e-9).astype(int), layers - 1), wall.layer)
        assert set(wall.layer) == set(range(layers))


def test_surface_row_lies_on_the_surface_at_the_wall_spacing():
    lo, hi = [0.0, 0.0, 0.0], [0.6, 0.4, 0.5]
    beta = 2.0
    wall = mesh_wall(box_mesh(lo, hi), DX, fluid="outside", layout="surface", beta=beta)
    assert np.allclose(_box_distance(wall.positions, lo, hi), 0.0, atol=1e-12)
    ds = DX / beta
    assert wall.spacing == pytest.approx(ds)
    area = 2 * (0.6 * 0.4 + 0.6 * 0.5 + 0.4 * 0.5)
    # cell centres of every face at spacing ds, and one row along every edge and corner
    edges = 4 * (0.6 + 0.4 + 0.5)
    assert wall.n == round(area / ds ** 2 + edges / ds + 8)


# -- fills ---------------------------------------------------------------------------------------

def test_fill_of_a_lattice_box_is_the_block():
    lo, hi = [0.0, 0.0, 0.0], [0.4, 0.6, 0.3]
    fill = fill_mesh(box_mesh(lo, hi), DX)
    block = shapes.block(lo, hi, DX)
    assert fill.n == block.n == round(0.4 * 0.6 * 0.3 / DX ** 3)
    assert np.array_equal(np.sort(np.round(fill.positions / DX * 2), axis=0),
                          np.sort(np.round(block.positions / DX * 2), axis=0))


@pytest.mark.parametrize("clearance", [None, 0.0, 0.08])
def test_fill_clearance_and_count_off_the_lattice(clearance):
    lo, hi = np.array([0.013, 0.027, 0.041]), np.array([0.613, 0.427, 0.541])
    fill = fill_mesh(box_mesh(lo, hi), DX, clearance=clearance)
    c = 0.5 * DX if clearance is None else clearance
    d = -_box_distance(fill.positions, lo, hi)
    assert d.min() >= c - 1e-12
    # every lattice point at least c inside is there: the count is that of the box shrunk by c
    axes = [(np.arange(int(l / DX) - 1, int(h / DX) + 2) + 0.5) * DX for l, h in zip(lo, hi)]
    expected = np.prod([np.sum((a >= l + c - 1e-12) & (a <= h - c + 1e-12)) for a, l, h in zip(axes, lo, hi)])
    assert fill.n == expected
    # close to volume / dx^3: within one layer of cells over the surface
    volume, area = 0.6 * 0.4 * 0.5, 2 * (0.6 * 0.4 + 0.6 * 0.5 + 0.4 * 0.5)
    assert abs(fill.n - volume / DX ** 3) <= area / DX ** 2 * (0.5 + c / DX)


def test_fill_of_a_tilted_box_is_inside_and_clear():
    mesh, rot, centre = _rotated_box([0.0, 0.0, 0.0], [0.8, 0.6, 0.5], math.radians(30.0))
    fill = fill_mesh(mesh, 0.05)
    local = (fill.positions - centre) @ rot + [0.4, 0.3, 0.25]
    d = -_box_distance(local, [0.0, 0.0, 0.0], [0.8, 0.6, 0.5])
    assert d.min() >= 0.025 - 1e-12
    # the volume the particles stand for is that of the box shrunk by the clearance, within a cell layer
    shrunk = 0.75 * 0.55 * 0.45
    area = 2 * (0.75 * 0.55 + 0.75 * 0.45 + 0.55 * 0.45)
    assert abs(fill.n * 0.05 ** 3 - shrunk) <= area * 0.05


def test_polygon_fill_square_and_l_shape():
    square = fill_polygon([(0, 0), (0.6, 0), (0.6, 0.4), (0, 0.4)], DX)
    assert square.n == 24 and np.array_equal(square.positions, shapes.rectangle([0, 0], [0.6, 0.4], DX).positions)
    ell = [(0, 0), (0.6, 0), (0.6, 0.2), (0.2, 0.2), (0.2, 0.6), (0, 0.6)]
    fill = fill_polygon(ell, DX)
    assert fill.n == round((0.6 * 0.2 + 0.2 * 0.4) / DX ** 2)
    assert not np.any((fill.positions[:, 0] > 0.2) & (fill.positions[:, 1] > 0.2))   # the notch stays empty
    clockwise = fill_polygon(ell[::-1], DX)                # either orientation
    assert clockwise.n == fill.n


def test_polygon_fill_of_a_triangle_keeps_the_clearance():
    tri = np.array([(0.0, 0.0), (1.0, 0.0), (0.0, 0.7)])
    fill = fill_polygon(tri, 0.02, clearance=0.03)
    _, d = shapes._closest_on_polyline(fill.positions, np.vstack([tri, tri[:1]]))
    assert d.min() >= 0.03 - 1e-12
    inside = (fill.positions[:, 0] > 0) & (fill.positions[:, 1] > 0) & (
        fill.positions[:, 0] / 1.0 + fill.positions[:, 1] / 0.7 < 1.0)
    assert inside.all()
    perimeter = 1.0 + 0.7 + math.hypot(1.0, 0.7)
    # the triangle shrunk by 0.03 on every side, within one row of cells along its perimeter
    r = 0.35 / (0.5 * perimeter)                             # inradius: area / semi-perimeter
    shrunk = 0.35 * ((r - 0.03) / r) ** 2
    assert abs(fill.n * 0.02 ** 2 - shrunk) <= perimeter * 0.02


# -- files and errors ----------------------------------------------------------------------------

def test_stl_and_obj_files_round_trip(tmp_path):
    box = box_mesh([0.0, 0.0, 0.0], [0.4, 0.3, 0.2])
    stl = write_stl(tmp_path / "box.stl", box)
    obj = tmp_path / "box.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in box.vertices)
                   + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in box.faces))
    for path in (stl, obj):
        mesh = meshes.load_mesh(path)
        assert mesh.watertight and mesh.faces.shape == (12, 3)
        assert mesh.signed_volume == pytest.approx(0.4 * 0.3 * 0.2)
        assert mesh_wall(mesh, DX, 2).n == mesh_wall(box, DX, 2).n
    scaled = meshes.load_mesh(stl, scale=1000.0, offset=[1.0, 0.0, 0.0])
    assert np.allclose(scaled.bounds[1], [401.0, 300.0, 200.0])


def test_missing_file_is_one_line(tmp_path):
    with pytest.raises(ParameterError, match=r"mesh file .*nothing\.stl: no such file"):
        meshes.load_mesh(tmp_path / "nothing.stl")
    with pytest.raises(ParameterError, match="must be an .stl or .obj file"):
        meshes.load_mesh(tmp_path / "box.ply")


def test_trimesh_missing_names_the_extra(tmp_path, monkeypatch):
    path = write_stl(tmp_path / "box.stl", box_mesh([0, 0, 0], [1, 1, 1]))
    monkeypatch.setitem(sys.modules, "trimesh", None)      # import trimesh now raises ImportError
    with pytest.raises(ParameterError) as err:
        meshes.load_mesh(path)
    message = str(err.value)
    assert "\n" not in message and "box.stl" in message and "pip install seawall[geometry]" in message


def test_fill_refuses_an_open_mesh(tmp_path):
    path = write_stl(tmp_path / "open.stl", box_mesh([0, 0, 0], [1, 1, 1], open_top=True))
    with pytest.raises(ParameterError, match=r"open\.stl: not watertight \(4 open edges\); a fluid fill"):
        fill_mesh(path, DX)


def test_inverted_normals_are_refused(tmp_path):
    inward = write_stl(tmp_path / "pillar.stl", box_mesh([0, 0, 0], [0.3, 0.3, 1], inward=True))
    with pytest.raises(ParameterError, match=r"pillar\.stl: inverted normals: .* point into the solid"):
        mesh_wall(inward, DX, fluid="outside")
    outward = write_stl(tmp_path / "tank.stl", box_mesh([0, 0, 0], [1, 1, 1], open_top=True))
    with pytest.raises(ParameterError, match=r"tank\.stl: inverted normals: .* out of the container"):
        mesh_wall(outward, DX, fluid="inside")


def test_inconsistent_winding_and_bad_meshes_are_refused():
    box = box_mesh([0, 0, 0], [1, 1, 1])
    faces = box.faces.copy()
    faces[3] = faces[3, ::-1]                               # one face wound the other way
    with pytest.raises(ParameterError, match="not consistently oriented"):
        TriangleMesh(box.vertices, faces, "mesh file flipped.stl")
    with pytest.raises(ParameterError, match="shared by 3 faces"):
        TriangleMesh(box.vertices, np.vstack([box.faces, box.faces[:1, ::-1]]))
    with pytest.raises(ParameterError, match="fluid must be 'outside'"):
        mesh_wall(box, DX, fluid="above")


def test_fill_overlapping_a_wall_is_refused():
    pillar = mesh_wall(box_mesh([0.5, 0.2, 0.0], [0.7, 0.4, 0.5]), DX, 3)
    tank = shapes.tank([0.0, 0.0, 0.0], [1.0, 0.6, 0.5], DX, 3)
    good = fill_mesh(box_mesh([0.0, 0.0, 0.0], [0.4, 0.6, 0.3]), DX, walls=[("tank", tank), ("pillar", pillar)])
    assert good.n == 72
    with pytest.raises(ParameterError, match="column: the fluid fill overlaps wall pillar"):
        fill_mesh(box_mesh([0.0, 0.0, 0.0], [0.6, 0.6, 0.3], label="column"), DX, walls=[("pillar", pillar)])
    # a fill deep inside a wall, on a lattice offset so no particle is near a wall particle
    deep = box_mesh([0.55, 0.25, 0.05], [0.65, 0.35, 0.45], label="inside")
    with pytest.raises(ParameterError, match="inside: the fluid fill overlaps wall pillar"):
        fill_mesh(deep, DX, origin=[0.05, 0.05, 0.05], clearance=0.0, walls=[("pillar", pillar)])
    with pytest.raises(ParameterError, match="polygon: the fluid fill overlaps wall floor"):
        fill_polygon([(0, -0.2), (1, -0.2), (1, 0.5), (0, 0.5)], DX,
                     walls=[("floor", shapes.tank([0, 0], [1, 1], DX, 3))])


# -- seawall geometry ------------------------------------------------------------------------------

def test_geometry_command_writes_the_wall_as_vtu(tmp_path, capsys):
    from seawall.cli import main
    from seawall.io.vtk import read_vtu

    path = write_stl(tmp_path / "pillar.stl", box_mesh([0.5, 0.2, 0.0], [0.7, 0.4, 0.5]))
    out = tmp_path / "pillar.vtu"
    assert main(["geometry", str(path), "--dx", "0.05", "--layers", "2", "--out", str(out)]) == 0
    line = capsys.readouterr().out.strip()
    assert line.endswith(f"{4 * 4 * 10} wall particles in 2 layers -> {out}")   # 4 cells wide: all of it
    points, fields = read_vtu(out)
    wall = mesh_wall(path, 0.05, 2)
    assert np.allclose(points, wall.positions)
    assert np.allclose(fields["normal"], wall.normals) and np.array_equal(fields["layer"], wall.layer)


def test_geometry_command_bad_mesh_is_one_line_and_exit_2(tmp_path, capsys):
    from seawall.cli import main

    path = write_stl(tmp_path / "tank.stl", box_mesh([0, 0, 0], [1, 1, 1], open_top=True))
    assert main(["geometry", str(path), "--dx", "0.1", "--fluid", "inside"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("seawall: error: mesh file") and "tank.stl: inverted normals" in err and "\n" not in err
    assert main(["geometry", str(tmp_path / "none.obj"), "--dx", "0.1"]) == 2
    assert "none.obj: no such file" in capsys.readouterr().err


def test_toml_wall_tables_are_checked(tmp_path):
    from seawall.cases.toml_case import case_from_toml

    base = '[parameters]\ndx = 0.1\n[[water]]\nlo = [0, 0, 0]\nhi = [0.3, 0.3, 0.3]\n'
    cases = {
        '[[wall]]\nname = "pillar"\n': "[[wall]] number 1 needs file",
        '[[wall]]\nfile = "p.stl"\nfluid = "above"\n': "fluid must be 'outside'",
        '[[wall]]\nfile = "p.stl"\n[[wall]]\nfile = "p.stl"\n': "name 'p' is taken",
        '[tank]\nlo = [0, 0]\nhi = [1, 1]\n[[wall]]\nfile = "p.stl"\n': "mesh walls are 3D",
    }
    for extra, message in cases.items():
        path = tmp_path / "case.toml"
        path.write_text(base + extra)
        with pytest.raises(ParameterError, match=rf"case file .*case\.toml: .*{re.escape(message)}"):
            case_from_toml(str(path))
    path.write_text('[parameters]\ndx = 0.1\n[[wall]]\nfile = "p.stl"\n[[water]]\nfile = "c.stl"\nlo = [0, 0, 0]\n')
    with pytest.raises(ParameterError, match="either file or lo and hi"):
        case_from_toml(str(path))


def test_sphere_from_trimesh_fill_and_wall(tmp_path):
    import trimesh                               # in the [test] extra
    path = tmp_path / "ball.stl"
    trimesh.creation.icosphere(subdivisions=3, radius=0.5).export(path)
    mesh = meshes.load_mesh(path)
    assert mesh.watertight and mesh.signed_volume > 0
    dx = 0.05
    fill = fill_mesh(mesh, dx, clearance=0.0)
    area = 4 * math.pi * 0.5 ** 2
    # a cell per lattice point inside: the volume within one layer of cells over the surface
    assert abs(fill.n * dx ** 3 - mesh.signed_volume) <= area * dx / 2
    clear = fill_mesh(mesh, dx)
    assert np.linalg.norm(clear.positions, axis=1).max() <= 0.5 - 0.5 * dx + 1e-9
    wall = mesh_wall(mesh, dx, 3)
    r = np.linalg.norm(wall.positions, axis=1)
    assert r.max() < 0.5 and r.min() > 0.5 - 3 * dx - 0.01          # 0.01: the facets sit inside the sphere
    assert np.all(np.einsum("ij,ij->i", wall.normals, wall.surface_points) > 0)   # outward, into the fluid


def test_a_face_covered_by_another_wall_is_refused():
    tank = shapes.tank([0.0, 0.0, 0.0], [1.0, 0.6, 0.6], DX, 3, open_top=False)
    closed = box_mesh([0.5, 0.2, 0.0], [0.7, 0.4, 0.5], label="mesh file pillar.stl")
    walls = [(None, "tank", tank), (closed, "pillar", mesh_wall(closed, DX, 3))]
    with pytest.raises(ParameterError, match=r"pillar\.stl: 2 faces of wall pillar are covered by wall tank"):
        meshes.check_wall_junctions(walls)
    open_foot = box_mesh([0.5, 0.2, 0.0], [0.7, 0.4, 0.5], open_bottom=True)
    meshes.check_wall_junctions([(None, "tank", tank), (open_foot, "pillar", mesh_wall(open_foot, DX, 3))])
    # a tank drawn as a mesh: its floor under the pillar is not all covered, so it stays
    box = box_mesh([0.0, 0.0, 0.0], [1.0, 0.6, 0.6], inward=True)
    meshes.check_wall_junctions([(box, "tank", mesh_wall(box, DX, 3, fluid="inside")),
                                 (open_foot, "pillar", mesh_wall(open_foot, DX, 3))])


def test_fill_beside_a_convex_edge_is_not_an_overlap():
    # fluid dx/2 in front of a pillar's faces, up to its edges: nearest wall particles may belong to
    # the other face at the edge (the obstacle's medial planes); that is no overlap
    pillar = mesh_wall(box_mesh([0.5, 0.2, 0.0], [0.7, 0.4, 0.5], open_bottom=True), DX, 3)
    fill = shapes.block([0.3, 0.0, 0.0], [0.9, 0.6, 0.3], DX)
    fill = fill.subset(_box_distance(fill.positions, [0.5, 0.2, -1.0], [0.7, 0.4, 0.5]) > 0.0)
    meshes.check_fill_against_walls(fill, [("pillar", pillar)], 0.5 * DX)
    assert fill.n == 6 * 6 * 3 - 2 * 2 * 3
