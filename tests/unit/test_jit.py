"""The serial build the suite runs (seawall.jit) and the threaded build users run compute the same flow."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from seawall import jit
from seawall.jit import LOOPS_VARIABLE, loop_mode


def test_loop_mode_reads_the_environment_and_names_the_variable_when_wrong():
    assert loop_mode({}) == "threaded"
    assert loop_mode({LOOPS_VARIABLE: " Serial "}) == "serial"
    with pytest.raises(ValueError, match=LOOPS_VARIABLE):
        loop_mode({LOOPS_VARIABLE: "gpu"})


def test_the_suite_compiles_its_loops_serially():
    from seawall.fluid.rates import fluid_rates

    assert not jit.THREADED
    assert fluid_rates.targetoptions["parallel"] is False


def _dam_break(out, mode, threads):
    # the threaded run as users start it: with a compile helper (seawall.compile_ahead), whose
    # compiled loops the run loads from the cache
    env = dict(os.environ, **{LOOPS_VARIABLE: mode, "NUMBA_NUM_THREADS": "2",
                              "SEAWALL_COMPILE_AHEAD": "1" if mode == "threaded" else "0"})
    cmd = [sys.executable, "-m", "seawall", "run", "dam-break", "--dx", "0.02", "--t-end", "0.7",
           "--threads", str(threads), "--out", str(out)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    # the outlined loop bodies' "no transformation for parallel execution" is not shown (cold cache)
    assert "no transformation for parallel execution" not in done.stderr
    with open(out / "summary.json") as fh:
        assert json.load(fh)["provenance"]["loops"] == mode
    return np.genfromtxt(out / "probes.csv", delimiter=",", names=True)


def test_threaded_build_on_two_threads_runs_the_serial_builds_dam_break(tmp_path):
    """The default dam break (adami walls) through the impact on the downstream wall (t = 0.7 s,
    wall pressures up to 28 kPa): the builds' machine code differs (reductions over threads,
    vectorisation), so the series agree to round-off grown by the flow, not bitwise. Measured:
    3.5e-10 of the largest wall pressure, 3.0e-12 of the kinetic energy; a serial run whose
    initial positions move by one ulp differs by 1e-10 (docs/parallel.md). A race or a build
    defect moves the pressures by whole percents."""
    serial = _dam_break(tmp_path / "serial", "serial", 1)
    threaded = _dam_break(tmp_path / "threaded", "threaded", 2)
    assert serial.shape == threaded.shape
    for name in serial.dtype.names:
        scale = max(1.0, float(np.max(np.abs(serial[name]))))
        assert np.max(np.abs(serial[name] - threaded[name])) <= 1e-8 * scale, name


def test_the_threaded_build_asks_numba_for_prange_loops_only():
    """Each threaded loop keeps its options through every specialisation (a dict would be emptied
    by Numba at the first compile, turning the array-expression conversions back on)."""
    assert jit.parallel_options(threaded=False) is False
    options = jit.parallel_options(threaded=True)
    if options is True:
        pytest.skip("this Numba has no ParallelOptions")
    from numba import njit, prange

    @njit(parallel=options)
    def add_one(a):
        for i in prange(a.shape[0]):
            a[i] += 1.0

    add_one(np.zeros(3))
    add_one(np.zeros(3, dtype=np.float32))
    assert len(add_one.signatures) == 2
    kept = add_one.targetoptions["parallel"]._get_values()
    assert kept["prange"] and kept["enabled"]
    assert not any(kept[k] for k in ("numpy", "setitem", "comprehension", "inplace_binop", "stencil", "fusion"))


def test_a_switch_read_from_its_tag_is_a_literal_whose_dead_branch_is_never_typed():
    """The branch a tag rules out is pruned before typing (so before the parallel passes copy the loop):
    had it survived to typing, the attribute no array has would fail the compile."""
    from numba import njit

    from seawall.fluid.rates import tag_value
    from seawall.neighbors import layout_tag, tag_dim, tag_periodic

    @njit
    def value_or_untypable(tag):
        if tag_value(tag) == 2:
            return 2.0
        return tag.no_such_attribute

    @njit
    def dim_or_untypable(layout):
        if tag_dim(layout) == 3 and not tag_periodic(layout):
            return 3.0
        return layout.no_such_attribute

    assert value_or_untypable(np.empty((0, 0, 0))) == 2.0
    assert dim_or_untypable(layout_tag(3, False)) == 3.0


def test_switch_values_read_from_tags_in_compiled_and_plain_code():
    from numba import njit

    from seawall.fluid.rates import tag_value
    from seawall.neighbors import layout_tag, tag_dim, tag_periodic

    @njit
    def read(layout, tag):
        return tag_dim(layout), tag_periodic(layout), tag_value(tag)

    for dim in (2, 3):
        for periodic in (False, True):
            for value in (0, 1, 4):
                assert read(layout_tag(dim, periodic), np.empty((0,) * (value + 1))) == (dim, periodic, value)


def test_a_run_that_asks_for_no_thread_count_gets_one_per_4000_particles():
    """Small runs step faster on one thread (every parallel loop wakes the others); the count is
    chosen by the problem's size unless the Simulation, a case file or NUMBA_NUM_THREADS gives it."""
    assert jit.threads_for(3162, available=2) == 1
    assert jit.threads_for(7999, available=2) == 1
    assert jit.threads_for(14598, available=2) == 2
    assert jit.threads_for(400_000, available=2) == 2
    assert jit.threads_for(0, available=8) == 1
    script = (
        "import json\n"
        "from seawall.cases import build\n"
        "from seawall.jit import thread_count, threads_for\n"
        "counts = []\n"
        "for dx in (0.05, 0.004):\n"
        "    sim = build('dam-break', dx=dx)\n"
        "    counts.append([thread_count(), threads_for(sim.particles_per_step())])\n"
        "sim = build('dam-break', dx=0.05, threads=1)\n"
        "counts.append([thread_count(), 1])\n"
        "print(json.dumps(counts))\n")
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_NUM_THREADS"}
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    counts = json.loads(done.stdout.strip().splitlines()[-1])
    assert all(got == want for got, want in counts)
    assert counts[0][0] == 1 and counts[1][0] == min(2, jit.threads_for(14598))   # 3.2k and 14.6k particles
    env["NUMBA_NUM_THREADS"] = "1"      # the user's choice wins: no count is set
    done = subprocess.run([sys.executable, "-c", "from seawall.cases import build; from seawall import jit\n"
                           "build('dam-break', dx=0.05); print(jit._requested_threads[0])"],
                          env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip().splitlines()[-1] == "None"
