"""Short versions of the [Li2022] test cases (Li, Zhang & Yuan), asserting the measured behaviour.

Tolerances (docs/idbc.md has the full runs):
* one reflection in ``particle-in-box``: IDBC's force field is a ridge parallel
  to the wall, so the reflection angle error comes only from the time
  integration and the rectangle's edges; with ``wall_density=consistent``
  measured <= 0.009 deg for three start points, asserted < 0.02 deg (the
  default, the seed's continuity rule, misses by up to 4.2 deg: docs/idbc.md). DBC's circular supports ripple along the
  wall: measured 0.079-0.091 deg at the same start points, asserted > 0.04 deg,
  so the test separates the two models by a factor of two on either side.
* the drop on the symmetric wall keeps f_sym at round-off (measured 1.6e-13; asserted
  < 1e-10, room for another machine's rounding, far below any real asymmetry).
* break-through (single wall row, h = 1.3 dx): measured escape from 20 m/s for
  both models; asserted: none at 10 m/s with IDBC and at 5 m/s with DBC.
"""

import math

import numpy as np
import pytest

from seawall.cases import build
from seawall.cases.idbc_tests import drop_run


def _reflect(boundary, x0, **options):
    sim = build("particle-in-box", boundary=boundary, threads=1, x0=x0, y0=30.0, **options)
    sim.run(0.4, progress=False)
    v = sim.fluid.particles["v"][0]
    angle = math.degrees(math.atan2(-v[1], -v[0]) - math.pi / 4)
    return angle, float(v @ v / 800.0 - 1.0)


@pytest.mark.parametrize("x0", [55.0, 55.3, 55.7])
def test_idbc_reflection_is_specular(x0):
    # with the wall density integrated across the rectangle's edges; the seed's rule (the default,
    # chosen for still water) gives 4.2, 1.7 and 0.094 deg at these start points (docs/idbc.md)
    angle, dke = _reflect("idbc", x0, wall_density="consistent")
    assert abs(angle) < 0.02
    assert abs(dke) < 1e-3   # measured 3.1e-4, 9.2e-5, 1.9e-6 at x0 = 55.0, 55.3, 55.7


def test_dbc_reflection_is_not_specular():
    angle, dke = _reflect("dbc", 55.3)
    assert abs(angle) > 0.04
    assert abs(dke) < 1e-6  # but the energy comes back (continuity + circular kernel conserve it): measured 1.8e-7


def test_drop_on_symmetric_wall_stays_symmetric():
    out = drop_run("idbc", t_end=1.0e-3, threads=1)
    assert out["status"] == "completed"
    assert np.max(out["f_sym"]) < 1e-10   # measured 1.6e-13
    assert out["final_through"] == 0


@pytest.mark.parametrize("boundary,speed", [("idbc", 10.0), ("dbc", 5.0)])
def test_no_escape_below_breakthrough_speed(boundary, speed):
    R, H = 1.0e-3, 2.0e-3
    out = drop_run(boundary, t_end=(H - R + 6 * R) / speed, threads=1, speed=speed, gravity=False,
                   rho_min=0.05, rho_max=20.0)
    assert out["status"] == "completed"
    assert out["final_through"] == 0
    assert out["min_y"] > 0.0


# ------------------------------------------------------------ still water (issue 15, item 4.1)
RHO0_TANK, G, DEPTH = 1000.0, 9.81, 0.3


@pytest.fixture(scope="module")
def idbc_still_water():
    sim = build("hydrostatic", boundary="idbc", dx=0.025, threads=1)
    sim.add(every=0.01)
    result = sim.run(1.5, progress=False)
    return sim, result


def test_idbc_keeps_still_water_still(idbc_still_water):
    # [Li2022]'s wall density (eq. 8 with eq. 26): measured rms speed 0.0094 m/s = 0.0055 sqrt(g H) at
    # 1.5 s; the `consistent` rule (the default before) gave 0.73 m/s = 0.43 sqrt(g H)
    sim, result = idbc_still_water
    v = sim.fluid.particles["v"]
    rms = np.sqrt(np.mean(np.sum(v * v, axis=1)))
    assert rms < 0.03 * math.sqrt(G * DEPTH)
    assert result.summary["escaped_particles"] == 0


def _late_probe_errors(result):
    late = result.times >= 1.0
    return {name: np.max(np.abs(result[name][late] / (RHO0_TANK * G * (DEPTH - y)) - 1.0))
            for name, y in {"P0": 0.0, "P1": 0.1, "P2": 0.2}.items()}


def test_idbc_wall_probes_stay_near_hydrostatic(idbc_still_water):
    # measured over 1.0-1.5 s: largest relative errors P0 0.195, P1 0.267, P2 0.087 (the `consistent`
    # rule: 29, 9.0 and 25 times the hydrostatic value); asserted below 0.5, about twice the worst
    errors = _late_probe_errors(idbc_still_water[1])
    assert max(errors.values()) < 0.5, errors


@pytest.mark.xfail(strict=True, reason="IDBC's near-wall fluid pressure is 10-27 % above hydrostatic at P1 "
                                       "(dx = 0.025 and 0.0125 m); the 3 % target is not reached (docs/idbc.md)")
def test_idbc_wall_probes_within_3_percent(idbc_still_water):
    errors = _late_probe_errors(idbc_still_water[1])
    assert max(errors.values()) < 0.03, errors
