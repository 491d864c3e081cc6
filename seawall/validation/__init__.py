"""``seawall validate``: validation entries, their stored results and docs/validation.md.

Each validated case has one folder of the repository checkout, ``validation/<case>/``:

* ``entry.py`` -- its entry, ``ENTRY = Entry(...)`` (or several as a tuple ``ENTRIES``,
  when they share one run with other settings): a name, a title, the expected
  duration of its full run, and ``run(ctx)`` returning rows (case, quantity,
  reference, reference value, seawall value, error, tolerance, pass/fail) and plots;
* ``results/<name>.json`` -- the stored result of each of its entries (committed);
* ``img/`` -- its figures; other ``*.py`` there are stand-alone scripts about the
  same subject (``python validation/<case>/<script>.py``), ``runs/`` their
  uncommitted output.

The folders are discovered automatically, so adding an entry is adding one
folder with an ``entry.py`` (or one ``Entry`` to a tuple). Each ``entry.py`` is
loaded as ``seawall.validation.entries.<case>`` (``-`` read as ``_``), the name
it had when the entries lived inside the package. The shared helpers
(:class:`Entry`, :func:`row`, :class:`Context`, ``_common``, ``_channel``) stay
here. Without the checkout (seawall installed on its own) there is nothing to
validate and ``seawall validate`` says so in one line.

``seawall validate [NAME ...]`` runs the named entries (default: all) at their
stated resolution, stores each entry's result as ``validation/<case>/results/<name>.json``
and regenerates ``docs/validation.md`` from *all* stored results, so one entry
can be re-run without re-running the others; ``--doc-only`` regenerates the
markdown alone. Every number in the markdown comes from a stored result, which
records the command that produced it, the git commit and the date.

Tolerances are part of each entry's source, fixed before its result is seen;
a row that misses its tolerance is reported as ``fail``, never tuned.

Long entries can be resumed: ``seawall validate NAME --checkpoints DIR`` makes every
entry that runs its simulation through :meth:`Context.run` keep a checkpoint in
``DIR/<name>/checkpoint.h5`` (``<name>-quick`` with ``--quick``; every 1/20 of its end time, and at Ctrl-C or SIGTERM),
and continue from it when the same command is given again. A restart continues bit
for bit (:meth:`seawall.Simulation.restart`, ``tests/unit/test_simulation.py``), so the
stored result is that of the uninterrupted run; it records where it resumed.
"""

import datetime
import importlib
import importlib.util
import json
import math
import os
import subprocess
import sys
import time
from dataclasses import dataclass, field

from ..errors import ParameterError

PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(PACKAGE_DIR))
DATA = os.path.join(ROOT, "data")
VALIDATION_DIR = os.path.join(ROOT, "validation")   # one folder per validated case
#: ``None``: each entry's result is stored in its own folder, ``validation/<case>/results/``
DEFAULT_RESULTS = None
ENTRY_MODULES = "seawall.validation.entries"
DEFAULT_DOC = os.path.join(ROOT, "docs", "validation.md")
QUICK_DIR = os.path.join("runs", "validate-quick")


@dataclass
class Entry:
    """One validation entry.

    ``run(ctx)`` receives a :class:`Context` and returns a dict with ``rows``
    (list of :func:`row` dicts), optionally ``plots`` (PNG paths written with
    ``ctx.plot_path``), ``settings`` (one line: resolution, model, end time)
    and ``notes`` (list of sentences).
    """

    name: str
    title: str
    run: object
    expected_s: float            # duration of the full run on one core of the reference machine [s]
    order: int = 100             # position in docs/validation.md
    description: str = ""
    quick_s: float = 30.0
    folder: str = field(default=None, compare=False)   # validation/<case>/, set when discovered

    @property
    def results_dir(self):
        """Where ``seawall validate`` stores this entry's result by default."""
        return os.path.join(self.folder, "results") if self.folder else None

    @property
    def command(self):
        return f"seawall validate {self.name}"


@dataclass
class Context:
    quick: bool
    img_dir: str
    threads: int = None
    data_dir: str = DATA
    plots: list = field(default_factory=list)
    #: ``seawall validate --checkpoints DIR``: where :meth:`run` keeps this entry's checkpoint
    checkpoint_dir: str = None
    #: the simulated times at which :meth:`run` continued from a checkpoint (stored with the result)
    resumed_at: list = field(default_factory=list)
    #: where the entry's result JSON goes (``seawall validate --results DIR``); files an entry keeps
    #: beside it (e.g. a series for figures) go there too
    results_dir: str = None

    def run(self, sim, t_end, *, checkpoints=20):
        """``sim.run(t_end)`` for an entry, resumable with ``--checkpoints``; returns its RunResult.

        With a checkpoint directory the run writes ``checkpoint.h5`` there every ``t_end /
        checkpoints`` and at Ctrl-C or SIGTERM (after the current step), and an existing one is
        loaded first (it must come from the same entry: :meth:`seawall.Simulation.restart` checks
        the build), so a stopped entry continues where it stopped. A checkpoint already at
        ``t_end`` is measured as it is.
        """
        if self.checkpoint_dir is None:
            return sim.run(t_end, progress=False)
        from ..interrupts import stop_on_signals
        from ..output import Checkpoint

        path = os.path.join(self.checkpoint_dir, "checkpoint.h5")
        if os.path.isfile(path):
            sim.restart(path)
            self.resumed_at.append(float(sim.time))
            print(f"  continuing from {path} at t = {sim.time:.6g} s (step {sim.step})", flush=True)
        sim.add(Checkpoint(self.checkpoint_dir, every=t_end / checkpoints))
        if sim.time >= t_end * (1.0 - 1e-9):
            return sim.result(sim.summary_so_far())
        with stop_on_signals(lambda: sim):
            return sim.run(t_end, progress=False)

    def data(self, folder, name):
        import numpy as np

        return np.loadtxt(os.path.join(self.data_dir, folder, name), delimiter=",", skiprows=1)

    def result_path(self, filename):
        """Path of a file the entry keeps beside its result JSON (a series for figures), in
        :attr:`results_dir` (:func:`run_entry` sets it: the entry's ``results/`` or ``--results DIR``)."""
        if self.results_dir is None:
            raise ParameterError("this validation context has no results directory (run the entry with run_entry)")
        os.makedirs(self.results_dir, exist_ok=True)
        return os.path.join(self.results_dir, filename)

    def plot_path(self, name, suffix=""):
        os.makedirs(self.img_dir, exist_ok=True)
        path = os.path.join(self.img_dir, f"validation_{name}{suffix}.png")
        self.plots.append(path)
        return path


def row(case, quantity, reference, ref_value, value, *, error=None, kind="relative", tolerance, unit="",
        passed=None, fmt="{:.4g}"):
    """One table row. ``kind``: ``relative`` (error = (value - ref) / ref unless given), ``absolute``
    (value - ref), ``"% of <scale>"`` (error given as a fraction of a named scale) or a free text describing ``error``. ``passed`` defaults to |error| <= tolerance."""
    if error is None and value is not None and ref_value is not None:
        error = (value - ref_value) / ref_value if kind == "relative" else value - ref_value
    if passed is None:
        passed = error is not None and math.isfinite(error) and abs(error) <= tolerance
    return {"case": case, "quantity": quantity, "reference": reference, "reference_value": ref_value,
            "value": value, "error": error, "error_kind": kind, "tolerance": tolerance, "unit": unit,
            "pass": bool(passed), "format": fmt}


def case_folders(validation_dir=None):
    """The case folders holding an ``entry.py`` (name -> path), sorted by name."""
    validation_dir = validation_dir or VALIDATION_DIR
    if not os.path.isdir(validation_dir):
        raise ParameterError(f"the validation folder is not there ({validation_dir}): seawall validate needs the "
                             "repository checkout (validation/<case>/entry.py), not only the installed package")
    return {name: os.path.join(validation_dir, name) for name in sorted(os.listdir(validation_dir))
            if os.path.isfile(os.path.join(validation_dir, name, "entry.py"))}


def _import_path(name, path):
    """The module of the file ``path`` as ``sys.modules[name]``: imported once, again only when that
    name holds another file (another checkout's)."""
    module = sys.modules.get(name)
    if module is None or os.path.abspath(getattr(module, "__file__", "")) != os.path.abspath(path):
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[name]
            raise
    return module


def load_script(path):
    """The script at ``path`` of the checkout (a validation study, e.g. ``validation/leaks/sweep.py``,
    a benchmark, the docs builder; relative paths are taken from the checkout's root), imported once
    by its path: the case folders' names (``dam-break``) are not package names, and the study
    scripts build on each other. Scripts pass their sibling's full path, so that a checkout's
    scripts load each other, whichever seawall is imported."""
    path = os.path.abspath(os.path.join(ROOT, path))
    if not os.path.isfile(path):
        raise ParameterError(f"no script at {path}: the validation studies need the repository checkout")
    folder, stem = os.path.split(os.path.splitext(path)[0])
    # a flat module name (a dotted one would name parent packages that do not exist)
    name = "seawall_script_" + "".join(c if c.isalnum() else "_" for c in f"{os.path.basename(folder)}_{stem}")
    return _import_path(name, path)


def entry_modules(validation_dir=None):
    """Each case folder's ``entry.py``, imported as ``seawall.validation.entries.<case>`` (module name -> module)."""
    folders = case_folders(validation_dir)
    # the package they are named after (its __init__ calls back here; the nested call finds it importing)
    package = importlib.import_module(ENTRY_MODULES)
    modules = {}
    for case, folder in folders.items():
        name = f"{ENTRY_MODULES}.{case.replace('-', '_')}"
        path = os.path.join(folder, "entry.py")
        module = _import_path(name, path)
        modules[case.replace("-", "_")] = module
        setattr(package, case.replace("-", "_"), module)
    return modules


def all_entries(validation_dir=None):
    """All entries, discovered in validation/<case>/entry.py, sorted by order then name."""
    found = {}
    for module in entry_modules(validation_dir).values():
        entries = [getattr(module, "ENTRY", None), *getattr(module, "ENTRIES", ())]
        for entry in entries:
            if not isinstance(entry, Entry):
                continue
            if entry.name in found:
                raise ParameterError(f"two validation entries are named {entry.name!r}")
            entry.folder = os.path.dirname(os.path.abspath(module.__file__))
            found[entry.name] = entry
    return dict(sorted(found.items(), key=lambda kv: (kv[1].order, kv[0])))


def _git_commit():
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                             timeout=10)
        # the package and the entries' sources (their results and figures change with every run)
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "seawall",
                                ":(glob)validation/*/entry.py"], cwd=ROOT,
                               capture_output=True, text=True, timeout=10)
        if out.returncode == 0:
            return out.stdout.strip() + ("+local changes" if dirty.stdout.strip() else "")
    except (OSError, subprocess.SubprocessError):
        pass
    return None


def _fmt_duration(s):
    return f"{s / 60:.1f} min" if s >= 90 else f"{s:.0f} s"


def run_entry(entry, *, quick, results=None, img_dir=None, threads=None, checkpoints=None):
    """Run one entry, store ``results/<name>.json`` and return the stored dict (``results`` and
    ``img_dir`` default to the entry's own ``validation/<case>/results`` and ``validation/<case>/img``;
    ``checkpoints``: the directory under which the entry keeps ``<name>/checkpoint.h5``, see
    :meth:`Context.run`)."""
    import numba

    if results is None or img_dir is None:
        if entry.folder is None:
            raise ParameterError(f"validation entry {entry.name!r} has no folder: give results and img_dir")
        results = results or entry.results_dir
        img_dir = img_dir or os.path.join(entry.folder, "img")
    if threads is not None:
        numba.set_num_threads(int(threads))
    ctx = Context(quick=quick, img_dir=img_dir, threads=threads, results_dir=results,
                  checkpoint_dir=None if checkpoints is None
                  else os.path.join(checkpoints, entry.name + ("-quick" if quick else "")))
    started = time.perf_counter()
    out = entry.run(ctx)
    duration = time.perf_counter() - started
    rows = out.get("rows", [])
    stored = {
        "name": entry.name, "title": entry.title, "description": entry.description,
        "command": entry.command + (" --quick" if quick else ""),
        "quick": quick, "commit": _git_commit(), "date": datetime.date.today().isoformat(),
        "duration_s": round(duration, 1), "threads": numba.get_num_threads(),
        "settings": out.get("settings", ""),
        "notes": out.get("notes", []) + ([
            "Run resumed from its checkpoint at t = " + ", ".join(f"{t:.6g}" for t in ctx.resumed_at)
            + " s (seawall validate --checkpoints; a restart continues bit for bit)."] if ctx.resumed_at else []),
        "rows": rows,
        **({"resumed_at": ctx.resumed_at} if ctx.resumed_at else {}),
        # relative to the repository root, so the stored result does not depend on this machine
        "plots": [os.path.relpath(os.path.abspath(p), ROOT) for p in (out.get("plots") or ctx.plots)],
    }
    os.makedirs(results, exist_ok=True)
    with open(os.path.join(results, f"{entry.name}.json"), "w") as fh:
        json.dump(_plain(stored), fh, indent=1)
    return stored


def _plain(obj):
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if hasattr(obj, "item"):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def load_results(results, registry=None):
    """Stored results (name -> dict): every JSON in the directory ``results``, or, when ``results``
    is None, each entry of ``registry`` (default: all) from its own ``validation/<case>/results/``."""
    out = {}
    if results is None:
        for name, entry in (all_entries() if registry is None else registry).items():
            path = os.path.join(entry.results_dir, f"{name}.json") if entry.results_dir else None
            if path and os.path.isfile(path):
                with open(path) as fh:
                    data = json.load(fh)
                out[data["name"]] = data
        return out
    if os.path.isdir(results):
        for fname in sorted(os.listdir(results)):
            if fname.endswith(".json"):
                with open(os.path.join(results, fname)) as fh:
                    data = json.load(fh)
                out[data["name"]] = data
    return out


def _cell(value, fmt):
    if value is None:
        return "n/a"
    if isinstance(value, str):
        return value
    return fmt.format(value)


def _error_cell(r):
    e = r["error"]
    if e is None:
        return "n/a"
    kind = r["error_kind"]
    if kind == "relative":
        return f"{100 * e:+.2f} %"
    if kind == "absolute":
        return f"{e:+.4g}{(' ' + r['unit']) if r['unit'] else ''}"
    if kind.startswith("% of "):
        return f"{100 * e:+.2f} {kind}"
    return f"{e:.4g} ({kind})"


def _tolerance_cell(r):
    t = r["tolerance"]
    kind = r["error_kind"]
    if isinstance(t, str):
        return t
    if kind == "relative":
        return f"{100 * t:g} %"
    if kind == "absolute":
        return f"{t:g}{(' ' + r['unit']) if r['unit'] else ''}"
    if kind.startswith("% of "):
        return f"{100 * t:g} {kind}"
    return f"{t:g} ({kind})"


def replace_block(doc, begin, end, body, *, append=False):
    """Replace the text between the marker lines ``begin`` and ``end`` of the file ``doc`` by ``body``.

    The scripts that write measured tables into docs/ (leak sweep, plateau profiles, benchmarks) keep
    the prose around their block. A missing marker stops with one line naming the file, unless
    ``append``, which adds the block at the end.
    """
    with open(doc) as fh:
        text = fh.read()
    block = f"{begin}\n{body}\n{end}"
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        text = head + block + rest.split(end, 1)[1]
    elif append:
        text = text.rstrip() + "\n\n" + block + "\n"
    else:
        raise SystemExit(f"{doc} lacks the markers {begin} ... {end}")
    with open(doc, "w") as fh:
        fh.write(text)


def write_markdown(doc, stored, registry, *, title_note=""):
    """docs/validation.md from the stored results (entries without a result are listed as not run)."""
    doc_dir = os.path.dirname(os.path.abspath(doc))
    lines = ["# Validation", "",
             "Generated by `seawall validate` from the stored per-entry results in "
             "`validation/<case>/results/*.json`; do not edit by hand. Re-run one entry with "
             "`seawall validate NAME` (its rows are replaced, the others kept), all with `seawall validate`. "
             "Each section names the command, commit and date that produced its numbers; "
             "tolerances are fixed in the entry's source (`validation/<case>/entry.py`) before the result "
             "is seen, and a miss is reported as **fail**, never tuned away.", ""]
    if title_note:
        lines += [title_note, ""]
    names = list(registry) + [n for n in stored if n not in registry]
    lines += ["| entry | case | quantity | reference | reference value | seawall | error | tolerance | result |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name in names:
        res = stored.get(name)
        if res is None:
            lines.append(f"| {name} | | | | | | | | not run |")
            continue
        for r in res["rows"]:
            fmt = r.get("format", "{:.4g}")
            unit = f" {r['unit']}" if r["unit"] and not isinstance(r["value"], str) else ""
            lines.append("| " + " | ".join([
                f"[{name}](#{name})", r["case"], r["quantity"], r["reference"],
                _cell(r["reference_value"], fmt) + (unit if r["reference_value"] is not None else ""),
                _cell(r["value"], fmt) + (unit if r["value"] is not None else ""),
                _error_cell(r), _tolerance_cell(r), "pass" if r["pass"] else "**fail**"]) + " |")
    n_rows = sum(len(stored[n]["rows"]) for n in names if n in stored)
    n_pass = sum(r["pass"] for n in names if n in stored for r in stored[n]["rows"])
    lines += ["", f"{n_pass} of {n_rows} rows pass.", ""]
    for name in names:
        entry = registry.get(name)
        res = stored.get(name)
        lines += [f"## {name}", ""]
        title = res["title"] if res else entry.title
        lines += [f"**{title}**", ""]
        desc = res.get("description") if res else entry.description
        if desc:
            lines += [desc, ""]
        if res is None:
            lines += [f"Not run yet: `{entry.command}` (about {_fmt_duration(entry.expected_s)}).", ""]
            continue
        lines += [f"- command: `{res['command']}`",
                  f"- commit {res['commit'] or 'unknown'}, {res['date']}, {_fmt_duration(res['duration_s'])} "
                  f"with {res['threads']} thread(s)" + (" (quick smoke run, not a validation)" if res["quick"] else ""),
                  f"- settings: {res['settings']}" if res["settings"] else "", ""]
        for note in res.get("notes", []):
            lines += [note, ""]
        for plot in res.get("plots", []):
            rel = os.path.relpath(os.path.join(ROOT, plot), doc_dir)
            lines += [f"![{name}]({rel})", ""]
    text = "\n".join(ln for k, ln in enumerate(lines) if not (ln == "" and k > 0 and lines[k - 1] == "")) + "\n"
    os.makedirs(doc_dir, exist_ok=True)
    with open(doc, "w") as fh:
        fh.write(text)
    return doc


def run_validate(names=None, *, quick=False, results=None, doc=None, threads=None, list_only=False,
                 doc_only=False, scheduler=None, workers=None, checkpoints=None):
    """The ``seawall validate`` command. Exit code 0 when every entry ran (a failed row is a result,
    not an error), 1 when an entry could not run. ``doc_only``: regenerate the markdown from the
    stored results without running anything. ``scheduler``: run the entries as tasks of a
    dask.distributed cluster (``"local"``: a LocalCluster of ``workers`` processes started here;
    seawall.executors) instead of one after the other in this process."""
    if checkpoints is not None and (doc_only or list_only):
        raise ParameterError("--checkpoints: --doc-only and --list run no entry")
    if checkpoints is not None and scheduler is not None:
        raise ParameterError("--checkpoints: keeps the checkpoints of entries run here, not with --scheduler")
    registry = all_entries()
    if list_only:
        width = max(len(n) for n in registry)
        for name, e in registry.items():
            print(f"{name:<{width}}  ~{_fmt_duration(e.quick_s if quick else e.expected_s):>8}  {e.title}")
        return 0
    if doc_only and names:
        raise ParameterError("--doc-only runs no entry: give no NAME")
    if checkpoints is not None:
        checkpoints = os.path.abspath(checkpoints)
    names = list(names or registry)
    unknown = [n for n in names if n not in registry]
    if unknown:
        raise ParameterError(f"unknown validation entry {unknown[0]!r}; available: {', '.join(registry)}")
    if quick:
        results = results or os.path.join(QUICK_DIR, "results")
        doc = doc or os.path.join(QUICK_DIR, "validation.md")
    else:
        doc = doc or DEFAULT_DOC
    # figures beside the results: in each entry's folder (default), else beside the markdown
    img_dir = None if results is None else os.path.join(os.path.dirname(os.path.abspath(doc)), "img")
    title_note = "Quick smoke run (coarse, short): these are not validation results." if quick else ""
    if doc_only:
        write_markdown(doc, load_results(results, registry), registry, title_note=title_note)
        print(f"wrote {doc}")
        return 0
    from ..executors import InProcess, Task, executor_for, run_tasks

    # without --scheduler the entries run here, one after the other, as they always have
    executor = executor_for(scheduler=scheduler, workers=workers, n_tasks=len(names), threads_per_run=threads,
                            default_in_process=True)
    total = sum((registry[n].quick_s if quick else registry[n].expected_s) for n in names)
    print(f"seawall validate: {len(names)} entr{'y' if len(names) == 1 else 'ies'}, expected about "
          f"{_fmt_duration(total)} in total (one core; less with more)", flush=True)
    for n in names:
        e = registry[n]
        print(f"  {n:<18} ~{_fmt_duration(e.quick_s if quick else e.expected_s):>8}  {e.title}", flush=True)
    here = isinstance(executor, InProcess)
    if not here:
        print(f"on {executor.description}", flush=True)
        # a worker's working directory is its own: every path it is given is absolute
        results = None if results is None else os.path.abspath(results)
    tasks = [Task(run_named_entry, (n, VALIDATION_DIR, quick, results, img_dir,
                                    threads if here else executor.threads_per_run, checkpoints), n) for n in names]
    status = 0

    def report(index, outcome):
        nonlocal status
        n = names[index]
        if not outcome.ok:   # one broken entry must not lose the others' results
            print(f"[{n}] failed to run: {outcome.error}", file=sys.stderr, flush=True)
            status = 1
            return
        res = outcome.value
        if not here:
            print(f"\n[{n}] {registry[n].title}", flush=True)
        for r in res["rows"]:
            print(f"  {r['quantity']:<45} {_cell(r['value'], r.get('format', '{:.4g}')):>10} vs "
                  f"{_cell(r['reference_value'], r.get('format', '{:.4g}')):>10}  error {_error_cell(r):>10}  "
                  f"tol {_tolerance_cell(r):>8}  {'pass' if r['pass'] else 'FAIL'}", flush=True)
        print(f"[{n}] done in {_fmt_duration(res['duration_s'])}", flush=True)

    run_tasks(executor, tasks, desc="validate", progress=not here, on_done=report, report_failures=False)
    write_markdown(doc, load_results(results, registry), registry, title_note=title_note)
    print(f"\nwrote {doc}")
    return status


def run_named_entry(name, validation_dir, quick, results, img_dir, threads, checkpoints=None):
    """Find entry ``name`` in ``validation_dir`` and run it (:func:`run_entry`): a task of
    seawall.executors, given names and paths only, so a cluster's worker can run it."""
    entry = all_entries(validation_dir)[name]
    print(f"\n[{name}] {entry.title}: expected about {_fmt_duration(entry.quick_s if quick else entry.expected_s)}",
          flush=True)
    return run_entry(entry, quick=quick, results=results, img_dir=img_dir, threads=threads, checkpoints=checkpoints)
