"""Moved to ``validation/idbc/figures.py`` of the repository checkout (with its figures in validation/idbc/img).

This name stays so that ``python -m seawall.plots_idbc [fields|box|drop|sweep|all] [--out DIR]`` and
``from seawall.plots_idbc import fields, box, drop, sweep, main`` keep working from a checkout.
"""

import os

from .validation import load_script

_PATH = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "validation", "idbc", "figures.py")
if not os.path.isfile(_PATH):
    raise ModuleNotFoundError("seawall.plots_idbc moved to validation/idbc/figures.py of the repository checkout, "
                              "which is not there")
_figures = load_script(_PATH)

fields, box, drop, sweep, main = _figures.fields, _figures.box, _figures.drop, _figures.sweep, _figures.main
__all__ = ["fields", "box", "drop", "sweep", "main"]

if __name__ == "__main__":
    raise SystemExit(main())
