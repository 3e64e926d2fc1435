"""Bodies: the contact geometry of a run, its grid, its traction bound per step, and its closed forms.

A body knows everything about the contact that is not elasticity and not
friction law: the grid of world-fixed elements, the normal pressure under a
given centre position and normal load (so the traction bound ``mu p`` of every
element at every step), the Hertz scales, how the tangential load maps to a
sum of element tractions, and its closed-form references.

:class:`Cylinder` is the line contact of Wetter (2015): a 1D grid, the Hertz
pressure of eq 4 averaged exactly over each element, half-width and peak both
scaling as ``sqrt(P)`` (eq 5). Point contacts (sphere, ellipsoid: 2D grids)
are added by writing one module with a class of the same interface and
registering it in :data:`BODIES` (see the developer guide, ``docs/dev/adding-a-body.md``).

Normalised units: lengths in the nominal half-width ``a``, pressure in the
nominal ``p0``, tractions in ``mu p0``, normal load in the nominal ``P``,
tangential load in ``mu P``.
"""

from __future__ import annotations

import math

import numpy as np

from . import analytical
from ._hertz import element_means

__all__ = ["Cylinder", "BODIES", "get_body", "MAX_ELEMENTS", "MAX_FFT_ELEMENTS"]

#: Largest grid of the dense solver (its matrix and interval inverses need 8 n^2 bytes each).
MAX_ELEMENTS = 4000
#: Largest grid of any run: the matrix-free solver (``solver="fft"``) stores no matrix.
MAX_FFT_ELEMENTS = 16384


class Cylinder:
    """The rocking cylinder (line contact, plane problem) on a uniform 1D grid.

    Parameters
    ----------
    edges : array_like, shape (n + 1,)
        Uniform, increasing element edges [a] (see :meth:`for_reach`).

    Attributes
    ----------
    name : str
        ``"cylinder"``, its key in :data:`BODIES`.
    edges, x : ndarray
        Element edges and centres [a] (read-only).
    dx : float
        Element width [a]; also the element measure of the load balance.
    shape : tuple
        ``(n,)``: the shape of a traction field on this body.
    """

    name = "cylinder"
    #: Total load of a unit traction over the Hertz area per unit of Q: ``sum q dx = (pi/2) Q`` (eq 5: P = pi a p0 / 2).
    load_factor = 0.5 * math.pi

    def __init__(self, edges):
        edges = np.array(edges, dtype=float)
        if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0):
            raise ValueError("edges must be a strictly increasing 1-D array of at least 2 values")
        if edges.size - 1 > MAX_FFT_ELEMENTS:
            raise ValueError(f"the grid has {edges.size - 1} elements (> {MAX_FFT_ELEMENTS}): use a larger dx")
        edges.setflags(write=False)
        self.edges = edges
        self.dx = float(edges[1] - edges[0])
        x = 0.5 * (edges[1:] + edges[:-1])
        x.setflags(write=False)
        self.x = x
        self.shape = (edges.size - 1,)

    @property
    def size(self) -> int:
        """Number of elements."""
        return self.shape[0]

    # ---- grid ----------------------------------------------------------------
    @classmethod
    def for_reach(cls, reach, dx, max_elements=MAX_ELEMENTS):
        """The uniform grid symmetric about 0 that covers ``[-reach, reach]`` with one spare element each side.

        Parameters
        ----------
        reach : float
            Largest distance from 0 that the contact reaches [a].
        dx : float
            Element width [a].
        max_elements : int
            Largest grid allowed: :data:`MAX_ELEMENTS` (the dense solver's, the default)
            or up to :data:`MAX_FFT_ELEMENTS` (the matrix-free solver's).

        Raises
        ------
        ValueError
            If the grid would exceed ``max_elements`` elements (names ``dx`` and the smallest it may be).
        """
        max_elements = min(int(max_elements), MAX_FFT_ELEMENTS)
        half = math.ceil(reach / dx - 1e-9) + 1
        n = 2 * half
        if n > max_elements:
            hint = " or solver='fft'" if max_elements < MAX_FFT_ELEMENTS else ""
            raise ValueError(f"dx = {dx:g} needs {n} elements (> {max_elements}): dx must be >= "
                             f"{reach / (max_elements // 2 - 1):.4g} here; use a larger dx{hint}")
        return cls(dx * (np.arange(n + 1) - half))

    @classmethod
    def for_history(cls, history, dx, max_elements=MAX_ELEMENTS):
        """The grid covering every contact of a loading history (:class:`~core.schedule.Schedule`)."""
        return cls.for_reach(cls.reach(history.xc, history.P), dx, max_elements)

    # ---- Hertz scales (eq 5) -------------------------------------------------
    @staticmethod
    def half_width(P):
        """Contact half-width [a] under the normal load ``P`` [nominal P]: ``a ~ sqrt(P)``."""
        return np.sqrt(P)

    @staticmethod
    def peak_pressure(P):
        """Peak pressure [nominal p0] under ``P``: ``p0 = 2 P / (pi a) ~ sqrt(P)``."""
        return np.sqrt(P)

    @classmethod
    def reach(cls, xc, P) -> float:
        """Largest distance from 0 that any contact of the steps ``(xc, P)`` reaches [a]."""
        return float(np.max(np.abs(xc) + cls.half_width(P)))

    # ---- the traction bound --------------------------------------------------
    def bounds(self, xc, P, out=None):
        """Traction bound ``mu p`` of every element at every step [mu p0], shape (steps, n).

        The exact element mean of the Hertz pressure (eq 4) centred at ``xc``
        under the normal load ``P``; 0 out of contact. The one definition used
        by the solvers and by :attr:`core.CycleResult.pressure`.
        """
        P = np.asarray(P, dtype=float)
        return element_means(self.edges, xc, self.half_width(P), self.peak_pressure(P), out)

    def load_target(self, Q):
        """``sum q_i`` [mu p0] that carries the tangential load ``Q`` [mu P]."""
        return np.asarray(Q, dtype=float) * (self.load_factor / self.dx)

    def lowest_bound(self, w):
        """``mu p_min`` per element while the centre rocks over ``[-w, w]`` at the nominal load [mu p0].

        The element mean of the concave Hertz profile is quasi-concave in the
        centre position, so its minimum over the period is at a turning point.
        """
        turning = self.bounds(np.array([-w, w]), np.ones(2))
        return turning.min(axis=0)

    # ---- closed-form references (Wetter 2015) ---------------------------------
    ft_limit = staticmethod(analytical.ft_limit)                          # eq 35
    w_limit = staticmethod(analytical.w_limit)                            # inverse of eq 35
    cattaneo_stick_halfwidth = staticmethod(analytical.cattaneo_stick_halfwidth)  # eq 7
    cattaneo_traction = staticmethod(analytical.cattaneo_traction)        # eqs 8-12
    shakedown_stick_halfwidth = staticmethod(analytical.shakedown_stick_halfwidth)  # eq 30
    shakedown_traction = staticmethod(analytical.shakedown_traction)      # eqs 22-26


#: The bodies a run can use, by name. A point contact adds its class here.
BODIES = {"cylinder": Cylinder}


def get_body(name):
    """The body class registered under ``name`` (a class passes through).

    Raises
    ------
    ValueError
        If ``name`` is not in :data:`BODIES` (the message lists them).
    """
    if isinstance(name, type):
        return name
    if name not in BODIES:
        raise ValueError(f"body must be one of {', '.join(sorted(BODIES))}, got {name!r:.60}")
    return BODIES[name]
