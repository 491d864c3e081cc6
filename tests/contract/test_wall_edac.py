"""Every registered wall model with an EDAC fluid ([Ramachandran2019]; seawall.fluid.edac), read from the registry.

A model either works with a fluid whose pressure is its own variable -- a short run from rest stays
finite, keeps every particle and gives the tank floor a positive force -- or declares why not
(``WallModel.edac_refusal``) and the simulation refuses the combination in one line naming the model.
The same with the transport velocity on (tvf_free_surface, the tank having a free surface), where the
pressure equation gains (v~ - v) . grad p over the fluid and the walls carrying a pressure.
"""

import numpy as np
import pytest

import seawall as sw
from seawall.boundary.registry import BOUNDARIES, boundary_by_name
from seawall.cases import build
from seawall.errors import ParameterError

MODELS = list(BOUNDARIES)


def edac_tank(boundary, **tvf):
    sim = build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3, initial="rest", boundary=boundary,
                delta=0.0, pressure_model="edac", **tvf)
    sim.add(sw.probes.WallForce("fy", "tank", axis=1))
    return sim


TVF = {"transport_velocity": "true", "tvf_free_surface": "true"}


@pytest.mark.parametrize("tvf", [False, True], ids=["edac", "edac-tvf"])
@pytest.mark.parametrize("boundary", MODELS)
def test_edac_runs_or_is_refused_in_one_line(boundary, tvf):
    options = TVF if tvf else {}
    reason = boundary_by_name(boundary).edac_refusal
    if reason is not None:
        with pytest.raises(ParameterError, match=f"does not work with wall model {boundary!r}") as info:
            edac_tank(boundary, **options)
        assert "\n" not in str(info.value)
        return
    sim = edac_tank(boundary, **options)
    result = sim.run(0.05, progress=False)
    fp = sim.fluid.particles
    if tvf:
        assert np.abs(fp["dv_transport"]).max() > 0.0     # v~ differs from v: the pressure term acted
    for name in ("x", "v", "rho", "p", "dp"):
        assert np.all(np.isfinite(fp[name])), name
    assert result.summary["escaped_particles"] == 0
    # the water (falling from rest) presses on the floor: the fluid pushes the wall down
    assert result["fy"][-1] < 0.0


def test_refused_models_are_the_ones_declaring_a_reason():
    refused = sorted(name for name in MODELS if boundary_by_name(name).edac_refusal is not None)
    assert refused == ["mdbc", "mdbc-noslip"]
