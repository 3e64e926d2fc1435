"""The coupled shakedown limit ``ft_lim(w)`` of a line contact of dissimilar materials, found numerically.

With Dundurs' ``beta != 0`` the normal and tangential problems are solved
together (:mod:`core.elastic.coupling`) and Melan's theorem no longer gives the
limit: eq 35 is only the uncoupled reference. The limit is then where the
coupled cycle solver's verdict changes, found here by bisection in ``ft`` at
each ``w``, as ``benchmarks/coupled.py`` does for its table: the bracket
starts at fractions of eq 35 (``ft`` below eq 35 is where a coupled limit
lies: ``beta`` lowers it), is widened if an end is on the wrong side, and is
halved until its width is at most ``tol`` times eq 35.

One limit costs a few runs (``2 + log2((hi - lo) / tol)``: 7 at the default
bracket and ``tol = 0.02``), each a coupled run of ``periods`` periods; on
the coarse grid ``dx = a/20`` a run takes a few tenths of a second, so a curve
of five ``w`` is seconds of CPU time (``benchmarks/coupled_limit_curve.py``
prints it).

:func:`coupled_limit_curve` is the headless computation: the explorer runs it
off its event loop and draws each ``w``'s bracket as it comes
(``on_point``), the docs gallery draws a table of it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..base._validate import check_int, check_range, check_scalar
from ..theory.materials import check_beta

__all__ = ["CoupledLimit", "CoupledLimitCurve", "coupled_limit", "coupled_limit_curve", "DEFAULT_W",
           "NOT_RATCHETING", "MAX_PERIODS"]

#: The rocking amplitudes of a curve by default: five, from 0.1 to 0.9.
DEFAULT_W = (0.1, 0.3, 0.5, 0.7, 0.9)
#: Regimes on the shakedown side of the bracket (the body does not walk; as :mod:`core.maps.limits_search`).
NOT_RATCHETING = ("shakedown", "cyclic slip")
#: Most periods a run of the search is given: an undetermined run is repeated with twice the periods up to this.
MAX_PERIODS = 160
#: Times an end of the starting bracket is moved out (halved towards 0 or towards 1) if it is on the wrong side.
_WIDENINGS = 4


@dataclass(frozen=True)
class CoupledLimit:
    """The coupled limit ``ft_lim`` at one ``w``: the final bracket in ``ft`` and the runs that set it.

    Attributes
    ----------
    w : float
        The rocking amplitude ``W / a``.
    ft_shakedown, ft_ratcheting : float
        The final bracket: the largest ``ft`` that did not ratchet (shakedown or
        cyclic slip) and the smallest that ratcheted (NaN if not found).
    ft_eq35 : float
        Eq 35 at ``w``: the uncoupled reference, not the limit.
    converged : bool
        Whether the bracket closed to ``tol`` times eq 35.
    runs : tuple of (float, str, int, float)
        Every run, in the order run: ``(ft, regime, periods, cpu seconds)``.
    message : str
        What happened, in words.
    """

    w: float
    ft_shakedown: float
    ft_ratcheting: float
    ft_eq35: float
    converged: bool
    runs: tuple = field(repr=False)
    message: str = ""

    @property
    def ft_limit(self) -> float:
        """The midpoint of the bracket (NaN unless :attr:`converged`)."""
        return 0.5 * (self.ft_shakedown + self.ft_ratcheting) if self.converged else math.nan

    @property
    def fall(self) -> float:
        """How far the limit lies below eq 35, as a fraction of it (``1 - ft_limit / ft_eq35``)."""
        return 1.0 - self.ft_limit / self.ft_eq35

    @property
    def cpu_s(self) -> float:
        """CPU time of the runs [s]."""
        return float(sum(r[3] for r in self.runs))


@dataclass(frozen=True)
class CoupledLimitCurve:
    """The coupled limit curve ``ft_lim(w)`` of :func:`coupled_limit_curve`, one :class:`CoupledLimit` per ``w``.

    Attributes
    ----------
    beta, mu : float
        Dundurs' beta and the friction coefficient of the runs.
    dx, tol : float
        The grid [a] and the relative width of the brackets.
    periods : int
        The periods a run starts with.
    points : tuple of CoupledLimit
        The limits, in the order of ``w``.
    """

    beta: float
    mu: float
    dx: float
    tol: float
    periods: int
    points: tuple

    def _column(self, name: str) -> np.ndarray:
        """Attribute ``name`` of every point, in the order of ``w``."""
        return np.array([getattr(p, name) for p in self.points])

    @property
    def w(self) -> np.ndarray:
        """The amplitudes."""
        return self._column("w")

    @property
    def ft_shakedown(self) -> np.ndarray:
        """The lower end of each bracket."""
        return self._column("ft_shakedown")

    @property
    def ft_ratcheting(self) -> np.ndarray:
        """The upper end of each bracket."""
        return self._column("ft_ratcheting")

    @property
    def ft_limit(self) -> np.ndarray:
        """The midpoints (NaN where a search did not converge)."""
        return self._column("ft_limit")

    @property
    def ft_eq35(self) -> np.ndarray:
        """Eq 35 at each ``w``: the uncoupled reference."""
        return self._column("ft_eq35")

    @property
    def runs(self) -> int:
        """Runs of the whole curve."""
        return sum(len(p.runs) for p in self.points)

    @property
    def cpu_s(self) -> float:
        """CPU time of the whole curve [s]."""
        return float(sum(p.cpu_s for p in self.points))

    def ft_limit_at(self, w) -> float:
        """The coupled limit at ``w`` between the curve's amplitudes: the ratio ``ft_limit / eq 35`` interpolated
        linearly in ``w`` (it varies slowly, eq 35 carries the steep part), times eq 35 at ``w``.

        Parameters
        ----------
        w : float
            Rocking amplitude ``W / a``, in [0, 1).

        Returns
        -------
        float
            The interpolated limit, NaN outside the range of the converged points' ``w`` (no extrapolation).

        Examples
        --------
        >>> from core.maps.coupled_limits import CoupledLimit, CoupledLimitCurve
        >>> pts = tuple(CoupledLimit(w, 0.9 * e, 0.92 * e, e, True, ()) for w, e in ((0.3, 0.6238), (0.5, 0.3910)))
        >>> curve = CoupledLimitCurve(0.25, 0.3, 0.05, 0.02, 20, pts)
        >>> round(curve.ft_limit_at(0.4), 4), curve.ft_limit_at(0.6)
        (0.4592, nan)
        """
        from ..theory.analytical import ft_limit as eq35

        w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
        ok = [p for p in self.points if p.converged]
        ws = np.array([p.w for p in ok])
        if ws.size == 0 or not ws.min() - 1e-12 <= w <= ws.max() + 1e-12:
            return math.nan
        ratio = np.interp(w, ws, [p.ft_limit / p.ft_eq35 for p in ok])
        return float(ratio * float(eq35(w)))

    def at(self, w: float) -> CoupledLimit | None:
        """The limit at the curve's ``w`` nearest ``w`` if within 1e-9 of it, else None."""
        for p in self.points:
            if abs(p.w - w) <= 1e-9:
                return p
        return None


def _ratchets(ft, w, beta, mu, dx, periods, log, cancel) -> bool:
    """Whether the coupled run at ``(ft, w)`` ratchets (an undetermined run repeated with twice the periods)."""
    from ..api.solver import simulate_cycles

    while True:
        c0 = time.process_time()
        r = simulate_cycles(ft, w, periods=periods, dx=dx, beta=beta, mu=mu, kernel="plane", cancel=cancel)
        log.append((float(ft), str(r.regime), int(periods), time.process_time() - c0))
        if r.regime != "undetermined" or 2 * periods > MAX_PERIODS:
            break
        periods *= 2
    if r.regime == "undetermined":
        raise RuntimeError(f"the regime at ft = {ft:.6g}, w = {w:.6g} is undetermined after {periods} periods")
    return r.regime not in NOT_RATCHETING


def _search(w, beta, mu, dx, tol, periods, lo, hi, cancel) -> CoupledLimit:
    from ..theory.analytical import ft_limit as eq35

    ref = float(eq35(w))
    log: list = []
    verdicts: dict = {}

    def out(f_sd, f_r, converged, message):
        return CoupledLimit(float(w), f_sd, f_r, ref, converged, tuple(log), message)

    def ratchets(fraction):  # an end moved out keeps its verdict: it is not run again
        if fraction not in verdicts:
            verdicts[fraction] = _ratchets(fraction * ref, w, beta, mu, dx, periods, log, cancel)
        return verdicts[fraction]

    ceiling = 0.999 / ref  # ft < 1
    hi = min(hi, ceiling)
    try:
        for _ in range(_WIDENINGS + 1):  # the lower end must not ratchet
            if not ratchets(lo):
                break
            hi, lo = lo, lo / 2.0
        else:
            return out(math.nan, lo * ref, False, f"ratchets even at ft = {lo * ref:.4g}")
        for _ in range(_WIDENINGS + 1):  # the upper end must ratchet
            if ratchets(hi):
                break
            if hi >= ceiling:
                return out(hi * ref, math.nan, False, f"does not ratchet up to ft = {hi * ref:.4g}")
            lo, hi = hi, min(ceiling, 0.5 * (hi + ceiling))
        else:
            return out(lo * ref, math.nan, False, f"does not ratchet up to ft = {hi * ref:.4g}")
        while hi - lo > tol:
            mid = 0.5 * (lo + hi)
            if ratchets(mid):
                hi = mid
            else:
                lo = mid
    except RuntimeError as e:
        return out(math.nan, math.nan, False, str(e))
    return out(lo * ref, hi * ref, True, f"ft in [{lo * ref:.4g}, {hi * ref:.4g}] ([{lo:.3f}, {hi:.3f}] x eq 35) "
                                         f"in {len(log)} runs")


def _check(beta, mu, dx, tol, periods, lo, hi):
    beta = check_beta(beta)
    mu = check_scalar("mu", mu, 0.0, 10.0, lo_closed=False)
    dx = check_scalar("dx", dx, 1e-3, 0.25)
    tol = check_scalar("tol", tol, 1e-4, 0.5)
    periods = check_int("periods", periods, 2, MAX_PERIODS)
    lo = check_scalar("lo", lo, 0.0, 1.0, lo_closed=False, hi_closed=False)
    hi = check_scalar("hi", hi, lo, 2.0, lo_closed=False)
    return beta, mu, dx, tol, periods, lo, hi


def coupled_limit(w, beta, mu, *, dx=1 / 20, tol=0.02, periods=20, lo=0.5, hi=1.02, cancel=None) -> CoupledLimit:
    """The coupled shakedown limit ``ft_lim`` at one ``w``, bisected in ``ft`` on the coupled solver's verdict.

    Parameters
    ----------
    w : float
        Rocking amplitude ``W / a``, in (0, 0.99].
    beta : float
        Dundurs' beta, body 1 the rocking body, in (-0.5, 0.5).
    mu : float
        Friction coefficient, in (0, 10] (the coupling enters as ``beta / mu``).
    dx : float
        Element width [a], in [1e-3, 0.25] (default ``1/20``: coarse, a run in tenths of a second).
    tol : float
        Width of the final bracket as a fraction of eq 35 at ``w``, in [1e-4, 0.5].
    periods : int
        Periods of a run, in [2, :data:`MAX_PERIODS`]; an undetermined run is repeated with twice the periods.
    lo, hi : float
        The starting bracket as fractions of eq 35: ``lo`` in (0, 1), ``hi`` in (lo, 2]; an end on the wrong side
        is moved out (at most four times).
    cancel : callable, optional
        Polled by the runs; when it returns True the run raises :class:`core.SolveCancelled`.

    Returns
    -------
    CoupledLimit

    Raises
    ------
    ValueError
        If an input is out of its range (the message names it).
    core.SolveCancelled
        If ``cancel`` asked for it.

    Examples
    --------
    >>> import core
    >>> lim = core.coupled_limit(0.6, beta=0.25, mu=0.3, tol=0.1)
    >>> bool(lim.converged), bool(lim.ft_limit < lim.ft_eq35)
    (True, True)
    """
    w = check_scalar("w", w, 0.0, 0.99, lo_closed=False)
    return _search(w, *_check(beta, mu, dx, tol, periods, lo, hi), cancel)


def coupled_limit_curve(beta, mu, w=DEFAULT_W, *, dx=1 / 20, tol=0.02, periods=20, lo=0.5, hi=1.02, cancel=None,
                        on_point=None) -> CoupledLimitCurve:
    """The coupled shakedown limit curve ``ft_lim(w)`` of the rocking cylinder of dissimilar materials.

    Each ``w`` is one bisection in ``ft`` (:func:`coupled_limit`) on the verdict
    of the coupled cycle solver (:func:`core.simulate_cycles` with ``beta``,
    ``mu``, the plane-strain kernel); eq 35 only scales the starting bracket and
    is kept beside each limit as the uncoupled reference.

    Parameters
    ----------
    beta : float
        Dundurs' beta, body 1 the rocking body, in (-0.5, 0.5); 0 gives eq 35 within the brackets.
    mu : float
        Friction coefficient, in (0, 10].
    w : sequence of float
        Rocking amplitudes ``W / a``, each in (0, 0.99], at most 20 (default :data:`DEFAULT_W`).
    dx, tol, periods, lo, hi, cancel
        As for :func:`coupled_limit`.
    on_point : callable, optional
        Called with each :class:`CoupledLimit` as it is found (a view draws the curve progressively).

    Returns
    -------
    CoupledLimitCurve

    Raises
    ------
    ValueError
        If an input is out of its range (the message names it).
    core.SolveCancelled
        If ``cancel`` asked for it.

    Notes
    -----
    Melan's theorem does not hold for a coupled contact (Klarbring, Ciavarella
    and Barber 2007), so its limit is the solver's alone: it depends on the grid
    (``dx``), the periods and the loading path. At ``dx = a/20`` the brackets
    agree with those at ``a/40`` of ``benchmarks/results/coupled_limits.txt``
    within about 2 % of eq 35.

    Examples
    --------
    >>> import core
    >>> curve = core.coupled_limit_curve(0.25, 0.3, w=[0.6], tol=0.1)
    >>> curve.points[0].converged, curve.runs > 2
    (True, True)
    """
    ws = check_range("w", w, 0.0, 0.99, lo_closed=False).ravel()
    if not 1 <= ws.size <= 20:
        raise ValueError(f"w must hold 1 to 20 amplitudes, got {ws.size}")
    args = _check(beta, mu, dx, tol, periods, lo, hi)
    points = []
    for wi in ws:
        point = _search(float(wi), *args, cancel)
        points.append(point)
        if on_point is not None:
            on_point(point)
    beta, mu, dx, tol, periods, _, _ = args
    return CoupledLimitCurve(beta, mu, dx, tol, periods, tuple(points))
