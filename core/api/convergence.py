"""Error bars: the discretisation error of a run's increment per period, from the run itself.

The increment per period converges at first order in the element width
``dx`` (and the rocking step ``dW``, ``dx`` or the body's multiple of it): the contact edges cross the
world-fixed elements, and the element-mean bound is exact only up to the
element in which the edge lies. This holds for the line contact and for the
point contacts alike. Runs at ``dx``, ``2 dx`` and ``4 dx`` give the observed
order ``p = log2(|I(4dx) - I(2dx)| / |I(2dx) - I(dx)|)``; where it is clean
(within :data:`ORDER_TOLERANCE` of the expected 1), Richardson's extrapolation
at the expected order, ``I* = I(dx) + (I(dx) - I(2dx)) / (2^1 - 1)``, removes
the leading error term. The error bar of ``I(dx)`` is Roache's grid
convergence index at the expected order, ``Fs |I(dx) - I(2dx)| / (2^1 - 1)``,
with the safety factor ``Fs = 1.25`` when three grids give a clean order or
when two grids are run (the order measured for every body, see below), and
``Fs = 3`` when three grids give an order that is not clean (the grids are not
yet in the asymptotic range).

Measured orders (the increment of the last of 6 periods, :func:`core.simulate_cycles`):

* cylinder, ft 0.58, w 0.77: clean first order between a/20 and a/80,
  and the extrapolation from a/40 and a/80 is within 0.3 of the a/80 error of
  the a/400 run (``tests/test_convergence.py``);
* sphere, ft 0.4, w 0.6 (ratcheting): 0.17415, 0.17786, 0.17901, 0.17970 at
  a/5, a/10, a/20, a/40; observed orders 1.68 (a/5-a/10-a/20) and 0.75
  (a/10-a/20-a/40);
* sphere, ft 0.6, w 0.3: 0.02743, 0.02936, 0.02966, 0.02977; orders 2.70 and 1.45.

(Before the 3D discretisation fix of issue 21: 0.15885, 0.17310, 0.17705,
0.17884, orders 1.85 and 1.14; and 0.02608, 0.02804, 0.02912, 0.02957,
orders 0.86 and 1.26.) First order is the orders' middle ground.
For the sphere at its default a/20 the two-grid error bar (a/20 with a/10)
is 0.0014 at ft 0.4, w 0.6 and 0.00037 at ft 0.6, w 0.3, against the
distances 0.00069 and 0.00011 to the a/40 run: it covers them.

The coarser runs cost a quarter and a sixteenth of the fine one or less for
the cylinder (the dense solver's cost grows at least as n^2 x steps), an
eighth and a sixty-fourth for the point contacts (n^2 elements x steps).
:func:`grid_error` gives the error bar of a run already made, from one run at
twice its ``dx`` (the cheap form for a run card).

References
----------
.. [1] L. F. Richardson, "The deferred approach to the limit", Phil. Trans. R.
   Soc. A 226 (1927) 299-361.
.. [2] P. J. Roache, *Verification and validation in computational science and
   engineering*, Hermosa 1998 (observed order of accuracy, grid convergence index).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..base._validate import check_int, check_scalar
from ..geometry.resolution import default_dW, default_dx
from .solver import simulate_cycles

__all__ = ["ConvergedIncrement", "converged_increment", "grid_error", "increment_error", "EXPECTED_ORDER", "ORDER_TOLERANCE",
           "SAFETY_FACTOR", "SAFETY_FACTOR_UNCLEAN"]

#: The order of convergence of the increment per period in dx (every body; measured, see the module's notes).
EXPECTED_ORDER = 1.0
#: Largest distance of the observed order from :data:`EXPECTED_ORDER` that counts as clean.
ORDER_TOLERANCE = 0.5
#: Safety factor of the error bar with a clean observed order, or two grids at the expected order (Roache).
SAFETY_FACTOR = 1.25
#: Safety factor of the error bar when three grids give an order that is not clean (Roache).
SAFETY_FACTOR_UNCLEAN = 3.0
# the coarsest element width a grid of the error bar may have [a]
_DX_MAX = 0.5


@dataclass(frozen=True, eq=False)
class ConvergedIncrement:
    """The increment of the last period at two or three grids, its observed order and its extrapolation.

    Attributes
    ----------
    value : float
        Increment of the last period at ``dx`` [mu P/E*, or mu Fn/(E* a) for a point contact].
    coarse, coarser : float
        The same at ``2 dx`` and ``4 dx`` (``coarser`` NaN with two grids).
    order : float
        Observed order of convergence (NaN with two grids, or where the differences vanish or change sign).
    clean : bool
        Whether ``order`` is within :data:`ORDER_TOLERANCE` of :data:`EXPECTED_ORDER`.
    extrapolated : float
        Richardson's extrapolation from ``dx`` and ``2 dx`` if the order is clean, else ``value``.
    error : float
        Error bar of ``value`` (its estimated discretisation error, with a safety factor):
        ``safety * |value - coarse| / (2^1 - 1)``.
    dx : float
        The finest element width [a].
    result : CycleResult
        The run at ``dx``.
    body : str
        Name of the body.
    grids : int
        Grids run (2 or 3).
    safety : float
        Safety factor of ``error``.
    """

    value: float
    coarse: float
    coarser: float
    order: float
    clean: bool
    extrapolated: float
    error: float
    dx: float
    result: object = field(repr=False)
    body: str = "cylinder"
    grids: int = 3
    safety: float = SAFETY_FACTOR

    @property
    def relative_error(self) -> float:
        """``error / |value|`` (inf for a zero increment)."""
        return self.error / abs(self.value) if self.value else math.inf


def _estimate(runs, dx, body, safety_two=SAFETY_FACTOR) -> ConvergedIncrement:
    """The error bar from runs at dx, 2 dx (and 4 dx)."""
    values = [float(r.increment_per_period[-1]) for r in runs]
    fine, coarse = values[0], values[1]
    d1 = fine - coarse
    if len(values) == 3:
        coarser = values[2]
        d2 = coarse - coarser
        order = math.log2(d2 / d1) if d1 * d2 > 0 else math.nan
        clean = bool(abs(order - EXPECTED_ORDER) <= ORDER_TOLERANCE)
        safety = SAFETY_FACTOR if clean else SAFETY_FACTOR_UNCLEAN
    else:
        coarser, order, clean = math.nan, math.nan, False
        safety = safety_two
    # the expected order (the observed one, from the coarser grids, only tells whether the grids are asymptotic:
    # extrapolating at it is less accurate, e.g. 0.00067 instead of 0.00039 from the a/400 run of the cylinder at
    # ft 0.58, w 0.77, where a/20-a/40-a/80 observe 1.17)
    factor = 2.0 ** EXPECTED_ORDER - 1.0
    error = safety * abs(d1) / factor
    extrapolated = fine + d1 / factor if clean else fine
    name = body if isinstance(body, str) else getattr(body, "name", str(body))
    return ConvergedIncrement(value=fine, coarse=coarse, coarser=coarser, order=order, clean=clean,
                              extrapolated=extrapolated, error=error, dx=dx, result=runs[0], body=name,
                              grids=len(values), safety=safety)


def converged_increment(ft, w, dx=None, *, body="cylinder", grids=3, **options) -> ConvergedIncrement:
    """The increment per period of the last period with its own error bar (runs at dx, 2 dx and 4 dx).

    Parameters
    ----------
    ft, w : float
        As in :func:`core.simulate_cycles`.
    dx : float, optional
        The finest element width [a]; default the body's grid
        (:func:`core.geometry.resolution.default_dx`: a/40 for the cylinder, a/20 for
        the point contacts). The coarsest grid, ``2^(grids-1) dx``, must be at
        most 0.5.
    body : str or core.Ellipsoid
        The body, as in :func:`core.simulate_cycles` (``"cylinder"``,
        ``"sphere"``, ``"ellipsoid"`` with ``ratio=``, ...).
    grids : {2, 3}
        Three grids measure the order and extrapolate; two (``dx`` and
        ``2 dx``, the cheap form) give the error bar at the expected order.
    **options
        Further options of :func:`core.simulate_cycles` (``periods``,
        ``kernel``, ``ratio``, ...); ``dW`` follows ``dx`` at each grid unless given.

    Returns
    -------
    ConvergedIncrement

    Examples
    --------
    >>> import core
    >>> c = core.converged_increment(0.58, 0.77, dx=1 / 80, periods=4)
    >>> c.clean, c.grids, c.safety
    (True, 3, 1.25)
    >>> s = core.converged_increment(0.4, 0.6, dx=0.1, body="sphere", grids=2, periods=3)
    >>> s.grids, s.error > 0
    (2, True)
    """
    grids = check_int("grids", grids, 2, 3)
    dx = default_dx(body) if dx is None else dx
    dx = check_scalar("dx", dx, 1e-4, _DX_MAX / 2 ** (grids - 1))
    runs = [simulate_cycles(ft, w, dx=dx * 2 ** i, body=body, **options) for i in range(grids)]
    return _estimate(runs, dx, body)


def grid_error(result, *, grids=2) -> ConvergedIncrement:
    """The error bar of a run already made: the same run again at ``2 dx`` (and ``4 dx`` with ``grids=3``).

    The cheap form of :func:`converged_increment` for a result in hand (the
    explorer's "estimated discretisation error" of a run): one more run at
    twice the element width, an eighth of a point contact's cost and a
    quarter of the cylinder's or less. ``dW`` follows ``dx`` if it did in
    the run.

    Parameters
    ----------
    result : CycleResult
        A run of :func:`core.simulate_cycles` (not of an arbitrary schedule:
        its inputs must be in ``result.params``).
    grids : {2, 3}
        Grids in all, the run's own included.

    Returns
    -------
    ConvergedIncrement
        ``value`` is the run's last increment; ``error`` its error bar;
        ``relative_error`` the same over ``|value|``.

    Raises
    ------
    ValueError
        If the result cannot be run again (a schedule given as arrays), or
        ``2^(grids-1) dx`` exceeds 0.5.

    Examples
    --------
    >>> import core
    >>> r = core.simulate_cycles(0.58, 0.77, periods=4, dx=1 / 40)
    >>> e = core.grid_error(r)
    >>> bool(e.value == r.increment_per_period[-1]), e.coarse != e.value, e.error > 0
    (True, True, True)
    """
    grids = check_int("grids", grids, 2, 3)
    params = dict(getattr(result, "params", None) or {})
    if not {"ft", "w", "periods", "dx"} <= set(params) or params.get("history", "rocking") == "arrays":
        raise ValueError("result must be a run of core.simulate_cycles with a rocking, normal or tangential "
                         "history (its inputs in result.params)")
    dx = float(params.pop("dx"))
    check_scalar("dx", dx * 2 ** (grids - 1), 0.0, _DX_MAX)
    dW = params.pop("dW", None)
    follows = dW is None or math.isclose(float(dW), default_dW(result.body, dx))
    ft, w = params.pop("ft"), params.pop("w")
    body = result.body  # the body object carries its parameters (a punch's flat, an ellipsoid's ratio)
    for key in ("body", "ratio", *getattr(body, "parameters", {})):
        params.pop(key, None)
    options = dict(params, tol=result.tol, shakedown_rtol=result.shakedown_rtol, body=body)
    runs = [result]
    for i in range(1, grids):
        h = dx * 2 ** i
        runs.append(simulate_cycles(ft, w, dx=h, dW=None if follows else dW, **options))
    return _estimate(runs, dx, body)


# inputs a run's params may differ in between two grids (the grid itself, and dW which follows it)
_GRID_KEYS = ("dx", "dW", "runtime_s")


def increment_error(fine, coarse) -> ConvergedIncrement:
    """The error bar of ``fine``'s last increment from ``coarse``, the same run already made at ``2 dx``.

    The two-grid form of :func:`grid_error` for two runs in hand (the
    explorer solves the coarse run in its worker pool, with its cache):
    ``error = 1.25 |u(dx) - u(2 dx)| / (2^1 - 1)`` at the expected first order.

    Parameters
    ----------
    fine, coarse : CycleResult
        Two runs of the same kind, inputs (``result.params``) and periods but
        the grid: ``coarse.dx == 2 fine.dx`` (within 1e-9).

    Returns
    -------
    ConvergedIncrement
        With ``grids == 2``; ``value`` is ``fine``'s last increment.

    Raises
    ------
    ValueError
        If the runs are of different kinds, inputs or periods, or ``coarse.dx`` is not ``2 fine.dx``.

    Examples
    --------
    >>> import core
    >>> fine = core.simulate_cycles(0.4, 0.6, dx=0.125, body="sphere", periods=3)
    >>> coarse = core.simulate_cycles(0.4, 0.6, dx=0.25, body="sphere", periods=3)
    >>> e = core.increment_error(fine, coarse)
    >>> bool(e.value == fine.increment_per_period[-1]), e.error > 0, e.grids
    (True, True, 2)
    """
    from ..records.result import CycleResult

    for name, r in (("fine", fine), ("coarse", coarse)):
        if not isinstance(r, CycleResult):
            raise ValueError(f"{name} must be a core.CycleResult, got {type(r).__name__}")
    if fine.is_patch != coarse.is_patch:
        kinds = ["a patch" if r.is_patch else "a line" for r in (fine, coarse)]
        raise ValueError(f"fine and coarse must be runs of the same kind, got {kinds[0]} and {kinds[1]}")
    if not math.isclose(coarse.dx, 2.0 * fine.dx, rel_tol=1e-9):
        raise ValueError(f"coarse.dx must be 2 fine.dx = {2 * fine.dx:.6g}, got {coarse.dx:.6g}")
    inputs = [{k: v for k, v in r.params.items() if k not in _GRID_KEYS} for r in (fine, coarse)]
    if inputs[0] != inputs[1] or fine.periods != coarse.periods:
        raise ValueError("fine and coarse must be runs of the same inputs and periods (only dx, dW differ)")
    return _estimate([fine, coarse], float(fine.dx), getattr(fine, "body", "cylinder"))
