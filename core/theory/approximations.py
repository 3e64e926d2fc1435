"""The paper's regressions and reconstructed approximations.

Everything in this module is an *approximation* fitted by the paper's author [1]_
(or reconstructed from its garbled text), kept apart from the exact results of
:mod:`core.theory.analytical` so the two are never confused. Use them to compare with
the paper's figures; the numerical solver (:mod:`core.api.solver`) is the ground
truth of this project.

Normalised units: ``ft = Ft/(mu Fn)``, ``w = W/a``, displacements ``u = U/U0``
unless stated otherwise.

References
----------
.. [1] R. Wetter, Physical Mesomechanics 18 (2015), eqs 13, 14, 34, 36, 38.
"""

from __future__ import annotations

import numpy as np

from ..base._validate import check_range

__all__ = [
    "W_LIMIT_REGRESSION_EXPONENT",
    "static_displacement_approx",
    "u0_approx",
    "shakedown_displacement_approx",
    "w_limit_regression",
    "ratchet_increment_approx",
]

#: Exponent ``k`` of eq 36, ``w_lim ~ 1 - ft_lim**k``. The paper's digits are
#: unreadable (0.7 to 0.75); 0.73 is the least-squares fit of this form to the
#: exact eq 35 over ft in (0, 1) (max error 0.011 in w).
W_LIMIT_REGRESSION_EXPONENT = 0.73


def static_displacement_approx(ft):
    """Static tangential displacement ``U_stat / U0 = 1 - (1 - ft)^0.92`` (eq 13, regression).

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1].
    """
    ft = check_range("ft", ft, 0.0, 1.0)
    return 1.0 - (1.0 - ft) ** 0.92


def u0_approx(L_over_a, nu):
    """Displacement at ``ft = 1`` of a strip of length ``L``, in ``mu P / E*`` (eq 14, reconstructed).

    ``U0 E* / (mu P) = (2/pi) [ln(L/a) + ln 2 + 1/2 + nu/(1 - nu)]``: the
    asymptotic form for ``L >> a`` of the Cerruti solution integrated over the
    strip, which matches the paper's garbled eq 14 when its ``ln(1.8 E*/G*)``
    is read as ``nu / (1 - nu)``. Compare with the strip kernel's exact value
    (:func:`core.elastic.kernels.strip_u0`).

    Parameters
    ----------
    L_over_a : array_like
        Cylinder length over half-width, > 1.
    nu : array_like
        Effective Poisson ratio in [0, 0.5].
    """
    L_over_a = check_range("L_over_a", L_over_a, 1.0, None, lo_closed=False)
    nu = check_range("nu", nu, 0.0, 0.5)
    return (2.0 / np.pi) * (np.log(L_over_a) + np.log(2.0) + 0.5 + nu / (1.0 - nu))


def shakedown_displacement_approx(ft, w):
    """Shakedown displacement ``u_sd = 1 - (1 - ft)^0.92 + 0.3 ft w`` (eq 34, regression).

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1).
    w : array_like
        ``W / a`` in [0, 1).

    Returns
    -------
    ndarray
        ``U_sd / U0``.
    """
    ft = check_range("ft", ft, 0.0, 1.0, hi_closed=False)
    w = check_range("w", w, 0.0, 1.0, hi_closed=False)
    return 1.0 - (1.0 - ft) ** 0.92 + 0.3 * ft * w


def w_limit_regression(ft, k=W_LIMIT_REGRESSION_EXPONENT):
    """The paper's regression for the limit amplitude, ``w_lim ~ 1 - ft^k`` (eq 36).

    Use :func:`core.w_limit` for the exact inverse of eq 35.

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1].
    k : float
        Exponent, default :data:`W_LIMIT_REGRESSION_EXPONENT`.
    """
    ft = check_range("ft", ft, 0.0, 1.0)
    k = float(check_range("k", k, 0.0, None, lo_closed=False))
    return 1.0 - ft**k


def ratchet_increment_approx(ft, w, w_lim=None):
    """Ratcheting displacement per period ``du = 0.64 ft (w - w_lim)`` (eq 38, regression).

    A linear regression of the paper's data; the numerical rate is not linear
    in ``w - w_lim`` near the limit, so treat this as rough and compare with
    the solver. Returns 0 below the limit.

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1).
    w : array_like
        ``W / a`` in [0, 1).
    w_lim : array_like, optional
        Limit amplitude; defaults to the exact inverse of eq 35.

    Returns
    -------
    ndarray
        Increment of ``u = U / U0`` per period.
    """
    from .analytical import w_limit

    ft = check_range("ft", ft, 0.0, 1.0, hi_closed=False)
    w = check_range("w", w, 0.0, 1.0, hi_closed=False)
    wl = w_limit(ft) if w_lim is None else check_range("w_lim", w_lim, 0.0, 1.0)
    return 0.64 * ft * np.clip(w - wl, 0.0, None)
