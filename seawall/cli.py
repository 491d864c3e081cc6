"""Command line: ``seawall cases | boundaries | run | compare | sweep | validate | plot | forces | sample |
discharge | bench | geometry``.

The output files of ``run`` (probes.csv, summary.json, the VTU/PVD series)
and the JSON line of ``bench`` are a contract other tools rely on: columns
and keys may be added, never renamed or dropped.
"""

import argparse
import json
import math
import os
import sys
import time

EXIT_BAD_INPUT = 2
EXIT_UNSTABLE = 3
#: an output file could not be written (disk full, output directory removed during the run)
EXIT_IO_ERROR = 4
#: stopped by Ctrl-C (SIGINT) / by SIGTERM: 128 + the signal's number, as a shell reports it
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143


def _parse_sets(items):
    from .sweep import parse_set_items

    return parse_set_items(items)


def _bad_input(message):
    from .errors import ParameterError

    return ParameterError(message)


def _positive(name):
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        if not (value > 0) or not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name} must be a positive number, got {text!r}")
        return value
    return parse


def _skin(text):
    """--neighbour-skin: a fraction of the support in [0, MAX_SKIN] (seawall.pair_list.check_skin)."""
    from .errors import ParameterError
    from .pair_list import check_skin

    try:
        return check_skin(text)
    except ParameterError as exc:
        # the option's name as typed; the rest of the message (the value given included) as it is
        raise argparse.ArgumentTypeError(str(exc).replace("neighbour_skin", "--neighbour-skin", 1)) from None


def _positive_int(name):
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a whole number, got {text!r}") from None
        if value < 1:
            raise argparse.ArgumentTypeError(f"{name} must be at least 1, got {text!r}")
        return value
    return parse


class _OneLineParser(argparse.ArgumentParser):
    """Bad arguments give one line naming the problem (``--help`` still shows usage)."""

    def error(self, message):
        self.exit(EXIT_BAD_INPUT, f"seawall: error: {message}\n")


class _VersionAction(argparse.Action):
    """``seawall --version``; the git commit is looked up only when asked."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        from .provenance import version_text

        print(version_text())
        parser.exit(0)


def _time_of_snapshot(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--time must be a number, got {text!r}") from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"--time must be a finite time >= 0, got {text!r}")
    return value


def build_parser():
    parser = _OneLineParser(
        prog="seawall", description="SPH with swappable, validated solid walls.")
    parser.add_argument("--version", action=_VersionAction, help="print the version (and git commit) and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_OneLineParser)
    sub.required = True

    cases = sub.add_parser("cases", help="list the named cases; with a NAME (or a case file), its parameters")
    cases.add_argument("name", nargs="?", metavar="NAME", help="a case name or a case file (.py or .toml)")
    new = sub.add_parser("new-case", help="write a commented starting case file NAME.py (or NAME.toml)")
    new.add_argument("name", metavar="NAME", help="file to write: NAME.py, or NAME.toml with --toml")
    new.add_argument("--toml", action="store_true", help="write the declarative TOML form instead of Python")
    new.add_argument("--force", action="store_true", help="replace an existing file")
    sub.add_parser("boundaries", help="list the wall models")

    run = sub.add_parser("run", help="run a case and write probes.csv, summary.json and VTU files")
    run.add_argument("case")
    run.add_argument("--boundary", help="wall model (see 'seawall boundaries'); default the case's own "
                     "(adami, or adami-noslip for flows that need no slip)")
    run.add_argument("--dx", type=_positive("--dx"), help="particle spacing [m] (case default otherwise)")
    run.add_argument("--t-end", type=_positive("--t-end"), help="simulated end time [s] (case default otherwise)")
    run.add_argument("--out", help="output directory (default runs/CASE-BOUNDARY)")
    run.add_argument("--threads", type=_positive_int("--threads"),
                     help="threads of the compiled loops (default: NUMBA_NUM_THREADS if set, else one per 4000 "
                          "particles, at most the cores)")
    run.add_argument("--set", action="append", metavar="KEY=VALUE", help="case or wall-model parameter")
    run.add_argument("--neighbour-skin", type=_skin, metavar="FRACTION",
                     help="skin of the fluid's kept pair list, as a fraction of the kernel support (default 0.1; "
                          "0: walk the cells every evaluation)")
    run.add_argument("--output-every", type=_positive("--output-every"), help="VTU interval [s]")
    run.add_argument("--probe-every", type=_positive("--probe-every"), help="probe sampling interval [s]")
    run.add_argument("--checkpoint-every", type=_positive("--checkpoint-every"),
                     help="HDF5 checkpoint interval [s] (default t_end/10)")
    run.add_argument("--restart", metavar="CHECKPOINT",
                     help="continue from a checkpoint of the same case, wall model and parameters")
    run.add_argument("--overwrite", action="store_true",
                     help="reuse an --out that holds an earlier run: delete seawall's files in it first")
    run.add_argument("--line", action="append", metavar="x0,y0:x1,y1:n",
                     help="sample pressure and velocity at n points on a line every --output-every seconds "
                          "into line_<k>.csv (repeatable; x0,y0,z0:x1,y1,z1:n in 3D)")
    run.add_argument("--sensor", action="append", metavar="x,y[,z][:diameter]",
                     help="pressure sensor: the wall pressure averaged over a face of the given diameter [m] "
                          "(a segment in 2D; default one kernel support) on the wall at the point; column "
                          "sensor:<k> in probes.csv (repeatable)")
    run.add_argument("--gauge", action="append", metavar="x[,y][:NAME]",
                     help="free-surface gauge: the elevation of the surface [m] above this horizontal position "
                          "(x in 2D, x,y in 3D; gravity gives the vertical), as `seawall sample --gauge` reads "
                          "it, the bed's elevation where dry; column gauge:<k> (gauge:NAME) in probes.csv "
                          "(repeatable)")
    run.add_argument("--discharge", action="append", metavar="x0,y0:x1,y1[:NAME]",
                     help="fluid volume that has crossed the section from (x0, y0) to (x1, y1), counted every step "
                          "(positive towards the side of end - start turned clockwise: +x for a section drawn "
                          "upwards): columns NAME [m^2 per metre] and NAME_rate [m^2/s] in probes.csv (default "
                          "NAME discharge:<k>; repeatable); in 3D x0,y0,z0:x1,y1,z1, the opposite corners of a "
                          "rectangle normal to the axis they share, positive along + that axis [m^3, m^3/s]")
    run.add_argument("--wall-force", action="append", metavar="NAME",
                     help="the fluid's force on the wall system NAME: columns wall_force:NAME:fx, :fy[, :fz] in "
                          "probes.csv [N, per metre of depth in 2D] (repeatable)")
    run.add_argument("--no-vtk", action="store_true", help="write no VTU/PVD files")
    run.add_argument("--vtk-float32", action="store_true",
                     help="VTU floating-point arrays and positions in single precision (about half the size)")
    run.add_argument("--vtk-uncompressed", action="store_true",
                     help="VTU arrays without zlib compression (the default compresses them)")
    run.add_argument("--vtk-gather", action="store_true",
                     help="under mpiexec: gather the fluid on rank 0 into one fluid_k.vtu per frame instead of a "
                          "fluid_k.pvtu with one piece per rank")
    run.add_argument("--no-progress", action="store_true", help="no progress bar")
    run.add_argument("--diagnostics", action="store_true",
                     help="also record the smallest fluid-to-wall distance (probe min_wall_distance_dx)")

    comp = sub.add_parser("compare", help="run a case with several wall models; write compare.md/.csv and plots")
    comp.add_argument("case")
    comp.add_argument("--boundaries", required=True, help="comma-separated wall models, e.g. adami,dbc,ghost-shepard")
    comp.add_argument("--dx", type=_positive("--dx"))
    comp.add_argument("--t-end", type=_positive("--t-end"))
    comp.add_argument("--out", help="output directory (default runs/compare-CASE, CASE the case's name)")
    comp.add_argument("--jobs", type=_positive_int("--jobs"), help="models run at once (default: cores)")
    comp.add_argument("--set", action="append", metavar="KEY=VALUE", help="case parameter, given to every model")
    _cluster_options(comp)

    swp = sub.add_parser("sweep", help="run a case once per combination of --set values; write sweep.md/.csv")
    swp.add_argument("case")
    swp.add_argument("--set", action="append", metavar="KEY=v1,v2,...", required=True,
                     help="a case or wall-model parameter and its values (repeatable: the runs are every "
                          "combination; KEY boundary sweeps the wall model)")
    swp.add_argument("--boundary", help="wall model of every run; default the case's own")
    swp.add_argument("--t-end", type=_positive("--t-end"), help="simulated end time [s] (case default otherwise)")
    swp.add_argument("--out", help="output directory (default runs/sweep-CASE, CASE the case's name)")
    swp.add_argument("--jobs", type=_positive_int("--jobs"), help="runs at once on this machine (default: cores)")
    _cluster_options(swp)

    val = sub.add_parser("validate", help="run the validation entries and write docs/validation.md")
    val.add_argument("names", nargs="*", metavar="NAME", help="entries to run (default: all; see --list)")
    val.add_argument("--list", action="store_true", help="list the entries with their expected durations")
    val.add_argument("--quick", action="store_true",
                     help="coarse, short runs (a smoke test; results go to runs/validate-quick unless --results)")
    val.add_argument("--results", help="directory of the per-entry JSON results (default: each entry's "
                     "validation/<case>/results/)")
    val.add_argument("--doc", help="markdown file to (re)generate (default docs/validation.md)")
    val.add_argument("--doc-only", action="store_true",
                     help="regenerate the markdown from the stored results without running any entry")
    val.add_argument("--threads", type=_positive_int("--threads"), help="threads of the compiled loops")
    val.add_argument("--checkpoints", metavar="DIR",
                     help="keep a checkpoint of each entry's run in DIR/<name>/ (every 1/20 of its end time and at "
                     "Ctrl-C) and continue from it when run again; for the entries that support it (the cavity's)")
    _cluster_options(val, threads=False)

    plot = sub.add_parser("plot", help="draw a particle snapshot (and probe histories) of a run directory")
    plot.add_argument("run_dir")
    plot.add_argument("--time", type=_time_of_snapshot, help="snapshot time [s] (default: the last one)")
    plot.add_argument("--field", default="pressure", help="point field to colour by (default pressure)")
    plot.add_argument("--out", help="PNG path (default RUN_DIR/snapshot.png); the probe plot goes beside it "
                      "as <OUT stem>_probes.png")
    plot.add_argument("--probes", action="store_true", help="also draw the probe histories (RUN_DIR/probes.png)")
    plot.add_argument("--clim", metavar="LO,HI", type=_clim,
                      help="colour range of the field (default: its 1st to 99th percentile over the frame)")

    forces = sub.add_parser("forces", help="the fluid's force on each wall at every output time of a run "
                            "(from its VTU files) -> forces.csv")
    forces.add_argument("run_dir")
    forces.add_argument("--out", help="CSV path (default RUN_DIR/forces.csv)")
    forces.add_argument("--wall", action="append", metavar="NAME",
                        help="only this wall system (repeatable; default every wall)")

    sample = sub.add_parser("sample", help="fluid fields at points and lines, wall pressure sensors and free-surface "
                                           "gauges in the stored frames of a run -> CSV")
    sample.add_argument("run_dir")
    sample.add_argument("--line", metavar="x0,y0:x1,y1:n",
                        help="n points from (x0, y0) to (x1, y1) (x0,y0,z0:x1,y1,z1:n in 3D)")
    sample.add_argument("--point", action="append", metavar="x,y[,z]",
                        help="one point (repeatable; written after the line's points in sample.csv)")
    sample.add_argument("--sensor", action="append", metavar="x,y[,z][:diameter]",
                        help="pressure sensor on a wall, as `seawall run --sensor`: face-averaged wall pressure "
                             "[Pa], column sensor:<k> of sensors.csv (repeatable)")
    sample.add_argument("--gauge", action="append", metavar="x[,y]",
                        help="free-surface elevation [m] above this horizontal position (the horizontal "
                             "coordinate(s), gravity giving the vertical; the bed's elevation where dry), as "
                             "`seawall run --gauge`, column gauge:<k> of sensors.csv (repeatable)")
    sample.add_argument("--time", type=_time_of_snapshot, action="append",
                        help="the frame nearest to this time (repeatable; default every frame)")
    sample.add_argument("--quantities", default="pressure,u,v",
                        help="comma-separated: pressure (gauge), density, u, v, w, speed (default pressure,u,v)")
    sample.add_argument("--out", help="CSV path of the points and lines (default RUN_DIR/sample.csv)")
    sample.add_argument("--sensors-out", help="CSV path of the sensors and gauges (default RUN_DIR/sensors.csv)")

    discharge = sub.add_parser("discharge", help="fluid volume that has passed a section at every output time of a "
                               "run (from its VTU files and escaped.csv) -> discharge.csv; the check of --discharge")
    discharge.add_argument("run_dir")
    discharge.add_argument("--section", required=True, metavar="x0,y0:x1,y1",
                           help="the section, positive as for `seawall run --discharge`; exact only for a section "
                                "spanning the whole fluid depth")
    discharge.add_argument("--out", help="CSV path (default RUN_DIR/discharge.csv)")

    geometry = sub.add_parser("geometry", help="wall particles and normals of an STL/OBJ file -> VTU, to "
                              "inspect before a run (needs seawall[geometry])")
    geometry.add_argument("file", metavar="FILE", help="an .stl or .obj file (coordinates in m)")
    geometry.add_argument("--dx", type=_positive("--dx"), required=True, help="the fluid's particle spacing [m]")
    geometry.add_argument("--layers", type=_positive_int("--layers"), default=3,
                          help="wall layers (default 3: the cubic spline's support 2.6 dx at h = 1.3 dx)")
    geometry.add_argument("--fluid", choices=("outside", "inside"), default="outside",
                          help="outside: an obstacle, normals point out of it (default); inside: a container, "
                          "normals point into it")
    geometry.add_argument("--fill", action="store_true",
                          help="write the fluid filling the closed mesh (clearance dx/2) instead of the wall")
    geometry.add_argument("--out", help="VTU path (default FILE's stem + _wall.vtu or _fill.vtu, here)")

    bench = sub.add_parser("bench", help="time a fixed number of steps; print one JSON line")
    bench.add_argument("case")
    bench.add_argument("--boundary", help="wall model; default the case's own")
    bench.add_argument("--dx", type=_positive("--dx"))
    bench.add_argument("--steps", type=_positive_int("--steps"), default=100)
    bench.add_argument("--chunks", type=_positive_int("--chunks"), default=5,
                       help="split the timed steps into this many chunks and also report their median and best")
    bench.add_argument("--threads", type=_positive_int("--threads"), help="as for run")
    bench.add_argument("--set", action="append", metavar="KEY=VALUE")
    bench.add_argument("--neighbour-skin", type=_skin, metavar="FRACTION", help="as for run")
    return parser


def _cluster_options(parser, threads=True):
    """--scheduler / --workers (and --threads) of the commands whose runs go to seawall.executors."""
    parser.add_argument("--scheduler", nargs="?", const="local", metavar="ADDRESS",
                        help="run through dask.distributed: the scheduler at ADDRESS (tcp://host:8786), or "
                             "'local' (also the flag alone) for a local cluster (docs/sweeps.md)")
    parser.add_argument("--workers", type=_positive_int("--workers"),
                        help="workers of the local cluster (--scheduler local; default: cores)")
    if threads:
        parser.add_argument("--threads", type=_positive_int("--threads"),
                            help="threads of each run's compiled loops (default: the cores shared among the "
                                 "runs at once; 1 on a remote cluster)")


def _executor(args, n_tasks):
    from .executors import executor_for

    return executor_for(scheduler=args.scheduler, workers=args.workers, jobs=args.jobs, n_tasks=n_tasks,
                        threads_per_run=args.threads)


def _clim(text):
    parts = text.split(",")
    try:
        lo, hi = (float(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--clim expects LO,HI (two numbers), got {text!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
        raise argparse.ArgumentTypeError(f"--clim needs finite LO < HI, got {text!r}")
    return lo, hi


def cmd_cases(args):
    from .cases import CASES, case_by_name

    if args.name:
        print(case_help(case_by_name(args.name)), end="")
        return 0
    width = max(len(n) for n in CASES)
    for name, case in CASES.items():
        print(f"{name:<{width}}  {case.dimension}D  {case.description}")
    return 0


def case_help(case):
    """``seawall cases NAME``: the case's description, run defaults and every parameter with default and unit."""
    lines = [f"{case.name}  {case.dimension}D  {case.description}"]
    if case.source is not None:
        lines.append(f"  file          {case.source['path']} (sha256 {case.source['sha256'][:12]})")
    lines.append(f"  defaults      --boundary {case.default_boundary}  --t-end {case.t_end:g}  "
                 f"--output-every {case.output_every:g}  --probe-every {case.probe_every:g}")
    budget = _damage_budget_defaults(case)
    lines.append(f"  damage budget --set unstable_fraction={budget['unstable_fraction']:g}  "
                 f"--set unstable_window={budget['unstable_window']:g} (s; a run with a fluid stops when more "
                 f"than that fraction is removed as wall/unstable within the window)")
    lines.append("  parameters (--set KEY=VALUE):")
    rows = [(key, "(case)" if p.default is None else _default_text(p.default), p.units, p.kind.__name__, p.doc)
            for key, p in case.parameters.items()]
    wk = max((len(r[0]) for r in rows), default=0)
    wd = max((len(r[1]) for r in rows), default=0)
    wu = max((len(r[2]) for r in rows), default=0)
    for key, default, unit, kind, doc in rows:
        lines.append(f"    {key:<{wk}}  {default:<{wd}}  {unit or '-':<{max(wu, 1)}}  {kind:<5}  {doc}")
    return "\n".join(lines) + "\n"


def _damage_budget_defaults(case):
    """The case's damage budget: its own ([case] keys of a TOML file) over Simulation's defaults."""
    import inspect

    from .simulation import Simulation

    sig = inspect.signature(Simulation).parameters
    return {k: (case.guards or {}).get(k, sig[k].default) for k in ("unstable_fraction", "unstable_window")}


def cmd_new_case(args):
    from .cases.templates import write_template

    print(write_template(args.name, toml=args.toml, force=args.force))
    return 0


def cmd_boundaries(_args):
    """One line per wall model (name, description, as before), then, indented, its ``--set`` keys with
    their defaults and its class's options (``WallModel.options()``) with the values the name builds
    (the constructor's default where the model keeps no attribute of that name)."""
    from .boundary.registry import BOUNDARIES, boundary_by_name, boundary_option_defaults

    width = max(len(n) for n in BOUNDARIES)
    pad = " " * (width + 2)
    for name, (_, description) in BOUNDARIES.items():
        print(f"{name:<{width}}  {description}")
        keys = boundary_option_defaults(name)
        print(f"{pad}--set: " + (" ".join(f"{k}={_default_text(v)}" for k, v in keys.items()) or "(none)"))
        model = boundary_by_name(name)
        print(f"{pad}options: {_describe(model)}")
    return 0


def _describe(obj):
    """``Class(option=value, ...)`` of a wall model (or of an object it holds) from its constructor's keywords."""
    import inspect

    if obj is None or isinstance(obj, (str, int, float, bool)):
        return repr(obj)
    if hasattr(type(obj), "option_defaults"):          # a WallModel: WallModel.options() and their defaults
        defaults = type(obj).option_defaults()
    else:
        defaults = {p.name: p.default for p in inspect.signature(type(obj).__init__).parameters.values()
                    if p.name != "self" and p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)}
    parts = []
    for name, default in defaults.items():
        if hasattr(obj, name):
            parts.append(f"{name}={_describe(getattr(obj, name))}")
        elif default is not inspect.Parameter.empty:
            parts.append(f"{name}={default!r}")
        else:
            parts.append(name)
    return f"{type(obj).__name__}({', '.join(parts)})"


def _default_text(value):
    """A --set default as typed on the command line; None: the model's (or the fluid's) own choice."""
    if value is None:
        return "(model)"
    if isinstance(value, bool):
        return str(int(value))
    return str(value)


def _build(args):
    from .cases import case_by_name
    from .errors import ParameterError

    case = case_by_name(args.case)
    params = _parse_sets(args.set)
    if args.dx is not None:
        params["dx"] = args.dx
    if "dx" in params and "dx" not in case.parameters:
        raise ParameterError(f"case {case.name!r} takes no dx")
    args.boundary = args.boundary or case.default_boundary
    sim = case.build(boundary=args.boundary, threads=args.threads, **params)
    skin = getattr(args, "neighbour_skin", None)
    if skin is not None and hasattr(sim, "set_neighbour_skin"):
        sim.set_neighbour_skin(skin)
    return case, sim


def _interval_flags(args):
    return (("--probe-every", args.probe_every), ("--output-every", args.output_every),
            ("--checkpoint-every", args.checkpoint_every))


def _check_intervals(args, sim):
    """An output interval below the time step would write at every step; refuse it by name."""
    given = [(flag, value) for flag, value in _interval_flags(args) if value is not None]
    if not given:
        return
    dt = sim.first_time_step()
    for flag, value in given:
        if value < dt:
            raise _bad_input(f"{flag} {value:g} s is below the first time step {dt:.3g} s; give at least that")


def _restart(sim, path):
    from .errors import ParameterError

    try:
        sim.restart(path)
    except ParameterError as exc:
        raise ParameterError(f"--restart: {exc}") from None


def cmd_run(args):
    from . import output, rundir
    from .errors import InstabilityError, OutputError, ParameterError
    from .provenance import provenance
    from .sampling import LineSampler, parse_line

    rundir.check_out_path(args.out)
    case, sim = _build(args)
    comm = _mpi(sim, args)
    record = provenance(args.argv)   # after the build: --threads is taken there
    args.running["sim"] = sim
    t_end = args.t_end or case.t_end
    out = args.out or os.path.join("runs", f"{case.name}-{args.boundary}")
    rundir.check_out_path(out)
    # everything that can be refused is checked before the run directory is created or cleared
    lines = [parse_line(text, sim.dim) for text in args.line or []]
    if lines and not sim.accepts(LineSampler):
        raise ParameterError(f"--line: case {case.name!r} has no fluid to sample")
    # probes and the sampling interval first: a checkpoint carries the probe list and schedule
    sim.add(every=args.probe_every or case.probe_every)
    for k, text in enumerate(args.sensor or [], start=1):
        from .probes import PressureSensor
        from .sampling import parse_sensor

        point, diameter = parse_sensor(text, sim.dim)
        sim.add(PressureSensor(f"sensor:{k}", point, diameter))
    for k, text in enumerate(args.gauge or [], start=1):
        _add_gauge(sim, case, k, text)
    for k, text in enumerate(args.discharge or [], start=1):
        _add_discharge(sim, case, k, text)
    for name in args.wall_force or []:
        _add_wall_force(sim, case, name)
    if args.diagnostics:
        from .compare import MinWallDistance

        if not hasattr(sim, "fluid"):
            raise ParameterError(f"--diagnostics: case {case.name!r} has no fluid to measure")

        sim.add(MinWallDistance())
    if args.restart:
        _restart(sim, args.restart)
        if t_end <= sim.time:
            raise _bad_input(f"--t-end {t_end:g} s must exceed the checkpoint's time {sim.time:g} s")
    _check_intervals(args, sim)
    _on_root(comm, lambda: rundir.prepare(out, overwrite=args.overwrite, restart=args.restart))

    sim.metadata["provenance"] = record
    if args.restart:
        sim.metadata["restarted_from"] = {"checkpoint": args.restart, "time": sim.time, "step": sim.step}
    if not args.no_vtk:
        sim.add(output.VTK(out, every=args.output_every or case.output_every, compress=not args.vtk_uncompressed,
                           float32=args.vtk_float32, gather=args.vtk_gather))
    checkpoint = output.Checkpoint(out, every=args.checkpoint_every or t_end / 10.0)
    sim.add(checkpoint)
    line_files = []
    for k, (start, end, n) in enumerate(lines, start=1):
        sim.add(LineSampler(out, start, end, n, every=args.output_every or case.output_every, name=str(k)))
        line_files.append(f"line_{k}.csv")
    if hasattr(sim, "headline"):   # simulations without a fluid (dem-box) describe themselves
        what = sim.headline()
    else:
        what = (f"boundary {args.boundary}, {sim.dim}D, {sim.fluid.n} fluid + {sum(w.n for w in sim.walls)} wall "
                f"particles, dx = {sim.fluid.spacing:g} m")
    if comm is not None:
        what += f", {comm.Get_size()} MPI ranks"
    if comm is None or comm.Get_rank() == 0:
        print(f"seawall run {case.name}: {what}, t_end = {t_end:g} s -> {out}", flush=True)
    status, error, code = "completed", None, 0
    result = None
    try:
        result = sim.run(t_end, progress=not args.no_progress, probe_csv=os.path.join(out, "probes.csv"))
    except ParameterError as exc:   # raised before any file is written: an existing file refuses to continue
        raise ParameterError(f"--restart: {exc}" if args.restart else str(exc)) from None
    except InstabilityError as exc:
        status, error, code = "unstable", str(exc), EXIT_UNSTABLE
    except OutputError as exc:
        status, error, code = "io-error", str(exc), EXIT_IO_ERROR
    except OSError as exc:   # an OSError the run loop did not name (it turns its own into OutputError)
        status, error, code = "io-error", str(rundir.output_error(exc, exc.filename or out)), EXIT_IO_ERROR
    except KeyboardInterrupt as exc:
        name = getattr(exc, "signal_name", "SIGINT")
        status, code = "interrupted", EXIT_TERMINATED if name == "SIGTERM" else EXIT_INTERRUPTED
        error = f"interrupted by {name} at t = {sim.time:.6g} s after {sim.step} steps" + (
            f"; continue with --restart {checkpoint.last_written}" if checkpoint.last_written else "")
    if result is None:
        result = _partial_result(sim)
    summary = {"case": case.name, "boundary": args.boundary, **result.summary, "status": status}
    if error:
        summary["error"] = error
    if hasattr(result, "probes"):
        from .probes import probe_unit

        summary["probes"] = _probe_summary(result)
        summary["probe_units"] = {p.name: probe_unit(p, sim.dim) for p in sim.probes}
        if hasattr(sim, "fluid"):
            summary["diagnostics"] = _diagnostics(sim, result)
    summary["files"] = {"probes": "probes.csv", "fluid_series": None if args.no_vtk else "fluid.pvd",
                        "wall_series": [] if args.no_vtk or not hasattr(sim, "fluid") else
                        [f"wall_{w.name}.pvd" for w in sim.walls],
                        "checkpoint": "checkpoint.h5", "escaped": "escaped.csv",
                        **({"lines": line_files} if line_files else {})}
    if comm is not None and comm.Get_rank() != 0:   # rank 0 writes the run's files and prints
        return code
    for name, write in (("escaped.csv", lambda path: _write_escaped(path, sim)),
                        ("summary.json", lambda path: rundir.write_json(path, _jsonable(summary)))):
        try:
            write(os.path.join(out, name))
        except OSError as exc:
            if status != "io-error":   # an io-error has already said what went wrong
                status, code = "io-error", EXIT_IO_ERROR
                error = str(rundir.output_error(exc, os.path.join(out, name)))
                summary.update(status=status, error=error)
    _print_summary(summary)
    if error:
        print(f"seawall: {'interrupted' if status == 'interrupted' else 'error'}: {error}", file=sys.stderr)
    return code


def _mpi(sim, args):
    """Under mpiexec with several ranks: make ``sim`` one rank of a decomposed run (seawall.parallel)."""
    from . import parallel
    from .errors import ParameterError

    comm = parallel.world()
    if comm is None:
        return None
    if getattr(args, "line", None):
        raise ParameterError("--line: the line sampler is not decomposed; run it in one process")
    if args.threads is None:   # without --threads the ranks on a machine share its cores
        parallel.share_cores(comm)
    parallel.distribute(sim, comm, argv=args.argv)
    return comm


def _on_root(comm, action):
    """Run ``action`` on rank 0 only (all of it in a serial run); a refusal there stops every rank."""
    from .errors import ParameterError

    if comm is None:
        return action()
    message = None
    if comm.Get_rank() == 0:
        try:
            action()
        except ParameterError as exc:
            message = str(exc)
    message = comm.bcast(message, root=0)
    if message is not None:
        raise ParameterError(message)


def parse_gauge(text, k):
    """``--gauge x[,y][:NAME]`` -> (column name, horizontal coordinates): ``gauge:NAME``, else ``gauge:<k>``
    (the column of `seawall sample --gauge`)."""
    from .errors import ParameterError

    where, sep, name = str(text).partition(":")
    name = name.strip()
    if sep and (not name or "," in name or ":" in name):
        raise ParameterError(f"--gauge: NAME after ':' must be non-empty without ',' or ':', got {text!r}")
    return f"gauge:{name or k}", _coordinates("--gauge", where, (1, 2))


def _add_gauge(sim, case, k, text):
    """--gauge x[,y][:NAME]: a FreeSurfaceGauge probe."""
    from .errors import ParameterError
    from .probes import FreeSurfaceGauge

    name, position = parse_gauge(text, k)
    if not hasattr(sim, "fluid"):
        raise ParameterError(f"--gauge: case {case.name!r} has no fluid to gauge")
    try:
        sim.add(FreeSurfaceGauge(name, position))
    except ParameterError as exc:
        raise ParameterError(f"--gauge: {exc}") from None


def _add_wall_force(sim, case, name):
    """--wall-force NAME: one WallForce probe per component of the force on wall NAME."""
    from .errors import ParameterError
    from .probes import WallForce

    walls = [w.name for w in getattr(sim, "walls", [])] if hasattr(sim, "fluid") else []
    if name not in walls:
        raise ParameterError(f"--wall-force: case {case.name!r} has no wall named {name!r}; its walls: "
                             + (", ".join(walls) if walls else "none"))
    for axis, component in enumerate(("fx", "fy", "fz")[:sim.dim]):
        sim.add(WallForce(f"wall_force:{name}:{component}", name, axis=axis))


def parse_section(option, text, name=False):
    """``x0,y0:x1,y1`` (with ``name``: ``[:NAME]`` after it) as given to ``option``: (start, end, NAME or None)."""
    from .errors import ParameterError

    parts = str(text).split(":")
    form = "x0,y0:x1,y1" + ("[:NAME]" if name else "")
    try:
        if len(parts) not in ((2, 3) if name else (2,)):
            raise ValueError
        start, end = ([float(c) for c in part.split(",")] for part in parts[:2])
    except ValueError:
        raise ParameterError(f"{option} must look like {form}, got {text!r}") from None
    if len(start) not in (2, 3) or len(end) != len(start) or not all(math.isfinite(c) for c in start + end):
        raise ParameterError(f"{option} {text!r}: start and end need 2 finite coordinates each (3 for a 3D "
                             f"rectangle's corners)")
    if start == end:
        raise ParameterError(f"{option} {text!r}: start and end are the same point")
    label = parts[2] if len(parts) == 3 else None
    if label is not None and (not label or "," in label or '"' in label):
        raise ParameterError(f"{option} {text!r}: NAME must be non-empty, without commas or quotes")
    return start, end, label


def _add_discharge(sim, case, k, text):
    """--discharge x0,y0:x1,y1[:NAME]: a Discharge probe (columns NAME and NAME_rate)."""
    from .errors import ParameterError
    from .probes import Discharge

    start, end, name = parse_section("--discharge", text, name=True)
    if not hasattr(sim, "fluid"):
        raise ParameterError(f"--discharge: case {case.name!r} has no fluid to count")
    if len(start) != sim.dim:
        raise ParameterError(f"--discharge {text!r}: case {case.name!r} is {sim.dim}D, the section has {len(start)} "
                             f"coordinates")
    try:
        sim.add(Discharge(name or f"discharge:{k}", start, end))
    except ParameterError as exc:
        raise ParameterError(f"--discharge: {exc}") from None


def _partial_result(sim):
    """Summary and probe series of a run that stopped early (blow-up, full disk, signal)."""
    return sim.result(sim.summary_so_far())


def _probe_summary(result):
    out = {}
    for name, values in result.probes.items():
        finite = values[~(values != values)]
        out[name] = {"final": float(values[-1]) if values.size else None,
                     "max": float(finite.max()) if finite.size else None,
                     "min": float(finite.min()) if finite.size else None}
    return out


def _diagnostics(sim, result):
    """Run diagnostics for summary.json: wall-pressure noise per WallPressure probe, smallest wall distance."""
    import numpy as np

    from .diagnostics import pressure_noise
    from .probes import WallPressure

    noise = {p.name: pressure_noise(result.times, result.probes[p.name])
             for p in sim.probes if isinstance(p, WallPressure)}
    out = {"wall_pressure_noise_pa": noise,
           "wall_pressure_noise_definition": "RMS of p minus its running mean over 0.05 s (seawall.diagnostics)"}
    if "min_wall_distance_dx" in result.probes:
        d = result.probes["min_wall_distance_dx"]
        out["min_wall_distance_dx"] = float(np.nanmin(d)) if d.size and np.isfinite(d).any() else None
    return out


def _write_escaped(path, sim):
    """escaped.csv: time, id, position at removal, the face crossed and the reason, one row per particle."""
    from .diagnostics import escape_sides, record_reason

    from .io.vtk import _atomic_write

    coords = ["x", "y", "z"][:sim.dim]
    with _atomic_write(path, "w") as fh:
        fh.write(",".join(["time", "id", *coords, "side", "reason"]) + "\n")
        sides = escape_sides(sim.escaped, sim.grid, sim.hull_box() if hasattr(sim, "hull_box") else None)
        for rec, side in zip(sim.escaped, sides):
            fh.write(",".join([f"{rec[0]:.9g}", str(int(rec[1])), *(f"{c:.9g}" for c in rec[2:2 + sim.dim]), side,
                               record_reason(rec, sim.dim)]) + "\n")


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if hasattr(obj, "item"):
        return obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _print_summary(s):
    print(f"\n{s['case']} with {s['boundary']}: {s['status']} at t = {s['t_end']:.4g} s after {s['steps']} steps")
    print(f"  particles     {s['n_fluid']} fluid, {s['n_wall']} wall ({s['dimension']}D)")
    print(f"  wall time     {s['wall_time_s']:.1f} s ({s.get('startup_s', 0.0):.1f} s start-up incl. compilation)")
    print(f"  speed         {s['particle_steps_per_s'] / 1e6:.3f} M particle-steps/s")
    where = (s.get("escaped_where") or {}).get("by_side") or {}
    sides = f" ({', '.join(f'{k}: {v}' for k, v in sorted(where.items()))})" if where else ""
    reasons = s.get("escaped_by_reason") or {}
    if s["escaped_particles"] and reasons:
        sides += " [" + ", ".join(f"{k}: {v}" for k, v in reasons.items()) + "]"
    print(f"  escaped       {s['escaped_particles']} particles{sides};  mass drift {s['mass_drift']:.2e}")
    for name, p in (s.get("probes") or {}).items():
        if p["max"] is None:
            continue
        print(f"  probe {name:<14} final {p['final']:12.5g}   min {p['min']:12.5g}   max {p['max']:12.5g}")


def cmd_compare(args):
    from .compare import compare

    from .cases import case_by_name

    out = args.out or os.path.join("runs", f"compare-{case_by_name(args.case).name}")
    boundaries = [b.strip() for b in args.boundaries.split(",") if b.strip()]
    print(f"seawall compare {args.case}: {', '.join(boundaries)} -> {out}", flush=True)
    rows = compare(args.case, boundaries, out=out, dx=args.dx, t_end=args.t_end, params=_parse_sets(args.set),
                   executor=_executor(args, len(boundaries)))
    print(open(os.path.join(out, "compare.md")).read())
    return 0 if all(r["status"] == "completed" for r in rows) else EXIT_UNSTABLE


def cmd_sweep(args):
    from .cases import case_by_name
    from .sweep import combinations, parse_sweep_sets, sweep

    grid = parse_sweep_sets(args.set)
    out = args.out or os.path.join("runs", f"sweep-{case_by_name(args.case).name}")
    executor = _executor(args, len(combinations(grid)))
    print(f"seawall sweep {args.case}: {len(combinations(grid))} runs over {', '.join(grid)} on "
          f"{executor.description} -> {out}", flush=True)
    rows = sweep(args.case, grid, out=out, boundary=args.boundary, t_end=args.t_end, executor=executor)
    print(open(os.path.join(out, "sweep.md")).read())
    return 0 if all(r["status"] == "completed" for r in rows) else EXIT_UNSTABLE


def cmd_validate(args):
    from .validation import run_validate

    return run_validate(args.names, quick=args.quick, results=args.results, doc=args.doc, threads=args.threads,
                        list_only=args.list, doc_only=args.doc_only, scheduler=args.scheduler, workers=args.workers,
                        checkpoints=args.checkpoints)


def cmd_plot(args):
    from . import plots
    from .errors import ParameterError

    out = args.out or os.path.join(args.run_dir, "snapshot.png")
    # the probe plot follows --out: beside it as <stem>_probes.png (RUN_DIR/probes.png without --out)
    probes_png = (os.path.splitext(args.out)[0] + "_probes.png" if args.out
                  else os.path.join(args.run_dir, "probes.png"))
    try:
        if os.path.dirname(out):
            os.makedirs(os.path.dirname(out), exist_ok=True)
        plots.snapshot(args.run_dir, out, time=args.time, field=args.field, clim=args.clim)
        print(out)
        if args.probes:
            print(plots.probe_histories(args.run_dir, probes_png))
    except (FileNotFoundError, ValueError) as exc:
        raise ParameterError(str(exc)) from None
    return 0


def cmd_forces(args):
    import numpy as np

    from .postprocess import wall_force_series, write_forces_csv

    from .errors import ParameterError
    from .postprocess import impulse

    series = wall_force_series(args.run_dir)
    if args.wall:
        unknown = [w for w in args.wall if w not in series]
        if unknown:
            raise ParameterError(f"--wall: {args.run_dir} has no wall named {unknown[0]!r}; its walls: "
                                 + ", ".join(series))
        series = {w: series[w] for w in args.wall}
    out = args.out or os.path.join(args.run_dir, "forces.csv")
    write_forces_csv(out, series)
    unit = "N" if next(iter(series.values()))[1].shape[-1] == 3 else "N/m"
    for name, (t, f) in series.items():
        if len(t):
            k = int(np.argmax(np.linalg.norm(f, axis=1)))
            print(f"wall {name}: {len(t)} frames, largest |F| = {np.linalg.norm(f[k]):.5g} at t = {t[k]:.4g} s "
                  f"({', '.join(f'{v:.5g}' for v in f[k])}) {unit}; impulse over "
                  f"{t[0]:.4g}-{t[-1]:.4g} s: ({', '.join(f'{v:.5g}' for v in impulse(t, f))}) {unit} s")
    print(out)
    return 0


def cmd_discharge(args):
    from .postprocess import discharge_series, write_discharge_csv

    from .errors import ParameterError

    start, end, _ = parse_section("--section", args.section)
    if not os.path.isdir(args.run_dir):
        raise ParameterError(f"run directory {args.run_dir} not found")
    try:
        times, columns = discharge_series(args.run_dir, start, end)
    except FileNotFoundError as exc:
        raise ParameterError(str(exc)) from None
    out = args.out or os.path.join(args.run_dir, "discharge.csv")
    write_discharge_csv(out, times, columns)
    if len(times):
        print(f"{len(times)} frames, {times[0]:.4g}-{times[-1]:.4g} s: volume passed {columns['volume'][-1]:.6g} m^2 "
              f"(per metre) at the last frame")
    print(out)
    return 0


def _coordinates(option, text, counts):
    from .errors import ParameterError

    try:
        values = [float(c) for c in str(text).split(",")]
    except ValueError:
        values = []
    if len(values) not in counts or not all(math.isfinite(v) for v in values):
        raise ParameterError(f"{option} must be {' or '.join(str(c) for c in counts)} finite comma-separated "
                             f"numbers, got {text!r}")
    return values


def cmd_sample(args):
    import numpy as np

    from .errors import ParameterError
    from .postprocess import gauge_series, sample_series, sensor_series, write_sample_csv, write_sensor_csv
    from .sampling import line_points, parse_line, parse_sensor

    if not (args.line or args.point or args.sensor or args.gauge):
        raise ParameterError("seawall sample needs at least one of --line, --point, --sensor, --gauge")
    groups = []
    if args.line:
        start, end, n = parse_line(args.line)
        groups.append(line_points(start, end, n))
    for text in args.point or []:
        groups.append(np.asarray([_coordinates("--point", text, (2, 3))]))
    if groups:
        if len({g.shape[1] for g in groups}) > 1:
            raise ParameterError("--line and --point must have the same number of coordinates")
        points = np.concatenate(groups)
        quantities = tuple(q.strip() for q in args.quantities.split(",") if q.strip())
        times, result = sample_series(args.run_dir, points, quantities, times=args.time)
        out = args.out or os.path.join(args.run_dir, "sample.csv")
        write_sample_csv(out, times, points, result)
        print(f"{len(times)} frames x {len(points)} points -> {out}")
    columns = {}
    if args.sensor:
        sensors = [parse_sensor(text) for text in args.sensor]
        times, values = sensor_series(args.run_dir, sensors, times=args.time)
        columns.update({f"sensor:{k + 1}": values[:, k] for k in range(len(sensors))})
    if args.gauge:
        positions = [_coordinates("--gauge", text, (1, 2)) for text in args.gauge]
        times, values = gauge_series(args.run_dir, positions, times=args.time)
        columns.update({f"gauge:{k + 1}": values[:, k] for k in range(len(positions))})
    if columns:
        out = args.sensors_out or os.path.join(args.run_dir, "sensors.csv")
        write_sensor_csv(out, times, columns)
        print(f"{len(times)} frames: {', '.join(columns)} (sensor Pa, gauge m) -> {out}")
    return 0


def cmd_geometry(args):
    import numpy as np

    from .io.vtk import write_vtu
    from .meshes import fill_mesh, load_mesh, mesh_wall

    mesh = load_mesh(args.file)
    lo, hi = mesh.bounds
    closed = "watertight" if mesh.watertight else f"open ({mesh.n_open_edges} open edges)"
    stem = os.path.splitext(os.path.basename(args.file))[0]
    meta = {"source": os.path.basename(args.file), "dx": args.dx}
    if args.fill:
        shape = fill_mesh(mesh, args.dx)
        out = args.out or f"{stem}_fill.vtu"
        write_vtu(out, shape.positions, {}, field_data={"dx": args.dx}, metadata=meta, compress=True)
        what = f"{shape.n} fluid particles (clearance {0.5 * args.dx:g} m)"
    else:
        shape = mesh_wall(mesh, args.dx, args.layers, fluid=args.fluid)
        out = args.out or f"{stem}_wall.vtu"
        write_vtu(out, shape.positions, {"normal": shape.normals, "surface_point": shape.surface_points,
                                         "layer": shape.layer},
                  field_data={"dx": args.dx}, metadata={**meta, "fluid": args.fluid}, compress=True)
        what = f"{shape.n} wall particles in {int(shape.layer.max()) + 1} layers"
    print(f"{args.file}: {mesh.faces.shape[0]} faces, {closed}, bounds {np.round(lo, 6).tolist()} - "
          f"{np.round(hi, 6).tolist()} m; {what} -> {out}")
    return 0


def cmd_bench(args):
    from .simulation import Simulation  # noqa: F401  (import cost outside the timing)

    case, sim = _build(args)
    comm = _mpi(sim, args)
    # what one step updates: fluid and wall particles (SPH), the elements (DEM: its walls are fixed);
    # counted before a decomposed run splits the fluid
    n_particles = sim.particles_per_step()
    n_fluid = sim.fluid.n if hasattr(sim, "fluid") else 0
    t0 = time.perf_counter()
    sim.run_steps(2)  # compiles (or loads the cache) and warms up
    compile_s = time.perf_counter() - t0
    n_wall = sum(w.n for w in sim.walls)
    fluid = getattr(sim, "fluid", None)
    # timed in chunks: on a shared machine single timings scatter by +-15 %, so the
    # median and best chunk are reported beside the overall rate
    chunks = min(args.chunks, args.steps)
    sizes = [args.steps // chunks + (1 if k < args.steps % chunks else 0) for k in range(chunks)]
    rates = []
    seconds = 0.0
    cpu0 = time.process_time()   # CPU time of all threads: steadier than wall time on a shared machine
    for size in sizes:
        t1 = time.perf_counter()
        sim.run_steps(size)
        dt = time.perf_counter() - t1
        seconds += dt
        rates.append(n_particles * size / dt)
    cpu_seconds = time.process_time() - cpu0
    import numba

    from .jit import THREADED

    rates.sort()
    line = {"case": case.name, "boundary": args.boundary, "dimension": sim.dim,
            "n_particles": n_particles, "n_fluid": n_fluid, "n_wall": n_wall,
            **({"n_dem": sim.dem.n} if hasattr(sim, "dem") else {}),
            "steps": args.steps, "seconds": seconds,
            "particle_steps_per_s": n_particles * args.steps / seconds,
            "median_chunk_particle_steps_per_s": rates[len(rates) // 2],
            "best_chunk_particle_steps_per_s": rates[-1],
            "compile_seconds": compile_s, "threads": numba.get_num_threads(), "cpu_seconds": cpu_seconds,
            "loops": "threaded" if THREADED else "serial",
            "dx": fluid.spacing if fluid is not None else None,
            **({"pair_list_builds": sim.pair_list.builds, "pair_list_evaluations": sim.pair_list.evaluations}
               if getattr(sim, "pair_list", None) is not None else {})}
    if comm is not None:   # a decomposed run: rank 0's timings (the ranks step together), the ranks' CPU time
        stats = sim.summary_so_far()["mpi"]
        line.update(ranks=comm.Get_size(), cpu_seconds=comm.allreduce(cpu_seconds),
                    halo_fraction=stats["halo_fraction"], comm_seconds_max_rank=stats["comm_seconds_max_rank"],
                    comm_seconds_per_step=stats["comm_seconds_max_rank"] / (args.steps + 2))
        if comm.Get_rank() != 0:
            return 0
    print(json.dumps(line))
    return 0


def quiet_outlined_loop_warnings():
    """Hide Numba's "parallel=True ... no transformation for parallel execution was possible" in the CLI.

    On a cold compile Numba says this of the outlined bodies of the fluid loop and the two Adami wall
    loops (located at line 1 of their modules), three warnings of eight lines before the first step,
    while the loops themselves run on every thread (docs/performance.md, "Start-up"). Only the command
    line hides it: a program that imports seawall keeps Numba's warnings as they are.
    """
    import warnings

    from numba.core.errors import NumbaPerformanceWarning

    warnings.filterwarnings("ignore", message=r"(?s).*no transformation for parallel execution was possible",
                            category=NumbaPerformanceWarning)


def main(argv=None):
    from .errors import ParameterError
    from .interrupts import stop_on_signals

    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = ["seawall", *(sys.argv[1:] if argv is None else argv)]
    quiet_outlined_loop_warnings()
    args.running = {}   # the simulation of `run`, for the signal handler
    handlers = {"cases": cmd_cases, "boundaries": cmd_boundaries, "run": cmd_run, "bench": cmd_bench,
                "plot": cmd_plot, "compare": cmd_compare, "sweep": cmd_sweep, "new-case": cmd_new_case,
                "forces": cmd_forces, "sample": cmd_sample, "discharge": cmd_discharge,
                "geometry": cmd_geometry, "validate": cmd_validate}
    try:
        if args.command == "run":
            with stop_on_signals(lambda: args.running.get("sim")):
                return handlers[args.command](args)
        return handlers[args.command](args)
    except ParameterError as exc:
        from .parallel import launched_rank

        if launched_rank() == 0:   # under mpiexec every rank stops; rank 0 says why
            print(f"seawall: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as exc:
        # before a run directory was prepared (or in a command without one): nothing to keep
        name = getattr(exc, "signal_name", "SIGINT")
        when = " before the run started" if args.command == "run" else ""
        print(f"seawall: interrupted by {name}{when}", file=sys.stderr)
        return EXIT_TERMINATED if name == "SIGTERM" else EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
