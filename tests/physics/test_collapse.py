"""Column collapse (Koshizuka & Oka 1996 geometry; Martin & Moyce 1952, n^2 = 2) at dx = a/40.

Measured (Adami free slip, a = 0.146 m): the surge front agrees with K&O's MPS
computation of the same inviscid problem within 3 %, and runs ahead of both
experiments: +12 ... +16 % against Martin & Moyce (a = 2.25 in) at T <= 2.6,
+14 ... +18 % at dx = a/80 (so not a resolution effect). The experiment's gate
takes time to lift and the floor is not frictionless; neither is modelled.
"""

import os

import numpy as np
import pytest

from seawall.cases import build

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(os.path.dirname(os.path.dirname(HERE)), "data")
A = 0.146
G = 9.81


def load(folder, name):
    return np.loadtxt(os.path.join(DATA, folder, name), delimiter=",", skiprows=1)


@pytest.fixture(scope="module")
def front():
    sim = build("collapse", dx=A / 40)
    sim.add(every=0.002)
    result = sim.run(0.3, progress=False)
    T = result.times * np.sqrt(2 * G / A)
    Z = result["front"] / A
    return T, Z, result


def until_far_wall(data, T, Z):
    """Reference points before the simulated front reaches the far wall (Z = 4)."""
    t_wall = T[np.argmax(Z >= 3.95)] if np.any(Z >= 3.95) else T[-1]
    return data[(data[:, 0] > 0.5) & (data[:, 0] < t_wall) & (data[:, 1] < 3.95)]


def test_front_matches_the_mps_computation_within_5_percent(front):
    T, Z, _ = front
    ref = until_far_wall(load("koshizuka_oka1996_collapse", "ko1996_mps_front_pysph.csv"), T, Z)
    assert len(ref) >= 8
    sph = np.interp(ref[:, 0], T, Z)
    err = np.abs(sph - ref[:, 1]) / ref[:, 1]
    assert err.max() < 0.05, list(zip(ref[:, 0], ref[:, 1], sph))


@pytest.mark.xfail(strict=True, reason="measured +12..+16 % at dx = a/40 (+14..+18 % at a/80): the modelled "
                                       "column is released instantly on a frictionless floor; see docs/validation-notes.md")
def test_front_within_5_percent_of_martin_moyce(front):
    T, Z, _ = front
    ref = until_far_wall(load("martin_moyce1952_collapse", "mm1952_n2_2_a2.25in_front_pysph.csv"), T, Z)
    sph = np.interp(ref[:, 0], T, Z)
    assert np.max(np.abs(sph - ref[:, 1]) / ref[:, 1]) < 0.05


def test_front_is_monotone_and_nothing_escapes(front):
    T, Z, result = front
    before_wall = Z < 3.9
    assert np.all(np.diff(Z[before_wall]) >= -1e-9)
    assert Z.max() > 3.9  # it does reach the far wall within the run
    assert Z[0] == pytest.approx((40 - 0.5) / 40, abs=1e-9)  # the last particle column at a - dx/2
    assert result.summary["escaped_particles"] == 0
