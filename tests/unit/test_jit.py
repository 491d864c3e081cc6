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
    env = dict(os.environ, **{LOOPS_VARIABLE: mode, "NUMBA_NUM_THREADS": "2"})
    cmd = [sys.executable, "-m", "seawall", "run", "dam-break", "--dx", "0.02", "--t-end", "0.7",
           "--threads", str(threads), "--out", str(out)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
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


def _tvf_cavity(out, mode, threads):
    """The cavity at Re = 100 with the [Adami2013] scheme of entry cavity-re100-tvf (transport velocity,
    summed density, no EOS background), dx = L/20, 0.5 s (~420 steps); its final checkpoint."""
    from seawall.io.checkpoint import load_checkpoint

    env = dict(os.environ, **{LOOPS_VARIABLE: mode, "NUMBA_NUM_THREADS": "2"})
    cmd = [sys.executable, "-m", "seawall", "run", "cavity", "--dx", "5e-5", "--t-end", "0.5", "--set", "reynolds=100",
           "--set", "transport_velocity=true", "--set", "density=summation", "--set", "background=0",
           "--threads", str(threads), "--no-vtk", "--no-progress", "--out", str(out)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    arrays, attrs = load_checkpoint(out / "checkpoint.h5")
    assert float(attrs["time"]) == 0.5
    return arrays["fluid"], (out / "probes.csv").read_text()


def test_threaded_build_repeats_the_transport_velocity_cavity_bit_for_bit(tmp_path):
    """Two runs of the threaded build on two threads give the same state to the last bit: every
    particle loop writes only its own particle's rows, so the threads' timing cannot reach the
    result (a race, or a reduction summed in the order the threads finish, would). The serial
    build agrees to round-off (measured: bit for bit at dx = L/50 to t = 2 s, 4373 steps)."""
    first, probes_first = _tvf_cavity(tmp_path / "a", "threaded", 2)
    second, probes_second = _tvf_cavity(tmp_path / "b", "threaded", 2)
    serial, _ = _tvf_cavity(tmp_path / "serial", "serial", 1)
    assert probes_first == probes_second
    for name in ("x", "v", "rho", "p", "dv", "dv_transport"):
        assert np.array_equal(first[name], second[name]), name
        scale = max(1e-30, float(np.max(np.abs(serial[name]))))
        assert np.max(np.abs(serial[name] - first[name])) <= 1e-8 * scale, name
