"""The fluid's kept pair list (seawall.pair_list): complete, in the cell walk's order, rebuilt when it must be."""

import math

import numpy as np
import pytest

import seawall as sw
from seawall.cases import build
from seawall.errors import ParameterError
from seawall.neighbors import CellGrid
from seawall.pair_list import MAX_SKIN, PairList


def brute_pairs(x, radius):
    d = x[:, None, :] - x[None, :, :]
    mask = np.sum(d * d, axis=-1) < radius * radius
    np.fill_diagonal(mask, False)
    return [set(np.flatnonzero(row).tolist()) for row in mask]


def listed(pl, i):
    return pl.index[i * pl.stride:i * pl.stride + pl.counts[i]].tolist()


def random_set(dim, n=500, seed=0):
    rng = np.random.default_rng(seed + dim)
    x = rng.uniform(0.0, 1.0, size=(n, dim))
    # a few particles outside the grid's box: clamped into its edge cells
    x[:5] = rng.uniform(-0.1, 1.1, size=(5, dim))
    return np.ascontiguousarray(x)


SUPPORT = 0.13


def built_list(skin, n=500, dim=3):
    """A random set (:func:`random_set`), its ids and a list of its pairs built with this skin."""
    x = random_set(dim, n=n)
    ids = np.arange(x.shape[0])
    grid = CellGrid(np.zeros(dim), np.ones(dim), SUPPORT)
    pl = PairList(skin, SUPPORT)
    pl.current(grid, grid.build(x), x, ids)
    return x, ids, grid, pl


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("skin", [0.1, MAX_SKIN])
def test_the_list_holds_every_pair_within_support_plus_skin(dim, skin):
    x, _, _, pl = built_list(skin, dim=dim)
    expected = brute_pairs(x, SUPPORT * (1.0 + skin))
    for i in range(x.shape[0]):
        got = listed(pl, i)
        assert len(got) == len(set(got)), i
        assert set(got) == expected[i], i


@pytest.mark.parametrize("dim", [2, 3])
def test_a_particle_with_more_pairs_than_the_room_makes_the_build_walk_again(dim):
    x, ids, grid, pl = built_list(0.1, dim=dim)
    pl.stride = 2                      # far too little room: the build must grow it and walk again
    pl._build(grid, grid.build(x), x, ids)
    assert pl.stride > pl.counts.max() >= 2
    expected = brute_pairs(x, SUPPORT * 1.1)
    assert all(set(listed(pl, i)) == expected[i] for i in range(x.shape[0]))


def test_rebuilt_when_a_particle_moved_half_the_skin_or_the_particles_changed():
    x, ids, grid, pl = built_list(0.2)
    assert pl.builds == 1
    half_skin = 0.5 * 0.2 * SUPPORT
    moved = x.copy()
    moved[7, 1] += 0.99 * half_skin
    assert not pl.stale(moved, ids)
    moved[7, 1] = x[7, 1] + 1.01 * half_skin
    assert pl.stale(moved, ids)
    assert pl.stale(x[::-1].copy(), ids[::-1].copy())          # reordered
    assert pl.stale(x[1:].copy(), ids[1:].copy())              # one removed
    assert not pl.stale(x, ids)
    pl.current(grid, grid.build(moved), moved, ids)
    assert pl.builds == 2 and pl.evaluations == 2


def test_moves_within_half_the_skin_lose_no_pair_within_the_support():
    skin = 0.2
    x, ids, grid, pl = built_list(skin, n=800)
    rng = np.random.default_rng(5)
    step = rng.normal(size=x.shape)
    step *= 0.999 * 0.5 * skin * SUPPORT / np.linalg.norm(step, axis=1)[:, None]
    moved = x + step
    assert not pl.stale(moved, ids)
    now = brute_pairs(moved, SUPPORT)
    for i in range(x.shape[0]):
        assert now[i] <= set(listed(pl, i)), i


def test_a_checkpointed_list_is_rebuilt_exactly():
    x, ids, grid, pl = built_list(0.1)
    again = PairList(0.1, SUPPORT)
    again.set_state(grid, pl.state())
    assert again.stride == pl.stride and again.builds == 0
    assert np.array_equal(again.counts, pl.counts) and np.array_equal(again.index, pl.index)
    assert not again.stale(x, ids)


def dam_break(skin, dx=0.03):
    sim = build("dam-break", dx=dx, boundary="adami")
    sim.set_neighbour_skin(skin)
    return sim


def test_the_fluid_loop_sums_the_same_pairs_in_the_same_order_as_the_cell_walk():
    # right after a build the listed pairs within the support are the walk's, in its order:
    # the rates agree bit for bit
    sim = dam_break(0.1)
    sim.run_steps(40)
    fp = sim.fluid.particles
    saved = {name: fp[name].copy() for name in fp.names()}
    rates = []
    for skin in (0.1, 0.0):
        sim.set_neighbour_skin(skin)     # a fresh list: built at this state
        for name, array in saved.items():
            fp[name] = array.copy()
        sim.evaluate(sim.time)
        if skin:
            assert sim.pair_list.builds == 1 and sim.pair_list.evaluations == 1
        rates.append((fp["dv"].copy(), fp["drho"].copy()))
    assert sim.pair_list is None
    assert np.array_equal(rates[0][0], rates[1][0]) and np.array_equal(rates[0][1], rates[1][1])


def test_a_run_with_the_list_rebuilds_it_and_agrees_with_the_walk():
    walked = dam_break(0.0)
    kept = dam_break(0.1)
    for sim in (walked, kept):
        sim.run(0.15, progress=False)
    pl = kept.pair_list
    assert 1 < pl.builds < pl.evaluations
    # with a list the particles are reordered at its rebuilds, not every 20 steps: compare by id
    a = walked.fluid.particles["x"][np.argsort(walked.fluid.particles["id"])]
    b = kept.fluid.particles["x"][np.argsort(kept.fluid.particles["id"])]
    # the sums differ in the order of a few pairs (particles that changed cell since the build, a
    # different particle order): rounding, not physics
    assert float(np.abs(a - b).max()) < 1e-9 * float(np.abs(a).max())
    summary = kept.summary(wall_time=1.0, loop_time=1.0, particle_steps=1, steps=1, startup=0.0)
    assert summary["pair_list"]["builds"] == pl.builds and summary["pair_list"]["skin"] == 0.1


def test_restart_with_a_kept_list_continues_identically(tmp_path):
    reference = dam_break(0.1)
    reference.add(sw.output.Checkpoint(str(tmp_path), every=0.06), every=0.01)
    reference.run(0.1, progress=False)
    assert reference.pair_list.builds > 2
    second = dam_break(0.1)
    second.restart(str(tmp_path / "checkpoint.h5"))
    assert 0.06 <= second.time < 0.07
    second.run(0.1, progress=False)
    assert second.step == reference.step
    for name in ("x", "v", "rho", "id"):
        assert np.array_equal(second.fluid.particles[name], reference.fluid.particles[name]), name


@pytest.mark.parametrize("skin", [-0.1, MAX_SKIN * 1.01, math.nan, "thin"])
def test_bad_skin_names_the_parameter(skin):
    sim = build("hydrostatic", dx=0.05, length=0.5, depth=0.2, height=0.3, initial="rest")
    with pytest.raises(ParameterError, match="neighbour_skin"):
        sim.set_neighbour_skin(skin)


def test_periodic_domains_walk_the_cells():
    sim = build("poiseuille")
    assert sim.grid.periodic_any and sim.pair_list is None
    sim.set_neighbour_skin(0.2)
    assert sim.pair_list is None
