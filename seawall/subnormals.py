"""Subnormal numbers flushed to zero while a run's loops work.

A nonzero double below 2.2e-308 in magnitude is *subnormal*, and x86 CPUs take an operation
on one through a slow microcode assist. SPH produces them wherever a disturbance spreads into
fluid at rest. The dam break starts with zero horizontal velocity in the column; the collapse
at its free face reaches one kernel support further each step, and ahead of it the velocities
fall off geometrically (the smallest falls by about four decades a step). So once the front
is far enough from the column's other side, every evaluation meets a band of particles whose
velocities, accelerations and density rates are subnormal. At 80k particles (H/200) 1,854
velocity components were subnormal after 150 steps, and the fluid loop took 44.0 ms on that
state on one thread, 32.5 ms with them flushed (docs/performance.md, "Subnormal numbers"). The
band also lies in one thread's share of the particles, so the two threads' halves took unequal
time: 28.9 ms on two threads, 16.5 ms flushed.

Flushing gives up values below 2.2e-308, which cannot change a sum with a term of ordinary
size: the loops' results agree to rounding. The x86 control register MXCSR holds the two
switches: flush-to-zero (FTZ, results) and denormals-are-zero (DAZ, inputs). The register is
per thread. :func:`flushing` sets both on the calling thread and on every thread of Numba's
pool for the time of a run, and afterwards gives them all back the caller's switches as they
were, so the user's own arithmetic before and after a run is untouched. On other CPUs it
changes nothing; :func:`supported` says which.
"""

from __future__ import annotations

import contextlib
import platform

import numba
import numpy as np
from numba import njit, prange, types
from numba.core import cgutils
from numba.extending import intrinsic

from .jit import THREADED, particle_loop, pool_started

#: MXCSR's flush-to-zero (bit 15) and denormals-are-zero (bit 6) switches
FLUSH_BITS = 0x8040
#: the rest of MXCSR, kept as it is
_OTHER_BITS = 0xFFFFFFFF ^ FLUSH_BITS


def supported() -> bool:
    """Whether this CPU's floating-point control register is one seawall can set (x86-64)."""
    return platform.machine().lower() in ("x86_64", "amd64")


def _mxcsr_call(builder, name, slot):
    from llvmlite import ir

    pointer = ir.IntType(8).as_pointer()
    fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), [pointer]), name)
    builder.call(fn, [builder.bitcast(slot, pointer)])


@intrinsic
def _read_mxcsr(typingctx):
    """The calling thread's MXCSR (LLVM's ``llvm.x86.sse.stmxcsr``)."""
    def codegen(context, builder, signature, args):
        from llvmlite import ir

        slot = cgutils.alloca_once(builder, ir.IntType(32))
        _mxcsr_call(builder, "llvm.x86.sse.stmxcsr", slot)
        return builder.load(slot)
    return types.uint32(), codegen


@intrinsic
def _write_mxcsr(typingctx, value):
    """Load ``value`` into the calling thread's MXCSR (LLVM's ``llvm.x86.sse.ldmxcsr``)."""
    if value != types.uint32:
        return None

    def codegen(context, builder, signature, args):
        from llvmlite import ir

        slot = cgutils.alloca_once(builder, ir.IntType(32))
        builder.store(args[0], slot)
        _mxcsr_call(builder, "llvm.x86.sse.ldmxcsr", slot)
        return context.get_dummy_value()
    return types.none(value), codegen


@njit(cache=True)
def _switch(bits):
    """The calling thread's flush switches; set them to ``bits`` first unless ``bits`` < 0."""
    old = _read_mxcsr()
    if bits >= 0:
        _write_mxcsr(np.uint32((old & np.uint32(_OTHER_BITS)) | np.uint32(bits & FLUSH_BITS)))
    return np.int64(old & np.uint32(FLUSH_BITS))


@particle_loop(fastmath=False)
def switch_pool(bits, old, thread):
    """Every pool thread: ``old[k]`` = its flush switches, then set to ``bits`` unless ``bits`` < 0.

    One iteration per thread: Numba splits a ``prange`` into equal blocks, one a thread, so
    with as many iterations as threads each thread takes one; ``thread[k]`` records which.
    """
    for k in prange(old.shape[0]):
        old[k] = _switch(bits)
        thread[k] = numba.get_thread_id()


def rehearse():
    """Call :func:`switch_pool` with a run's argument types, for a compile helper's rehearsal.

    In the helper a particle loop is recorded, not run (:mod:`seawall.compile_ahead`), so the
    helper compiles it; called anywhere else this would start Numba's pool and set its switches.
    """
    if supported() and THREADED:
        switch_pool(np.int64(-1), np.empty(1, dtype=np.int64), np.empty(1, dtype=np.int64))


def _pool_running():
    # a serial build (SEAWALL_LOOPS=serial) runs its loops on the calling thread only
    return THREADED and pool_started()


def pool_switches(bits=-1):
    """The flush switches of each thread of Numba's pool, by thread id (-1: not reached), after
    setting them all to ``bits`` unless ``bits`` < 0. Empty while no pool runs."""
    if not _pool_running():
        return np.empty(0, dtype=np.int64)
    size = int(numba.config.NUMBA_NUM_THREADS)
    used = numba.get_num_threads()
    numba.set_num_threads(size)   # the whole pool: a later run may use more threads than this one
    try:
        found = np.full(size, -1, dtype=np.int64)
        thread = np.empty(size, dtype=np.int64)
        old = np.empty(size, dtype=np.int64)
        for _ in range(3):   # should a thread have taken no block, the next pass reaches it
            switch_pool(np.int64(bits), old, thread)
            for k in range(size):
                if 0 <= thread[k] < size and found[thread[k]] < 0:
                    found[thread[k]] = old[k]
            if np.all(found >= 0):
                break
        return found
    finally:
        numba.set_num_threads(used)


@contextlib.contextmanager
def flushing(enabled: bool = True):
    """Flush subnormal numbers to zero, in this thread and in Numba's pool, until the block ends.

    A pool that starts inside the block inherits the switches (a new thread copies its
    creator's control register). On leaving, the calling thread and every pool thread get the
    calling thread's switches as they were on entry. ``enabled=False``, a CPU other than x86-64
    and a block inside another (the caller flushes already) change nothing.
    """
    if not enabled or not supported():
        yield
        return
    before = int(_switch(FLUSH_BITS))
    if before == FLUSH_BITS:
        yield
        return
    try:
        pool_switches(FLUSH_BITS)
        yield
    finally:
        pool_switches(before)
        _switch(before)


def calling_thread_switches() -> int:
    """The calling thread's flush switches (``FLUSH_BITS`` when flushing, 0 by default); -1 off x86-64."""
    return int(_switch(-1)) if supported() else -1
