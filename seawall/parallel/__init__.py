"""Domain decomposition over MPI ranks (``mpiexec -n N seawall run CASE``).

Every rank builds the whole case (or loads the whole checkpoint), then keeps
the fluid particles of its slab: the domain is cut across its longest
non-periodic axis at particle-count quantiles (:mod:`.slabs`). Each rank adds
halo copies of the neighbours' particles within a few kernel supports of its
slab, refreshed before every evaluation of the rates, so that the rates of
the particles it owns are those a single process computes
(:mod:`.distributed`; docs/parallel.md). Walls are replicated on every rank.

Nothing here imports mpi4py unless the process was started by ``mpiexec``
with more than one rank (:func:`launched_size`), so a serial run never pays
for it and never needs it.
"""

from __future__ import annotations

import os

#: environment variables by which MPI launchers give the number of ranks (MPICH/Hydra, Open MPI, Slurm's PMI)
SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MPI_LOCALNRANKS", "PMIX_SIZE")


def launched_size() -> int:
    """The number of ranks the launcher started (1 when not started by mpiexec); reads the environment only."""
    for name in SIZE_VARIABLES:
        value = os.environ.get(name)
        if value:
            try:
                return max(1, int(value))
            except ValueError:
                continue
    return 1


#: ... and by which they give this process's rank
RANK_VARIABLES = ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "PMIX_RANK")


def launched_rank() -> int:
    """This process's rank as the launcher gave it (0 when not started by mpiexec); reads the environment only."""
    for name in RANK_VARIABLES:
        value = os.environ.get(name)
        if value:
            try:
                return int(value)
            except ValueError:
                continue
    return 0


def world():
    """COMM_WORLD when this process is one of several MPI ranks, else None.

    Raises ParameterError when the launcher started several ranks but mpi4py is missing.
    """
    if launched_size() <= 1:
        return None
    try:
        from mpi4py import MPI
    except ImportError:
        from ..errors import ParameterError

        raise ParameterError("mpiexec started several ranks but mpi4py is not installed: "
                             "pip install seawall[mpi]") from None
    comm = MPI.COMM_WORLD
    return comm if comm.Get_size() > 1 else None


def share_cores(comm) -> int:
    """Set the compiled loops' threads to this node's cores divided among the ranks on it (at least 1);
    return the count. Ranks that each took every core would fight for them."""
    import numba
    from mpi4py import MPI

    local = comm.Split_type(MPI.COMM_TYPE_SHARED).Get_size()
    threads = max(1, min(numba.config.NUMBA_NUM_THREADS, (os.cpu_count() or 1) // local))
    numba.set_num_threads(threads)
    return threads


def is_root(comm) -> bool:
    """Rank 0, or a serial run (comm None): the process that writes the run's files."""
    return comm is None or comm.Get_rank() == 0


from .distributed import distribute, refusal  # noqa: E402  (after the helpers it uses)

__all__ = ["distribute", "is_root", "share_cores", "launched_rank", "launched_size", "refusal", "world"]
