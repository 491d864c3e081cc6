"""Issue 15 item 2 (no leaks on the dam break): the opt-in safeguards of the wall models that cannot hold
the dam break in their published form -- the ghost walls' ``reflect`` and the Liu et al. (2012) force's ``c``."""

import numpy as np
import pytest

from seawall.boundary.liu2012 import liu2012_factor
from seawall.boundary.registry import boundary_by_name, boundary_options
from seawall.cases import build
from seawall.errors import ParameterError


def small_ghost_tank(**kwargs):
    # 10 x 4 particles (dx = 0.05) in a 0.5 m tank with 0.3 m walls; the left wall surface is x = 0
    return build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3, initial="rest",
                 boundary="ghost-sfdi", **kwargs)


@pytest.mark.parametrize("name", ["ghost-mls1", "ghost-mls2", "ghost-sfdi", "ghost-normalized", "ghost-shepard"])
def test_every_ghost_wall_takes_reflect_off_by_default(name):
    assert "reflect" in boundary_options(name)
    assert boundary_by_name(name).reflect is False
    assert boundary_by_name(name, {"reflect": "1"}).reflect is True
    with pytest.raises(ParameterError, match="true/false"):
        boundary_by_name(name, {"reflect": "maybe"})


@pytest.mark.parametrize("reflect", [False, True])
def test_reflect_sends_a_crossed_particle_back_with_its_normal_velocity_reversed(reflect):
    sim = small_ghost_tank(reflect=int(reflect))
    sim.run(0.002, progress=False)
    fp = sim.fluid.particles
    wall = sim.walls[0]
    fp["x"][5] = (-0.012, 0.1)          # 0.24 dx behind the left wall surface
    fp["v"][5] = (-0.8, 0.3)            # moving into the wall
    fp["x"][6] = (0.2, 0.1)             # in the fluid
    fp["v"][6] = (-0.8, 0.3)
    x_before = fp["x"].copy()
    v_before = fp["v"].copy()
    wall.model.after_step(wall, sim.fluid, sim)
    if not reflect:
        assert np.array_equal(fp["x"], x_before) and np.array_equal(fp["v"], v_before)
        return
    assert fp["x"][5] == pytest.approx((0.012, 0.1), abs=1e-12)     # mirrored across x = 0
    assert fp["v"][5] == pytest.approx((0.8, 0.3), abs=1e-12)       # normal part reversed, tangential kept
    keep = np.arange(fp.n) != 5
    assert np.array_equal(fp["x"][keep], x_before[keep]) and np.array_equal(fp["v"][keep], v_before[keep])
    assert wall.model.reflections == 1


def test_reflect_keeps_an_outward_velocity_and_handles_the_corner():
    sim = small_ghost_tank(reflect=1)
    sim.run(0.002, progress=False)
    fp = sim.fluid.particles
    wall = sim.walls[0]
    fp["x"][5] = (0.1, -0.01)           # 0.2 dx below the floor, already moving back up
    fp["v"][5] = (0.5, 0.4)
    fp["x"][6] = (-0.01, -0.01)         # behind the corner of the left wall and the floor
    fp["v"][6] = (-0.3, -0.3)
    wall.model.after_step(wall, sim.fluid, sim)
    assert fp["x"][5] == pytest.approx((0.1, 0.01), abs=1e-12)
    assert fp["v"][5] == pytest.approx((0.5, 0.4), abs=1e-12)
    # the nearest wall particle is the corner's: its normal is the diagonal, its surface point the corner
    assert fp["x"][6] == pytest.approx((0.01, 0.01), abs=1e-12)
    assert fp["v"][6] == pytest.approx((0.3, 0.3), abs=1e-12)


def test_liu2012_force_speed_is_a_wall_option():
    assert "c" in boundary_options("liu2012")
    model = boundary_by_name("liu2012", {"c": "48.5"})
    assert model.c == 48.5
    with pytest.raises(ParameterError, match="c must be"):
        boundary_by_name("liu2012", {"c": "fast"})


def liu2012_holding_pressure(dx, c, beta=2.0, h_factor=1.3):
    """Largest pressure p = rho a dx the row can hold (docs/boundaries.md): the wall-normal
    acceleration a of one fluid particle, maximised over its height above the row, at the
    weakest point of the row (midway between two boundary particles), per unit density."""
    h = h_factor * dx
    xb = (np.arange(-12, 13) + 0.5) * dx / beta        # the particle at x = 0 is midway between two
    ys = np.linspace(1e-4, 1.0, 4000) * dx
    acc = [sum(liu2012_factor(np.hypot(b, y), h, dx, c) * y for b in xb) for y in ys]
    return max(acc) * dx


@pytest.mark.parametrize("dx", [0.02, 0.006])
def test_liu2012_row_holds_at_most_two_percent_of_rho_c_squared(dx):
    """The published force 0.01 c^2 ... caps the pressure one row holds at 0.0187 rho c^2, whatever dx:
    3.7 rho g H with the dam break's c = 10 sqrt(2 g H), below its impact pressures."""
    c = 10.0 * np.sqrt(2 * 9.81 * 0.3)
    p = liu2012_holding_pressure(dx, c)
    assert p / c ** 2 == pytest.approx(0.0187, abs=0.0005)
    assert liu2012_holding_pressure(dx, 2 * c) == pytest.approx(4 * p, rel=1e-9)
