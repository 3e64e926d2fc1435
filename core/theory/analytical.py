"""Closed-form model of the rocking cylinder (Wetter 2015), in normalised units.

Normalisation used throughout this module (plane problem, per unit length):

* lengths ``x``, ``xc``, ``c`` in units of the Hertz half-width ``a``;
* pressure in units of the peak pressure ``p0``;
* tractions in units of ``mu * p0``;
* ``ft = Ft / (mu Fn)`` and ``w = W / a``.

Everything is vectorised over numpy arrays and broadcasts like a ufunc.
What is *exact* lives here (Hertz, Cattaneo-Mindlin, the shakedown limit of
eq 35 and its inverse); the paper's stick-zone ansatz (eqs 22-30) is exact
only as far as the ansatz is, and is checked against the numerical solver in
:mod:`core.api.solver`. The paper's regressions live in :mod:`core.theory.approximations`.

References
----------
.. [1] R. Wetter, "Frictional shakedown and ratcheting of an oscillating
   cylindrical, elastic contact with Coulomb friction", Physical
   Mesomechanics 18 (2015). Equation numbers below refer to this paper.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import elementwise

from ..base._hertz import element_means
from ..base._validate import check_range
from ..base.states import Zone

__all__ = [
    "hertz_pressure",
    "hertz_pressure_element_mean",
    "cattaneo_stick_halfwidth",
    "cattaneo_traction",
    "ft_limit",
    "w_limit",
    "shakedown_closure",
    "shakedown_stick_halfwidth",
    "shakedown_traction",
    "shakedown_zones",
    "lowest_pressure",
    "classify_regime",
    "fretting_energy_line",
    "fretting_energy_sphere",
    "ZONE_NONE",
    "ZONE_STICK",
    "ZONE_SLIP",
    "ZONE_RELEASED",
    "REGIMES",
]

#: Zone codes returned by :func:`shakedown_zones` (aliases of :class:`core.base.states.Zone`).
ZONE_NONE, ZONE_STICK, ZONE_SLIP, ZONE_RELEASED = Zone.NONE, Zone.STICK, Zone.SLIP, Zone.RELEASED
#: Regime names returned by :func:`classify_regime`, in code order.
REGIMES = ("shakedown", "ratcheting", "gross sliding")


def _sqrt_pos(v):
    """sqrt(max(v, 0)): the elliptic profiles vanish outside their support."""
    return np.sqrt(np.clip(v, 0.0, None))


def _ft(ft, *, upper_closed=False):
    return check_range("ft", ft, 0.0, 1.0, hi_closed=upper_closed)


def _w(w, *, upper_closed=False):
    return check_range("w", w, 0.0, 1.0, hi_closed=upper_closed)


# --------------------------------------------------------------------------
# Hertz line contact (eqs 4-5)
# --------------------------------------------------------------------------
def hertz_pressure(x, xc=0.0):
    """Hertz pressure of a line contact centred at ``xc`` (eq 4).

    Parameters
    ----------
    x : array_like
        Position, in units of the half-width ``a``.
    xc : array_like, optional
        Contact centre, in units of ``a``. Default 0.

    Returns
    -------
    ndarray
        ``p / p0 = sqrt(1 - (x - xc)^2)`` inside the contact, 0 outside.

    Examples
    --------
    >>> hertz_pressure([0.0, 0.6, 1.2])
    array([1. , 0.8, 0. ])
    >>> round(float(hertz_pressure(0.6, xc=0.2)), 4)
    0.9165
    """
    x = check_range("x", x)
    xc = check_range("xc", xc)
    return _sqrt_pos(1.0 - (x - xc) ** 2)


def _ellipse_primitive(t):
    """Antiderivative of sqrt(1 - t^2) on [-1, 1], constant outside."""
    t = np.clip(t, -1.0, 1.0)
    return 0.5 * (t * np.sqrt(1.0 - t * t) + np.arcsin(t))


def hertz_pressure_element_mean(edges, xc=0.0, a=1.0, p0=1.0):
    """Mean Hertz pressure over each element between consecutive ``edges``.

    The exact element average (not the midpoint value), so that the element
    loads add up exactly to the normal load ``pi a p0 / 2`` whatever the grid:
    this is what a discretisation with piecewise-constant pressure must use so
    that ``ft < 1`` is always feasible.

    Parameters
    ----------
    edges : array_like, shape (n + 1,)
        Increasing element edges, in units of the nominal half-width.
    xc : float
        Contact centre, same units.
    a : float
        Current half-width, same units (``sqrt(P / P_nominal)`` if the load varies).
    p0 : float
        Current peak pressure, in units of the nominal ``p0``.

    Returns
    -------
    ndarray, shape (n,)
        Mean pressure of each element, in units of the nominal ``p0``.
    """
    edges = check_range("edges", edges)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError("edges must be a strictly increasing 1-D array of at least 2 values")
    a = float(check_range("a", a, 0.0, None, lo_closed=False))
    p0 = float(check_range("p0", p0, 0.0, None))
    xc = float(check_range("xc", xc))
    return element_means(edges, xc, a, p0)[0]


# --------------------------------------------------------------------------
# Cattaneo-Mindlin partial slip (eqs 7-12)
# --------------------------------------------------------------------------
def cattaneo_stick_halfwidth(ft):
    """Stick half-width of the Cattaneo-Mindlin line contact (eq 7).

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1].

    Returns
    -------
    ndarray
        ``c / a = sqrt(1 - ft)``.

    Examples
    --------
    >>> round(float(cattaneo_stick_halfwidth(0.36)), 12)
    0.8
    """
    ft = _ft(ft, upper_closed=True)
    return np.sqrt(1.0 - ft)


def cattaneo_traction(x, ft):
    """Cattaneo-Mindlin traction after monotonic loading to ``ft`` (eqs 8-12).

    Parameters
    ----------
    x : array_like
        Position in units of ``a``.
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1].

    Returns
    -------
    ndarray
        ``q / (mu p0) = sqrt(1 - x^2) - (c/a) sqrt(1 - (x/c)^2)``, the second
        term only inside the stick zone ``|x| < c``.

    Examples
    --------
    >>> cattaneo_traction([0.0, 0.9], 0.36).round(4)
    array([0.2   , 0.4359])
    """
    x = check_range("x", x)
    c = cattaneo_stick_halfwidth(ft)
    x, c = np.broadcast_arrays(x, c)
    inner = np.where(c > 0, c * _sqrt_pos(1.0 - (x / np.where(c > 0, c, 1.0)) ** 2), 0.0)
    return _sqrt_pos(1.0 - x**2) - inner


# --------------------------------------------------------------------------
# Shakedown limit (eq 35) and its inverse
# --------------------------------------------------------------------------
def _segment_area(s):
    """(2/pi) (arccos s - s sqrt(1 - s^2)): the load fraction beyond s."""
    s = np.clip(s, -1.0, 1.0)
    return (2.0 / np.pi) * (np.arccos(s) - s * np.sqrt(1.0 - s * s))


def ft_limit(w):
    """Exact shakedown limit of the tangential load (eq 35).

    As the shaken-down stick zone shrinks to nothing, the whole load is
    carried at ``mu`` times the lowest pressure over the cycle, which gives

    ``ft_lim = (2/pi) (arccos w - w sqrt(1 - w^2))``.

    Parameters
    ----------
    w : array_like
        ``W / a`` in [0, 1].

    The cylinder's; any body's, by name or object: :func:`core.ft_limit`
    (:func:`core.bounds.limits.ft_limit`).

    Returns
    -------
    ndarray
        ``ft_lim`` in [0, 1], decreasing in ``w``.

    Examples
    --------
    >>> round(float(ft_limit(0.26)), 4)
    0.6727
    """
    w = _w(w, upper_closed=True)
    return _segment_area(w)


def w_limit(ft):
    """Exact inverse of :func:`ft_limit`: the largest amplitude that shakes down.

    Solved numerically (elementwise Chandrupatla root finding, to about
    1e-13); the paper's regression eq 36 is in :mod:`core.theory.approximations`.

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1].

    The cylinder's; any body's: :func:`core.w_limit` (:func:`core.bounds.limits.w_limit`).

    Returns
    -------
    ndarray
        ``w_lim`` in [0, 1] with ``ft_limit(w_lim) == ft``.

    Examples
    --------
    >>> round(float(w_limit(0.3)), 4)
    0.5851
    >>> w_limit([0.1, 0.5]).round(4)
    array([0.8054, 0.404 ])
    >>> round(float(ft_limit(w_limit(0.3))), 12)
    0.3
    """
    ft = _ft(ft, upper_closed=True)
    shape = ft.shape
    flat = ft.ravel()
    lo = np.zeros_like(flat)
    hi = np.ones_like(flat)
    res = elementwise.find_root(
        lambda w, f: _segment_area(w) - f, (lo, hi), args=(flat,),
        tolerances=dict(xatol=1e-14, xrtol=0.0, fatol=0.0, frtol=0.0),
    )
    out = np.where(flat >= 1.0, 0.0, np.where(flat <= 0.0, 1.0, res.x))
    return out.reshape(shape)[()]


# --------------------------------------------------------------------------
# The shaken-down state (eqs 22-30)
# --------------------------------------------------------------------------
def lowest_pressure(x, w):
    """Lowest Hertz pressure a point sees while the centre rocks over [-W, W].

    Parameters
    ----------
    x : array_like
        Position in units of ``a``.
    w : array_like
        ``W / a`` in [0, 1].

    Returns
    -------
    ndarray
        ``sqrt(1 - (|x| + w)^2)`` for ``|x| < 1 - w``, else 0 (eq 21).

    Examples
    --------
    >>> lowest_pressure([0.0, 0.5, 0.8], 0.3).round(4)
    array([0.9539, 0.6   , 0.    ])
    """
    x = check_range("x", x)
    w = _w(w, upper_closed=True)
    return _sqrt_pos(1.0 - (np.abs(x) + w) ** 2)


def _tau21(c, w):
    """Stick-zone amplitude tau21 / (mu p0) from continuity at c (eq 26)."""
    b = 1.0 - w
    r = np.clip(c / b, 0.0, 1.0)
    num = 1.0 - (c + w) ** 2
    den = 1.0 - r * r
    # c -> b: both vanish like 2 eps and 2 eps / b, the ratio tends to b
    safe = den > 1e-300
    return np.where(safe, np.sqrt(np.clip(num, 0.0, None) / np.where(safe, den, 1.0)), np.sqrt(b))


def shakedown_closure(c, w):
    """Load fraction carried by the shaken-down state of stick half-width ``c`` (eq 30).

    ``ft(c, w) = (2/pi) [arccos s0 - s0 sqrt(1 - s0^2)]
    + (2/pi) tau21 b [arcsin(c/b) + (c/b) sqrt(1 - (c/b)^2) - (pi/2) (c/b)^2]``
    with ``s0 = c + w``, ``b = 1 - w`` (all lengths in ``a``).

    Parameters
    ----------
    c : array_like
        Stick half-width in units of ``a``, ``0 <= c <= 1 - w``.
    w : array_like
        ``W / a`` in [0, 1).

    Returns
    -------
    ndarray
        The ``ft`` that the state with stick half-width ``c`` balances. It falls
        from ``ft_limit(w)`` at ``c = 0`` to 0 at ``c = 1 - w``; at ``w = 0`` it
        is Cattaneo's ``1 - c^2``.
    """
    c = check_range("c", c, 0.0, 1.0)
    w = _w(w)
    return _closure(c, w)


def _closure(c, w):
    b = 1.0 - w
    r = np.clip(c / b, 0.0, 1.0)
    stick = (2.0 / np.pi) * _tau21(c, w) * b * (np.arcsin(r) + r * np.sqrt(1.0 - r * r) - 0.5 * np.pi * r * r)
    return _segment_area(c + w) + stick


def shakedown_stick_halfwidth(ft, w):
    """Stick half-width after shakedown, ``c_sd / a``, from the closure eq 30.

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1).
    w : array_like
        ``W / a`` in [0, 1).

    Returns
    -------
    ndarray
        ``c_sd / a`` in [0, 1 - w]; NaN where no shakedown state exists
        (``ft > ft_limit(w)``). ``w = 0`` gives Cattaneo's ``sqrt(1 - ft)``.

    Notes
    -----
    ``ft(c)`` of eq 30 is monotonic in ``c`` on ``[0, 1 - w]``; the root is
    bracketed there and found elementwise with Chandrupatla's method to about
    1e-13.

    Examples
    --------
    >>> import core
    >>> float(core.shakedown_stick_halfwidth(0.36, 0.0))
    0.8
    """
    ft = _ft(ft)
    w = _w(w)
    ft, w = np.broadcast_arrays(ft, w)
    shape = ft.shape
    f, ww = ft.ravel(), w.ravel()
    inside = f <= _segment_area(ww)
    out = np.full(f.shape, np.nan)
    if inside.any():
        fi, wi = f[inside], ww[inside]
        res = elementwise.find_root(
            lambda c, f_, w_: _closure(c, w_) - f_,
            (np.zeros_like(wi), 1.0 - wi), args=(fi, wi),
            tolerances=dict(xatol=1e-13, xrtol=0.0, fatol=0.0, frtol=0.0),
        )
        out[inside] = np.clip(res.x, 0.0, 1.0 - wi)
    return out.reshape(shape)[()]


def _traction_and_zones(x, c, w):
    b = 1.0 - w
    ax = np.abs(x)
    tau1 = _sqrt_pos(1.0 - (ax + w) ** 2)
    t21 = _tau21(c, w)
    cs = np.where(c > 0, c, 1.0)
    tau2 = t21 * (_sqrt_pos(1.0 - (x / b) ** 2) - (c / b) * _sqrt_pos(1.0 - (x / cs) ** 2))
    stick = ax < c
    slip = (~stick) & (ax < b)
    released = (ax >= b) & (ax < 1.0)
    q = np.where(stick, tau2, np.where(slip, tau1, 0.0))
    zones = np.where(stick, ZONE_STICK, np.where(slip, ZONE_SLIP, np.where(released, ZONE_RELEASED, ZONE_NONE)))
    nan = np.isnan(c)
    return np.where(nan, np.nan, q), np.where(nan, ZONE_NONE, zones)


def shakedown_traction(x, ft, w):
    """Traction after shakedown, from the paper's ansatz (eqs 22-26).

    Three zones (``b = 1 - w``, ``c = c_sd``):

    * stick ``|x| < c``: ``tau21 sqrt(1 - (x/b)^2) - tau22 sqrt(1 - (x/c)^2)``,
      ``tau22 = tau21 c / b``;
    * slip ``c <= |x| < b``: ``sqrt(1 - (|x| + w)^2)`` (mu times the lowest
      pressure of the cycle, eq 22);
    * zero traction ``b <= |x| < 1`` (released once a period).

    Parameters
    ----------
    x : array_like
        Position in units of ``a`` (centre of the rocking at 0).
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1).
    w : array_like
        ``W / a`` in [0, 1).

    Returns
    -------
    ndarray
        ``q / (mu p0)``; NaN where no shakedown state exists.

    Notes
    -----
    The stick-zone form is the paper's proposal, not a proven solution. It
    integrates to ``ft`` by construction (eq 30) and is continuous at ``c``.
    Whether it respects ``|q| <= mu p_min`` everywhere is tested in
    ``tests/test_analytical.py``; compare it with the numerical solver's state
    in the app.

    Examples
    --------
    At the centre the stick-zone ansatz; in the slip zone the bound ``mu p_min``:

    >>> shakedown_traction([0.0, 0.6], 0.3, 0.3).round(4)
    array([0.2522, 0.4359])
    """
    x = check_range("x", x)
    c = shakedown_stick_halfwidth(ft, w)
    w = _w(w)
    x, c, w = np.broadcast_arrays(x, c, w)
    return _traction_and_zones(x, c, w)[0]


def shakedown_zones(x, ft, w):
    """Zone of each point after shakedown.

    Returns
    -------
    ndarray of int
        :data:`ZONE_STICK` (``|x| < c_sd``), :data:`ZONE_SLIP`
        (``c_sd <= |x| < 1 - w``), :data:`ZONE_RELEASED` (``1 - w <= |x| < 1``)
        or :data:`ZONE_NONE` (outside the contact, or no shakedown state).

    Examples
    --------
    >>> shakedown_zones([0.0, 0.6, 0.9], 0.3, 0.3)
    array([1, 2, 3])
    >>> [int(z) for z in (ZONE_STICK, ZONE_SLIP, ZONE_RELEASED)]
    [1, 2, 3]
    """
    x = check_range("x", x)
    c = shakedown_stick_halfwidth(ft, w)
    w = _w(w)
    x, c, w = np.broadcast_arrays(x, c, w)
    return _traction_and_zones(x, c, w)[1]


# --------------------------------------------------------------------------
# Regimes
# --------------------------------------------------------------------------
def classify_regime(ft, w):
    """Regime predicted by the exact limit: shakedown, ratcheting or gross sliding.

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)``, ``>= 0``. ``ft >= 1`` is gross sliding.
    w : array_like
        ``W / a`` in [0, 1).

    Returns
    -------
    ndarray of str
        ``"shakedown"`` where ``ft <= ft_limit(w)``, ``"ratcheting"`` where
        ``ft_limit(w) < ft < 1``, ``"gross sliding"`` where ``ft >= 1``.
    """
    ft = check_range("ft", ft, 0.0, None)
    w = _w(w)
    ft, w = np.broadcast_arrays(ft, w)
    code = np.where(ft >= 1.0, 2, np.where(ft <= _segment_area(w), 0, 1))
    names = np.asarray(REGIMES)[code]
    return str(names) if np.ndim(names) == 0 else names


def fretting_energy_line(amplitude):
    """Energy dissipated per cycle by a cylinder (plane strain, per unit length) under a constant normal load and an
    oscillating tangential one: ``E = (2/pi) [1 - (1 - A)^2 + 2 (1 - A) ln(1 - A)]`` [mu^2 P^2/E*].

    Any body's by name: :func:`core.fretting_energy` (the derivation there).

    Examples
    --------
    >>> round(float(fretting_energy_line(0.5)), 6)
    0.036194
    """
    A = check_range("amplitude", amplitude, 0.0, 1.0, hi_closed=False)
    s = 1.0 - A  # > 0: A < 1
    out = (2.0 / np.pi) * (1.0 - s * s + 2.0 * s * np.log(s))
    return out[()] if isinstance(out, np.ndarray) else out


def fretting_energy_sphere(amplitude, nu=0.5):
    """Energy dissipated per cycle by a rigid sphere on a half-space of Poisson ratio ``nu`` under a constant normal
    load and an oscillating tangential one (Mindlin and Deresiewicz, the transverse traction neglected):
    ``E = 9 (2 - nu)/(5 (1 - nu)) [1 - (1 - A)^(5/3) - (5A/6) (1 + (1 - A)^(2/3))]`` [mu^2 Fn^2/(E* a)].

    Any body's by name: :func:`core.fretting_energy` (the derivation there).

    Examples
    --------
    >>> round(float(fretting_energy_sphere(0.35)), 7)
    0.0093676
    """
    A = check_range("amplitude", amplitude, 0.0, 1.0, hi_closed=False)
    nu = check_range("nu", nu, 0.0, 0.5)
    s = 1.0 - A
    out = 9.0 * (2.0 - nu) / (5.0 * (1.0 - nu)) * (1.0 - s ** (5.0 / 3.0) - (5.0 * A / 6.0) * (1.0 + s ** (2.0 / 3.0)))
    return out[()] if isinstance(out, np.ndarray) else out
