"""Discrete elements: discs (2D) and spheres (3D) with a normal spring-dashpot
contact, and the DEM wall of [TrixiBoundary] ("BoundaryDEMSystem(initial_condition,
normal_stiffness)").

Contact law (linear spring-dashpot, Cundall & Strack 1979; the damping from
the coefficient of restitution as in Luding 2008, "Introduction to discrete
element methods", eq. 5-7). For particles i, j with centres x_i, x_j, radii
R_i, R_j, overlap delta = R_i + R_j - |x_i - x_j| > 0 and unit normal
n = (x_i - x_j) / |x_i - x_j|, the force on i is

    F_i = (k delta - gamma v_n) n,    v_n = (v_i - v_j) . n,
    gamma = 2 zeta sqrt(k m*),        m* = m_i m_j / (m_i + m_j),
    zeta = -ln(e) / sqrt(pi^2 + ln(e)^2),

so that a head-on collision lasts t_c = pi / (omega0 sqrt(1 - zeta^2)),
omega0 = sqrt(k / m*), and leaves with e times the approach speed (the force
is not clipped at zero, which keeps this relation exact). A wall particle
is a fixed particle of radius spacing / 2 and infinite mass (m* = m_i) whose
stiffness is the wall's ``normal_stiffness``. No tangential force: the
model of [TrixiBoundary]'s DEM wall is normal only.

Time integration: velocity Verlet with a fixed step of t_c / 50 for the
stiffest, lightest contact (Luding 2008 recommends about t_c / 50). The
damping force jumps at the start of a contact, so the error in e is first
order in dt and depends on where in a step the contact starts. Measured
over five contact phases at t_c / 50, largest |e_sim - e| / e: 0.17 % at
e = 0.9, 0.97 % at e = 0.6, 3.9 % at e = 0.3, 4.8 % at e = 0.1 (at t_c / 100:
0.1, 0.7, 0.8, 3.3 %). Give ``dt`` for strongly damped contacts that need more.
"""

import math
import os

import numpy as np
from numba import prange

from .errors import InstabilityError, ParameterError, require_positive
from .jit import apply_threads, loop_helper, particle_loop
from .neighbors import CellGrid, cell_index, layout_tag, neighbour_range, point_of, separation, tag_dim
from .output import VTK, Checkpoint
from .particles import ParticleArrays
from .probes import Probe
from .runner import Runner
from .schedule import first_due_after, next_due

STEPS_PER_CONTACT = 50


def damping_ratio(restitution):
    """zeta of the linear spring-dashpot that gives restitution coefficient e (Luding 2008, eq. 7)."""
    e = float(restitution)
    if not 0.0 < e <= 1.0:
        raise ParameterError(f"restitution must be in (0, 1], got {restitution!r}")
    if e == 1.0:
        return 0.0
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le * le)


def contact_time(stiffness, reduced_mass, zeta):
    """Duration of a head-on contact, pi / (sqrt(k / m*) sqrt(1 - zeta^2))."""
    return math.pi / (math.sqrt(stiffness / reduced_mass) * math.sqrt(1.0 - zeta * zeta))


@loop_helper
def pair_force(delta, vn, k, zeta, m_eff):
    """Magnitude along n of the spring-dashpot force: k delta - 2 zeta sqrt(k m*) v_n."""
    return k * delta - 2.0 * zeta * math.sqrt(k * m_eff) * vn


@particle_loop()
def contact_accelerations(layout, x, v, radius, mass, start, order, xw, rw, start_w, order_w, lo, inv_cell, ncell,
                          period, k, k_wall, zeta, gx, gy, gz, acc, overlap):
    """Acceleration of every element from its contacts (elements and wall particles) plus gravity.

    ``overlap[i]`` receives the largest overlap of element i divided by its radius.
    """
    for i in prange(x.shape[0]):
        dim = tag_dim(layout)   # inside the parallel body, where it is a constant
        nrows = 25 if dim == 3 else 5
        p0, p1, p2 = point_of(x, i, dim)
        cx, cy, cz = cell_index(p0, p1, p2, lo, inv_cell, ncell)
        vi0, vi1, vi2 = point_of(v, i, dim)
        mi = mass[i]
        ri = radius[i]
        f0 = f1 = f2 = 0.0
        worst = 0.0
        for which in range(2):
            for row in range(nrows):
                for part in range(2):
                    if which == 0:
                        ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start)
                    else:
                        ka, kb = neighbour_range(row, part, cx, cy, cz, ncell, period, start_w)
                    for kk in range(ka, kb):
                        if which == 0:
                            j = order[kk]
                            if j == i:
                                continue
                            d0, d1, d2, r2 = separation(p0, p1, p2, x, j, dim, False, period)
                            reach = ri + radius[j]
                        else:
                            j = order_w[kk]
                            d0, d1, d2, r2 = separation(p0, p1, p2, xw, j, dim, False, period)
                            reach = ri + rw[j]
                        if r2 >= reach * reach or r2 == 0.0:
                            continue
                        r = math.sqrt(r2)
                        n0 = d0 / r
                        n1 = d1 / r
                        n2 = d2 / r
                        delta = reach - r
                        if which == 0:
                            vj0, vj1, vj2 = point_of(v, j, dim)
                            vn = (vi0 - vj0) * n0 + (vi1 - vj1) * n1 + (vi2 - vj2) * n2
                            mj = mass[j]
                            fmag = pair_force(delta, vn, k, zeta, mi * mj / (mi + mj))
                        else:
                            vn = vi0 * n0 + vi1 * n1 + vi2 * n2
                            fmag = pair_force(delta, vn, k_wall, zeta, mi)
                        f0 += fmag * n0
                        f1 += fmag * n1
                        f2 += fmag * n2
                        if delta / ri > worst:
                            worst = delta / ri
        acc[i, 0] = f0 / mi + gx
        acc[i, 1] = f1 / mi + gy
        if dim == 3:
            acc[i, 2] = f2 / mi + gz
        overlap[i] = worst


class DEMSystem:
    """Discs (2D) or spheres (3D) that interact by normal contact only.

    Parameters
    ----------
    positions : (N, d) array
        Centres [m].
    radius : float or (N,) array
        Radii [m].
    density : float
        Material density [kg/m^3]; mass = density * pi R^2 (per metre, 2D) or
        density * 4/3 pi R^3 (3D).
    normal_stiffness : float
        Spring constant k of element-element contacts [N/m (per metre in 2D)].
    restitution : float
        Coefficient of restitution e in (0, 1] of every contact (sets the damping).
    velocity : array-like, optional
        Initial velocity, a vector or an (N, d) array.
    """

    def __init__(self, positions, radius, *, density=2500.0, normal_stiffness=1e6, restitution=0.5, velocity=None,
                 name="dem"):
        x = np.ascontiguousarray(positions, dtype=np.float64)
        if x.ndim != 2 or x.shape[1] not in (2, 3) or x.shape[0] == 0:
            raise ParameterError(f"positions must be an (N, 2) or (N, 3) array with N > 0, got {x.shape}")
        n, dim = x.shape
        r = np.broadcast_to(np.asarray(radius, dtype=np.float64), (n,)).copy()
        if not np.all(r > 0):
            raise ParameterError("radius must be positive")
        self.name = str(name)
        self.dim = dim
        self.density = require_positive("density", density)
        self.normal_stiffness = require_positive("normal_stiffness", normal_stiffness)
        self.restitution = float(restitution)
        self.zeta = damping_ratio(restitution)
        pa = ParticleArrays(dim)
        pa.add("x", x)
        v = np.zeros((n, dim))
        if velocity is not None:
            v[:] = np.asarray(velocity, dtype=np.float64)
        pa.add("v", v)
        pa.add("radius", r)
        volume = math.pi * r ** 2 if dim == 2 else 4.0 / 3.0 * math.pi * r ** 3
        pa.add("m", self.density * volume)
        pa.add("a", np.zeros((n, dim)))
        pa.add("overlap", np.zeros(n))
        pa.add("id", np.arange(n, dtype=np.int64))
        self.particles = pa

    @property
    def n(self):
        return self.particles.n


class DEMWall:
    """Fixed wall particles acting on DEM elements ([TrixiBoundary], ``BoundaryDEMSystem``).

    Parameters
    ----------
    shape : seawall.shapes.Shape
        Wall particle positions and spacing (e.g. ``shapes.tank_surface``); each
        wall particle is a sphere of radius ``spacing / 2``.
    normal_stiffness : float
        Spring constant of element-wall contacts [N/m (per metre in 2D)].
    """

    def __init__(self, shape, normal_stiffness, *, name="wall"):
        x = np.ascontiguousarray(getattr(shape, "positions", None), dtype=np.float64)
        if x.ndim != 2 or x.shape[1] not in (2, 3) or x.shape[0] == 0:
            raise ParameterError(f"wall positions must be an (N, 2) or (N, 3) array with N > 0, got {x.shape}")
        self.name = str(name)
        self.dim = x.shape[1]
        self.spacing = require_positive("spacing", shape.spacing)
        self.normal_stiffness = require_positive("normal_stiffness", normal_stiffness)
        self.x = x
        self.radius = np.full(x.shape[0], 0.5 * self.spacing)

    @property
    def n(self):
        return self.x.shape[0]

    def describe(self):
        return f"dem-wall(normal_stiffness={self.normal_stiffness:g})"


class DEMSimulation(Runner):
    """DEM elements in DEM walls under gravity; run, probed and checkpointed by the same loop as Simulation.

    Parameters
    ----------
    systems : list
        One :class:`DEMSystem` and any number of :class:`DEMWall`.
    gravity : sequence of float, optional
    dt : float, optional
        Time step [s]; default t_c / 50 of the stiffest, lightest contact.
    domain : (lo, hi), optional
        Box for the neighbour grid; elements leaving it are an error.
    """

    def __init__(self, systems, *, gravity=None, dt=None, domain=None, threads=None, metadata=None):
        dems = [s for s in systems if isinstance(s, DEMSystem)]
        walls = [s for s in systems if isinstance(s, DEMWall)]
        if len(dems) != 1 or len(dems) + len(walls) != len(systems):
            raise ParameterError("systems must be one DEMSystem and any number of DEMWall")
        self.dem = dems[0]
        self.walls = walls
        self.dim = self.dem.dim
        if any(w.dim != self.dim for w in walls):
            raise ParameterError("DEM walls and elements must have the same dimension")
        g = np.zeros(3)
        if gravity is not None:
            gravity = np.asarray(gravity, dtype=np.float64)
            if gravity.shape != (self.dim,):
                raise ParameterError(f"gravity must have {self.dim} components")
            g[:self.dim] = gravity
        self.gravity = g
        if threads is not None:
            import numba

            numba.set_num_threads(int(threads))
        pa = self.dem.particles
        r_max = float(pa["radius"].max())
        wr = max([float(w.radius.max()) for w in walls], default=0.0)
        self.reach = max(2.0 * r_max, r_max + wr)
        allx = [pa["x"]] + [w.x for w in walls]
        if domain is None:
            lo = np.min([a.min(0) for a in allx], axis=0) - 2 * self.reach
            hi = np.max([a.max(0) for a in allx], axis=0) + 2 * self.reach
        else:
            lo, hi = (np.asarray(d, dtype=np.float64) for d in domain)
        self.grid = CellGrid(lo, hi, self.reach)
        self.layout = layout_tag(self.dim, False)
        self.wall_x = np.concatenate([w.x for w in walls]) if walls else np.zeros((0, self.dim))
        self.wall_r = np.concatenate([w.radius for w in walls]) if walls else np.zeros(0)
        self.wall_k = walls[0].normal_stiffness if walls else 1.0
        if any(w.normal_stiffness != self.wall_k for w in walls):
            raise ParameterError("all DEM walls of one simulation must share normal_stiffness")
        self.wall_cells = self.grid.build(self.wall_x)
        m_min = float(pa["m"].min())
        t_c = min(contact_time(self.dem.normal_stiffness, 0.5 * m_min, self.dem.zeta),
                  contact_time(self.wall_k, m_min, self.dem.zeta))
        self.contact_time = t_c
        self.dt = require_positive("dt", dt) if dt is not None else t_c / STEPS_PER_CONTACT
        self.metadata = dict(metadata or {})
        self.reference = None
        self._init_run_state()      # time, step, probes, outputs (seawall.runner)
        self.escaped = []           # elements are never removed: leaving the domain is an error
        self._accelerate()

    # -------------------------------------------------------------- physics
    def _accelerate(self):
        pa = self.dem.particles
        g = self.grid
        cells = g.build(pa["x"])
        contact_accelerations(self.layout, pa["x"], pa["v"], pa["radius"], pa["m"], cells.start, cells.order,
                              self.wall_x, self.wall_r, self.wall_cells.start, self.wall_cells.order, g.lo,
                              g.inv_cell, g.ncell, g.period, self.dem.normal_stiffness, self.wall_k, self.dem.zeta,
                              self.gravity[0], self.gravity[1], self.gravity[2], pa["a"], pa["overlap"])

    def _integrate(self, dt):
        """Velocity Verlet: v' = v + a dt/2, x += v' dt, a = a(x, v'), v = v' + a dt/2.

        The damping force is evaluated with the half-step velocity v'. The
        restitution error is dominated by the contact's start and end falling
        inside a step (the damping force jumps there), which is O(dt): see
        STEPS_PER_CONTACT.
        """
        pa = self.dem.particles
        pa["v"] += 0.5 * dt * pa["a"]
        pa["x"] += dt * pa["v"]
        inside = self.grid.inside(pa["x"])
        if not inside.all():
            k = int(np.argmin(inside))
            raise InstabilityError(
                f"DEM element {int(pa['id'][k])} left the domain at step {self.step + 1}, t = {self.time + dt:.6g} s, "
                f"position {pa['x'][k].tolist()}: reduce dt or raise normal_stiffness",
                step=self.step + 1, time=self.time + dt, particle_id=int(pa["id"][k]), position=pa["x"][k].tolist())
        self._accelerate()
        pa["v"] += 0.5 * dt * pa["a"]

    # -------------------------------------------------------------- runner hooks (seawall.runner)
    OUTPUT_TYPES = (VTK, Checkpoint)   # no fluid for a LineSampler to sample

    def _initialise(self):
        apply_threads()   # a case file's threads (seawall.cases.files), asked for before the run
        # accelerations are those of the current state from construction (or from the checkpoint)
        if self.next_dt is None:
            self.next_dt = self.dt

    def _time_step(self):
        return self.dt

    def particles_per_step(self):
        return self.dem.n

    def _adopt_output(self, out):
        # a VTK output of a DEM run writes the elements (dem.pvd) rather than a fluid
        return DEMVTK.like(out) if type(out) is VTK else out

    def headline(self):
        return f"{self.dem.n} DEM elements + {sum(w.n for w in self.walls)} wall particles, dt = {self.dt:.3g} s"

    def summary(self, *, wall_time, loop_time, particle_steps, steps, startup):
        pa = self.dem.particles
        return {
            **self.metadata,
            "boundary": "dem-wall",   # DEM walls act by contact whatever --boundary names
            "dimension": self.dim,
            "n_fluid": 0,
            "n_dem": int(pa.n),
            "n_wall": int(sum(w.n for w in self.walls)),
            "steps": int(self.step),
            "steps_this_run": int(steps),
            "t_end": float(self.time),
            "dt": self.dt,
            "contact_time": self.contact_time,
            "wall_time_s": float(wall_time),
            "startup_s": float(startup),
            "particle_steps_per_s": float(particle_steps / loop_time) if loop_time > 0 else 0.0,
            "escaped_particles": 0,
            "mass_drift": 0.0,
            "max_overlap_over_radius": float(pa["overlap"].max()),
            "walls": {w.name: w.describe() for w in self.walls},
        }

    # -------------------------------------------------------------- checkpoints (the runner adds clock and probes)
    def _constants(self):
        """What fixes the trajectory besides the case parameters; a restart must find the same."""
        return {"dt": self.dt, "gravity": self.gravity.tolist(), "normal_stiffness": self.dem.normal_stiffness,
                "restitution": self.dem.restitution, "wall_stiffness": self.wall_k}

    def _state_arrays(self):
        return {"dem": self.dem.particles.as_dict()}

    def _state_attrs(self):
        return {"physics": self._constants()}

    def _check_state(self, path, arrays, attrs):
        from . import restart_checks as checks

        if "dem" not in arrays or arrays["dem"]["x"].shape[0] != self.dem.n:
            raise ParameterError(f"checkpoint {path} does not match this DEM simulation")
        checks.check_setup(path, attrs, self.metadata, self._constants())
        checks.check_clock(path, attrs)
        checks.check_arrays(path, "the DEM elements", arrays["dem"], self.dem.particles.as_dict())

    def _load_state(self, path, arrays, attrs):
        for name, a in arrays["dem"].items():
            self.dem.particles[name] = a


class DEMVTK(VTK):
    """VTU/PVD snapshots of DEM elements: ``DIR/dem.pvd`` (velocity, radius, overlap, id) and each
    wall once as ``DIR/wall_<name>.pvd`` (radius)."""

    @classmethod
    def like(cls, vtk):
        return cls(vtk.directory, every=vtk.every, walls=vtk.walls, compress=vtk.compress, float32=vtk.float32)

    def open(self, sim, resume_after=None):
        from .io.vtk import PVDSeries

        os.makedirs(self.directory, exist_ok=True)
        resume = resume_after is not None
        self._elements = PVDSeries(self.directory, "dem", resume=resume, resume_after=resume_after)
        if resume:
            self.next_time = first_due_after(resume_after, self.every)
        elif self.walls:
            for w in sim.walls:   # fixed: written once
                PVDSeries(self.directory, f"wall_{w.name}").write(0.0, w.x, {"radius": w.radius},
                                                                  compress=self.compress, float32=self.float32)

    def write(self, sim):
        pa = sim.dem.particles
        self._elements.write(sim.time, pa["x"], {"velocity": pa["v"], "radius": pa["radius"],
                                                 "overlap": pa["overlap"], "id": pa["id"]},
                                 field_data={"TimeValue": sim.time}, compress=self.compress, float32=self.float32)
        self.next_time = next_due(self.next_time, self.every, sim.time)

    def last_time(self):
        files = self._elements.files if getattr(self, "_elements", None) is not None else []
        return files[-1][0] if files else None


# ------------------------------------------------------------------ probes
class DEMKineticEnergy(Probe):
    """Total kinetic energy of the DEM elements [J (per metre in 2D)]."""

    unit = "J"

    def __init__(self, name="kinetic_energy"):
        super().__init__(name)

    def sample(self, sim):
        pa = sim.dem.particles
        return float(0.5 * np.sum(pa["m"] * np.sum(pa["v"] ** 2, axis=1)))


class LowestBottom(Probe):
    """Lowest point of any element (centre minus radius, along the last axis) [m]."""

    unit = "m"

    def __init__(self, name="lowest_bottom"):
        super().__init__(name)

    def sample(self, sim):
        pa = sim.dem.particles
        return float(np.min(pa["x"][:, -1] - pa["radius"]))


class MaxOverlap(Probe):
    """Largest contact overlap divided by the element's radius."""

    unit = "m"

    def __init__(self, name="max_overlap"):
        super().__init__(name)

    def sample(self, sim):
        return float(sim.dem.particles["overlap"].max())
