"""The simulation: systems, neighbour grid, integrator and callbacks.

One step is a handful of compiled calls (neighbour sort, equation of state,
each wall's update, the fluid rates, each wall's interaction); Python only
sequences them. Particles that leave the domain are removed and counted,
never a crash; a run that blows up stops with the step, time and particle,
keeping its last good checkpoint and everything already written.
"""

import math
import sys
import time as _time

import numpy as np
from numba import njit

from .boundary.adhesion import add_adhesion
from .boundary.base import EvaluationContext, WallSystem, check_contract
from .coupling import Coupling
from .diagnostics import escaped_where
from .errors import InstabilityError, ParameterError, require_positive
from .fluid.params import DIFFUSION_NONE, DIFFUSION_RENORMALISED, Physics
from .fluid.rates import equation_of_state, fluid_rates, renormalised_density_gradient, summation_density
from .fluid.system import FluidSystem
from .integrators import Integrator, Symplectic
from .kernels import CubicSpline, Kernel, kernel_shape
from .neighbors import CellGrid, neighbour_pairs
from .output import VTK, Checkpoint
from .probes import Probe
from .sampling import LineSampler
from .views import cell_view, fluid_rates_view, fluid_view


@njit(cache=True)
def first_bad_particle(x, v, rho, rho_lo, rho_hi):
    """Index of the first particle with a non-finite state or density outside [rho_lo, rho_hi], else -1."""
    for i in range(x.shape[0]):
        r = rho[i]
        if not (r >= rho_lo and r <= rho_hi):
            return i
        for k in range(x.shape[1]):
            if not (np.isfinite(x[i, k]) and np.isfinite(v[i, k])):
                return i
    return -1


class RunResult:
    """What :meth:`Simulation.run` returns: probe series as arrays and a summary dict."""

    def __init__(self, times, probes, summary, escaped):
        self.times = times
        self.probes = probes
        self.summary = summary
        self.escaped = escaped

    def __getitem__(self, name):
        return self.probes[name]

    def __repr__(self):
        return f"RunResult(steps={self.summary.get('steps')}, probes={list(self.probes)})"


class Simulation:
    """A fluid with its walls, ready to run.

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
        A run is unstable when any density leaves [lo, hi] x rho0 (default 0.5, 2).
    threads : int, optional
        Number of threads of the compiled loops (default: all cores).
    """

    def __init__(self, systems, *, kernel=None, h, gravity=None, integrator=None, domain=None,
                 periodic=None, reorder_every=20, density_band=(0.5, 2.0), threads=None,
                 metadata=None):
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
            g[:self.dim] = gravity
        self.gravity = g[:self.dim].copy()
        self.integrator = integrator if integrator is not None else Symplectic()
        if not isinstance(self.integrator, Integrator):
            raise ParameterError(f"integrator must be Symplectic or LeapFrog, got {self.integrator!r}")
        if int(reorder_every) < 1:
            raise ParameterError(f"reorder_every must be >= 1, got {reorder_every}")
        self.reorder_every = int(reorder_every)
        self.density_band = (float(density_band[0]), float(density_band[1]))
        if threads is not None:
            import numba

            threads = int(threads)
            if not 1 <= threads <= numba.config.NUMBA_NUM_THREADS:
                raise ParameterError(
                    f"threads must be between 1 and {numba.config.NUMBA_NUM_THREADS}, got {threads}")
            numba.set_num_threads(threads)
        self.metadata = dict(metadata or {})
        #: what the case compares against (set by cases; used by seawall compare)
        self.reference = None
        #: wall name -> force of the fluid on it at the last evaluation [N (per m in 2D)]; filled for
        #: the walls a WallForce probe asks about
        self.wall_forces = {}

        self.physics = self._compile_physics(g)
        self.grid = self._make_grid(domain, periodic)
        self._check_overlap()
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

        self.time = 0.0
        self.step = 0
        self.next_dt = None
        self.fluid_cells = None
        self._rates_ready = False
        self.escaped = []           # (time, id, x...) of removed particles
        self.escaped_mass = 0.0
        self.probes = []
        self.outputs = []
        self.probe_times = []
        self.probe_values = []
        self.probe_every = None
        self._next_probe = 0.0
        self.probe_csv = None
        for coupling in self.couplings:
            coupling.prepare(self)

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
            gx=float(g[0]), gy=float(g[1]), gz=float(g[2]))

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

    def add(self, *items, every=None):
        """Add probes and outputs (:class:`~seawall.output.VTK`, :class:`~seawall.output.Checkpoint`).

        ``every`` sets the probe sampling interval [s] (default t_end / 1000).
        """
        for item in items:
            if isinstance(item, Probe):
                if any(p.name == item.name for p in self.probes):
                    raise ParameterError(f"two probes are named {item.name!r}")
                wall_name = getattr(item, "wall", None)
                if wall_name is not None:
                    if wall_name not in [w.name for w in self.walls]:
                        raise ParameterError(f"probe {item.name!r}: no wall named {wall_name!r}")
                    self.wall_forces.setdefault(wall_name, np.zeros(self.dim))
                self.probes.append(item)
            elif isinstance(item, (VTK, Checkpoint, LineSampler)):
                self.outputs.append(item)
            else:
                raise ParameterError(f"cannot add {item!r}: expected a probe, VTK, Checkpoint or LineSampler")
        if every is not None:
            self.probe_every = require_positive("every", every)
        return self

    def wall_moves(self, wall):
        return wall.movement is not None

    # ------------------------------------------------------------------ physics
    def evaluate(self, t):
        """Compute the fluid's rates at time t from the current state."""
        fp = self.fluid.particles
        g = self.grid
        prm = self.physics
        cells = g.build(fp["x"])
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
        equation_of_state(fp["rho"], fp["m"], prm, fp["p"], fp["c"], fp["p_over_rho2"], fp["volume"])
        ctx = EvaluationContext(physics=prm, grid=g, fluid_cells=cells, time=t, dx=self.fluid.spacing,
                                rates=fluid_rates_view(fp))
        for wall in self.walls:
            if wall.movement is not None and wall.movement.apply(wall, t):
                wall.cells = g.build(wall.x)  # neighbour structures refreshed only while moving
            wall.model.update(wall, self.fluid, ctx)
        lagged = prm.diffusion == DIFFUSION_RENORMALISED and prm.lagged_gradient
        if prm.diffusion == DIFFUSION_RENORMALISED and (not lagged or not self._rates_ready):
            # exact: this state's gradient (also the first evaluation of a lagged run)
            grad = fp["grad_rho"]
            renormalised_density_gradient(g.layout, fp["x"], fp["rho"], fp["volume"], cells.start, cells.order, g.lo,
                                          g.inv_cell, g.ncell, g.period, prm, grad)
        elif lagged:
            grad = fp["grad_rho"]
        else:
            grad = self._empty_grad
        fluid_rates(fluid_view(fp), cell_view(g, cells), grad, prm, 0, ctx.rates,
                    fp["grad_rho_next"] if lagged else self._empty_grad)
        if lagged:
            fp["grad_rho"], fp["grad_rho_next"] = fp["grad_rho_next"], fp["grad_rho"]
        for wall in self.walls:
            if wall.name in self.wall_forces:
                before = fp["dv"].copy()
                self._wall_acts(wall, ctx)
                # force of the fluid on the wall = minus what the wall adds to m_i dv_i (pairwise forms)
                self.wall_forces[wall.name] = -np.sum(fp["m"][:, None] * (fp["dv"] - before), axis=0)
            else:
                self._wall_acts(wall, ctx)
        for coupling in self.couplings:
            coupling.add_rates(self, ctx)
        if self.fluid.density_mode == "summation":
            fp["drho"][:] = 0.0

    def _wall_acts(self, wall, ctx):
        """The wall model's terms, then the wall's adhesion (if any), added to the fluid's rates."""
        fp = self.fluid.particles
        wall.model.interact(self.fluid, wall, ctx, fp["dv"], fp["drho"])
        if wall.adhesion_coefficient > 0.0:
            add_adhesion(wall, self.fluid, ctx, self.kernel.support(self.h), fp["dv"])

    def _maintain(self):
        """Between steps: wrap periodic axes, remove escaped particles, reorder by cell."""
        fp = self.fluid.particles
        x = fp["x"]
        if np.any(self.grid.period > 0):
            self.grid.wrap(x)
        inside = self.grid.inside(x)
        if not inside.all():
            gone = ~inside
            for k in np.flatnonzero(gone):
                self.escaped.append((self.time, int(fp["id"][k]), *x[k].tolist()))
            self.escaped_mass += float(fp["m"][gone].sum())
            fp.keep(inside)
        if self.step % self.reorder_every == 0 and fp.n:
            fp.permute(self.grid.build(fp["x"]).order)

    def _check_health(self):
        fp = self.fluid.particles
        rho0 = self.physics.rho0
        bad = first_bad_particle(fp["x"], fp["v"], fp["rho"], self.density_band[0] * rho0,
                                 self.density_band[1] * rho0)
        if bad < 0:
            return
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
            f"{fp['v'][bad].tolist()} (allowed density band {self.density_band[0]:g}-{self.density_band[1]:g} "
            f"x rho0)" + (f"; last good checkpoint: {checkpoint}" if checkpoint else ""),
            step=self.step, time=self.time, particle_id=pid, position=pos, checkpoint=checkpoint)

    # ------------------------------------------------------------------ running
    def _initialise(self):
        if not self._rates_ready:
            self._maintain()
            self.evaluate(self.time)
            self._rates_ready = True
            self.next_dt = self.integrator.time_step(self.fluid, self.physics)

    def _sample(self, force=False):
        if not self.probes:
            return
        if not force and self.time < self._next_probe - 1e-12:
            return
        self.fluid_cells = self.grid.build(self.fluid.particles["x"])
        # the equation of state is cheap; it keeps probe pressures consistent with rho
        fp = self.fluid.particles
        equation_of_state(fp["rho"], fp["m"], self.physics, fp["p"], fp["c"], fp["p_over_rho2"], fp["volume"])
        row = [p.sample(self) for p in self.probes]
        self.probe_times.append(self.time)
        self.probe_values.append(row)
        if self.probe_csv is not None:
            self.probe_csv.append(self.time, row)
        while self._next_probe <= self.time + 1e-12:
            self._next_probe += self.probe_every

    def run_steps(self, n_steps):
        """Advance exactly ``n_steps`` steps with no probes or output (benchmarks)."""
        self._initialise()
        for _ in range(int(n_steps)):
            self._one_step(self.next_dt)

    def _one_step(self, dt):
        self._maintain()
        self.integrator.step(self, dt)
        self.time += dt
        self.step += 1
        for coupling in self.couplings:
            coupling.after_step(self, dt)
        self._check_health()
        self.next_dt = self.integrator.time_step(self.fluid, self.physics)
        if not (self.next_dt > 0) or not math.isfinite(self.next_dt):
            self._check_health()
            raise InstabilityError(f"time step became {self.next_dt} at step {self.step}, t = {self.time:.6g} s",
                                   step=self.step, time=self.time)

    def run(self, t_end, *, progress=True, probe_csv=None, max_steps=None):
        """Run until simulated time ``t_end`` [s]; return a :class:`RunResult`.

        ``probe_csv``: path of a CSV file receiving every probe sample as it
        is taken (flushed row by row, so an interrupted run keeps its data).
        """
        t_end = require_positive("t_end", t_end)
        if t_end <= self.time:
            raise ParameterError(f"t_end = {t_end:g} s must exceed the current time {self.time:g} s")
        if self.probe_every is None:
            self.probe_every = t_end / 1000.0
        resume_after = self.time if self.step > 0 else None
        for out in self.outputs:
            out.open(self, resume_after=resume_after)
        if probe_csv is not None and self.probes:
            from .io.csvout import ProbeCSVWriter

            self.probe_csv = ProbeCSVWriter(probe_csv, [p.name for p in self.probes],
                                            resume=resume_after is not None,
                                            resume_after=resume_after if resume_after is not None else 0.0)
        wall_start = _time.perf_counter()
        self._initialise()
        startup = _time.perf_counter() - wall_start
        if self.step == 0:
            self._sample(force=True)
            for out in self.outputs:
                if isinstance(out, (VTK, LineSampler)):
                    out.write(self)
        n_total_walls = sum(w.n for w in self.walls)
        particle_steps = 0
        steps_at_start = self.step
        loop_start = _time.perf_counter()
        bar = _progress_bar(t_end, self.time, progress)
        last_bar = loop_start
        try:
            while self.time < t_end - 1e-12:
                if max_steps is not None and self.step - steps_at_start >= max_steps:
                    break
                dt = min(self.next_dt, t_end - self.time)
                n_now = self.fluid.particles.n + n_total_walls
                self._one_step(dt)
                particle_steps += n_now
                self._sample()
                for out in self.outputs:
                    if out.due(self.time):
                        out.write(self)
                now = _time.perf_counter()
                if bar is not None and (now - last_bar > bar.mininterval or self.time >= t_end - 1e-12):
                    rate = particle_steps / max(now - loop_start, 1e-9)
                    bar.n = round(self.time, 6)
                    bar.set_postfix_str(f"step {self.step}, dt {self.next_dt:.2e} s, {rate / 1e6:.2f} M particle-steps/s")
                    last_bar = now
        finally:
            if bar is not None:
                bar.close()
            if self.probe_csv is not None:
                self.probe_csv.close()
                self.probe_csv = None
        loop_time = _time.perf_counter() - loop_start
        self._sample(force=self.probe_times[-1] < self.time if self.probe_times else bool(self.probes))
        for out in self.outputs:
            if isinstance(out, VTK) and (not out._fluid.files or out._fluid.files[-1][0] < self.time):
                out.write(self)
            if isinstance(out, LineSampler):
                if out.next_time - out.every < self.time - 1e-12:
                    out.write(self)
                out.close()
        summary = self.summary(wall_time=_time.perf_counter() - wall_start, loop_time=loop_time,
                               particle_steps=particle_steps, steps=self.step - steps_at_start,
                               startup=startup)
        return self.result(summary)

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
            "escaped_where": escaped_where(self.escaped, self.grid),
            "mass_drift": float((mass_now + self.escaped_mass - initial - added) / initial),
            "fluid_mass_in_domain_change": float((mass_now - initial) / initial),
            "kernel": self.kernel.name,
            "h": self.h,
            "dx": self.fluid.spacing,
            "walls": {w.name: w.model.describe() for w in self.walls},
            **({"couplings": {c.name: {"model": c.describe(), **c.summary()} for c in self.couplings}}
               if self.couplings else {}),
        }

    def result(self, summary):
        times = np.asarray(self.probe_times, dtype=np.float64)
        values = np.asarray(self.probe_values, dtype=np.float64).reshape(len(self.probe_times), len(self.probes))
        probes = {p.name: values[:, k].copy() for k, p in enumerate(self.probes)}
        return RunResult(times, probes, summary, list(self.escaped))

    # ------------------------------------------------------------------ checkpoints
    def save_checkpoint(self, path):
        """Write the complete state (HDF5) so that :meth:`restart` continues bit for bit."""
        from .io.checkpoint import save_checkpoint

        arrays = {"fluid": self.fluid.particles.as_dict()}
        for wall in self.walls:
            arrays[f"wall_{wall.name}"] = wall.particles.as_dict()
        arrays["probes"] = {
            "times": np.asarray(self.probe_times, dtype=np.float64),
            "values": np.asarray(self.probe_values, dtype=np.float64).reshape(len(self.probe_times), len(self.probes)),
        }
        for coupling in self.couplings:
            arrays[f"coupling_{coupling.name}"] = dict(coupling.arrays())
        arrays["escaped"] = {"records": np.asarray(self.escaped, dtype=np.float64).reshape(len(self.escaped), 2 + self.dim)}
        attrs = {"time": self.time, "step": self.step, "next_dt": self.next_dt,
                 "escaped_mass": self.escaped_mass, "next_probe": self._next_probe,
                 "probe_every": self.probe_every, "probe_names": [p.name for p in self.probes],
                 "wall_model_state": {w.name: w.model.state() for w in self.walls},
                 "coupling_state": {c.name: c.state() for c in self.couplings},
                 "dim": self.dim, "n_fluid_initial_mass": self.fluid.initial_mass,
                 "metadata": self.metadata}
        save_checkpoint(path, arrays, attrs)

    def restart(self, path):
        """Load a checkpoint written by :meth:`save_checkpoint` into this (identically built) simulation."""
        from .io.checkpoint import load_checkpoint

        arrays, attrs = load_checkpoint(path)
        if attrs.get("dim") != self.dim:
            raise ParameterError(f"checkpoint {path} is {attrs.get('dim')}D, this simulation is {self.dim}D")
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
        self.time = float(attrs["time"])
        self.step = int(attrs["step"])
        self.next_dt = float(attrs["next_dt"])
        self.escaped_mass = float(attrs["escaped_mass"])
        self._next_probe = float(attrs["next_probe"])
        self.probe_every = attrs["probe_every"]
        self.fluid.initial_mass = float(attrs["n_fluid_initial_mass"])
        names = list(attrs.get("probe_names") or [])
        if names != [p.name for p in self.probes]:
            raise ParameterError(f"checkpoint {path} has probes {names}, this simulation {[p.name for p in self.probes]}")
        self.probe_times = arrays["probes"]["times"].tolist()
        self.probe_values = arrays["probes"]["values"].tolist()
        self.escaped = [(r[0], int(r[1]), *r[2:].tolist()) for r in arrays["escaped"]["records"]]
        self._rates_ready = True
        self.fluid_cells = self.grid.build(self.fluid.particles["x"])
        return self


def _progress_bar(t_end, t_start, enabled):
    if not enabled:
        return None
    from tqdm import tqdm

    # in a terminal the bar redraws twice a second; in a log file one line every 30 s is plenty
    interactive = sys.stderr.isatty()
    return tqdm(total=round(t_end, 6), initial=round(t_start, 6), unit="s", file=sys.stderr,
                bar_format="{l_bar}{bar}| {n:.4f}/{total:.4f} s simulated [{elapsed}<{remaining}{postfix}]",
                dynamic_ncols=True, mininterval=0.5 if interactive else 30.0)
