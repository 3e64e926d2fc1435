"""Loading schedules: what the cycle solver is driven by, as plain arrays.

A schedule is the list of steps of the quasi-static history: at each step the
contact centre ``xc`` [a], the normal load ``P`` [nominal P] and the
tangential load ``Q`` [mu P_nominal], and the period the step belongs to (-1
for the initial loading). The default is the paper's: ``Q`` applied at
``xc = 0``, then ``N`` periods of rocking ``0 -> +W -> -W -> 0`` in steps of
``dW``. An oscillating normal or tangential load (the paper's future work) is
the same solver driven by other arrays.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base._validate import check_int, check_range, check_scalar

__all__ = ["Schedule", "rocking_schedule", "SHAPES", "MAX_STEPS"]

#: Waveforms of the rocking motion.
SHAPES = ("triangle", "sine")
#: Largest number of steps a schedule may have.
MAX_STEPS = 2_000_000


@dataclass(frozen=True, eq=False)
class Schedule:
    """Steps of a loading history (normalised units).

    Attributes
    ----------
    xc : ndarray, shape (steps,)
        Contact centre [a].
    P : ndarray, shape (steps,)
        Normal load per length [nominal P], > 0 (the half-width scales as ``sqrt(P)``).
    Q : ndarray, shape (steps,)
        Tangential load per length [mu P_nominal], ``|Q| < P``.
    period : ndarray of int, shape (steps,)
        Period index, -1 for the loading; non-decreasing.
    """

    xc: np.ndarray
    P: np.ndarray
    Q: np.ndarray
    period: np.ndarray

    def __post_init__(self):
        xc = check_range("xc", self.xc)
        P = check_range("P", self.P, 0.0, None, lo_closed=False)
        Q = check_range("Q", self.Q)
        period = np.asarray(self.period)
        n = xc.size
        if xc.ndim != 1 or n == 0 or n > MAX_STEPS:
            raise ValueError(f"xc must be a 1-D array of 1 to {MAX_STEPS} steps, got shape {xc.shape}")
        for name, arr in (("P", P), ("Q", Q), ("period", period)):
            if arr.shape != xc.shape:
                raise ValueError(f"{name} must have the shape of xc {xc.shape}, got {arr.shape}")
        if not np.all(np.isfinite(xc)):
            raise ValueError("xc must be finite")
        if np.any(np.abs(Q) >= P):
            bad = int(np.argmax(np.abs(Q) >= P))
            raise ValueError(f"Q must satisfy |Q| < P (ft < 1) at every step; step {bad} has Q = {Q[bad]:g}, P = {P[bad]:g}")
        if period.dtype.kind not in "iu" or np.any(np.diff(period) < 0) or period.min() < -1:
            raise ValueError("period must be a non-decreasing integer array starting at -1 or 0")
        for name, arr in (("xc", xc), ("P", P), ("Q", Q), ("period", period.astype(np.int64))):
            arr = np.ascontiguousarray(arr)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def __len__(self) -> int:
        return int(self.xc.size)

    @property
    def periods(self) -> int:
        """Number of periods after the loading."""
        return int(self.period.max()) + 1

    @property
    def reach(self) -> float:
        """Largest distance from 0 that any contact of a cylinder reaches [a]: ``max |xc| + sqrt(P)`` (Hertz's
        half-width grows as ``sqrt(P)``; the same as :meth:`core.geometry.bodies.Cylinder.reach`)."""
        return float(np.max(np.abs(self.xc) + np.sqrt(self.P)))

    def is_periodic(self) -> bool:
        """True if every period repeats the same steps (so a repeated state repeats the whole period)."""
        rocking = self.period >= 0
        counts = np.bincount(self.period[rocking])
        if counts.size < 2 or np.any(counts != counts[0]):
            return False
        m = counts[0]
        for arr in (self.xc, self.P, self.Q):
            blocks = arr[rocking].reshape(-1, m)
            if not np.array_equal(blocks, np.broadcast_to(blocks[0], blocks.shape)):
                return False
        return True


def _steps_per_period(w: float, dW: float, shape: str) -> int:
    if w == 0.0:
        return 4
    if shape == "triangle":
        # 0 -> W -> -W -> 0 is 4 W long: 4 round(W / dW) steps (the paper's counts)
        return 4 * max(1, round(w / dW))
    # sine: largest step 2 pi W / N <= dW, N a multiple of 4 so the turning points are steps
    return 4 * max(1, math.ceil(2.0 * math.pi * w / dW / 4.0))


def rocking_schedule(ft, w, periods=10, dW=0.025, shape="triangle", load_steps=1):
    """The paper's schedule: apply ``ft`` at ``xc = 0``, then rock ``periods`` times.

    Parameters
    ----------
    ft : float
        Tangential load ``Ft / (mu Fn)`` in [0, 1). Negative values pull the
        other way (``(-1, 1)`` is accepted).
    w : float
        Rocking amplitude ``W / a`` in [0, 1).
    periods : int
        Number of rocking periods, in [1, 10000].
    dW : float
        Largest step of the contact centre [a], in (0, 1].
    shape : {"triangle", "sine"}
        ``"triangle"``: ``xc`` moves at constant speed ``0 -> W -> -W -> 0``
        with ``4 round(W / dW)`` steps a period, as in the paper (2641 steps for
        w = 0.77, dW = a/85.45, 10 periods). ``"sine"``: ``xc = W sin(2 pi t)``
        with steps no larger than ``dW``.
    load_steps : int
        Steps of the initial monotonic loading at ``xc = 0``, in [1, 10000]. One
        step gives the exact Cattaneo-Mindlin state (monotonic loading is
        path-independent), as the paper's step counts imply.

    Returns
    -------
    Schedule

    Examples
    --------
    The loading step, then the centre ``0 -> W -> -W -> 0`` in steps of ``dW`` each period:

    >>> s = rocking_schedule(0.3, 0.5, periods=1, dW=0.25)
    >>> s.xc
    array([ 0.  ,  0.25,  0.5 ,  0.25,  0.  , -0.25, -0.5 , -0.25,  0.  ])
    >>> s.period
    array([-1,  0,  0,  0,  0,  0,  0,  0,  0])
    """
    ft = check_scalar("ft", ft, -1.0, 1.0, lo_closed=False, hi_closed=False)
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    periods = check_int("periods", periods, 1, 10_000)
    dW = check_scalar("dW", dW, 0.0, 1.0, lo_closed=False)
    if shape not in SHAPES:
        raise ValueError(f"shape must be one of {SHAPES}, got {shape!r:.60}")
    load_steps = check_int("load_steps", load_steps, 1, 10_000)
    m = _steps_per_period(w, dW, shape)
    total = load_steps + m * periods
    if total > MAX_STEPS:
        raise ValueError(f"the schedule would have {total} steps (> {MAX_STEPS}): use fewer periods or a larger dW")
    phase = np.arange(1, m + 1) / m
    if shape == "triangle":
        one = w * np.where(phase <= 0.25, 4 * phase, np.where(phase <= 0.75, 2 - 4 * phase, 4 * phase - 4))
    else:
        one = w * np.sin(2 * np.pi * phase)
        one[np.isclose(phase, 0.5) | np.isclose(phase, 1.0)] = 0.0
    xc = np.concatenate([np.zeros(load_steps), np.tile(one, periods)])
    Q = np.concatenate([ft * np.arange(1, load_steps + 1) / load_steps, np.full(m * periods, ft)])
    period = np.concatenate([np.full(load_steps, -1), np.repeat(np.arange(periods), m)])
    return Schedule(xc=xc, P=np.ones_like(xc), Q=Q, period=period)
