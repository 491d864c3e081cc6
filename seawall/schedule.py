"""When the next output is due: interval catch-up that always moves forward.

Outputs (probe samples, VTU snapshots, line profiles, checkpoints) are due at
multiples of their interval ``every``. After writing at time t, the next due
time is the first multiple past t. Adding ``every`` until that holds is exact
and cheap when a step spans a few intervals, but never ends when ``every`` is
below the floating-point resolution of t (t + 1e-300 == t) and takes
billions of iterations when it is merely tiny. These helpers add at most a
bounded number of times (keeping the usual values bit for bit) and then jump.
"""

import math

#: times closer than this count as equal (the tolerance used by the run loop)
TIME_TOLERANCE = 1e-12

_MAX_ADDITIONS = 1000


def next_due(next_time, every, t):
    """The first ``next_time + k * every`` (k >= 0) later than ``t`` (+ tolerance); always > t."""
    limit = t + TIME_TOLERANCE
    for _ in range(_MAX_ADDITIONS):
        if next_time > limit:
            return next_time
        next_time += every
    if next_time > limit:
        return next_time
    k = math.floor((limit - next_time) / every) + 1.0
    jumped = next_time + k * every
    # an interval below the resolution of t: due again at the next step
    return jumped if jumped > limit else math.nextafter(limit, math.inf)


def first_due_after(t, every):
    """The first multiple of ``every`` after ``t`` (used when a run resumes from a checkpoint)."""
    k = math.floor(t / every + 1e-9) + 1.0
    candidate = k * every
    return candidate if candidate > t + TIME_TOLERANCE else next_due(candidate, every, t)
