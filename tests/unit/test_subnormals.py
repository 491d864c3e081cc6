"""Subnormal numbers are flushed to zero during a run, and only then (seawall.subnormals)."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from numba import njit

import seawall as sw
from seawall.cases import case_by_name
from seawall.errors import ParameterError
from seawall.subnormals import FLUSH_BITS, calling_thread_switches, flushing, supported

pytestmark = pytest.mark.skipif(not supported(), reason="the flush switches are set on x86-64 only")

SMALLEST_NORMAL = np.finfo(np.float64).tiny
STEPS = 5


@njit
def _product(a, b):
    return a[0] * b[0]


def _tiny_product():
    # 1e-300 * 1e-10 = 1e-310: subnormal, or zero when flushed
    return _product(np.array([1e-300]), np.array([1e-10]))


def test_flushing_zeroes_subnormal_results_inside_the_block_only():
    if calling_thread_switches() != 0:
        pytest.skip("this process flushes subnormals already")
    assert 0.0 < _tiny_product() < SMALLEST_NORMAL
    with flushing():
        assert calling_thread_switches() == FLUSH_BITS
        assert _tiny_product() == 0.0
        with flushing():   # an inner block leaves the outer one's switches in place
            assert _tiny_product() == 0.0
        assert calling_thread_switches() == FLUSH_BITS
        assert _tiny_product() == 0.0
    assert calling_thread_switches() == 0
    assert 0.0 < _tiny_product() < SMALLEST_NORMAL
    with flushing(enabled=False):
        assert calling_thread_switches() == 0


def test_flushing_restores_the_switches_when_the_block_raises():
    if calling_thread_switches() != 0:
        pytest.skip("this process flushes subnormals already")
    with pytest.raises(RuntimeError):
        with flushing():
            raise RuntimeError("stop")
    assert calling_thread_switches() == 0


_POOL_SCRIPT = """
import json
import numpy as np
from seawall.jit import apply_threads, use_threads
from seawall.subnormals import flushing, pool_switches
report = {}
with flushing():   # the pool starts inside the block: its threads copy the switches
    use_threads(2)
    apply_threads()
    report["started_inside"] = pool_switches().tolist()
report["after_first"] = pool_switches().tolist()
with flushing():   # the pool runs already: each thread is set
    report["running"] = pool_switches().tolist()
report["after_second"] = pool_switches().tolist()
print(json.dumps(report))
"""


def test_every_thread_of_the_pool_flushes_in_the_block_and_is_restored_after():
    env = dict(os.environ, SEAWALL_LOOPS="threaded", NUMBA_NUM_THREADS="2")
    done = subprocess.run([sys.executable, "-c", _POOL_SCRIPT], env=env, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["started_inside"] == [FLUSH_BITS, FLUSH_BITS]
    assert report["after_first"] == [0, 0]
    assert report["running"] == [FLUSH_BITS, FLUSH_BITS]
    assert report["after_second"] == [0, 0]


def _dam_break(flush):
    sim = case_by_name("dam-break").build(boundary="adami", dx=0.02, threads=1)
    sim.flush_subnormals = flush
    # subnormal horizontal velocities, as ahead of a disturbance in still water (the dam break at
    # dx = 0.0015 has a band of them by step 80; at this dx the disturbance fills the
    # column before its tail falls that low)
    v = sim.fluid.particles["v"]
    v[::2, 0] = 3e-310
    sim.run_steps(STEPS)
    return sim.fluid.particles


def test_a_run_flushes_by_default_and_its_flow_is_the_same_to_rounding():
    """Only values below 2.2e-308 are given up, so the flow is the same as without flushing:
    measured, positions and densities equal bit for bit after 5 steps of the dam break with
    half of its horizontal velocities subnormal (3e-310) at the start; the velocities differ by
    those subnormals, which the kept run still has in 54 places."""
    kept = _dam_break(False)
    flushed = _dam_break(True)
    assert calling_thread_switches() == 0   # the run gave the switches back
    for name in ("x", "rho", "v"):
        scale = float(np.max(np.abs(kept[name])))
        assert np.max(np.abs(kept[name] - flushed[name])) <= 1e-12 * scale, name
    assert np.count_nonzero((np.abs(kept["v"]) > 0) & (np.abs(kept["v"]) < SMALLEST_NORMAL)) > 0
    assert np.count_nonzero((np.abs(flushed["v"]) > 0) & (np.abs(flushed["v"]) < SMALLEST_NORMAL)) == 0


def test_flush_subnormals_must_be_a_bool():
    fluid = sw.FluidSystem(sw.shapes.rectangle((0, 0), (0.2, 0.1), 0.02), eos=sw.Tait(c0=10.0))
    with pytest.raises(ParameterError, match="flush_subnormals"):
        sw.Simulation([fluid], h=0.026, flush_subnormals="yes")
    assert sw.Simulation([fluid], h=0.026).flush_subnormals is True
