"""Where does a decomposed run part from the serial one? Per-step states, and a serial run perturbed by one ulp.

Two measurements of docs/parallel.md ("LUST and pressure mirroring"):

* ``dump``: one ``seawall run`` (serial, or under ``mpiexec``) that records the whole fluid, sorted by
  particle id, after every ``--every`` steps, to an ``.npz`` (x, v, rho, p per recorded step);
* ``compare``: two such files, step by step: max over particles of |dx| / spacing, |dv| / max |v|,
  |drho| / rho0; the first step beyond each threshold and the steps where the difference jumps most,
  with the particle that jumped;
* ``perturb``: a serial ``seawall run`` whose fluid positions are all moved by one ulp
  (``np.nextafter``) once the case is built: how much the model amplifies a round-off difference
  by itself (compare its probes.csv with an unperturbed run's by ``mpi_agreement.compare``).

    python benchmarks/mpi_divergence.py dump a.npz -- run dam-break --boundary lust --set H=0.1 --dx 0.005 \\
        --t-end 0.3 --no-vtk --out runs/a
    SEAWALL_MPI_COMPARE_ANY_MODEL=1 mpiexec -n 2 python benchmarks/mpi_divergence.py dump b.npz -- run ...
    python benchmarks/mpi_divergence.py compare a.npz b.npz --dx 0.005
    python benchmarks/mpi_divergence.py perturb -- run dam-break --boundary lust ... --out runs/c
"""

import argparse
import os
import sys

import numpy as np

# the seawall of this tree, as mpi_agreement.py runs it
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def dump(path, every, argv):
    import seawall.cli as cli

    record = {"step": [], "t": [], "x": [], "v": [], "rho": [], "p": []}
    ids = []
    original = cli._mpi

    def recording(sim, args):
        comm = original(sim, args)
        one_step = sim._one_step

        def step(dt):
            one_step(dt)
            if sim.step % every:
                return
            whole = sim._gather_fluid() if comm is not None else sim.fluid.particles
            if whole is None:            # ranks other than 0
                return
            order = np.argsort(whole["id"], kind="stable")
            if not ids:
                ids.append(np.array(whole["id"][order]))
            record["step"].append(sim.step)
            record["t"].append(sim.time)
            for name in ("x", "v", "rho", "p"):
                record[name].append(np.array(whole[name][order]))

        sim._one_step = step
        return comm

    cli._mpi = recording
    code = cli.main(argv)
    if record["step"]:
        np.savez(path, id=ids[0], **{k: np.array(v) for k, v in record.items()})
    return code


def perturb(argv):
    import seawall.cli as cli

    build = cli._build

    def moved(args):
        case, sim = build(args)
        x = sim.fluid.particles["x"]
        x[...] = np.nextafter(x, np.inf)     # one ulp: the smallest change of the input there is
        return case, sim

    cli._build = moved
    return cli.main(argv)


def compare(a_path, b_path, spacing, rho0):
    a, b = np.load(a_path), np.load(b_path)
    n = min(len(a["step"]), len(b["step"]))
    if not np.array_equal(a["id"], b["id"]) or not np.array_equal(a["step"][:n], b["step"][:n]):
        raise SystemExit("the two runs hold other particles or recorded other steps")
    steps = a["step"][:n]
    dx = np.abs(a["x"][:n] - b["x"][:n]).max(axis=(1, 2)) / spacing
    dv = np.abs(a["v"][:n] - b["v"][:n]).max(axis=(1, 2)) / np.abs(a["v"][:n]).max()
    drho = np.abs(a["rho"][:n] - b["rho"][:n]).max(axis=1) / rho0
    diff = np.maximum.reduce([dx, dv, drho])
    print(f"{n} recorded steps; largest time difference {np.abs(a['t'][:n] - b['t'][:n]).max():.3g} s")
    for threshold in (1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5):
        beyond = np.flatnonzero(diff > threshold)
        print(f"  first step beyond {threshold:g}: {steps[beyond[0]] if beyond.size else None}")
    for k in np.linspace(0, n - 1, 5).astype(int):
        print(f"  step {steps[k]}: {diff[k]:.2g}")
    # jumps, once the states differ at all (the first differences jump from exactly zero)
    growth = np.where(diff[:-1] > 1e-15, diff[1:] / np.maximum(diff[:-1], 1e-300), 0.0)
    for k in np.argsort(-growth)[:5]:
        s = k + 1
        dv_particle = np.abs(a["v"][s] - b["v"][s]).max(axis=1)
        i = int(np.argmax(dv_particle))
        print(f"  x{growth[k]:.3g} at step {steps[s]} (t = {a['t'][s]:.6f} s): {diff[k]:.2g} -> {diff[s]:.2g}; "
              f"particle {a['id'][i]} at {np.round(a['x'][s][i], 6).tolist()}, |dv| {dv_particle[i]:.2g} m/s")
    return 0


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    rest = []
    if "--" in argv:
        rest = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="what", required=True)
    d = sub.add_parser("dump")
    d.add_argument("npz")
    d.add_argument("--every", type=int, default=1)
    sub.add_parser("perturb")
    c = sub.add_parser("compare")
    c.add_argument("a")
    c.add_argument("b")
    c.add_argument("--dx", type=float, required=True, help="particle spacing [m]")
    c.add_argument("--rho0", type=float, default=1000.0)
    args = parser.parse_args(argv)
    if args.what == "dump":
        return dump(args.npz, args.every, rest)
    if args.what == "perturb":
        return perturb(rest)
    return compare(args.a, args.b, args.dx, args.rho0)


if __name__ == "__main__":
    sys.exit(main())
