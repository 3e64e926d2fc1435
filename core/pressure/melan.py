"""The exact shakedown limit of any uncoupled body: Melan's theorem with the bound ``mu p_min``.

For an uncoupled frictional contact (Dundurs beta = 0: the pressure does not
depend on the tangential tractions) Melan's theorem holds (Klarbring,
Ciavarella and Barber 2007): the contact shakes down if and only if a
residual traction field exists that never exceeds the friction bound, i.e.
``|q(x)| <= mu p_min(x)`` with ``p_min(x)`` the LOWEST pressure the point ``x``
sees over the whole cycle, and carries the load. With a constant ``Ft`` the
condition is

``ft = Ft / (mu P) <= ft_lim = (1/P) integral p_min dx``

(in the normalised units ``integral p dx = P``). ``p_min`` is the minimum
over every centre position of the cycle, not only the turning points: a
rounded punch's pressure has two peaks and a dip between them, so a point can
see its lowest pressure while the centre passes. For a body that translates
by ``xc`` in ``[-w, w]``, ``p_min(x) = min over |s| <= w of p(x - s)``.

Closed forms where known: the cylinder (:func:`core.theory.analytical.ft_limit`,
eq 35) and the sphere and every ellipsoid rocked along a principal axis
(``(1 - w)^2 (2 + w)/2``, :func:`core.theory.point_contact.ft_limit_point`); any
other body numerically (:func:`ft_limit_numerical`).

References
----------
.. [1] A. Klarbring, M. Ciavarella, J. R. Barber, "Shakedown in elastic
   contact problems with Coulomb friction", Int. J. Solids Struct. 44 (2007) 8355.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import minimum_filter1d
from scipy.optimize import brentq

from ..base._validate import check_scalar

__all__ = ["ft_limit", "w_limit", "ft_limit_numerical", "ft_limit_oscillating", "lowest_pressure", "grid_limit",
           "MELAN_DX"]

#: Default sampling step [a] of the numerical limit: the pressure's points for a closed form, the normal
#: solve's elements otherwise (the limit converges about as dx^1.5: 1e-5 at 1/4000, ``tests/test_melan.py``).
MELAN_DX = {"exact": 1.0 / 4000.0, "numerical": 1.0 / 400.0}


def _step(w, dx):
    """A step ``<= dx`` that divides ``w`` (so the window of centres is whole)."""
    return dx if w <= 0 else w / math.ceil(w / dx - 1e-12)


def lowest_pressure(body, w, dx=None, normal="auto"):
    """``p_min`` [p0] of a translating line body over centres in ``[-w, w]``, on a grid of step ``dx``.

    Parameters
    ----------
    body : core.geometry.bodies.Body
        A line-contact body.
    w : float
        Amplitude ``W / a`` in [0, 1).
    dx : float, optional
        Sampling step [a] (default :data:`MELAN_DX`; adjusted down so that it divides ``w``).
    normal : {"auto", "exact", "numerical"}
        The closed-form pressure sampled at points ``k dx``, or the numerical
        normal solve's element pressures (:meth:`core.geometry.bodies.Body.solve_normal`).

    Returns
    -------
    x, p, p_min : ndarray
        The sample positions [a], the pressure at ``xc = 0`` and the lowest pressure over the cycle.
    """
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    mode = body.normal_mode(normal)
    dx = _step(w, check_scalar("dx", MELAN_DX[mode] if dx is None else dx, 1e-5, 0.1))
    if mode == "exact":
        a = float(body.half_width(1.0))
        half = math.ceil((a + w) / dx) + 1
        x = dx * np.arange(-half, half + 1)
        p = body.pressure(x, 0.0, 1.0)
    else:
        edges, sol = body.solve_normal(dx, 1.0)
        pad = math.ceil(w / dx) + 1
        p = np.concatenate((np.zeros(pad), sol.pressure, np.zeros(pad)))
        x = 0.5 * (edges[1:] + edges[:-1])
        x = np.concatenate((x[0] - dx * np.arange(pad, 0, -1), x, x[-1] + dx * np.arange(1, pad + 1)))
    k = int(round(w / dx))
    p_min = minimum_filter1d(p, 2 * k + 1, mode="constant", cval=0.0) if k > 0 else p.copy()
    return x, p, p_min


def ft_limit_numerical(w, body, dx=None, normal="auto"):
    """``ft_lim = integral p_min / integral p`` of a line body (:func:`lowest_pressure`), or of a point body.

    Point bodies (objects with ``pressure(x, y, xc)`` and ``dim == 2``, e.g.
    :class:`core.theory.point_contact.Ellipsoid`) use their closed-form pressure on a
    square grid of step ``dx`` (default 1/400) and the minimum along x.

    Examples
    --------
    >>> import core
    >>> from core.pressure.melan import ft_limit_numerical
    >>> round(float(ft_limit_numerical(0.26, core.Cylinder())), 4)
    0.6727
    """
    if getattr(body, "dim", 1) == 2 and hasattr(body, "grid_pressure"):  # a height map: its own grid and solve
        return body.ft_limit(w)
    if getattr(body, "dim", 1) == 2:
        w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
        dx = _step(w, check_scalar("dx", 1.0 / 400.0 if dx is None else dx, 1e-4, 0.1))
        kappa = float(getattr(body, "kappa", 1.0))
        half = math.ceil((1 + w) / dx) + 1
        x = dx * np.arange(-half, half + 1)
        y = dx * np.arange(-math.ceil(kappa / dx) - 1, math.ceil(kappa / dx) + 2)
        p = body.pressure(x[None, :], y[:, None], 0.0)
        k = int(round(w / dx))
        p_min = minimum_filter1d(p, 2 * k + 1, axis=1, mode="constant", cval=0.0) if k > 0 else p
        return float(p_min.sum() / p.sum())
    _, p, p_min = lowest_pressure(body, w, dx, normal)
    return float(p_min.sum() / p.sum())


def grid_limit(lowest, now, load=1.0):
    """Melan's limit of a discrete problem with no moment to balance: ``load * sum(p_min) / sum(p)`` [the unit of Q].

    The run shakes down if and only if a fixed traction within ``mu p_min``
    (``lowest``: each element's lowest pressure over the period) carries the
    tangential load; with tractions along the load that is the sum of ``mu
    p_min dA``, over the total ``sum(mu p dA)`` of the pressure ``now`` that
    carries the normal load ``load``. Any grid (a line or a patch of equal
    elements).

    Returns
    -------
    float or None
        None where ``now`` carries no load.

    Examples
    --------
    >>> grid_limit([0.0, 0.5, 0.5, 0.0], [0.5, 1.0, 1.0, 0.5])
    0.3333333333333333
    """
    total = float(np.sum(now))
    if total <= 0:
        return None
    return float(np.sum(lowest)) / total * float(load)


def _checked(body, name) -> bool:
    """Whether ``body`` has a closed-form limit; a ValueError naming it if it gives Melan's integral nothing to
    integrate (no closed form, no pressure)."""
    if isinstance(body, str):
        raise ValueError(f"body must be a body object here (core.{name} takes names), got {body!r:.60}")
    if getattr(body, "closed_limit", False):
        return True
    if not (hasattr(body, "normal_mode") or hasattr(body, "grid_pressure") or hasattr(body, "pressure")):
        raise ValueError(f"body {body!r:.60} has no limit: neither a closed form (closed_limit) nor a pressure")
    return False


def ft_limit(w, body, *, normal="auto", dx=None):
    """The exact shakedown limit ``ft_lim(w)`` of a body object: its closed form where it has one, Melan's integral
    otherwise (:func:`ft_limit_numerical`). By name: :func:`core.ft_limit` (:func:`core.bounds.limits.ft_limit`).

    Parameters
    ----------
    w : array_like
        ``W / a`` in [0, 1] (numerical bodies: [0, 1)).
    body : core.geometry.bodies.Body, core.Ellipsoid or another body object
        A body with ``closed_limit`` (the cylinder's eq 35, every ellipsoid's ``(1 - w)^2 (2 + w)/2``) gives its
        own :meth:`ft_limit`; any other is integrated.
    normal, dx :
        For the numerical bodies (see :func:`lowest_pressure`).

    Examples
    --------
    >>> import core
    >>> from core.pressure.melan import ft_limit
    >>> round(float(ft_limit(0.3, core.Punch(flat=0.5))), 4)
    0.5527
    """
    if _checked(body, "ft_limit"):
        return body.ft_limit(w)
    return _each(lambda v: ft_limit_numerical(v, body, dx, normal), w)


def w_limit(ft, body, *, normal="auto", dx=None):
    """The inverse of :func:`ft_limit`: the largest amplitude that shakes down at ``ft`` (root of ft_lim(w) = ft).

    Examples
    --------
    >>> import core
    >>> from core.pressure.melan import w_limit
    >>> round(float(w_limit(0.5527, core.Punch(flat=0.5))), 3)
    0.3
    """
    if _checked(body, "w_limit"):
        return body.w_limit(ft)

    def one(f):
        f = check_scalar("ft", f, 0.0, 1.0)
        if f >= 1.0:
            return 0.0
        if f <= 0.0:
            return 1.0
        top = 1.0 - 1e-6
        if ft_limit_numerical(top, body, dx, normal) >= f:
            return top
        return brentq(lambda v: ft_limit_numerical(v, body, dx, normal) - f, 0.0, top, xtol=1e-7)

    return _each(one, ft)


def ft_limit_oscillating(w, body, amplitude, phase=0.0, *, shape="triangle", dx=None, samples=400):
    """Melan's limit of a body rocked while its normal force oscillates (the history ``"normal"``).

    The rocking of :func:`core.loading.histories.rocking` with ``P = 1 + A sin(2 pi t + phase)``: the bound of a
    shaken-down traction is ``mu p_min(x)``, the lowest pressure over the centres and the loads of the period, so

    ``ft_lim = integral p_min dA / integral p(P = 1) dA``

    in units of the mean normal force (``ft = Ft / (mu Fn_mean)``). It is at most ``1 - A`` (gross sliding
    at the lowest load) and, for ``A = 0``, the body's own limit (:func:`ft_limit`).

    Parameters
    ----------
    w : array_like
        ``W / a`` in [0, 1), ``a`` the half-width (a point contact: the semi-axis along x) under the mean load.
    body : object
        A line body with a closed-form ``pressure(x, xc, P)`` (:class:`core.Cylinder`, :class:`core.Punch`) or an
        ellipsoid (:class:`core.Ellipsoid`: Hertz's pressure scaled by ``P^(1/3)``).
    amplitude : float
        ``A``, the normal force's relative amplitude, in [0, 1).
    phase : float
        Its phase [rad] to the rocking (``t = 1/4`` where the centre reaches ``+W``), finite.
    shape : {"triangle", "sine"}
        The centre's waveform.
    dx : float, optional
        Sampling step [a] along x (and y), default 1/1000 for a line, 1/100 for an ellipsoid.
    samples : int
        Steps of the period the minimum is taken over, in [8, 20000].

    Returns
    -------
    ndarray
        ``ft_lim``, of the shape of ``w``.

    Raises
    ------
    ValueError
        For an input out of its range, or a body with neither pressure.

    Examples
    --------
    >>> import core
    >>> from core.pressure.melan import ft_limit_oscillating
    >>> round(float(ft_limit_oscillating(0.26, core.Cylinder(), 0.0)), 3)
    0.673
    >>> round(float(ft_limit_oscillating(0.26, core.Cylinder(), 0.2)), 3)  # the engine's run: 0.6486
    0.649
    """
    from ..loading.schedule import SHAPES  # (histories layer, below this one)

    A = check_scalar("amplitude", amplitude, 0.0, 1.0, hi_closed=False)
    phi = check_scalar("phase", phase)
    if shape not in SHAPES:
        raise ValueError(f"shape must be one of {sorted(SHAPES)}, got {shape!r:.40}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 8 <= samples <= 20000:
        raise ValueError(f"samples must be an integer in [8, 20000], got {samples!r:.40}")
    point = getattr(body, "dim", 1) == 2
    if point and not hasattr(body, "kappa") or not point and not hasattr(body, "half_width"):
        raise ValueError(f"body {body!r:.60} has no closed-form pressure to take the lowest of "
                         "(a line body or an ellipsoid)")
    t = np.arange(samples) / samples
    P = 1.0 + A * np.sin(2.0 * np.pi * t + phi)

    def one(v):
        v = check_scalar("w", v, 0.0, 1.0, hi_closed=False)
        s = np.sin(2.0 * np.pi * t) if shape == "sine" else 4.0 * np.abs(((t - 0.25) % 1.0) - 0.5) - 1.0
        xc = v * s  # both reach +W at t = 1/4
        if point:
            h = check_scalar("dx", 1.0 / 100.0 if dx is None else dx, 1e-4, 0.1)
            scale = P ** (1.0 / 3.0)
            kappa = float(body.kappa) * float(scale.max())
            x = np.arange(-(1.0 + v) * scale.max() - h, (1.0 + v) * scale.max() + h, h)
            y = np.arange(-kappa - h, kappa + h, h)
            X, Y = np.meshgrid(x, y)
            p_min = np.full(X.shape, np.inf)
            for c, k in zip(xc, scale):
                np.minimum(p_min, k * body.pressure(X / k, Y / k, c / k), out=p_min)
            return float(p_min.sum() / body.pressure(X, Y, 0.0).sum())
        h = check_scalar("dx", 1.0 / 1000.0 if dx is None else dx, 1e-5, 0.1)
        reach = float(body.half_width(float(P.max()))) + v + h
        x = np.arange(-reach, reach + h, h)
        p_min = np.full(x.shape, np.inf)
        for c, load in zip(xc, P):
            np.minimum(p_min, body.pressure(x, float(c), float(load)), out=p_min)
        return float(p_min.sum() / body.pressure(x, 0.0, 1.0).sum())

    return _each(one, w)


def _each(fn, x):
    """``fn`` of every value of ``x`` (a float each): a NumPy scalar for a scalar, else an array of its shape."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 0:
        return np.float64(fn(float(x)))
    return np.vectorize(lambda v: fn(float(v)), otypes=[float])(x)
