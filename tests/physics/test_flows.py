"""Channel start-up flows with no-slip walls and fluid-only flows, at small resolution.

The full-resolution numbers are in docs/validation.md (``seawall validate``).
"""

import json
import math

import numpy as np
import pytest

from seawall.analytic import couette_startup, elliptical_drop, poiseuille_startup
from seawall.cases import build
from seawall.cli import main

L = 1e-3
NU = 1e-6


def load(data_dir, folder, name):
    return np.loadtxt(f"{data_dir}/{folder}/{name}", delimiter=",", skiprows=1)


def test_series_reproduce_the_tabulated_data(data_dir):
    for fname, func, kw in (("poiseuille_startup_u_over_umax.csv", poiseuille_startup, dict(F=8.0, nu=1.0)),
                            ("couette_startup_u_over_U.csv", couette_startup, dict(U=1.0, nu=1.0))):
        d = load(data_dir, "poiseuille_couette_analytic", fname)
        header = open(f"{data_dir}/poiseuille_couette_analytic/{fname}").readline().strip().split(",")
        for c, head in enumerate(header[1:], start=1):
            if head.startswith("tau_") and float(head[4:]) >= 0.01:
                assert np.allclose(func(d[:, 0], float(head[4:]), L=1.0, **kw), d[:, c], atol=1e-7), (fname, head)
    drop = load(data_dir, "elliptic_and_oscillating_drop_computed", "elliptical_drop_monaghan1994_pysph_params.csv")
    A, a = elliptical_drop(drop[-1, 0])
    assert a == pytest.approx(drop[-1, 2], rel=1e-7) and A == pytest.approx(drop[-1, 1], rel=1e-6)


@pytest.mark.parametrize("name", ["poiseuille", "couette"])
def test_channel_startup_matches_the_series_within_2_percent(name):
    sim = build(name, boundary="adami-noslip", dx=L / 20)
    ref = sim.reference
    scale = ref["force"] * L * L / (8 * NU) if name == "poiseuille" else ref["wall_speed"]
    for tau in (0.02, 0.2):
        sim.run(tau * L * L / NU, progress=False)
        y = sim.fluid.particles["x"][:, 1]
        u = sim.fluid.particles["v"][:, 0]
        exact = (poiseuille_startup(y, sim.time, L=L, F=ref["force"], nu=NU) if name == "poiseuille"
                 else couette_startup(y, sim.time, L=L, U=scale, nu=NU))
        # measured 0.0037, 0.0054 (poiseuille) and 0.0072, 0.0010 (couette) at tau = 0.02, 0.2
        assert np.max(np.abs(u - exact)) / scale < 0.02, (name, tau)
    assert len(sim.escaped) == 0


def test_free_slip_walls_give_a_plug_not_a_parabola():
    """With free slip there is no wall shear: the body force accelerates the whole channel alike."""
    sim = build("poiseuille", boundary="adami", dx=L / 10, free_slip=True)
    sim.run(0.1, progress=False)
    u = sim.fluid.particles["v"][:, 0]
    # a uniform translation to round-off: measured spread 7.2e-8 of u and mean off by 2.6e-8
    assert u.min() > (1.0 - 1e-6) * u.max()
    assert u.mean() == pytest.approx(2e-4 * sim.time, rel=1e-6)


def test_taylor_green_runs_without_walls_and_decays_at_first_as_exact():
    sim = build("taylor-green", n=20)
    assert sim.walls == []
    res = sim.run(0.1, progress=False)
    exact = 0.25 * math.exp(2 * (-8 * math.pi ** 2 / 100) * res.times[-1])
    assert res["kinetic_energy"][-1] == pytest.approx(exact, rel=0.02)   # measured +0.09 % (lind2012 shifting)
    assert res.summary["escaped_particles"] == 0
    assert res["mass"][-1] == pytest.approx(res["mass"][0], rel=1e-12)


def test_taylor_green_keeps_its_decay_with_shifting_and_loses_it_without():
    shifted = build("taylor-green", n=32).run(0.5, progress=False)
    exact = 0.25 * math.exp(2 * (-8 * math.pi ** 2 / 100) * shifted.times[-1])
    assert shifted["kinetic_energy"][-1] == pytest.approx(exact, rel=0.015)   # measured +0.59 % (default lind2012)
    plain = build("taylor-green", n=32, shifting="none").run(0.5, progress=False)
    assert plain["kinetic_energy"][-1] < 0.5 * exact                           # measured -84 %


def test_elliptical_drop_semi_axes_early():
    """The scheme itself at early times (before the lattice is stretched far), without the case's shifting."""
    sim = build("elliptical-drop", dx=0.1, shifting="none")
    res = sim.run(0.002, progress=False)
    a = elliptical_drop(res.times[-1])[1]
    assert res["moment_semi_axis_x"][-1] == pytest.approx(a, rel=0.02)        # measured +0.63 %
    assert res["moment_semi_axis_y"][-1] == pytest.approx(1 / a, rel=1e-3)    # measured +0.018 %


def test_elliptical_drop_keeps_its_short_axis_with_shifting_and_loses_it_without():
    """At t = 7.6 ms the lattice is stretched 1 : 3.8; without shifting the kernel (h = 1.3 dx) reads it 7 % too
    dense and the patch spreads along x, at any dx (validation/elliptical-drop/lattice_moments.py)."""
    shifted = build("elliptical-drop", dx=0.05).run(0.0076, progress=False)
    a = elliptical_drop(shifted.times[-1])[1]
    assert shifted["moment_semi_axis_x"][-1] == pytest.approx(a, rel=0.04)          # measured +2.03 % (sun2017)
    assert shifted["moment_semi_axis_y"][-1] == pytest.approx(1 / a, rel=0.01)      # measured -0.49 %
    plain = build("elliptical-drop", dx=0.05, shifting="none").run(0.0076, progress=False)
    assert plain["moment_semi_axis_x"][-1] > 1.05 * a                                # measured +7.44 %


def test_validate_one_entry_updates_only_its_rows(tmp_path, capsys):
    results = tmp_path / "results"
    doc = tmp_path / "validation.md"
    assert main(["validate", "poiseuille", "--quick", "--results", str(results), "--doc", str(doc)]) == 0
    out = capsys.readouterr().out
    assert "expected about" in out
    stored = json.loads((results / "poiseuille.json").read_text())
    assert stored["command"] == "seawall validate poiseuille --quick"
    assert stored["rows"] and all(set(r) >= {"quantity", "reference", "value", "error", "tolerance", "pass"}
                                  for r in stored["rows"])
    # a second entry is added to the same table; the first one's rows stay
    assert main(["validate", "elliptical-drop", "--quick", "--results", str(results), "--doc", str(doc)]) == 0
    md = doc.read_text()
    assert "| [poiseuille](#poiseuille) | poiseuille |" in md and "| [elliptical-drop](#elliptical-drop) |" in md
    assert "| hydrostatic | | | | | | | | not run |" in md
    assert (tmp_path / "img" / "validation_poiseuille.png").exists()
    assert main(["validate", "nonsense", "--quick", "--results", str(results), "--doc", str(doc)]) == 2
    assert "nonsense" in capsys.readouterr().err
