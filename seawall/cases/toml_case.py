"""The declarative case file: water blocks in a tank, with probes, read from TOML (``tomllib``).

Layout (every table is described in docs/case-files.md)::

    [case]        name, description, t_end, output_every, probe_every, boundary,
                  unstable_fraction, unstable_window      (the damage budget; each also a --set key)
    [parameters]  NAME = {default = ..., unit = "m", help = "..."}   (dx is required)
    [fluid]       rho0, c0, alpha, delta, h_factor, cfl      (each also a --set parameter)
    [tank]        lo, hi, open_top                             (the interior box; 2 or 3 coordinates)
    [[wall]]      file, name, fluid = "outside" | "inside"     (3D walls from STL/OBJ files, seawall.meshes)
                  points, name, fluid = "outside" | "inside" | "left" | "right", layers
                                                               (2D structures by their outline, seawall.polygons)
    [[water]]     lo, hi | file, pressure = "hydrostatic" | "rest"   (blocks, or fills of closed meshes)
    [[probe]]     kind = wall_pressure | pressure | front | kinetic_energy | mass | wall_force | gauge, name, point,
                  axis, wall, part  (a gauge's point is its horizontal position: [x] in 2D, [x, y] in 3D;
                  a wall_force's part = [lo, hi] is a box of the wall's particles)
    [[probe]]     kind = wall_pressure | pressure | front | kinetic_energy | mass | wall_force, name, point, axis,
                  wall; kind = discharge with start, end | crest, direction

[tank] may be left out when [[wall]] entries bound the water; mesh files are
found relative to the TOML file. 2D outlines displace the water: [[water]]
particles inside a structure or closer than dx/2 to its surface are left out.

A number anywhere in [tank], [[water]] and [[probe]] may instead be a string:
an arithmetic expression over the parameters ("2 * H", "length - 0.1").
The fluid is the tank cases' standard one (Tait EOS, gamma = 7, artificial
viscosity, delta-SPH, cubic spline, symplectic integrator: see
:mod:`seawall.cases.tanks`), so a TOML dam break behaves as ``dam-break``.
"""

import ast
import math
import operator
import os
import tomllib

from ..errors import ParameterError
from .base import GRAVITY, GUARD_KEYS, Case, Parameter, check_guard_settings

#: the [fluid] keys, their defaults (those of seawall.cases.tanks.COMMON) and help
FLUID_KEYS = {
    "rho0": Parameter(1000.0, "reference density [kg/m^3]"),
    "c0": Parameter(None, "speed of sound [m/s] (default 10 sqrt(2 g H), H the highest water top)"),
    "alpha": Parameter(0.02, "artificial viscosity alpha"),
    "delta": Parameter(0.1, "delta-SPH diffusion coefficient (0 = off)"),
    "h_factor": Parameter(1.3, "smoothing length h / dx"),
    "cfl": Parameter(0.2, "CFL number"),
}
CASE_KEYS = {"name", "description", "t_end", "output_every", "probe_every", "boundary",
             "unstable_fraction", "unstable_window"}
TANK_KEYS = {"lo", "hi", "open_top"}
WATER_KEYS = {"lo", "hi", "pressure", "file"}
WALL_KEYS = {"file", "name", "fluid", "points", "layers"}
PROBE_KINDS = ("wall_pressure", "pressure", "front", "kinetic_energy", "mass", "wall_force", "gauge")
PROBE_KEYS = {"kind", "name", "point", "axis", "direction", "wall", "part"}
KINDS = {"float": float, "int": int, "str": str, "bool": bool}
#: the discharge section (seawall.probes.Discharge): points start and end, or crest = a wall's name
PROBE_KINDS += ("discharge",)
PROBE_KEYS |= {"start", "end", "crest"}

_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.Pow: operator.pow, ast.USub: operator.neg, ast.UAdd: operator.pos}
_FUNCS = {"sqrt": math.sqrt, "min": min, "max": max, "abs": abs}


class _Bad(Exception):
    """A problem in the file; turned into one ParameterError line naming the file."""


def evaluate(text, names):
    """Value of the arithmetic expression ``text`` over ``names`` (+ - * / **, sqrt, min, max, abs, pi, g)."""
    env = {"pi": math.pi, "g": GRAVITY, **names}

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return node.value
        if isinstance(node, ast.Name):
            if node.id not in env:
                raise _Bad(f"unknown name {node.id!r} in {text!r} (the parameters: {', '.join(sorted(names))})")
            value = env[node.id]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise _Bad(f"parameter {node.id} in {text!r} is not a number")
            return value
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](ev(node.operand))
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS
                and not node.keywords):
            return _FUNCS[node.func.id](*[ev(a) for a in node.args])
        raise _Bad(f"{text!r} is not an arithmetic expression over the parameters")

    try:
        value = ev(ast.parse(text, mode="eval"))
    except SyntaxError:
        raise _Bad(f"{text!r} is not an arithmetic expression") from None
    except (ZeroDivisionError, OverflowError, ValueError) as exc:
        raise _Bad(f"{text!r} cannot be evaluated: {exc}") from None
    if not math.isfinite(value):
        raise _Bad(f"{text!r} is not finite")
    return float(value)


def _table(data, key, allowed, *, required=False):
    table = data.get(key, {})
    if not isinstance(table, dict):
        raise _Bad(f"[{key}] must be a table")
    if required and not table:
        raise _Bad(f"needs a [{key}] table")
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise _Bad(f"[{key}] has no key {unknown[0]!r}; its keys: {', '.join(sorted(allowed))}")
    return table


def _array_of_tables(data, key, allowed):
    items = data.get(key, [])
    if not isinstance(items, list) or not all(isinstance(t, dict) for t in items):
        raise _Bad(f"{key} must be written [[{key}]] (an array of tables)")
    for k, item in enumerate(items, start=1):
        unknown = sorted(set(item) - set(allowed))
        if unknown:
            raise _Bad(f"[[{key}]] number {k} has no key {unknown[0]!r}; its keys: {', '.join(sorted(allowed))}")
    return items


def _parameters(data):
    table = data.get("parameters", {})
    if not isinstance(table, dict):
        raise _Bad("[parameters] must be a table")
    out = {}
    for name, spec in table.items():
        if not name.isidentifier():
            raise _Bad(f"parameter name {name!r} must be an identifier (letters, digits, _)")
        if name in FLUID_KEYS:
            raise _Bad(f"parameter {name} is a [fluid] key; set its default there")
        if not isinstance(spec, dict):
            spec = {"default": spec}
        unknown = sorted(set(spec) - {"default", "unit", "help", "type"})
        if unknown:
            raise _Bad(f"parameter {name} has no key {unknown[0]!r}; its keys: default, unit, help, type")
        if "default" not in spec:
            raise _Bad(f"parameter {name} needs a default")
        default = spec["default"]
        kind_name = spec.get("type") or ("bool" if isinstance(default, bool) else "int" if isinstance(default, int)
                                         else "str" if isinstance(default, str) else "float")
        if kind_name not in KINDS:
            raise _Bad(f"parameter {name}: type must be one of {', '.join(KINDS)}, got {kind_name!r}")
        if isinstance(default, (list, dict)):
            raise _Bad(f"parameter {name}: the default must be a number, string or boolean")
        out[name] = Parameter(default, str(spec.get("help", "")), KINDS[kind_name], str(spec.get("unit", "")))
    if "dx" not in out:
        raise _Bad("[parameters] must declare dx (the particle spacing [m]), e.g. dx = {default = 0.01, unit = \"m\"}")
    return out


def _fluid_parameters(fluid):
    out = {}
    for key, spec in FLUID_KEYS.items():
        if key in fluid:
            value = fluid[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise _Bad(f"[fluid] {key} must be a number, got {value!r}")
            out[key] = Parameter(float(value), spec.doc)
        else:
            out[key] = spec
    return out


class _Geometry:
    """Numbers and points of the file, evaluated against the resolved parameters."""

    def __init__(self, params):
        self.params = params

    def number(self, where, value):
        if isinstance(value, bool):
            raise _Bad(f"{where} must be a number, got {value!r}")
        if isinstance(value, (int, float)):
            return float(value)
        if isinstance(value, str):
            return evaluate(value, self.params)
        raise _Bad(f"{where} must be a number or an expression, got {value!r}")

    def point(self, where, value, dim=None):
        if not isinstance(value, list) or len(value) not in (2, 3):
            raise _Bad(f"{where} must be a list of 2 or 3 numbers, got {value!r}")
        if dim is not None and len(value) != dim:
            raise _Bad(f"{where} has {len(value)} coordinates, the tank has {dim}")
        return [self.number(f"{where}[{k}]", v) for k, v in enumerate(value)]


def _check_structure(data):
    known = {"case", "parameters", "fluid", "tank", "wall", "water", "probe"}
    unknown = sorted(set(data) - known)
    if unknown:
        raise _Bad(f"unknown table [{unknown[0]}]; the tables: {', '.join(sorted(known))}")
    case = _table(data, "case", CASE_KEYS)
    _table(data, "fluid", FLUID_KEYS)
    walls = _array_of_tables(data, "wall", WALL_KEYS)
    names = {"tank"} if "tank" in data else set()
    for k, w in enumerate(walls, start=1):
        if "points" in w:
            _check_outline(k, w)
        else:
            if not isinstance(w.get("file"), str):
                raise _Bad(f"[[wall]] number {k} needs file = \"NAME.stl\" (a 3D mesh) or points = [[x, y], ...] "
                           "(a 2D outline)")
            if "layers" in w:
                raise _Bad(f"[[wall]] number {k}: layers is a key of 2D outlines (points); a mesh wall takes "
                           "the model's layers")
            if w.get("fluid", "outside") not in ("outside", "inside"):
                raise _Bad(f"[[wall]] number {k}: fluid must be 'outside' (an obstacle) or 'inside' (a container), "
                           f"got {w['fluid']!r}")
        name = _wall_name(k, w)
        if not isinstance(name, str) or name in names:
            raise _Bad(f"[[wall]] number {k}: name {name!r} is taken or not a string (give name = ...)")
        names.add(name)
    tank = _table(data, "tank", TANK_KEYS, required=not walls)
    if tank:
        for key in ("lo", "hi"):
            if key not in tank:
                raise _Bad(f"[tank] needs {key}")
    waters = _array_of_tables(data, "water", WATER_KEYS)
    if not waters:
        raise _Bad("needs at least one [[water]] block")
    for k, w in enumerate(waters, start=1):
        if "file" in w:
            if "lo" in w or "hi" in w:
                raise _Bad(f"[[water]] number {k}: give either file or lo and hi, not both")
            if not isinstance(w["file"], str):
                raise _Bad(f"[[water]] number {k}: file must be a string (a closed .stl or .obj)")
            continue
        for key in ("lo", "hi"):
            if key not in w:
                raise _Bad(f"[[water]] number {k} needs {key} (or file)")
        if w.get("pressure", "hydrostatic") not in ("hydrostatic", "rest"):
            raise _Bad(f"[[water]] number {k}: pressure must be 'hydrostatic' or 'rest', got {w['pressure']!r}")
    for k, p in enumerate(_array_of_tables(data, "probe", PROBE_KEYS), start=1):
        if p.get("kind") not in PROBE_KINDS:
            raise _Bad(f"[[probe]] number {k}: kind must be one of {', '.join(PROBE_KINDS)}, got {p.get('kind')!r}")
        if p["kind"] in ("wall_pressure", "pressure", "gauge") and "point" not in p:
            raise _Bad(f"[[probe]] number {k} ({p['kind']}) needs a point")
        if p["kind"] == "discharge":
            _check_discharge(k, p)
    if not isinstance(tank.get("open_top", True), bool):
        raise _Bad(f"[tank] open_top must be true or false, got {tank['open_top']!r}")
    return case


def _check_discharge(k, p):
    """A discharge probe has start and end, or a crest (and direction only with a crest)."""
    where = f"[[probe]] number {k} (discharge)"
    if "crest" in p:
        if "start" in p or "end" in p:
            raise _Bad(f"{where}: give start and end, or crest, not both")
        if not isinstance(p["crest"], str) or not p["crest"]:
            raise _Bad(f"{where}: crest must be a wall's name, got {p['crest']!r}")
    elif "start" not in p or "end" not in p:
        raise _Bad(f"{where} needs start and end (points), or crest = a wall's name")
    elif "direction" in p:
        raise _Bad(f"{where}: direction goes with crest; with start and end the order of the points gives it")


def _wall_name(k, w):
    """A [[wall]]'s name: given, or its mesh file's stem, or wall_<k> for an outline."""
    if w.get("name"):
        return w["name"]
    return os.path.splitext(os.path.basename(w["file"]))[0] if "file" in w else f"wall_{k}"


def _check_outline(k, w):
    """A 2D [[wall]]: points (a list of [x, y], numbers or expressions), fluid side, layers."""
    from ..polygons import FLUID_SIDES

    where = f"[[wall]] number {k}"
    if "file" in w:
        raise _Bad(f"{where}: give file (a 3D mesh) or points (a 2D outline), not both")
    pts = w["points"]
    if (not isinstance(pts, list) or len(pts) < 3
            or not all(isinstance(q, list) and len(q) == 2 for q in pts)):
        raise _Bad(f"{where}: points must be a list of at least 3 [x, y] pairs, got {pts!r}")
    fluid = w.get("fluid", "outside")
    if fluid not in FLUID_SIDES:
        raise _Bad(f"{where}: fluid must be one of {', '.join(FLUID_SIDES)} (an obstacle, a container, or the "
                   f"side of the outline's direction of travel where the water is), got {fluid!r}")
    layers = w.get("layers")
    if layers is not None and (isinstance(layers, bool) or not isinstance(layers, int) or layers < 1):
        raise _Bad(f"{where}: layers must be a whole number >= 1, got {layers!r}")


def _discharge_probe(geo, k, p, name, dim, wall_names):
    """The Discharge probe of a [[probe]] kind = "discharge" (checked by _check_discharge)."""
    from ..probes import Discharge

    where = f"[[probe]] number {k}"
    if dim != 2 and "crest" in p:
        raise _Bad(f"{where} (discharge): a crest section is 2D; in a {dim}D tank give start and end, the corners "
                   "of a rectangle normal to an axis")
    try:
        if "crest" not in p:
            return Discharge(name, geo.point(f"{where} start", p["start"], dim),
                             geo.point(f"{where} end", p["end"], dim))
        if p["crest"] not in wall_names:
            raise _Bad(f"{where}: crest names no wall, got {p['crest']!r}; the walls: {', '.join(wall_names)}")
        direction = p.get("direction", 1)
        if direction not in (1, -1) or isinstance(direction, bool):
            raise _Bad(f"{where}: direction must be 1 or -1, got {direction!r}")
        return Discharge.over_crest(name, p["crest"], direction=direction)
    except ParameterError as exc:
        raise _Bad(f"{where}: {exc}") from None


def case_from_toml(path):
    """The :class:`Case` of the TOML file at ``path``; ParameterError naming the file on any problem."""
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"case file {path}: invalid TOML: {exc}") from None
    except OSError as exc:
        raise ParameterError(f"case file {path}: cannot be read ({exc.strerror or exc})") from None
    try:
        meta = _check_structure(data)
        parameters = {**_parameters(data), **_fluid_parameters(data.get("fluid", {}))}
        outlines = [k for k, w in enumerate(data.get("wall", []), start=1) if "points" in w]
        mesh_files = [k for k, w in enumerate(data.get("wall", []), start=1) if "points" not in w]
        if "tank" not in data:
            dim = 2 if outlines else 3  # outlines are 2D, mesh walls 3D
        else:
            dim = len(data["tank"]["lo"]) if isinstance(data["tank"]["lo"], list) else 0
        if mesh_files and dim != 3:
            raise _Bad(f"[[wall]] number {mesh_files[0]}: mesh walls are 3D: the tank needs 3 coordinates "
                       "(a 2D structure is given by its outline, points = [[x, y], ...])")
        if outlines and dim != 2:
            raise _Bad(f"[[wall]] number {outlines[0]} is a 2D outline (points): the tank needs 2 coordinates")
        if dim not in (2, 3):
            raise _Bad(f"[tank] lo must be a list of 2 or 3 numbers, got {data['tank']['lo']!r}")
        numbers = {}
        for key in ("t_end", "output_every", "probe_every"):
            if key in meta:
                value = meta[key]
                if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
                    raise _Bad(f"[case] {key} must be a number > 0, got {value!r}")
                numbers[key] = float(value)
        guards = {k: meta[k] for k in GUARD_KEYS if k in meta}
        try:
            check_guard_settings(guards)
        except ParameterError as exc:
            raise _Bad(f"[case] {exc}") from None
        boundary = meta.get("boundary", "adami")
        from ..boundary.registry import BOUNDARIES

        if boundary not in BOUNDARIES:
            raise _Bad(f"[case] boundary {boundary!r} is not a wall model; available: {', '.join(BOUNDARIES)}")
        name = meta.get("name") or os.path.splitext(os.path.basename(path))[0]
        if not isinstance(name, str) or "," in name or "/" in name:
            raise _Bad(f"[case] name must be a string without ',' or '/', got {name!r}")
    except _Bad as exc:
        raise ParameterError(f"case file {path}: {exc}") from None

    folder = os.path.dirname(os.path.abspath(path))

    def builder(params, wall_model, threads):
        try:
            return _build(data, dim, params, wall_model, threads, folder)
        except _Bad as exc:
            raise ParameterError(f"case file {path}: {exc}") from None

    return Case(name=name, description=str(meta.get("description", f"water in a tank ({os.path.basename(path)})")),
                builder=builder, parameters=parameters, dimension=dim, default_boundary=boundary,
                guards={k: float(v) for k, v in guards.items()}, **numbers)


def _horizontal(geo, where, value, dim):
    """A gauge's point: its horizontal coordinates, [x] in 2D, [x, y] in 3D (gravity along the last axis)."""
    if not isinstance(value, list) or len(value) != dim - 1:
        raise _Bad(f"{where} of a gauge is its horizontal position: a list of {dim - 1} number(s) "
                   f"({'[x]' if dim == 2 else '[x, y]'}), got {value!r}")
    return [geo.number(f"{where}[{k}]", v) for k, v in enumerate(value)]


def _mesh_path(folder, name):
    return name if os.path.isabs(name) else os.path.join(folder, name)


def _build(data, dim, params, wall_model, threads, folder="."):
    import numpy as np

    from .. import meshes, polygons, probes, shapes
    from ..boundary.base import WallSystem
    from ..errors import require_positive
    from ..integrators import Symplectic
    from ..kernels import CubicSpline
    from ..simulation import Simulation
    from .base import outline_wall, tank_wall
    from .tanks import _fluid, _gravity, _hydrostatic, snap

    geo = _Geometry(params)
    dx = require_positive("dx", params["dx"])
    h = require_positive("h_factor", params["h_factor"]) * dx
    kernel = CubicSpline()
    tank = data.get("tank")
    lo = hi = None
    wall_systems = []
    if tank:
        lo = geo.point("[tank] lo", tank["lo"], dim)
        hi = geo.point("[tank] hi", tank["hi"], dim)
        if not all(b > a for a, b in zip(lo, hi)):
            raise _Bad(f"[tank] hi {hi} must exceed lo {lo} in every coordinate")
        # the walls continue the fluid's lattice: the tank's sides are whole multiples of dx
        hi = [a + snap(b - a, dx) for a, b in zip(lo, hi)]
        model = wall_model()
        wall_systems.append(WallSystem(tank_wall(model, lo, hi, dx, kernel, h, open_top=tank.get("open_top", True)),
                                       model=model, name="tank"))
    # mesh walls and outlines on the fluid's lattice: origin 0, or the tank's corner when there is a tank
    origin = np.asarray(lo, dtype=float) if lo is not None else np.zeros(dim)
    wall_meshes = [None] * len(wall_systems)
    outlines = []                       # (points, fluid side) of the 2D structures: they displace water
    for k, w in enumerate(data.get("wall", []), start=1):
        name = _wall_name(k, w)
        model = wall_model()
        if "points" in w:
            where = f"[[wall]] number {k}"
            pts = [geo.point(f"{where} points[{j}]", q, 2) for j, q in enumerate(w["points"])]
            fluid_side = w.get("fluid", "outside")
            interior = None
            if tank:
                top = hi[1] if not tank.get("open_top", True) else np.inf
                interior = ((lo[0], lo[1]), (hi[0], top))
            try:
                shape = outline_wall(model, pts, dx, kernel, h, fluid=fluid_side, origin=origin,
                                     layers=w.get("layers"), inside=interior, label=where)
            except ParameterError as exc:
                raise _Bad(str(exc)) from None
            outlines.append((pts, fluid_side, where, interior))
            wall_meshes.append(None)
        else:
            mesh = meshes.load_mesh(_mesh_path(folder, w["file"]))
            shape = meshes.mesh_wall_for_model(model, mesh, dx, kernel, h, fluid=w.get("fluid", "outside"),
                                               origin=origin)
            wall_meshes.append(mesh)
        wall_systems.append(WallSystem(shape, model=model, name=name))
    wall_shapes = [(w.name, shapes.Shape(w.x, w.spacing, normals=w.particles["normal"] if "normal" in w.particles
                                         else None,
                                         surface_points=w.particles["surface"] if "surface" in w.particles else None))
                   for w in wall_systems]
    mesh_walls = [ws for ws, m in zip(wall_shapes, wall_meshes) if m is not None]
    if mesh_walls:
        meshes.check_wall_junctions([(m, n, w) for m, (n, w) in zip(wall_meshes, wall_shapes)])

    blocks = []
    fills = []
    for k, w in enumerate(data["water"], start=1):
        initial = w.get("pressure", "hydrostatic")
        if "file" in w:
            fill = meshes.fill_mesh(_mesh_path(folder, w["file"]), dx, origin=origin, walls=wall_shapes)
            top = float(fill.positions[:, -1].max() + 0.5 * dx)
            bottom = float(fill.positions[:, -1].min() - 0.5 * dx)
            fills.append((fill, top, bottom, initial))
            continue
        wlo = geo.point(f"[[water]] number {k} lo", w["lo"], dim)
        whi = geo.point(f"[[water]] number {k} hi", w["hi"], dim)
        if tank and not all(a >= tl - 1e-12 and b <= th + 1e-12 and b > a
                            for a, b, tl, th in zip(wlo, whi, lo, hi)):
            raise _Bad(f"[[water]] number {k}: the block {wlo} - {whi} must lie inside the tank {lo} - {hi}")
        if not all(b > a for a, b in zip(wlo, whi)):
            raise _Bad(f"[[water]] number {k}: hi {whi} must exceed lo {wlo} in every coordinate")
        for j, (olo, ohi, _) in enumerate(blocks, start=1):
            if all(a < od - 1e-12 and b > oa + 1e-12 for a, b, oa, od in zip(wlo, whi, olo, ohi)):
                raise _Bad(f"[[water]] number {k} overlaps [[water]] number {j}")
        if mesh_walls:
            meshes.check_fill_against_walls(shapes.block(wlo, whi, dx), mesh_walls, meshes.default_clearance(dx),
                                            f"[[water]] number {k}")
        blocks.append((wlo, whi, initial))
    floor = lo[-1] if lo is not None else min([b[0][-1] for b in blocks] + [f[2] for f in fills])
    top = max([b[1][-1] - floor for b in blocks] + [f[1] - floor for f in fills])
    c0 = params["c0"] or 10.0 * (2.0 * GRAVITY * top) ** 0.5
    params["c0"] = c0
    parts = [shapes.block(wlo, whi, dx) for wlo, whi, _ in blocks] + [f[0] for f in fills]
    x = np.concatenate([p.positions for p in parts])
    for pts, fluid_side, where, junction in outlines:
        # the structure displaces the water: its material, and dx/2 in front of its surface
        x = x[~polygons.polygon_overlap(x, pts, fluid=fluid_side, clearance=0.5 * dx, junction=junction, label=where)]
    if x.shape[0] == 0:
        raise _Bad("the structures displace all the water of the [[water]] blocks")
    if len(fills) > 1 or len(blocks) > 1 or (fills and blocks):
        # each block's own hydrostatic column (rest where a block asks for it); fills take their own top
        columns = [(np.asarray(wlo), np.asarray(whi), whi[-1], initial) for wlo, whi, initial in blocks]
        columns += [(f[0].positions.min(axis=0) - 1e-9, f[0].positions.max(axis=0) + 1e-9, f[1], f[3])
                    for f in fills]

        def pressure(pos):
            p = np.zeros(pos.shape[0])
            for cmin, cmax, ctop, initial in columns:
                if initial != "hydrostatic":
                    continue
                inside = np.all((pos >= cmin) & (pos <= cmax), axis=1)
                p[inside] = params["rho0"] * GRAVITY * np.maximum(ctop - pos[inside, dim - 1], 0.0)
            return p
    else:
        only_top, initial = (blocks[0][1][-1], blocks[0][2]) if blocks else (fills[0][1], fills[0][3])
        pressure = _hydrostatic(only_top, params["rho0"], dim) if initial == "hydrostatic" else None
    fluid = _fluid(shapes.Shape(x, dx), {**params, "lagged_gradient": True}, c0=c0, pressure=pressure)
    sim = Simulation([fluid, *wall_systems], kernel=kernel, h=h, gravity=_gravity(dim),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads)
    names = set()
    wall_names = [w.name for w in wall_systems]
    for k, p in enumerate(data.get("probe", []), start=1):
        kind = p["kind"]
        name = p.get("name") or {"front": "front", "kinetic_energy": "kinetic_energy", "mass": "mass"}.get(kind,
                                                                                                            f"{kind}_{k}")
        if name in names:
            raise _Bad(f"[[probe]] number {k}: a second probe named {name!r}")
        names.add(name)
        axis = geo.number(f"[[probe]] number {k} axis", p.get("axis", 0))
        if not (axis == int(axis) and 0 <= axis < dim):   # 0.5 is not an axis: no silent rounding
            raise _Bad(f"[[probe]] number {k}: axis must be 0 .. {dim - 1}, got {p.get('axis')!r}")
        axis = int(axis)
        if "part" in p and kind != "wall_force":
            raise _Bad(f"[[probe]] number {k}: part is a key of wall_force probes, not of {kind}")
        if kind == "wall_pressure":
            sim.add(probes.WallPressure(name, geo.point(f"[[probe]] number {k} point", p["point"], dim)))
        elif kind == "pressure":
            sim.add(probes.Pressure(name, geo.point(f"[[probe]] number {k} point", p["point"], dim)))
        elif kind == "front":
            sim.add(probes.SurgeFront(name, axis=axis, direction=int(geo.number("direction", p.get("direction", 1)))))
        elif kind == "kinetic_energy":
            sim.add(probes.KineticEnergy(name))
        elif kind == "mass":
            sim.add(probes.TotalMass(name))
        elif kind == "gauge":
            try:
                sim.add(probes.FreeSurfaceGauge(name, _horizontal(geo, f"[[probe]] number {k} point", p["point"],
                                                                  dim)))
            except ParameterError as exc:
                raise _Bad(f"[[probe]] number {k}: {exc}") from None
        elif kind == "discharge":
            sim.add(_discharge_probe(geo, k, p, name, dim, wall_names))
        else:
            # without wall = NAME: the first wall, the tank when there is one
            wall = p.get("wall", wall_names[0])
            if wall not in wall_names:
                raise _Bad(f"[[probe]] number {k}: no wall named {wall!r}; the walls: {', '.join(wall_names)}")
            part = None
            if "part" in p:
                box = p["part"]
                if not isinstance(box, list) or len(box) != 2:
                    raise _Bad(f"[[probe]] number {k} part must be a box [[lo], [hi]] (two points), got {box!r}")
                part = [geo.point(f"[[probe]] number {k} part[{j}]", c, dim) for j, c in enumerate(box)]
            try:
                sim.add(probes.WallForce(name, wall, axis=axis, part=part))
            except ParameterError as exc:
                raise _Bad(f"[[probe]] number {k}: {exc}") from None
    return sim
