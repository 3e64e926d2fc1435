"""The exact element mean of the Hertz line-contact pressure: one numba kernel for the solver and the result.

The traction bound of an element is ``mu`` times the mean of the Hertz
pressure (Wetter 2015, eq 4) over the element, not its midpoint value, so the
element loads add up exactly to the normal load on any grid.
"""

from __future__ import annotations

import math

import numpy as np

from ._jit import jit

__all__ = ["element_means"]

_QUARTER_PI = 0.5 * math.asin(1.0)


@jit
def _primitive(t):
    """Antiderivative of ``sqrt(1 - t^2)`` on [-1, 1], constant outside."""
    if t >= 1.0:
        return _QUARTER_PI  # the same number as the formula at t = 1, without its asin
    if t <= -1.0:
        return -_QUARTER_PI
    return 0.5 * (t * math.sqrt(1.0 - t * t) + math.asin(t))


@jit
def _element_means(edges, xc, a, peak, out):
    for k in range(xc.size):
        F1 = _primitive((edges[0] - xc[k]) / a[k])
        for i in range(edges.size - 1):
            F2 = _primitive((edges[i + 1] - xc[k]) / a[k])
            # differences of the primitive can round to -1e-16 where the profile vanishes
            out[k, i] = max(peak[k] * a[k] * (F2 - F1) / (edges[i + 1] - edges[i]), 0.0)
            F1 = F2


def element_means(edges, xc, a, peak, out=None):
    """Mean of ``peak sqrt(1 - ((x - xc)/a)^2)`` over each element, for every step.

    Parameters
    ----------
    edges : ndarray, shape (n + 1,)
        Increasing element edges.
    xc, a, peak : array_like, shape (steps,) or scalars
        Centre, half-width and peak of the profile at each step (broadcast together).
    out : ndarray, shape (steps, n), optional
        Where to write.

    Returns
    -------
    ndarray, shape (steps, n)
    """
    xc, a, peak = (np.ascontiguousarray(v, dtype=float) for v in np.broadcast_arrays(
        np.atleast_1d(xc), np.atleast_1d(a), np.atleast_1d(peak)))
    edges = np.ascontiguousarray(edges, dtype=float)
    if out is None:
        out = np.empty((xc.size, edges.size - 1))
    _element_means(edges, xc, a, peak, out)
    return out
