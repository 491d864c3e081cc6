"""The declarative case file: water blocks in a tank, with probes, read from TOML (``tomllib``).

Layout (every table is described in docs/case-files.md)::

    [case]        name, description, t_end, output_every, probe_every, boundary
    [parameters]  NAME = {default = ..., unit = "m", help = "..."}   (dx is required)
    [fluid]       rho0, c0, alpha, delta, h_factor, cfl      (each also a --set parameter)
    [tank]        lo, hi, open_top                             (the interior box; 2 or 3 coordinates)
    [[water]]     lo, hi, pressure = "hydrostatic" | "rest"    (one or more blocks)
    [[probe]]     kind = wall_pressure | pressure | front | kinetic_energy | mass | wall_force, name, point, axis

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
from .base import GRAVITY, Case, Parameter

#: the [fluid] keys, their defaults (those of seawall.cases.tanks.COMMON) and help
FLUID_KEYS = {
    "rho0": Parameter(1000.0, "reference density [kg/m^3]"),
    "c0": Parameter(None, "speed of sound [m/s] (default 10 sqrt(2 g H), H the highest water top)"),
    "alpha": Parameter(0.02, "artificial viscosity alpha"),
    "delta": Parameter(0.1, "delta-SPH diffusion coefficient (0 = off)"),
    "h_factor": Parameter(1.3, "smoothing length h / dx"),
    "cfl": Parameter(0.2, "CFL number"),
}
CASE_KEYS = {"name", "description", "t_end", "output_every", "probe_every", "boundary"}
TANK_KEYS = {"lo", "hi", "open_top"}
WATER_KEYS = {"lo", "hi", "pressure"}
PROBE_KINDS = ("wall_pressure", "pressure", "front", "kinetic_energy", "mass", "wall_force")
PROBE_KEYS = {"kind", "name", "point", "axis", "direction"}
KINDS = {"float": float, "int": int, "str": str, "bool": bool}

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
    known = {"case", "parameters", "fluid", "tank", "water", "probe"}
    unknown = sorted(set(data) - known)
    if unknown:
        raise _Bad(f"unknown table [{unknown[0]}]; the tables: {', '.join(sorted(known))}")
    case = _table(data, "case", CASE_KEYS)
    _table(data, "fluid", FLUID_KEYS)
    tank = _table(data, "tank", TANK_KEYS, required=True)
    for key in ("lo", "hi"):
        if key not in tank:
            raise _Bad(f"[tank] needs {key}")
    waters = _array_of_tables(data, "water", WATER_KEYS)
    if not waters:
        raise _Bad("needs at least one [[water]] block")
    for k, w in enumerate(waters, start=1):
        for key in ("lo", "hi"):
            if key not in w:
                raise _Bad(f"[[water]] number {k} needs {key}")
        if w.get("pressure", "hydrostatic") not in ("hydrostatic", "rest"):
            raise _Bad(f"[[water]] number {k}: pressure must be 'hydrostatic' or 'rest', got {w['pressure']!r}")
    for k, p in enumerate(_array_of_tables(data, "probe", PROBE_KEYS), start=1):
        if p.get("kind") not in PROBE_KINDS:
            raise _Bad(f"[[probe]] number {k}: kind must be one of {', '.join(PROBE_KINDS)}, got {p.get('kind')!r}")
        if p["kind"] in ("wall_pressure", "pressure") and "point" not in p:
            raise _Bad(f"[[probe]] number {k} ({p['kind']}) needs a point")
    if not isinstance(tank.get("open_top", True), bool):
        raise _Bad(f"[tank] open_top must be true or false, got {tank['open_top']!r}")
    return case


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
        dim = len(data["tank"]["lo"]) if isinstance(data["tank"]["lo"], list) else 0
        if dim not in (2, 3):
            raise _Bad(f"[tank] lo must be a list of 2 or 3 numbers, got {data['tank']['lo']!r}")
        numbers = {}
        for key in ("t_end", "output_every", "probe_every"):
            if key in meta:
                value = meta[key]
                if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
                    raise _Bad(f"[case] {key} must be a number > 0, got {value!r}")
                numbers[key] = float(value)
        boundary = meta.get("boundary", "adami")
        from ..boundary.registry import BOUNDARIES

        if boundary not in BOUNDARIES:
            raise _Bad(f"[case] boundary {boundary!r} is not a wall model; available: {', '.join(BOUNDARIES)}")
        name = meta.get("name") or os.path.splitext(os.path.basename(path))[0]
        if not isinstance(name, str) or "," in name or "/" in name:
            raise _Bad(f"[case] name must be a string without ',' or '/', got {name!r}")
    except _Bad as exc:
        raise ParameterError(f"case file {path}: {exc}") from None

    def builder(params, wall_model, threads):
        try:
            return _build(data, dim, params, wall_model, threads)
        except _Bad as exc:
            raise ParameterError(f"case file {path}: {exc}") from None

    return Case(name=name, description=str(meta.get("description", f"water in a tank ({os.path.basename(path)})")),
                builder=builder, parameters=parameters, dimension=dim, default_boundary=boundary,
                **numbers)


def _build(data, dim, params, wall_model, threads):
    from .. import probes, shapes
    from ..boundary.base import WallSystem
    from ..errors import require_positive
    from ..integrators import Symplectic
    from ..kernels import CubicSpline
    from ..simulation import Simulation
    from .base import tank_wall
    from .tanks import _fluid, _gravity, _hydrostatic, snap

    geo = _Geometry(params)
    dx = require_positive("dx", params["dx"])
    h = require_positive("h_factor", params["h_factor"]) * dx
    tank = data["tank"]
    lo = geo.point("[tank] lo", tank["lo"], dim)
    hi = geo.point("[tank] hi", tank["hi"], dim)
    if not all(b > a for a, b in zip(lo, hi)):
        raise _Bad(f"[tank] hi {hi} must exceed lo {lo} in every coordinate")
    # the walls continue the fluid's lattice: the tank's sides are whole multiples of dx
    hi = [a + snap(b - a, dx) for a, b in zip(lo, hi)]
    blocks = []
    top = 0.0
    for k, w in enumerate(data["water"], start=1):
        wlo = geo.point(f"[[water]] number {k} lo", w["lo"], dim)
        whi = geo.point(f"[[water]] number {k} hi", w["hi"], dim)
        if not all(a >= tl - 1e-12 and b <= th + 1e-12 and b > a for a, b, tl, th in zip(wlo, whi, lo, hi)):
            raise _Bad(f"[[water]] number {k}: the block {wlo} - {whi} must lie inside the tank {lo} - {hi}")
        for j, (olo, ohi, _) in enumerate(blocks, start=1):
            if all(a < od - 1e-12 and b > oa + 1e-12 for a, b, oa, od in zip(wlo, whi, olo, ohi)):
                raise _Bad(f"[[water]] number {k} overlaps [[water]] number {j}")
        blocks.append((wlo, whi, w.get("pressure", "hydrostatic")))
        top = max(top, whi[-1] - lo[-1])
    c0 = params["c0"] or 10.0 * (2.0 * GRAVITY * top) ** 0.5
    params["c0"] = c0
    parts = []
    for wlo, whi, initial in blocks:
        block = shapes.block(wlo, whi, dx)
        depth = whi[-1]
        pressure = _hydrostatic(depth, params["rho0"], dim) if initial == "hydrostatic" else None
        parts.append((block, pressure))
    positions = [b.positions for b, _ in parts]
    import numpy as np

    x = np.concatenate(positions) if len(positions) > 1 else positions[0]
    fluid_shape = shapes.Shape(x, dx)
    if len(parts) == 1:
        pressure = parts[0][1]
    else:
        # each block's own hydrostatic column (rest where a block asks for it)
        def pressure(pos):
            p = np.zeros(pos.shape[0])
            for (wlo, whi, initial) in blocks:
                if initial != "hydrostatic":
                    continue
                inside = np.all((pos >= np.asarray(wlo)) & (pos <= np.asarray(whi)), axis=1)
                p[inside] = params["rho0"] * GRAVITY * np.maximum(whi[-1] - pos[inside, dim - 1], 0.0)
            return p
    fluid = _fluid(fluid_shape, {**params, "lagged_gradient": True}, c0=c0, pressure=pressure)
    kernel = CubicSpline()
    model = wall_model()
    walls = WallSystem(tank_wall(model, lo, hi, dx, kernel, h, open_top=tank.get("open_top", True)),
                       model=model, name="tank")
    sim = Simulation([fluid, walls], kernel=kernel, h=h, gravity=_gravity(dim),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads)
    names = set()
    for k, p in enumerate(data.get("probe", []), start=1):
        kind = p["kind"]
        name = p.get("name") or {"front": "front", "kinetic_energy": "kinetic_energy", "mass": "mass"}.get(kind,
                                                                                                            f"{kind}_{k}")
        if name in names:
            raise _Bad(f"[[probe]] number {k}: a second probe named {name!r}")
        names.add(name)
        axis = int(geo.number(f"[[probe]] number {k} axis", p.get("axis", 0)))
        if not 0 <= axis < dim:
            raise _Bad(f"[[probe]] number {k}: axis must be 0 .. {dim - 1}, got {axis}")
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
        else:
            sim.add(probes.WallForce(name, "tank", axis=axis))
    return sim
