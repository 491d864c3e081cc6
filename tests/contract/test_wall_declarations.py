"""The wall-model declarations (seawall/boundary/base.py) decide behaviour where they say they do.

That every registered model declares the contract is checked per model in test_wall_contract.py
(``test_registry_builds_a_wall_model_that_declares_the_contract``); here, the declarations' effects.
"""

import numpy as np
import pytest

from seawall.boundary.base import WallModel, check_contract
from seawall.boundary.dbc import DynamicBoundary
from seawall.boundary.registry import BOUNDARIES, boundary_by_name
from seawall.cases import CASES
from seawall.errors import ParameterError


def test_surface_models_and_declared_terms():
    assert boundary_by_name("monaghan-kajtar").layout == "surface"
    assert boundary_by_name("liu2012").layout == "surface"
    assert "xsph" in boundary_by_name("dbc").fluid_terms
    assert "xsph" not in boundary_by_name("adami").fluid_terms
    assert "laminar_viscosity" in boundary_by_name("adami-noslip").fluid_terms
    assert "laminar_viscosity" not in boundary_by_name("adami").fluid_terms
    assert boundary_by_name("continuity").integrated_arrays == ("rho",)
    # layered walls count in particle shifting and the transport velocity, surface rows do not
    for name in BOUNDARIES:
        model = boundary_by_name(name)
        layered = model.layout == "layers"
        assert ("shifting" in model.fluid_terms) == layered, name
        assert ("transport_velocity" in model.fluid_terms) == layered, name


def test_legacy_wall_layout_attribute_still_sets_the_layout():
    class Old(WallModel):
        wall_layout = "surface"

    assert Old().layout == "surface"


def test_set_keys_go_to_the_model_that_takes_them():
    sim = CASES["hydrostatic"].build(boundary="dbc", dx=0.05, alpha_wall="0.1", threads=1)
    assert sim.walls[0].model.alpha_wall == 0.1
    with pytest.raises(ParameterError, match="alpha_wall"):
        CASES["hydrostatic"].build(boundary="adami", dx=0.05, alpha_wall="0.1", threads=1)


def test_unknown_fluid_term_is_refused():
    class Odd(WallModel):
        name = "odd"
        fluid_terms = frozenset({"surface_tension"})

    with pytest.raises(ParameterError, match="surface_tension"):
        check_contract(Odd())


def test_no_slip_without_viscosity_is_refused_by_check():
    sim = CASES["hydrostatic"].build(boundary="adami", dx=0.05, threads=1)
    fluid = sim.fluid
    physics = sim.physics._replace(alpha=0.0, nu=0.0)
    with pytest.raises(ParameterError, match="viscosity"):
        boundary_by_name("adami-noslip").check(fluid, physics)


class _DbcWithoutXsph(DynamicBoundary):
    fluid_terms = DynamicBoundary.fluid_terms - {"xsph"}


@pytest.mark.parametrize("model_class, acts", [(DynamicBoundary, True), (_DbcWithoutXsph, False)])
def test_declared_terms_decide_whether_xsph_crosses_the_wall(model_class, acts):
    sim = CASES["drop-impact"].build(boundary=lambda: model_class(), threads=1)
    assert sim.physics.xsph > 0.0
    fp = sim.fluid.particles
    wall = sim.walls[0]
    # lower the drop to one spacing above the wall row, so that it is within the wall's reach
    fp["x"][:, -1] -= fp["x"][:, -1].min() - wall.x[:, -1].max() - sim.fluid.spacing
    sim.run_steps(0)  # the first evaluation: equation of state, fluid rates
    xsph_before = fp["xsph"].copy()
    dv = np.zeros_like(fp["dv"])
    drho = np.zeros_like(fp["drho"])
    from seawall.boundary.base import EvaluationContext

    ctx = EvaluationContext(physics=sim.physics, grid=sim.grid, fluid_cells=sim.grid.build(fp["x"]),
                            time=sim.time, dx=sim.fluid.spacing)
    wall.model.interact(sim.fluid, wall, ctx, dv, drho)
    assert np.any(drho != 0.0)  # the drop touches the wall
    assert np.any(fp["xsph"] != xsph_before) == acts
