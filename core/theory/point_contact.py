"""Point contacts: the rocking sphere and ellipsoid (Hertz pressure, shakedown limit, physical units).

A rigid sphere or ellipsoid (principal relative radii ``Rx``, ``Ry``; the
sphere is ``Rx = Ry``) is pressed by ``Fn`` onto an elastic half-space, pulled
by a constant tangential force ``Ft`` (along x, or at an angle to it) and
rocked so that its contact centre moves along x between ``-W`` and ``+W``.
Uncoupled (Dundurs beta = 0): the pressure is Hertz's at the current centre.

Normalised units: lengths in ``a``, the contact's semi-axis along x (the
other is ``b = kappa a``); pressure in ``p0``; tractions in ``mu p0``;
displacements in ``mu Fn / (E* a)``; ``ft = Ft/(mu Fn)``, ``w = W/a``.

The exact shakedown limit follows from the bound ``|q| <= mu p_min`` that a
shaken-down state must respect at every point, ``p_min`` the lowest pressure
over the period, i.e. the pressure of the farther turning point,
``p_min = p0 sqrt(1 - (|x| + w)^2 - (y/kappa)^2)``. Shakedown is possible iff
``Ft <= integral of mu p_min`` (Melan's theorem holds for uncoupled frictional
systems). With ``u = |x| + w`` the y-integral of the ellipsoidal cap is
``kappa (pi/2)(1 - u^2)``, so

``ft_lim = [2 integral_w^1 kappa (pi/2) (1 - u^2) du] / (2 pi kappa/3) = (1 - w)^2 (2 + w)/2``

for the sphere and every ellipsoid rocked along a principal axis, whatever
the direction of ``Ft`` (the disk bound is isotropic). Its inverse is the
root in [0, 1] of the cubic ``w^3 - 3 w + 2 (1 - ft) = 0``,
``w_lim = 2 cos(arccos(ft - 1)/3 - 2 pi/3)``.

References
----------
.. [1] K. L. Johnson, *Contact Mechanics*, CUP 1985, ch. 4 (Hertz elliptical
   contact, eqs 4.36-4.41) and ch. 7 (Mindlin).
.. [2] R. Wetter, V. L. Popov, Int. J. Solids Struct. 51 (2014) 930-935 (the
   rocking sphere); R. Wetter, Physical Mesomechanics 18 (2015), Fig. 14.
.. [3] A. Klarbring, M. Ciavarella, J. R. Barber, "Shakedown in elastic
   contact problems with Coulomb friction", Int. J. Solids Struct. 44 (2007) 8355.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from ..base._validate import check_range, check_scalar
from .analytical import _ellipse_primitive, fretting_energy_sphere

__all__ = ["Ellipsoid", "Sphere", "POINT_BODIES", "gap_curvatures", "axis_ratio", "ft_limit_point",
           "w_limit_point", "hertz_pressure_3d", "hertz_element_means", "lowest_pressure_3d"]

#: Body names of the point contacts.
POINT_BODIES = ("sphere", "ellipsoid")
#: Gauss points per element row of the pressure quadrature (the x-integral is exact).
_GAUSS_POINTS = 12


@dataclass(frozen=True)
class Ellipsoid:
    """A point-contact body given by the ratio ``Ry/Rx`` of its principal relative radii.

    Parameters
    ----------
    ratio : float
        ``Ry / Rx`` in [0.05, 20] (1: the sphere). ``Rx`` is the radius in the
        rocking direction x.

    Examples
    --------
    >>> from core.theory.point_contact import Ellipsoid
    >>> round(Ellipsoid(1.0).kappa, 12), round(Ellipsoid(4.0).kappa, 3)
    (1.0, 2.501)
    """

    ratio: float = 1.0
    #: A point contact: a patch of elements (the 3D solver, :mod:`core.solvers.solver3d`).
    dim = 2

    def __post_init__(self):
        object.__setattr__(self, "ratio", check_scalar("ratio", self.ratio, 0.05, 20.0))

    @property
    def name(self) -> str:
        return "sphere" if self.ratio == 1.0 else "ellipsoid"

    @property
    def parameters(self) -> dict:
        """The body's parameters by name: ``{"ratio": Ry/Rx}``."""
        return {"ratio": self.ratio}

    #: Its limit is in closed form (every ellipsoid rocked along a principal axis): :meth:`ft_limit`.
    closed_limit = True

    @staticmethod
    def ft_limit(w):
        """The exact limit ``(1 - w)^2 (2 + w)/2`` (:func:`ft_limit_point`; the same for every ratio)."""
        return ft_limit_point(w)

    @staticmethod
    def w_limit(ft):
        """Its inverse (:func:`w_limit_point`)."""
        return w_limit_point(ft)

    def fretting_energy(self, amplitude, nu=0.5):
        """The sphere's energy dissipated per cycle of an oscillating tangential load (Mindlin and Deresiewicz,
        :func:`core.theory.analytical.fretting_energy_sphere`); an ellipsoid has no closed form here.

        Raises
        ------
        ValueError
            For an ellipsoid (``ratio != 1``).
        """
        if self.ratio != 1.0:
            raise ValueError(f"body {self!r} (an ellipsoid) has no closed-form fretting loop: only the sphere has")
        return fretting_energy_sphere(amplitude, nu)

    def pressure(self, x, y, xc=0.0):
        """Hertz's pressure [p0] at ``(x, y)`` [a] with the centre at ``(xc, 0)`` (:func:`hertz_pressure_3d`)."""
        return hertz_pressure_3d(x, y, xc, self.kappa)

    @cached_property
    def kappa(self) -> float:
        """``b / a``: the contact's semi-axis along y over that along x (Hertz, Johnson ch. 4)."""
        return axis_ratio(self.ratio)

    @property
    def total_load(self) -> float:
        """Integral of the Hertz pressure in ``p0 a^2``: ``2 pi kappa / 3`` (i.e. ``Fn``)."""
        return 2.0 * math.pi * self.kappa / 3.0

    @property
    def kernel_scale(self) -> float:
        """``p0 a^2 / (pi Fn) = 3 / (2 pi^2 kappa)``: the factor of the half-space kernel in these units."""
        return 1.5 / (math.pi ** 2 * self.kappa)

    def profile(self, x, y):
        """The gap ``A x^2 + B y^2`` [Fn/(E* a)] whose Hertz solution is this body's contact (Johnson ch. 3:
        the displacement under ``p0 sqrt(1 - x^2 - (y/kappa)^2)``; :func:`gap_curvatures`); the sphere's is
        ``(3/8) r^2``."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        A, B = gap_curvatures(self.kappa)
        return (A * x * x + B * y * y) / self.total_load


def gap_curvatures(kappa):
    """``(A, B)`` of the gap ``A x^2 + B y^2`` whose Hertz contact has semi-axes 1 (x) and ``kappa`` (y).

    Units: lengths in ``a``, pressure in ``p0``, ``E* = 1`` (the kernel
    ``1/(pi E*)`` of the half-space). Johnson eqs 3.57-3.61: with the
    semi-axes ``a' >= b'``, ``e^2 = 1 - (b'/a')^2``, ``A' = (b'/a'^2)(K - E)/e^2``
    along ``a'`` and ``B' = (b'/a'^2)((a'/b')^2 E - K)/e^2``; ``pi/4`` each for
    the sphere.
    """
    if abs(kappa - 1.0) < 1e-9:
        return 0.25 * math.pi, 0.25 * math.pi
    major, minor = max(1.0, kappa), min(1.0, kappa)
    e2 = 1.0 - (minor / major) ** 2
    K, E = float(ellipk(e2)), float(ellipe(e2))
    along = minor / major**2 * (K - E) / e2
    across = minor / major**2 * ((major / minor) ** 2 * E - K) / e2
    return (along, across) if kappa < 1.0 else (across, along)


def Sphere() -> Ellipsoid:
    """The sphere: ``Ellipsoid(1.0)``."""
    return Ellipsoid(1.0)


def _curvature_ratio(m):
    """``C_minor / C_major`` of the Hertz ellipse with semi-axis ratio ``m = major/minor >= 1`` (Johnson eq 4.39)."""
    e2 = 1.0 - 1.0 / (m * m)
    K, E = ellipk(e2), ellipe(e2)
    return (m * m * E - K) / (K - E)


def _k_minus_e_over_e2(e2):
    """``(K(e) - E(e)) / e^2``, with its series near ``e = 0``."""
    if e2 < 1e-6:
        return 0.25 * math.pi * (1.0 + 0.375 * e2)
    return float((ellipk(e2) - ellipe(e2)) / e2)


def axis_ratio(ratio):
    """Semi-axis ratio ``kappa = b/a`` of the Hertz contact of relative radii with ``Ry/Rx = ratio``.

    The ellipse's minor axis lies along the more curved direction, and
    ``C_minor/C_major = (m^2 E(e) - K(e))/(K(e) - E(e))`` with ``m`` the
    major/minor ratio and ``e^2 = 1 - 1/m^2`` (Johnson eq 4.39).

    Parameters
    ----------
    ratio : float
        ``Ry / Rx`` in [0.05, 20].

    Returns
    -------
    float
        ``kappa = b / a`` (> 1 when ``Ry > Rx``).
    """
    ratio = check_scalar("ratio", ratio, 0.05, 20.0)
    if abs(ratio - 1.0) < 1e-12:
        return 1.0
    target = max(ratio, 1.0 / ratio)
    m = brentq(lambda m: _curvature_ratio(m) - target, 1.0 + 1e-7, 1e3, xtol=1e-15, rtol=1e-15)
    return m if ratio > 1.0 else 1.0 / m


# --------------------------------------------------------------------------
# Hertz pressure
# --------------------------------------------------------------------------
def hertz_pressure_3d(x, y, xc=0.0, kappa=1.0):
    """Hertz pressure ``p/p0 = sqrt(1 - (x - xc)^2 - (y/kappa)^2)`` (0 outside the ellipse); lengths in ``a``."""
    x, y = check_range("x", x), check_range("y", y)
    return np.sqrt(np.clip(1.0 - (x - xc) ** 2 - (y / kappa) ** 2, 0.0, None))


def hertz_element_means(x_edges, y_edges, xc=0.0, kappa=1.0, scale=1.0):
    """Element means of the Hertz pressure over the rectangles of a grid [p0 of the nominal load].

    The x-integral of each element is exact; the y-integral uses
    Gauss-Legendre points per row, and the field is rescaled so the element
    loads add up exactly to the normal load ``(2 pi/3) kappa scale^3`` (so that
    any ``ft < 1`` stays feasible). ``scale`` is the contact size relative to
    the nominal one (``(Fn/Fn0)^(1/3)``; semi-axes and peak pressure scale
    with it).

    Parameters
    ----------
    x_edges, y_edges : ndarray
        Increasing edges of the uniform grid [a].
    xc : float
        Contact centre on the x axis [a].
    kappa : float
        ``b / a``.
    scale : float
        Load scale ``(Fn/Fn0)^(1/3)``.

    Returns
    -------
    ndarray, shape (ny, nx)
        Mean pressure per element [p0].
    """
    gx, gw = np.polynomial.legendre.leggauss(_GAUSS_POINTS)
    y0, y1 = y_edges[:-1, None], y_edges[1:, None]
    ys = 0.5 * (y0 + y1) + 0.5 * (y1 - y0) * gx[None, :]  # (ny, g)
    c2 = np.clip(1.0 - (ys / (kappa * scale)) ** 2, 0.0, None)[:, :, None]  # (ny, g, 1)
    c = np.sqrt(c2)
    safe = np.where(c > 0, c, 1.0)
    t = (x_edges[None, None, :] - xc) / scale / safe
    F = _ellipse_primitive(t)
    inner = scale * scale * c2 * np.diff(F, axis=-1)  # integral over x of p(x, y) (peak = scale)
    loads = np.einsum("rgi,g->ri", inner, 0.5 * gw) * (y1 - y0)  # element loads
    total = 2.0 * math.pi / 3.0 * kappa * scale ** 3
    s = loads.sum()
    if s > 0:
        loads *= total / s
    area = np.diff(y_edges)[:, None] * np.diff(x_edges)[None, :]
    return np.clip(loads / area, 0.0, None)


def lowest_pressure_3d(x_edges, y_edges, w, kappa=1.0):
    """``p_min``: the lowest element-mean pressure over a rocking period ``xc in [-w, w]`` [p0].

    The element mean of the concave Hertz cap is quasi-concave in ``xc``, so
    the minimum over the period is at a turning point.
    """
    return np.minimum(hertz_element_means(x_edges, y_edges, -w, kappa), hertz_element_means(x_edges, y_edges, w, kappa))


# --------------------------------------------------------------------------
# exact shakedown limit and its inverse
# --------------------------------------------------------------------------
def ft_limit_point(w):
    """Exact shakedown limit of a rocking sphere or ellipsoid: ``ft_lim = (1 - w)^2 (2 + w) / 2``.

    Derived in the module docstring from ``Ft <= integral of mu p_min``; the
    same for every axis ratio and every direction of ``Ft``.

    Parameters
    ----------
    w : array_like
        ``W / a`` in [0, 1].

    Returns
    -------
    ndarray
        ``ft_lim`` in [0, 1], decreasing in ``w``.

    Examples
    --------
    >>> from core.theory.point_contact import ft_limit_point
    >>> round(float(ft_limit_point(0.3)), 4)
    0.5635
    """
    w = check_range("w", w, 0.0, 1.0)
    return (1.0 - w) ** 2 * (2.0 + w) / 2.0


def w_limit_point(ft):
    """Exact inverse of :func:`ft_limit_point`: ``w_lim = 2 cos(arccos(ft - 1)/3 - 2 pi/3)``.

    Parameters
    ----------
    ft : array_like
        ``Ft / (mu Fn)`` in [0, 1].

    Returns
    -------
    ndarray
        ``w_lim`` in [0, 1].

    Examples
    --------
    >>> from core.theory.point_contact import w_limit_point
    >>> round(float(w_limit_point(0.5635)), 3)
    0.3
    """
    ft = check_range("ft", ft, 0.0, 1.0)
    return np.clip(2.0 * np.cos(np.arccos(ft - 1.0) / 3.0 - 2.0 * math.pi / 3.0), 0.0, 1.0)
