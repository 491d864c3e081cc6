"""Cost per step of the five ghost-wall interpolations against particle count ([Huang2019] Fig. 4a).

For each spacing the hydrostatic tank ([Huang2019] sec. 4.1, marrone2011
scheme) is built once per method; the script times

* ``step``   -- one full time step (2 rate evaluations of the symplectic scheme),
* ``ghost``  -- one ghost update alone (interpolation at every mirror point + laws of mirror),

and prints particle-steps per second and the cost ratios to the improved
Shepard method. [Huang2019] reports, for the whole step, Shepard faster by
about 1.5x than normalised, 2x than SFDI and 4-11x than MLS (linear-quadratic).

Usage: python benchmarks/ghost_interpolation_cost.py [--dx 0.02 0.01 0.0071] [--steps 50] [--threads N]
"""

import argparse
import time


from seawall.boundary.base import EvaluationContext
from seawall.cases import build

METHODS = ["ghost-shepard", "ghost-normalized", "ghost-sfdi", "ghost-mls1", "ghost-mls2"]


def measure(method, dx, steps, threads):
    sim = build("hydrostatic", boundary=method, dx=dx, scheme="marrone2011", dt=1e-4, threads=threads)
    sim.run_steps(3)  # compile and warm up
    t0 = time.perf_counter()
    sim.run_steps(steps)
    step = (time.perf_counter() - t0) / steps
    wall = sim.walls[0]
    ctx = EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.grid.build(sim.fluid.particles["x"]),
                            time=sim.time, dx=sim.fluid.spacing)
    reps = max(20, steps)
    wall.model.update(wall, sim.fluid, ctx)
    t0 = time.perf_counter()
    for _ in range(reps):
        wall.model.update(wall, sim.fluid, ctx)
    ghost = (time.perf_counter() - t0) / reps
    n = sim.fluid.n + wall.n
    return {"n_fluid": sim.fluid.n, "n_ghost": wall.n, "step_s": step, "ghost_s": ghost,
            "particle_steps_per_s": n / step}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dx", type=float, nargs="*", default=[0.02, 0.01, 0.0071])
    ap.add_argument("--steps", type=int, default=50)
    ap.add_argument("--threads", type=int, default=None)
    args = ap.parse_args()
    rows = []
    for dx in args.dx:
        for method in METHODS:
            r = measure(method, dx, args.steps, args.threads)
            r.update(method=method, dx=dx)
            rows.append(r)
            print(f"dx={dx:<7g} {method:17s} fluid {r['n_fluid']:6d} ghosts {r['n_ghost']:5d}  step "
                  f"{r['step_s'] * 1e3:8.3f} ms  ghost update {r['ghost_s'] * 1e3:8.3f} ms  "
                  f"{r['particle_steps_per_s'] / 1e6:6.2f} M particle-steps/s", flush=True)
    print()
    print("| dx [m] | fluid | ghosts | method | step [ms] | ghost update [ms] | M particle-steps/s "
          "| step / Shepard | ghost update / Shepard |")
    print("|---|---|---|---|---|---|---|---|---|")
    for dx in args.dx:
        sub = [r for r in rows if r["dx"] == dx]
        ref = next(r for r in sub if r["method"] == "ghost-shepard")
        for r in sub:
            print(f"| {dx:g} | {r['n_fluid']} | {r['n_ghost']} | {r['method'].replace('ghost-', '')} | "
                  f"{r['step_s'] * 1e3:.3f} | {r['ghost_s'] * 1e3:.3f} | {r['particle_steps_per_s'] / 1e6:.2f} | "
                  f"{r['step_s'] / ref['step_s']:.2f} | {r['ghost_s'] / ref['ghost_s']:.2f} |")


if __name__ == "__main__":
    main()
