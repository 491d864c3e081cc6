"""Refuse a set-up that cannot fit in memory before allocating it.

A mistyped ``--dx 1e-5`` asks for billions of particles; numpy would try to
allocate tens of GiB and die with a MemoryError traceback (or the machine
would swap). Shapes and line samplers call :func:`require_memory` with
their point count first, so the error names the parameter instead.
"""

import os

from .errors import ParameterError

#: memory a running particle costs [bytes]: measured as the growth of the peak resident size of a 2D
#: dam break from 2.7k to 32k particles (14.4 MB for 29.5k particles, about 490 bytes each)
BYTES_PER_PARTICLE = 500


def available_memory():
    """Bytes of memory available to a new allocation (MemAvailable on Linux, else physical memory)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


def require_memory(what, count, bytes_each=BYTES_PER_PARTICLE):
    """Raise ParameterError if ``count`` items of ``bytes_each`` bytes exceed the available memory."""
    need = float(count) * float(bytes_each)
    have = available_memory()
    if have is not None and need > have:
        raise ParameterError(f"{what}: {count:.3g} points need about {need / 2**30:.3g} GiB, "
                             f"only {have / 2**30:.3g} GiB of memory is available")
