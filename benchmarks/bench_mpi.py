"""2 MPI ranks x 1 thread against 1 process x 2 threads, side by side (issue 22, item 4).

Both configurations use the machine's two cores: ``seawall bench dam-break --threads 2`` in one
process, and ``mpiexec -n 2 seawall bench dam-break --threads 1`` (seawall.parallel). They run
interleaved, round by round, because the project's machines are shared and their speed drifts
within minutes: only the ratio within a round means anything; the median over the rounds is
reported (goal of the issue: at least 0.85 of the threaded rate at 320k particles). The 2-rank
line also gives the halo fraction (halo rows / owned rows, summed over the ranks) and the time a
rank spends in communication calls per step, waiting for the other rank included.

    python benchmarks/bench_mpi.py                       # 320k particles, 3 rounds
    python benchmarks/bench_mpi.py --dx 0.0015 --rounds 5 --steps 100     # 80k
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def bench(dx, steps, ranks):
    threads = 2 if ranks == 1 else 1
    env = {**os.environ, "PYTHONPATH": ROOT, "NUMBA_NUM_THREADS": str(threads)}
    cmd = [sys.executable, "-m", "seawall", "bench", "dam-break", "--dx", str(dx), "--steps", str(steps),
           "--threads", str(threads)]
    if ranks > 1:
        cmd = ["mpiexec", "-n", str(ranks), *cmd]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, cwd=ROOT, env=env)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=0.00075, help="dam break spacing (0.00075: 320k fluid)")
    parser.add_argument("--steps", type=int, default=60)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--json", help="also write the rounds here")
    args = parser.parse_args(argv)
    rounds = []
    for k in range(args.rounds):
        threaded = bench(args.dx, args.steps, 1)
        ranks = bench(args.dx, args.steps, 2)
        ratio = ranks["particle_steps_per_s"] / threaded["particle_steps_per_s"]
        # CPU seconds per step (both threads; both ranks, MPICH's busy waiting included): steadier than wall
        # time on a loaded machine, where a parallel region waits for its slowest thread
        ratio_cpu = threaded["cpu_seconds"] / ranks["cpu_seconds"]
        rounds.append({"threaded": threaded, "mpi": ranks, "ratio": ratio, "ratio_cpu": ratio_cpu,
                       "load": os.getloadavg()[0]})
        print(f"round {k + 1}: 1 x 2 threads {threaded['particle_steps_per_s'] / 1e6:.3f} M/s, "
              f"2 ranks x 1 thread {ranks['particle_steps_per_s'] / 1e6:.3f} M/s, ratio {ratio:.3f} "
              f"(CPU time: {ratio_cpu:.3f}, load {os.getloadavg()[0]:.1f}); halo "
              f"{ranks['halo_fraction']:.4f}, communication {1e3 * ranks['comm_seconds_per_step']:.2f} ms/step "
              f"of {1e3 * ranks['seconds'] / ranks['steps']:.1f} ms", flush=True)
    summary = {"n_particles": rounds[0]["threaded"]["n_particles"], "dx": args.dx, "steps": args.steps,
               "median_ratio": statistics.median(r["ratio"] for r in rounds),
               "ratios": [r["ratio"] for r in rounds],
               "median_ratio_cpu": statistics.median(r["ratio_cpu"] for r in rounds),
               "ratios_cpu": [r["ratio_cpu"] for r in rounds], "load": os.getloadavg()}
    print(json.dumps(summary))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"summary": summary, "rounds": rounds}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
