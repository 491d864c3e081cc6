"""``seawall new-case NAME``: a commented starting case file (Python, or TOML with ``--toml``).

Both templates are a small 2D dam break that runs as written
(``seawall run NAME.py``); the user edits the geometry from there.
"""

import os

from ..errors import ParameterError

PYTHON_TEMPLATE = '''"""{name}: a water column collapsing in a tank (edit me).

Run it with  seawall run {file}  [--boundary MODEL] [--set KEY=VALUE ...]
List its parameters with  seawall cases {file}
"""

import math

import seawall as sw
from seawall.cases import Parameter, tank_wall

# Optional settings (these are the defaults seawall uses when one is left out):
NAME = "{name}"              # the case's name in summary.json and the default output directory
T_END = 1.0                  # simulated time [s] of `seawall run` without --t-end
OUTPUT_EVERY = 0.02          # VTU interval [s]
PROBE_EVERY = 1e-3           # probe sampling interval [s]
DIMENSION = 2
DEFAULT_BOUNDARY = "adami"   # the wall model without --boundary (see `seawall boundaries`)

# Every parameter a user may change with --set KEY=VALUE: default, help, type, unit.
# dx is required; `seawall run --dx` sets it too.
PARAMETERS = {{
    "dx": Parameter(0.01, "particle spacing", float, "m"),
    "H": Parameter(0.2, "height of the water column", float, "m"),
    "length": Parameter(0.8, "tank length", float, "m"),
    "alpha": Parameter(0.02, "artificial viscosity alpha", float),
}}


def build(dx, boundary, H, length, alpha):
    """Return the Simulation. ``boundary()`` gives a fresh wall model of the chosen kind."""
    h = 1.3 * dx
    c0 = 10.0 * math.sqrt(2.0 * 9.81 * H)          # Mach <= 0.1 for the collapse speed sqrt(2 g H)
    column = sw.shapes.rectangle((0.0, 0.0), (H, H), dx)
    fluid = sw.FluidSystem(column, rho0=1000.0, eos=sw.Tait(c0=c0),
                           viscosity=sw.ArtificialViscosity(alpha=alpha),
                           density_diffusion=sw.DeltaSPH(delta=0.1),
                           pressure=lambda x: 1000.0 * 9.81 * (H - x[:, 1]))
    model = boundary()
    kernel = sw.CubicSpline()
    tank_length = round(length / dx) * dx           # the walls continue the fluid lattice
    # wall particles in the layout the model needs (layers for dummy/ghost models, one row for repulsive ones)
    wall = sw.WallSystem(tank_wall(model, (0.0, 0.0), (tank_length, round(2 * H / dx) * dx), dx, kernel, h),
                         model=model, name="tank")
    sim = sw.Simulation([fluid, wall], kernel=kernel, h=h, gravity=(0.0, -9.81))
    sim.add(sw.probes.WallPressure("p_right", (tank_length, 0.2 * H)),
            sw.probes.SurgeFront("front"), sw.probes.KineticEnergy())
    return sim
'''

TOML_TEMPLATE = '''# {name}: a water column collapsing in a tank (edit me).
# Run it with  seawall run {file}  [--boundary MODEL] [--set KEY=VALUE ...]
# List its parameters with  seawall cases {file}
# A number may be written as an expression over the parameters: "2 * H".

[case]
name = "{name}"
description = "water column 2H x H collapsing in a tank"
t_end = 1.0            # [s] without --t-end
output_every = 0.02    # VTU interval [s]
probe_every = 0.001    # probe interval [s]
boundary = "adami"     # wall model without --boundary (see `seawall boundaries`)

[parameters]           # each one is a --set KEY=VALUE; dx is required
dx = {{ default = 0.01, unit = "m", help = "particle spacing" }}
H = {{ default = 0.2, unit = "m", help = "height of the water column" }}
length = {{ default = 0.8, unit = "m", help = "tank length" }}

[fluid]                # Tait EOS (gamma 7), cubic spline, symplectic integrator; each key is a --set parameter
rho0 = 1000.0          # [kg/m^3]
alpha = 0.02           # artificial viscosity
delta = 0.1            # delta-SPH (0 = off)
h_factor = 1.3         # h / dx
cfl = 0.2
# c0 = 20.0            # [m/s]; default 10 sqrt(2 g H), H the highest water top

[tank]                 # the inside of the tank; walls are added around it
lo = [0.0, 0.0]
hi = ["length", "2 * H"]
open_top = true

[[water]]              # one block per [[water]]; pressure = "hydrostatic" or "rest"
lo = [0.0, 0.0]
hi = ["2 * H", "H"]
pressure = "hydrostatic"

[[probe]]              # kinds: wall_pressure, pressure (need point), front, kinetic_energy, mass, wall_force
kind = "wall_pressure"
name = "p_right"
point = ["length", "0.2 * H"]

[[probe]]
kind = "front"
'''


def write_template(name, *, toml=False, force=False):
    """Write the starting file for ``name`` (suffix added if missing); return its path."""
    suffix = ".toml" if toml else ".py"
    path = name if name.endswith(suffix) else name + suffix
    stem = os.path.splitext(os.path.basename(path))[0]
    if not stem or (not toml and not stem.replace("-", "_").isidentifier()):
        raise ParameterError(f"new-case: {name!r} is not usable as a case file name (letters, digits, - and _)")
    if os.path.exists(path) and not force:
        raise ParameterError(f"new-case: {path} exists; give --force to replace it")
    text = (TOML_TEMPLATE if toml else PYTHON_TEMPLATE).format(name=stem, file=path)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return path
