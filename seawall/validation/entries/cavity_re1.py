"""Lid-driven cavity at Re = 1: centreline velocities against a computed reference.

Case ``cavity`` (L = 1 mm, lid U = 1 mm/s, nu = U L / Re; seed 003 sec. 4.2
runs Re = 1), no-slip dummy walls (``adami-noslip``), dx = L/50, h = 1.2 dx,
c0 = 0.05 m/s, until t = 2.0 s (two viscous times L^2 / nu). The seed's
c0 = 10 U = 0.01 m/s is not used: with it the viscous stress at the lid's
corners (~ rho nu U / dx) is half of rho0 c0^2, and the run stops at
t = 0.82 s with a particle in the top right corner compressed to 2 rho0.
Quantity: u/U on the vertical and v/U on the horizontal
centreline at the reference points; the largest deviation. Tolerance (fixed
before the run): 5 % of U.
"""

from .. import Entry
from ._cavity import run_cavity


def run(ctx):
    return run_cavity(ctx, 1, 2.0, c0=0.05)


ENTRY = Entry(name="cavity-re1", title="Lid-driven cavity, Re = 1: centreline velocities", run=run,
              expected_s=90, quick_s=10, order=80, description=" ".join(__doc__.split("\n\n")[1].split()))
