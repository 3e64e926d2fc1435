"""Error bars: the discretisation error of a run's increment per period, from the run itself.

The increment per period converges at first order in the element width
``dx`` (and the rocking step ``dW = dx``): the contact edges cross the
world-fixed elements, and the element-mean bound is exact only up to the
element in which the edge lies. Runs at ``dx``, ``2 dx`` and ``4 dx`` give
the observed order ``p = log2(|I(4dx) - I(2dx)| / |I(2dx) - I(dx)|)``; where it
is clean (close to the expected 1), Richardson's extrapolation
``I* = I(dx) + (I(dx) - I(2dx)) / (2^1 - 1)`` removes the leading error term
and ``|I(dx) - I(2dx)|`` estimates the error of ``I(dx)``. The coarser runs
cost a quarter and a sixteenth of the fine one or less (the dense solver's
cost grows at least as n^2 x steps).

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

from ._validate import check_scalar
from .result import CycleResult
from .solver import DEFAULT_DX, simulate_cycles

__all__ = ["ConvergedIncrement", "converged_increment", "EXPECTED_ORDER", "ORDER_TOLERANCE"]

#: The order of convergence of the increment per period in dx.
EXPECTED_ORDER = 1.0
#: Largest distance of the observed order from :data:`EXPECTED_ORDER` that counts as clean.
ORDER_TOLERANCE = 0.5


@dataclass(frozen=True, eq=False)
class ConvergedIncrement:
    """The increment of the last period at three grids, its observed order and its extrapolation.

    Attributes
    ----------
    value : float
        Increment of the last period at ``dx`` [mu P/E*].
    coarse, coarser : float
        The same at ``2 dx`` and ``4 dx``.
    order : float
        Observed order of convergence (NaN where the differences vanish or change sign).
    clean : bool
        Whether ``order`` is within :data:`ORDER_TOLERANCE` of :data:`EXPECTED_ORDER`.
    extrapolated : float
        Richardson's extrapolation from ``dx`` and ``2 dx`` if the order is clean, else ``value``.
    error : float
        Estimated discretisation error of ``value``: ``|value - coarse| / (2^1 - 1)``.
    dx : float
        The finest element width [a].
    result : CycleResult
        The run at ``dx``.
    """

    value: float
    coarse: float
    coarser: float
    order: float
    clean: bool
    extrapolated: float
    error: float
    dx: float
    result: CycleResult = field(repr=False)

    @property
    def relative_error(self) -> float:
        """``error / |value|`` (inf for a zero increment)."""
        return self.error / abs(self.value) if self.value else math.inf


def converged_increment(ft, w, dx=DEFAULT_DX, **options) -> ConvergedIncrement:
    """The increment per period of the last period with its own error bar (runs at dx, 2 dx and 4 dx).

    Parameters
    ----------
    ft, w : float
        As in :func:`core.simulate_cycles`.
    dx : float
        The finest element width [a], in [1e-4, 0.125] (``4 dx`` must be a valid grid).
    **options
        Further options of :func:`core.simulate_cycles` (``periods``, ``kernel``,
        ...); ``dW`` follows ``dx`` at each grid unless given.

    Returns
    -------
    ConvergedIncrement

    Examples
    --------
    >>> import core
    >>> c = core.converged_increment(0.58, 0.77, dx=1 / 80, periods=4)
    >>> c.clean, abs(c.extrapolated - c.value) == c.error
    (True, True)
    """
    dx = check_scalar("dx", dx, 1e-4, 0.125)
    runs = [simulate_cycles(ft, w, dx=h, **options) for h in (dx, 2 * dx, 4 * dx)]
    fine, coarse, coarser = (float(r.increment_per_period[-1]) for r in runs)
    d1, d2 = fine - coarse, coarse - coarser
    order = math.log2(d2 / d1) if d1 * d2 > 0 else math.nan
    clean = bool(abs(order - EXPECTED_ORDER) <= ORDER_TOLERANCE)
    factor = 2.0 ** EXPECTED_ORDER - 1.0
    error = abs(d1) / factor
    extrapolated = fine + d1 / factor if clean else fine
    return ConvergedIncrement(value=fine, coarse=coarse, coarser=coarser, order=order, clean=clean,
                              extrapolated=extrapolated, error=error, dx=dx, result=runs[0])
