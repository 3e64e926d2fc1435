"""The discretisation error of a run's last increment per period, from the same run on a grid twice as coarse.

The increment per period converges at first order in the element width ``dx``
(:data:`core.convergence.EXPECTED_ORDER`, measured for every body), so two runs
that differ only in ``dx`` (``dx`` and ``2 dx``) bound the error of the finer
one by Richardson's estimate with Roache's safety factor for two grids:
``error = 1.25 |u(dx) - u(2 dx)| / (2^1 - 1)``. The explorer shows it on its run
card for point contacts, which it runs on a coarse grid.

This is the two-grid form of :func:`core.converged_increment` for runs already
made (the explorer solves the coarse run in its worker pool, with its cache).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from .convergence import EXPECTED_ORDER
from .result import CycleResult
from .solver3d import PointContactResult

__all__ = ["GridEstimate", "increment_error", "SAFETY_FACTOR_TWO_GRIDS"]

#: Roache's safety factor of an error bar from two grids at the expected order.
SAFETY_FACTOR_TWO_GRIDS = 1.25
# inputs a run's params may differ in between the two grids (the grid itself, and dW which follows it)
_GRID_KEYS = ("dx", "dW", "runtime_s")


@dataclass(frozen=True, eq=False)
class GridEstimate:
    """The last increment of a run with its estimated discretisation error.

    Attributes
    ----------
    value : float
        The run's last increment per period (its own units).
    coarse : float
        The same on the grid twice as coarse.
    error : float
        Estimated error of ``value``: ``1.25 |value - coarse| / (2^1 - 1)``.
    extrapolated : float
        Richardson's extrapolation ``value + (value - coarse) / (2^1 - 1)``.
    dx : float
        The run's element width [a].
    result : CycleResult or PointContactResult
        The run (at ``dx``).
    """

    value: float
    coarse: float
    error: float
    extrapolated: float
    dx: float
    result: object = field(repr=False)

    @property
    def relative_error(self) -> float:
        """``error / |value|`` (inf for a zero increment)."""
        return self.error / abs(self.value) if self.value else math.inf


def _inputs(result) -> dict:
    return {k: v for k, v in result.params.items() if k not in _GRID_KEYS}


def increment_error(fine, coarse) -> GridEstimate:
    """The estimated discretisation error of ``fine``'s last increment, from ``coarse``, the same run at ``2 dx``.

    Parameters
    ----------
    fine, coarse : CycleResult or PointContactResult
        Two runs of the same kind and inputs (``result.params``) but the grid:
        ``coarse.dx == 2 fine.dx`` (within 1e-9).

    Returns
    -------
    GridEstimate

    Raises
    ------
    ValueError
        If the runs are of different kinds, inputs or periods, or ``coarse.dx`` is not ``2 fine.dx``.

    Examples
    --------
    >>> import core
    >>> from core.grid_estimate import increment_error
    >>> fine = core.simulate_cycles(0.4, 0.6, dx=0.125, body="sphere", periods=3)
    >>> coarse = core.simulate_cycles(0.4, 0.6, dx=0.25, body="sphere", periods=3)
    >>> e = increment_error(fine, coarse)
    >>> bool(e.value == fine.increment_per_period[-1]), e.error > 0
    (True, True)
    """
    kinds = (CycleResult, PointContactResult)
    for name, r in (("fine", fine), ("coarse", coarse)):
        if not isinstance(r, kinds):
            raise ValueError(f"{name} must be a core.CycleResult or core.PointContactResult, got {type(r).__name__}")
    if type(fine) is not type(coarse):
        raise ValueError(f"fine and coarse must be runs of the same kind, got {type(fine).__name__} and "
                         f"{type(coarse).__name__}")
    if not math.isclose(coarse.dx, 2.0 * fine.dx, rel_tol=1e-9):
        raise ValueError(f"coarse.dx must be 2 fine.dx = {2 * fine.dx:.6g}, got {coarse.dx:.6g}")
    if _inputs(fine) != _inputs(coarse) or fine.periods != coarse.periods:
        raise ValueError("fine and coarse must be runs of the same inputs and periods (only dx, dW differ)")
    value = float(fine.increment_per_period[-1])
    low = float(coarse.increment_per_period[-1])
    factor = 2.0 ** EXPECTED_ORDER - 1.0
    return GridEstimate(value=value, coarse=low, error=SAFETY_FACTOR_TWO_GRIDS * abs(value - low) / factor,
                        extrapolated=value + (value - low) / factor, dx=float(fine.dx), result=fine)
