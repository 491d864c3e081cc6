"""``dem-box``: DEM discs falling into a box of DEM wall particles come to rest inside it.

Measured (2D, 100 discs of radius 5 mm, k = 1e6 N/m, e = 0.5, dt = t_c / 50, 1.5 s): final
kinetic energy 2.3e-8 of the potential energy the fall can release; largest overlap 5.8 %
of the radius at impact, 0.8 % at rest; every disc inside the box.
"""

import numpy as np
import pytest

from seawall.cases import build


@pytest.mark.parametrize("dimension, params, t_end", [
    (2, {}, 1.5),
    (3, {"columns": 3, "layers": 3, "width": 0.05, "normal_stiffness": 1e4, "wall_stiffness": 1e4}, 0.5),
])
def test_discs_come_to_rest_inside_the_box(dimension, params, t_end):
    sim = build("dem-box", dimension=dimension, **params)
    result = sim.run(t_end, progress=False)
    bound = sim.metadata["potential_energy_drop_bound"]
    ke = result["kinetic_energy"]
    # at rest: less than a millionth of the energy the fall can release is left as motion
    assert ke[-1] < 1e-6 * bound
    # no element passes through a wall: centres inside the box, overlaps small against the radius
    x = sim.dem.particles["x"]
    width = sim.metadata["parameters"]["width"]
    assert np.all(x[:, :-1] > 0.0) and np.all(x[:, :-1] < width) and np.all(x[:, -1] > 0.0)
    assert result["lowest_bottom"].min() > -sim.dem.particles["radius"][0]
    assert result["max_overlap"].max() < 0.1
