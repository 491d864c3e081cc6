"""CPU time per step of the 3D dam break, pass by pass (issue 19, item 2).

Builds ``dam-break-3d`` at dx = 0.01 m with Adami walls and no lid (27,000 fluid + 76,041
wall particles, the case of "3D dam break against f56cb9a" in docs/performance.md), runs a
few steps untimed (compiling), then ``--repeats`` blocks of ``--steps`` steps. Each compiled
pass the simulation calls by a module-level name is wrapped by a timer of the process CPU
time (``time.process_time``: all threads; passive waiting costs none); a block prints one
JSON line of milliseconds per step: every wrapped pass, the whole step's CPU time (``step``)
and its wall time (``wall_ms``), and the load average.

To compare two trees, run the script with each tree first on ``PYTHONPATH``, alternating:

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/pass_profile.py --steps 15 --repeats 2
"""

import argparse
import json
import os
import sys
import time


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=0.01)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--steps", type=int, default=15)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)

    import seawall
    import seawall.boundary.dummy as dummy
    import seawall.neighbors as neighbors
    import seawall.simulation as simulation
    from seawall.cases import case_by_name

    totals = {}

    def timed(module, name):
        inner = getattr(module, name)

        def call(*a, **k):
            t = time.process_time()
            try:
                return inner(*a, **k)
            finally:
                totals[name] = totals.get(name, 0.0) + time.process_time() - t

        setattr(module, name, call)

    for module, name in ((simulation, "fluid_rates"), (dummy, "adami_wall_state"), (dummy, "dummy_wall_forces"),
                         (simulation, "wall_depth_codes"), (simulation, "classify_particles"),
                         (neighbors, "cells_within_reach")):
        timed(module, name)

    sim = case_by_name("dam-break-3d").build(boundary="adami", threads=args.threads, dx=args.dx, lid=False)
    print(f"# {seawall.__file__}: {sim.fluid.n} fluid, {sum(w.n for w in sim.walls)} wall particles, "
          f"{args.threads} thread(s)", file=sys.stderr, flush=True)
    sim.run_steps(3)
    for _ in range(args.repeats):
        totals.clear()
        cpu0, wall0 = time.process_time(), time.perf_counter()
        sim.run_steps(args.steps)
        row = {name: round(t / args.steps * 1e3, 2) for name, t in sorted(totals.items())}
        row["step"] = round((time.process_time() - cpu0) / args.steps * 1e3, 1)
        row["wall_ms"] = round((time.perf_counter() - wall0) / args.steps * 1e3, 1)
        row["load"] = round(os.getloadavg()[0], 1)
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
