"""The lid-driven cavity case: the lid drives one clockwise vortex (short, coarse run).

The centreline comparison at the seed's resolution is ``seawall validate cavity-re1``.
"""

import numpy as np

from seawall.cases import build
from seawall.cases.lid_cavity import centrelines


def test_lid_drives_a_clockwise_vortex_and_nothing_leaves():
    sim = build("cavity", boundary="adami-noslip", dx=1e-3 / 20)
    res = sim.run(0.2, progress=False)
    u, v = centrelines(sim, np.array([0.25, 0.5, 0.9]))
    assert u[2] > 0.2 and u[0] < -0.05          # along the lid below it, back along the floor
    assert v[0] > 0.05 and v[2] < -0.05          # up on the left, down on the right
    assert res.summary["escaped_particles"] == 0
    assert res["mass"][-1] == res["mass"][0]
