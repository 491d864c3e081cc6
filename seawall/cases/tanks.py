"""Water in tanks: the hydrostatic tank, the 2D/3D dam breaks and the column collapse.

Fluid settings shared by these cases (literature defaults): Tait EOS with
gamma = 7, artificial viscosity alpha = 0.02 (Marrone et al. 2011),
delta-SPH with delta = 0.1 (Antuono et al. 2010), cubic spline with
h = 1.3 dx, symplectic integrator with CFL 0.2 (Monaghan & Kos 1999).
The speed of sound is 10 times the largest expected speed, sqrt(2 g H)
for a collapsing column of height H (Monaghan 1994), so Mach <= 0.1.
"""

import math

import numpy as np

from .. import probes, shapes
from ..boundary.base import WallSystem
from ..eos import Tait
from ..errors import ParameterError, require_positive
from ..fluid import ArtificialViscosity, DeltaSPH, FluidSystem, MolteniColagrossi, RiemannSolver
from ..integrators import Symplectic
from ..fluid.presets import marrone2011
from ..kernels import CubicSpline
from ..simulation import Simulation
from .base import GRAVITY, Case, Parameter, tank_wall

RHO0 = 1000.0


SCHEMES = ("standard", "marrone2011")


def _scheme(params, c0):
    """(kernel, fluid factory) of the chosen scheme: the cases' standard one or [Huang2019]'s delta-SPH."""
    scheme = params.get("scheme", "standard")
    if scheme not in SCHEMES:
        raise ParameterError(f"scheme must be one of {', '.join(SCHEMES)}; got {scheme!r}")
    if scheme == "marrone2011":
        preset = marrone2011(c0, alpha=params["alpha"], delta=params["delta"])
        return preset.kernel, lambda block, pressure=None: preset.fluid(block, rho0=params["rho0"], pressure=pressure)
    return CubicSpline(), lambda block, pressure=None: _fluid(block, params, c0=c0, pressure=pressure)


def _integrator(params):
    dt = params.get("dt") or None
    return Symplectic(cfl=params["cfl"], dt=dt)


def dam_break_pressure(x, y, L, H, *, rho0=RHO0, c0, g=GRAVITY, n_terms=400):
    """Initial pressure of a water column [0, L] x [0, H] released at t = 0 ([Huang2019] sec. 4.2, eq. 22-24).

    Solves the Laplace problem  lap P = 0,  dP/dy = -rho g at y = 0 (rho = rho0 + P/c0^2,
    the linear EOS), dP/dx = 0 at x = 0, P = 0 at x = L and y = H:

        P = c0^2 sum_n alpha_n cos(lambda_n x) sinh(lambda_n (H - y)),   lambda_n = (n + 1/2) pi / L,
        alpha_n = rho0 g sin(lambda_n L) / [lambda_n (c0^2 lambda_n cosh(lambda_n H) - g sinh(lambda_n H))
                                              (L/2 + sin(2 lambda_n L) / (4 lambda_n))].

    Evaluated with sinh(lambda (H - y)) / cosh(lambda H) written in decaying
    exponentials so that no term overflows.
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    p = np.zeros(np.broadcast(x, y).shape)
    for n in range(n_terms):
        lam = (n + 0.5) * math.pi / L
        norm = 0.5 * L + math.sin(2.0 * lam * L) / (4.0 * lam)
        coef = rho0 * g * math.sin(lam * L) / (lam * (c0 * c0 * lam - g * math.tanh(lam * H)) * norm)
        ratio = (np.exp(-lam * y) - np.exp(-lam * (2.0 * H - y))) / (1.0 + math.exp(-2.0 * lam * H))
        p += c0 * c0 * coef * np.cos(lam * x) * ratio
    return p


#: density-diffusion variants of the standard scheme (case parameter ``diffusion``)
DIFFUSIONS = ("renormalised", "molteni")


def _diffusion(params):
    """The density-diffusion model: delta-SPH with the renormalised gradient (Antuono et al. 2010) or the
    plain Molteni & Colagrossi (2009) term; None when delta = 0."""
    delta = params["delta"]
    kind = params.get("diffusion", "renormalised")
    if kind not in DIFFUSIONS:
        raise ParameterError(f"diffusion must be one of {', '.join(DIFFUSIONS)}; got {kind!r}")
    if delta <= 0:
        return None
    if kind == "molteni":
        return MolteniColagrossi(delta=delta)
    return DeltaSPH(delta=delta, lagged_gradient=params["lagged_gradient"])


def _riemann(params):
    """The Riemann formulation ([Zhang2017]) when the case parameter ``riemann`` is set, else None."""
    if not params.get("riemann", False):
        return None
    if params["alpha"] > 0 or params["delta"] > 0:
        raise ParameterError(f"riemann=true replaces the artificial viscosity and the density diffusion: set "
                             f"alpha=0 and delta=0 (got alpha={params['alpha']:g}, delta={params['delta']:g})")
    return RiemannSolver(eta=params.get("riemann_eta", 3.0))


def _fluid(block, params, *, c0, pressure=None):
    return FluidSystem(block, rho0=params["rho0"], eos=Tait(c0=c0, gamma=7.0),
                       viscosity=ArtificialViscosity(alpha=params["alpha"]) if params["alpha"] > 0 else None,
                       density_diffusion=_diffusion(params),
                       pressure=pressure, riemann=_riemann(params))


def _hydrostatic(depth, rho0, dim):
    """Initial pressure rho0 g (H - y) of still water, y the last axis."""
    def pressure(x):
        return rho0 * GRAVITY * np.maximum(depth - x[:, dim - 1], 0.0)
    return pressure


def _gravity(dim):
    g = [0.0] * dim
    g[-1] = -GRAVITY
    return g


def snap(length, dx):
    """Length rounded to a whole number of particle spacings (tank walls share the fluid's lattice)."""
    return max(1, round(length / dx)) * dx


def _common(params):
    dx = require_positive("dx", params["dx"])
    h = require_positive("h", params["h_factor"] * dx)
    return dx, h


COMMON = {
    "dx": Parameter(None, "particle spacing [m]"),
    "h_factor": Parameter(1.3, "smoothing length h / dx"),
    "c0": Parameter(None, "speed of sound [m/s] (default 10 sqrt(2 g H))"),
    "alpha": Parameter(0.02, "artificial viscosity alpha"),
    "delta": Parameter(0.1, "delta-SPH diffusion coefficient (0 = off)"),
    "cfl": Parameter(0.2, "CFL number"),
    "rho0": Parameter(RHO0, "reference density [kg/m^3]"),
    "lagged_gradient": Parameter(True, "delta-SPH gradient from the previous evaluation (one pass); false = two passes", bool),
}

#: the Riemann formulation of the standard scheme (hydrostatic tank and 2D dam break)
RIEMANN_PARAMETERS = {
    "riemann": Parameter(False, "Riemann formulation of continuity and momentum with the low-dissipation "
                         "limiter ([Zhang2017]; needs alpha=0, delta=0)", bool),
    "riemann_eta": Parameter(3.0, "limiter coefficient eta of the Riemann formulation ([Zhang2017]: 3)"),
}

#: parameters of the cases that can run [Huang2019]'s settings
SEED001 = {
    "scheme": Parameter("standard", "fluid scheme: standard (Tait, cubic spline) or marrone2011 "
                        "([Huang2019]: linear EOS, Gaussian cut at 3h, delta-SPH)", str),
    "dt": Parameter(0.0, "fixed time step [s] (0 = adaptive CFL; [Huang2019] uses 1e-4)"),
}


# ---------------------------------------------------------------- hydrostatic
def build_hydrostatic(params, wall_model, threads):
    """Still water in a tank ([Huang2019], sec. 4.1): probes P0-P3 on the left wall."""
    if params["dx"] is None:
        params["dx"] = 0.01
    dx, h = _common(params)
    depth = require_positive("depth", params["depth"])
    length = require_positive("length", params["length"])
    if depth >= params["height"]:
        raise ParameterError(f"depth ({depth} m) must be below the tank height ({params['height']} m)")
    c0 = params["c0"] or 10.0 * math.sqrt(2 * GRAVITY * depth)
    params["c0"] = c0
    kernel, make_fluid = _scheme(params, c0)
    fluid = make_fluid(shapes.rectangle((0.0, 0.0), (length, depth), dx),
                       pressure=_hydrostatic(depth, params["rho0"], 2) if params["initial"] == "hydrostatic" else None)
    if params["initial"] not in ("hydrostatic", "rest"):
        raise ParameterError(f"initial must be 'hydrostatic' or 'rest', got {params['initial']!r}")
    model = wall_model()
    tank = tank_wall(model, (0.0, 0.0), (snap(length, dx), snap(params["height"], dx)), dx, kernel, h)
    walls = WallSystem(tank, model=model, name="tank")
    sim = Simulation([fluid, walls], kernel=kernel, h=h, gravity=_gravity(2),
                     integrator=_integrator(params), threads=threads)
    for k, y in enumerate((0.0, 0.1, 0.2, 0.25)):
        if y <= depth:
            sim.add(probes.WallPressure(f"P{k}", (0.0, y)))
    sim.add(probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "hydrostatic", "depth": depth, "rho0": params["rho0"], "g": GRAVITY}
    return sim


HYDROSTATIC = Case(
    name="hydrostatic",
    description="still water 0.3 m deep in a 1 m tank, wall pressure probes P0-P3 ([Huang2019] sec. 4.1)",
    builder=build_hydrostatic,
    parameters={**COMMON, **SEED001, **RIEMANN_PARAMETERS,
                "depth": Parameter(0.3, "water depth [m]"),
                "length": Parameter(1.0, "tank length [m]"),
                "height": Parameter(0.4, "tank wall height [m]"),
                "initial": Parameter("hydrostatic", "initial pressure: hydrostatic or rest", str)},
    t_end=2.0, probe_every=2e-3, output_every=0.05)


# ---------------------------------------------------------------- dam break 2D
#: tank height of the dam breaks in H: the experiments' tanks are 2 H high (Lobovsky et
#: al. 2014: 0.6 m for H = 0.3 m). Open, the thin run-up jet goes over the crest (past
#: 1.2 m at 0.79 s at dx = H/50), and what leaves is counted ``overtopped``
#: (docs/overtopping.md); the experiments' pressures are those of the closed tank, so the
#: default tank is closed by a lid (``lid``) at this height.
TANK_HEIGHT = 2.0


def _tank_height(params, H, dx):
    factor = require_positive("tank_height", params["tank_height"])
    if factor <= 1.0:
        raise ParameterError(f"tank_height must exceed 1 (the column height H), got {factor:g}")
    return snap(factor * H, dx)


TANK_PARAMETERS = {
    "tank_height": Parameter(TANK_HEIGHT, "tank wall height / H (2 = the experiments' tank)"),
    "lid": Parameter(True, "close the tank with a lid at tank_height (false: open, the run-up jet goes over its crest)",
                     bool),
}


def build_dam_break(params, wall_model, threads):
    """2D dam break: column 2H x H at the left wall of a tank 5.366 H long, ``tank_height`` H high.

    H = 0.3 m is the "ETSIN" experiment (Lobovsky et al. 2014) used by seed
    003; H = 0.6 m the case of [Huang2019] (Buchner 2002 sensor P1). Sensors on
    the downstream wall: S1-S4 at y = 0.010, 0.050, 0.100, 0.2667 H (the
    experiment's sensors) and P1 at y = 0.2 H.
    """
    H = require_positive("H", params["H"])
    if params["dx"] is None:
        params["dx"] = H / 50.0
    dx, h = _common(params)
    c0 = params["c0"] or 10.0 * math.sqrt(2 * GRAVITY * H)
    params["c0"] = c0
    length = snap(5.366 * H, dx)
    kernel, make_fluid = _scheme(params, c0)
    if params["initial"] not in ("rest", "analytic"):
        raise ParameterError(f"initial must be 'rest' or 'analytic', got {params['initial']!r}")
    pressure = None
    if params["initial"] == "analytic":
        def pressure(x):
            return dam_break_pressure(x[:, 0], x[:, 1], 2.0 * H, H, rho0=params["rho0"], c0=c0)
    fluid = make_fluid(shapes.rectangle((0.0, 0.0), (2.0 * H, H), dx), pressure=pressure)
    model = wall_model()
    tank = tank_wall(model, (0.0, 0.0), (length, _tank_height(params, H, dx)), dx, kernel, h,
                     open_top=not params["lid"])
    walls = WallSystem(tank, model=model, name="tank")
    sim = Simulation([fluid, walls], kernel=kernel, h=h, gravity=_gravity(2),
                     integrator=_integrator(params), threads=threads)
    for name, frac in (("S1", 0.010), ("S2", 0.050), ("S3", 0.100), ("S4", 0.2667), ("P1", 0.2)):
        sim.add(probes.WallPressure(name, (length, frac * H)))
    sim.add(probes.SurgeFront("front"), probes.KineticEnergy(), probes.TotalMass())
    return sim


DAM_BREAK = Case(
    name="dam-break",
    description="2D dam break, column 2H x H in a closed 5.366 H x 2 H tank, wall sensors S1-S4, P1 and surge front",
    builder=build_dam_break,
    parameters={**COMMON, **SEED001, **TANK_PARAMETERS,
                "H": Parameter(0.3, "column height [m] (0.3 ETSIN, 0.6 Buchner)"),
                "diffusion": Parameter("renormalised", "density diffusion of the standard scheme: renormalised "
                                       "(delta-SPH, Antuono et al. 2010) or molteni (Molteni & Colagrossi 2009)",
                                       str),
                **RIEMANN_PARAMETERS,
                "initial": Parameter("rest", "initial pressure: rest (p = 0) or analytic ([Huang2019] sec. 4.2, "
                                     "Laplace-problem series)", str)},
    t_end=1.5, probe_every=5e-4, output_every=0.02)


# ---------------------------------------------------------------- collapse
def build_collapse(params, wall_model, threads):
    """Koshizuka & Oka (1996) column collapse ([Liu2015] sec. 4.4).

    Column a = 0.146 m wide and 2a high (n^2 = 2 in Martin & Moyce's terms)
    in a tank 4a long; probe ``front`` is the x of the foremost particle.
    """
    a = require_positive("width", params["width"])
    if params["dx"] is None:
        params["dx"] = a / 40.0
    dx, h = _common(params)
    height = 2.0 * a
    c0 = params["c0"] or 10.0 * math.sqrt(2 * GRAVITY * height)
    params["c0"] = c0
    kernel = CubicSpline()
    fluid = _fluid(shapes.rectangle((0.0, 0.0), (a, height), dx), params, c0=c0)
    model = wall_model()
    tank = tank_wall(model, (0.0, 0.0), (snap(4.0 * a, dx), snap(2.4 * a, dx)), dx, kernel, h)
    walls = WallSystem(tank, model=model, name="tank")
    sim = Simulation([fluid, walls], kernel=kernel, h=h, gravity=_gravity(2),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads)
    sim.add(probes.SurgeFront("front"), probes.KineticEnergy(), probes.TotalMass())
    sim.reference = {"type": "collapse", "a": a}
    return sim


COLLAPSE = Case(
    name="collapse",
    description="Koshizuka & Oka column collapse, 0.146 x 0.292 m column in a 0.584 m tank, surge front",
    builder=build_collapse,
    parameters={**COMMON, "width": Parameter(0.146, "column width a [m] (height 2a, tank 4a)")},
    t_end=0.5, probe_every=1e-3, output_every=0.01)


# ---------------------------------------------------------------- dam break 3D
def build_dam_break_3d(params, wall_model, threads):
    """3D dam break: column 2H x W x H at the end of a box 5.366 H x W x ``tank_height`` H (W = width_factor H)."""
    H = require_positive("H", params["H"])
    if params["dx"] is None:
        params["dx"] = H / 15.0
    dx, h = _common(params)
    W = require_positive("width_factor", params["width_factor"]) * H
    c0 = params["c0"] or 10.0 * math.sqrt(2 * GRAVITY * H)
    params["c0"] = c0
    length = snap(5.366 * H, dx)
    W = snap(W, dx)
    kernel = CubicSpline()
    fluid = _fluid(shapes.box((0.0, 0.0, 0.0), (2.0 * H, W, H), dx), params, c0=c0)
    model = wall_model()
    tank = tank_wall(model, (0.0, 0.0, 0.0), (length, W, _tank_height(params, H, dx)), dx, kernel, h,
                     open_top=not params["lid"])
    walls = WallSystem(tank, model=model, name="tank")
    sim = Simulation([fluid, walls], kernel=kernel, h=h, gravity=_gravity(3),
                     integrator=Symplectic(cfl=params["cfl"]), threads=threads)
    for name, frac in (("S1", 0.010), ("S3", 0.100), ("P1", 0.2)):
        sim.add(probes.WallPressure(name, (length, 0.5 * W, frac * H)))
    sim.add(probes.SurgeFront("front"), probes.KineticEnergy(), probes.TotalMass())
    return sim


DAM_BREAK_3D = Case(
    name="dam-break-3d",
    description="3D dam break, column 2H x 0.5H x H in a closed 5.366H x 0.5H x 2H box, wall sensors and front",
    builder=build_dam_break_3d,
    parameters={**COMMON, **TANK_PARAMETERS, "H": Parameter(0.3, "column height [m]"),
                "width_factor": Parameter(0.5, "tank width / H")},
    t_end=1.0, probe_every=1e-3, output_every=0.02, dimension=3)
