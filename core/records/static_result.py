"""The record of a static partial-slip solve (:class:`StaticResult`), and the stick test it shares with the cycle
result (:func:`below_bound`, :func:`central_halfwidth`, :data:`STICK_MARGIN`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base._validate import read_only

__all__ = ["StaticResult", "STICK_MARGIN", "below_bound", "central_halfwidth"]


#: Margin [mu p0] below the traction bound that counts as sticking in the final state.
STICK_MARGIN = 1e-7
def below_bound(q, bound):
    """Elements whose traction stays strictly below a positive bound (by :data:`STICK_MARGIN`)."""
    return (bound > 0) & (np.abs(q) < bound - STICK_MARGIN)


def central_halfwidth(mask, edges) -> float:
    """Half-width [a] of the contiguous run of ``mask`` elements closest to x = 0 (0 if none)."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return 0.0
    x = 0.5 * (edges[1:] + edges[:-1])
    lo = hi = idx[np.argmin(np.abs(x[idx]))]
    while lo - 1 >= 0 and mask[lo - 1]:
        lo -= 1
    while hi + 1 < mask.size and mask[hi + 1]:
        hi += 1
    return float(0.5 * (edges[hi + 1] - edges[lo]))


@dataclass(frozen=True, eq=False)
class StaticResult:
    """A static partial-slip solution on a line or a patch of elements: the one result of the static solves.

    :func:`core.solve_static`, :func:`core.shakedown_state` and
    :func:`core.mindlin_state` return it for every body (the former
    ``StaticSolution``, ``ShakedownState`` and ``StaticResult3D`` are its
    names). Every array is read-only.

    Attributes
    ----------
    traction : ndarray, shape (n,) or (2, ny, nx)
        Element tractions [mu p0] (a patch: both components).
    displacement : float or ndarray, shape (2,)
        Rigid-body displacement [mu P/E*; a patch: mu Fn/(E* a)].
    residuals : dict
        The named KKT residuals (:data:`core.base.states.RESIDUAL_NAMES`).
    bound : ndarray, shape (n,) or (ny, nx)
        The traction bound [mu p0]: ``mu p`` (Cattaneo-Mindlin) or ``mu p_min`` (the shaken-down state).
    edges : ndarray
        Element edges along x [a] (a line given only ``dx``: centred on the origin).
    y_edges : ndarray or None
        A patch's edges along y (None on a line).
    iterations : int
        Active-set iterations.
    state : ndarray of int8
        0 out of contact (no bound), 1 stick (below the bound by :data:`STICK_MARGIN`), 2 at the bound.
    """

    traction: np.ndarray
    displacement: float | np.ndarray
    residuals: dict
    bound: np.ndarray
    edges: np.ndarray
    y_edges: np.ndarray | None = None
    iterations: int = 0
    state: np.ndarray | None = None

    def __post_init__(self):
        if self.state is None:
            mag = np.hypot(self.traction[0], self.traction[1]) if self.is_patch else self.traction
            state = np.where(self.bound > 0, np.where(below_bound(mag, self.bound), 1, 2), 0).astype(np.int8)
            object.__setattr__(self, "state", state)
        for value in (self.traction, self.bound, self.edges, self.y_edges, self.state, self.displacement,
                      *self.residuals.values()):
            if isinstance(value, np.ndarray):
                read_only(value)

    @property
    def is_patch(self) -> bool:
        """True on a patch of elements, False on a line."""
        return self.y_edges is not None

    @property
    def x_edges(self) -> np.ndarray:
        """The edges along x [a] (:attr:`edges`)."""
        return self.edges

    @property
    def x(self) -> np.ndarray:
        """Element centres along x [a]."""
        return 0.5 * (self.edges[1:] + self.edges[:-1])

    @property
    def y(self) -> np.ndarray | None:
        """A patch's element centres along y [a] (None on a line)."""
        return None if self.y_edges is None else 0.5 * (self.y_edges[1:] + self.y_edges[:-1])

    @property
    def cut_row(self) -> int | None:
        """A patch's grid row on ``y = 0`` (None on a line)."""
        return None if self.y_edges is None else (self.y_edges.size - 1) // 2

    @property
    def stick_halfwidth(self) -> float:
        """Half-extent along x [a] of the central stick zone (a patch: on ``y = 0``); 0 if none."""
        stick = self.state[self.cut_row] if self.is_patch else self.state
        return central_halfwidth(stick == 1, self.edges)

    @property
    def stick_halfwidth_y(self) -> float | None:
        """A patch's half-extent along y [a] of the central stick zone on ``x = 0`` (None on a line)."""
        if not self.is_patch:
            return None
        return central_halfwidth(self.state[:, (self.edges.size - 1) // 2] == 1, self.y_edges)
