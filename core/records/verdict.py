"""The verdict of a run from its increments per period: the trend ``D_n = D_inf + C r^n`` and the regime.

:func:`fit_trend` fits the tail of the increments per period,
:func:`classify_increments` turns it into a :class:`Verdict` (shakedown,
ratcheting or undetermined, checked against Melan's limit of the run's grid
where it has one), :func:`classify_energy` the energy dissipated per period
into an :class:`EnergyVerdict` (cyclic slip), and :func:`combine_verdicts`
joins them. Pure functions of arrays: :class:`core.records.result.CycleResult` asks
them for its verdict (the user guide's page on verdicts, ``docs/guide/verdicts.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from ._fit import fit_window

__all__ = ["classify_increments", "fit_trend", "Trend", "Verdict", "EnergyVerdict", "classify_energy",
           "combine_verdicts", "REGIMES", "VERDICT_SIGMAS", "MIN_FIT_PERIODS", "SETTLED_FRACTION", "STEADY_FRACTION",
           "FIT_WINDOWS", "RATIO_RANGE"]

#: Half-width of the confidence interval of ``D_inf``, in standard errors: the verdict needs the whole
#: interval ``D_inf +- VERDICT_SIGMAS * D_inf_error`` on one side of the shakedown tolerance.
VERDICT_SIGMAS = 3.0
#: Fewest periods of the tail that the trend ``D_n = D_inf + C r^n`` is fitted to (three parameters and
#: at least one degree of freedom left to measure the scatter).
MIN_FIT_PERIODS = 4
#: A run counts as settled (ratcheting needs no steady trend) when the part of its last increment still
#: changing is at most this fraction of ``D_inf``.
SETTLED_FRACTION = 0.25
#: Largest relative difference of the limits fitted to tails twice and half as long for a steady trend.
STEADY_FRACTION = 0.05
#: Lengths of the tails tried (the shortest error of ``D_inf`` wins; at most ``periods - 1`` after the first).
FIT_WINDOWS = (4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192)
#: Range of the ratio ``r`` searched by the fit.
RATIO_RANGE = (0.0, 1.2)


@dataclass(frozen=True)
class Trend:
    """The fit ``D_n = D_inf + C r^n`` of the tail of the increments per period.

    Attributes
    ----------
    D_inf : float
        The limit of the increment per period as the periods go on (the
        increments' unit and sign; positive along ``Ft``).
    D_inf_error : float
        Its standard error: the least-squares covariance of the fit with the
        scatter of the residuals (at least the solver noise ``floor``),
        combined with the distance to Aitken's delta-squared limit of the
        fitted tail (the cross-check: a tail that is not one geometric decay
        widens it).
    ratio : float
        ``r``: the factor by which the part of the increment that is still
        changing shrinks each period (NaN when nothing changes any more).
    transient : float
        ``C r^n`` at the last period: how far the last increment still is from ``D_inf``.
    periods_fitted : int
        Length of the tail fitted (the last ``periods_fitted`` periods).
    aitken : float
        Aitken's delta-squared limit of the first, middle and last increments of the fitted tail.
    sigma : float
        Scatter of the increments about the fit (at least ``floor``).
    steady : bool or None
        Whether the fit of a tail twice (or half) as long gives the same
        ``D_inf`` within their errors (None when the run is too short to
        try): a decay that is still slowing down, as it does close to the
        limit, gives a ``D_inf`` that drifts down as the tail moves on.
    """

    D_inf: float
    D_inf_error: float
    ratio: float
    transient: float
    periods_fitted: int
    aitken: float
    sigma: float
    steady: bool | None = None


class Verdict(NamedTuple):
    """The verdict of :func:`classify_increments`: ``(shakedown_period, regime, reason, trend, periods_to_decide)``."""

    shakedown_period: int | None
    regime: str
    reason: str
    trend: Trend | None
    periods_to_decide: int | None


def _fit_window(y: np.ndarray, floor: float):
    """Least squares of ``y_j = D + C r^j`` (j = 0 ... k-1): a search over r, linear in D and C for each
    (:func:`core.records._fit.fit_window`), and the standard error of D."""
    k = y.size
    D, C, r, s, unit_err = fit_window(np.ascontiguousarray(y, dtype=float), *RATIO_RANGE)
    sigma = max(math.sqrt(s / (k - 3)) if k > 3 else 0.0, float(floor))
    return D, sigma * unit_err, r, C * r ** (k - 1), sigma


def _aitken(y: np.ndarray, stride: int = 1) -> float:
    """Aitken's delta-squared limit of ``y[-1 - 2 stride], y[-1 - stride], y[-1]`` (the last value if they do not decay).

    Exact for ``D + C r^n`` at any stride; a stride of half the fitted tail keeps the solver noise of the
    differences small beside the differences themselves when ``r`` is close to 1.
    """
    a, b, c = y[-1 - 2 * stride], y[-1 - stride], y[-1]
    d1, d2 = c - b, b - a
    curvature = d1 - d2
    if curvature == 0 or abs(d1) >= abs(d2):
        return float(c)
    return float(c - d1 * d1 / curvature)


def fit_trend(increments, floor=0.0) -> Trend | None:
    """Fit ``D_n = D_inf + C r^n`` to the tail of the increments per period (None below 4 periods).

    Tails of :data:`FIT_WINDOWS` periods are tried (leaving out the first
    period, a transient of its own, when there are 5 periods or more); the one
    with the smallest error of ``D_inf`` is kept. Each fit is a least-squares
    one: a search over ``r`` in :data:`RATIO_RANGE` with ``D_inf`` and ``C``
    linear for each ``r``; the error of ``D_inf`` is its standard error (the
    Jacobian of all three parameters and the residuals' scatter, at least
    ``floor``) combined with its distance to Aitken's delta-squared limit of
    the first, middle and last increments of the tail.

    Parameters
    ----------
    increments : array_like
        Increment of each period (any sign; the fit is in the sign of the largest).
    floor : float
        Noise of an increment: its smallest credible scatter (>= 0).

    Returns
    -------
    Trend or None

    Examples
    --------
    >>> from core.records.result import fit_trend
    >>> t = fit_trend([0.3 + 0.5 ** n for n in range(12)], floor=1e-9)
    >>> round(t.D_inf, 6), round(t.ratio, 6)
    (0.3, 0.5)
    """
    inc = np.asarray(increments, dtype=float)
    n = inc.size
    if n < MIN_FIT_PERIODS:
        return None
    sign = 1.0 if inc[np.argmax(np.abs(inc))] >= 0 else -1.0
    y = sign * inc
    longest = n - 1 if n > MIN_FIT_PERIODS else n
    fits = {k: _fit_window(y[n - k:], floor) for k in [w for w in FIT_WINDOWS if w <= longest] or [MIN_FIT_PERIODS]}
    k = min(fits, key=lambda w: fits[w][1])
    D, err, r, transient, sigma = fits[k]
    aitken = _aitken(y, max(1, (k - 1) // 2))
    err = math.hypot(err, D - aitken)
    # the same limit from tails twice and half as long (those fitted): a decay that is still slowing down drifts.
    # Within the errors *and* within STEADY_FRACTION of D_inf: a loose fit can agree within its errors while the
    # limit drifts tail after tail (the free cone 5 % below its limit after 40 periods: 1.2e-4, 6.4e-5, 4.0e-5,
    # 2.7e-5 from tails of 32, 24, 16, 12 periods; after 20 periods 4.3e-4, 3.3e-4, 2.9e-4 from 16, 12, 6; it
    # shakes down after 101 and 130 periods); one geometric approach gives one limit on every tail
    others = [w for w in (2 * k, k // 2) if w in fits]
    steady = None
    if others:
        steady = all(abs(D - fits[w][0]) <= min(VERDICT_SIGMAS * math.hypot(err, fits[w][1]), STEADY_FRACTION * abs(D))
                     for w in others)
    if abs(transient) <= sigma:  # nothing left that decays: r is not measured
        r = math.nan
    return Trend(D_inf=sign * D, D_inf_error=err, ratio=r, transient=sign * transient, periods_fitted=k,
                 aitken=sign * aitken, sigma=sigma, steady=steady)


class _MelanSide:
    """Where ``load`` is against Melan's limit ``(lo, hi)`` (or a callable giving it): ``below``, ``above``, words.

    The limit is asked for (a callable called) at most once, when a verdict needs it.
    """

    #: Relative margin beyond which a load counts as off the limit (the limit's own rounding).
    MARGIN = 1e-9

    def __init__(self, load, limit):
        self._load, self._limit = load, limit

    @cached_property
    def bounds(self):
        limit = self._limit() if callable(self._limit) else self._limit
        if self._load is None or limit is None:
            return None
        lo, hi = (float(v) for v in limit)
        return (lo, hi) if math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi else None

    @property
    def below(self) -> bool:
        return self.bounds is not None and abs(self._load) < self.bounds[0] * (1 - self.MARGIN)

    @property
    def above(self) -> bool:
        return self.bounds is not None and abs(self._load) > self.bounds[1] * (1 + self.MARGIN)

    @property
    def words(self) -> str:
        lo, hi = self.bounds
        where = f"{lo:.5g}" if hi - lo <= 1e-12 * hi else f"between {lo:.5g} and {hi:.5g}"
        load = abs(self._load)
        if load < lo:
            return f"the load {load:.5g} is {(lo - load) / lo:.2%} below Melan's limit on this grid ({where})"
        if load > hi:
            return f"the load {load:.5g} is {(load - hi) / hi:.2%} above Melan's limit on this grid ({where})"
        return f"the load {load:.5g} is within Melan's limit on this grid ({where})"

    @property
    def aside(self) -> str:
        """For an undetermined reason: the side of the limit, and what it implies ('' without a limit)."""
        if self.below:
            return f"; {self.words}: it will shake down"
        if self.above:
            return f"; {self.words}: it will ratchet"
        return ""


def _periods_to_decide(trend: Trend, tolerance: float) -> int | None:
    """Roughly how many more periods until the decaying part is below the tolerance (None if it does not decay)."""
    r, transient = trend.ratio, abs(trend.transient)
    if not (0.0 < r < 1.0) or transient <= 0:
        return None
    target = 0.5 * max(tolerance, VERDICT_SIGMAS * trend.sigma)
    if transient <= target:
        return 1
    return int(math.ceil(math.log(target / transient) / math.log(r)))


def classify_increments(increments, shakedown_rtol, periodic_from=None, *, floor=0.0, unit="mu P/E*", load=None,
                        limit=None) -> Verdict:
    """The verdict of a run from its increments per period: one rule for every body.

    The increments of a run that shakes down decay to zero; those of a run
    that ratchets tend to a constant, the distance the body walks every period.
    Close to the limit both approaches are slow geometric ones (a ratio of
    0.9 or more per period), so the verdict reads the trend of the tail: the
    fit ``D_n = D_inf + C r^n`` (:func:`fit_trend`), whose ``D_inf`` is
    compared with the shakedown tolerance ``tol = max(shakedown_rtol * largest
    increment, floor)``:

    * ``"shakedown"``: from some period on every increment is at most ``tol``
      (that period is the shakedown period); or the fit's ``D_inf`` is below
      ``tol`` by more than :data:`VERDICT_SIGMAS` standard errors (zero to
      the tolerance, within its uncertainty) and the increments decay
      (``r < 1``): they will fall below ``tol``.
    * ``"ratcheting"``: the state repeats (``periodic_from``) with an increment
      above ``tol``; or ``D_inf`` is above ``tol`` by more than
      :data:`VERDICT_SIGMAS` standard errors: the body keeps walking. The
      increments must also have settled (the part still changing at most
      :data:`SETTLED_FRACTION` of ``D_inf``) or the trend be steady (a tail
      twice and half as long give the same ``D_inf``, within the errors and
      within :data:`STEADY_FRACTION` of it): close to the limit the decay
      of a run that shakes down slows period after period, and a short tail
      would extrapolate it to a constant.
    * ``"undetermined"``: fewer than :data:`MIN_FIT_PERIODS` periods, or the
      interval ``D_inf +- VERDICT_SIGMAS * error`` straddles ``tol``; the
      reason says roughly how many more periods would decay the changing part
      of the increment below ``tol`` (``periods_to_decide``).

    Given Melan's limit of the run's own discrete problem (``limit``, with the
    ``load`` it is compared with), a verdict read from the trend that
    contradicts it is undetermined instead: a load below the limit shakes down
    (Klarbring, Ciavarella and Barber 2007), however slowly, and one above it
    ratchets. Close to the limit of a slow body (the free cone) the increments
    fall by 0.99 or more a period with a ratio that creeps up each time the
    slip zones change, for hundreds of periods, and tails of any length look
    like convergence to a constant on one side of the limit as on the other.
    The increments themselves still decide (every increment below ``tol``; a
    repeating state), and an undetermined reason says on which side of the
    limit the load is.

    Parameters
    ----------
    increments : array_like
        Rigid-body displacement increment of each period (any sign).
    shakedown_rtol : float
        Relative tolerance of the shakedown verdict.
    periodic_from : int or None
        Period from which the solver found the state repeating.
    floor : float
        Absolute size below which an increment counts as zero, and the
        smallest scatter the fit assumes (the solver noise; >= 0).
    unit : str
        Unit of the increments, for the reason.
    load : float, optional
        The tangential load of the last period, in the unit of ``limit``.
    limit : tuple of float, or callable returning one or None, optional
        ``(lo, hi)``: Melan's limit of the load on the run's grid, between
        ``lo`` and ``hi`` (equal when it is exact); a callable is called only
        when a verdict from the trend is to be checked.

    Returns
    -------
    Verdict
        ``shakedown_period`` (int or None), ``regime``, ``reason`` (in words),
        ``trend`` (:class:`Trend`, None below 4 periods) and
        ``periods_to_decide`` (more periods likely to decide an undetermined
        run, else None).

    Examples
    --------
    >>> from core.records.result import classify_increments
    >>> v = classify_increments([0.1 * 0.95 ** n for n in range(40)], 1e-3, floor=1e-9)
    >>> v.regime, round(v.trend.ratio, 4), abs(v.trend.D_inf) < 1e-6
    ('shakedown', 0.95, True)
    """
    inc = np.asarray(increments, dtype=float)
    if inc.size == 0:
        return Verdict(None, "undetermined", "no rocking period was run", None, 1)
    scale = float(np.abs(inc).max())
    tolerance = max(shakedown_rtol * scale, float(floor))
    trend = fit_trend(inc, floor)
    k = _zero_from(inc, tolerance)
    if k is not None:
        return Verdict(k, "shakedown", (f"the increment per period fell to <= {shakedown_rtol:g} of its largest "
                                             f"from period {k}"), trend, None)
    last = float(inc[-1])
    if periodic_from is not None:
        return Verdict(None, "ratcheting", (f"the state repeats from period {periodic_from}, walking {last:.3g} "
                                            f"{unit} per period"), trend, None)
    if trend is None:
        need = MIN_FIT_PERIODS - inc.size
        return Verdict(None, "undetermined", (f"{inc.size} period{'s' if inc.size > 1 else ''}: too few to see "
                                              f"whether the increment per period decays to zero (shakedown) or "
                                              f"to a constant (ratcheting); run at least {MIN_FIT_PERIODS} "
                                              f"periods"), None, need)
    D, err, r = abs(trend.D_inf), trend.D_inf_error, trend.ratio
    band = VERDICT_SIGMAS * err
    fitted = (f"D_inf = {trend.D_inf:.3g} +- {err:.2g} {unit} (fit of the last {trend.periods_fitted} periods")
    fitted += f", the rest shrinking by r = {r:.4g} per period)" if math.isfinite(r) else ", nothing left changing)"
    settled = abs(trend.transient) <= SETTLED_FRACTION * D
    melan = _MelanSide(load, limit)
    if D - band > tolerance and (settled or trend.steady):
        reason = (f"the increment per period tends to a constant: {fitted}; the body keeps walking about "
                  f"{trend.D_inf:.3g} {unit} per period")
        if not melan.below:
            return Verdict(None, "ratcheting", reason, trend, None)
        return Verdict(None, "undetermined", (f"after {inc.size} periods {reason}; but {melan.words}, so the "
                                              f"increments must decay to zero however slowly (Melan's theorem): "
                                              f"run more periods"), trend, None)
    if D + band <= tolerance and math.isfinite(r) and r < 1.0:
        reason = (f"the increment per period decays geometrically towards zero: {fitted}; within its uncertainty "
                  f"D_inf is below the shakedown tolerance {tolerance:.2g} {unit} ({shakedown_rtol:g} of the largest)")
        if not melan.above:
            return Verdict(None, "shakedown", reason, trend, None)
        return Verdict(None, "undetermined", (f"after {inc.size} periods {reason}; but {melan.words}, so the "
                                              f"body must keep walking (Melan's theorem): run more periods"),
                       trend, None)
    more = _periods_to_decide(trend, tolerance)
    if D - band > tolerance:  # above the tolerance, but the decay may still be slowing down
        if 0.0 < r < 1.0:
            target = SETTLED_FRACTION * D
            more = max(1, int(math.ceil(math.log(target / abs(trend.transient)) / math.log(r))))
        else:
            more = None
        advice = (f"roughly {more} more periods would likely decide" if more is not None else "run more periods")
        why = ("fits of tails half or twice as long disagree" if trend.steady is False else
               "the run is too short to check that the trend is steady")
        return Verdict(None, "undetermined", (
            f"after {inc.size} periods the increment per period ({last:.3g} {unit}) extrapolates to {fitted}, "
            f"above the shakedown tolerance {tolerance:.2g} {unit}; but the increment is still "
            f"{abs(last) / D:.3g} times D_inf and {why}: close to the limit the decay slows down period after "
            f"period, and the run may yet shake down; {advice}{melan.aside}"), trend, more)
    if more is None:
        advice = ("the increment does not decay yet" if math.isfinite(r) and r >= 1.0 else
                  "its changing part cannot be told from the noise") + ": run more periods"
    else:
        advice = f"roughly {more} more periods would likely decide"
    return Verdict(None, "undetermined", (f"after {inc.size} periods the increment per period ({last:.3g} {unit}, "
                                          f"{abs(last) / scale:.3g} of its largest) extrapolates to {fitted}: "
                                          f"D_inf +- {VERDICT_SIGMAS:g} errors straddles the shakedown tolerance "
                                          f"{tolerance:.2g} {unit}, so it may still shake down or ratchet; "
                                          f"{advice}{melan.aside}"), trend, more)


def _zero_from(values: np.ndarray, tolerance: float) -> int | None:
    """The first period from which every value is at most ``tolerance`` in size; None if the last is above it."""
    above = np.flatnonzero(np.abs(values) > tolerance)
    if above.size and above[-1] == values.size - 1:
        return None
    return int(above[-1] + 1) if above.size else 0


#: The regimes a run can end in (:attr:`CycleResult.regime`): after Klarbring, Ciavarella and Barber (2007) and
#: Barber, Davies and Hills (2011), plus ``"undetermined"`` when the periods run cannot tell.
REGIMES = ("shakedown", "cyclic slip", "ratcheting", "undetermined")


class EnergyVerdict(NamedTuple):
    """What the energy dissipated per period does (:func:`classify_energy`): ``(kind, words, trend)``.

    ``kind`` is ``"zero"`` (it decays to zero: slip stops), ``"steady"`` (it tends to a positive constant:
    slip goes on every period) or ``"undetermined"``; ``words`` says why; ``trend`` is the fit
    ``E_n = E_inf + C r^n`` of its tail (:func:`fit_trend`; None below 4 periods).
    """

    kind: str
    words: str
    trend: Trend | None


def _fitted(trend: Trend, unit: str) -> str:
    """The energy's fitted limit in words: ``E_inf = ... +- ... unit``."""
    return f"E_inf = {trend.D_inf:.4g} +- {trend.D_inf_error:.2g} {unit}"


def classify_energy(energy, rtol, periodic_from=None, *, floor=0.0, unit="mu^2 P^2/E*") -> EnergyVerdict:
    """Whether the energy dissipated per period decays to zero or tends to a positive constant.

    The same reading as the walk's (:func:`classify_increments`): the energy of a
    run that shakes down decays geometrically to zero (slip stops); that of a
    run in cyclic slip or ratcheting tends to a positive constant, the energy
    of the steady loop. With ``tol = max(rtol * largest, floor)``:

    * ``"steady"``: the state repeats (``periodic_from``) and its period dissipates
      more than ``floor``: it does so for ever, however small a part of the
      largest that is (a coupled contact's micro-slip below its limit: 7e-4 of
      the first period's energy at ``beta = 0.1``);
    * ``"steady"`` also when the fit has settled (the changing part at most
      :data:`SETTLED_FRACTION` of ``E_inf``) on an ``E_inf`` above ``floor`` by
      more than :data:`VERDICT_SIGMAS` errors and the trend is steady (or the
      run is too short to fit the tails that tell, and ``E_inf`` is known to
      :data:`STEADY_FRACTION` of itself), however
      small a part of the largest: the same dissipation as a repeating state
      before the state repeats to the solver's tolerance;
    * ``"undetermined"`` when the energies fell below ``tol`` but toward an
      ``E_inf`` the fit knows to be above ``floor`` (by :data:`VERDICT_SIGMAS`
      errors, to :data:`STEADY_FRACTION` of itself) and have not settled there:
      more periods will tell (a coupled contact near its limit after 6-12
      periods; 30 periods give cyclic slip);
    * ``"zero"``: the state repeats dissipating at most ``floor``; or from some
      period on every energy is at most ``tol``, or the fit's ``E_inf`` is below
      ``tol`` by more than :data:`VERDICT_SIGMAS` standard errors and the
      energies decay (``r < 1``);
    * ``"steady"`` also when ``E_inf`` is above ``tol`` by more than
      :data:`VERDICT_SIGMAS` errors and the energies have settled (the changing
      part at most :data:`SETTLED_FRACTION` of ``E_inf``) or the trend is steady;
    * ``"undetermined"`` otherwise.

    Melan's limit does not enter: it tells shakedown from the other two regimes,
    not cyclic slip from ratcheting (docs/guide/regimes.md).

    Parameters
    ----------
    energy : array_like
        Energy dissipated in each period (>= 0 up to solver noise).
    rtol : float
        Relative tolerance below which an energy counts as zero (of the largest).
    periodic_from : int or None
        Period from which the solver found the state repeating.
    floor : float
        Absolute size below which an energy counts as zero, the smallest scatter of the fit (>= 0).
    unit : str
        Unit of the energies, for the words.

    Returns
    -------
    EnergyVerdict

    Examples
    --------
    >>> from core.records.result import classify_energy
    >>> classify_energy([0.07] + [0.036] * 9, 1e-3, periodic_from=1).kind
    'steady'
    >>> classify_energy([0.039, 0.0016, 0.00014] + [2.8e-5] * 7, 1e-3, periodic_from=4, floor=1e-9).kind
    'steady'
    >>> classify_energy([0.1 * 0.3 ** n for n in range(10)], 1e-3, floor=1e-12).kind
    'zero'
    """
    e = np.asarray(energy, dtype=float)
    if e.size == 0:
        return EnergyVerdict("undetermined", "no period was run", None)
    scale = float(np.abs(e).max())
    tolerance = max(rtol * scale, float(floor))
    trend = fit_trend(e, floor)
    last = float(e[-1])
    if periodic_from is not None and abs(last) > floor:  # the state repeats: so does this dissipation, for ever
        return EnergyVerdict("steady", f"the state repeats from period {periodic_from}, dissipating {last:.4g} "
                                       f"{unit} per period", trend)
    # the fit's limit is above the floor by three errors, and known to STEADY_FRACTION of itself (a decay still
    # falling by a tenth a period fits a limit known to 7-30 % only)
    above = trend is not None and trend.D_inf - VERDICT_SIGMAS * trend.D_inf_error > floor
    known = above and trend.D_inf_error <= STEADY_FRACTION * abs(trend.D_inf)
    if above and (trend.steady or (trend.steady is None and known)) \
            and abs(trend.transient) <= SETTLED_FRACTION * trend.D_inf:
        # the same dissipation as a repeating state, without the state repeating to the solver's tolerance yet:
        # the fit has settled on a constant above the floor, and tails twice and half as long give it within
        # their errors (a decay, however slow, drifts by more than its errors from tail to tail), or the run is
        # too short to fit those tails (steady None) and the limit is known: 6 to 10 periods of steel on aluminium
        # (4.1e-5 dissipated a period, known to 2e-4 of it) read shakedown by the 1e-3 rule while 12 and 30
        # periods give cyclic slip. Small beside the first period's energy is not zero (micro-slip of a coupled
        # contact: 7e-4 of it at beta = 0.1)
        return EnergyVerdict("steady", f"the energy dissipated per period tends to a constant, {_fitted(trend, unit)}",
                             trend)
    k = _zero_from(e, tolerance)  # (a repeating state that dissipates at most the floor is zero here)
    if k is not None and known:
        # the energies fell below the 1e-3 rule, but toward a limit the fit knows to be positive and still some
        # way off: neither zero nor settled yet
        return EnergyVerdict("undetermined", f"the energy dissipated per period ({last:.3g} {unit} in the last) "
                                             f"falls toward {_fitted(trend, unit)}, above zero, and has not settled "
                                             f"there yet: more periods will tell", trend)
    if k is not None:
        return EnergyVerdict("zero", f"the energy dissipated per period fell to <= {rtol:g} of its largest from "
                                     f"period {k}", trend)
    if trend is None:
        return EnergyVerdict("undetermined", f"{e.size} period{'s' if e.size > 1 else ''} are too few to fit the "
                                             f"energy per period ({last:.3g} {unit} in the last)", None)
    E, err, r = trend.D_inf, trend.D_inf_error, trend.ratio
    band = VERDICT_SIGMAS * err
    fitted = _fitted(trend, unit)
    if E - band > tolerance and (abs(trend.transient) <= SETTLED_FRACTION * abs(E) or trend.steady):
        return EnergyVerdict("steady", f"the energy dissipated per period tends to a constant, {fitted}", trend)
    if E + band <= tolerance and math.isfinite(r) and r < 1.0:
        return EnergyVerdict("zero", f"the energy dissipated per period decays to zero, {fitted} (r = {r:.4g})",
                             trend)
    return EnergyVerdict("undetermined", f"the energy dissipated per period ({last:.3g} {unit} in the last) "
                                         f"extrapolates to {fitted}, which does not tell zero (tolerance "
                                         f"{tolerance:.2g}) from a constant yet", trend)


def combine_verdicts(walk: Verdict, energy: EnergyVerdict) -> Verdict:
    """The regime from the two trends: the walk per period and the energy dissipated per period.

    * ``"ratcheting"``: the walk tends to a non-zero constant (whatever the energy);
    * ``"shakedown"``: the walk and the energy both go to zero (slip stops);
    * ``"cyclic slip"``: the walk goes to zero and the energy to a positive
      constant (slip repeats every period, the body does not walk: fretting);
    * ``"undetermined"``: either trend cannot tell yet.

    The reason names both trends. ``shakedown_period`` is kept for a shakedown
    only; ``periods_to_decide`` is the walk's.
    """
    regime = walk.regime
    if regime == "shakedown":
        regime = {"zero": "shakedown", "steady": "cyclic slip"}.get(energy.kind, "undetermined")
    why = {"shakedown": "the walk and the energy per period both go to zero",
           "cyclic slip": "the body stops walking but slips every period",
           "ratcheting": "the body keeps walking", "undetermined": "the trends cannot tell yet"}[regime]
    reason = f"{why}: walk: {walk.reason}; energy: {energy.words}"
    return Verdict(walk.shakedown_period if regime == "shakedown" else None, regime, reason, walk.trend,
                   walk.periods_to_decide)
