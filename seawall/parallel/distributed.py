"""A simulation split over MPI ranks: owned particles, halos, migration, rebalancing and reductions.

Each rank's fluid arrays hold the particles it owns first (rows ``[0, n_own)``)
and halo copies of other ranks' particles after them. The rates of an owned
particle read, at most, the fluid within ``depth`` kernel supports of it: one
support for the fluid's own pair terms and one more for every quantity they
read that is itself a sum over neighbours (a wall particle's pressure from
the fluid around it, the summation density). The halo therefore holds every
particle within ``depth`` supports of the slab, plus one support of margin for
the motion during a step (a step moves a particle by a small fraction of h).

* **Membership** of the halo and ownership are fixed for a step: before it
  (``_maintain``) the halo is dropped, owned particles that left the slab
  migrate to their new owner, and the halo is rebuilt.
* **Values** of the halo rows are refreshed from their owners before every
  evaluation of the rates and before the probes sample (one exchange of the
  rows, all arrays), so an owned particle sees exactly the neighbours and
  values a single process would. Sums over neighbours are taken in another
  order, so results agree to round-off, which grows with the steps as in any
  SPH run (docs/parallel.md gives the measured differences).
* **Rebalancing**: every ``rebalance_every`` steps the owned counts are
  compared; beyond ``imbalance`` (max / mean - 1) the cuts are recomputed from
  the summed histogram and particles migrate.
* **Reductions**: the time step is the minimum over ranks (the rule is a
  minimum over particles); removals are gathered so every rank keeps the same
  escaped records; probes are sums, maxima or minima over the owned particles,
  or sampled on the rank whose slab holds the probe point.

Walls are replicated on every rank (they do not migrate). A wall model whose
``update`` integrates wall arrays in time keeps exact values only near the
fluid a rank holds; the owner of each wall particle (the rank whose slab holds
it) broadcasts them before a rebalance, a checkpoint and a VTU frame.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import os
import time as _time
from types import SimpleNamespace

import numpy as np

from ..diagnostics import record_reason
from ..errors import InstabilityError, ParameterError
from ..fluid.regularisation import max_speed
from ..health import DAMAGE, KEEP, reason_name
from ..output import VTK
from ..particles import ParticleArrays
from ..schedule import first_due_after, next_due
from . import slabs

#: kernel supports of margin beyond the dependency depth (motion during one step)
MARGIN_SUPPORTS = 1.0
#: wall models whose decomposed run matched one process to round-off (benchmarks/mpi_agreement.py,
#: docs/parallel.md); the others are refused until they are compared. lust, mirroring, mdbc and
#: mdbc-noslip differ by more (2e-5, 1.3e-5, 1.7e-7, 6.7e-7 after the impact) but by what a serial run
#: differs from itself when its initial positions move by one ulp (0.17, 2.5e-5, 4.8e-8, 7.8e-7): LUST's
#: stencil nodes switch on and off at the wall surface, the others' flows amplify round-off faster; the
#: decomposition adds nothing to that (docs/parallel.md)
VERIFIED_MODELS = ("adami", "adami-noslip", "summation", "continuity", "zeroing", "dbc", "idbc", "ghost-mls1",
                   "ghost-mls2", "ghost-sfdi", "ghost-normalized", "ghost-shepard", "monaghan-kajtar", "liu2015",
                   "liu2015-noslip", "liu2012", "lust", "mirroring", "mdbc", "mdbc-noslip")
#: set (to anything) by benchmarks/mpi_agreement.py: run a model not yet compared, to compare it
COMPARE_ANY_MODEL = "SEAWALL_MPI_COMPARE_ANY_MODEL"
#: signal names a stop may carry (seawall.interrupts), in the order a reduction by max prefers
SIGNALS = ("SIGINT", "SIGTERM")
#: check the balance every this many steps
REBALANCE_EVERY = 50
#: rebalance when the largest rank holds more than (1 + this) times the mean
IMBALANCE = 0.10


# ---------------------------------------------------------------------------- what can be decomposed
def _probe_reduction(probe):
    """How a probe's value is combined over ranks: 'sum', 'max', 'min', 'point', 'global' (every rank
    computes the same value) or None. A probe class may declare its own (``mpi_reduction``)."""
    from ..compare import MinWallDistance
    from ..probes import KineticEnergy, PressureSensor, SurgeFront, TotalMass, WallForce, WallPressure, Pressure
    from ..sampling import FieldProbe

    declared = getattr(probe, "mpi_reduction", None)
    if declared is not None:
        return declared
    if isinstance(probe, (KineticEnergy, TotalMass)):
        return "sum"
    if isinstance(probe, SurgeFront):
        return "max" if probe.direction > 0 else "min"
    if isinstance(probe, MinWallDistance):
        return "min"
    if isinstance(probe, WallForce):
        return "global"      # the wall forces are summed over ranks in every evaluation
    if isinstance(probe, (WallPressure, Pressure, PressureSensor, FieldProbe)):
        return "point"
    return None


def refusal(sim):
    """Why ``sim`` cannot run decomposed (one line naming what), or None."""
    from ..simulation import Simulation

    if not isinstance(sim, Simulation):
        return f"MPI: {type(sim).__name__} runs are not decomposed (only SPH simulations); run it in one process"
    if sim.couplings:
        names = ", ".join(f"{c.name} ({type(c).__name__})" for c in sim.couplings)
        return f"MPI: coupling {names} acts on the whole fluid and is not decomposed; run it in one process"
    for w in sim.walls:
        name = getattr(w.model, "name", type(w.model).__name__)
        if name not in VERIFIED_MODELS and not os.environ.get(COMPARE_ANY_MODEL):
            return (f"MPI: wall {w.name} ({name}): this wall model has not been compared with one process on "
                    f"several ranks (verified: {', '.join(VERIFIED_MODELS)}); run it in one process")
    if slabs.longest_axis(sim.grid.lo[:sim.dim], sim.grid.hi[:sim.dim], sim.grid.periodic) is None:
        return "MPI: every axis is periodic, no axis to cut; run it in one process"
    bad = [p.name for p in sim.probes if _probe_reduction(p) is None]
    if bad:
        return f"MPI: probe {', '.join(bad)} has no reduction over ranks; run it in one process"
    return None


def _mirror_reach(sim):
    """Farthest a wall's update reads the fluid beyond one support of its particles, in supports.

    Ghost particles ([Huang2019]) and mDBC interpolate the fluid at mirror points, 2 d from a wall
    particle at depth d behind the surface; the other models read the fluid around the particle.
    """
    from ..boundary.ghost import GhostParticles
    from ..boundary.mdbc import ModifiedDynamicBoundary

    support = sim.kernel.support(sim.h)
    reach = 0.0
    for wall in sim.walls:
        if isinstance(wall.model, (GhostParticles, ModifiedDynamicBoundary)) and "surface" in wall.particles:
            depth = np.sqrt(np.sum((wall.x - wall.particles["surface"]) ** 2, axis=1))
            reach = max(reach, 2.0 * float(depth.max(initial=0.0)) / support)
    return reach


def halo_depth(sim):
    """Kernel supports of fluid an owned particle's rates depend on (see the module docstring)."""
    # particle shifting and the transport velocity add nothing: grad C, B and a_b are sums over the
    # neighbours' positions and volumes (depth 1, 2 with summation density), and the transport stress
    # reads a neighbour's v~ - v, itself such a sum (depth 2, 3 with summation density)
    depth = 2.0                                  # fluid pair terms + the wall particles' update
    if sim.fluid.density_mode == "summation":
        depth += 1.0                             # the neighbours' densities are themselves sums
    return depth + _mirror_reach(sim)


def distribute(sim, comm, argv=()):
    """Turn the built simulation ``sim`` into one rank of a decomposed run over ``comm`` (in place;
    returns it). The particles are split when the run starts, after a restart has loaded its state.
    Raises ParameterError (one line) for what cannot be decomposed."""
    reason = refusal(sim)
    if reason:
        raise ParameterError(reason)
    base = type(sim)
    sim.__class__ = type(f"Distributed{base.__name__}", (DistributedSimulation, base), {})
    sim._mpi_setup(comm, argv)
    sim._check_agreement()     # before any file is touched; again when the run starts (after a restart)
    sim._plan_cuts()
    return sim


def _digest(*parts):
    h = hashlib.sha256()
    for part in parts:
        if isinstance(part, np.ndarray):
            h.update(np.ascontiguousarray(part).tobytes())
        else:
            h.update(repr(part).encode())
    return h.hexdigest()


# ---------------------------------------------------------------------------- row exchange
def _columns(pa):
    """(name, columns, dtype, row shape) of every array, in a fixed order."""
    return [(name, int(np.prod(a.shape[1:], dtype=np.int64)), a.dtype, a.shape[1:]) for name, a in pa.items()]


def _pack(pa, rows, columns):
    """The rows ``rows`` of every array as one float64 matrix (8-byte integers bit for bit)."""
    width = sum(c[1] for c in columns)
    buf = np.empty((rows.size, width))
    c = 0
    for name, k, dtype, _shape in columns:
        part = pa[name][rows].reshape(rows.size, k)
        if dtype.kind != "f" and dtype.itemsize == 8:
            part = part.view(np.float64)
        buf[:, c:c + k] = part
        c += k
    return buf


def _unpack(buf, columns):
    out = {}
    c = 0
    for name, k, dtype, shape in columns:
        part = np.ascontiguousarray(buf[:, c:c + k])
        part = part.view(dtype) if dtype.kind != "f" and dtype.itemsize == 8 else part.astype(dtype)
        out[name] = part.reshape((buf.shape[0],) + tuple(shape))
        c += k
    return out


def _alltoallv(comm, blocks, width, recv_counts=None):
    """Send block r (rows x width float64) to rank r; return the received rows (rank order) and the counts."""
    from mpi4py import MPI

    size = comm.Get_size()
    send_counts = np.array([b.shape[0] for b in blocks], dtype=np.int64)
    if recv_counts is None:
        recv_counts = np.empty(size, dtype=np.int64)
        comm.Alltoall(send_counts, recv_counts)
    send = np.concatenate(blocks) if blocks else np.zeros((0, width))
    recv = np.empty((int(recv_counts.sum()), width))
    sc = send_counts * width
    rc = recv_counts * width
    sd = np.concatenate([[0], np.cumsum(sc)[:-1]])
    rd = np.concatenate([[0], np.cumsum(rc)[:-1]])
    comm.Alltoallv([send, (sc, sd), MPI.DOUBLE], [recv, (rc, rd), MPI.DOUBLE])
    return recv, recv_counts


# ---------------------------------------------------------------------------- the rank's simulation
class DistributedSimulation:
    """Mixed in before :class:`~seawall.simulation.Simulation` by :func:`distribute`."""

    # every rank compiles for itself: forking an MPI process is not safe
    compile_helper = False

    def _mpi_setup(self, comm, argv):
        self.comm = comm
        self.rank = comm.Get_rank()
        self.nranks = comm.Get_size()
        self._argv = list(argv)
        support = self.kernel.support(self.h)
        self.halo_depth = halo_depth(self)
        self.halo_width = (self.halo_depth + MARGIN_SUPPORTS) * support
        g = self.grid
        # the longest axis of what the particles occupy (the domain box is grown upwards for splashes)
        boxes = [self.fluid.particles["x"]] + [w.x for w in self.walls if w.n]
        lo = np.min([b.min(axis=0) for b in boxes], axis=0)
        hi = np.max([b.max(axis=0) for b in boxes], axis=0)
        self.cut_axis = slabs.longest_axis(lo, hi, g.periodic)
        self._bin = g.cell_size[self.cut_axis]
        self._nbins = int(g.ncell[self.cut_axis])
        self._n_own = None          # None until the particles are split
        self._cuts = None
        self._halo_send = None
        self._halo_counts = None
        self._halo_fresh = False
        # the halo is rebuilt before every step, so a kept pair list would be rebuilt at every evaluation
        self.pair_list = None
        self.mpi_stats = {"rebalances": 0, "exchanges": 0, "comm_seconds": 0.0, "halo_rows": 0, "halo_samples": 0}

    # ---------------------------------------------------------------- helpers
    def _owned_rows(self):
        return self.fluid.particles.n if self._n_own is None else self._n_own

    def _allreduce(self, value, op="sum"):
        from mpi4py import MPI

        started = _time.perf_counter()
        out = self.comm.allreduce(value, op={"sum": MPI.SUM, "max": MPI.MAX, "min": MPI.MIN}[op])
        self.mpi_stats["comm_seconds"] += _time.perf_counter() - started
        return out

    def _allreduce_array(self, local, op="sum"):
        from mpi4py import MPI

        started = _time.perf_counter()
        out = np.empty_like(local)
        self.comm.Allreduce(local, out, op={"sum": MPI.SUM, "max": MPI.MAX, "min": MPI.MIN}[op])
        self.mpi_stats["comm_seconds"] += _time.perf_counter() - started
        return out

    @contextlib.contextmanager
    def _owned_view(self):
        """The fluid's particles cut to the owned rows while the block runs (views, no copies)."""
        fp = self.fluid.particles
        n = self._owned_rows()
        view = ParticleArrays(fp.dim)
        for name, a in fp.items():
            view.add(name, a[:n])
        self.fluid.particles = view
        try:
            yield view
        finally:
            self.fluid.particles = fp

    def _exchange(self, blocks, width, recv_counts=None):
        started = _time.perf_counter()
        out = _alltoallv(self.comm, blocks, width, recv_counts)
        self.mpi_stats["comm_seconds"] += _time.perf_counter() - started
        self.mpi_stats["exchanges"] += 1
        return out

    # ---------------------------------------------------------------- splitting, migration, halos
    def _check_agreement(self):
        """Every rank must hold the same command, case and state (a decomposed run splits one state)."""
        fp = self.fluid.particles
        digest = _digest(self._argv, fp["x"], fp["v"], fp["rho"], fp["m"], fp["id"], self.time, self.step,
                         tuple(self.physics), [w.n for w in self.walls], self.metadata.get("case_sha256"))
        digests = self.comm.allgather(digest)
        if len(set(digests)) > 1:
            differ = [r for r, d in enumerate(digests) if d != digests[0]]
            raise ParameterError(f"MPI: the ranks disagree on the input (ranks {differ} differ from rank 0 in "
                                 f"their arguments, case or state); start every rank with the same command")

    def _split(self):
        """Check that the ranks hold the same input, cut the domain and keep this rank's slab."""
        self._check_agreement()
        fp = self.fluid.particles
        cuts, owner = self._plan_cuts()
        fp.keep(owner == self.rank)
        self._cuts = cuts
        self._n_own = fp.n

    def _plan_cuts(self):
        """Cuts of the whole fluid (held by every rank before the split) and each particle's owner;
        ParameterError when a rank would own no particle."""
        coord = self.fluid.particles["x"][:, self.cut_axis]
        lo = self.grid.lo[self.cut_axis]
        counts = slabs.histogram(coord, lo, self._bin, self._nbins)
        cuts = slabs.quantile_cuts(counts, lo, self._bin, self.nranks)
        owner = slabs.owners(coord, cuts)
        per_rank = np.bincount(owner, minlength=self.nranks)
        if per_rank.min() == 0:
            usable = next(n for n in range(self.nranks - 1, 0, -1)
                          if np.bincount(slabs.owners(coord, slabs.quantile_cuts(counts, lo, self._bin, n)),
                                         minlength=n).min() > 0)
            raise ParameterError(
                f"MPI: {self.nranks} ranks are more than the fluid allows: it spans "
                f"{int(np.count_nonzero(counts))} cells of {self._bin:.3g} m along axis {'xyz'[self.cut_axis]} "
                f"and rank {int(np.argmin(per_rank))} would own no particle; use at most {usable} ranks")
        return cuts, owner

    def _strip_halo(self):
        fp = self.fluid.particles
        if fp.n != self._n_own:
            fp.truncate(self._n_own)
        self._halo_send = None

    def _migrate(self):
        """Send the owned particles that left the slab to their owner (halo already stripped)."""
        fp = self.fluid.particles
        owner = slabs.owners(fp["x"][:, self.cut_axis], self._cuts)
        leaving = owner != self.rank
        columns = _columns(fp)
        blocks = [_pack(fp, np.flatnonzero(owner == r) if r != self.rank else np.zeros(0, dtype=np.int64), columns)
                  for r in range(self.nranks)]
        width = sum(c[1] for c in columns)
        recv, _ = self._exchange(blocks, width)
        if leaving.any():
            fp.keep(~leaving)
        if recv.shape[0]:
            fp.append(recv.shape[0], **_unpack(recv, columns))
        self._n_own = fp.n

    def _build_halo(self):
        fp = self.fluid.particles
        rows = slabs.halo_rows(fp["x"][:, self.cut_axis], self._cuts, self.rank, self.halo_width)
        columns = _columns(fp)
        width = sum(c[1] for c in columns)
        recv, counts = self._exchange([_pack(fp, r, columns) for r in rows], width)
        self._halo_send = rows
        self._halo_counts = counts
        if recv.shape[0]:
            fp.append(recv.shape[0], **_unpack(recv, columns))
        self.mpi_stats["halo_rows"] += recv.shape[0]
        self.mpi_stats["halo_samples"] += 1
        self._halo_fresh = True

    def _refresh_halo(self):
        """Overwrite the halo rows with their owners' current values (membership unchanged)."""
        fp = self.fluid.particles
        columns = _columns(fp)
        width = sum(c[1] for c in columns)
        recv, _ = self._exchange([_pack(fp, r, columns) for r in self._halo_send], width, self._halo_counts)
        n = self._n_own
        for name, part in _unpack(recv, columns).items():
            fp[name][n:] = part
        self._halo_fresh = True

    def _rebalance_if_needed(self):
        counts = np.array(self.comm.allgather(self._n_own), dtype=np.int64)
        mean = counts.mean()
        if mean <= 0 or counts.max() <= (1.0 + IMBALANCE) * mean:
            return
        self._sync_walls()      # the old slabs' owners hold the exact integrated wall arrays
        coord = self.fluid.particles["x"][:, self.cut_axis]
        local = slabs.histogram(coord, self.grid.lo[self.cut_axis], self._bin, self._nbins)
        total = np.empty_like(local)
        from mpi4py import MPI

        self.comm.Allreduce(local, total, op=MPI.SUM)
        self._cuts = slabs.quantile_cuts(total, self.grid.lo[self.cut_axis], self._bin, self.nranks)
        self._migrate()
        self.mpi_stats["rebalances"] += 1

    def _sync_walls(self):
        """Every rank takes each integrated wall array from the rank whose slab holds the wall particle."""
        from mpi4py import MPI

        for wall in self.walls:
            names = tuple(getattr(wall.model, "integrated_arrays", ()) or ())
            if not names:
                continue
            mine = slabs.owners(wall.x[:, self.cut_axis], self._cuts) == self.rank
            for name in names:
                a = wall.particles[name]
                part = np.where(mine.reshape((-1,) + (1,) * (a.ndim - 1)), a, 0.0).astype(np.float64)
                total = np.empty_like(part)
                self.comm.Allreduce(part, total, op=MPI.SUM)
                a[...] = total

    # ---------------------------------------------------------------- hooks of the run loop
    def _initialise(self):
        if self._n_own is None:
            self._split()
        ready = self._rates_ready
        super()._initialise()
        if not ready:
            self.next_dt = self._time_step()

    def restart(self, path):
        if self._n_own is not None:
            raise ParameterError("MPI: a restart must be loaded before the run starts")
        return super().restart(path)

    def _maintain(self):
        fp = self.fluid.particles
        self._strip_halo()
        if np.any(self.grid.period > 0):
            self.grid.wrap(fp["x"])
        self._migrate()
        if self.step > 0 and self.step % REBALANCE_EVERY == 0:
            self._rebalance_if_needed()
        fp = self.fluid.particles
        if self.step % self.reorder_every == 0 and fp.n:
            fp.permute(self.grid.build(fp["x"]).order)
        self._build_halo()

    def _integrate(self, dt):
        self._halo_fresh = False     # the integrator's predictor moves the owned rows
        super()._integrate(dt)

    def evaluate(self, t):
        if self._halo_send is not None and not self._halo_fresh:
            self._refresh_halo()
        self._halo_fresh = False
        self.record_particle_forces = False   # per-particle wall forces are not decomposed
        super().evaluate(t)
        if self.wall_forces:
            names = sorted(self.wall_forces)
            local = np.concatenate([self.wall_forces[n] for n in names])
            total = self._allreduce_array(local)
            for k, n in enumerate(names):
                self.wall_forces[n] = total[k * self.dim:(k + 1) * self.dim]

    def record_particle_forces_now(self):
        """Per-particle wall forces are not written in a decomposed run (docs/parallel.md)."""

    def _time_step(self):
        with self._owned_view() as view:
            dt = self.integrator.time_step(SimpleNamespace(particles=view), self.physics) if view.n else math.inf
        return self._allreduce(dt, "min")

    def _largest_speed(self):
        # max |v| over the owned rows of every rank: the halo rows, advanced with discarded rates, are not the
        # fluid's ([Sun2017]'s Ma of the shift, as one process takes it)
        n = self._owned_rows()
        local = max_speed(self.fluid.particles["v"][:n]) if n else 0.0
        return self._allreduce(float(local), "max")

    def particles_per_step(self):
        return self._owned_rows() + (sum(w.n for w in self.walls) if self.rank == 0 else 0)

    def _prepare_probes(self):
        if self._halo_send is not None:
            self._refresh_halo()
        super()._prepare_probes()

    def _register_probe(self, probe):
        if _probe_reduction(probe) is None:
            raise ParameterError(f"MPI: probe {probe.name} has no reduction over ranks; run it in one process")
        super()._register_probe(probe)

    def _sample_probe(self, probe):
        kind = _probe_reduction(probe)
        if kind == "global":
            return probe.sample(self)
        if kind == "point":
            point = probe.center if getattr(probe, "center", None) is not None else probe.point
            owner = int(slabs.owners(np.array([point[self.cut_axis]]), self._cuts)[0])
            value = probe.sample(self) if self.rank == owner else None
            return self.comm.bcast(value, root=owner)
        with self._owned_view() as view:
            value = probe.sample(self) if view.n else float("nan")
        if value != value:   # no particle here: neutral for the reduction
            value = {"sum": 0.0, "max": -math.inf, "min": math.inf}[kind]
        value = self._allreduce(float(value), kind)
        return value if math.isfinite(value) or kind == "sum" else float("nan")

    def _adopt_output(self, out):
        from ..sampling import LineSampler

        if isinstance(out, LineSampler):
            raise ParameterError("MPI: the line sampler is not decomposed; run it in one process")
        out = super()._adopt_output(out)
        if isinstance(out, VTK) and not isinstance(out, DecomposedVTK):
            return DecomposedVTK(out, self.comm)
        return out

    def run(self, t_end, *, progress=True, probe_csv=None, max_steps=None):
        root = self.rank == 0
        return super().run(t_end, progress=progress and root, probe_csv=probe_csv if root else None,
                           max_steps=max_steps)

    # ---------------------------------------------------------------- removals
    def _check_health(self, stop=True):
        fp = self.fluid.particles
        n = self._owned_rows()
        codes = self._guard_codes()
        codes[n:] = KEEP                     # halo rows are their owners' to judge
        bad = np.flatnonzero(codes != KEEP)
        # one reduction per step also carries a stop asked for by a signal: every rank stops after
        # the same step (a rank stopping alone would leave the others waiting in the next exchange)
        signal = SIGNALS.index(self.stop_requested) + 1 if self.stop_requested in SIGNALS else 0
        n_bad, signal = self._allreduce_array(np.array([bad.size, signal], dtype=np.int64), "max")
        if signal and self.stop_requested is None:
            self.stop_requested = SIGNALS[int(signal) - 1]
        if n_bad == 0:
            return
        records = [((self.time, int(fp["id"][k]), *fp["x"][k].tolist(), reason_name(int(codes[k]))),
                    float(fp["m"][k])) for k in bad]
        gathered = sorted((r for part in self.comm.allgather(records) for r in part), key=lambda r: r[0][1])
        n_before = self._allreduce(int(n))
        damage = [rec for rec, _m in gathered if record_reason(rec, self.dim) in DAMAGE]
        if stop and damage:
            earlier = sum(1 for rec in self.escaped
                          if rec[0] > self.time - self.unstable_window and record_reason(rec, self.dim) in DAMAGE)
            recent = earlier + len(damage)
            if recent > self.unstable_fraction * (n_before + earlier):
                rec = damage[0]
                raise InstabilityError(
                    f"run became unstable at step {self.step}, t = {self.time:.6g} s: particle id {rec[1]} at "
                    f"{[round(c, 6) for c in rec[2:2 + self.dim]]} removed as {record_reason(rec, self.dim)}; "
                    f"{recent} of {n_before + earlier} fluid particles removed as damage within "
                    f"{self.unstable_window:g} s, more than unstable_fraction = {self.unstable_fraction:g}",
                    step=self.step, time=self.time, particle_id=rec[1], position=list(rec[2:2 + self.dim]))
        self.escaped.extend(rec for rec, _m in gathered)
        self.escaped_mass += sum(m for _rec, m in gathered)
        for rec, m in gathered:
            reason = record_reason(rec, self.dim)
            self.escaped_mass_by_reason[reason] = self.escaped_mass_by_reason.get(reason, 0.0) + m
        keep = codes == KEEP
        self._n_own = int(np.count_nonzero(keep[:n]))
        fp.keep(keep)
        if self._halo_send is not None:      # the send lists named rows that are gone
            self._strip_halo()
            self._build_halo()

    # ---------------------------------------------------------------- gathered state: checkpoint, frames, summary
    def _gather_fluid(self):
        """The owned rows of every rank, on rank 0 (sorted by id: independent of the rank count); None elsewhere."""
        started = _time.perf_counter()
        with self._owned_view() as view:
            parts = self.comm.gather({name: np.array(a) for name, a in view.items()}, root=0)
        self.mpi_stats["comm_seconds"] += _time.perf_counter() - started
        if self.rank != 0:
            return None
        whole = ParticleArrays(self.dim)
        for name in parts[0]:
            whole.add(name, np.concatenate([p[name] for p in parts]))
        whole.permute(np.argsort(whole["id"], kind="stable"))
        return whole

    @contextlib.contextmanager
    def _whole_fluid(self, whole):
        fp = self.fluid.particles
        self.fluid.particles = whole
        try:
            yield
        finally:
            self.fluid.particles = fp

    def _frame_format(self):
        """How the fluid frames are written, for the summary (None without VTU output)."""
        for out in self.outputs:
            if isinstance(out, DecomposedVTK):
                return "vtu gathered on rank 0" if out.gather else "pvtu, one vtu piece per rank"
        return None

    def save_checkpoint(self, path):
        self._sync_walls()
        whole = self._gather_fluid()
        if self.rank == 0:
            with self._whole_fluid(whole):
                super().save_checkpoint(path)
        self.comm.Barrier()

    def summary(self, *, wall_time, loop_time, particle_steps, steps, startup):
        particle_steps = self._allreduce(float(particle_steps))
        loop_time = self._allreduce(float(loop_time), "max")
        with self._owned_view() as view:
            out = super().summary(wall_time=wall_time, loop_time=loop_time, particle_steps=particle_steps,
                                  steps=steps, startup=startup)
            mass_now = self._allreduce(float(view["m"].sum()))
            n_fluid = self._allreduce(int(view.n))
        initial = self.fluid.initial_mass
        samples = max(1, self.mpi_stats["halo_samples"])
        halo = self._allreduce(self.mpi_stats["halo_rows"] / samples)
        owned = max(1, n_fluid)
        comm_max = self._allreduce(self.mpi_stats["comm_seconds"], "max")
        out.update({
            "n_fluid": int(n_fluid),
            "mass_drift": float((mass_now + self.escaped_mass - initial) / initial),
            "fluid_mass_in_domain_change": float((mass_now - initial) / initial),
            "mpi": {"ranks": self.nranks, "cut_axis": "xyz"[self.cut_axis],
                    "cuts": [float(c) for c in self._cuts[1:-1]] if self._cuts is not None else [],
                    "halo_supports": self.halo_depth + MARGIN_SUPPORTS,
                    "halo_fraction": float(halo / owned),
                    "rebalances": int(self.mpi_stats["rebalances"]),
                    "comm_seconds_max_rank": float(comm_max),
                    "comm_seconds_per_step": float(comm_max / steps) if steps else None,
                    "walls": "replicated on every rank",
                    "fluid_frames": self._frame_format()},
        })
        return out


class DecomposedVTK(VTK):
    """The VTU/PVD series of a decomposed run.

    By default each rank writes its owned fluid particles as one piece, ``fluid_{k:05d}_p{rank}.vtu``,
    and rank 0 writes the frame ``fluid_{k:05d}.pvtu`` naming the pieces (rank order) and lists it in
    ``fluid.pvd``, so no rank ever holds the whole fluid. With ``gather`` (``--vtk-gather``) rank 0
    gathers the fluid, sorted by id, and writes the serial ``fluid_{k:05d}.vtu`` instead. The walls are
    replicated: rank 0 writes their serial series, after the integrated wall arrays are synchronised.
    """

    def __init__(self, inner, comm):
        self.__dict__.update(inner.__dict__)
        self.comm = comm
        self._last = None

    def open(self, sim, resume_after=None):
        if self.comm.Get_rank() == 0:
            super().open(sim, resume_after)
        else:
            forces = getattr(sim, "wall_forces", None)
            if self.walls and forces is not None:     # every rank reduces the same wall forces
                for wall in sim.walls:
                    forces.setdefault(wall.name, np.zeros(sim.dim))
            if resume_after is not None:
                self.next_time = first_due_after(resume_after, self.every)

    def write(self, sim):
        sim._sync_walls()
        if self.gather:
            whole = sim._gather_fluid()
            if self.comm.Get_rank() == 0:
                with sim._whole_fluid(whole):
                    super().write(sim)
        else:
            self._write_pieces(sim)
        if self.comm.Get_rank() != 0:
            self.next_time = next_due(self.next_time, self.every, sim.time)
        self._last = sim.time

    def _write_pieces(self, sim):
        from ..io.vtk import write_pvtu, write_vtu

        rank = self.comm.Get_rank()
        index = self.comm.bcast(self._fluid.next_index if rank == 0 else None, root=0)
        stem = f"fluid_{index:05d}"
        sources = [f"{stem}_p{r}.vtu" for r in range(self.comm.Get_size())]
        metadata = {**self._metadata(sim, "fluid"), "pieces": len(sources)}
        error = None
        with sim._owned_view() as view:
            data = self.fluid_point_data(sim, view)
            try:
                write_vtu(os.path.join(self.directory, sources[rank]), view["x"], data,
                          metadata={**metadata, "piece": rank}, **self._options(sim))
            except OSError as exc:
                error = exc
            # the frame is listed only once every piece is on disk; a rank that failed stops every rank
            failed = [(r, e) for r, e in enumerate(self.comm.allgather(None if error is None else str(error))) if e]
            if failed:
                if error is not None:
                    raise error
                raise OSError(f"rank {failed[0][0]} could not write its piece of frame {stem}: {failed[0][1]}")
            if rank == 0:
                try:
                    pvtu = write_pvtu(os.path.join(self.directory, f"{stem}.pvtu"), sources, view["x"], data,
                                      metadata=metadata, compress=self.compress, float32=self.float32)
                    self._fluid.add(sim.time, os.path.basename(pvtu))
                    self.write_walls(sim)
                except OSError as exc:
                    error = exc
                self.next_time = next_due(self.next_time, self.every, sim.time)
        # rank 0's files too: the others must not go on into an exchange rank 0 has left
        failed = self.comm.bcast(None if error is None else str(error), root=0)
        if failed:
            if error is not None:
                raise error
            raise OSError(f"rank 0 could not write frame {stem}: {failed}")

    def last_time(self):
        # every rank must agree on whether a last frame is due (writing one is collective)
        return self.comm.bcast(super().last_time() if self.comm.Get_rank() == 0 else None, root=0)

    def write_state(self, sim, filename):
        if self.comm.Get_rank() == 0:
            super().write_state(sim, filename)
