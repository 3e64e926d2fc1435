"""Influence kernels of the tangential problem on a uniform world-fixed grid.

Piecewise-constant tractions on elements of width ``dx``; displacement
collocated at element centres; every element integral in closed form. Both
kernels are Toeplitz (they depend on ``i - j`` only), so one function builds
the matrix from a vector of element influences, and the two kernels differ in
nothing but that vector.

Normalised units: lengths in the half-width ``a``, tractions in ``mu p0``,
displacements in ``mu P / E*`` (``P = Fn / L``), so that a traction ``q`` gives
the displacement ``u = K @ q``.

* ``"plane"``: plane strain (2D) with the log kernel,
  ``u(x) = -(2 / (pi E*)) integral q(xi) ln(|x - xi| / l) dxi``; a rigid
  displacement in 2D is defined only up to a constant, fixed here by the
  reference length ``l = PLANE_REFERENCE_LENGTH`` (in ``a``).
* ``"strip"``: the truncated 3D model of the paper and of CONTACT: the Cerruti
  solution integrated over each element's rectangle ``dx`` by ``L``,
  ``u_x = (1/(2 pi)) integral [A / rho + B (x - xi)^2 / rho^3] q dxi deta``
  with ``A = sum (1 - nu_i)/G_i = 2/E*`` and ``B = sum nu_i / G_i``. Its
  displacements are absolute (relative to a remote point).

References
----------
.. [1] K. L. Johnson, *Contact Mechanics*, CUP 1985, sections 2.2 and 3.2.
.. [2] R. Wetter, Physical Mesomechanics 18 (2015), eq 31.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import toeplitz

from ..base._validate import check_int, check_scalar
from ..theory.analytical import hertz_pressure_element_mean

__all__ = [
    "KERNELS",
    "PLANE_REFERENCE_LENGTH",
    "plane_strain_influence",
    "strip_influence",
    "influence_matrix",
    "strip_b_coefficient",
    "strip_u0",
    "kernel_column",
    "kernel_symbol",
]

#: Reference length [a] of the plane-strain kernel (displacement zero at that distance).
#: It also keeps the log kernel positive definite for contacts narrower than 4 l.
PLANE_REFERENCE_LENGTH = 4.0


def _xlogx(t):
    """t ln|t| with the limit 0 at t = 0."""
    t = np.asarray(t, dtype=float)
    at = np.abs(t)
    return np.where(at > 0, t * np.log(np.where(at > 0, at, 1.0)), 0.0)


def plane_strain_influence(offsets, dx, reference_length=PLANE_REFERENCE_LENGTH):
    """Plane-strain displacement at distance ``offsets`` from a unit element of width ``dx``.

    ``(4/pi^2) integral over |t - d| < dx/2 of ln(l / |t|) dt`` [mu P/E* per mu p0],
    the factor ``4/pi^2 = (2/pi) * (2/pi)`` coming from ``2/(pi E*)`` and
    ``mu p0 a = 2 mu P / pi``.

    Parameters
    ----------
    offsets : array_like
        Collocation point minus element centre [a].
    dx : float
        Element width [a], > 0.
    reference_length : float
        Distance [a] at which the displacement is zero.
    """
    dx = check_scalar("dx", dx, 0.0, None, lo_closed=False)
    ell = check_scalar("reference_length", reference_length, 0.0, None, lo_closed=False)
    d = np.asarray(offsets, dtype=float)
    h = 0.5 * dx
    # integral of -ln|t| dt = -(t ln|t| - t)
    val = -(_xlogx(d + h) - _xlogx(d - h)) + 2.0 * h + dx * np.log(ell)
    return (4.0 / np.pi**2) * val


def _strip_primitive(t, S, bE):
    """G(t) = int_0^t int_0^S (A/rho + B t^2/rho^3) ds dt, times E*, for t >= 0 (odd extension)."""
    at = np.abs(t)
    rho = np.hypot(at, S)
    aE = 2.0  # E* A = E* sum (1 - nu_i)/G_i = 2 for every pair of materials
    g = (aE * (at * np.log(S + rho) - _xlogx(at))
         + (aE + bE) * S * (np.log(at + rho) - np.log(S)))
    return np.sign(t) * g


def strip_influence(offsets, dx, L_over_a, b_coefficient):
    """Truncated-3D (strip) displacement at ``offsets`` from a unit element of width ``dx`` and length ``L``.

    Parameters
    ----------
    offsets : array_like
        Collocation point minus element centre [a].
    dx : float
        Element width [a], > 0.
    L_over_a : float
        Strip length over the half-width, > 0.
    b_coefficient : float
        ``E* sum nu_i / G_i`` (``2 nu / (1 - nu)`` for a rigid cylinder on a
        substrate of Poisson ratio ``nu``), >= 0; see :func:`strip_b_coefficient`.

    Returns
    -------
    ndarray
        Displacement [mu P/E*] per unit traction [mu p0]: ``(1/pi^2) * 2 * (G(d + dx/2) - G(d - dx/2))``.
    """
    dx = check_scalar("dx", dx, 0.0, None, lo_closed=False)
    L = check_scalar("L_over_a", L_over_a, 0.0, None, lo_closed=False)
    bE = check_scalar("b_coefficient", b_coefficient, 0.0, None)
    d = np.asarray(offsets, dtype=float)
    S = 0.5 * L
    h = 0.5 * dx
    return (2.0 / np.pi**2) * (_strip_primitive(d + h, S, bE) - _strip_primitive(d - h, S, bE))


def strip_b_coefficient(nu):
    """``E* B = 2 nu / (1 - nu)`` for a rigid cylinder on a substrate with Poisson ratio ``nu`` (or equal bodies)."""
    nu = check_scalar("nu", nu, 0.0, 0.5)
    return 2.0 * nu / (1.0 - nu)


#: The kernels, by name: each maps (offsets, dx, **options) to element influences.
KERNELS = {
    "plane": plane_strain_influence,
    "strip": strip_influence,
}


def kernel_column(n, dx, kernel="plane", **options):
    """First column of the influence matrix: the influence of element 0 on elements ``0 .. n-1``.

    The matrix is symmetric Toeplitz, ``K[i, j] = column[|i - j|]``; this is
    all that the FFT form of the operator (:mod:`core.elastic.operators`) keeps.

    Parameters
    ----------
    n : int
        Number of entries, >= 1.
    dx : float
        Element width [a].
    kernel : {"plane", "strip"}
        Which kernel (see the module docstring).
    **options
        Passed to the kernel.

    Returns
    -------
    ndarray, shape (n,)
        Element influences [mu P/E* per mu p0] at offsets ``0, dx, .., (n-1) dx``.
    """
    n = check_int("n", n, 1, 10**8)
    if kernel not in KERNELS:
        raise ValueError(f"kernel must be one of {sorted(KERNELS)}, got {kernel!r:.60}")
    return np.asarray(KERNELS[kernel](np.arange(n) * float(dx), dx, **options), dtype=float)


def kernel_symbol(k, kernel="plane", **options):
    """Continuous symbol of the kernel: the Fourier transform of ``u = K q`` at wavenumbers ``k`` != 0.

    With ``u(x) = integral k(x - xi) q(xi) dxi`` and ``hat f(k) = integral f(x) exp(-i k x) dx``,
    ``hat u = symbol(k) hat q``. For the plane-strain kernel
    ``k(t) = (4/pi^2) ln(l/|t|)``, ``hat ln(1/|t|) = pi/|k|`` away from ``k = 0``, so

        ``symbol = 4 / (pi |k|)``   [mu P/E* per mu p0, k in 1/a]

    (the reference length ``l`` adds only a multiple of ``delta(k)``). For the
    strip of length ``L = 2 S``, integrating the Cerruti kernel over the strip
    (the x-transforms of ``1/rho`` and ``x^2/rho^3`` are ``2 K0(|k eta|)`` and
    ``2 (K0 - |k eta| K1)(|k eta|)``, and ``integral_0^X t K1 = integral_0^X K0 - X K0(X)``):

        ``symbol = (4 / (pi^2 |k|)) [2 integral_0^{|k| S} K0(t) dt + bE |k| S K0(|k| S)]``,

    which tends to the plane-strain symbol for ``|k| S >> 1``. Both are first
    order and decay as ``1/|k|``; their inverse (about ``pi |k| / 4``) is the
    preconditioner of the matrix-free solver.

    Parameters
    ----------
    k : array_like
        Wavenumbers [1/a], != 0.
    kernel : {"plane", "strip"}
    **options
        ``L_over_a`` and ``b_coefficient`` for ``"strip"`` (``reference_length`` is accepted and unused).

    Returns
    -------
    ndarray
        The symbol at ``|k|``.
    """
    ak = np.abs(np.asarray(k, dtype=float))
    if np.any(ak == 0) or not np.all(np.isfinite(ak)):
        raise ValueError("k must be finite and non-zero (the symbols are singular at k = 0)")
    if kernel == "plane":
        return 4.0 / (np.pi * ak)
    if kernel == "strip":
        from scipy.special import iti0k0, k0

        if "L_over_a" not in options or "b_coefficient" not in options:
            raise ValueError("the strip symbol needs L_over_a and b_coefficient")
        S = 0.5 * check_scalar("L_over_a", options["L_over_a"], 0.0, None, lo_closed=False)
        bE = check_scalar("b_coefficient", options["b_coefficient"], 0.0, None)
        X = ak * S
        # K0(X) underflows harmlessly to 0 for large X; X K0(X) -> 0 as X -> 0
        return 4.0 / (np.pi**2 * ak) * (2.0 * iti0k0(X)[1] + bE * X * k0(X))
    raise ValueError(f"kernel must be one of {sorted(KERNELS)}, got {kernel!r:.60}")


def influence_matrix(n, dx, kernel="plane", **options):
    """Dense influence matrix ``K`` of ``n`` uniform elements: ``u = K @ q``.

    Parameters
    ----------
    n : int
        Number of elements, >= 1.
    dx : float
        Element width [a].
    kernel : {"plane", "strip"}
        Which kernel (see the module docstring).
    **options
        Passed to the kernel (``reference_length`` for ``"plane"``;
        ``L_over_a`` and ``b_coefficient`` for ``"strip"``).

    Returns
    -------
    ndarray, shape (n, n)
        Symmetric Toeplitz matrix [mu P/E* per mu p0].
    """
    n = check_int("n", n, 1, 100_000)
    if kernel not in KERNELS:
        raise ValueError(f"kernel must be one of {sorted(KERNELS)}, got {kernel!r:.60}")
    column = KERNELS[kernel](np.arange(n) * float(dx), dx, **options)
    return np.ascontiguousarray(toeplitz(column))


def strip_u0(L_over_a, b_coefficient, n=4000):
    """``U0``: displacement at ``ft = 1`` of the strip, at the contact centre [mu P/E*].

    The full-slip traction ``q = mu p`` (Hertz) loads the strip; ``U0`` is the
    displacement it gives at ``x = 0``, the limit of the stick displacement as
    ``ft -> 1``. Computed with the exact element integrals of
    :func:`strip_influence` on ``n`` elements across the contact (the
    element-mean Hertz traction), which converges like ``dx^2``.

    Compare with the paper's reconstructed eq 14,
    :func:`core.theory.approximations.u0_approx`.
    """
    n = check_int("n", n, 2, 10**6)
    edges = np.linspace(-1.0, 1.0, n + 1)
    dx = edges[1] - edges[0]
    q = hertz_pressure_element_mean(edges, 0.0)
    centres = 0.5 * (edges[1:] + edges[:-1])
    return float(strip_influence(0.0 - centres, dx, L_over_a, b_coefficient) @ q)
