"""Lid-driven cavity at Re = 1000: centreline velocities against Ghia, Ghia & Shin (1982).

Case ``cavity`` (L = 1 mm, lid U = 1 mm/s, nu = U L / Re; seed 003 sec. 4.2
runs Re = 1), no-slip dummy walls (``adami-noslip``), dx = L/50, h = 1.2 dx,
until t = 30.0 s. Quantity: u/U on the vertical and v/U on the horizontal
centreline at the reference points; the largest deviation. Tolerance (fixed
before the run): 5 % of U.
"""

from .. import Entry
from ._cavity import run_cavity


def run(ctx):
    return run_cavity(ctx, 1000, 30.0)


ENTRY = Entry(name="cavity-re1000", title="Lid-driven cavity, Re = 1000: centreline velocities", run=run,
              expected_s=300, quick_s=10, order=82, description=" ".join(__doc__.split("\n\n")[1].split()))
