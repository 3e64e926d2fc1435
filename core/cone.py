"""The rocking cone (a cone or tapered roller, a frustum, on its side): its shakedown limit from Melan's theorem.

A rigid cone of half-angle ``alpha`` lies on its side on an elastic
half-space, touching it along a generatrix from the distance ``r1`` to ``r2``
from its apex (``r1 = 0``: a full cone; ``r1 > 0``: a frustum, a tapered
roller). It rocks by rolling back and forth without slip, so it turns about
the vertical axis through its apex: the contact line sweeps the angle
``[-Theta, Theta]`` and each of its points moves along a circle about the apex,
by ``r Theta`` at the distance ``r``. A constant tangential force ``Ft`` acts
perpendicular to the cone's axis (across the contact line) at the distance
``r_F`` from the apex; the body is free to translate and to turn about the
normal (no applied twisting moment). Uncoupled (Dundurs beta = 0).

Slices. Across the contact line at ``r`` the cone's surface has the radius of
curvature ``R(r) = r tan(alpha)`` (zero curvature along the generatrix), so
each slice is a Hertz line contact (the strip or slice theory of rollers,
valid while the contact is long against its width). With a uniform line load
``P`` (this module's assumption), its half-width is
``a(r) = sqrt(4 R(r) P / (pi E*)) = a_m sqrt(r / r_m)``, ``r_m = (r1 + r2)/2``.
A rotation about the apex keeps every point's distance from the apex, so a
point at ``(r, phi)`` sees only the slice at ``r``, whose contact centre passes
it at the arc distance ``r (phi - theta)``: the slice rocks with the amplitude
``W(r) = r Theta``.

Normalised parameters: ``inner = r1 / r2`` in [0, 1) (0: the full cone; near
1: a frustum far from its apex, i.e. a cylinder); ``w = W_m / a_m``, the
amplitude over the half-width both at the mid-length ``r_m``; ``ft = Ft / (mu
Fn)``. The local amplitude is then ``w(r) = w sqrt(r / r_m)``: it grows along
the contact, and the slices with ``w(r) >= 1`` lose contact once a period.

Limit (Melan, :mod:`core.melan`). The lowest pressure over the cycle at
``(r, phi)`` is that of slice ``r`` at its own amplitude ``w(r)``, so its
line density is ``m(r) = mu P ft_cyl(w(r))`` with eq 35's
``ft_cyl``. Shakedown needs a traction field ``|q| <= mu p_min`` carrying
``Ft`` with no moment about the normal through ``r_F``:
maximise ``integral f dr`` over ``|f| <= m``, ``integral (r - r_F) f dr = 0``.
If ``r_F`` is the centroid of ``m`` the answer is ``integral m dr`` (the body's
rotation plays no part); otherwise the optimum is ``f = +-m`` with one switch
of sign (the Lagrange condition ``f = m sign(1 - lambda (r - r_F))``), which
this module finds. ``load_point=None`` drops the moment condition (the
rotation about the normal restrained): an upper bound.

What is new against the cylinder: the local amplitude varies along the contact
(``w sqrt(r / r_m)``), so the outer end reaches release first, and the moment
condition couples the slices: with ``Ft`` at the mid-length the lowest-pressure
centroid lies nearer the apex, and part of the contact must carry traction
against ``Ft`` to balance the moment, which lowers the limit.

Examples
--------
>>> from core.cone import cone_ft_limit
>>> round(float(cone_ft_limit(0.3, inner=0.999)), 3)  # a frustum far from its apex: the cylinder's 0.624
0.624
"""

from __future__ import annotations


import numpy as np
from scipy.optimize import brentq

from ._validate import check_scalar

__all__ = ["Cone", "cone_ft_limit", "cone_w_limit", "slice_amplitude", "lowest_pressure_density"]


def _quad(inner, n=4000):
    """Gauss-Legendre nodes and weights on [inner, 1] (lengths in r2), in panels."""
    g, wts = np.polynomial.legendre.leggauss(8)
    edges = np.linspace(inner, 1.0, n // 8 + 1)
    h = np.diff(edges)
    r = (0.5 * (edges[:-1] + edges[1:]))[:, None] + 0.5 * h[:, None] * g[None, :]
    return r.ravel(), (0.5 * h[:, None] * wts[None, :]).ravel()


def slice_amplitude(r, w, inner):
    """The local amplitude ``w(r) = w sqrt(r / r_m)`` (``r`` in ``r2``, ``r_m = (1 + inner)/2``)."""
    return w * np.sqrt(np.asarray(r, dtype=float) / (0.5 * (1.0 + inner)))


def lowest_pressure_density(r, w, inner):
    """``m(r) / (mu P)``: eq 35 at the slice's own amplitude (0 where ``w(r) >= 1``)."""
    from .analytical import ft_limit
    return ft_limit(np.minimum(slice_amplitude(r, w, inner), 1.0))


def cone_ft_limit(w, inner=0.5, load_point="centre"):
    """The shakedown limit ``ft_lim = Ft_lim / (mu Fn)`` of the rocking cone (slices, uniform line load).

    Parameters
    ----------
    w : float
        ``W_m / a_m`` at the mid-length, in [0, 10].
    inner : float
        ``r1 / r2`` in [0, 1) (0: the full cone).
    load_point : "centre", float or None
        Where ``Ft`` acts: ``"centre"`` (the mid-length, where a uniform
        normal load acts), a distance from the apex in ``r2`` (in
        ``[inner, 1]``), or None (no moment condition: the rotation about the
        normal restrained; an upper bound).

    Returns
    -------
    float
    """
    w = check_scalar("w", w, 0.0, 10.0)
    inner = check_scalar("inner", inner, 0.0, 1.0, hi_closed=False)
    r, wq = _quad(inner)
    m = lowest_pressure_density(r, w, inner)
    length = 1.0 - inner
    total = float(np.dot(wq, m))
    if load_point is None or total == 0.0:
        return float(total / length)
    rF = 0.5 * (1.0 + inner) if (isinstance(load_point, str) and load_point == "centre") else check_scalar(
        "load_point", load_point, inner, 1.0)
    arm = r - rF
    moment = float(np.dot(wq, m * arm))
    if abs(moment) <= 1e-15:
        return float(total / length)
    # one switch of sign at c (the Lagrange condition): f = +-m for r < c, -+m beyond, with zero moment:
    # 2 M(c) = M(1), M(c) the moment of m over [inner, c] (cumulative over the quadrature nodes, linear
    # between: continuous in c). Of the switch points (where 2 M - M(1) changes sign) the one carrying most.
    M = np.concatenate(([0.0], np.cumsum(wq * m * arm)))
    F = np.concatenate(([0.0], np.cumsum(wq * m)))
    g = 2.0 * M - M[-1]
    best = 0.0
    for k in np.flatnonzero(np.sign(g[1:]) != np.sign(g[:-1])) + 1:
        t = g[k - 1] / (g[k - 1] - g[k])
        Fc = F[k - 1] + t * (F[k] - F[k - 1])
        best = max(best, abs(2.0 * Fc - F[-1]))
    return float(best / length)


def cone_w_limit(ft, inner=0.5, load_point="centre"):
    """The inverse of :func:`cone_ft_limit` in ``w`` (the largest amplitude that shakes down at ``ft``)."""
    ft = check_scalar("ft", ft, 0.0, 1.0)
    if ft >= 1.0:
        return 0.0
    hi = 10.0
    if cone_ft_limit(hi, inner, load_point) >= ft:
        return hi
    return brentq(lambda v: cone_ft_limit(v, inner, load_point) - ft, 0.0, hi, xtol=1e-10)


class Cone:
    """The rocking cone or frustum as an object with parameters (its limit; see the module's text).

    Parameters
    ----------
    inner : float
        ``r1 / r2`` in [0, 1) (0: a full cone). Default 0.5.
    load_point : "centre", float or None
        Where ``Ft`` acts (see :func:`cone_ft_limit`).

    Examples
    --------
    >>> from core.cone import Cone
    >>> c = Cone(inner=0.5)
    >>> bool(c.ft_limit(0.3) < c.ft_limit(0.3, restrained=True))
    True
    """

    name = "cone"

    def __init__(self, inner=0.5, load_point="centre"):
        self.inner = check_scalar("inner", inner, 0.0, 1.0, hi_closed=False)
        if not (load_point is None or (isinstance(load_point, str) and load_point == "centre")):
            load_point = check_scalar("load_point", load_point, self.inner, 1.0)
        self.load_point = load_point

    @property
    def parameters(self) -> dict:
        return {"inner": self.inner, "load_point": self.load_point}

    def __repr__(self):
        return f"Cone(inner={self.inner!r}, load_point={self.load_point!r})"

    def ft_limit(self, w, restrained=False):
        """:func:`cone_ft_limit` (``restrained``: no moment condition)."""
        return cone_ft_limit(w, self.inner, None if restrained else self.load_point)

    def w_limit(self, ft, restrained=False):
        """:func:`cone_w_limit`."""
        return cone_w_limit(ft, self.inner, None if restrained else self.load_point)
