"""``dem-box``: DEM discs (spheres in 3D) falling into a box of DEM wall particles and coming to rest."""

import numpy as np

from .. import shapes
from ..dem import DEMKineticEnergy, DEMSimulation, DEMSystem, DEMWall, LowestBottom, MaxOverlap
from ..errors import ParameterError, require_positive
from .base import GRAVITY, Case, Parameter


def build_dem_box(params, wall_model, threads):
    """A lattice of elements (jittered) above the floor of an open box; gravity along the last axis.

    The box's walls are one row of DEM wall particles on its surface at spacing
    ``radius`` (wall particles of radius radius / 2), so the floor a disc rests
    on is the wall row + radius / 2. ``--boundary`` does not apply: DEM walls act
    on DEM elements by contact.
    """
    dim = params["dimension"]
    if dim not in (2, 3):
        raise ParameterError(f"dimension must be 2 or 3, got {dim}")
    r = require_positive("radius", params["radius"])
    width = require_positive("width", params["width"])
    height = require_positive("height", params["height"])
    nx, nz = params["columns"], params["layers"]
    if nx < 1 or nz < 1:
        raise ParameterError("columns and layers must be >= 1")
    pitch = 2.6 * r
    if nx * pitch > width - r:
        raise ParameterError(f"{nx} columns of pitch {pitch:g} m do not fit in width {width} m: lower columns")
    rng = np.random.default_rng(params["seed"])
    base = 0.5 * r + r + params["drop_height"]
    if base + nz * pitch > height:
        raise ParameterError(f"{nz} layers do not fit below height {height} m: lower layers or drop_height")
    across = 0.5 * (width - (nx - 1) * pitch) + np.arange(nx) * pitch
    up = base + np.arange(nz) * pitch
    if dim == 2:
        pts = np.array([(x, y) for y in up for x in across])
    else:
        pts = np.array([(x, z, y) for y in up for x in across for z in across])
    pts[:, :-1] += rng.uniform(-0.2 * r, 0.2 * r, size=pts[:, :-1].shape)   # break the symmetry
    elements = DEMSystem(pts, r, density=params["density"], normal_stiffness=params["normal_stiffness"],
                         restitution=params["restitution"], name="discs")
    hi = (width,) * (dim - 1) + (height,)
    wall = DEMWall(shapes.tank_surface((0.0,) * dim, hi, r), params["wall_stiffness"], name="box")
    g = [0.0] * dim
    g[-1] = -GRAVITY
    sim = DEMSimulation([elements, wall], gravity=g, threads=threads)
    sim.add(DEMKineticEnergy(), LowestBottom(), MaxOverlap())
    # what "at rest" is measured against: the potential energy the elements can lose at most
    m = elements.particles["m"]
    floor = 0.5 * r + r
    sim.metadata["potential_energy_drop_bound"] = float(np.sum(m * GRAVITY * (pts[:, -1] - floor)))
    sim.metadata["floor_surface"] = 0.5 * r
    return sim


DEM_BOX = Case(
    name="dem-box",
    description="DEM discs (spheres in 3D) fall into a box of DEM wall particles and come to rest ([TrixiBoundary] DEM walls)",
    builder=build_dem_box,
    parameters={
        "dimension": Parameter(2, "2 (discs) or 3 (spheres)", int),
        "radius": Parameter(0.005, "element radius [m]"),
        "width": Parameter(0.15, "box width [m]"),
        "height": Parameter(0.3, "box height [m]"),
        "columns": Parameter(10, "elements across", int),
        "layers": Parameter(10, "layers of elements", int),
        "drop_height": Parameter(0.05, "gap between the floor and the lowest layer [m]"),
        "density": Parameter(2500.0, "material density [kg/m^3]"),
        "normal_stiffness": Parameter(1e6, "element-element spring constant [N/m, per metre in 2D]"),
        "wall_stiffness": Parameter(1e6, "DEM wall normal_stiffness [N/m, per metre in 2D]"),
        "restitution": Parameter(0.5, "coefficient of restitution"),
        "seed": Parameter(1, "random seed of the lattice jitter", int),
    },
    t_end=1.5,
    probe_every=0.01,
    output_every=0.02,
)
