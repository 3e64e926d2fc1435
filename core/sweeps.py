"""Maps of the cycle solver over parameters, run in parallel, and the numerical shakedown limit.

:func:`sweep` runs :func:`core.simulate_cycles` for every combination of its
inputs and returns a tidy table, one row per run. :func:`numerical_w_limit`
bisects the regime verdict in ``w`` for one ``ft``; :func:`numerical_limit_curve`
does that for many ``ft`` at once. All three share one execution layer:

* ``scheduler=None`` (or ``"processes"``): a local pool of processes over all
  cores (``concurrent.futures.ProcessPoolExecutor``, ``spawn`` start method,
  one BLAS/OpenMP thread per worker). The solver holds the GIL, so processes,
  not threads, give the speed-up.
* ``scheduler="serial"``: in the calling process, one run after the other.
* a ``concurrent.futures.Executor``: your own pool (it is not shut down).
* a Dask scheduler address (``"tcp://host:8786"``), a ``distributed.Client``
  or a ``distributed.LocalCluster``: the runs go to the Dask cluster
  (``client.map``, collected as they complete). The workers need this package
  installed; start them with ``--nthreads 1`` and as many processes as cores.

The solver is deterministic, so every path gives the same table for the same
inputs (only the measured ``runtime`` differs); the rows come in the order of
the grid whatever order the runs finish in. Work is sent in chunks of runs so
that the per-task overhead stays small, and a run that fails becomes a row
with ``regime = "error"`` and its message: it does not stop the sweep.

Before workers start, the parent process runs the solver once so that the
compiled code is in numba's on-disk cache; each worker then loads it instead
of compiling it again (the warm-up times are in ``table.attrs``).

Bounded work: a sweep may have at most :func:`default_max_runs` runs, and every run at
most :func:`default_max_cells` (steps x elements, the size of the per-step arrays).
Both default to the constants :data:`MAX_RUNS` and :data:`MAX_CELLS` and can be
set by the operator with the environment variables ``SHAKEDOWN_MAX_RUNS`` and
``SHAKEDOWN_MAX_CELLS`` or per call.
"""

from __future__ import annotations

import contextlib
import inspect
import itertools
import math
import multiprocessing
import os
import queue
import sys
import threading
import time
import concurrent.futures as cf
from dataclasses import dataclass, field
from importlib import resources

import numpy as np
import pandas as pd

from ._validate import check_int, check_range, check_scalar, env_int
from .analytical import w_limit as _w_limit_eq35
from .schedule import rocking_schedule
from .solver import make_grid, simulate_cycles

__all__ = [
    "sweep", "sweep_grid", "run_points", "numerical_w_limit", "numerical_limit", "numerical_limit_curve",
    "LimitResult", "SweepCancelled", "ProgressBar", "load_default_map", "default_max_runs", "default_max_cells",
    "MAX_RUNS", "MAX_CELLS", "DEFAULT_MAP", "INPUT_COLUMNS", "RESULT_COLUMNS",
]

#: Default cap on the number of runs of one sweep (env ``SHAKEDOWN_MAX_RUNS``).
MAX_RUNS = 20_000
#: Default cap on steps x elements of one run, about 9 bytes each in memory
#: (env ``SHAKEDOWN_MAX_CELLS``); the default resolution needs about 2e5.
MAX_CELLS = 25_000_000
#: File name of the shipped map under ``core/data`` (see :func:`load_default_map`).
DEFAULT_MAP = "default_map.csv.gz"
#: Inputs that every sweep table has as columns (further options add theirs).
INPUT_COLUMNS = ("ft", "w", "periods", "dx", "kernel", "shape")
#: Result columns of a sweep table, in order.
RESULT_COLUMNS = ("regime", "increment", "stick_halfwidth", "shakedown_period", "runtime",
                  "max_kkt_residual", "max_iterations", "elements", "steps", "periodic_from", "error")
_INT_COLUMNS = ("periods", "load_steps", "shakedown_period", "max_iterations", "elements", "steps",
                "periodic_from")
_STR_COLUMNS = ("kernel", "shape", "regime", "error")
# simulate_cycles' own parameters (besides ft and w, and the per-call hooks), with their defaults
_SOLVER_DEFAULTS = {name: p.default for name, p in inspect.signature(simulate_cycles).parameters.items()
                    if name not in ("ft", "w", "cancel", "progress")}
# W / a of the widest rocking the limit search tries
_W_MAX = 0.999
# environment of worker processes: parallelism comes from the processes
_WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
               "NUMBA_NUM_THREADS": "1"}
_ENV_LOCK = threading.Lock()
_POLL_S = 0.2  # how often a waiting sweep checks for cancellation [s]
_START_TIMEOUT_S = 600.0  # longest wait for a worker process to start (it may compile the solver) [s]


class SweepCancelled(RuntimeError):
    """A sweep was cancelled (``cancel`` was set or ``timeout`` passed) before it finished.

    Attributes
    ----------
    table : pandas.DataFrame
        The rows that were finished (for :func:`run_points` and
        :func:`numerical_limit_curve`), in grid order.
    """

    def __init__(self, message: str, table: pd.DataFrame | None = None):
        super().__init__(message)
        self.table = table


# --------------------------------------------------------------------------
# caps, configurable by the operator
# --------------------------------------------------------------------------
def default_max_runs() -> int:
    """Largest number of runs a sweep may have: ``$SHAKEDOWN_MAX_RUNS``, else :data:`MAX_RUNS`."""
    return env_int("SHAKEDOWN_MAX_RUNS", MAX_RUNS)


def default_max_cells() -> int:
    """Largest steps x elements of one run: ``$SHAKEDOWN_MAX_CELLS``, else :data:`MAX_CELLS`."""
    return env_int("SHAKEDOWN_MAX_CELLS", MAX_CELLS)


# --------------------------------------------------------------------------
# the grid
# --------------------------------------------------------------------------
def _axis(name: str, value, lo, hi, *, hi_closed=False, lo_closed=True) -> list[float]:
    arr = check_range(name, value, lo, hi, lo_closed=lo_closed, hi_closed=hi_closed)
    if arr.ndim > 1:
        raise ValueError(f"{name} must be a number or a 1-D sequence, got an array of shape {arr.shape}")
    arr = np.atleast_1d(arr)
    if arr.size == 0:
        raise ValueError(f"{name} must have at least one value")
    return [float(v) for v in arr]


def _is_axis(value) -> bool:
    return isinstance(value, (list, tuple, range, np.ndarray, pd.Series, pd.Index)) and np.ndim(value) > 0


def _plain(value):
    """NumPy scalars to Python scalars (for tables, keys and pickling)."""
    return value.item() if isinstance(value, np.generic) else value


def _option_axes(options: dict) -> dict[str, list]:
    unknown = sorted(set(options) - set(_SOLVER_DEFAULTS))
    if unknown:
        raise ValueError(f"unknown solver option(s) {', '.join(map(repr, unknown))}; "
                         f"expected some of {', '.join(_SOLVER_DEFAULTS)}")
    axes = {}
    for name in ("periods", "dx", "kernel", "shape"):
        axes[name] = [_SOLVER_DEFAULTS[name]]
    for name, value in options.items():
        values = list(value) if _is_axis(value) else [value]
        if not values:
            raise ValueError(f"{name} must have at least one value")
        axes[name] = [_plain(v) for v in values]
    return axes


def _check_option(ft_values, w_values, option: dict, cells_cap: int) -> None:
    """Check one option combination before any work: its largest run against the cell cap, then
    every option as the solver sees it (a one-period run at rest, which raises the solver's own
    ``ValueError`` for a bad value)."""
    ft = max(ft_values, key=abs)
    w = max(w_values)
    dx = check_scalar("dx", option.get("dx", _SOLVER_DEFAULTS["dx"]), 1e-4, 0.5)
    dW = option.get("dW")
    schedule = rocking_schedule(ft, w, periods=option.get("periods", _SOLVER_DEFAULTS["periods"]),
                                dW=dx if dW is None else dW, shape=option.get("shape", _SOLVER_DEFAULTS["shape"]),
                                load_steps=option.get("load_steps", _SOLVER_DEFAULTS["load_steps"]))
    elements = make_grid(schedule.reach, dx).size - 1
    cells = len(schedule) * elements
    if cells > cells_cap:
        described = ", ".join(f"{k} = {v}" for k, v in option.items())
        raise ValueError(f"a run at w = {w:g} ({described}) would have {len(schedule)} steps x {elements} "
                         f"elements = {cells:.3g} cells (> {cells_cap:.3g}, see SHAKEDOWN_MAX_CELLS): "
                         "use fewer periods or a larger dx")
    try:
        simulate_cycles(0.0, 0.0, **{**option, "periods": 1})
    except ValueError:
        raise
    except Exception:  # noqa: BLE001 - not about the inputs (e.g. a tiny time budget); the runs will tell
        pass


def sweep_grid(ft, w, *, max_runs: int | None = None, max_cells: int | None = None, **solver_options) -> list[dict]:
    """The runs of a sweep: every combination of ``ft``, ``w`` and the option axes, in order.

    Parameters
    ----------
    ft : float or sequence of float
        ``Ft / (mu Fn)`` values, each in (-1, 1).
    w : float or sequence of float
        ``W / a`` values, each in [0, 1).
    max_runs : int, optional
        Cap on the number of runs (default :func:`default_max_runs`, 20000).
    max_cells : int, optional
        Cap on steps x elements of each run (default :func:`default_max_cells`).
    **solver_options
        Options of :func:`core.simulate_cycles`. A list, tuple, range or array
        makes that option a further axis; a scalar (or a string) is fixed.

    Returns
    -------
    list of dict
        One dict of keyword arguments of :func:`core.simulate_cycles` per run,
        ``ft`` varying slowest, then ``w``, then the options in the order
        given. Each has ``ft``, ``w``, ``periods``, ``dx``, ``kernel``,
        ``shape`` and every option given.

    Raises
    ------
    ValueError
        For values out of range, unknown options, or a grid beyond the caps.

    Examples
    --------
    >>> from core.sweeps import sweep_grid
    >>> [(p["ft"], p["w"], p["periods"]) for p in sweep_grid([0.1, 0.2], 0.5, periods=[5, 10])]
    [(0.1, 0.5, 5), (0.1, 0.5, 10), (0.2, 0.5, 5), (0.2, 0.5, 10)]
    """
    ft_values = _axis("ft", ft, -1.0, 1.0, lo_closed=False)
    w_values = _axis("w", w, 0.0, 1.0)
    axes = _option_axes(solver_options)
    runs_cap = default_max_runs() if max_runs is None else check_int("max_runs", max_runs, 1)
    cells_cap = default_max_cells() if max_cells is None else check_int("max_cells", max_cells, 1)
    n = len(ft_values) * len(w_values) * math.prod(len(v) for v in axes.values())
    if n > runs_cap:
        raise ValueError(f"the sweep would have {n} runs (> {runs_cap}, see SHAKEDOWN_MAX_RUNS): "
                         "use fewer values or raise the cap")
    names = list(axes)
    combos = [dict(zip(names, values)) for values in itertools.product(*axes.values())]
    for option in combos:
        _check_option(ft_values, w_values, option, cells_cap)
    return [{"ft": f, "w": x, **option} for f, x in itertools.product(ft_values, w_values) for option in combos]


# --------------------------------------------------------------------------
# one run, one chunk (these run in the workers)
# --------------------------------------------------------------------------
def _failed_row(message: str, runtime: float = float("nan")) -> dict:
    return {"regime": "error", "increment": float("nan"), "stick_halfwidth": float("nan"),
            "shakedown_period": None, "runtime": runtime, "max_kkt_residual": float("nan"),
            "max_iterations": None, "elements": None, "steps": None, "periodic_from": None,
            "error": message[:500]}


def _run_point(point: dict) -> dict:
    """Run one point; return its result columns. Never raises: a failure becomes an error row."""
    t0 = time.perf_counter()
    try:
        r = simulate_cycles(**point)
        s = r.summary()
    except Exception as e:  # noqa: BLE001 - a failing point must not stop the sweep
        return _failed_row(f"{type(e).__name__}: {e}", time.perf_counter() - t0)
    return {"regime": s["regime"], "increment": s["increment_last_period"], "stick_halfwidth": s["stick_halfwidth"],
            "shakedown_period": s["shakedown_period"], "runtime": s["runtime_s"],
            "max_kkt_residual": s["max_kkt_residual"], "max_iterations": s["max_iterations"],
            "elements": s["elements"], "steps": s["steps"], "periodic_from": s["periodic_from"], "error": None}


def _run_chunk(points: list[dict]) -> list[dict]:
    """Run a chunk of points in order (the unit of work sent to a worker)."""
    return [_run_point(p) for p in points]


def _warm_up() -> float:
    """Run the solver once (compiling it or loading numba's cache); return the seconds it took."""
    t0 = time.perf_counter()
    simulate_cycles(0.3, 0.3, periods=1)
    return time.perf_counter() - t0


def _init_worker(started) -> None:
    """Initializer of pool workers: one thread each, solver loaded before the first task."""
    os.environ.update(_WORKER_ENV)
    started.put((os.getpid(), _warm_up()))


def _nothing() -> None:
    return None


# --------------------------------------------------------------------------
# execution backends
# --------------------------------------------------------------------------
def _default_workers() -> int:
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


class _Serial:
    """Runs the tasks one after the other in the calling process."""

    def __init__(self, max_workers):
        self.name = "serial"
        self.workers = 1
        self.warmup = {"worker": _warm_up()}

    def run(self, fn, tasks, stopped):
        for i, task in enumerate(tasks):
            if stopped():
                return
            try:
                yield i, fn(task), None
            except Exception as e:  # noqa: BLE001 - reported per task
                yield i, None, e

    def close(self):
        pass


class _Futures:
    """Runs the tasks on something with futures; subclasses say how to submit and wait."""

    def run(self, fn, tasks, stopped):
        futures = self._submit(fn, tasks)
        index = {id(f): i for i, f in enumerate(futures)}
        pending = set(futures)
        try:
            while pending:
                if stopped():
                    return
                done, pending = self._wait(pending)
                for f in sorted(done, key=lambda f: index[id(f)]):
                    try:
                        yield index[id(f)], f.result(), None
                    except Exception as e:  # noqa: BLE001 - a lost worker or a cancelled task
                        yield index[id(f)], None, e
        finally:
            if pending:
                self._cancel(pending)

    def _submit(self, fn, tasks):
        return [self.executor.submit(fn, t) for t in tasks]

    def _wait(self, pending):
        done, pending = cf.wait(pending, timeout=_POLL_S, return_when=cf.FIRST_COMPLETED)
        return done, set(pending)

    def _cancel(self, pending):
        for f in pending:
            f.cancel()


class _Executor(_Futures):
    """A ``concurrent.futures.Executor`` given by the caller (left running)."""

    def __init__(self, executor):
        self.executor = executor
        self.name = type(executor).__name__
        self.workers = getattr(executor, "_max_workers", 1)
        self.warmup = {}

    def close(self):
        pass


class _Processes(_Futures):
    """A pool of ``max_workers`` local processes, started for one sweep."""

    def __init__(self, max_workers):
        self.workers = max_workers
        self.name = f"processes({max_workers})"
        ctx = multiprocessing.get_context("spawn")
        started = ctx.Queue()
        with _single_threaded_children():
            self.executor = cf.ProcessPoolExecutor(max_workers, mp_context=ctx, initializer=_init_worker,
                                                   initargs=(started,))
            # one task per worker starts them all now, under the single-threaded environment
            starts = [self.executor.submit(_nothing) for _ in range(max_workers)]
        # each worker reports its warm-up once it is ready
        self.warmup = {}
        deadline = time.perf_counter() + _START_TIMEOUT_S
        while len(self.warmup) < max_workers:
            try:
                pid, seconds = started.get(timeout=_POLL_S)
            except queue.Empty:
                if any(f.done() and f.exception() is not None for f in starts) or time.perf_counter() > deadline:
                    self.executor.shutdown(wait=False, cancel_futures=True)
                    raise RuntimeError(
                        "the worker processes failed to start. They import the main module again (the "
                        "'spawn' start method): run sweeps from a file guarded by "
                        "`if __name__ == \"__main__\":`, or pass scheduler='serial'") from None
                continue
            self.warmup[f"pid-{pid}"] = seconds

    def close(self):
        self.executor.shutdown(wait=True, cancel_futures=True)


class _Dask(_Futures):
    """A Dask cluster: an address, a ``distributed.Client`` or a cluster object."""

    def __init__(self, scheduler):
        try:
            import distributed
        except ImportError as e:
            raise ValueError("a Dask scheduler needs dask.distributed: pip install 'dask[distributed]'") from e
        self._distributed = distributed
        if isinstance(scheduler, distributed.Client):
            self.client, self._own = scheduler, False
        else:
            if isinstance(scheduler, str):
                _check_address(scheduler)
            elif not hasattr(scheduler, "scheduler_address"):
                raise ValueError("scheduler must be None, 'processes', 'serial', a concurrent.futures.Executor, "
                                 f"a Dask address, Client or cluster; got {type(scheduler).__name__}")
            try:
                self.client = distributed.Client(scheduler, set_as_default=False, timeout="10s")
            except (OSError, TimeoutError, ValueError) as e:
                raise ValueError(f"cannot connect to the Dask scheduler {scheduler!r:.100}: {e}") from e
            self._own = True
        self.workers = max(1, sum(self.client.nthreads().values()))
        self.name = f"dask({self.client.scheduler.address}, {self.workers} threads)"
        self.warmup = self.client.run(_warm_up)

    def _submit(self, fn, tasks):
        return self.client.map(fn, tasks, pure=False)

    def _wait(self, pending):
        try:
            done, pending = self._distributed.wait(list(pending), timeout=_POLL_S, return_when="FIRST_COMPLETED")
        except TimeoutError:
            return set(), pending
        return set(done), set(pending)

    def _cancel(self, pending):
        self.client.cancel(list(pending))

    def close(self):
        if self._own:
            self.client.close()


def _check_address(address: str) -> None:
    """Refuse a malformed Dask address before a Client is made (a failed Client lingers at exit)."""
    from distributed.comm import parse_address
    from distributed.comm.addressing import parse_host_port

    scheme, location = parse_address(address)
    if scheme in ("tcp", "tls", "ws", "wss"):
        try:
            parse_host_port(location)
        except ValueError as e:
            raise ValueError(f"scheduler must be a Dask address such as tcp://host:8786, got {address!r:.100} "
                             f"({e})") from e


def _backend(scheduler, max_workers, max_tasks):
    """Pick and start the execution backend (a small dispatch on ``scheduler``)."""
    if isinstance(scheduler, cf.Executor):
        return _Executor(scheduler)
    if isinstance(scheduler, str) and scheduler in ("serial", "processes"):
        workers = _default_workers() if max_workers is None else check_int("max_workers", max_workers, 1, 1024)
        workers = min(workers, max_tasks)
        if scheduler == "serial" or workers <= 1:
            return _Serial(1)
        _warm_up()  # fill numba's on-disk cache before the workers load it
        return _Processes(workers)
    if isinstance(scheduler, str) and len(scheduler) > 300:
        raise ValueError(f"scheduler must be a Dask address of at most 300 characters, got {scheduler!r:.60}...")
    return _Dask(scheduler)


def _run_tasks(fn, make_tasks, max_tasks, scheduler, max_workers, *, on_result, cancel=None, timeout=None):
    """Run ``fn`` over the tasks on the chosen backend; ``on_result(i, value, exc)`` as each finishes.

    ``make_tasks(workers)`` gives the tasks once the backend knows its number
    of workers (at most ``max_tasks`` are useful). Returns a dict of execution
    facts (backend, workers, warm-up times, wall time); raises
    :class:`SweepCancelled` (without a table) if stopped.
    """
    if timeout is not None:
        timeout = check_scalar("timeout", timeout, 0.0, None, lo_closed=False)
    if scheduler is None:
        scheduler = "processes"
    t0 = time.perf_counter()
    deadline = math.inf if timeout is None else t0 + timeout

    cancelled = _cancel_check(cancel)

    def stopped():
        return cancelled() or time.perf_counter() > deadline

    backend = _backend(scheduler, max_workers, max_tasks)
    t_started = time.perf_counter()
    tasks = make_tasks(backend.workers)
    finished = 0
    try:
        for i, value, exc in backend.run(fn, tasks, stopped):
            on_result(i, value, exc)
            finished += 1
    finally:
        backend.close()
    if finished < len(tasks):
        why = "cancelled" if cancelled() else f"timed out after {timeout:g} s"
        raise SweepCancelled(f"sweep {why}: {finished} of {len(tasks)} tasks finished")
    return {"backend": backend.name, "workers": backend.workers, "warmup_s": backend.warmup,
            "startup_s": t_started - t0, "wall_s": time.perf_counter() - t0}


def _cancel_check(cancel):
    """``cancel`` as a function: a ``threading.Event`` (set means stop) or a callable returning True to stop."""
    if cancel is None:
        return lambda: False
    if callable(getattr(cancel, "is_set", None)):
        return cancel.is_set
    if callable(cancel):
        return lambda: bool(cancel())
    raise ValueError(f"cancel must be a threading.Event or a callable, got {cancel!r:.60}")


def _progress_callback(progress, label="runs"):
    if progress is None or progress is False:
        return lambda done, total: None
    if progress is True:
        return ProgressBar(label=label)
    if callable(progress):
        return progress
    raise ValueError(f"progress must be None, True or a callable(done, total), got {progress!r:.60}")


# --------------------------------------------------------------------------
# tables
# --------------------------------------------------------------------------
def _tidy(rows: list[dict], columns) -> pd.DataFrame:
    """A table with fixed columns and dtypes (so that tables from any path, or read back, compare equal)."""
    df = pd.DataFrame(rows, columns=list(columns))
    return normalise_table(df)


def normalise_table(df: pd.DataFrame) -> pd.DataFrame:
    """Give a sweep table its canonical dtypes: nullable ints, str for text, float64 otherwise.

    Used on fresh tables and on tables read back from CSV or Parquet, so that
    they compare equal with :func:`pandas.testing.assert_frame_equal`.
    """
    df = df.copy()
    for col in df.columns:
        if col in _INT_COLUMNS:
            df[col] = pd.to_numeric(df[col]).astype("Int64")
        elif col in _STR_COLUMNS:
            df[col] = df[col].astype("str")
        elif col in ("detect_periodic",):
            df[col] = df[col].astype(bool)
        else:
            df[col] = pd.to_numeric(df[col], errors="coerce").astype("float64")
    return df.reset_index(drop=True)


def _input_columns(points: list[dict]) -> list[str]:
    names = list(INPUT_COLUMNS)
    for p in points:
        names += [k for k in p if k not in names]
    return names


def run_points(points, scheduler=None, *, max_workers=None, progress=None, on_rows=None, cancel=None,
               timeout=None, chunksize=None) -> pd.DataFrame:
    """Run a list of solver inputs (as made by :func:`sweep_grid`) in parallel; one row per point.

    Parameters
    ----------
    points : list of dict
        Keyword arguments of :func:`core.simulate_cycles`, one dict per run.
    scheduler, max_workers, progress, cancel, timeout
        See :func:`sweep`.
    on_rows : callable, optional
        ``on_rows(table)`` is called in the calling thread with the rows of
        each finished chunk (a DataFrame like the result's, in grid order
        within the chunk): the hook for incremental writes.
    chunksize : int, optional
        Runs per task; default: about eight tasks per worker, at most 32 runs each.

    Returns
    -------
    pandas.DataFrame
        See :func:`sweep`.
    """
    points = [dict(p) for p in points]
    n = len(points)
    columns = _input_columns(points) + list(RESULT_COLUMNS)
    if n == 0:
        return _tidy([], columns)
    if chunksize is not None:
        chunksize = check_int("chunksize", chunksize, 1, 100_000)
    report = _progress_callback(progress)
    chunks: list[list[dict]] = []

    def make_chunks(workers):
        size = chunksize or min(32, max(1, math.ceil(n / (8 * workers))))
        chunks.extend(points[i:i + size] for i in range(0, n, size))
        return chunks

    results: list[dict | None] = [None] * n
    done = 0

    def on_result(i, rows, exc):
        nonlocal done
        start = i * len(chunks[0])
        if exc is not None:  # the whole task was lost (worker died, cancelled, ...)
            rows = [_failed_row(f"task failed: {type(exc).__name__}: {exc}")] * len(chunks[i])
        for k, row in enumerate(rows):
            results[start + k] = {**points[start + k], **row}
        done += len(rows)
        if on_rows is not None:
            on_rows(_tidy(results[start:start + len(rows)], columns))
        report(done, n)

    report(0, n)
    try:
        info = _run_tasks(_run_chunk, make_chunks, n, scheduler, max_workers, on_result=on_result,
                          cancel=cancel, timeout=timeout)
    except SweepCancelled as e:
        e.table = _tidy([r for r in results if r is not None], columns)
        raise
    table = _tidy(results, columns)
    table.attrs.update(info, runs=n, chunksize=len(chunks[0]))
    return table


def sweep(ft, w, scheduler=None, *, max_workers=None, progress=None, cancel=None, timeout=None,
          max_runs=None, max_cells=None, **solver_options) -> pd.DataFrame:
    """Run the cycle solver over every combination of ``ft``, ``w`` and any option axes.

    Parameters
    ----------
    ft : float or sequence of float
        ``Ft / (mu Fn)`` values, each in (-1, 1).
    w : float or sequence of float
        Rocking amplitudes ``W / a``, each in [0, 1).
    scheduler : None, str, Executor or distributed.Client, optional
        Where to run: ``None`` or ``"processes"`` (a local process pool),
        ``"serial"`` (in this process), a ``concurrent.futures.Executor``, a
        Dask scheduler address such as ``"tcp://10.0.0.1:8786"``, a
        ``distributed.Client`` or a ``distributed.LocalCluster``.
    max_workers : int, optional
        Processes of the local pool (default: all cores). 1 runs in this process.
    progress : bool or callable, optional
        ``True`` draws a progress bar on stderr; a callable is called as
        ``progress(done, total)`` (runs) in the calling thread.
    cancel : threading.Event or callable, optional
        Set the event (from another thread), or return True from the
        callable, to stop the sweep; runs not started are dropped and
        :class:`SweepCancelled` is raised with the finished rows.
    timeout : float, optional
        Time budget [s]; past it the sweep stops like ``cancel``.
    max_runs, max_cells : int, optional
        Caps on the number of runs and on steps x elements per run (defaults:
        :func:`default_max_runs`, :func:`default_max_cells`).
    **solver_options
        Options of :func:`core.simulate_cycles` (``periods``, ``dx``, ``dW``,
        ``kernel``, ``shape``, ``load_steps``, ``L_over_a``, ``nu``, ``tol``,
        ``detect_periodic``, ``shakedown_rtol``, ``time_budget``: a run past
        its budget becomes an error row). A list, tuple, range or
        array makes the option a further axis of the product; a scalar or a
        string is the same for every run.

    Returns
    -------
    pandas.DataFrame
        One row per run, ``ft`` varying slowest, then ``w``, then the option
        axes in the order given. Columns: the inputs (``ft``, ``w``,
        ``periods``, ``dx``, ``kernel``, ``shape`` and every option given),
        then ``regime`` (``"shakedown"``, ``"ratcheting"`` or ``"error"``),
        ``increment`` (rigid-body displacement in the last period [mu P/E*]),
        ``stick_halfwidth`` (``c_sd / a``), ``shakedown_period`` (first
        period below the shakedown tolerance, else NA), ``runtime`` (solve
        time [s]), ``max_kkt_residual``, ``max_iterations`` (active-set
        iterations of the hardest step), ``elements``, ``steps``,
        ``periodic_from`` (period from which the state repeated) and ``error``
        (the message of a failed run, else NA). ``table.attrs`` records the
        backend, the number of workers, warm-up and wall times.

    Raises
    ------
    ValueError
        Inputs out of range, an unknown option, a sweep beyond the caps, or an
        unreachable Dask scheduler.
    SweepCancelled
        If ``cancel`` was set or ``timeout`` passed.

    Notes
    -----
    Runs that fail do not stop the sweep: their row has ``regime = "error"``
    and the message in ``error``. The solver is deterministic, so the local
    pool, the serial path and a Dask cluster return equal tables except for
    the measured ``runtime``.

    Examples
    --------
    >>> from core.sweeps import sweep  # also core.sweep
    >>> table = sweep([0.1, 0.6], 0.5, scheduler="serial", periods=6)
    >>> table[["ft", "w", "regime"]]
        ft    w      regime
    0  0.1  0.5   shakedown
    1  0.6  0.5  ratcheting
    """
    points = sweep_grid(ft, w, max_runs=max_runs, max_cells=max_cells, **solver_options)
    return run_points(points, scheduler, max_workers=max_workers, progress=progress, cancel=cancel,
                      timeout=timeout)


# --------------------------------------------------------------------------
# the numerical shakedown limit
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class LimitResult:
    """The numerical shakedown limit ``w_lim`` for one ``ft``, found by bisection.

    Attributes
    ----------
    ft : float
        The tangential load ``Ft / (mu Fn)``.
    w_limit : float
        Midpoint of the final bracket: the numerical limit, within ``tol`` of
        the regime change (NaN if the search failed).
    w_shakedown, w_ratcheting : float
        The final bracket: the largest ``w`` that shook down and the smallest
        that ratcheted (NaN if not found).
    tol : float
        Tolerance in ``w``: ``(w_ratcheting - w_shakedown) / 2 <= tol``.
    w_limit_eq35 : float
        The exact limit of eq 35 (:func:`core.w_limit`) for comparison.
    converged : bool
        Whether the bracket closed to ``tol``.
    message : str
        What happened, in words.
    runs : pandas.DataFrame
        Every run of the search (the sweep table's columns), in the order run.
    """

    ft: float
    w_limit: float
    w_shakedown: float
    w_ratcheting: float
    tol: float
    w_limit_eq35: float
    converged: bool
    message: str
    runs: pd.DataFrame = field(repr=False, compare=False)

    @property
    def difference(self) -> float:
        """``w_limit - w_limit_eq35``: how far the numerical limit lies from eq 35."""
        return self.w_limit - self.w_limit_eq35

    def as_row(self) -> dict:
        """The scalars, for a table row."""
        return {"ft": self.ft, "w_limit": self.w_limit, "w_shakedown": self.w_shakedown,
                "w_ratcheting": self.w_ratcheting, "tol": self.tol, "w_limit_eq35": self.w_limit_eq35,
                "difference": self.difference, "runs": len(self.runs), "converged": self.converged,
                "runtime": float(self.runs["runtime"].sum()), "message": self.message}


def _limit_search(ft: float, tol: float, options: dict) -> LimitResult:
    """Bracket and bisect the regime change in ``w`` for one ``ft`` (runs in a worker)."""
    w35 = float(_w_limit_eq35(ft))
    runs: list[dict] = []
    columns = _input_columns([{"ft": ft, "w": 0.0, **options}]) + list(RESULT_COLUMNS)
    verdicts: dict[float, bool] = {}

    def shakes_down(w: float) -> bool:
        if w in verdicts:
            return verdicts[w]
        point = {"ft": ft, "w": w, **options}
        row = {**point, **_run_point(point)}
        runs.append(row)
        if row["regime"] == "error":
            raise RuntimeError(f"the run at w = {w:.6g} failed: {row['error']}")
        verdicts[w] = row["regime"] == "shakedown"
        return verdicts[w]

    def result(lo, hi, converged, message):
        mid = 0.5 * (lo + hi) if converged else float("nan")
        return LimitResult(ft, mid, lo, hi, tol, w35, converged, message, _tidy(runs, columns))

    try:
        # bracket around eq 35, widening until the regimes differ at the ends
        step = max(4.0 * tol, 0.02)
        lo, hi = max(0.0, min(w35, _W_MAX) - step), min(_W_MAX, w35 + step)
        while not shakes_down(lo):
            if lo == 0.0:
                return result(float("nan"), 0.0, False, f"ratchets even at w = 0 (ft = {ft:g})")
            lo, hi, step = max(0.0, lo - 2 * step), lo, 2 * step
        while shakes_down(hi):
            if hi == _W_MAX:
                return result(hi, float("nan"), False, f"shakes down up to w = {_W_MAX:g}")
            lo, hi, step = hi, min(_W_MAX, hi + 2 * step), 2 * step
        # bisect
        while hi - lo > 2.0 * tol:
            mid = 0.5 * (lo + hi)
            if shakes_down(mid):
                lo = mid
            else:
                hi = mid
    except RuntimeError as e:
        return result(float("nan"), float("nan"), False, str(e))
    return result(lo, hi, True, f"bracket [{lo:.6g}, {hi:.6g}] after {len(runs)} runs")


def _limit_options(tol, options) -> tuple[float, dict]:
    tol = check_scalar("tol", tol, 1e-6, 0.1)
    for name, value in options.items():
        if _is_axis(value):
            raise ValueError(f"{name} must be a single value for a limit search, got a sequence")
    # validate the options (and the caps) once, on the widest rocking the search may try
    probe = sweep_grid(0.5, _W_MAX, **options)[0]
    probe.pop("ft")
    probe.pop("w")
    return tol, probe


def numerical_limit(ft, tol=1e-3, **solver_options) -> LimitResult:
    """The numerical shakedown limit for one ``ft``, with the bracketing runs and diagnostics.

    Parameters
    ----------
    ft : float
        ``Ft / (mu Fn)`` in (0, 1).
    tol : float
        Tolerance in ``w``, in [1e-6, 0.1]: the returned limit lies within
        ``tol`` of every ``w`` where the verdict changes in the final bracket.
    **solver_options
        Options of :func:`core.simulate_cycles` (single values).

    Returns
    -------
    LimitResult

    Notes
    -----
    The search starts from a bracket of +-max(4 tol, 0.02) around eq 35
    (:func:`core.w_limit`), widens it until the lower end shakes down and
    the upper end ratchets, then bisects; about ``log2(0.04 / tol) + 2`` runs.
    It assumes that the verdict changes once in ``w``. The verdict depends on
    ``periods`` and ``shakedown_rtol``: just past the limit the ratcheting
    increment is still below ``shakedown_rtol`` times the first period's, so
    the default verdict (1e-3, 10 periods) puts the limit 0.7e-4 to 1.9e-4
    above eq 35 at ``dx = 1/40``; with ``shakedown_rtol=1e-6`` and 40 periods
    it agrees with eq 35 to 1e-5. Just below the limit shakedown is slow, so
    too few periods pull the limit below eq 35 (``dx = 1/80``, ``ft = 0.1``:
    -1.4e-3 with 10 periods, +1.3e-4 with 40).

    Examples
    --------
    >>> import core
    >>> res = core.numerical_limit(0.5, tol=0.01, periods=6)
    >>> bool(res.converged), abs(res.difference) < 0.05
    (True, True)
    """
    ft = check_scalar("ft", ft, 0.0, 1.0, lo_closed=False, hi_closed=False)
    tol, options = _limit_options(tol, solver_options)
    return _limit_search(ft, tol, options)


def numerical_w_limit(ft, tol=1e-3, **solver_options) -> float:
    """The numerical shakedown limit ``w_lim`` for one ``ft``, to ``tol`` in ``w``.

    The largest rocking amplitude ``W / a`` that still shakes down in the
    cycle solver, found by bisection (see :func:`numerical_limit`, which also
    returns the runs and the bracket).

    Parameters
    ----------
    ft : float
        ``Ft / (mu Fn)`` in (0, 1).
    tol : float
        Tolerance in ``w`` (default 1e-3).
    **solver_options
        Options of :func:`core.simulate_cycles` (single values).

    Returns
    -------
    float
        ``w_lim`` (NaN if the regime does not change in [0, 0.999]).

    Examples
    --------
    >>> import core
    >>> w = core.numerical_w_limit(0.5, tol=0.01, periods=6)
    >>> abs(w - float(core.w_limit(0.5))) < 0.05
    True
    """
    return numerical_limit(ft, tol, **solver_options).w_limit


def _limit_task(args) -> LimitResult:
    ft, tol, options = args
    return _limit_search(ft, tol, options)


def numerical_limit_curve(ft_values, tol=1e-3, scheduler=None, *, max_workers=None, progress=None, cancel=None,
                          timeout=None, **solver_options) -> pd.DataFrame:
    """The numerical limit ``w_lim(ft)`` for several ``ft``, searched in parallel.

    Each ``ft`` is one task (a whole bisection, :func:`numerical_limit`) on
    the same backends as :func:`sweep`.

    Parameters
    ----------
    ft_values : sequence of float
        Values of ``Ft / (mu Fn)``, each in (0, 1); at most :func:`default_max_runs`.
    tol : float
        Tolerance in ``w`` of every limit.
    scheduler, max_workers, progress, cancel, timeout
        As for :func:`sweep` (``progress`` counts ``ft`` values).
    **solver_options
        Options of :func:`core.simulate_cycles` (single values).

    Returns
    -------
    pandas.DataFrame
        One row per ``ft`` in the order given: ``ft``, ``w_limit``,
        ``w_shakedown``, ``w_ratcheting``, ``tol``, ``w_limit_eq35``,
        ``difference`` (``w_limit - w_limit_eq35``), ``runs``, ``converged``,
        ``runtime`` (solver time summed over the runs [s]) and ``message``.
        ``table.attrs["results"]`` holds the :class:`LimitResult` objects.
    """
    ft_list = _axis("ft", ft_values, 0.0, 1.0, lo_closed=False)
    cap = default_max_runs()
    if len(ft_list) > cap:
        raise ValueError(f"{len(ft_list)} ft values (> {cap}, see SHAKEDOWN_MAX_RUNS)")
    tol, options = _limit_options(tol, solver_options)
    report = _progress_callback(progress, label="ft values")
    results: list[LimitResult | None] = [None] * len(ft_list)

    def on_result(i, value, exc):
        results[i] = value if exc is None else LimitResult(
            ft_list[i], float("nan"), float("nan"), float("nan"), tol, float(_w_limit_eq35(ft_list[i])), False,
            f"task failed: {type(exc).__name__}: {exc}", _tidy([], list(INPUT_COLUMNS) + list(RESULT_COLUMNS)))
        report(sum(r is not None for r in results), len(ft_list))

    def table():
        done = [r for r in results if r is not None]
        df = pd.DataFrame([r.as_row() for r in done],
                          columns=["ft", "w_limit", "w_shakedown", "w_ratcheting", "tol", "w_limit_eq35",
                                   "difference", "runs", "converged", "runtime", "message"])
        df = df.astype({"runs": "int64", "converged": bool})
        df.attrs["results"] = done
        return df

    report(0, len(ft_list))
    try:
        info = _run_tasks(_limit_task, lambda workers: [(f, tol, options) for f in ft_list], len(ft_list),
                          scheduler, max_workers, on_result=on_result, cancel=cancel, timeout=timeout)
    except SweepCancelled as e:
        e.table = table()
        raise
    out = table()
    out.attrs.update(info)
    return out


# --------------------------------------------------------------------------
# progress on a terminal
# --------------------------------------------------------------------------
class ProgressBar:
    """A one-line progress bar: ``progress(done, total)`` redraws it on ``stream`` (stderr).

    On a terminal the line is redrawn in place (at most ten times a second);
    otherwise (a log file) a line is written at every tenth of the work.

    Parameters
    ----------
    stream : file, optional
        Where to draw (default ``sys.stderr``).
    label : str
        What is counted.
    width : int
        Characters of the bar.
    """

    def __init__(self, stream=None, label: str = "runs", width: int = 30):
        self.stream = sys.stderr if stream is None else stream
        self.label, self.width = label, width
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._t0 = time.perf_counter()
        self._last_draw = -math.inf
        self._last_tenth = -1

    def line(self, done: int, total: int) -> str:
        """The text of the bar."""
        frac = done / total if total else 1.0
        filled = int(round(frac * self.width))
        elapsed = time.perf_counter() - self._t0
        eta = elapsed / done * (total - done) if done else float("nan")
        eta_s = f"eta {eta:.0f} s" if done and done < total else ""
        return (f"[{'#' * filled}{'.' * (self.width - filled)}] {done}/{total} {self.label} "
                f"{100 * frac:3.0f}%  {elapsed:.1f} s {eta_s}").rstrip()

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        final = done >= total
        if self.tty:
            if final or now - self._last_draw >= 0.1:
                self.stream.write("\r" + self.line(done, total) + ("\n" if final else ""))
                self.stream.flush()
                self._last_draw = now
            return
        tenth = int(10 * done / total) if total else 10
        if tenth != self._last_tenth:
            self.stream.write(self.line(done, total) + "\n")
            self.stream.flush()
            self._last_tenth = tenth


# --------------------------------------------------------------------------
# the shipped map
# --------------------------------------------------------------------------
def load_default_map() -> pd.DataFrame:
    """The numerical (ft, w) map shipped with the package, as a sweep table.

    A 40 x 40 grid over ``ft, w`` in [0.02, 0.95] at the solver's default
    resolution (plane-strain kernel, triangle rocking, ``dx = dW = 1/40``, 10
    periods), made with the command recorded in ``core/data/README.md``.

    Returns
    -------
    pandas.DataFrame
        The columns of :func:`sweep`; ``attrs["source"]`` names the file.

    Examples
    --------
    >>> import core
    >>> m = core.load_default_map()
    >>> len(m), sorted(m["regime"].unique())
    (1600, ['ratcheting', 'shakedown'])
    """
    path = resources.files("core") / "data" / DEFAULT_MAP
    with resources.as_file(path) as p:
        table = normalise_table(pd.read_csv(p))
    table.attrs["source"] = f"core/data/{DEFAULT_MAP}"
    return table
