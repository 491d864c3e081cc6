"""Build the API reference (HTML) from seawall's docstrings with pdoc.

    pip install -e ".[docs]"
    python docs/build_api.py [--out docs/api] [--show-source]

Open ``docs/api/index.html`` in a browser. The pages are not committed (they are
generated, 3.4 MB of which 2 MB are the search index; 5 MB with ``--show-source``):
build them when you need them.

Any warning pdoc raises while reading the package (a docstring it cannot parse, a
broken cross-reference, a module that fails to import) stops the build with exit
code 1, so the reference builds cleanly or not at all (``tests/unit/test_tutorials.py``
runs this script when pdoc is installed).
"""

import argparse
import os
import sys
import warnings
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

#: the modules a user of the library calls, in the order of the reference's sidebar
#: (the compiled loops' modules are left out: their functions are internals)
PUBLIC_MODULES = [
    "seawall",
    "seawall.cases",
    "seawall.simulation",
    "seawall.fluid",
    "seawall.boundary",
    "seawall.shapes",
    "seawall.probes",
    "seawall.sampling",
    "seawall.output",
    "seawall.io",
    "seawall.postprocess",
    "seawall.kernels",
    "seawall.eos",
    "seawall.integrators",
    "seawall.coupling",
    "seawall.openboundary",
    "seawall.dem",
    "seawall.errors",
]


def build(out, show_source=False):
    """Write the HTML reference of :data:`PUBLIC_MODULES` into ``out``; return the warnings pdoc raised."""
    # numba asks the platform for the processor name at import; pdoc blocks subprocesses unless allowed
    os.environ.setdefault("PDOC_ALLOW_EXEC", "1")
    import pdoc
    import pdoc.render

    pdoc.render.configure(docformat="numpy", show_source=show_source, math=False, search=True,
                          footer_text="seawall API reference (generated from the docstrings by docs/build_api.py)")
    sys.path.insert(0, str(REPO))   # this checkout's package, installed or not
    import seawall

    # the submodules in seawall.__all__ come with the package's page; naming them again is an error to pdoc
    modules = [m for m in PUBLIC_MODULES if m.split(".", 1)[-1] not in seawall.__all__]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = Path(out).resolve()
        out.mkdir(parents=True, exist_ok=True)
        here = os.getcwd()
        os.chdir(out)   # pdoc warns when a folder named like the module is in the working directory
        try:
            pdoc.pdoc(*modules, output_directory=out)
        finally:
            os.chdir(here)
    return [f"{w.category.__name__}: {w.message}" for w in caught]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(Path(__file__).resolve().parent / "api"),
                        help="output directory (default docs/api)")
    parser.add_argument("--show-source", action="store_true", help="include each function's source (5x larger)")
    args = parser.parse_args(argv)
    try:
        import pdoc  # noqa: F401
    except ImportError:
        print("build_api: pdoc is not installed; pip install -e \".[docs]\"", file=sys.stderr)
        return 2
    problems = build(args.out, show_source=args.show_source)
    for line in problems:
        print(f"build_api: {line}", file=sys.stderr)
    if problems:
        return 1
    print(os.path.join(args.out, "index.html"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
