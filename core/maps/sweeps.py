"""Maps of the cycle solver over parameters, run in parallel: :func:`sweep` and :func:`run_points`.

:func:`sweep` runs :func:`core.simulate_cycles` for every combination of its
inputs and returns a tidy table, one row per run. The work is split between
modules with one job each:

* :mod:`core.maps.grid`: the runs of a sweep (any solver option may be an axis),
  checked against the caps before any work;
* :mod:`core.maps.tasks`: where they run, always through the
  ``concurrent.futures.Executor`` interface (this process, local processes,
  your executor, a Dask cluster);
* :mod:`core.maps.tables`: the table's columns and dtypes, one row per run, files
  that a sweep resumes, the shipped map;
* :mod:`core.maps.limits_search`: the numerical shakedown limit;
* :mod:`core.base.progress`: the progress bar.

The solver is deterministic, so every path gives the same table for the same
inputs (only the measured ``runtime`` differs); the rows come in the order of
the grid whatever order the runs finish in. Work is sent in chunks of runs so
that the per-task overhead stays small, and a run that fails becomes a row
with ``regime = "error"`` and its message: it does not stop the sweep.
"""

from __future__ import annotations

import math

import pandas as pd

from ..base._validate import check_int
from .grid import MAX_CELLS, MAX_RUNS, default_max_cells, default_max_runs, run_cells, sweep_grid
from .limits_search import LimitResult, numerical_limit, numerical_limit_curve, numerical_w_limit
from ..base.progress import ProgressBar, progress_callback
from .tables import (DEFAULT_MAP, INPUT_COLUMNS, RESULT_COLUMNS, failed_row, input_columns, load_default_map,
                     normalise_table, run_chunk, tidy)
from .tasks import SweepCancelled, run_tasks

__all__ = [
    "sweep", "sweep_grid", "run_points", "numerical_w_limit", "numerical_limit", "numerical_limit_curve",
    "LimitResult", "SweepCancelled", "ProgressBar", "load_default_map", "default_max_runs", "default_max_cells",
    "normalise_table", "MAX_RUNS", "MAX_CELLS", "DEFAULT_MAP", "INPUT_COLUMNS", "RESULT_COLUMNS",
]


def _job_cells(points) -> float | None:
    """Summed steps x elements of the runs (None if some cannot be told beforehand)."""
    total = 0
    for p in points:
        cells = run_cells(p)
        if cells is None:
            return None
        total += cells
    return total


def run_points(points, scheduler=None, *, workers=None, max_workers=None, progress=None, on_rows=None,
               cancel=None, timeout=None, chunksize=None) -> pd.DataFrame:
    """Run a list of solver inputs (as made by :func:`sweep_grid`) in parallel; one row per point.

    Parameters
    ----------
    points : list of dict
        Keyword arguments of :func:`core.simulate_cycles`, one dict per run.
    scheduler, workers, max_workers, progress, cancel, timeout
        See :func:`sweep`.
    on_rows : callable, optional
        ``on_rows(table)`` is called in the calling thread with the rows of
        each finished chunk (a DataFrame like the result's, in grid order
        within the chunk): the hook for incremental writes
        (:meth:`core.maps.tables.TableFile.append`).
    chunksize : int, optional
        Runs per task; default: about eight tasks per worker, at most 32 runs each.

    Returns
    -------
    pandas.DataFrame
        See :func:`sweep`.
    """
    points = [dict(p) for p in points]
    n = len(points)
    columns = input_columns(points) + list(RESULT_COLUMNS)
    if n == 0:
        return tidy([], columns)
    if chunksize is not None:
        chunksize = check_int("chunksize", chunksize, 1, 100_000)
    if max_workers is not None:
        if workers is not None:
            raise ValueError("give workers or max_workers (its old name), not both")
        workers = max_workers
    report = progress_callback(progress)
    chunks: list[list[dict]] = []

    def make_chunks(n_workers):
        size = chunksize or min(32, max(1, math.ceil(n / (8 * n_workers))))
        chunks.extend(points[i:i + size] for i in range(0, n, size))
        return chunks

    results: list[dict | None] = [None] * n
    done = 0

    def on_result(i, rows, exc):
        nonlocal done
        start = i * len(chunks[0])
        if exc is not None:  # the whole task was lost (worker died, cancelled, ...)
            rows = [failed_row(f"task failed: {type(exc).__name__}: {exc}")] * len(chunks[i])
        for k, row in enumerate(rows):
            results[start + k] = {**points[start + k], **row}
        done += len(rows)
        if on_rows is not None:
            on_rows(tidy(results[start:start + len(rows)], columns))
        report(done, n)

    report(0, n)
    try:
        # run_chunk is looked up here, at call time, so that it can be replaced (tests interrupt a sweep with it)
        info = run_tasks(globals()["run_chunk"], make_chunks, workers=workers, scheduler=scheduler,
                         on_result=on_result, cancel=cancel, timeout=timeout, cells=_job_cells(points), runs=n)
    except SweepCancelled as e:
        e.table = tidy([r for r in results if r is not None], columns)
        raise
    table = tidy(results, columns)
    table.attrs.update(info, runs=n, chunksize=len(chunks[0]))
    return table


def sweep(ft, w, scheduler=None, *, workers=None, max_workers=None, progress=None, cancel=None, timeout=None,
          max_runs=None, max_cells=None, **solver_options) -> pd.DataFrame:
    """Run the cycle solver over every combination of ``ft``, ``w`` and any option axes.

    Parameters
    ----------
    ft : float or sequence of float
        ``Ft / (mu Fn)`` values, each in (-1, 1).
    w : float or sequence of float
        Rocking amplitudes ``W / a``, each in [0, 1).
    scheduler : None, str, Executor, distributed.Client or cluster, optional
        A Dask cluster to run on: a scheduler address such as
        ``"tcp://10.0.0.1:8786"``, a ``distributed.Client`` or a cluster
        object such as ``distributed.LocalCluster`` (its executor,
        ``client.get_executor()``, runs the tasks). Also accepted:
        ``"serial"`` (``workers=1``), ``"processes"`` (local processes) and
        a ``concurrent.futures.Executor`` (as ``workers``).
    workers : None, int, Executor or callable, optional
        Local execution, as scipy's ``workers=``: ``1`` in this process,
        ``N`` a pool of N processes, ``-1`` one per core, a
        ``concurrent.futures.Executor`` (used, left running) or a map-like
        callable (``pool.map``). Default ``None``: by the size of the job, so
        that a small sweep runs in this process instead of waiting for a pool
        to start (:func:`core.maps.tasks.auto_workers`).
    max_workers : int, optional
        The old name of ``workers`` (an int).
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
        Any keyword option of :func:`core.simulate_cycles` (``periods``,
        ``dx``, ``dW``, ``kernel``, ``shape``, ``load_steps``, ``L_over_a``,
        ``nu``, ``tol``, ``detect_periodic``, ``shakedown_rtol``,
        ``time_budget`` (a run past its budget becomes an error row), the body
        and the loading history where the solver has them; ``dx`` defaults to
        the body's grid, :func:`core.geometry.resolution.default_dx`). A list, tuple,
        range or array makes the option a further axis of the product; a
        scalar or a string is the same for every run.

    Returns
    -------
    pandas.DataFrame
        One row per run, ``ft`` varying slowest, then ``w``, then the option
        axes in the order given. Columns: the inputs (``ft``, ``w``,
        ``periods``, ``dx``, ``kernel``, ``shape`` and every option given),
        then ``regime`` (``"shakedown"``, ``"cyclic slip"``, ``"ratcheting"``,
        ``"undetermined"`` when the periods run cannot tell, or ``"error"``),
        ``regime_reason`` (why, in words), ``increment`` (rigid-body
        displacement in the last period [mu P/E*]), ``D_inf`` and
        ``D_inf_error`` (the limit the increments tend to, with its standard
        error, from the fit of the verdict, :func:`core.records.result.fit_trend`),
        ``decay_ratio`` (``r``, the factor by which the changing part of the
        increment shrinks each period), ``periods_to_decide`` (for an
        undetermined run, the more periods likely to decide), ``energy`` (the
        energy dissipated by friction in the last period [mu^2 P^2/E* per unit
        length; a point contact mu^2 Fn^2/(E* a)]), ``E_inf`` and
        ``E_inf_error`` (the limit the energies per period tend to, with its
        standard error: zero in a shakedown, the energy of the steady loop in
        cyclic slip and ratcheting), ``stick_halfwidth``
        (``c_sd / a``), ``shakedown_period`` (first period below the shakedown
        tolerance, else NA), ``runtime`` (solve time [s]),
        ``max_kkt_residual``, ``max_iterations`` (active-set iterations of the
        hardest step), ``elements``, ``steps``, ``periodic_from`` (period from
        which the state repeated) and ``error`` (the message of a failed run,
        else NA). ``table.attrs`` records the backend, the number of workers,
        warm-up and wall times.

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
    the measured ``runtime``. Scripts that start local processes need an
    ``if __name__ == "__main__":`` guard (the workers start with "spawn").

    Examples
    --------
    >>> from core import sweep
    >>> table = sweep([0.1, 0.6], 0.5, workers=1, periods=6)
    >>> table[["ft", "w", "regime"]]
        ft    w      regime
    0  0.1  0.5   shakedown
    1  0.6  0.5  ratcheting
    """
    points = sweep_grid(ft, w, max_runs=max_runs, max_cells=max_cells, **solver_options)
    return run_points(points, scheduler, workers=workers, max_workers=max_workers, progress=progress, cancel=cancel,
                      timeout=timeout)
