"""Does a decomposed run give the serial run's answer? The same case on 1, 2, 4 ... ranks, compared.

Each configuration is one ``seawall run`` (under ``mpiexec -n N`` for N > 1) with one Numba
thread per rank; the probe series of every N > 1 is compared with the 1-rank series column by
column (max |difference| / max |value|), together with the step count, the fluid count and the
escaped records (ids and reasons).

    python benchmarks/mpi_agreement.py                                  # adami dam break, 1/2/4 ranks
    python benchmarks/mpi_agreement.py --boundary dbc --ranks 1 2
    python benchmarks/mpi_agreement.py --set H=0.1 --dx 0.005 --t-end 0.3 --json out.json
    python benchmarks/mpi_agreement.py --ranks 1 2 --set H=0.1 --set shifting=lind2012
    python benchmarks/mpi_agreement.py --case cavity --boundary adami-noslip --ranks 1 2 --dx 5e-5 \
        --t-end 2 --set reynolds=100 --set transport_velocity=true
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(case, boundary, ranks, dx, t_end, sets, out):
    # a model not yet in seawall.parallel.distributed.VERIFIED_MODELS runs decomposed only to be compared here
    env = {**os.environ, "NUMBA_NUM_THREADS": "1", "PYTHONPATH": ROOT, "SEAWALL_MPI_COMPARE_ANY_MODEL": "1"}
    cmd = [sys.executable, "-m", "seawall", "run", case, "--boundary", boundary, "--t-end", str(t_end),
           "--out", out, "--overwrite", "--no-progress", "--no-vtk"]
    if dx:
        cmd += ["--dx", str(dx)]
    for item in sets:
        cmd += ["--set", item]
    if ranks > 1:
        cmd = ["mpiexec", "-n", str(ranks)] + cmd
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    with open(os.path.join(out, "summary.json")) as fh:
        summary = json.load(fh)
    with open(os.path.join(out, "probes.csv")) as fh:
        rows = list(csv.reader(fh))
    header, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
    with open(os.path.join(out, "escaped.csv")) as fh:
        escaped = sorted((r[1], r[-1]) for r in list(csv.reader(fh))[1:])
    return summary, header, data, escaped


def compare(reference, other):
    """max |a - b| / max |a| per probe column (absolute when the column is all zero)."""
    _, header, a, _ = reference
    _, header_b, b, _ = other
    if header != header_b or len(a) != len(b):
        return {"error": f"{len(a)} vs {len(b)} rows"}
    out = {}
    for k, name in enumerate(header):
        col_a = [r[k] for r in a]
        col_b = [r[k] for r in b]
        diff = max(abs(x - y) for x, y in zip(col_a, col_b))
        scale = max(abs(x) for x in col_a)
        out[name] = diff / scale if scale > 0 else diff
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="dam-break")
    parser.add_argument("--boundary", default="adami")
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument("--dx", type=float, default=0.005)
    parser.add_argument("--t-end", type=float, default=0.3)
    parser.add_argument("--set", action="append", help="case parameters (default for the dam break: H=0.1)")
    parser.add_argument("--json", help="also write the result here")
    args = parser.parse_args(argv)
    if args.set is None:
        args.set = ["H=0.1"] if args.case == "dam-break" else []
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.ranks:
            results[n] = run(args.case, args.boundary, n, args.dx, args.t_end, args.set, os.path.join(tmp, f"r{n}"))
    ref = results[args.ranks[0]]
    table = {"case": args.case, "boundary": args.boundary, "dx": args.dx, "t_end": args.t_end, "sets": args.set,
             "steps": ref[0]["steps"], "n_fluid": ref[0]["n_fluid"], "escaped": len(ref[3]), "ranks": {}}
    for n in args.ranks[1:]:
        s = results[n][0]
        diff = compare(ref, results[n])
        table["ranks"][n] = {"steps": s["steps"], "n_fluid": s["n_fluid"],
                             "same_escaped": results[n][3] == ref[3],
                             "max_relative_probe_difference": max(v for k, v in diff.items() if k != "t"),
                             "per_probe": diff, "halo_fraction": s.get("mpi", {}).get("halo_fraction")}
    print(json.dumps(table, indent=1))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(table, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
