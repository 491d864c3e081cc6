"""The lid-driven cavity case: the lid drives one clockwise vortex (short, coarse run).

The centreline comparison at the seed's resolution is ``seawall validate cavity-re1``.
"""

import numpy as np
import pytest

from seawall.cases import build
from seawall.cases.lid_cavity import centrelines

#: the scheme without regularisation, the case's default until issue 17 (entries cavity-re*-plain)
PLAIN = {"transport_velocity": False, "density": "continuity", "background": 0.05}


@pytest.mark.parametrize("scheme", [{}, PLAIN], ids=["default", "plain"])
def test_lid_drives_a_clockwise_vortex_and_nothing_leaves(scheme):
    sim = build("cavity", boundary="adami-noslip", dx=1e-3 / 20, **scheme)
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
    plain = build("cavity", boundary="adami-noslip", dx=1e-3 / 20, transport_velocity=False, density="continuity")
    assert plain.fluid.density_mode == "continuity" and plain.fluid.density_diffusion.delta == 0.1
    assert plain.fluid.transport_velocity is None
    assert plain.metadata["parameters"]["background"] == 0.05     # the EOS background follows the density
    for bad, word in (({"density": "summation", "delta": 0.1}, "delta"), ({"density": "sum"}, "density"),
                      ({"kernel": "spline"}, "kernel"), ({"fluid": "liu2015", "kernel": "quintic"}, "kernel"),
                      ({"fluid": "liu2015", "density": "summation"}, "density"),
                      ({"transport_velocity": False, "tvf_background": 0.5}, "tvf_background"),
                      ({"transport_velocity": "maybe"}, "transport_velocity")):
        try:
            build("cavity", boundary="adami-noslip", dx=1e-3 / 20, **bad)
        except ParameterError as exc:
            assert word in str(exc)
        else:
            raise AssertionError(f"{bad} was accepted")


def test_the_default_scheme_is_adami2013s_transport_velocity():
    # issue 17: chosen by the centreline errors of the entries cavity-re*-plain and cavity-re100-tvf
    sim = build("cavity", boundary="adami-noslip", dx=1e-3 / 20)
    tv = sim.fluid.transport_velocity
    assert tv is not None and tv.background_factor == 1.0 and not tv.free_surface
    assert sim.fluid.density_mode == "summation" and sim.fluid.density_diffusion is None
    assert sim.physics.p_background == 0.0
    params = sim.metadata["parameters"]
    assert (params["transport_velocity"], params["density"], params["background"], params["delta"]) == \
        (True, "summation", 0.0, 0.0)
    # the seed's fluid keeps its evolved density, delta-SPH and zero EOS background, and gains the transport velocity
    seed = build("cavity", boundary="liu2015-noslip", fluid="liu2015", dx=1e-3 / 20)
    assert seed.fluid.transport_velocity is not None and seed.fluid.density_mode == "continuity"
    assert seed.metadata["parameters"]["background"] == 0.0 and seed.fluid.density_diffusion is not None
    assert build("cavity", boundary="liu2015-noslip", fluid="liu2015", dx=1e-3 / 20,
                 transport_velocity=False).fluid.transport_velocity is None
