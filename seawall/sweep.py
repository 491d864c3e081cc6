"""``seawall sweep CASE --set K=v1,v2,... [--set K2=...]``: one run per combination of values.

The runs are the Cartesian product of the ``--set`` values, the first key outermost (as
nested loops in the order given; a key with one value is a fixed setting of every run).
A key is anything ``seawall run --set`` takes -- a case parameter, an option of the wall
model, ``adhesion_coefficient``, a regularisation key or the damage budget (``unstable_fraction``,
``unstable_window``) -- checked the same way before any
run starts; the key ``boundary`` sweeps the wall model itself.

Each run has its own directory under ``--out``, ``NNN_K=v_K2=v2`` (NNN its position in the
product), holding ``probes.csv`` and ``summary.json`` as a run of ``seawall compare``
does. ``--out`` also gets ``sweep.csv`` and ``sweep.md``: each run's settings, its status,
escaped particles and the comparison metrics of ``seawall.compare`` (smallest wall
distance, wall-pressure error and noise, f_sym, energy drift), particle-steps/s, the
time-stepping wall time and the step count. A run that fails is a row with status
``failed: <error>``; the others go on. The runs go to local processes (``--jobs``) or to
a dask.distributed cluster (``--scheduler``; seawall.executors, docs/sweeps.md).
"""

import csv
import itertools
import os
import re

from .errors import ParameterError

#: the sweep key that chooses the wall model rather than a --set value
BOUNDARY_KEY = "boundary"
#: after the settings, the columns of sweep.csv (the metrics are defined in seawall.compare)
RESULT_COLUMNS = ["status", "escaped", "min_wall_distance_dx", "wall_pressure_error", "pressure_noise", "f_sym",
                  "energy_drift", "particle_steps_per_s", "wall_time_s", "steps", "escaped_domain",
                  "escaped_wall", "escaped_unstable", "run_dir", "escaped_overtopped"]


def split_set_item(item, form="KEY=VALUE"):
    """One ``--set`` item -> (key, value text), the key as ``seawall run --set`` reads it (``-`` is
    ``_``). No ``=`` or an empty key stops in one line naming the expected ``form``."""
    key, sep, text = item.partition("=")
    key = key.strip().replace("-", "_")
    if not sep or not key:
        raise ParameterError(f"--set expects {form}, got {item!r}")
    return key, text


def parse_set_items(items):
    """``--set KEY=VALUE`` items -> ``{KEY: value text}`` (stripped), as ``seawall run`` and the
    validation studies read them; a later item of the same key wins. Bad syntax stops in one line."""
    params = {}
    for item in items or []:
        key, value = split_set_item(item)
        params[key] = value.strip()
    return params


def parse_sweep_sets(items):
    """``--set K=v1,v2`` items -> ``{K: [v1, v2]}`` in the order given. Bad syntax, an empty value or
    a key given twice stop in one line."""
    grid = {}
    for item in items or []:
        key, text = split_set_item(item, "KEY=VALUE[,VALUE...]")
        values = [v.strip() for v in text.split(",")]
        if not text.strip() or any(not v for v in values):
            raise ParameterError(f"--set {key}: a value is empty in {item!r} (values are separated by commas)")
        if len(set(values)) != len(values):
            raise ParameterError(f"--set {key}: a value is listed twice in {item!r}")
        if key in grid:
            raise ParameterError(f"--set {key} is given twice; list its values once: {key}=v1,v2,...")
        grid[key] = values
    return grid


def combinations(grid):
    """The Cartesian product of ``grid`` (key -> values) as a list of {key: value}, first key outermost."""
    keys = list(grid)
    return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]


def run_dir_name(index, settings):
    """``NNN_K=v_K2=v2``: the run's position, then its settings with characters unsafe in a file name
    replaced by ``-`` (the position keeps two runs apart whose values read the same once replaced)."""
    parts = [f"{index:03d}"] + [f"{k}={v}" for k, v in settings.items()]
    return re.sub(r"[^A-Za-z0-9_.=+-]", "-", "_".join(parts))


def check_settings(case, boundary, params):
    """Refuse what ``case.build(boundary=boundary, **params)`` would refuse about the keys and the case
    parameters' values, without building: the same routing of a key (wall-model option, adhesion,
    regularisation, else a case parameter) and the same checks (``Case.resolve``, the model's factory)."""
    from .boundary.registry import boundary_by_name, boundary_options
    from .cases.base import ADHESION_KEY, GUARD_KEYS, REGULARISATION_KEYS, check_guard_settings

    model_keys = boundary_options(boundary)
    options = {k: v for k, v in params.items() if k in model_keys}
    check_guard_settings({k: v for k, v in params.items() if k in GUARD_KEYS and k not in model_keys})
    rest = {k: v for k, v in params.items()
            if k not in model_keys and k != ADHESION_KEY and k not in REGULARISATION_KEYS and k not in GUARD_KEYS}
    if "dx" in rest and "dx" not in case.parameters:
        raise ParameterError(f"case {case.name!r} takes no dx")
    case.resolve(rest)
    boundary_by_name(boundary, options)   # consumes the keys it takes
    if options:
        raise ParameterError(f"boundary {boundary!r} does not take option {sorted(options)[0]!r}")


def case_spec(case_name, case, executor):
    """How a run names its case: as given, or a case file by its absolute path for a cluster's workers
    (whose working directory is their own)."""
    from .executors import DaskCluster

    return os.path.abspath(case_name) if case.source is not None and isinstance(executor, DaskCluster) else case_name


def sweep(case_name, grid, *, out, boundary=None, t_end=None, executor=None, jobs=None, progress=True):
    """Run ``case_name`` once per combination of ``grid`` (key -> list of values, see
    :func:`parse_sweep_sets`) into ``out``; write sweep.csv and sweep.md; return the rows."""
    from .cases import case_by_name
    from .compare import run_case
    from .executors import Task, local_executor, run_tasks

    case = case_by_name(case_name)
    if not grid:
        raise ParameterError("seawall sweep needs at least one --set KEY=v1,v2,...")
    if BOUNDARY_KEY in grid and boundary is not None:
        raise ParameterError("--boundary and --set boundary=... both choose the wall model: give one")
    runs = combinations(grid)
    specs = []
    for index, settings in enumerate(runs):
        params = {k: v for k, v in settings.items() if k != BOUNDARY_KEY}
        model = settings.get(BOUNDARY_KEY, boundary or case.default_boundary)
        check_settings(case, model, params)   # every combination, before any run starts
        specs.append((model, params, run_dir_name(index, settings)))
    out = os.path.abspath(out)   # the runs may write from another process or machine
    os.makedirs(out, exist_ok=True)
    executor = executor or local_executor(jobs, len(runs))
    spec = case_spec(case_name, case, executor)
    tasks = [Task(run_case, (spec, model, params, t_end,
                             os.path.join(out, name), executor.threads_per_run, False), name)
             for model, params, name in specs]
    outcomes = run_tasks(executor, tasks, desc=f"sweep {case.name}", progress=progress)
    rows = []
    for settings, (model, _, name), outcome in zip(runs, specs, outcomes):
        row = {**settings, "boundary": model, "run_dir": name}
        if outcome.ok:
            m = outcome.value["summary"]["metrics"]
            row.update({c: m.get(c) for c in RESULT_COLUMNS if c in m})
        else:
            row["status"] = f"failed: {outcome.error}"
        rows.append(row)
    keys = list(grid) if BOUNDARY_KEY in grid else [BOUNDARY_KEY, *grid]
    _write_csv(os.path.join(out, "sweep.csv"), keys, rows)
    _write_markdown(os.path.join(out, "sweep.md"), case.name, grid, keys, rows, t_end)
    return rows


def _write_csv(path, keys, rows):
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(keys + RESULT_COLUMNS)
        for row in rows:
            writer.writerow(["" if row.get(c) is None else row.get(c) for c in keys + RESULT_COLUMNS])


def _write_markdown(path, case_name, grid, keys, rows, t_end):
    from .compare import _fmt

    header = keys + ["status", "escaped", "min wall distance [dx]", "wall-pressure error", "pressure noise", "f_sym",
                     "energy drift", "particle-steps/s", "wall time [s]", "steps", "run"]
    fields = [(k, None) for k in keys] + [
        ("status", None), ("escaped", "int"), ("min_wall_distance_dx", None), ("wall_pressure_error", "pct"),
        ("pressure_noise", "pct"), ("f_sym", None), ("energy_drift", "pct"), ("particle_steps_per_s", "M"),
        ("wall_time_s", None), ("steps", "int"), ("run_dir", None)]
    lines = [f"# {case_name}: sweep over {', '.join(grid)}", "",
             f"{len(rows)} runs, t_end = {t_end if t_end is not None else 'case default'}; metrics as in "
             "`seawall compare` (defined in `seawall/compare.py`); wall time: time stepping only. "
             "n/a: nothing to measure in this case.", "",
             "| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    for row in rows:
        cells = [_fmt(row.get(key), kind) for key, kind in fields]
        if os.path.exists(os.path.join(os.path.dirname(path), row["run_dir"], "summary.json")):   # a failed run has none
            cells[-1] = f"[{row['run_dir']}]({row['run_dir']}/summary.json)"
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |")
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
