"""Speed of the core engine: particle-steps per second of the 2D and 3D dam breaks.

Runs ``seawall bench`` in a fresh process per configuration (so the thread
count is set before numba starts) at about 20k, 80k and 320k particles in 2D
and one 3D size, with 1 and 2 threads, and prints a table plus one JSON line
per run. Compilation is excluded from the timing (reported separately).

    python benchmarks/bench_engine.py            # the full set (about 3 minutes on 2 cores)
    python benchmarks/bench_engine.py --quick    # 20k and 80k, 2 threads

Targets (issue 2; 2-core machine, float64, 2 threads): >= 2.5 M particle-steps/s
for the 2D dam break at 80k particles; time per step from 80k to 320k growing
at most 4.4 times.
"""

import argparse
import json
import subprocess
import sys

# dx for the 2D dam break (H = 0.3 m) giving about 20k, 80k and 320k particles (fluid + wall)
SIZES_2D = {"20k": 0.003, "80k": 0.0015, "320k": 0.00075}
SIZE_3D = {"3d-100k": 0.01}


def bench(case, dx, threads, steps):
    cmd = [sys.executable, "-m", "seawall", "bench", case, "--dx", str(dx), "--steps", str(steps),
           "--threads", str(threads)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.strip().splitlines()[-1]
    return json.loads(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--steps", type=int, default=200, help="timed steps at 80k particles (scaled for other sizes)")
    args = parser.parse_args(argv)

    runs = []
    sizes = {"20k": 0.003, "80k": 0.0015} if args.quick else SIZES_2D
    threads_list = (2,) if args.quick else (1, 2)
    for label, dx in sizes.items():
        for threads in threads_list:
            steps = {"20k": 2 * args.steps, "80k": args.steps, "320k": max(20, args.steps // 3)}[label]
            runs.append(("dam-break", label, threads, bench("dam-break", dx, threads, steps)))
    if not args.quick:
        for label, dx in SIZE_3D.items():
            for threads in threads_list:
                runs.append(("dam-break-3d", label, threads, bench("dam-break-3d", dx, threads, max(20, args.steps // 3))))

    print(f"{'case':<14}{'size':>8}{'threads':>9}{'particles':>11}{'ms/step':>10}{'M p-steps/s':>13}"
          f"{'median':>8}{'best':>8}{'compile s':>11}")
    for case, label, threads, rec in runs:
        ms = rec["seconds"] / rec["steps"] * 1e3
        print(f"{case:<14}{label:>8}{threads:>9}{rec['n_particles']:>11}{ms:>10.2f}"
              f"{rec['particle_steps_per_s'] / 1e6:>13.3f}{rec['median_chunk_particle_steps_per_s'] / 1e6:>8.3f}"
              f"{rec['best_chunk_particle_steps_per_s'] / 1e6:>8.3f}{rec['compile_seconds']:>11.1f}")
    for *_, rec in runs:
        print(json.dumps(rec))

    by = {(c, l, t): r for c, l, t, r in runs}
    target = by.get(("dam-break", "80k", 2))
    if target:
        ok = target["particle_steps_per_s"] >= 2.5e6
        print(f"target 2D 80k, 2 threads >= 2.5 M particle-steps/s: "
              f"{target['particle_steps_per_s'] / 1e6:.2f} M -> {'met' if ok else 'NOT met'}")
    big = by.get(("dam-break", "320k", 2))
    if target and big:
        growth = (big["seconds"] / big["steps"]) / (target["seconds"] / target["steps"])
        ratio = big["n_particles"] / target["n_particles"]
        print(f"time per step 80k -> 320k ({ratio:.2f}x particles): {growth:.2f}x "
              f"-> {'met' if growth <= 4.4 else 'NOT met'} (limit 4.4x)")


if __name__ == "__main__":
    main()
