"""The simulation: systems, neighbour grid, integrator and callbacks.

One step is a handful of compiled calls (neighbour sort, equation of state,
each wall's update, the fluid rates, each wall's interaction); Python only
sequences them. Particles that leave the domain or the walls' hull, cross
into a wall or go unstable are removed and recorded (``seawall.health``),
never a crash; a run that blows up -- more than a small fraction of the
fluid removed as damage within a short window, or a state no removal
repairs -- stops with the step, time and particle, keeping its last good
checkpoint and everything already written.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from .boundary.adhesion import add_adhesion
from .boundary.base import EvaluationContext, WallSystem, check_contract
from . import compile_ahead, subnormals
from .coupling import Coupling
from .boundary.particle_forces import defines_particle_forces, part_force, particle_forces
from .diagnostics import REASONS, escaped_by_reason, escaped_where, record_reason
from .errors import InstabilityError, ParameterError, require_positive
from .fluid.edac import edac_pressure_advection_rates, edac_state, edac_wall_diffusion
from .fluid.params import DIFFUSION_NONE, DIFFUSION_RENORMALISED, Physics
from .fluid.rates import equation_of_state, fluid_rates, renormalised_density_gradient, scheme_tag, summation_density
from .fluid.regularisation import (concentration_sums, corrected_vectors, max_speed, surface_lambda,
                                   transport_stress)
from .fluid.system import FluidSystem
from .health import (DAMAGE, DOMAIN, KEEP, OVERTOPPED, UNSTABLE, WALL, _DENSITY, classify_particles, derive_hull,
                     overtopped_mask, parse_guard_settings, parse_hull, reason_name, wall_depth_codes, walls_top)
from .integrators import Integrator, Symplectic
from .jit import PARTICLE_LOOPS, apply_threads, threads_for, use_threads
from .kernels import CubicSpline, Kernel, kernel_shape
from .neighbors import CellGrid, neighbour_pairs
from .output import VTK, Checkpoint
from .probes import Discharge, PressureSensor
from .runner import RunResult, Runner, _progress_bar  # noqa: F401  (RunResult, _progress_bar: their old home)
from .pair_list import PairList, check_skin
from .views import cell_view, fluid_rates_view, fluid_view, pair_view


class Simulation(Runner):
    """A fluid with its walls, ready to run (the run loop is :class:`~seawall.runner.Runner`'s).

    Parameters
    ----------
    systems : list
        One :class:`FluidSystem`, any number of :class:`WallSystem` and of
        :class:`~seawall.coupling.Coupling` (spring-mounted walls, open
        boundaries, ...).
    kernel : Kernel
        Smoothing kernel, default :class:`CubicSpline`.
    h : float
        Smoothing length [m], typically 1.2-1.5 dx.
    gravity : sequence of float
        Body acceleration [m/s^2], length 2 or 3.
    integrator : Integrator
        Default ``Symplectic(cfl=0.2)``.
    domain : (lo, hi), optional
        Box that particles may occupy; those leaving it are removed and
        counted. Default: the particles' bounding box grown by two kernel
        supports, and doubled upwards (the last axis) for splashes.
    periodic : sequence of bool, optional
        Periodic axes of the domain.
    reorder_every : int
        Reorder the fluid particles by cell every this many steps (memory locality).
    density_band : (float, float)
        Fluid particles whose density leaves [lo, hi] x rho0 are removed as
        ``unstable`` (default 0.5, 2).
    hull : "walls", None or (lo, hi)
        Region the fluid may occupy besides the domain box; particles outside
        it are removed as ``domain``. "walls" (default): derived from the
        walls across gravity (``seawall.health``); None: the domain box only;
        a box with None entries for open sides.
    wall_removal_depth : "support", float or None
        Fluid particles deeper than this behind a wall surface are removed as
        ``wall``: "support" (default) = one kernel support, a number = that
        many particle spacings dx, None = never.
    unstable_fraction, unstable_window : float
        The run stops as unstable when the particles removed as ``wall`` or
        ``unstable`` within the last ``unstable_window`` seconds (default
        0.05) exceed ``unstable_fraction`` (default 0.001) of the fluid.
    threads : int, optional
        Number of threads of the compiled loops; set when the first run starts
        (``seawall.jit.use_threads``), not at construction. Default: ``NUMBA_NUM_THREADS`` if
        set in the environment, else one per 4000 fluid and wall particles, at least one and
        at most the cores (``seawall.jit.threads_for``: below that a thread costs more than
        it saves).
    neighbour_skin : float
        The fluid loop reads its pairs from a list of those within (1 + ``neighbour_skin``)
        kernel supports, rebuilt when a particle has moved half the skin or the particles were
        reordered or removed (:mod:`seawall.pair_list`); default 0.1, at most 0.5. 0: the loop
        walks the cells every evaluation. Periodic domains always walk the cells.
    flush_subnormals : bool
        Flush subnormal numbers (below 2.2e-308) to zero while the run's loops work (default
        True; x86-64 only, elsewhere ignored). They arise ahead of every disturbance spreading
        into still fluid, and x86 CPUs are slow on them: the 80k dam break's fluid loop took
        1.35x as long with them on one thread, 1.75x on two (``seawall.subnormals``). The
        results agree to rounding.
    """

    def __init__(self, systems: Sequence[FluidSystem | WallSystem | Coupling], *, kernel: Kernel | None = None,
                 h: float, gravity: Sequence[float] | None = None, integrator: Integrator | None = None,
                 domain: tuple[Sequence[float], Sequence[float]] | None = None,
                 periodic: Sequence[bool] | None = None, reorder_every: int = 20,
                 density_band: tuple[float, float] = (0.5, 2.0), threads: int | None = None,
                 metadata: dict[str, Any] | None = None, hull: str | tuple | None = "walls",
                 wall_removal_depth: str | float | None = "support", unstable_fraction: float = 1e-3,
                 unstable_window: float = 0.05, flush_subnormals: bool = True,
                 neighbour_skin: float = 0.1) -> None:
        fluids = [s for s in systems if isinstance(s, FluidSystem)]
        walls = [s for s in systems if isinstance(s, WallSystem)]
        couplings = [s for s in systems if isinstance(s, Coupling)]
        others = [s for s in systems if not isinstance(s, (FluidSystem, WallSystem, Coupling))]
        if len(fluids) != 1:
            raise ParameterError(f"systems must contain exactly one FluidSystem, got {len(fluids)}")
        if others:
            raise ParameterError(f"unknown system type {type(others[0]).__name__}")
        self.fluid = fluids[0]
        self.walls = walls
        self.couplings = couplings
        self.dim = self.fluid.dim
        names = [w.name for w in walls]
        if len(set(names)) != len(names):
            raise ParameterError(f"wall names must be unique, got {names}")
        coupling_names = [c.name for c in couplings]
        if len(set(coupling_names)) != len(coupling_names):
            raise ParameterError(f"coupling names must be unique, got {coupling_names}")
        for w in walls:
            if w.dim != self.dim:
                raise ParameterError(f"wall {w.name!r} is {w.dim}D but the fluid is {self.dim}D")
        self.kernel = kernel if kernel is not None else CubicSpline()
        if not isinstance(self.kernel, Kernel):
            raise ParameterError(f"kernel must be a seawall kernel, got {self.kernel!r}")
        self.h = require_positive("h", h)
        g = np.zeros(3)
        if gravity is not None:
            gravity = np.asarray(gravity, dtype=np.float64)
            if gravity.shape != (self.dim,):
                raise ParameterError(f"gravity must have {self.dim} components, got {gravity.tolist()}")
            if not np.all(np.isfinite(gravity)):
                raise ParameterError(f"gravity must be finite, got {gravity.tolist()}")
            g[:self.dim] = gravity
        self.gravity = g[:self.dim].copy()
        self.integrator = integrator if integrator is not None else Symplectic()
        if not isinstance(self.integrator, Integrator):
            raise ParameterError(f"integrator must be Symplectic or LeapFrog, got {self.integrator!r}")
        if int(reorder_every) < 1:
            raise ParameterError(f"reorder_every must be >= 1, got {reorder_every}")
        self.reorder_every = int(reorder_every)
        band = tuple(float(b) for b in density_band)
        if len(band) != 2 or not 0.0 <= band[0] < band[1]:
            raise ParameterError(f"density_band must be (lo, hi) with 0 <= lo < hi, got {tuple(density_band)}")
        self.density_band = band
        self.wall_removal_depth, self.unstable_fraction, self.unstable_window = parse_guard_settings(
            wall_removal_depth, unstable_fraction, unstable_window)
        self.hull = parse_hull(hull, self.dim)
        if not isinstance(flush_subnormals, (bool, np.bool_)):
            raise ParameterError(f"flush_subnormals must be True or False, got {flush_subnormals!r}")
        self.flush_subnormals = bool(flush_subnormals)
        if threads is not None:
            import numba

            threads = int(threads)
            if not 1 <= threads <= numba.config.NUMBA_NUM_THREADS:
                raise ParameterError(
                    f"threads must be between 1 and {numba.config.NUMBA_NUM_THREADS}, got {threads}")
            use_threads(threads)   # set when the first run starts, after a compile helper is forked
        elif "NUMBA_NUM_THREADS" not in os.environ:   # nobody chose: by the size of the problem
            use_threads(threads_for(self.particles_per_step()))
        self.metadata = dict(metadata or {})
        #: what the case compares against (set by cases; used by seawall compare)
        self.reference = None
        #: wall name -> force of the fluid on it at the last evaluation [N (per m in 2D)]; filled for
        #: the walls a WallForce probe asks about
        self.wall_forces = {}
        #: wall name -> the acceleration it added to each fluid particle at the last evaluation
        #: [m/s^2]; kept for the walls in ``wall_forces`` (their force is its mass-weighted sum)
        self.wall_accelerations = {}
        #: force of the fluid on each wall particle (seawall.boundary.particle_forces), recorded at the
        #: evaluations the runner asks for (record_particle_forces) for the VTU frames
        self.record_particle_forces = False
        self.wall_particle_forces = {}
        #: {wall name: {(lo, hi): force}} of the WallForce probes given a part of a wall
        self.wall_part_forces = {}
        self._last_context = None

        self.physics = self._compile_physics(g)
        self.grid = self._make_grid(domain, periodic)
        self.pair_list = self._make_pair_list(neighbour_skin)
        self._check_overlap()
        self._check_hull()
        fp = self.fluid.particles
        n = fp.n
        for name, shape in (("dv", (n, self.dim)), ("xsph", (n, self.dim))):
            fp[name] = np.zeros(shape)
        for name in ("drho", "mu_max", "p_over_rho2", "volume"):
            fp[name] = np.zeros(n)
        if self.physics.diffusion == DIFFUSION_RENORMALISED:
            fp["grad_rho"] = np.zeros((n, self.dim))
            if self.physics.lagged_gradient:
                fp["grad_rho_next"] = np.zeros((n, self.dim))
        self._empty_grad = np.zeros((0, self.dim))
        self._empty_scalar = np.zeros(0)
        self._allocate_regularisation()
        self._allocate_edac()
        for wall in self.walls:
            cells = self.grid.build(wall.x)
            wall.particles.permute(cells.order)  # walls sorted once for locality
            wall.cells = self.grid.build(wall.x)
            check_contract(wall.model)
            wall.model.check(self.fluid, self.physics)
            wall.model.prepare(wall, self.fluid, self.physics)
            if wall.model.joins_summation_density and "m" not in wall.particles:
                raise ParameterError(f"wall model {wall.model.name!r} joins the summation density but its "
                                     f"prepare() gave wall {wall.name!r} no masses 'm'")

        self._init_run_state()      # time, step, probes, outputs (seawall.runner)
        self.fluid_cells = None
        self._reordered_at = 0
        self._rates_ready = False
        self.escaped = []           # (time, id, x..., reason) of removed particles
        self.escaped_mass = 0.0
        self.escaped_mass_by_reason = {}   # reason -> removed fluid mass
        for coupling in self.couplings:
            coupling.prepare(self)
        self._check_edac()

    def set_neighbour_skin(self, skin):
        """Use a pair list with this skin (a fraction of the support, see ``neighbour_skin``), or none (0)."""
        self.pair_list = self._make_pair_list(skin)

    def _make_pair_list(self, skin):
        """The fluid loop's :class:`~seawall.pair_list.PairList`, or None (no skin, or a periodic grid)."""
        skin = check_skin(skin)
        if skin == 0.0 or self.grid.periodic_any:
            return None
        return PairList(skin, math.sqrt(self.physics.support2))

    def _fluid_pairs(self, cells):
        """The fluid loop's :class:`~seawall.views.PairView` for this evaluation's positions."""
        if self.pair_list is None:
            return pair_view()
        fp = self.fluid.particles
        return pair_view(*self.pair_list.current(self.grid, cells, fp["x"], fp["id"]))

    # ------------------------------------------------------------------ regularisation
    def _allocate_regularisation(self):
        """Arrays of particle shifting / the transport velocity (seawall.fluid.regularisation)."""
        fluid = self.fluid
        self._regularise = fluid.shifting is not None or fluid.transport_velocity is not None
        #: the time step being taken (the transport velocity's dt / 2 a_b needs it); 0 before the first step
        self._dt_now = 0.0
        if not self._regularise:
            return
        fp = fluid.particles
        n = fp.n
        for name, shape in (("grad_c", (n, self.dim)), ("bmat", (n, 6)), ("lambda", (n,))):
            fp[name] = np.zeros(shape)
        if fluid.transport_velocity is not None:
            fp["bg"] = np.zeros((n, self.dim))
            fp["dv_transport"] = np.zeros((n, self.dim))
            self.background_pressure = fluid.transport_velocity.pressure(fluid.rho0, fluid.eos.c0)
        else:
            self._bg_scratch = np.zeros((n, self.dim))
        self._shift = np.zeros((n, self.dim))
        w_dx = self.physics.sigma * kernel_shape(self.kernel.kind, fluid.spacing / self.h)
        self._inv_w_dx = 1.0 / w_dx if w_dx > 0 else 0.0

    def set_regularisation(self, *, shifting="keep", transport_velocity="keep"):
        """Set the fluid's particle shifting and / or transport velocity (as FluidSystem takes them) on a
        built simulation, before it first runs."""
        from .fluid.regularisation import as_shifting, as_transport_velocity

        if self._rates_ready:
            raise ParameterError("shifting and transport_velocity must be set before the simulation first runs")
        if shifting != "keep":
            self.fluid.shifting = as_shifting(shifting)
        if transport_velocity != "keep":
            self.fluid.transport_velocity = as_transport_velocity(transport_velocity)
        for name in ("grad_c", "bmat", "lambda", "bg", "dv_transport"):
            self.fluid.particles.remove(name)
        self._allocate_regularisation()
        return self

    # ------------------------------------------------------------------ EDAC (seawall.fluid.edac)
    def _allocate_edac(self):
        """dp/dt of an EDAC fluid (its pressure is a variable the integrators advance)."""
        fp = self.fluid.particles
        if self.fluid.edac is not None:
            if "dp" not in fp:
                fp["dp"] = np.zeros(fp.n)
        elif "dp" in fp:
            fp.remove("dp")

    def _check_edac(self):
        """Refuse, in one line, the walls and couplings that cannot work with an EDAC fluid."""
        if self.fluid.edac is None:
            return
        for wall in self.walls:
            reason = getattr(wall.model, "edac_refusal", None)
            if reason:
                raise ParameterError(f"pressure_model=edac does not work with wall model {wall.model.name!r}: {reason}")
        for coupling in self.couplings:
            reason = getattr(coupling, "edac_refusal", None)
            if reason:
                raise ParameterError(f"pressure_model=edac does not work with coupling {coupling.name!r} "
                                     f"({type(coupling).__name__}): {reason}")

    def set_pressure_model(self, pressure_model):
        """Set the fluid's pressure model (None / "eos", "edac" or a :class:`~seawall.fluid.EDAC`) on a built
        simulation, before it first runs."""
        if self._rates_ready:
            raise ParameterError("pressure_model must be set before the simulation first runs")
        before = self.fluid.pressure_model
        self.fluid.set_pressure_model(pressure_model)
        try:
            self._check_edac()
        except ParameterError:
            self.fluid.pressure_model = before
            raise
        g = np.array([self.physics.gx, self.physics.gy, self.physics.gz])
        self.physics = self._compile_physics(g)
        self._allocate_edac()
        return self

    def _edac_walls(self, ctx, drho_fluid):
        """The walls' share of an EDAC fluid's dp/dt: c0^2 times what they added to the continuity rate
        (the divergence term), and the damping term over the walls whose particles carry a pressure."""
        fp = self.fluid.particles
        g = self.grid
        prm = self.physics
        dp = fp["dp"]
        dp += (prm.c0 * prm.c0) * (fp["drho"] - drho_fluid)
        for wall in self._edac_pressure_walls():
            wp = wall.particles
            edac_wall_diffusion(g.layout, fp["x"], fp["m"], fp["volume"], fp["rho"], fp["p"], wall.x,
                                wp["m"] / wp["rho"], wp["rho"], wp["p"], wall.cells.start, wall.cells.order, g.lo,
                                g.inv_cell, g.ncell, g.period, prm, dp)

    def _edac_pressure_walls(self):
        """The walls whose particles carry a pressure an EDAC fluid's pressure sums read (damping, and the
        transport velocity's (v~ - v) . grad p): layered models declaring the pressure term, with p, rho, m."""
        out = []
        for wall in self.walls:
            wp = wall.particles
            if (wall.model.layout != "layers" or "pressure" not in wall.model.fluid_terms
                    or not all(k in wp for k in ("p", "rho", "m"))
                    or wp["p"].shape[0] != wall.n or wp["rho"].shape[0] != wall.n):
                continue
            out.append(wall)
        return out

    def _edac_pressure_advection(self):
        """EDAC with the transport velocity: dp_i/dt += (v~_i - v_i) . grad p_i over the fluid and the walls
        carrying a pressure ([Ramachandran2019] sec. 3; seawall.fluid.edac.edac_pressure_advection_rates)."""
        fp = self.fluid.particles
        g = self.grid
        prm = self.physics
        cells = self.fluid_cells
        dvt = fp["dv_transport"]
        edac_pressure_advection_rates(g.layout, fp["x"], fp["p"], dvt, fp["x"], fp["volume"], fp["p"], cells.start,
                                      cells.order, g.lo, g.inv_cell, g.ncell, g.period, prm, True, fp["dp"])
        for wall in self._edac_pressure_walls():
            wp = wall.particles
            edac_pressure_advection_rates(g.layout, fp["x"], fp["p"], dvt, wall.x, wp["m"] / wp["rho"], wp["p"],
                                          wall.cells.start, wall.cells.order, g.lo, g.inv_cell, g.ncell, g.period,
                                          prm, False, fp["dp"])

    def _fluid_state(self):
        """p (equation of state; EDAC: kept), c, p/rho^2 and m/rho of every fluid particle."""
        fp = self.fluid.particles
        if self.physics.edac:
            edac_state(fp["rho"], fp["m"], fp["p"], self.physics.c0, fp["c"], fp["p_over_rho2"], fp["volume"])
        else:
            equation_of_state(fp["rho"], fp["m"], self.physics, fp["p"], fp["c"], fp["p_over_rho2"], fp["volume"])

    def _wall_volumes(self, wall):
        """V_b = m_b / rho0 of a wall's particles (the lattice volume for layered walls)."""
        vol = getattr(wall, "_regularisation_volume", None)
        if vol is None or vol.shape[0] != wall.n:
            vol = np.ascontiguousarray(wall.particles["m"] / self.physics.rho0)
            wall._regularisation_volume = vol
        return vol

    def _regularisation_walls(self, term):
        return [w for w in self.walls if term in w.model.fluid_terms and "m" in w.particles]

    def _regularisation_sums(self):
        """grad C, B and the background-pressure sum over the fluid and the walls declaring the terms."""
        fp = self.fluid.particles
        g = self.grid
        prm = self.physics
        cells = self.fluid_cells
        shifting = self.fluid.shifting
        R = shifting.R if shifting is not None else 0.2
        nexp = shifting.n if shifting is not None else 4.0
        bg = fp["bg"] if "bg" in fp else self._scratch_vectors("_bg_scratch")
        vol = fp["volume"]
        concentration_sums(g.layout, fp["x"], vol, fp["x"], vol, cells.start, cells.order, g.lo, g.inv_cell,
                           g.ncell, g.period, prm, True, R, nexp, self._inv_w_dx, fp["grad_c"], fp["bmat"], bg)
        term = "shifting" if shifting is not None else "transport_velocity"
        for wall in self._regularisation_walls(term):
            concentration_sums(g.layout, fp["x"], vol, wall.x, self._wall_volumes(wall), wall.cells.start,
                               wall.cells.order, g.lo, g.inv_cell, g.ncell, g.period, prm, False, R, nexp,
                               self._inv_w_dx, fp["grad_c"], fp["bmat"], bg)
        surface_lambda(fp["bmat"], self.dim, fp["lambda"])

    def _scratch_vectors(self, name):
        arr = getattr(self, name, None)
        n = self.fluid.particles.n
        if arr is None or arr.shape[0] != n:
            arr = np.zeros((n, self.dim))
            setattr(self, name, arr)
        return arr

    def _transport_velocity(self, ctx):
        """[Adami2013]: v~ - v = dt/2 a_b into the drift correction, then the extra stress and density terms."""
        fp = self.fluid.particles
        tv = self.fluid.transport_velocity
        g = self.grid
        prm = self.physics
        cells = self.fluid_cells
        dvt = fp["dv_transport"]
        a_b = fp["bg"] / fp["m"][:, None]
        corrected_vectors(a_b, fp["grad_c"], fp["lambda"], -0.5 * self._dt_now * self.background_pressure,
                          tv.lambda_surface, tv.free_surface, dvt)
        ctx.rates.xsph[:] += dvt
        transport_stress(g.layout, fp["x"], fp["v"], fp["rho"], fp["volume"], fp["m"], dvt, fp["x"], fp["v"],
                         fp["rho"], fp["volume"], dvt, cells.start, cells.order, g.lo, g.inv_cell, g.ncell, g.period,
                         prm, True, ctx.rates.dv, ctx.rates.drho)
        for wall in self._regularisation_walls("transport_velocity"):
            vol = self._wall_volumes(wall)
            zero = np.zeros((wall.n, self.dim))     # a wall moves with its own velocity: v~ - v = 0, A_b = 0
            transport_stress(g.layout, fp["x"], fp["v"], fp["rho"], fp["volume"], fp["m"], dvt, wall.x, zero,
                             vol, vol, zero, wall.cells.start, wall.cells.order, g.lo, g.inv_cell, g.ncell,
                             g.period, prm, False, ctx.rates.dv, ctx.rates.drho)
        if prm.edac:
            self._edac_pressure_advection()

    def _apply_shifting(self, dt):
        """After a step: x_i += delta r_i ([Sun2017] / [Lind2012]) from the last evaluation's
        grad C and lambda, with the free-surface correction."""
        fp = self.fluid.particles
        shifting = self.fluid.shifting
        if shifting.kind == "sun2017":
            # CFL Ma (2h)^2 with CFL = c0 dt / h and Ma = U / c0: coefficient * h * U * dt, U = max |v|
            # (taken before the empty-fluid return: in a decomposed run every rank joins the reduction)
            scale = -shifting.coefficient * self.h * self._largest_speed() * dt
        else:
            scale = -shifting.coefficient * self.h * self.h
        if fp.n == 0:
            return
        shift = self._scratch_vectors("_shift")
        corrected_vectors(fp["grad_c"], fp["grad_c"], fp["lambda"], scale, shifting.lambda_surface,
                          shifting.free_surface, shift)
        fp["x"] += shift

    def _largest_speed(self):
        """U = max |v| over the fluid, the Ma of [Sun2017]'s shift (a decomposed run reduces it over ranks)."""
        return max_speed(self.fluid.particles["v"])

    def couple(self, *couplings):
        """Add :class:`~seawall.coupling.Coupling` objects to a built simulation (before it runs)."""
        for coupling in couplings:
            if not isinstance(coupling, Coupling):
                raise ParameterError(f"cannot couple {coupling!r}: expected a seawall.coupling.Coupling")
            if any(c.name == coupling.name for c in self.couplings):
                raise ParameterError(f"coupling names must be unique, {coupling.name!r} is taken")
            if self._rates_ready:
                raise ParameterError("couplings must be added before the simulation first runs")
            self.couplings.append(coupling)
            coupling.prepare(self)
        return self

    # ------------------------------------------------------------------ setup
    def _compile_physics(self, g):
        fluid = self.fluid
        eos = fluid.eos
        h = self.h
        dx = fluid.spacing
        av = fluid.artificial_viscosity
        lam = fluid.laminar_viscosity
        diff = fluid.density_diffusion
        sigma = self.kernel.sigma(h, self.dim)
        w_dx = sigma * kernel_shape(self.kernel.kind, dx / h)
        support = self.kernel.support(h)
        if support < dx:
            raise ParameterError(f"h = {h:g} gives a kernel support of {support:g} m, below the spacing dx = {dx:g}: increase h")
        return Physics(
            dim=self.dim, kernel=self.kernel.kind, h=h, sigma=sigma, support2=support * support,
            eta2=0.01 * h * h, rho0=fluid.rho0, eos=eos.kind, c0=eos.c0, gamma=eos.gamma,
            p_background=eos.background_pressure,
            alpha=av.alpha if av else 0.0, beta=av.beta if av else 0.0,
            nu=lam.nu if lam else 0.0,
            diffusion=diff.kind if diff else DIFFUSION_NONE, delta=diff.delta if diff else 0.0,
            lagged_gradient=1 if getattr(diff, "lagged_gradient", False) else 0,
            tensile=1 if fluid.tensile_correction else 0,
            inv_w_dx=1.0 / w_dx if w_dx > 0 else 0.0, xsph=fluid.xsph,
            gx=float(g[0]), gy=float(g[1]), gz=float(g[2]),
            alpha_all_pairs=1 if getattr(av, "all_pairs", False) else 0,
            riemann=1 if getattr(fluid, "riemann", None) is not None else 0,
            riemann_eta=fluid.riemann.eta if getattr(fluid, "riemann", None) is not None else 3.0,
            edac=1 if getattr(fluid, "edac", None) is not None else 0,
            edac_nu=fluid.edac.viscosity(h, eos.c0) if getattr(fluid, "edac", None) is not None else 0.0)

    def _make_grid(self, domain, periodic):
        support = self.kernel.support(self.h)
        if domain is None:
            allx = [self.fluid.particles["x"]] + [w.x for w in self.walls]
            lo = np.min([a.min(axis=0) for a in allx], axis=0) - 2 * support
            hi = np.max([a.max(axis=0) for a in allx], axis=0) + 2 * support
            hi[-1] += hi[-1] - lo[-1]
        else:
            lo = np.asarray(domain[0], dtype=np.float64)
            hi = np.asarray(domain[1], dtype=np.float64)
            if lo.shape != (self.dim,) or hi.shape != (self.dim,):
                raise ParameterError(f"domain must be (lo, hi) with {self.dim} coordinates each")
        grid = CellGrid(lo, hi, support, periodic)
        outside = ~grid.inside(self.fluid.particles["x"])
        if outside.any():
            k = int(np.argmax(outside))
            raise ParameterError(f"fluid particle {k} at {self.fluid.particles['x'][k].tolist()} lies outside the domain")
        return grid

    def _check_overlap(self):
        dx = self.fluid.spacing
        x = self.fluid.particles["x"]
        for wall in self.walls:
            # exactly 0.5 dx (a wall row on the surface, fluid at the first lattice site) is allowed
            pi, pj = neighbour_pairs(self.grid, x, wall.x, radius=min(0.5 * dx * (1 - 1e-6), self.grid.radius))
            if pi.size:
                k = int(pi[0])
                raise ParameterError(
                    f"fluid overlaps wall {wall.name!r}: fluid particle at {x[k].tolist()} is closer than "
                    f"0.5 dx = {0.5 * dx:g} m to a wall particle; move the fluid block or the wall")

    def _register_probe(self, probe):
        """A probe of the force on a wall names an existing wall; its force is then computed. Probes placed
        on the geometry (PressureSensor) check their place here."""
        wall_name = getattr(probe, "wall", None)
        if wall_name is not None:
            if wall_name not in [w.name for w in self.walls]:
                raise ParameterError(f"probe {probe.name!r}: no wall named {wall_name!r}")
            self.wall_forces.setdefault(wall_name, np.zeros(self.dim))
        if hasattr(probe, "attach"):
            probe.attach(self)

    def wall_moves(self, wall):
        return wall.movement is not None

    # ------------------------------------------------------------------ physics
    def evaluate(self, t):
        """Compute the fluid's rates at time t from the current state."""
        fp = self.fluid.particles
        g = self.grid
        prm = self.physics
        # the arrays of this evaluation's list are reused by the next (see CellGrid.build)
        cells = g.build(fp["x"], reuse=getattr(self, "_evaluation_cells", None))
        self._evaluation_cells = cells
        self.fluid_cells = cells
        if self.fluid.density_mode == "summation":
            rho = fp["rho"]
            summation_density(g.layout, fp["x"], fp["m"], fp["x"], fp["m"], cells.start, cells.order, g.lo,
                              g.inv_cell, g.ncell, g.period, prm, True, rho)
            for wall in self.walls:
                if wall.model.joins_summation_density:
                    summation_density(g.layout, fp["x"], fp["m"], wall.x, wall.particles["m"], wall.cells.start,
                                      wall.cells.order, g.lo, g.inv_cell, g.ncell, g.period, prm,
                                      False, rho)
            # the integrator's density update (zero rate) would put back the density from before the step
            self._summed_rho = rho.copy()
        self._fluid_state()
        ctx = EvaluationContext(physics=prm, grid=g, fluid_cells=cells, time=t, dx=self.fluid.spacing,
                                rates=fluid_rates_view(fp))
        for wall in self.walls:
            if wall.movement is not None and wall.movement.apply(wall, t):
                wall.cells = g.build(wall.x)  # neighbour structures refreshed only while moving
            wall.model.update(wall, self.fluid, ctx)
        lagged = prm.diffusion == DIFFUSION_RENORMALISED and prm.lagged_gradient
        if lagged and not self._rates_ready:
            # the first evaluation of a lagged run needs this state's gradient: a fluid pass (whose
            # rates the one below overwrites) accumulates it, so that the default run never compiles
            # renormalised_density_gradient (about a tenth of its compile time)
            fp["grad_rho"][:] = 0.0
            fluid_rates(fluid_view(fp), cell_view(g, cells), self._fluid_pairs(cells), fp["grad_rho"], prm, ctx.rates,
                        fp["grad_rho_next"],
                        scheme_tag(prm), fp["dp"] if prm.edac else self._empty_scalar)
            fp["grad_rho"], fp["grad_rho_next"] = fp["grad_rho_next"], fp["grad_rho"]
            grad = fp["grad_rho"]
        elif prm.diffusion == DIFFUSION_RENORMALISED and not lagged:
            # exact: this state's gradient
            grad = fp["grad_rho"]
            renormalised_density_gradient(g.layout, fp["x"], fp["rho"], fp["volume"], cells.start, cells.order, g.lo,
                                          g.inv_cell, g.ncell, g.period, prm, grad)
        elif lagged:
            grad = fp["grad_rho"]
        else:
            grad = self._empty_grad
        fluid_rates(fluid_view(fp), cell_view(g, cells), self._fluid_pairs(cells), grad, prm, ctx.rates,
                    fp["grad_rho_next"] if lagged else self._empty_grad, scheme_tag(prm),
                    fp["dp"] if prm.edac else self._empty_scalar)
        if lagged:
            fp["grad_rho"], fp["grad_rho_next"] = fp["grad_rho_next"], fp["grad_rho"]
        drho_fluid = fp["drho"].copy() if prm.edac and self.walls else None
        for wall in self.walls:
            if wall.name in self.wall_forces:
                before = fp["dv"].copy()
                self._wall_acts(wall, ctx)
                added = fp["dv"] - before
                self.wall_accelerations[wall.name] = added
                # force of the fluid on the wall = minus what the wall adds to m_i dv_i (pairwise forms);
                # over the particles this process owns (all of them unless the run is decomposed)
                n = self._owned_rows()
                self.wall_forces[wall.name] = -np.sum(fp["m"][:n, None] * added[:n], axis=0)
                for box in self.wall_part_forces.get(wall.name, ()):   # WallForce(part=...) probes
                    self.wall_part_forces[wall.name][box] = part_force(self, wall, ctx, box)
            else:
                self._wall_acts(wall, ctx)
            if self.record_particle_forces and defines_particle_forces(wall):
                # asked for by the runner when a VTU frame follows this step; scratch arrays only
                self.wall_particle_forces[wall.name] = particle_forces(self, wall, ctx)
        self._last_context = ctx
        if drho_fluid is not None:
            self._edac_walls(ctx, drho_fluid)
        if self._regularise:
            self._regularisation_sums()
            if self.fluid.transport_velocity is not None:
                self._transport_velocity(ctx)
        for coupling in self.couplings:
            coupling.add_rates(self, ctx)
        if self.fluid.density_mode == "summation":
            fp["drho"][:] = 0.0

    def _owned_rows(self):
        """Fluid rows this process owns: every row (a decomposed run keeps halo copies after them)."""
        return self.fluid.particles.n

    def record_particle_forces_now(self):
        """Record the per-particle wall forces of the last evaluation's state, if no step has moved
        the particles since (the frame at t = 0, when the rates were computed before the run)."""
        ctx = self._last_context
        if ctx is None:
            return
        for wall in self.walls:
            if wall.name not in self.wall_particle_forces and defines_particle_forces(wall):
                self.wall_particle_forces[wall.name] = particle_forces(self, wall, ctx)

    def _wall_acts(self, wall, ctx):
        """The wall model's terms, then the wall's adhesion (if any), added to the fluid's rates."""
        fp = self.fluid.particles
        wall.model.interact(self.fluid, wall, ctx, fp["dv"], fp["drho"])
        if wall.adhesion_coefficient > 0.0:
            add_adhesion(wall, self.fluid, ctx, self.kernel.support(self.h), fp["dv"])

    def _maintain(self):
        """Before a step: wrap periodic axes, reorder by cell (removals happen after each step)."""
        fp = self.fluid.particles
        x = fp["x"]
        if np.any(self.grid.period > 0):
            self.grid.wrap(x)
        if fp.n and self._reorder_due():
            fp.permute(self.grid.build(fp["x"]).order)
            self._reordered_at = self.step

    def _reorder_due(self):
        """Every ``reorder_every`` steps; with a pair list, from then on at its next rebuild (a reorder
        makes it rebuild: the two then come together instead of adding rebuilds)."""
        if self.step - self._reordered_at < self.reorder_every and self.step != 0:
            return False
        fp = self.fluid.particles
        return self.pair_list is None or self.pair_list.stale(fp["x"], fp["id"])

    # ------------------------------------------------------------------ guards (seawall.health)
    def _check_hull(self):
        box = self.hull_box()
        if box is None:
            return
        x = self.fluid.particles["x"]
        outside = np.any((x < box[0]) | (x >= box[1]), axis=1)
        if outside.any():
            k = int(np.argmax(outside))
            raise ParameterError(
                f"hull: fluid particle {k} at {x[k].tolist()} lies outside the walls' hull "
                f"(lo {box[0].tolist()}, hi {box[1].tolist()}); give hull=None or a box that holds the fluid")

    def hull_box(self):
        """(lo, hi) of the region outside which fluid counts as ``domain`` (+-inf = open), or None."""
        if self.hull is None:
            return None
        if not isinstance(self.hull, str):
            return self.hull
        moving = any(w.movement is not None for w in self.walls) or bool(self.couplings)
        if moving or not hasattr(self, "_hull_box"):
            self._hull_box = derive_hull(self.walls, self.gravity, self.grid.periodic, self.fluid.spacing)
        return self._hull_box

    def _removal_box(self):
        """The domain box (open along periodic axes) intersected with the hull."""
        dim = self.dim
        lo = np.where(self.grid.period[:dim] > 0, -np.inf, self.grid.lo[:dim])
        hi = np.where(self.grid.period[:dim] > 0, np.inf, self.grid.hi[:dim])
        box = self.hull_box()
        if box is not None:
            lo = np.maximum(lo, box[0])
            hi = np.minimum(hi, box[1])
        return lo, hi

    def _guard_codes(self):
        """Per fluid particle: KEEP, or why it must go (seawall.health codes)."""
        fp = self.fluid.particles
        rho0 = self.physics.rho0
        codes = np.zeros(fp.n, dtype=np.int8)
        lo, hi = self._removal_box()
        classify_particles(fp["x"], fp["v"], fp["rho"], self.density_band[0] * rho0, self.density_band[1] * rho0,
                           lo, hi, codes)
        gone = np.flatnonzero(codes == DOMAIN)
        if gone.size and self.walls:
            over = overtopped_mask(fp["x"][gone], self.walls, self.gravity, self.fluid.spacing,
                                   self.kernel.support(self.h))
            codes[gone[over]] = OVERTOPPED
        if self.wall_removal_depth is not None and self.walls:
            depth = (self.kernel.support(self.h) if self.wall_removal_depth == "support"
                     else self.wall_removal_depth * self.fluid.spacing)
            wall_depth_codes(self, depth, codes, walls_top(self.walls, self.gravity, self.fluid.spacing))
        codes[codes == _DENSITY] = UNSTABLE
        return codes

    def _check_health(self, stop=True):
        """Remove and record the particles the guards reject; stop when the damage is beyond repair.

        Raises InstabilityError when the particles removed as ``wall`` or
        ``unstable`` within the last ``unstable_window`` seconds exceed
        ``unstable_fraction`` of the fluid (with ``stop``).
        """
        fp = self.fluid.particles
        codes = self._guard_codes()
        bad = np.flatnonzero(codes != KEEP)
        if bad.size == 0:
            return
        n_before = fp.n
        damage = bad[(codes[bad] == WALL) | (codes[bad] == UNSTABLE)]
        if stop and damage.size:
            earlier = sum(1 for rec in self.escaped
                          if rec[0] > self.time - self.unstable_window and record_reason(rec, self.dim) in DAMAGE)
            recent = earlier + damage.size
            if recent > self.unstable_fraction * (n_before + earlier):
                self._stop_unstable(damage[0], codes[damage[0]], recent, n_before + earlier)
        for k in bad:
            self.escaped.append((self.time, int(fp["id"][k]), *fp["x"][k].tolist(), reason_name(int(codes[k]))))
        self.escaped_mass += float(fp["m"][bad].sum())
        for code in np.unique(codes[bad]):
            name = reason_name(int(code))
            self.escaped_mass_by_reason[name] = (self.escaped_mass_by_reason.get(name, 0.0)
                                                 + float(fp["m"][bad][codes[bad] == code].sum()))
        fp.keep(codes == KEEP)

    def _stop_unstable(self, bad, code, recent, n_fluid):
        fp = self.fluid.particles
        pid = int(fp["id"][bad])
        pos = fp["x"][bad].tolist()
        checkpoint = None
        for out in self.outputs:
            if isinstance(out, Checkpoint):
                checkpoint = out.last_written
            if isinstance(out, VTK) and out._fluid is not None:
                try:
                    out.write_state(self, "unstable_state.vtu")
                except OSError:
                    pass
        raise InstabilityError(
            f"run became unstable at step {self.step}, t = {self.time:.6g} s: particle id {pid} at "
            f"{[round(c, 6) for c in pos]} has density {fp['rho'][bad]:.6g} kg/m^3 and velocity "
            f"{fp['v'][bad].tolist()} ({'inside a wall' if code == WALL else 'non-finite or outside the density band'}"
            f"; allowed density band {self.density_band[0]:g}-{self.density_band[1]:g} x rho0); "
            f"{recent} of {n_fluid} fluid particles removed as damage within {self.unstable_window:g} s, more than "
            f"unstable_fraction = {self.unstable_fraction:g}"
            + (f"; last good checkpoint: {checkpoint}" if checkpoint else ""),
            step=self.step, time=self.time, particle_id=pid, position=pos, checkpoint=checkpoint)

    # ------------------------------------------------------------------ running
    #: whether the first run of a process may fork a compile helper (seawall.compile_ahead)
    compile_helper = True

    def _initialise(self):
        if not self._rates_ready and self.compile_helper:
            compile_ahead.start(self._rehearsal(), PARTICLE_LOOPS)
        apply_threads()
        # a state given or edited before this run is screened as after a step (a no-op after a restart)
        self._check_health()
        if not self._rates_ready:
            self._maintain()
            self.evaluate(self.time)
            self._rates_ready = True
            self.next_dt = self.integrator.time_step(self.fluid, self.physics)

    def _rehearsal(self):
        """The start of a run as a compile helper rehearses it in its forked copy (seawall.compile_ahead).

        Stages: the first rates, the probes' read-out, one step, the threads' flush switches.
        The particle loops are skipped there, so values computed from their outputs are
        meaningless (a sound speed of zero makes the time step fail); each stage is therefore
        tried on its own. Nothing is written: the copy's outputs are dropped first. The guards
        are left out: the run calls them first, so the helper would only wait for the run's
        compile of their serial loops.
        """
        def rates():
            self.outputs = []
            self.probe_csv = None
            self._check_health = lambda stop=True: None
            self._initialise()

        def probes():
            if self.probes:
                self._probe_row()

        def step():
            dt = getattr(self, "next_dt", None)
            self._one_step(dt if dt is not None and math.isfinite(dt) and dt > 0 else 1e-6)

        def switches():
            # the pool loop that sets the threads' flush switches (seawall.subnormals), which the run
            # calls when its first evaluation is done
            if self.flush_subnormals:
                subnormals.rehearse()
        return rates, probes, step, switches

    def _prepare_probes(self):
        self.fluid_cells = self.grid.build(self.fluid.particles["x"])
        # the equation of state is cheap; it keeps probe pressures consistent with rho (EDAC: p is kept)
        self._fluid_state()

    def _integrate(self, dt):
        self._dt_now = dt
        self.integrator.step(self, dt)
        if self.fluid.density_mode == "summation":
            # keep the step's summed density: the integrators' density updates (drho = 0 here) restore
            # the value from before the step, which left rho, the output pressure and the density guard
            # at the first evaluation's values for the whole run
            np.copyto(self.fluid.particles["rho"], self._summed_rho)
        if self.fluid.shifting is not None:
            self._apply_shifting(dt)

    def _after_step(self, dt):
        for wall in self.walls:
            model = getattr(wall, "model", None)
            if model is not None:
                model.after_step(wall, self.fluid, self)
        for coupling in self.couplings:
            coupling.after_step(self, dt)

    def _time_step(self):
        return self.integrator.time_step(self.fluid, self.physics)

    def particles_per_step(self):
        return self.fluid.particles.n + sum(w.n for w in self.walls)

    def summary(self, *, wall_time, loop_time, particle_steps, steps, startup):
        fp = self.fluid.particles
        mass_now = float(fp["m"].sum())
        initial = self.fluid.initial_mass
        added = float(sum(c.mass_added() for c in self.couplings))  # open boundaries add and remove particles
        return {
            **self.metadata,
            "dimension": self.dim,
            "n_fluid": int(fp.n),
            "n_wall": int(sum(w.n for w in self.walls)),
            "steps": int(self.step),
            "steps_this_run": int(steps),
            "t_end": float(self.time),
            "wall_time_s": float(wall_time),
            "startup_s": float(startup),
            "particle_steps_per_s": float(particle_steps / loop_time) if loop_time > 0 else 0.0,
            "escaped_particles": len(self.escaped),
            "escaped_by_reason": escaped_by_reason(self.escaped, self.dim),
            # the fluid mass removed per reason [kg, kg/m in 2D]: start mass = mass now + these + mass_drift
            "escaped_mass_by_reason": {r: float(self.escaped_mass_by_reason.get(r, 0.0)) for r in REASONS},
            "escaped_where": escaped_where(self.escaped, self.grid, self.hull_box()),
            "mass_drift": float((mass_now + self.escaped_mass - initial - added) / initial),
            "fluid_mass_in_domain_change": float((mass_now - initial) / initial),
            "kernel": self.kernel.name,
            "h": self.h,
            "dx": self.fluid.spacing,
            "walls": {w.name: w.model.describe() for w in self.walls},
            "pressure_model": ({"model": "edac", "alpha": self.fluid.edac.alpha, "nu_edac": self.physics.edac_nu}
                               if self.fluid.edac is not None else {"model": "eos"}),
            **({"sensors": {p.name: p.describe() for p in self.probes if isinstance(p, PressureSensor)}}
               if any(isinstance(p, PressureSensor) for p in self.probes) else {}),
            **({"discharge_sections": {p.name: p.describe() for p in self.probes if isinstance(p, Discharge)}}
               if any(isinstance(p, Discharge) for p in self.probes) else {}),
            "hull": _hull_summary(self.hull_box()),
            # the budget this run stopped by (or would have): --set unstable_fraction / unstable_window
            "damage_budget": {"unstable_fraction": self.unstable_fraction, "unstable_window": self.unstable_window},
            # the fluid loop's pairs: a kept list and how often it was rebuilt, or the cell walk
            "pair_list": self.pair_list.describe() if self.pair_list is not None else {"skin": 0.0},
            **({"couplings": {c.name: {"model": c.describe(), **c.summary()} for c in self.couplings}}
               if self.couplings else {}),
        }

    # ------------------------------------------------------------------ checkpoints
    def _state_arrays(self):
        arrays = {"fluid": self.fluid.particles.as_dict()}
        for wall in self.walls:
            arrays[f"wall_{wall.name}"] = wall.particles.as_dict()
        for coupling in self.couplings:
            arrays[f"coupling_{coupling.name}"] = dict(coupling.arrays())
        # one row per removed particle: time, id, position, reason as its index in REASONS
        rows = [(*rec[:2 + self.dim], float(REASONS.index(record_reason(rec, self.dim)))) for rec in self.escaped]
        arrays["escaped"] = {"records": np.asarray(rows, dtype=np.float64).reshape(len(rows), 3 + self.dim)}
        if self.pair_list is not None and self.pair_list.state():
            arrays["pair_list"] = self.pair_list.state()
        return arrays

    def _state_attrs(self):
        return {"escaped_mass": self.escaped_mass,
                "escaped_mass_by_reason": dict(self.escaped_mass_by_reason),
                "wall_model_state": {w.name: w.model.state() for w in self.walls},
                "coupling_state": {c.name: c.state() for c in self.couplings},
                "n_fluid_initial_mass": self.fluid.initial_mass,
                "reordered_at": self._reordered_at,
                "physics": dict(self.physics._asdict())}

    def _check_state(self, path, arrays, attrs):
        from . import restart_checks as checks

        checks.check_setup(path, attrs, self.metadata, dict(self.physics._asdict()))
        checks.check_clock(path, attrs)
        checks.check_arrays(path, "the fluid", arrays.get("fluid"), self.fluid.particles.as_dict())
        for wall in self.walls:
            key = f"wall_{wall.name}"
            if key in arrays and arrays[key].get("x", np.zeros(0)).shape[:1] == (wall.n,):
                checks.check_arrays(path, f"wall {wall.name!r}", arrays[key], wall.particles.as_dict(),
                                    require_all=False)

    def _load_state(self, path, arrays, attrs):
        for wall in self.walls:
            key = f"wall_{wall.name}"
            if key not in arrays or arrays[key]["x"].shape[0] != wall.n:
                raise ParameterError(f"checkpoint {path} does not match wall {wall.name!r} of this simulation")
            for name, a in arrays[key].items():
                wall.particles[name] = a
            wall.cells = self.grid.build(wall.x)
            wall.model.set_state((attrs.get("wall_model_state") or {}).get(wall.name, {}))
        for coupling in self.couplings:
            coupling.set_state((attrs.get("coupling_state") or {}).get(coupling.name, {}))
            coupling.set_arrays(arrays.get(f"coupling_{coupling.name}", {}))
        fp = self.fluid.particles
        for name in list(fp.names()):
            if name not in arrays["fluid"]:
                raise ParameterError(f"checkpoint {path} lacks fluid array {name!r}")
        new = type(fp)(self.dim)
        for name, a in arrays["fluid"].items():
            new.add(name, a)
        self.fluid.particles = new
        self.escaped_mass = float(attrs["escaped_mass"])
        # checkpoints written before the per-reason masses hold only the total (escaped_mass)
        self.escaped_mass_by_reason = {k: float(v) for k, v in (attrs.get("escaped_mass_by_reason") or {}).items()}
        self.fluid.initial_mass = float(attrs["n_fluid_initial_mass"])
        records = arrays["escaped"]["records"]
        dim = self.dim
        if records.shape[1] == 3 + dim:
            self.escaped = [(r[0], int(r[1]), *r[2:2 + dim].tolist(), REASONS[int(r[2 + dim])]) for r in records]
        else:   # checkpoints before the removal guards: every removal left the domain
            self.escaped = [(r[0], int(r[1]), *r[2:2 + dim].tolist(), "domain") for r in records]
        # checkpoints before the pair list reordered every reorder_every steps counted from 0
        step = int(attrs["step"])
        self._reordered_at = int(attrs.get("reordered_at", step - step % self.reorder_every))
        if self.pair_list is not None:
            self.pair_list.set_state(self.grid, arrays.get("pair_list", {}))
        self._rates_ready = True
        self.fluid_cells = self.grid.build(self.fluid.particles["x"])


def _hull_summary(box):
    """The hull box for summary.json: lo and hi lists with None for open sides, or None."""
    if box is None:
        return None
    return {"lo": [c if math.isfinite(c) else None for c in map(float, box[0])],
            "hi": [c if math.isfinite(c) else None for c in map(float, box[1])]}
