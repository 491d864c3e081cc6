"""Removal guards (seawall.health): wall crossings, the walls' hull, the damage budget, records and restart."""

import json

import h5py
import numpy as np
import pytest

import seawall as sw
from seawall.cases import build
from seawall.cli import _write_escaped, main
from seawall.errors import InstabilityError, ParameterError
from seawall.health import KEEP, WALL


def small_tank(**kwargs):
    # 10 x 4 particles (dx = 0.05) in a 0.5 m tank with 0.3 m walls, 3 layers each
    return build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3, initial="rest", **kwargs)


def tank_250():
    # 25 x 10 particles
    return build("hydrostatic", dx=0.02, length=0.5, depth=0.2, height=0.3)


def reasons_of(sim):
    return {int(rec[1]): rec[-1] for rec in sim.escaped}


def test_wall_depth_threshold_is_one_kernel_support():
    sim = small_tank()
    support = sim.kernel.support(sim.h)          # 0.13 m
    fp = sim.fluid.particles
    fp["x"][0] = (-0.05, 0.1)                    # 1 dx behind the left wall surface: kept
    fp["x"][1] = (-(support + 0.005), 0.1)       # deeper than the support: a wall crossing
    codes = sim._guard_codes()
    assert codes[0] == KEEP and codes[1] == WALL
    assert np.count_nonzero(codes != KEEP) == 1


def test_particle_inside_a_wall_is_removed_and_the_run_completes():
    sim = small_tank()
    sim.unstable_fraction = 0.05                 # 40 particles: two removals are within the budget
    sim.run(0.01, progress=False)
    fp = sim.fluid.particles
    victim = int(fp["id"][5])
    fp["x"][5] = (-0.14, 0.1)                    # inside the left wall, past the support (0.13 m)
    n = fp.n
    result = sim.run(0.03, progress=False)
    assert sim.time == pytest.approx(0.03)
    assert sim.fluid.n == n - 1
    assert reasons_of(sim) == {victim: "wall"}
    assert result.summary["escaped_by_reason"] == {"domain": 0, "wall": 1, "unstable": 0, "overtopped": 0}
    assert result.summary["escaped_particles"] == 1
    assert abs(result.summary["mass_drift"]) < 1e-12


def test_particle_over_the_side_wall_is_overtopped_once_outside_the_hull():
    sim = small_tank()
    fp = sim.fluid.particles
    lo, hi = sim.hull_box()
    wall_x = sim.walls[0].x
    # an open tank's walls have a back face: the hull ends at its particles' centres (seawall.health)
    assert hi[0] == pytest.approx(wall_x[:, 0].max()) and lo[0] == pytest.approx(wall_x[:, 0].min())
    assert hi[1] == np.inf and lo[1] == pytest.approx(wall_x[:, 1].min() - 0.025)
    over, splash = int(fp["id"][10]), int(fp["id"][25])
    fp["x"][10] = (0.45, 0.40)                   # above the right wall (0.3 m high), thrown over it
    fp["v"][10] = (3.0, 1.0)
    fp["x"][25] = (0.25, 0.36)                   # above the middle of the tank, thrown up: falls back in
    fp["v"][25] = (0.0, 1.5)
    result = sim.run(0.3, progress=False)
    assert reasons_of(sim) == {over: "overtopped"}
    rec = sim.escaped[0]
    # removed just outside the wall's outer layer, far from the domain's edge
    assert hi[0] <= rec[2] < hi[0] + 0.05 and rec[3] > 0.3
    assert rec[2] < sim.grid.hi[0] - 0.1
    assert result.summary["escaped_where"]["by_side"] == {"x+": 1}
    assert result.summary["escaped_by_reason"] == {"domain": 0, "wall": 0, "unstable": 0, "overtopped": 1}
    # what left is the removed mass of its reason: the start mass is accounted for
    assert result.summary["escaped_mass_by_reason"]["overtopped"] == pytest.approx(float(fp["m"][10]))
    assert result.summary["hull"]["hi"][1] is None
    assert splash in set(sim.fluid.particles["id"].tolist())


def test_damage_beyond_the_fraction_stops_the_run_with_step_time_and_particle():
    sim = tank_250()
    sim.unstable_fraction = 0.01                 # 2.5 particles of 250
    sim.run(0.01, progress=False)
    fp = sim.fluid.particles
    fp["rho"][[3, 4]] = 5000.0                   # two bad particles: removed, the run goes on
    sim.run(0.02, progress=False)
    assert sorted(set(reasons_of(sim).values())) == ["unstable"] and len(sim.escaped) == 2
    fp = sim.fluid.particles
    first = int(fp["id"][10])
    fp["v"][10:14, 0] = np.nan                   # four more within the window: 6 > 2.5
    with pytest.raises(InstabilityError) as info:
        sim.run(0.03, progress=False)
    err = info.value
    assert err.particle_id == first and err.step == sim.step and err.time == pytest.approx(sim.time)
    assert f"particle id {first}" in str(err) and f"step {sim.step}" in str(err)
    assert "unstable_fraction" in str(err)


def test_damage_older_than_the_window_does_not_count():
    sim = tank_250()
    sim.unstable_fraction = 0.01
    sim.unstable_window = 0.01
    sim.run(0.005, progress=False)
    sim.fluid.particles["rho"][[3, 4]] = 5000.0
    sim.run(0.02, progress=False)                # removed at 0.005 s, out of the window by 0.015 s
    sim.fluid.particles["rho"][[5, 6]] = 5000.0
    sim.run(0.03, progress=False)
    assert len(sim.escaped) == 4


@pytest.mark.parametrize("kwargs,match", [
    ({"unstable_fraction": 0.0}, "unstable_fraction"), ({"unstable_fraction": 1.0}, "unstable_fraction"),
    ({"unstable_fraction": "lots"}, "unstable_fraction"), ({"unstable_window": 0.0}, "unstable_window"),
    ({"wall_removal_depth": -1.0}, "wall_removal_depth"), ({"wall_removal_depth": "deep"}, "wall_removal_depth"),
    ({"hull": "tank"}, "hull"), ({"hull": ((0, 0), (1,))}, "hull"),
    ({"hull": ((0.2, 0.0), (1.0, None))}, "hull"),   # the fluid starts outside it
])
def test_bad_guard_parameters(kwargs, match):
    fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.1, 0.1), 0.01), eos=sw.Tait(c0=10.0))
    walls = sw.WallSystem(sw.shapes.tank((0, 0), (0.3, 0.2), 0.01))
    with pytest.raises(ParameterError, match=match) as info:
        sw.Simulation([fluid, walls], h=0.013, gravity=(0, -9.81), **kwargs)
    assert "\n" not in str(info.value)


def test_no_hull_without_gravity_and_along_periodic_axes():
    fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.1, 0.1), 0.01), eos=sw.Tait(c0=10.0))
    walls = sw.WallSystem(sw.shapes.tank((0, 0), (0.3, 0.2), 0.01))
    assert sw.Simulation([fluid, walls], h=0.013).hull_box() is None
    poiseuille = build("poiseuille")
    lo, hi = poiseuille.hull_box()
    assert lo[0] == -np.inf and hi[0] == np.inf and np.isfinite(lo[1]) and np.isfinite(hi[1])


def test_restart_is_bit_exact_with_escaped_records(tmp_path):
    def prepared():
        sim = small_tank()
        sim.unstable_fraction = 0.05
        fp = sim.fluid.particles
        fp["x"][5] = (-0.14, 0.1)                # wall, at the start
        fp["x"][10] = (0.6, 0.40)                # overtopped, over the right wall at ~0.07 s
        fp["v"][10] = (3.0, 1.0)
        return sim

    reference = prepared()
    reference.add(sw.output.Checkpoint(str(tmp_path), every=0.1), every=0.01)
    reference.run(0.15, progress=False)
    assert sorted(r[-1] for r in reference.escaped) == ["overtopped", "wall"]
    second = prepared()
    second.add(every=0.01)
    second.restart(str(tmp_path / "checkpoint.h5"))
    assert 0.1 <= second.time < 0.11 and len(second.escaped) == 2
    second.run(0.15, progress=False)
    assert second.escaped == reference.escaped
    assert second.escaped_mass_by_reason == reference.escaped_mass_by_reason
    for name in ("x", "v", "rho", "id"):
        assert np.array_equal(second.fluid.particles[name], reference.fluid.particles[name]), name


def test_checkpoints_without_reasons_still_load(tmp_path):
    sim = small_tank()
    sim.fluid.particles["x"][10] = (0.25, -0.3)  # outside the hull, under the floor: removed at the start
    sim.run_steps(1)
    path = tmp_path / "old.h5"
    sim.save_checkpoint(str(path))
    with h5py.File(path, "r+") as f:             # the format before the reasons: time, id, x, y
        old = f["escaped/records"][:, :4]
        del f["escaped/records"]
        f["escaped"].create_dataset("records", data=old)
    again = small_tank()
    again.restart(str(path))
    assert [r[-1] for r in again.escaped] == ["domain"] and again.escaped[0][:4] == sim.escaped[0][:4]


def test_escaped_csv_has_a_reason_column(tmp_path):
    sim = small_tank()
    sim.unstable_fraction = 0.05
    fp = sim.fluid.particles
    fp["x"][5] = (-0.14, 0.1)
    fp["x"][10] = (0.9, 0.40)                    # beyond the right wall, above its crest (0.3 m)
    fp["x"][12] = (0.25, -0.3)                   # under the floor: through it, not over a wall
    sim.run_steps(1)
    path = tmp_path / "escaped.csv"
    _write_escaped(str(path), sim)
    lines = path.read_text().splitlines()
    assert lines[0] == "time,id,x,y,side,reason"
    rows = sorted(line.split(",")[-2:] for line in lines[1:])
    assert rows == [["inside", "wall"], ["x+", "overtopped"], ["y-", "domain"]]


def test_summary_counts_escapes_by_reason(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(["run", "hydrostatic", "--dx", "0.05", "--t-end", "0.01", "--out", str(out), "--no-progress",
                 "--no-vtk", "--set", "length=0.5", "--set", "depth=0.2", "--set", "height=0.3"])
    capsys.readouterr()
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["escaped_by_reason"] == {"domain": 0, "wall": 0, "unstable": 0, "overtopped": 0}
    assert summary["escaped_particles"] == 0
    assert (out / "escaped.csv").read_text().splitlines() == ["time,id,x,y,side,reason"]


def test_dam_break_tank_height_and_lid():
    H = 0.3
    default = build("dam-break", dx=0.03)                      # the experiment's 2 H, closed by a lid
    y = default.walls[0].x[:, 1]
    assert y.max() == pytest.approx(2 * H + 2.5 * 0.03)        # 3 lid layers above 2 H
    open_tank = build("dam-break", dx=0.03, lid=False)
    assert open_tank.walls[0].x[:, 1].max() == pytest.approx(2 * H - 0.015)
    tall = build("dam-break", dx=0.03, tank_height=4.0, lid=False)
    assert tall.walls[0].x[:, 1].max() == pytest.approx(4 * H - 0.015)
    with pytest.raises(ParameterError, match="tank_height"):
        build("dam-break", dx=0.03, tank_height=0.9)


@pytest.mark.parametrize("case,kwargs", [
    ("hydrostatic", dict(dx=0.02, length=0.5, depth=0.2, height=0.3)),
    ("dam-break-3d", dict(dx=0.05, lid=False)),
])
def test_cells_skipped_by_the_wall_guard_hold_no_deep_point(case, kwargs):
    # the guard searches only the cells where cells_maybe_deep allows a point deeper than the support;
    # points scattered over the walls and the tank must never be deeper than that elsewhere
    from seawall.diagnostics import signed_wall_distance
    from seawall.health import cells_maybe_deep

    sim = build(case, **kwargs)
    g = sim.grid
    depth = sim.kernel.support(sim.h)
    rng = np.random.default_rng(7)
    for wall in sim.walls:
        pa = wall.particles
        lo = pa["x"].min(axis=0) - 0.5 * sim.fluid.spacing
        hi = pa["x"].max(axis=0) + 0.5 * sim.fluid.spacing
        points = rng.uniform(lo, hi, size=(40_000, sim.dim))
        s = np.empty(points.shape[0])
        reach = wall.cells.reach_mask(g)
        signed_wall_distance(points, pa["x"], pa["normal"], pa["surface"], wall.cells.start, wall.cells.order, reach,
                             g.lo, g.inv_cell, g.ncell, sim.physics.support2, wall.spacing, s)
        deep_cells = cells_maybe_deep(pa["x"], pa["normal"], pa["surface"], wall.cells.cell, g.lo, g.cell_size,
                                      g.ncell, depth)
        p3 = np.zeros((points.shape[0], 3))
        p3[:, :sim.dim] = points
        c = np.minimum(np.maximum(((p3 - g.lo) * g.inv_cell).astype(np.int64), 0), g.ncell - 1)
        flat = c[:, 0] + g.ncell[0] * (c[:, 1] + g.ncell[1] * c[:, 2])
        deep = s < -depth
        assert deep.sum() > 100                           # the scatter does reach behind the walls
        assert np.all(deep_cells[flat[deep]] == 1)
        # and it is a filter: the points near a wall but not deep in it are mostly in skipped cells
        near = np.isfinite(s) & (s > 0.0)
        assert np.mean(deep_cells[flat[near]] == 0) > 0.5


def test_wall_guard_codes_equal_those_of_the_full_search():
    # particles thrown over the whole tank, walls included: the guard flags exactly those the
    # signed distance (searched for every particle) puts deeper than the support
    from seawall.diagnostics import signed_wall_distance

    sim = tank_250()
    g = sim.grid
    fp = sim.fluid.particles
    wall = sim.walls[0]
    pa = wall.particles
    rng = np.random.default_rng(3)
    lo = pa["x"].min(axis=0) - 0.5 * sim.fluid.spacing   # the walls' outer faces
    # half over the left wall and the water beside it, half over the floor and the water above it
    # (below the walls' top); the walls are 0.06 m thick, the support 0.052 m
    half = fp.n // 2
    fp["x"][:half] = rng.uniform(lo, (lo[0] + 0.12, 0.25), size=(half, 2))
    fp["x"][half:] = rng.uniform(lo, (pa["x"][:, 0].max(), lo[1] + 0.12), size=(fp.n - half, 2))
    depth = sim.kernel.support(sim.h)
    codes = np.zeros(fp.n, dtype=np.int8)
    from seawall.health import wall_depth_codes, walls_top
    wall_depth_codes(sim, depth, codes, walls_top(sim.walls, sim.gravity, sim.fluid.spacing))
    s = np.empty(fp.n)
    signed_wall_distance(fp["x"], pa["x"], pa["normal"], pa["surface"], wall.cells.start, wall.cells.order,
                         wall.cells.reach_mask(g), g.lo, g.inv_cell, g.ncell, sim.physics.support2, wall.spacing, s)
    assert np.count_nonzero(s < -depth) > 5
    assert np.array_equal(codes == WALL, s < -depth)


def test_an_open_tanks_crest_and_back_are_surfaces_and_its_wall_still_catches_a_leak():
    # the small tank: dx 0.05, 3 layers, open walls 0.3 m high and 6 layers (0.3 m) thick
    from seawall.health import DOMAIN, OVERTOPPED

    sim = small_tank()
    support = sim.kernel.support(sim.h)          # 0.13 m
    fp = sim.fluid.particles
    fp["x"][0] = (-0.15, 0.3 - 0.02)             # landed on the crest, 0.4 dx into it: kept
    fp["x"][1] = (-0.3 + 0.04, 0.1)              # 0.8 dx into the back face, half way down: kept
    fp["x"][2] = (-(support + 0.005), 0.1)       # through the inner face, deeper than the support: a leak
    fp["x"][3] = (-0.3 + 0.02, 0.1)              # past the back face's particles, half way down: down the back
    fp["x"][4] = (0.25, -0.16)                   # out under the floor (0.15 m thick): domain
    codes = sim._guard_codes()
    assert codes[0] == KEEP and codes[1] == KEEP
    assert codes[2] == WALL
    assert codes[3] == OVERTOPPED and codes[4] == DOMAIN
