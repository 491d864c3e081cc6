"""Re-run stored regression series, report how much each changed, and rewrite them.

Run from the repository root::

    python -m tests.regression.regenerate                  # every series
    python -m tests.regression.regenerate 'dam-break-*' cavity-liu2015   # fnmatch patterns
    python -m tests.regression.regenerate --check '*-idbc' # report only, write nothing
    python -m tests.regression.regenerate --list           # the series' names

For each series one line: ``unchanged`` (bit-identical), ``within`` (largest scaled
deviation below the test tolerance ``series.RTOL``), ``CHANGED`` (above it, with the
quantity that moved most) or ``new``. Only the series named are rewritten, so a
deliberate change of one wall model regenerates exactly that model's series; run
``--check`` over everything first to see that nothing else moved. Exit code 1 when
``--check`` finds a series above the tolerance.
"""

import argparse
import sys
import time

from . import series


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m tests.regression.regenerate", description=__doc__.splitlines()[0])
    parser.add_argument("patterns", nargs="*", help="series names or fnmatch patterns (default: all)")
    parser.add_argument("--check", action="store_true", help="report the deviations, write nothing")
    parser.add_argument("--list", action="store_true", help="print the series' names and exit")
    parser.add_argument("--threads", type=int, default=None, help="threads of the compiled loops")
    args = parser.parse_args(argv)
    names = series.select(args.patterns)
    if args.list:
        print("\n".join(names))
        return 0
    if not names:
        print(f"no series matches {' '.join(args.patterns)}; see --list", file=sys.stderr)
        return 2
    above = 0
    for name in names:
        started = time.perf_counter()
        new = series.run(name, threads=args.threads)
        seconds = time.perf_counter() - started
        try:
            stored = series.load(name)
        except FileNotFoundError:
            stored = None
        if stored is None:
            status = "new"
        else:
            devs = series.deviations(stored, new)
            key, dev = series.worst(devs)
            if dev == 0.0:
                status = "unchanged"
            elif dev <= series.RTOL:
                status = f"within    largest scaled deviation {dev:.3g} ({key})"
            else:
                above += 1
                moved = sorted((k for k in devs if devs[k] > series.RTOL), key=lambda k: -devs[k])
                status = (f"CHANGED   largest scaled deviation {dev:.3g} ({key}); above {series.RTOL:g}: "
                          + ", ".join(f"{k} {devs[k]:.3g}" for k in moved[:6])
                          + (" ..." if len(moved) > 6 else ""))
        if not args.check and status != "unchanged":
            series.save(name, new)
        print(f"{name:34s} {int(new['steps']):5d} steps {seconds:6.1f} s  {status}", flush=True)
    if args.check and above:
        print(f"{above} series above the tolerance {series.RTOL:g}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
