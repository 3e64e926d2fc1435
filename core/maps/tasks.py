"""Where the runs of a sweep go: one ``concurrent.futures.Executor`` interface for every backend.

:func:`executor` turns the ``workers`` / ``scheduler`` arguments of
:func:`core.sweep` into an :class:`concurrent.futures.Executor` (as a context
manager that shuts down what it started), and :func:`run_tasks` runs tasks on
it, keeping a few in flight per worker so that a cancel or a time-out takes
effect within one task. The choices follow scipy's ``workers=`` convention:

* ``workers=1``: in the calling process (:class:`InlineExecutor`).
* ``workers=N`` (N > 1) or ``-1`` (all cores): a pool of local processes
  (``spawn`` start method, one BLAS/OpenMP thread each, each loading the
  compiled solver before its first task). The solver holds the GIL, so
  processes, not threads, give the speed-up.
* ``workers=None`` (default): by the size of the job. Starting a pool costs
  seconds (each process imports the package and loads the compiled solver),
  so a small job runs in this process and a large one on up to all cores
  (see :func:`auto_workers`).
* ``workers=`` a ``concurrent.futures.Executor`` (left running) or a map-like
  callable ``workers(fn, iterable)`` such as ``multiprocessing.Pool.map``.
* ``scheduler=`` a Dask scheduler address (``"tcp://host:8786"``), a
  ``distributed.Client`` or a cluster object: the Dask client's executor
  (``client.get_executor()``). The workers need this package installed;
  start them with ``--nthreads 1`` and as many processes as cores.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import math
import multiprocessing
import os
import queue
import threading
import time
from dataclasses import dataclass, field

from ..base._validate import check_int, check_scalar

__all__ = ["SweepCancelled", "InlineExecutor", "executor", "run_tasks", "check_address", "auto_workers", "cpu_count", "warm_up",
           "SECONDS_PER_CELL", "POOL_MIN_WORK_S"]

#: Solver time per cell (step x element) at the default resolution, one core [s]: the shipped 40 x 40 map
#: (core/data) took 11.5 s of solver time for 1.67e8 cells; benchmarks/sweep.py prints the figure again.
SECONDS_PER_CELL = 7.0e-8
#: Estimated solver time [s] one more local process must save before it is worth starting one
#: (a process takes about this long to import the package and load the compiled solver).
POOL_MIN_WORK_S = 4.0
# environment of worker processes: parallelism comes from the processes
_WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
               "NUMBA_NUM_THREADS": "1"}
_ENV_LOCK = threading.Lock()
_POLL_S = 0.2  # how often a waiting sweep checks for cancellation [s]
_START_TIMEOUT_S = 600.0  # longest wait for a worker process to start (it may compile the solver) [s]
_SCHEDULER_HELP = ("scheduler must be None, 'processes', 'serial', a concurrent.futures.Executor, a Dask address "
                   "(tcp://host:8786), a distributed.Client or a cluster object")


class SweepCancelled(RuntimeError):
    """A sweep was cancelled (``cancel`` was set or ``timeout`` passed) before it finished.

    Attributes
    ----------
    table : pandas.DataFrame
        The rows that were finished (for :func:`core.run_points` and
        :func:`core.numerical_limit_curve`), in grid order.
    """

    def __init__(self, message: str, table=None):
        super().__init__(message)
        self.table = table


# --------------------------------------------------------------------------
# executors
# --------------------------------------------------------------------------
class InlineExecutor(cf.Executor):
    """Runs each task in the calling thread when it is submitted (``workers=1``)."""

    _max_workers = 1

    def submit(self, fn, /, *args, **kwargs):
        future = cf.Future()
        try:
            result = fn(*args, **kwargs)
        except Exception as e:  # noqa: BLE001 - reported through the future, like any executor
            future.set_exception(e)
        else:
            future.set_result(result)
        return future


def warm_up() -> float:
    """Run the solver once (compiling it or loading numba's cache); return the seconds it took."""
    from ..api.solver import simulate_cycles

    t0 = time.perf_counter()
    simulate_cycles(0.3, 0.3, periods=1)
    return time.perf_counter() - t0


def _init_worker(started) -> None:
    """Initializer of pool workers: one thread each, solver loaded before the first task."""
    os.environ.update(_WORKER_ENV)
    started.put((os.getpid(), warm_up()))


def _nothing() -> None:
    return None


def cpu_count() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


@contextlib.contextmanager
def _single_threaded_children():
    """Set the worker environment while child processes start, then restore the parent's."""
    with _ENV_LOCK:
        saved = {k: os.environ.get(k) for k in _WORKER_ENV}
        os.environ.update(_WORKER_ENV)
        try:
            yield
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v


def _process_pool(workers: int) -> tuple[cf.ProcessPoolExecutor, dict]:
    """Start ``workers`` spawned processes and wait until each has loaded the solver; return it and the warm-ups."""
    warm_up()  # fill numba's on-disk cache before the workers load it
    ctx = multiprocessing.get_context("spawn")
    started = ctx.Queue()
    with _single_threaded_children():
        pool = cf.ProcessPoolExecutor(workers, mp_context=ctx, initializer=_init_worker, initargs=(started,))
        # one task per worker starts them all now, under the single-threaded environment
        starts = [pool.submit(_nothing) for _ in range(workers)]
    warmup = {}
    deadline = time.perf_counter() + _START_TIMEOUT_S
    while len(warmup) < workers:
        try:
            pid, seconds = started.get(timeout=_POLL_S)
        except queue.Empty:
            if any(f.done() and f.exception() is not None for f in starts) or time.perf_counter() > deadline:
                pool.shutdown(wait=False, cancel_futures=True)
                raise RuntimeError(
                    "the worker processes failed to start. They import the main module again (the "
                    "'spawn' start method): run sweeps from a file guarded by "
                    "`if __name__ == \"__main__\":`, or pass workers=1") from None
            continue
        warmup[f"pid-{pid}"] = seconds
    return pool, warmup


def check_address(address: str) -> None:
    """Refuse a malformed Dask address before a Client is made (a failed Client lingers at exit)."""
    try:
        from distributed.comm import parse_address
        from distributed.comm.addressing import parse_host_port
    except ImportError as e:
        raise ValueError("a Dask scheduler needs dask.distributed: pip install 'dask[distributed]'") from e
    if len(address) > 300:
        raise ValueError(f"scheduler must be a Dask address of at most 300 characters, got {address!r:.60}...")
    scheme, location = parse_address(address)
    if scheme in ("tcp", "tls", "ws", "wss"):
        try:
            parse_host_port(location)
        except ValueError as e:
            raise ValueError(f"scheduler must be a Dask address such as tcp://host:8786, got {address!r:.100} "
                             f"({e})") from e


@contextlib.contextmanager
def _dask_client(scheduler):
    """A ``distributed.Client`` for an address, a Client (used as is) or a cluster object (closed after)."""
    try:
        import distributed
    except ImportError as e:
        raise ValueError("a Dask scheduler needs dask.distributed: pip install 'dask[distributed]'") from e
    if isinstance(scheduler, distributed.Client):
        yield scheduler
        return
    if isinstance(scheduler, str):
        check_address(scheduler)
    elif not hasattr(scheduler, "scheduler_address"):
        raise ValueError(f"{_SCHEDULER_HELP}; got {type(scheduler).__name__}")
    try:
        client = distributed.Client(scheduler, set_as_default=False, timeout="10s")
    except (OSError, TimeoutError, ValueError) as e:
        raise ValueError(f"cannot connect to the Dask scheduler {scheduler!r:.100}: {e}") from e
    try:
        yield client
    finally:
        client.close()


def auto_workers(cells: float | None, runs: int, cores: int | None = None) -> int:
    """Local processes worth starting for a job of ``cells`` (summed steps x elements) in ``runs`` runs.

    One process per :data:`POOL_MIN_WORK_S` of estimated solver time
    (:data:`SECONDS_PER_CELL` per cell), at least 1 (this process, no pool)
    and at most the cores and the runs. Without an estimate (``cells`` None:
    another body or history), one process per 50 runs.
    """
    cores = cpu_count() if cores is None else cores
    if cells is None:
        wanted = runs // 50
    else:
        wanted = math.floor(cells * SECONDS_PER_CELL / POOL_MIN_WORK_S)
    return max(1, min(cores, runs, wanted))


@dataclass
class Backend:
    """An executor and the facts about it that a sweep table records."""

    executor: cf.Executor
    name: str
    workers: int
    window: int  # tasks kept in flight
    warmup: dict = field(default_factory=dict)
    map: object = None  # a map-like callable given as workers (then ``executor`` is unused)


@contextlib.contextmanager
def executor(workers=None, scheduler=None, *, cells: float | None = None, runs: int = 1):
    """The executor for a sweep, as a context manager yielding a :class:`Backend`.

    Parameters
    ----------
    workers : None, int, Executor or callable
        See the module docstring: ``None`` by the job's size, ``1`` this
        process, ``N`` or ``-1`` local processes, an Executor (left running)
        or a map-like callable.
    scheduler : None, str, distributed.Client or cluster
        A Dask cluster (overrides ``workers``); ``"serial"`` and
        ``"processes"`` are the same as ``workers=1`` and local processes.
    cells, runs : optional
        Size of the job (summed steps x elements, number of tasks), for
        ``workers=None``.
    """
    if isinstance(scheduler, cf.Executor):
        workers, scheduler = scheduler, None
    if isinstance(scheduler, str) and scheduler in ("serial", "processes"):
        if scheduler == "serial":
            workers = 1
        elif workers is None:
            workers = -1
        scheduler = None
    if scheduler is not None:
        with _dask_client(scheduler) as client:
            nthreads = max(1, sum(client.nthreads().values()))
            warmup = client.run(warm_up)
            pool = client.get_executor(pure=False)
            try:
                yield Backend(pool, f"dask({client.scheduler.address}, {nthreads} threads)", nthreads,
                              4 * nthreads, warmup)
            finally:
                pool.shutdown(wait=False)
        return
    if isinstance(workers, cf.Executor):
        n = getattr(workers, "_max_workers", 1)
        yield Backend(workers, type(workers).__name__, n, 2 * n)
        return
    if callable(workers):
        yield Backend(InlineExecutor(), getattr(workers, "__qualname__", "map"), 1, 1, map=workers)
        return
    if workers is None:
        n = auto_workers(cells, runs)
    else:
        n = check_int("workers", workers, -1, 1024)
        if n == 0:
            raise ValueError("workers must be -1 (all cores), a positive integer, an Executor or a map-like "
                             "callable, got 0")
        n = cpu_count() if n == -1 else n
    n = max(1, min(n, runs))
    if n == 1:
        yield Backend(InlineExecutor(), "serial", 1, 1, {"worker": warm_up()})
        return
    pool, warmup = _process_pool(n)
    try:
        yield Backend(pool, f"processes({n})", n, 2 * n, warmup)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def cancel_check(cancel):
    """``cancel`` as a function: a ``threading.Event`` (set means stop) or a callable returning True to stop."""
    if cancel is None:
        return lambda: False
    if callable(getattr(cancel, "is_set", None)):
        return cancel.is_set
    if callable(cancel):
        return lambda: bool(cancel())
    raise ValueError(f"cancel must be a threading.Event or a callable, got {cancel!r:.60}")


def run_tasks(fn, make_tasks, *, workers=None, scheduler=None, on_result, cancel=None, timeout=None,
              cells=None, runs: int = 1) -> dict:
    """Run ``fn`` over tasks on the chosen executor; ``on_result(i, value, exc)`` as each finishes.

    ``make_tasks(workers)`` gives the list of tasks once the number of workers
    is known. At most ``window`` tasks are in flight at a time (two per local
    worker, four per Dask thread, one in this process), so a cancel or a
    time-out stops within one task. ``on_result`` is called in the calling
    thread, in completion order. Returns the execution facts (backend,
    workers, warm-up, start-up and wall times); raises :class:`SweepCancelled`
    (without a table) if stopped.
    """
    if timeout is not None:
        timeout = check_scalar("timeout", timeout, 0.0, None, lo_closed=False)
    cancelled = cancel_check(cancel)
    t0 = time.perf_counter()
    deadline = math.inf if timeout is None else t0 + timeout

    def stopped():
        return cancelled() or time.perf_counter() > deadline

    finished = 0
    with executor(workers, scheduler, cells=cells, runs=runs) as backend:
        t_started = time.perf_counter()
        tasks = make_tasks(backend.workers)
        todo = iter(enumerate(tasks if backend.map is None else []))
        pending: dict = {}

        def fill():
            while len(pending) < backend.window and not stopped():
                item = next(todo, None)
                if item is None:
                    return
                pending[backend.executor.submit(fn, item[1])] = item[0]

        if backend.map is not None:  # scipy's convention: one call of the map-like over every task, in order
            for i, value in enumerate(backend.map(fn, tasks)):
                on_result(i, value, None)
                finished += 1
        try:
            fill()
            while pending and not stopped():
                done, _ = cf.wait(list(pending), timeout=_POLL_S, return_when=cf.FIRST_COMPLETED)
                for future in sorted(done, key=pending.get):
                    i = pending.pop(future)
                    try:
                        value, exc = future.result(), None
                    except Exception as e:  # noqa: BLE001 - a lost worker or a cancelled task
                        value, exc = None, e
                    on_result(i, value, exc)
                    finished += 1
                fill()
        finally:
            for future in pending:
                future.cancel()
    if finished < len(tasks):
        why = "cancelled" if cancelled() else f"timed out after {timeout:g} s"
        raise SweepCancelled(f"sweep {why}: {finished} of {len(tasks)} tasks finished")
    return {"backend": backend.name, "workers": backend.workers, "warmup_s": backend.warmup,
            "startup_s": t_started - t0, "wall_s": time.perf_counter() - t0}
