"""Run one case with several wall models and compare them in numbers and plots.

``seawall compare CASE --boundaries A,B,C`` runs the case once per model
(in parallel processes where cores allow, or on a dask.distributed cluster with
``--scheduler``: seawall.executors), keeps each run's probes.csv and
summary.json in ``DIR/<model>/``, and writes ``DIR/compare.csv``,
``DIR/compare.md`` and one overlay plot per probe (``DIR/probe_<name>.png``).

Metrics, per model (a cell is "n/a" only where the case has nothing to measure):

* ``escaped`` -- fluid particles removed by the guards (``seawall.health``), and
  per reason ``escaped_domain`` (left the domain or the walls' hull),
  ``escaped_wall`` (crossed into a wall), ``escaped_unstable`` (density or
  non-finite guard), ``escaped_overtopped`` (went over a wall's crest and out:
  flow, not damage);
* ``min_wall_distance_dx`` -- smallest signed distance of any fluid particle to
  the wall surface over the run, in particle spacings (the wall particle
  nearest to the fluid particle gives the surface point s and normal n, and
  the distance is (x - s) . n; negative = inside the wall);
* ``wall_pressure_error`` -- mean over the wall probes of |mean(p) - p_ref| /
  (rho0 g H) over the second half of the run, for cases with a reference
  (hydrostatic: p_ref = rho0 g (H - y));
* ``pressure_noise`` -- mean over the wall probes of the RMS of (p - its running
  mean over 0.05 s), divided by rho0 g H (or by the largest |p| for cases
  without a hydrostatic scale): the high-frequency part of the wall pressure;
* ``f_sym`` -- the final value of the case's ``f_sym`` probe ([Li2022] eq. 29),
  where the case is symmetric;
* ``energy_drift`` -- relative change of the kinetic energy between the first
  and the last sample, for cases that conserve it (``particle-in-box``);
* ``particle_steps_per_s`` and ``relative_time`` (time stepping only, without
  start-up and compilation): relative_time is the time per particle-step
  relative to the fastest model, i.e. the fastest model's particle-steps/s
  over this one's (1 for the fastest; models that take more or smaller steps
  are not penalised for that, as they were when wall times were divided).
"""

import csv
import math
import os
import numpy as np

from .diagnostics import REASONS, pressure_noise, signed_wall_distance
from .errors import ParameterError
from .probes import Probe, WallPressure
from .rundir import write_json

ENERGY_CONSERVING_CASES = {"particle-in-box"}
COLUMNS = ["boundary", "status", "escaped", "min_wall_distance_dx", "wall_pressure_error", "pressure_noise",
           "f_sym", "energy_drift", "particle_steps_per_s", "wall_time_s", "relative_time", "steps",
           "escaped_domain", "escaped_wall", "escaped_unstable", "escaped_overtopped"]


class MinWallDistance(Probe):
    """Probe: smallest signed distance of a fluid particle to any wall surface, in particle spacings."""

    unit = "dx"

    def __init__(self, name="min_wall_distance_dx"):
        super().__init__(name)

    def sample(self, sim):
        fp = sim.fluid.particles
        best = math.inf
        g = sim.grid
        for wall in sim.walls:
            pa = wall.particles
            if "normal" not in pa or "surface" not in pa or fp.n == 0:
                continue
            out = np.empty(fp.n)
            signed_wall_distance(fp["x"], pa["x"], pa["normal"], pa["surface"], wall.cells.start,
                                 wall.cells.order, wall.cells.reach_mask(g), g.lo, g.inv_cell, g.ncell,
                                 sim.physics.support2, wall.spacing, out)
            best = min(best, float(out.min()))
        return best / sim.fluid.spacing if math.isfinite(best) else float("nan")


def run_one(case_name, boundary, dx, t_end, params, out_dir, threads):
    """Run one model (in a worker process) into ``out_dir/<boundary>``; return its summary dict with metrics."""
    kwargs = dict(params)
    if dx is not None:
        kwargs["dx"] = dx
    return run_case(case_name, boundary, kwargs, t_end, os.path.join(out_dir, boundary), threads)


def run_case(case_name, boundary, params, t_end, run_dir, threads, series=True):
    """One run of ``case_name`` with wall model ``boundary`` and the ``--set`` values ``params`` into
    ``run_dir`` (probes.csv, summary.json); return ``{"summary": ..., "times": ..., "probes": ...}``
    as plain data (``series=False``: the summary alone). Every argument is plain data, so the run
    can be sent to a process or a cluster worker (seawall.executors)."""
    import time

    from .cases import case_by_name
    from .errors import InstabilityError

    case = case_by_name(case_name)
    sim = case.build(boundary=boundary, threads=threads, **dict(params))
    sim.add(MinWallDistance(), every=case.probe_every)
    os.makedirs(run_dir, exist_ok=True)
    t_end = t_end or case.t_end
    started = time.perf_counter()
    status = "completed"
    try:
        result = sim.run(t_end, progress=False, probe_csv=os.path.join(run_dir, "probes.csv"))
        summary = result.summary
        times, probes = result.times, result.probes
    except InstabilityError as exc:
        status = f"unstable at t = {exc.time:.4g} s"
        summary = sim.summary(wall_time=time.perf_counter() - started, loop_time=0.0, particle_steps=0,
                              steps=sim.step, startup=0.0)
        res = sim.result(summary)
        times, probes = res.times, res.probes
    summary = {**summary, "status": status, "case": case_name, "boundary": boundary}
    summary["metrics"] = metrics(case_name, sim, times, probes, summary)
    write_json(os.path.join(run_dir, "summary.json"), _plain(summary))
    if not series:
        return _plain({"summary": summary})
    return _plain({"summary": summary, "times": times.tolist(), "probes": {k: v.tolist() for k, v in probes.items()}})


def metrics(case_name, sim, times, probes, summary):
    """The comparison metrics of one run (see module docstring)."""
    m = {"escaped": summary.get("escaped_particles"), "status": summary.get("status")}
    by_reason = summary.get("escaped_by_reason") or {}
    for reason in REASONS:
        m[f"escaped_{reason}"] = by_reason.get(reason)
    dist = probes.get("min_wall_distance_dx")
    m["min_wall_distance_dx"] = float(np.nanmin(dist)) if dist is not None and np.isfinite(dist).any() else None
    wall_probes = [name for name, p in zip(probes, sim.probes) if isinstance(p, WallPressure)]
    ref = getattr(sim, "reference", None) or {}
    if ref.get("type") == "hydrostatic":
        scale = ref["rho0"] * ref["g"] * ref["depth"]
    elif wall_probes:
        peak = max(float(np.nanmax(np.abs(probes[n]))) for n in wall_probes)
        scale = peak if peak > 0 else None
    else:
        scale = None
    m["wall_pressure_error"] = None
    if ref.get("type") == "hydrostatic" and len(times):
        late = times >= 0.5 * times[-1]
        errs = []
        for name, p in zip(probes, sim.probes):
            if name in wall_probes:
                exact = ref["rho0"] * ref["g"] * (ref["depth"] - p.point[-1])
                errs.append(abs(float(np.mean(probes[name][late])) - exact) / scale)
        m["wall_pressure_error"] = float(np.mean(errs)) if errs else None
    m["pressure_noise"] = None
    if wall_probes and scale:
        noise = [pressure_noise(times, probes[name]) for name in wall_probes]
        noise = [n / scale for n in noise if n is not None]
        m["pressure_noise"] = float(np.mean(noise)) if noise else None
    m["f_sym"] = float(probes["f_sym"][-1]) if "f_sym" in probes and len(probes["f_sym"]) else None
    m["energy_drift"] = None
    if case_name in ENERGY_CONSERVING_CASES and "kinetic_energy" in probes and len(probes["kinetic_energy"]) > 1:
        ke = probes["kinetic_energy"]
        m["energy_drift"] = float((ke[-1] - ke[0]) / ke[0]) if ke[0] else None
    m["particle_steps_per_s"] = summary.get("particle_steps_per_s")
    # time stepping only: start-up (compilation in a fresh worker) would swamp the comparison
    m["wall_time_s"] = summary.get("wall_time_s", 0.0) - summary.get("startup_s", 0.0)
    m["steps"] = summary.get("steps")
    return m


def _plain(obj):
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist())
    if hasattr(obj, "item"):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def compare(case_name, boundaries, *, out, dx=None, t_end=None, params=None, jobs=None, executor=None,
            progress=True):
    """Run ``case_name`` once per wall model in ``boundaries``; write the report; return the rows.

    ``executor`` (seawall.executors): where the runs go; default ``jobs`` local processes (one:
    this process). A run that fails is a row with status ``failed: <error>``, the others go on.
    """
    from .boundary.registry import BOUNDARIES
    from .cases import case_by_name
    from .executors import Task, local_executor, run_tasks
    from .sweep import case_spec, check_settings

    case = case_by_name(case_name)
    if not boundaries:
        raise ParameterError("--boundaries needs at least one wall model")
    unknown = [b for b in boundaries if b not in BOUNDARIES]
    if unknown:
        raise ParameterError(f"unknown boundary {unknown[0]!r}; available: {', '.join(BOUNDARIES)}")
    if len(set(boundaries)) != len(boundaries):
        raise ParameterError("--boundaries lists a model twice")
    params = dict(params or {})
    for b in boundaries:   # a bad --set key stops here, in one line, not in every run
        check_settings(case, b, {**params, **({"dx": dx} if dx is not None else {})})
    out = os.path.abspath(out)   # the runs may write from another process or machine
    os.makedirs(out, exist_ok=True)
    executor = executor or local_executor(jobs, len(boundaries))
    spec = case_spec(case_name, case, executor)
    tasks = [Task(run_one, (spec, b, dx, t_end, params, out, executor.threads_per_run), b) for b in boundaries]
    outcomes = run_tasks(executor, tasks, desc=f"compare {case.name}", progress=progress)
    results = [o.value if o.ok else _failed_result(case_name, b, o.error) for b, o in zip(boundaries, outcomes)]
    rows = []
    # the column beside particle-steps/s: the same ranking (dividing wall times listed a model that took
    # more steps, or compiled inside its loop, as the slowest although its rate was the highest)
    fastest = max((r["summary"]["metrics"]["particle_steps_per_s"] or 0.0) for r in results)
    for b, r in zip(boundaries, results):
        m = r["summary"]["metrics"]
        row = {"boundary": b, **m, "escaped_by_reason": {r: m.get(f"escaped_{r}") for r in REASONS}}
        rate = m.get("particle_steps_per_s")
        row["relative_time"] = (fastest / rate) if rate and fastest > 0 else None
        rows.append(row)
    _write_csv(os.path.join(out, "compare.csv"), rows)
    _write_markdown(os.path.join(out, "compare.md"), case_name, rows, dx, t_end)
    _plot_probes(out, boundaries, results)
    return rows


def _failed_result(case_name, boundary, error):
    """The result of a run that raised (or whose worker was lost): its status, no metrics, no series."""
    status = f"failed: {error}"
    return {"summary": {"case": case_name, "boundary": boundary, "status": status,
                        "metrics": {**{c: None for c in COLUMNS if c != "boundary"}, "status": status}},
            "times": [], "probes": {}}


def _fmt(value, kind):
    if value is None:
        return "n/a"
    if kind == "reasons":
        return " / ".join("n/a" if value.get(r) is None else str(int(value[r])) for r in REASONS)
    if kind == "pct":
        return f"{100 * value:.2f} %"
    if kind == "int":
        return str(int(value))
    if kind == "M":
        return f"{value / 1e6:.3f} M"
    if isinstance(value, float):
        return f"{value:.3g}"
    return str(value)


def _write_csv(path, rows):
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(COLUMNS)
        for row in rows:
            writer.writerow(["" if row.get(c) is None else row.get(c) for c in COLUMNS])


def _write_markdown(path, case_name, rows, dx, t_end):
    header = ["model", "status", "escaped", "of which domain / wall / unstable / overtopped", "min wall distance [dx]", "wall-pressure error", "pressure noise",
              "f_sym", "energy drift", "particle-steps/s", "relative time"]
    kinds = [None, None, "int", "reasons", None, "pct", "pct", None, "pct", "M", None]
    keys = ["boundary", "status", "escaped", "escaped_by_reason", "min_wall_distance_dx", "wall_pressure_error", "pressure_noise",
            "f_sym", "energy_drift", "particle_steps_per_s", "relative_time"]
    lines = [f"# {case_name}: wall models compared", "",
             f"dx = {dx if dx is not None else 'case default'}, t_end = {t_end if t_end is not None else 'case default'}; "
             "metrics are defined in `seawall/compare.py`. n/a: nothing to measure in this case.", "",
             "| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    for row in rows:
        lines.append("| " + " | ".join(_fmt(row.get(k), kind) for k, kind in zip(keys, kinds)) + " |")
    lines.append("")
    probe_pngs = sorted(f for f in os.listdir(os.path.dirname(path) or ".") if f.startswith("probe_"))
    for png in probe_pngs:
        lines.append(f"![{png[6:-4]}]({png})")
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def _plot_probes(out, boundaries, results):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(n for r in results for n in r["probes"] if n != "mass"))   # failed runs have none
    for name in names:
        fig, ax = plt.subplots(figsize=(7, 3.4), dpi=100)
        for b, r in zip(boundaries, results):
            if name in r["probes"]:
                ax.plot(r["times"], [np.nan if v is None else v for v in r["probes"][name]], lw=1, label=b)
        ax.set_xlabel("t [s]")
        ax.set_title(name)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"probe_{name}.png"))
        plt.close(fig)
