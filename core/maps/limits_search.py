"""The numerical shakedown limit ``w_lim(ft)``, found by the solver alone and then set beside eq 35.

For one ``ft`` the search runs :func:`core.simulate_cycles` at the ends of
the whole range of rocking, ``w = 0`` (it must shake down) and
``w = 0.999`` (it must ratchet), and bisects between them. Eq 35
(:func:`core.w_limit`) is not used to place any run: it is only compared with
the final bracket afterwards (:attr:`LimitResult.eq35_inside`).

The same search runs for every body :func:`core.simulate_cycles` has
(``body="sphere"``, ...), each at its own default grid
(:func:`core.geometry.resolution.default_dx`), and compares the bracket with that
body's exact limit (:func:`core.w_limit` with ``body=``: eq 35 for the
cylinder, ``ft = 1 - 3w/2 + w^3/2`` for the point contacts). The columns keep
their names ``w_limit_eq35`` and ``eq35_inside`` for every body.

The bracket separates the runs whose body stops walking (``"shakedown"``, and
``"cyclic slip"``, which counts as not ratcheting: :data:`NOT_RATCHETING`)
from those that ratchet.

A run whose periods cannot tell the regime (``"undetermined"``, see
:attr:`core.CycleResult.verdict`) is run again with twice the periods, up to
:data:`MAX_PERIOD_DOUBLINGS` times. A run that still cannot tell lies close to
the limit (the increments decay ever more slowly there): the search then
tries ``w -+ tol/2`` on either side of it, and if those decide, the bracket
between them is at most ``tol`` wide and the search is done; otherwise it
stops and says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

from ..base._validate import check_scalar
from .grid import W_MAX, axis, default_max_runs, is_axis, sweep_grid
from ..base.progress import progress_callback
from .tables import INPUT_COLUMNS, RESULT_COLUMNS, input_columns, run_point, tidy
from .tasks import SweepCancelled, run_tasks

__all__ = ["LimitResult", "numerical_limit", "numerical_w_limit", "numerical_limit_curve", "MAX_PERIOD_DOUBLINGS",
           "LIMIT_COLUMNS", "NOT_RATCHETING"]

#: Regimes on the shakedown side of the bracket: the body does not walk (a cyclic slip counts with shakedown).
NOT_RATCHETING = ("shakedown", "cyclic slip")
#: Times an undetermined run is repeated with twice the periods before the search gives up.
MAX_PERIOD_DOUBLINGS = 3
#: Columns of :func:`numerical_limit_curve`'s table.
LIMIT_COLUMNS = ("ft", "start_lo", "start_hi", "w_shakedown", "w_ratcheting", "w_limit", "tol", "w_limit_eq35",
                 "eq35_inside", "exact_within_tol", "difference", "periods", "runs", "converged", "runtime", "message")


@dataclass(frozen=True)
class LimitResult:
    """The numerical shakedown limit ``w_lim`` for one ``ft``, found by bisection without eq 35.

    Attributes
    ----------
    ft : float
        The tangential load ``Ft / (mu Fn)``.
    start_lo, start_hi : float
        The bracket the search started from: the ends of the range of ``w``
        (0 and 0.999), not eq 35.
    w_shakedown, w_ratcheting : float
        The final bracket: the largest ``w`` that shook down and the smallest
        that ratcheted (NaN if not found).
    w_limit : float
        Midpoint of the final bracket: the numerical limit, within ``tol`` of
        the regime change (NaN if the search failed).
    tol : float
        Tolerance in ``w``: ``(w_ratcheting - w_shakedown) / 2 <= tol``.
    w_limit_eq35 : float
        The exact limit of the body (:func:`core.w_limit` with ``body=``: eq 35
        for the cylinder, the inverse of ``1 - 3w/2 + w^3/2`` for the point
        contacts), for comparison only.
    converged : bool
        Whether the bracket closed to ``tol``.
    message : str
        What happened, in words.
    runs : pandas.DataFrame
        Every run of the search (the sweep table's columns), in the order run.
    periods : int
        The most periods a run of the search needed to decide its regime.
    """

    ft: float
    start_lo: float
    start_hi: float
    w_shakedown: float
    w_ratcheting: float
    w_limit: float
    tol: float
    w_limit_eq35: float
    converged: bool
    message: str
    runs: pd.DataFrame = field(repr=False, compare=False)
    periods: int = 0

    @property
    def eq35_inside(self) -> bool:
        """Whether eq 35's limit lies in the final bracket ``[w_shakedown, w_ratcheting]``."""
        return bool(self.w_shakedown <= self.w_limit_eq35 <= self.w_ratcheting)

    @property
    def exact_within_tol(self) -> bool:
        """Whether the exact limit lies in the final bracket widened by ``tol`` on each side.

        The bracket is the search's, within its tolerance: just past the limit
        a ratcheting increment may still be below ``shakedown_rtol`` of the
        first period's, so the largest ``w`` that shook down may lie a little
        above the exact limit (see :func:`numerical_limit`).
        """
        return bool(self.w_shakedown - self.tol <= self.w_limit_eq35 <= self.w_ratcheting + self.tol)

    @property
    def difference(self) -> float:
        """``w_limit - w_limit_eq35``: the midpoint's offset from eq 35 (at most ``tol`` when eq 35 is inside)."""
        return self.w_limit - self.w_limit_eq35

    def as_row(self) -> dict:
        """The scalars, for a table row (:data:`LIMIT_COLUMNS`)."""
        return {"ft": self.ft, "start_lo": self.start_lo, "start_hi": self.start_hi,
                "w_shakedown": self.w_shakedown, "w_ratcheting": self.w_ratcheting, "w_limit": self.w_limit,
                "tol": self.tol, "w_limit_eq35": self.w_limit_eq35, "eq35_inside": self.eq35_inside,
                "exact_within_tol": self.exact_within_tol,
                "difference": self.difference, "periods": self.periods, "runs": len(self.runs),
                "converged": self.converged, "runtime": float(self.runs["runtime"].sum()), "message": self.message}


def _limit_search(ft: float, tol: float, options: dict) -> LimitResult:
    """Bracket and bisect the regime change in ``w`` for one ``ft`` (runs in a worker)."""
    from ..bounds.limits import w_limit as w_limit_eq35

    runs: list[dict] = []
    columns = input_columns([{"ft": ft, "w": 0.0, **options}]) + list(RESULT_COLUMNS)
    verdicts: dict[float, bool] = {}
    base_periods = options["periods"]
    most_periods = base_periods

    def shakes_down(w: float) -> bool:
        """Whether the run at ``w`` shakes down; :class:`_Undetermined` if its periods cannot tell."""
        nonlocal most_periods
        if w in verdicts:
            return verdicts[w]
        periods = base_periods
        for doubling in range(MAX_PERIOD_DOUBLINGS + 1):
            point = {"ft": ft, "w": w, **options, "periods": periods}
            row = {**point, **run_point(point)}
            runs.append(row)
            if row["regime"] == "error":
                raise RuntimeError(f"the run at w = {w:.6g} failed: {row['error']}")
            if row["regime"] != "undetermined" or periods >= 10_000 or doubling == MAX_PERIOD_DOUBLINGS:
                break
            periods = min(2 * periods, 10_000)
        most_periods = max(most_periods, periods)
        if row["regime"] == "undetermined":
            raise _Undetermined(f"the regime at w = {w:.6g} is undetermined after {periods} periods: "
                                f"{row['regime_reason']}")
        # the search is for the ratcheting limit: cyclic slip (no walk, slip every period) is "not ratcheting".
        # Under the rocking histories' constant tangential load it does not occur (docs/guide/regimes.md)
        verdicts[w] = row["regime"] in NOT_RATCHETING
        return verdicts[w]

    lo, hi = 0.0, W_MAX

    def result(w_sd, w_r, converged, message):
        mid = 0.5 * (w_sd + w_r) if converged else float("nan")
        if options.get("beta", 0.0):  # coupled: Melan's theorem does not hold, the exact limit is the uncoupled one
            message += (f"; coupled (beta = {options['beta']:g}, mu = {options.get('mu')}): w_limit_eq35 is the "
                        "uncoupled reference, not the limit")
        return LimitResult(ft, lo_start, hi_start, w_sd, w_r, mid, tol, float(w_limit_eq35(ft, body=options.get("body", "cylinder"))), converged, message,
                           tidy(runs, columns), most_periods)

    lo_start, hi_start = lo, hi
    nan = float("nan")
    try:
        if not shakes_down(lo):
            return result(nan, lo, False, f"ratchets even at w = 0 (ft = {ft:g})")
        if shakes_down(hi):
            return result(hi, nan, False, f"shakes down up to w = {hi:g}")
        while hi - lo > 2.0 * tol:
            mid = 0.5 * (lo + hi)
            try:
                if shakes_down(mid):
                    lo = mid
                else:
                    hi = mid
            except _Undetermined as e:  # close to the limit: decide on either side, tol apart
                near = [max(lo, mid - 0.5 * tol), min(hi, mid + 0.5 * tol)]
                try:
                    if not shakes_down(near[0]) or shakes_down(near[1]):
                        raise _Undetermined(f"{e}; and the runs at w = {near[0]:.6g} and {near[1]:.6g} do not "
                                            "bracket the limit")
                except _Undetermined as inner:
                    raise RuntimeError(str(inner)) from None
                lo, hi = near
    except RuntimeError as e:  # not to tol: the bracket of the runs that decided, around the undetermined one
        decided_sd = [w for w, sd in verdicts.items() if sd]
        decided_r = [w for w, sd in verdicts.items() if not sd]
        w_sd, w_r = max(decided_sd, default=nan), min(decided_r, default=nan)
        if w_sd < w_r:  # (False with a NaN)
            return result(w_sd, w_r, False, f"not to the tolerance: the limit is in [{w_sd:.6g}, {w_r:.6g}] (the "
                                            f"highest run that shook down, the lowest that ratcheted), but {e}")
        return result(nan, nan, False, str(e))
    return result(lo, hi, True, f"from [{lo_start:g}, {hi_start:g}] to [{lo:.6g}, {hi:.6g}] in {len(runs)} runs")


class _Undetermined(RuntimeError):
    """A run of the limit search whose periods could not tell its regime."""


def _limit_options(tol, options) -> tuple[float, dict]:
    tol = check_scalar("tol", tol, 1e-6, 0.1)
    for name, value in options.items():
        if is_axis(value):
            raise ValueError(f"{name} must be a single value for a limit search, got a sequence")
    # validate the options (and the caps) once, on the widest rocking the search tries
    probe = sweep_grid(0.5, W_MAX, **options)[0]
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
    The search starts from the whole range ``[0, 0.999]``, checks that its
    lower end shakes down and its upper end ratchets, then bisects: about
    ``2 + log2(0.999 / (2 tol))`` runs (11 at ``tol = 1e-3``). Eq 35 places
    no run; :attr:`LimitResult.eq35_inside` says afterwards whether it lies
    in the final bracket. The search assumes that the verdict changes once
    in ``w``. The verdict depends on ``periods`` and ``shakedown_rtol``: just
    past the limit the ratcheting increment is still below ``shakedown_rtol``
    times the first period's, so the default verdict (1e-3, 10 periods) puts
    the limit up to about 2e-4 above eq 35 at ``dx = 1/40``; with
    ``shakedown_rtol=1e-6`` and 40 periods it agrees with eq 35 to 1e-5.

    Examples
    --------
    >>> import core
    >>> res = core.numerical_limit(0.5, tol=0.01, periods=6)
    >>> bool(res.converged), res.start_lo, res.start_hi, res.eq35_inside
    (True, 0.0, 0.999, True)
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
    >>> abs(w - float(core.w_limit(0.5))) < 0.02
    True
    """
    return numerical_limit(ft, tol, **solver_options).w_limit


def _limit_task(args) -> LimitResult:
    ft, tol, options = args
    return _limit_search(ft, tol, options)


def numerical_limit_curve(ft_values, tol=1e-3, scheduler=None, *, workers=None, max_workers=None, progress=None,
                          cancel=None, timeout=None, **solver_options) -> pd.DataFrame:
    """The numerical limit ``w_lim(ft)`` for several ``ft``, searched in parallel.

    Each ``ft`` is one task (a whole bisection, :func:`numerical_limit`) on
    the same executors as :func:`core.sweep`.

    Parameters
    ----------
    ft_values : sequence of float
        Values of ``Ft / (mu Fn)``, each in (0, 1); at most :func:`core.maps.grid.default_max_runs`.
    tol : float
        Tolerance in ``w`` of every limit.
    scheduler, workers, max_workers, progress, cancel, timeout
        As for :func:`core.sweep` (``progress`` counts ``ft`` values;
        ``workers=None`` gives one process per ``ft``, up to the cores).
    **solver_options
        Options of :func:`core.simulate_cycles` (single values).

    Returns
    -------
    pandas.DataFrame
        One row per ``ft`` in the order given, columns :data:`LIMIT_COLUMNS`:
        ``ft``, the starting bracket ``start_lo``, ``start_hi``, the final
        one ``w_shakedown``, ``w_ratcheting``, its midpoint ``w_limit``,
        ``tol``, ``w_limit_eq35`` (the body's exact limit: eq 35 for the
        cylinder), ``eq35_inside`` (it lies in the final bracket),
        ``exact_within_tol`` (it lies within ``tol`` of the bracket), ``difference`` (``w_limit - w_limit_eq35``), ``periods``,
        ``runs``, ``converged``, ``runtime`` (solver time summed over the runs
        [s]) and ``message``. ``table.attrs["results"]`` holds the
        :class:`LimitResult` objects.
    """
    from ..bounds.limits import w_limit as w_limit_eq35

    ft_list = axis("ft", ft_values, 0.0, 1.0, lo_closed=False)
    cap = default_max_runs()
    if len(ft_list) > cap:
        raise ValueError(f"{len(ft_list)} ft values (> {cap}, see SHAKEDOWN_MAX_RUNS)")
    tol, options = _limit_options(tol, solver_options)
    body = options.get("body", "cylinder")
    if max_workers is not None:
        if workers is not None:
            raise ValueError("give workers or max_workers (its old name), not both")
        workers = max_workers
    if workers is None and scheduler is None:
        workers = -1 if len(ft_list) > 1 else 1  # each task is a whole search: seconds of work
    report = progress_callback(progress, label="ft values")
    results: list[LimitResult | None] = [None] * len(ft_list)

    def on_result(i, value, exc):
        nan = float("nan")
        results[i] = value if exc is None else LimitResult(
            ft_list[i], 0.0, W_MAX, nan, nan, nan, tol, float(w_limit_eq35(ft_list[i], body=body)), False,
            f"task failed: {type(exc).__name__}: {exc}", tidy([], list(INPUT_COLUMNS) + list(RESULT_COLUMNS)))
        report(sum(r is not None for r in results), len(ft_list))

    def table():
        done = [r for r in results if r is not None]
        df = pd.DataFrame([r.as_row() for r in done], columns=list(LIMIT_COLUMNS))
        df = df.astype({"runs": "int64", "periods": "int64", "converged": bool, "eq35_inside": bool,
                        "exact_within_tol": bool})
        df.attrs["results"] = done
        return df

    report(0, len(ft_list))
    try:
        info = run_tasks(_limit_task, lambda n: [(f, tol, options) for f in ft_list], workers=workers,
                         scheduler=scheduler, on_result=on_result, cancel=cancel, timeout=timeout,
                         runs=len(ft_list))
    except SweepCancelled as e:
        e.table = table()
        raise
    out = table()
    out.attrs.update(info)
    return out
