"""Parallel loops over blocks of particles, each block handled by a serial compiled function.

Numba lowers a ``prange`` loop by outlining its body into a separate function, and the
cost of that (copying, simplifying and re-typing the body's IR several times over) grows
with the size of the body: the fluid loop and the Adami wall loops, whose pair terms are
all inlined, spent most of the default run's cold compile in those passes
(docs/performance.md, "Start-up"). A loop written as

    for b in prange(block_count(n)):
        first, last = block_bounds(b, n)
        body(first, last, ...)

keeps the parallel region to a call, and the serial ``body`` (``for i in range(first,
last)``, the former loop body) is compiled by the ordinary pipeline once. Calling the body
once per particle instead cost 40-56 % of the step (the call, with every field of every
view as an argument, is not inlined); once per ``BLOCK`` particles the call is paid
rarely. Each particle's result does not depend on the block it falls in.
"""

import numpy as np
from numba import njit

# particles per call of a serial body: enough to make the call's cost negligible, few enough
# that a small run (a few thousand particles) still has tens of blocks to share among threads
BLOCK = 128


@njit(cache=True, inline="always")
def block_count(n):
    """Number of blocks of at most ``BLOCK`` particles covering ``n`` particles."""
    return (n + BLOCK - 1) // BLOCK


@njit(cache=True, inline="always")
def block_bounds(b, n):
    """First and one-past-last particle of block ``b`` of ``n`` particles.

    ``b`` is cast to int64: inside the outlined parallel loop the index is unsigned, and a
    body called with an unsigned and later a signed first index would compile twice.
    """
    first = np.int64(b) * BLOCK
    last = first + BLOCK
    if last > n:
        last = n
    return first, np.int64(last)
