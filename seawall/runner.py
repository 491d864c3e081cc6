"""The one run loop shared by every simulation type (SPH :class:`~seawall.Simulation`, DEM).

The runner owns everything that is about *running* rather than physics: the
clock (time, step, next time step), probes and their sampling schedule, the
probe CSV, outputs (VTU/PVD, checkpoints, line samplers), the progress bar,
signals (stop after a whole step), output errors, ``run()``, ``run_steps()``,
the summary timings and the checkpoint's clock and probe history. Probes that
count events of every step (:class:`~seawall.probes.Discharge`) define
``before_step(sim)`` and ``after_step(sim)``: the runner calls them around
``_integrate``, after ``_maintain`` and before the removals of
``_check_health``; their ``state()`` / ``set_state()`` go into checkpoints. A
simulation type subclasses :class:`Runner` and implements small hooks:

* ``_initialise()`` -- make the current state ready to step (rates, ``next_dt``);
* ``_maintain()`` -- between steps, before one (periodic wrap, removals, reordering);
* ``_integrate(dt)`` -- advance the state by ``dt`` (the clock is the runner's);
* ``_after_step(dt)`` -- after the clock moved (couplings);
* ``_check_health()`` -- raise :class:`~seawall.errors.InstabilityError` on a bad state;
* ``_time_step()`` -- the next time step;
* ``particles_per_step()`` -- particles one step updates (for particle-steps per second);
* ``_prepare_probes()`` -- make derived fields consistent before probes sample;
* ``_state_arrays()`` / ``_state_attrs()`` / ``_check_state()`` / ``_load_state()`` --
  the simulation's own part of a checkpoint and of a restart;
* ``summary(...)`` -- the summary dict from the runner's timings.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time as _time
from typing import Any

import numpy as np

from . import compile_ahead
from .errors import InstabilityError, OutputError, ParameterError, RunInterrupted, require_positive
from .output import VTK, Checkpoint
from .probes import Probe
from .rundir import output_error
from .sampling import LineSampler
from .schedule import TIME_TOLERANCE, next_due
from .subnormals import flushing


class RunResult:
    """What :meth:`Runner.run` returns: probe series as arrays and a summary dict."""

    def __init__(self, times, probes, summary, escaped):
        self.times = times
        self.probes = probes
        self.summary = summary
        self.escaped = escaped

    def __getitem__(self, name):
        return self.probes[name]

    def __repr__(self):
        return f"RunResult(steps={self.summary.get('steps')}, probes={list(self.probes)})"


class Runner:
    """Base class of simulations: the run loop, probes, outputs, signals and checkpoints.

    Subclasses call :meth:`_init_run_state` in their constructor, set ``dim``,
    ``metadata`` and ``escaped`` (records of removed particles), and implement
    the hooks listed in the module documentation.
    """

    #: output types :meth:`add` accepts (a subclass may narrow them)
    OUTPUT_TYPES = (VTK, Checkpoint, LineSampler)
    #: flush subnormal numbers to zero while the loops run (:mod:`seawall.subnormals`)
    flush_subnormals = True

    def _init_run_state(self):
        self.time = 0.0
        self.step = 0
        self.next_dt = None
        self.probes = []
        #: probes called around every step's integration (before_step / after_step)
        self._step_probes = []
        self.outputs = []
        self.probe_times = []
        self.probe_values = []
        self.probe_every = None
        self._next_probe = 0.0
        self.probe_csv = None
        self._output_dirs = []
        #: set (to the signal's name) to stop the run at the end of the current step (seawall.interrupts)
        self.stop_requested = None
        self.in_step_loop = False
        self.record_particle_forces = False
        self.wall_particle_forces = {}
        self._stats = None
        self._startup_s = 0.0

    def _frames_with_walls(self, t_next=None, t_last=None):
        """Whether a VTU frame with walls is written at t_next (any time if None; always at t_last)."""
        return any(isinstance(out, VTK) and out.walls and
                   (t_next is None or out.due(t_next) or t_next >= t_last) for out in self.outputs)

    def record_particle_forces_now(self):
        """Compute per-particle wall forces for a frame written before any step (Simulation does)."""

    # ------------------------------------------------------------------ hooks (defaults)
    def _initialise(self):
        """Make the current state ready to step; sets ``next_dt``."""
        raise NotImplementedError

    def _maintain(self):
        """Between steps: bookkeeping that is not part of the equations (nothing by default)."""

    def _integrate(self, dt):
        """Advance the state by ``dt``; the runner then advances time and step."""
        raise NotImplementedError

    def _after_step(self, dt):
        """After the clock moved (nothing by default)."""

    def _check_health(self):
        """Raise InstabilityError if the state is not usable (nothing by default)."""

    def _time_step(self):
        raise NotImplementedError

    def particles_per_step(self):
        raise NotImplementedError

    def _prepare_probes(self):
        """Bring derived fields up to date before the probes sample (nothing by default)."""

    def _register_probe(self, probe):
        """Subclass checks and bookkeeping for a probe being added (nothing by default)."""

    def _sample_probe(self, probe):
        """One probe's value now (a decomposed run combines the ranks' values here)."""
        return probe.sample(self)

    def _probe_row(self):
        """Every probe's value now, in order (derived fields brought up to date first)."""
        self._prepare_probes()
        return [self._sample_probe(p) for p in self.probes]

    def _adopt_output(self, out):
        """The output object to keep for ``out`` (a subclass may substitute its own writer)."""
        return out

    def _state_arrays(self):
        raise NotImplementedError

    def _state_attrs(self):
        raise NotImplementedError

    def _check_state(self, path, arrays, attrs):
        raise NotImplementedError

    def _load_state(self, path, arrays, attrs):
        raise NotImplementedError

    def summary(self, *, wall_time, loop_time, particle_steps, steps, startup):
        raise NotImplementedError

    # ------------------------------------------------------------------ probes and outputs
    def add(self, *items: Probe | VTK | Checkpoint | LineSampler, every: float | None = None) -> Runner:
        """Add probes and outputs (:class:`~seawall.output.VTK`, :class:`~seawall.output.Checkpoint`, ...).

        ``every`` sets the probe sampling interval [s] (default t_end / 1000).
        """
        for item in items:
            if isinstance(item, Probe):
                group = (item, *item.companions())
                for probe in group[1:]:     # refused before the probe itself is added
                    if any(p.name == probe.name for p in self.probes):
                        raise ParameterError(f"two probes are named {probe.name!r}")
                for probe in group:
                    self._add_probe(probe)
            elif isinstance(item, self.OUTPUT_TYPES):
                self.outputs.append(self._adopt_output(item))
            else:
                names = [t.__name__ for t in self.OUTPUT_TYPES]
                expected = ", ".join(names[:-1]) + " or " + names[-1] if len(names) > 1 else names[0]
                raise ParameterError(f"cannot add {item!r}: expected a probe, {expected}")
        if every is not None:
            self.probe_every = require_positive("every", every)
        return self

    def _add_probe(self, item):
        point = getattr(item, "point", None)
        if point is not None and np.size(point) != self.dim:
            raise ParameterError(f"probe {item.name!r}: point {np.asarray(point).tolist()} has "
                                 f"{np.size(point)} coordinates, the run is {self.dim}D")
        if any(p.name == item.name for p in self.probes):
            raise ParameterError(f"two probes are named {item.name!r}")
        self._register_probe(item)
        self.probes.append(item)
        if callable(getattr(item, "after_step", None)):
            self._step_probes.append(item)

    def accepts(self, output_type):
        """Whether :meth:`add` takes outputs of this type (the CLI asks before preparing a run directory)."""
        return issubclass(output_type, self.OUTPUT_TYPES)

    def _sample(self, force=False):
        if not self.probes:
            return
        if not force and self.time < self._next_probe - 1e-12:
            return
        row = self._probe_row()
        self.probe_times.append(self.time)
        self.probe_values.append(row)
        if self.probe_csv is not None:
            self._check_output_dirs()
            with self._writing(self.probe_csv.path):
                self.probe_csv.append(self.time, row)
        self._next_probe = next_due(self._next_probe, self.probe_every, self.time)

    # ------------------------------------------------------------------ stepping
    def _one_step(self, dt):
        self._maintain()
        for probe in self._step_probes:
            probe.before_step(self)
        self._integrate(dt)
        for probe in self._step_probes:
            probe.after_step(self)
        self.time += dt
        self.step += 1
        self._after_step(dt)
        self._check_health()
        self.next_dt = self._time_step()
        if not (self.next_dt > 0) or not math.isfinite(self.next_dt):
            self._check_health()
            raise InstabilityError(f"time step became {self.next_dt} at step {self.step}, t = {self.time:.6g} s",
                                   step=self.step, time=self.time)
        # every loop of a step is compiled now: a compile helper still running compiles what no step
        # needs, and would take a core from the run
        compile_ahead.finish()

    def run_steps(self, n_steps: int) -> None:
        """Advance exactly ``n_steps`` steps with no probes or output (benchmarks)."""
        with flushing(self.flush_subnormals):
            self._initialise()
            for _ in range(int(n_steps)):
                self._one_step(self.next_dt)

    def first_time_step(self) -> float:
        """Make the state ready (compiling the loops) and return the next time step [s]."""
        started = _time.perf_counter()
        with flushing(self.flush_subnormals):
            self._initialise()
        self._startup_s += _time.perf_counter() - started
        return self.next_dt

    def run(self, t_end: float, *, progress: bool = True, probe_csv: str | os.PathLike | None = None,
            max_steps: int | None = None) -> RunResult:
        """Run until simulated time ``t_end`` [s]; return a :class:`RunResult`.

        ``probe_csv``: path of a CSV file receiving every probe sample as it
        is taken (flushed row by row, so an interrupted run keeps its data).
        An output that cannot be written (disk full, directory removed)
        stops the run with :class:`~seawall.errors.OutputError`; a stop asked
        for by a signal (``stop_requested``, see :mod:`seawall.interrupts`)
        ends the current step, writes the checkpoints and raises
        :class:`~seawall.errors.RunInterrupted`.
        """
        with flushing(self.flush_subnormals):
            return self._run(t_end, progress=progress, probe_csv=probe_csv, max_steps=max_steps)

    def _run(self, t_end, *, progress, probe_csv, max_steps):
        t_end = require_positive("t_end", t_end)
        if t_end <= self.time:
            raise ParameterError(f"t_end = {t_end:g} s must exceed the current time {self.time:g} s")
        # the loop's "reached t_end" tolerance; below 1e-12 only for end times that small
        eps = min(TIME_TOLERANCE, 1e-9 * t_end)
        if self.probe_every is None:
            self.probe_every = t_end / 1000.0
        wall_start = _time.perf_counter()
        self._stats = {"wall_start": wall_start, "loop_start": None, "particle_steps": 0,
                       "steps_at_start": self.step, "startup": self._startup_s}
        resume_after = self.time if self.step > 0 else None
        self._output_dirs = sorted({out.directory for out in self.outputs}
                                   | ({os.path.dirname(os.path.abspath(probe_csv))} if probe_csv else set()))
        if probe_csv is not None and self.probes:
            from .io.csvout import ProbeCSVWriter

            # first: an existing probes.csv with other columns refuses the restart before any file is touched
            with self._writing(probe_csv):
                os.makedirs(os.path.dirname(os.path.abspath(probe_csv)), exist_ok=True)
                try:
                    self.probe_csv = ProbeCSVWriter(probe_csv, [p.name for p in self.probes],
                                                    resume=resume_after is not None,
                                                    resume_after=resume_after if resume_after is not None else 0.0)
                except ValueError as exc:
                    raise ParameterError(str(exc)) from None
        try:
            for out in self.outputs:
                with self._writing(getattr(out, "path", out.directory)):
                    out.open(self, resume_after=resume_after)
        except BaseException:
            if self.probe_csv is not None:
                self.probe_csv.close()
                self.probe_csv = None
            raise
        self._initialise()
        startup = self._startup_s + _time.perf_counter() - wall_start
        self._startup_s = 0.0
        self._stats["startup"] = startup
        if self.step == 0:
            self._sample(force=True)
            if self._frames_with_walls():
                self.record_particle_forces_now()
            for out in self.outputs:
                if isinstance(out, (VTK, LineSampler)):
                    self._write(out)
        steps_at_start = self.step
        loop_start = _time.perf_counter()
        self._stats["loop_start"] = loop_start
        bar = _progress_bar(t_end, self.time, progress)
        last_bar = loop_start
        self.in_step_loop = True
        try:
            while self.time < t_end - eps:
                if max_steps is not None and self.step - steps_at_start >= max_steps:
                    break
                dt = min(self.next_dt, t_end - self.time)
                n_now = self.particles_per_step()
                # per-particle wall forces are computed only in a step that ends with a VTU frame
                self.wall_particle_forces = {}
                self.record_particle_forces = self._frames_with_walls(self.time + dt, t_end - eps)
                self._one_step(dt)
                self.record_particle_forces = False
                self._stats["particle_steps"] += n_now
                self._sample()
                for out in self.outputs:
                    if out.due(self.time):
                        self._write(out)
                if self.stop_requested is not None:
                    self._stop_for_signal()
                now = _time.perf_counter()
                if bar is not None and (now - last_bar > bar.mininterval or self.time >= t_end - eps):
                    rate = self._stats["particle_steps"] / max(now - loop_start, 1e-9)
                    bar.n = round(self.time, 6)
                    bar.set_postfix_str(f"step {self.step}, dt {self.next_dt:.2e} s, {rate / 1e6:.2f} M particle-steps/s")
                    last_bar = now
        finally:
            self.in_step_loop = False
            self._stats["loop_end"] = _time.perf_counter()
            if bar is not None:
                bar.close()
            if self.probe_csv is not None:
                self.probe_csv.close()
                self.probe_csv = None
        self._sample(force=self.probe_times[-1] < self.time if self.probe_times else bool(self.probes))
        for out in self.outputs:
            if isinstance(out, VTK):
                last = out.last_time()
                if last is None or last < self.time:
                    self._write(out)
            if isinstance(out, LineSampler):
                if out.next_time - out.every < self.time - TIME_TOLERANCE:
                    self._write(out)
                out.close()
        self._check_output_dirs()
        return self.result(self.summary_so_far())

    def summary_so_far(self):
        """The summary of the current (or last) run up to now; also after an interruption or a blow-up."""
        stats = self._stats or {"wall_start": _time.perf_counter(), "loop_start": None, "particle_steps": 0,
                                "steps_at_start": self.step, "startup": self._startup_s}
        now = _time.perf_counter()
        loop_start = stats["loop_start"]
        loop_time = (stats.get("loop_end", now) - loop_start) if loop_start is not None else 0.0
        return self.summary(wall_time=now - stats["wall_start"], loop_time=loop_time,
                            particle_steps=stats["particle_steps"], steps=self.step - stats["steps_at_start"],
                            startup=stats["startup"] if loop_start is not None else now - stats["wall_start"])

    def result(self, summary: dict[str, Any]) -> RunResult:
        times = np.asarray(self.probe_times, dtype=np.float64)
        values = np.asarray(self.probe_values, dtype=np.float64).reshape(len(self.probe_times), len(self.probes))
        probes = {p.name: values[:, k].copy() for k, p in enumerate(self.probes)}
        return RunResult(times, probes, summary, list(self.escaped))

    # ------------------------------------------------------------------ writing
    @contextlib.contextmanager
    def _writing(self, path):
        """Turn an OSError while writing ``path`` into an OutputError naming the file and the free space."""
        try:
            yield
        except OutputError:
            raise
        except OSError as exc:
            raise output_error(exc, path) from None

    def _write(self, out):
        self._check_output_dirs()
        with self._writing(getattr(out, "path", None) or out.directory):
            out.write(self)

    def _check_output_dirs(self):
        # open files (probes.csv, line_*.csv) accept writes after their directory is deleted, so look
        for directory in self._output_dirs:
            if not os.path.isdir(directory):
                raise OutputError(f"output directory {directory} was removed during the run; stopped at "
                                  f"t = {self.time:.6g} s", path=directory)

    def _stop_for_signal(self):
        """Stop asked for by a signal: checkpoint the state reached (consistent, between steps) and raise."""
        for out in self.outputs:
            if isinstance(out, Checkpoint):
                self._write(out)
        raise RunInterrupted(self.stop_requested)

    # ------------------------------------------------------------------ checkpoints
    def save_checkpoint(self, path):
        """Write the complete state (HDF5) so that :meth:`restart` continues bit for bit."""
        from .io.checkpoint import save_checkpoint

        arrays = self._state_arrays()
        arrays["probes"] = {
            "times": np.asarray(self.probe_times, dtype=np.float64),
            "values": np.asarray(self.probe_values, dtype=np.float64).reshape(len(self.probe_times), len(self.probes)),
        }
        attrs = {"time": self.time, "step": self.step, "next_dt": self.next_dt,
                 "next_probe": self._next_probe, "probe_every": self.probe_every,
                 "probe_names": [p.name for p in self.probes], "dim": self.dim, "metadata": self.metadata,
                 **self._state_attrs()}
        states = {p.name: p.state() for p in self.probes if callable(getattr(p, "state", None))}
        if states:
            attrs["probe_state"] = states
        save_checkpoint(path, arrays, attrs)

    def restart(self, path: str | os.PathLike) -> None:
        """Load a checkpoint written by :meth:`save_checkpoint` into this (identically built) simulation."""
        from . import restart_checks as checks
        from .io.checkpoint import load_checkpoint

        try:
            arrays, attrs = load_checkpoint(path)
        except (OSError, ValueError) as exc:
            raise ParameterError(str(exc)) from None
        if attrs.get("dim") != self.dim:
            raise ParameterError(f"checkpoint {path} is {attrs.get('dim')}D, this simulation is {self.dim}D")
        self._check_state(path, arrays, attrs)
        checks.check_probes(path, arrays.get("probes") or {}, len(self.probes))
        self._load_state(path, arrays, attrs)
        self.time = float(attrs["time"])
        self.step = int(attrs["step"])
        self.next_dt = float(attrs["next_dt"])
        self._next_probe = float(attrs["next_probe"])
        self.probe_every = attrs["probe_every"]
        names = list(attrs.get("probe_names") or [])
        if names != [p.name for p in self.probes]:
            raise ParameterError(f"checkpoint {path} has probes {names}, this simulation {[p.name for p in self.probes]}")
        states = attrs.get("probe_state") or {}
        for p in self.probes:
            if callable(getattr(p, "set_state", None)):
                if p.name not in states:
                    raise ParameterError(f"checkpoint {path} lacks the state of probe {p.name!r}")
                p.set_state(states[p.name])
        self.probe_times = arrays["probes"]["times"].tolist()
        self.probe_values = arrays["probes"]["values"].tolist()
        return self


def _in_notebook():
    """Whether we run in a Jupyter kernel (its stderr is no terminal, but a person is watching)."""
    shell = sys.modules.get("IPython")
    try:
        return shell is not None and type(shell.get_ipython()).__name__ == "ZMQInteractiveShell"
    except Exception:
        return False


def _progress_bar(t_end, t_start, enabled):
    if not enabled:
        return None
    from tqdm.auto import tqdm   # a widget in a notebook, text in a terminal

    # in a terminal or a notebook the bar redraws twice a second; in a log file one line every 30 s is plenty
    interactive = sys.stderr.isatty() or _in_notebook()
    return tqdm(total=round(t_end, 6), initial=round(t_start, 6), unit="s", file=sys.stderr,
                bar_format="{l_bar}{bar}| {n:.4f}/{total:.4f} s simulated [{elapsed}<{remaining}{postfix}]",
                dynamic_ncols=True, mininterval=0.5 if interactive else 30.0)
