"""The threaded build users run repeats itself bit for bit (seawall.jit); a file of its own so that the
suite's two processes run it beside tests/unit/test_jit.py, the other threaded-build check."""

import os
import subprocess
import sys

import numpy as np

from seawall.jit import LOOPS_VARIABLE


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
