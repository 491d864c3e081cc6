"""Where independent runs execute: this process, local processes, or a dask.distributed cluster.

``seawall compare``, ``seawall validate`` and ``seawall sweep`` hand their runs to an
executor as :class:`Task` objects and get one :class:`Outcome` per task back, in the
order the tasks were given, whatever order they finished in:

* :class:`InProcess` -- one task after the other in this process (``--jobs 1``;
  ``seawall validate`` without ``--scheduler``);
* :class:`LocalProcesses` -- a pool of spawned processes on this machine (``--jobs N``),
  spawned rather than forked so that each has its own Numba thread pool;
* :class:`DaskCluster` -- the tasks of a ``dask.distributed`` scheduler (``--scheduler
  ADDRESS``), or of a ``LocalCluster`` it starts itself (``--scheduler`` alone or
  ``--scheduler local``, with ``--workers N``).

A task is a module-level function and plain arguments (strings, numbers, lists, dicts),
so it pickles by reference and runs the same on a worker of another machine, which
imports seawall itself. Paths in the arguments must be absolute and name a file system
the worker shares (see docs/sweeps.md). A task that raises is recorded as a failed
outcome (``error`` one line, ``details`` the traceback where there is one); the other
tasks go on. Only an interrupt (Ctrl-C) ends the whole set.
"""

import os
import sys
import traceback
from dataclasses import dataclass

from .errors import ParameterError

#: the --scheduler value (and the bare flag) that starts a LocalCluster on this machine
LOCAL_SCHEDULER = "local"


@dataclass(frozen=True)
class Task:
    """One independent run: ``fn(*args)``. ``fn`` must be importable by module and name."""

    fn: object
    args: tuple
    label: str


@dataclass
class Outcome:
    """What one task gave: its return ``value``, or ``error`` (one line) when it raised."""

    label: str
    value: object = None
    error: str = None
    details: str = None

    @property
    def ok(self):
        return self.error is None


def error_line(exc):
    """``Type: first line of the message`` -- a failure as one line of a table."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def _failed(label, exc):
    details = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
    return Outcome(label, error=error_line(exc), details=details)


def usable_cores():
    """Cores the compiled loops may use here: the machine's, capped by NUMBA_NUM_THREADS."""
    import numba

    return max(1, min(os.cpu_count() or 1, numba.config.NUMBA_NUM_THREADS))


class InProcess:
    """Run the tasks one after the other in this process."""

    description = "this process"

    def __init__(self, threads_per_run=None):
        self.threads_per_run = threads_per_run or usable_cores()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def completed(self, tasks):
        """Yield ``(index, Outcome)`` of each task as it finishes."""
        for index, task in enumerate(tasks):
            try:
                yield index, Outcome(task.label, value=task.fn(*task.args))
            except Exception as exc:   # one failed run must not lose the others
                yield index, _failed(task.label, exc)


class LocalProcesses:
    """Run the tasks in ``jobs`` spawned processes of this machine."""

    def __init__(self, jobs, threads_per_run=None):
        self.jobs = jobs
        self.threads_per_run = threads_per_run or max(1, usable_cores() // jobs)
        self.description = f"{jobs} local processes"
        self._pool = None

    def __enter__(self):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        ctx = multiprocessing.get_context("spawn")   # fresh Numba thread pools per worker
        self._pool = ProcessPoolExecutor(max_workers=self.jobs, mp_context=ctx)
        return self

    def __exit__(self, *exc):
        # on Ctrl-C the runs still queued are dropped rather than waited for
        self._pool.shutdown(wait=exc[0] is None, cancel_futures=True)
        return False

    def completed(self, tasks):
        from concurrent.futures import as_completed

        futures = {self._pool.submit(task.fn, *task.args): index for index, task in enumerate(tasks)}
        for future in as_completed(futures):
            index = futures[future]
            try:
                yield index, Outcome(tasks[index].label, value=future.result())
            except Exception as exc:   # a failed run (or a worker that died) is one failed outcome
                yield index, _failed(tasks[index].label, exc)


class DaskCluster:
    """Run the tasks on a ``dask.distributed`` cluster: the scheduler at ``scheduler`` (an
    address such as ``tcp://10.0.0.5:8786``), or a ``LocalCluster`` of ``workers`` processes
    (one task at a time each) started here when ``scheduler`` is ``"local"``.

    ``threads_per_run``: the Numba threads of each run; default the cores of this machine
    shared among the local workers, or 1 on a remote cluster (whose machines we cannot see;
    give ``--threads`` to match its workers).
    """

    def __init__(self, scheduler=LOCAL_SCHEDULER, workers=None, threads_per_run=None):
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise ParameterError("--scheduler needs dask.distributed: pip install 'seawall[cluster]'") from None
        self.scheduler = scheduler or LOCAL_SCHEDULER
        self.local = self.scheduler == LOCAL_SCHEDULER
        if workers is not None and not self.local:
            raise ParameterError("--workers sizes the local cluster (--scheduler local); a cluster at "
                                 f"{self.scheduler} has the workers started there")
        self.workers = workers or (usable_cores() if self.local else None)
        if self.local:
            self.threads_per_run = threads_per_run or max(1, usable_cores() // self.workers)
            self.description = f"a local dask cluster of {self.workers} workers"
        else:
            self.threads_per_run = threads_per_run or 1
            self.description = f"the dask scheduler at {self.scheduler}"
        self.cluster = self.client = None

    def __enter__(self):
        from distributed import Client, LocalCluster

        if self.local:
            # no memory limit, as for local processes: the nanny would otherwise kill a run near 1/workers
            # of the memory; its web server on a free port (8787 may be another cluster's)
            self.cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                        memory_limit=0, dashboard_address=":0")
            self.client = Client(self.cluster)
        else:
            try:
                self.client = Client(self.scheduler, timeout="20s")
            except (OSError, TimeoutError, ValueError) as exc:
                raise ParameterError(f"--scheduler {self.scheduler}: cannot connect ({error_line(exc)})") from None
        return self

    def __exit__(self, *exc):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        return False

    def completed(self, tasks):
        from distributed import as_completed

        import uuid

        batch = uuid.uuid4().hex[:12]
        # pure=False: two tasks with equal arguments are still two runs
        futures = [self.client.submit(task.fn, *task.args, pure=False, key=f"seawall-{batch}-{index}")
                   for index, task in enumerate(tasks)]
        index_of = {f.key: index for index, f in enumerate(futures)}
        for future in as_completed(futures):
            index = index_of[future.key]
            try:
                yield index, Outcome(tasks[index].label, value=future.result())
            except Exception as exc:   # the run's own error, or the cluster's (a worker lost, KilledWorker)
                yield index, _failed(tasks[index].label, exc)
            finally:
                future.release()


def local_executor(jobs, n_tasks, threads_per_run=None):
    """``--jobs``: at most one process per core and per task; one job runs in this process."""
    cores = usable_cores()
    jobs = max(1, min(jobs or cores, n_tasks, cores))
    threads = threads_per_run or max(1, cores // jobs)   # NUMBA_NUM_THREADS caps the threads
    return InProcess(threads) if jobs == 1 else LocalProcesses(jobs, threads)


def executor_for(*, scheduler=None, workers=None, jobs=None, n_tasks=1, threads_per_run=None,
                 default_in_process=False):
    """The executor the command-line options ask for. ``scheduler`` None: this machine
    (``jobs`` processes; ``default_in_process``: this process when no ``jobs`` is given)."""
    if scheduler is None:
        if workers is not None:
            raise ParameterError("--workers sizes a dask cluster: give it with --scheduler (on this machine, "
                                 "--jobs)")
        if default_in_process and jobs is None:
            return InProcess(threads_per_run)
        return local_executor(jobs, n_tasks, threads_per_run)
    if jobs is not None:
        raise ParameterError("--jobs counts local processes: with --scheduler give --workers (a local cluster) "
                             "or start the workers at the scheduler")
    workers = min(workers or usable_cores(), max(1, n_tasks)) if scheduler == LOCAL_SCHEDULER else workers
    return DaskCluster(scheduler, workers, threads_per_run)


def run_tasks(executor, tasks, *, desc="runs", progress=True, on_done=None, report_failures=True):
    """Run ``tasks`` on ``executor`` (entered here); return their outcomes in the order given.

    A progress bar (tqdm.auto) counts finished runs; ``on_done(index, outcome)`` is called as each
    finishes (in the order they finish); ``report_failures``: one line on stderr per failed task.
    """
    from tqdm.auto import tqdm

    outcomes = [None] * len(tasks)
    bar = tqdm(total=len(tasks), desc=desc, unit="run", file=sys.stderr, disable=not progress or not tasks,
               dynamic_ncols=True, leave=True)
    try:
        with executor:
            for index, outcome in executor.completed(tasks):
                outcomes[index] = outcome
                bar.update(1)
                if report_failures and not outcome.ok:
                    bar.write(f"{outcome.label}: failed: {outcome.error}", file=sys.stderr)
                if on_done is not None:
                    on_done(index, outcome)
    finally:
        bar.close()
    return outcomes
