"""The rounded flat punch (plane strain): a flat of half-width ``b`` with rounded edges of radius ``R``.

The rigid profile is ``h(x) = 0`` for ``|x| < b`` and ``(|x| - b)^2 / (2 R)``
beyond, pressed by ``P`` (per length) into an elastic half-space (plane
strain, Dundurs beta = 0, so friction does not change the pressure). The
contact half-width ``a > b`` follows from the load, and the pressure is in
closed form (Ciavarella, Hills and Monno 1998). With ``x = a sin(phi)``,
``b = a sin(phi0)``:

``P = (E* a^2 / (4 R)) [pi - 2 phi0 - sin(2 phi0)]``

``p(phi) = (E* a / (2 pi R)) [(pi - 2 phi0) cos(phi) - (sin(phi) - sin(phi0)) L(phi0 - phi, phi0 + phi)
+ (sin(phi) + sin(phi0)) L(phi0 + phi, phi0 - phi)]``,  ``L(s, t) = ln|sin(s/2) / cos(t/2)|``

derived here from the inversion of the plane-strain integral equation
(``p = (E*/(2 pi)) sqrt(a^2 - x^2) PV int h'(t) / (sqrt(a^2 - t^2) (t - x)) dt``,
bounded at both ends) with ``int dtheta / (sin(theta) - sin(phi)) =
ln|sin((theta - phi)/2) / cos((theta + phi)/2)| / cos(phi)``, and checked
against the numerical normal solve (:mod:`core.pressure.normal`, ``tests/test_punch.py``).
``phi0 = 0`` is Hertz's cylinder. The pressure is bounded and continuous,
zero at ``|x| = a``, with two peaks near ``x = +-b``.

Normalised units (the project's): lengths in the nominal contact half-width
``a``, ``flat = b / a`` in [0, 1); pressure in ``p0 = 2 P / (pi a)`` (the
cylinder's peak for the same ``P`` and ``a``, so ``integral p dx = pi/2``);
gaps in ``P / E*``: the profile is ``h = (2 / G) (|x| - flat)^2`` beyond the
flat, ``G = pi - 2 phi0 - sin(2 phi0)``. Under another load ``P`` [nominal]
the flat and the radius stay, so ``a(P)`` solves ``a^2 G(phi0(a)) = P G``
with ``sin(phi0(a)) = flat / a``.

References
----------
.. [1] M. Ciavarella, D. A. Hills, G. Monno, "The influence of rounded edges
   on indentation by a flat punch", Proc. IMechE C 212 (1998) 319-328.
.. [2] J. R. Barber, *Contact Mechanics*, Springer 2018, ch. 8 (plane
   contact, the inversion formula).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..base._validate import check_scalar

__all__ = ["punch_pressure", "punch_load", "punch_half_width", "punch_profile", "DEFAULT_FLAT"]

#: The punch's default flat ``b / a``.
DEFAULT_FLAT = 0.5


def _check_flat(flat):
    return check_scalar("flat", flat, 0.0, 1.0, hi_closed=False)


def _G(s0):
    phi0 = math.asin(s0)
    return math.pi - 2.0 * phi0 - math.sin(2.0 * phi0)


def _shape(xi, s0):
    """``F(xi)`` with ``p = a F(x/a) / G_nominal``: the bracket of the closed form at ``a = 1`` (``sin phi0 = s0``)."""
    phi0 = math.asin(s0)
    xi = np.clip(np.asarray(xi, dtype=float), -1.0, 1.0)
    phi = np.arcsin(xi)
    with np.errstate(divide="ignore", invalid="ignore"):
        l1 = np.log(np.abs(np.sin(0.5 * (phi0 - phi)) / np.cos(0.5 * (phi0 + phi))))
        l2 = np.log(np.abs(np.sin(0.5 * (phi0 + phi)) / np.cos(0.5 * (phi - phi0))))
        # (xi -+ s0) ln|xi -+ s0| -> 0 at the ends of the flat
        t1 = np.where(np.isfinite(l1), (xi - s0) * l1, 0.0)
        t2 = np.where(np.isfinite(l2), (xi + s0) * l2, 0.0)
    return np.maximum(np.cos(phi) * (math.pi - 2.0 * phi0) - t1 + t2, 0.0)


def punch_load(a, flat=DEFAULT_FLAT):
    """Normal load [nominal P] that gives the contact half-width ``a`` [nominal a] (``a >= flat``)."""
    flat = _check_flat(flat)
    a = check_scalar("a", a, flat, None, lo_closed=False) if flat > 0 else check_scalar("a", a, 0.0, None)
    return a * a * _G(flat / a) / _G(flat) if a > 0 else 0.0


def punch_half_width(P=1.0, flat=DEFAULT_FLAT):
    """Contact half-width [nominal a] under the load ``P`` [nominal P], ``P > 0``.

    Examples
    --------
    >>> from core.theory.punch import punch_half_width
    >>> punch_half_width(1.0, 0.5), round(punch_half_width(4.0, 0.0), 12)
    (1.0, 2.0)
    """
    flat = _check_flat(flat)
    P = check_scalar("P", P, 0.0, None, lo_closed=False)
    if P == 1.0:
        return 1.0
    if flat == 0.0:
        return math.sqrt(P)
    hi = max(2.0, 2.0 * math.sqrt(P))
    return brentq(lambda a: punch_load(a, flat) - P, flat * (1 + 1e-15), hi, xtol=1e-15, rtol=1e-15)


def punch_pressure(x, flat=DEFAULT_FLAT, xc=0.0, P=1.0):
    """Closed-form pressure [p0] of the rounded punch centred at ``xc`` [a] under the load ``P`` [nominal P].

    Parameters
    ----------
    x : array_like
        Positions [a].
    flat : float
        ``b / a`` in [0, 1) (0: the cylinder, Hertz).
    xc : float
        Centre of the punch [a].
    P : float
        Normal load [nominal P], > 0.

    Examples
    --------
    >>> import numpy as np
    >>> from core.theory.punch import punch_pressure
    >>> bool(np.allclose(punch_pressure([0.0, 0.6], flat=0.0), [1.0, 0.8]))
    True
    >>> round(float(punch_pressure(0.0, flat=0.5)), 4), float(punch_pressure(1.0, flat=0.5))
    (0.6329, 0.0)
    """
    flat = _check_flat(flat)
    a = punch_half_width(P, flat)
    xi = (np.asarray(x, dtype=float) - xc) / a
    return np.where(np.abs(xi) < 1.0, a * _shape(xi, flat / a) / _G(flat), 0.0)


def punch_profile(x, flat=DEFAULT_FLAT):
    """The gap ``h`` [P/E*] before the load: 0 over the flat, ``(2/G)(|x| - flat)^2`` beyond (nominal units)."""
    flat = _check_flat(flat)
    x = np.asarray(x, dtype=float)
    return (2.0 / _G(flat)) * np.clip(np.abs(x) - flat, 0.0, None) ** 2
