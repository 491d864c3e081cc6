"""Start-up Poiseuille flow between plates against the series of Morris, Fox & Zhu (1997).

Case ``poiseuille`` (plates L = 1 mm apart, periodic along x, nu = 1e-6 m^2/s; Re = 0.0125), no-slip
dummy walls (``adami-noslip``: Adami et al. 2012 wall velocity), dx = L/40,
laminar viscosity, until tau = nu t / L^2 = 1. Quantity: u / u_ref of every
particle against the series at tau = 0.02, 0.1, 0.2, 1 (the largest deviation);
tolerance (chosen before the run): 2 % of u_ref. The series is checked against
the tabulated data in data/poiseuille_couette_analytic.
"""

from seawall.validation import Entry
from seawall.validation._channel import run_channel


def run(ctx):
    return run_channel(ctx, "poiseuille")


ENTRY = Entry(name="poiseuille", title="Poiseuille start-up flow against the analytic series (Morris et al. 1997)", run=run,
              expected_s=40, quick_s=5, order=40,
              description=" ".join(__doc__.split("\n\n")[1].split()))
