"""The discharge probe: the crossing count, its checkpoint, the crest section and the check from frames."""

from types import SimpleNamespace

import numpy as np
import pytest

import seawall as sw
from seawall import shapes
from seawall.cases import DAM_BREAK
from seawall.errors import ParameterError
from seawall.particles import ParticleArrays
from seawall.probes import Discharge, DischargeRate, probe_unit

# the dam break of the real-run tests: H = 0.3 m at dx = 0.02 m (450 fluid particles), an open tank
# 1.2 H high; the middle section stands at x = 0.8 m, half way along the 1.6 m tank
SECTION_X = 0.8


def fake_sim(x, m, rho0=1000.0):
    """The little of a simulation the probe reads: the fluid's arrays, rho0, the dimension."""
    x = np.asarray(x, dtype=np.float64)
    pa = ParticleArrays(x.shape[1])
    pa.add("x", x)
    pa.add("m", np.asarray(m, dtype=np.float64))
    pa.add("id", np.arange(len(m)))
    return SimpleNamespace(fluid=SimpleNamespace(particles=pa, rho0=rho0), dim=x.shape[1], walls=[])


def step(probe, sim, move):
    """One step by hand: the probe sees the positions before and after ``move`` changes them."""
    probe.before_step(sim)
    move(sim.fluid.particles)
    probe.after_step(sim)


def test_crossings_by_hand_with_reordering_and_removal():
    # masses are powers of two (volumes m / rho0 with rho0 = 1): every sum below is exact
    m = np.array([1.0, 2.0, 4.0, 8.0, 16.0, 32.0])
    x = np.array([[-0.5, 0.5], [-0.5, 0.2], [0.5, 0.5], [-0.5, 1.5], [-0.2, 0.9], [-0.1, 0.0]])
    sim = fake_sim(x, m, rho0=1.0)
    # a vertical section x = 0, 0 <= y <= 1, drawn bottom to top: flow in +x is positive
    probe = Discharge("q", (0.0, 0.0), (0.0, 1.0))
    probe.attach(sim)
    assert probe.sample(sim) == 0.0

    def first(pa):
        pa["x"][0, 0] = 0.5     # crosses within the span: +1
        pa["x"][1, 0] = 0.3     # +2
        pa["x"][2, 0] = -0.5    # crosses back: -4
        pa["x"][3, 0] = 0.5     # crosses the line above the segment (y = 1.5): not counted
        pa["x"][4] = (0.4, 1.05)  # ends above the span, but meets the line at y = 0.9 + 0.15 / 3 < 1: +16
    step(probe, sim, first)
    assert probe.sample(sim) == 1 + 2 - 4 + 16

    # reorder and remove between steps, as the run loop does: nothing is counted for that
    sim.fluid.particles.permute(np.array([5, 4, 3, 2, 1, 0]))
    sim.fluid.particles.keep(sim.fluid.particles["id"] != 1)
    assert probe.sample(sim) == 15

    def second(pa):
        ids = pa["id"]
        pa["x"][ids == 0, 0] = -0.5   # back across: -1
        pa["x"][ids == 5, 0] = 0.0    # onto the line: the line itself is the negative side, not counted
        pa["x"][ids == 2, 0] = 0.25   # +4 again
    step(probe, sim, second)
    assert probe.sample(sim) == 15 - 1 + 4

    def third(pa):
        pa["x"][pa["id"] == 5, 0] = 1e-300   # off the line to the positive side: +32
    step(probe, sim, third)
    assert probe.sample(sim) == 18 + 32

    # drawn top to bottom, the same section counts flow in -x as positive
    reverse = Discharge("r", (0.0, 1.0), (0.0, 0.0))
    sim2 = fake_sim([[0.5, 0.5]], [3.0], rho0=2.0)
    reverse.attach(sim2)
    step(reverse, sim2, lambda pa: pa["x"].__setitem__((0, 0), -0.5))
    assert reverse.sample(sim2) == 1.5


def test_state_rate_and_units():
    probe = Discharge("q", (0.0, 0.0), (0.0, 1.0))
    rate = probe.companions()[0]
    assert isinstance(rate, DischargeRate) and rate.name == "q_rate"
    assert (probe_unit(probe, 2), probe_unit(rate, 2)) == ("m^2", "m^2/s")
    assert (probe_unit(probe, 3), probe_unit(rate, 3)) == ("m^3", "m^3/s")
    probe.mass = 0.1 + 0.2
    other = Discharge("q", (0.0, 0.0), (0.0, 1.0))
    other.set_state(probe.state())
    assert other.mass == probe.mass


@pytest.mark.parametrize("kwargs, match", [
    ({"start": (0, 0), "end": (0, 0)}, "same point"),
    ({"start": (0, 0, 0), "end": (0, 1, 0)}, "share exactly one coordinate"),
    ({"start": (0, 0, 0), "end": (1, 1, 1)}, "share exactly one coordinate"),
    ({"start": (0, 0, 0), "end": (0, 1)}, "same number of coordinates"),
    ({"start": (0, "a"), "end": (0, 1)}, "start must be 2 .* or 3"),
    ({"start": (0, 0), "end": (np.nan, 1)}, "end must be 2 .* or 3"),
    ({"start": (0, 0)}, "needs start and end"),
    ({"crest": "tank", "direction": 2}, "direction must be 1 or -1"),
    ({"crest": "tank", "start": (0, 0)}, "not both"),
])
def test_bad_sections_name_the_key(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        Discharge("q", **kwargs)


def free_jet():
    """A 10 x 10 block flying at 3 m/s in +x out of a small domain (no walls): reordered and removed as it goes."""
    fluid = sw.FluidSystem(shapes.rectangle((0, 0), (0.1, 0.1), 0.01), eos=sw.Tait(c0=10.0), velocity=(3.0, 0.0))
    return sw.Simulation([fluid], h=0.013, domain=((-0.05, -0.05), (0.3, 0.2)), reorder_every=3)


def test_free_jet_passes_a_section_before_it_is_removed():
    sim = free_jet()
    # x = 0.25 across the whole domain height: every particle crosses it, then leaves at x = 0.3
    sim.add(Discharge("q", (0.25, -0.05), (0.25, 0.2)), every=0.01)
    result = sim.run(0.15, progress=False)
    assert sim.fluid.n == 0 and len(result.escaped) == 100
    # all of it, 100 particles of volume m / rho0 = dx^2: the sum of 100 equal terms, to round-off
    assert result["q"][-1] == pytest.approx(0.1 * 0.1, rel=1e-13)
    assert result["q"][0] == 0.0 and np.isnan(result["q_rate"][0])
    # the rate is the difference of the cumulative samples over the interval
    rate = np.diff(result["q"]) / np.diff(result.times)
    assert np.array_equal(result["q_rate"][1:], rate)


def test_crest_section_of_an_open_tank():
    sim = DAM_BREAK.build(dx=0.02, lid=False, tank_height=1.2)
    probe = Discharge.over_crest("over", "tank")
    sim.add(probe)
    x = sim.walls[0].particles["x"]
    top = x[:, 1].max()
    row = x[(x[:, 1] == top) & (x[:, 0] > 1.0), 0]
    # the right side's top row (six layers: an open tank's walls are twice as thick), the section at its
    # middle, from the top up to the domain top
    assert probe.start[1] == top and probe.end[1] == sim.grid.hi[1]
    assert row.size == 6
    assert probe.start[0] == pytest.approx(0.5 * (row.min() + row.max())) and probe.end[0] == probe.start[0]
    left = Discharge.over_crest("back", "tank", direction=-1)
    sim.add(left)
    assert left.start[0] < 0 and left.start[1] == sim.grid.hi[1] and left.end[1] == top
    with pytest.raises(ParameterError, match="no wall named 'nope'"):
        sim.add(Discharge.over_crest("bad", "nope"))
    assert sim.summary(wall_time=0, loop_time=0, particle_steps=0, steps=0,
                       startup=0)["discharge_sections"]["over"]["crest"] == "tank"
    # the count is not decomposed: a run under mpiexec refuses it in one line
    from seawall.parallel.distributed import refusal

    assert refusal(sim) == ("MPI: probe over, over_rate, back, back_rate has no reduction over ranks; "
                            "run it in one process")


def dam_break():
    sim = DAM_BREAK.build(dx=0.02, lid=False, tank_height=1.2)
    sim.add(Discharge("mid", (SECTION_X, -1.0), (SECTION_X, 10.0)), every=0.02)
    return sim


def volume_beyond(sim):
    fp = sim.fluid.particles
    return fp["m"][fp["x"][:, 0] > SECTION_X].sum() / sim.fluid.rho0


def test_dam_break_discharge_is_the_volume_moved_beyond_the_section(tmp_path):
    from seawall.cli import _write_escaped
    from seawall.postprocess import discharge_series

    sim = dam_break()
    before = volume_beyond(sim)
    sim.add(sw.output.VTK(str(tmp_path), every=0.05))
    result = sim.run(0.3, progress=False)
    total = sim.fluid.initial_mass / sim.fluid.rho0
    assert before == 0.0 and not result.escaped
    # the front has passed the middle: a good part of the column is beyond it
    assert result["mid"][-1] > 0.05 * total
    # the count and the volume now beyond are sums of the same ~50 volumes dx^2 in other orders and
    # groupings: they differ by round-off, 7e-18 m^2 measured; 1e-13 of the fluid volume leaves room for
    # any summation order while a single particle (4e-4 m^2) counted wrong would fail by far
    assert result["mid"][-1] == pytest.approx(volume_beyond(sim) - before, abs=1e-13 * total)

    # the check from the stored frames agrees at every frame (frames and probes are both every 0.05 / 0.02 s)
    _write_escaped(str(tmp_path / "escaped.csv"), sim)
    times, columns = discharge_series(str(tmp_path), (SECTION_X, 0.0), (SECTION_X, 1.0))
    assert times.size == 7 and columns["volume"][0] == 0.0
    common = np.isin(result.times, times)
    assert common.sum() >= 4
    assert np.allclose(columns["volume"][np.isin(times, result.times)], result["mid"][common],
                       rtol=0, atol=1e-13 * total)


def test_restart_continues_the_count_bit_for_bit(tmp_path):
    reference = dam_break()
    reference.add(sw.output.Checkpoint(str(tmp_path), every=0.18))
    ref = reference.run(0.26, progress=False)
    assert ref["mid"][-1] > 0

    second = dam_break()
    second.restart(str(tmp_path / "checkpoint.h5"))
    assert 0.18 <= second.time < 0.19 and [p for p in second.probes if p.name == "mid"][0].mass > 0
    result = second.run(0.26, progress=False)
    assert np.array_equal(result.times, ref.times)
    for name in ("mid", "mid_rate"):
        assert np.array_equal(result[name], ref[name], equal_nan=True), name



# ---------------------------------------------------------------------------- command line and case files
def run_cli(args, capsys):
    from seawall.cli import main

    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


SMALL_TANK = ["--dx", "0.05", "--set", "length=0.5", "--set", "depth=0.2", "--set", "height=0.3"]


def test_cli_discharge_columns_units_and_the_check_from_frames(tmp_path, capsys):
    import json

    from seawall.io.csvout import read_probes_csv

    out_dir = tmp_path / "run"
    code, _, _ = run_cli(["run", "hydrostatic", *SMALL_TANK, "--t-end", "0.02", "--out", str(out_dir),
                          "--no-progress", "--discharge", "0.25,-1:0.25,1", "--discharge", "0.1,0:0.1,0.3:mine"],
                         capsys)
    assert code == 0
    t, cols = read_probes_csv(str(out_dir / "probes.csv"))
    assert {"discharge:1", "discharge:1_rate", "mine", "mine_rate"} <= set(cols)
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["probe_units"]["discharge:1"] == "m^2" and summary["probe_units"]["mine_rate"] == "m^2/s"
    assert summary["discharge_sections"]["mine"]["start"] == [0.1, 0.0]
    code, out, _ = run_cli(["discharge", str(out_dir), "--section", "0.25,-1:0.25,1"], capsys)
    assert code == 0 and (out_dir / "discharge.csv").exists()
    header = (out_dir / "discharge.csv").read_text().splitlines()[0]
    assert header == "time,volume,fluid_beyond,removed_beyond"


@pytest.mark.parametrize("args, word", [
    (["run", "hydrostatic", "--discharge", "0.1,0"], "--discharge must look like x0,y0:x1,y1[:NAME]"),
    (["run", "hydrostatic", "--discharge", "0.1,0:0.1"], "start and end need 2 finite coordinates"),
    (["run", "hydrostatic", "--discharge", "0.1,0:a,1"], "--discharge must look like"),
    (["run", "hydrostatic", "--discharge", "0.1,0:0.1,1:a:b"], "--discharge must look like"),
    (["run", "hydrostatic", "--discharge", "0.1,0:0.1,0"], "--discharge '0.1,0:0.1,0': start and end are the same"),
    (["run", "hydrostatic", "--discharge", "0,0,0:0,1,0"], "--discharge '0,0,0:0,1,0': case 'hydrostatic' is 2D"),
    (["run", "hydrostatic", "--discharge", "0,0,0:0,1"], "--discharge '0,0,0:0,1': start and end need 2 finite"),
    (["run", "hydrostatic", "--discharge", "0,0:0,nan"], "need 2 finite"),
    (["run", "hydrostatic", "--discharge", "0,0:0,1:"], "NAME must be non-empty"),
    (["run", "hydrostatic", "--discharge", "0,0:0,1:P0"], "--discharge: two probes are named 'P0'"),
    (["discharge", "RUN", "--section", "0,0"], "--section must look like x0,y0:x1,y1,"),
    (["discharge", "RUN", "--section", "0,0:0,1"], "not found"),
])
def test_cli_bad_values_give_one_line_naming_the_option(args, word, tmp_path, capsys):
    args = [str(tmp_path / "none") if a == "RUN" else a for a in args]
    if args[0] == "run":
        args = args[:2] + SMALL_TANK + args[2:] + ["--out", str(tmp_path / "out"), "--no-progress"]
    code, _, err = run_cli(args, capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and word in lines[0], lines
    assert not (tmp_path / "out").exists()


TOML = ('[parameters]\ndx = {default = 0.05, unit = "m"}\nL = 1.0\n[tank]\nlo = [0, 0]\nhi = ["L", 0.5]\n'
        '[[water]]\nlo = [0, 0]\nhi = [0.3, 0.2]\n')


def test_toml_discharge_probes(tmp_path):
    from seawall.cases import case_by_name

    path = tmp_path / "over.toml"
    path.write_text(TOML + '[[probe]]\nkind = "discharge"\nname = "mid"\nstart = ["L / 2", 0]\nend = ["L / 2", 1]\n'
                    '[[probe]]\nkind = "discharge"\ncrest = "tank"\ndirection = -1\n')
    sim = case_by_name(str(path)).build(boundary="adami")
    assert [p.name for p in sim.probes] == ["mid", "mid_rate", "discharge_2", "discharge_2_rate"]
    assert sim.probes[0].start.tolist() == [0.5, 0.0] and sim.probes[0].end.tolist() == [0.5, 1.0]
    crest = sim.probes[2]
    assert crest.crest == "tank" and crest.direction == -1 and crest.start[0] < 0 < crest.start[1] - crest.end[1]


@pytest.mark.parametrize("probe, problem", [
    ('kind = "discharge"\n', "[[probe]] number 1 (discharge) needs start and end (points), or crest"),
    ('kind = "discharge"\nstart = [0.5, 0]\n', "needs start and end"),
    ('kind = "discharge"\nstart = [0.5]\nend = [0.5, 1]\n', "[[probe]] number 1 start must be a list of 2 or 3"),
    ('kind = "discharge"\nstart = [0.5, 0, 0]\nend = [0.5, 1, 0]\n', "[[probe]] number 1 start has 3 coordinates"),
    ('kind = "discharge"\nstart = ["2 * nope", 0]\nend = [0.5, 1]\n', "unknown name 'nope'"),
    ('kind = "discharge"\nstart = [0.5, 0]\nend = ["L / 2", 0]\n', "start and end are the same point"),
    ('kind = "discharge"\nstart = [0.5, 0]\nend = [0.5, 1]\ndirection = -1\n', "direction goes with crest"),
    ('kind = "discharge"\ncrest = "wall"\n', "crest names no wall, got 'wall'"),
    ('kind = "discharge"\ncrest = 3\n', "crest must be a wall's name"),
    ('kind = "discharge"\ncrest = "tank"\nstart = [0.5, 0]\n', "give start and end, or crest, not both"),
    ('kind = "discharge"\ncrest = "tank"\ndirection = 2\n', "direction must be 1 or -1"),
    ('kind = "discharge"\nstart = [0.5, 0]\nend = [0.5, 1]\nthrough = 1\n', "has no key 'through'"),
])
def test_toml_bad_discharge_values_give_one_line_naming_the_key(tmp_path, capsys, probe, problem):
    path = tmp_path / "bad.toml"
    path.write_text(TOML + "[[probe]]\n" + probe)
    code, _, err = run_cli(["run", str(path), "--out", str(tmp_path / "out"), "--no-progress"], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and problem in lines[0], lines
    assert not (tmp_path / "out").exists()


def test_a_rate_column_name_taken_refuses_the_probe_whole():
    sim = free_jet()
    sim.add(sw.probes.TotalMass("q_rate"))
    with pytest.raises(ParameterError, match="two probes are named 'q_rate'"):
        sim.add(Discharge("q", (0.25, -0.05), (0.25, 0.2)))
    assert [p.name for p in sim.probes] == ["q_rate"] and not sim._step_probes


def test_a_3d_rectangle_counts_what_crosses_it_within_its_corners():
    # the plane x = 0.5, 0 <= y <= 1, 0 <= z <= 2: positive along +x
    probe = Discharge("q", (0.5, 0.0, 0.0), (0.5, 1.0, 2.0))
    sim = fake_sim([[0.4, 0.5, 1.0], [0.4, 1.5, 1.0], [0.6, 0.2, 0.1], [0.4, 0.9, 1.9], [0.4, 0.5, -0.1]],
                   [1.0, 2.0, 4.0, 8.0, 16.0], rho0=1.0)

    def move(pa):
        pa["x"][0, 0] = 0.6            # +1 through the rectangle
        pa["x"][1, 0] = 0.6            # beside it (y = 1.5): not counted
        pa["x"][2, 0] = 0.45           # back through it: -4
        pa["x"][3] = (0.6, 1.1, 1.9)   # meets the plane at y = 1.0, on the edge: +8
        pa["x"][4, 0] = 0.6            # below it (z = -0.1): not counted

    step(probe, sim, move)
    assert probe.sample(sim) == pytest.approx(1.0 - 4.0 + 8.0)
    assert probe.describe()["start"] == [0.5, 0.0, 0.0]
    # a 2D section in a 3D run (and the other way round) names the mismatch
    with pytest.raises(ParameterError, match="3 coordinates, the run is 2D"):
        Discharge("r", (0.5, 0.0, 0.0), (0.5, 1.0, 2.0)).attach(fake_sim([[0.0, 0.0]], [1.0], rho0=1.0))


def test_3d_dam_break_discharge_is_the_volume_moved_beyond_the_rectangle():
    # the 3D dam break at dx = 0.05 m: a rectangle across the whole tank in the middle of its length
    sim = sw.cases.build("dam-break-3d", dx=0.05)
    x_mid = 0.8
    lo, hi = sim.grid.lo, sim.grid.hi
    sim.add(Discharge("mid", (x_mid, lo[1] - 1.0, lo[2] - 1.0), (x_mid, hi[1] + 1.0, hi[2] + 1.0)), every=0.02)
    fp = sim.fluid.particles
    assert not np.any(fp["x"][:, 0] > x_mid)
    result = sim.run(0.3, progress=False)
    fp = sim.fluid.particles
    total = sim.fluid.initial_mass / sim.fluid.rho0
    beyond = fp["m"][fp["x"][:, 0] > x_mid].sum() / sim.fluid.rho0
    assert probe_unit(sim.probes[-2], 3) == "m^3" and not result.escaped
    assert result["mid"][-1] > 0.02 * total               # the front has passed the middle
    assert result["mid"][-1] == pytest.approx(beyond, abs=1e-13 * total)
