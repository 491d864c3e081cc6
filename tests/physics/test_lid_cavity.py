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


def test_summation_density_and_kernel_options_reach_the_fluid():
    from seawall.errors import ParameterError
    from seawall.kernels import QuinticSpline

    sim = build("cavity", boundary="adami-noslip", dx=1e-3 / 20, density="summation", kernel="quintic",
                h_factor=1.0, background=0.0)
    assert sim.fluid.density_mode == "summation"
    assert sim.fluid.density_diffusion is None          # delta defaults to 0 with a summed density
    assert sim.kernel.kind == QuinticSpline.kind and sim.h == 1e-3 / 20
    # the walls fill the quintic's support of 3 h = 3 dx
    walls = sim.walls[0].particles["x"]
    assert np.isclose(walls[:, 0].min(), -3 * 1e-3 / 20 + 0.5e-3 / 20)
    assert sim.physics.p_background == 0.0
    plain = build("cavity", boundary="adami-noslip", dx=1e-3 / 20)
    assert plain.fluid.density_mode == "continuity" and plain.fluid.density_diffusion.delta == 0.1
    for bad, word in (({"density": "summation", "delta": 0.1}, "delta"), ({"density": "sum"}, "density"),
                      ({"kernel": "spline"}, "kernel"), ({"fluid": "liu2015", "kernel": "quintic"}, "kernel")):
        try:
            build("cavity", boundary="adami-noslip", dx=1e-3 / 20, **bad)
        except ParameterError as exc:
            assert word in str(exc)
        else:
            raise AssertionError(f"{bad} was accepted")
