"""Plane Poiseuille flow through an inflow and an outflow zone (``channel``, H = 0.1 m, dx = H/20, Re = 10).

The fluid starts at rest; after 0.4 viscous times (H^2 / nu) the lane-averaged
velocity between x = L/4 and 3L/4, averaged over 10 snapshots in the next 0.2
viscous times, is compared with u(y) = 4 U y (H - y) / H^2. Measured here:
largest deviation 2.2 % of U (the lanes next to the plates are 1.5 % too fast,
the others 0.6-2 % too slow), mass flux in vs out over the window 0.8 %, no
particle lost. At dx = H/30 the deviation falls to 1.1 % (docs/open-boundaries.md).
"""

import numpy as np

from seawall.cases import build
from seawall.cases.channels import channel_profile, poiseuille_velocity


def test_channel_reaches_poiseuille_and_conserves_mass_flux():
    sim = build("channel", boundary="adami-noslip")
    ref = sim.reference
    T = ref["viscous_time"]
    sim.add(every=T / 50)
    sim.run(0.4 * T, progress=False)
    ob = sim.open_boundary
    mass_in0, mass_out0 = ob.net_inflow(0), -ob.net_inflow(1)
    profiles = []
    for k in range(10):
        result = sim.run(0.4 * T + (k + 1) * 0.02 * T, progress=False)
        y, u, count = channel_profile(sim)
        assert count.min() > 5
        profiles.append(u)
    u = np.mean(profiles, axis=0)
    exact = poiseuille_velocity(y, ref["height"], ref["u_max"])
    assert np.abs(u - exact).max() < 0.03 * ref["u_max"]
    flux_in = ob.net_inflow(0) - mass_in0
    flux_out = -ob.net_inflow(1) - mass_out0
    assert flux_in > 10.0   # ~13 kg/m passed in the window: the flux is measured, not noise
    assert abs(flux_in - flux_out) < 0.02 * flux_in
    summary = result.summary
    assert summary["escaped_particles"] == 0
    assert summary["couplings"]["open_boundary"]["particles_left_zone_wrongly"] == 0
    assert abs(summary["mass_drift"]) < 1e-12
