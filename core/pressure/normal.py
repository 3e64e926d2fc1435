"""The normal contact problem solved numerically: constrained conjugate gradients (Polonsky and Keer 1999).

Given the gap profile ``h`` of a rigid body over a grid of elements (its
distance from the flat surface before any load, the body touching at its
lowest point) and the total normal load ``P``, find the element pressures
``p >= 0`` and the rigid approach ``delta`` such that the deformed gap
``g = h + K p - delta`` is zero where ``p > 0`` and ``>= 0`` elsewhere, with
``sum p dA = P``. ``K`` is the elastic operator of the surface: uncoupled
(Dundurs beta = 0), so the normal problem does not depend on friction.

Two grids, the same algorithm:

* a line of elements (plane strain): :func:`line_operator`, the FFT form of the
  log kernel of :mod:`core.elastic.operators` (the operator family the 1D tangential
  solver uses). Units: lengths in ``a``, pressure in ``p0``, displacements
  and gaps in ``P/E*``, with ``p0 = 2 P/(pi a)`` so that the nominal load is
  ``sum p dx = pi/2``: Hertz's cylinder is ``h = (2/pi) x^2`` and ``p = sqrt(1 - x^2)``.
* a patch of square elements (3D half-space, Boussinesq): :class:`PatchOperator`,
  ``u = s * integral p / rho`` with the closed-form element integrals of
  :func:`core.elastic.halfspace.rectangle_integrals`, applied by zero-padded FFT.
  With ``s = 3/(2 pi^2)`` (:attr:`core.theory.point_contact.Ellipsoid.kernel_scale`
  of the sphere) the units are those of the point contacts: lengths in ``a``,
  pressure in ``p0 = 3 P/(2 pi a^2)``, gaps in ``P/(E* a)``, nominal load
  ``2 pi/3``: Hertz's sphere is ``h = (3/8) r^2``.

:func:`solve_normal` is the solver for any operator with ``shape`` and
``apply``; :func:`solve_line` and :func:`solve_patch` build the operator.

On a line the contact holds a few hundred elements, and the operator is a
symmetric Toeplitz matrix (its ``column``): there :func:`solve_normal` solves
the problem directly (``method="direct"``, the default for lines up to
:data:`DIRECT_MAX_ELEMENTS` elements), by an active set on the influence
matrix: Levinson's recursion solves ``K x = 1``, ``K x = h`` and ``K x = e_0``
in ``O(m^2)`` on the window of a contact set ``C`` (its first to its last
element), which is all for an interval; the system restricted to a set with
holes ``D`` in its window (``K_CC p_C = delta - h_C``, ``sum p dA = P``)
follows from a Schur complement on the holes, with the columns of ``K^-1``
from its first by the Gohberg-Semencul (Trench) recursion and the multipliers
the holes' gaps, or, if the holes outnumber the contact, from the dense
``K_CC``. Elements of negative pressure leave ``C``,
penetrating ones join it, until neither is left: a few sets from the coarse
grid's, the solution to round-off; the first set is the contact of the
same problem on elements 4 times wider (recursively), or the given initial
pressure's. If the sets do not settle within :data:`ACTIVE_SET_ITERATIONS`
(or repeat, or a set needs a dense system above :data:`MAX_HOLES`), the
conjugate gradient solves it instead, and the result says so
(:attr:`NormalSolution.method`). A window whose matrix is not positive
definite (the log kernel over a contact wider than 4 times its reference
length) is solved with a constant added to every influence: the load fixes
``sum p``, so that changes the approach only.

References
----------
.. [1] I. A. Polonsky, L. M. Keer, "A new numerical method for solving rough
   contact problems based on the multi-level multi-summation and conjugate
   gradient techniques", Wear 231 (1999) 206-219.
.. [2] G. H. Golub, C. F. Van Loan, "Matrix Computations", 4th ed., Johns
   Hopkins (2013), algorithm 4.7.2 (Levinson) and section 4.7.5 (Trench's
   inverse of a symmetric Toeplitz matrix).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..base._jit import jit
from ..base._validate import check_int, check_scalar
from ..elastic.halfspace import rectangle_integrals
from ..elastic.operators import elastic_operator

__all__ = ["NormalSolution", "solve_normal", "solve_line", "solve_patch", "line_operator", "PatchOperator",
           "LINE_LOAD", "NORMAL_TOL", "METHODS", "DIRECT_MAX_ELEMENTS", "ACTIVE_SET_ITERATIONS", "MAX_HOLES"]

#: Nominal load of a line contact in ``p0 a`` (``P = pi a p0 / 2``).
LINE_LOAD = 0.5 * math.pi
#: Default tolerance: the relative change of the pressure field in one iteration (sum |dp| dA / P).
NORMAL_TOL = 1e-10
#: Values of ``method`` (:func:`solve_normal`).
METHODS = ("auto", "cg", "direct")
#: ``method="auto"`` solves a line of at most this many elements directly (Levinson's ``O(n^2)``; the
#: conjugate gradient's ``O(n log n)`` iterations above it). Measured on a cylinder, a punch and two bumps over
#: [-2, 2]: direct 0.26 ms against CG 2.7 ms at 320 elements, 1.6-3.0 ms against 6.6-8.6 ms at 2048, about
#: equal at 3000.
DIRECT_MAX_ELEMENTS = 2048
#: Contact sets the direct solve tries before it hands the problem to the conjugate gradient.
ACTIVE_SET_ITERATIONS = 50
#: The direct solve's dense system of a contact set with holes (elements out of contact between the first and
#: the last in contact) is in the holes or in the contact, the fewer: above this many it hands the problem to
#: the conjugate gradient (a rough profile's many islands).
MAX_HOLES = 512


@dataclass(frozen=True)
class NormalSolution:
    """A solved normal contact problem (read-only arrays).

    Attributes
    ----------
    pressure : ndarray
        Element pressures (>= 0), the grid's shape [p0].
    contact : ndarray of bool
        Elements in contact (``pressure > 0``).
    area : float
        Contact area (sum of the elements in contact) [a or a^2].
    approach : float
        Rigid approach ``delta`` [the gap's unit].
    load : float
        ``sum p dA`` (equals the load asked for).
    iterations : int
        Conjugate-gradient iterations, or the contact sets the direct solve tried.
    gap_residual : float
        Largest ``|g|`` in contact, against the largest ``|h - delta|`` there (relative).
    penetration : float
        Largest penetration ``max(-g)`` out of contact, relative likewise (0 when none).
    method : str
        How it was solved: ``"cg"`` (Polonsky-Keer), ``"direct"`` (active set on
        the Toeplitz matrix), or ``"cg-fallback"`` (the direct solve did not
        settle and the conjugate gradient solved it).
    """

    pressure: np.ndarray
    contact: np.ndarray
    area: float
    approach: float
    load: float
    iterations: int
    gap_residual: float
    penetration: float
    method: str = "cg"


def line_operator(n, dx):
    """The plane-strain normal operator of ``n`` elements of width ``dx`` [a] (FFT form, :mod:`core.elastic.operators`).

    ``u = K p`` [P/E*] of pressures [p0]: the same log kernel as the tangential one.
    """
    return elastic_operator(n, dx, "plane", form="fft")


class PatchOperator:
    """Normal surface displacement of a half-space from element pressures on a square grid (Boussinesq).

    Parameters
    ----------
    ny, nx : int
        Rows (along y) and columns (along x), each in [1, 4096].
    h : float
        Element side [a], > 0.
    scale : float
        Kernel factor: ``u = scale * integral p / rho`` (``1/(pi E*)`` in the
        units used; ``3/(2 pi^2)`` for the sphere's point-contact units), > 0.

    Examples
    --------
    >>> import numpy as np
    >>> from core.pressure.normal import PatchOperator
    >>> op = PatchOperator(4, 5, 0.3)
    >>> p = np.random.default_rng(1).random(op.shape)
    >>> bool(np.allclose(op.apply(p).ravel(), op.matrix() @ p.ravel()))
    True
    """

    def __init__(self, ny, nx, h, scale=1.5 / math.pi**2):
        self.ny = check_int("ny", ny, 1, 4096)
        self.nx = check_int("nx", nx, 1, 4096)
        self.h = check_scalar("h", h, 0.0, None, lo_closed=False)
        self.scale = check_scalar("scale", scale, 0.0, None, lo_closed=False)
        self.shape = (self.ny, self.nx)
        self.size = self.ny * self.nx
        iy = np.arange(-(self.ny - 1), self.ny)[:, None]
        ix = np.arange(-(self.nx - 1), self.nx)[None, :]
        self._kernel = self.scale * rectangle_integrals(ix * self.h, iy * self.h, self.h)[0]
        self._pad = (sfft.next_fast_len(2 * self.ny - 1, real=True), sfft.next_fast_len(2 * self.nx - 1, real=True))
        e = np.zeros(self._pad)
        k = self._kernel
        # circulant embedding: offset (i, j) at index (i mod N, j mod M)
        e[np.arange(-(self.ny - 1), self.ny)[:, None] % self._pad[0],
          np.arange(-(self.nx - 1), self.nx)[None, :] % self._pad[1]] = k
        self._hat = sfft.rfft2(e)
        self._inv = None

    def precondition(self, r):
        """Approximate inverse: the inverse of the continuous symbol ``2 pi scale / |k|`` of ``scale / rho``,
        applied by FFT on the zero-padded grid (``k = 0`` replaced by the lowest non-zero wavenumber)."""
        r = np.asarray(r, dtype=float)
        if self._inv is None:
            ky = 2 * np.pi * sfft.fftfreq(self._pad[0], d=self.h)[:, None]
            kx = 2 * np.pi * sfft.rfftfreq(self._pad[1], d=self.h)[None, :]
            k = np.sqrt(kx * kx + ky * ky)
            k[0, 0] = min(kx[0, 1], ky[1, 0])
            self._inv = k / (2 * np.pi * self.scale)
        return sfft.irfft2(sfft.rfft2(r, self._pad) * self._inv, self._pad)[: self.ny, : self.nx]

    def apply(self, p):
        """Displacements ``u = K p`` of pressures ``p`` (shape ``(ny, nx)``)."""
        p = np.asarray(p, dtype=float)
        if p.shape != self.shape:
            raise ValueError(f"p must have shape {self.shape}, got {p.shape}")
        return sfft.irfft2(sfft.rfft2(p, self._pad) * self._hat, self._pad)[: self.ny, : self.nx]

    def matrix(self):
        """The dense ``(ny nx, ny nx)`` matrix (for checks; refused above 6000 unknowns)."""
        if self.size > 6000:
            raise ValueError(f"{self.size} unknowns is above 6000 for a dense matrix")
        iy, ix = np.divmod(np.arange(self.size), self.nx)
        return self._kernel[(iy[:, None] - iy[None, :]) + self.ny - 1, (ix[:, None] - ix[None, :]) + self.nx - 1]


def _fast_apply(operator):
    """``operator.apply`` and ``operator.precondition`` (or None) without their per-call checks: for the 1D FFT
    operator, its padded products with the kernel's spectrum and with its inverse continuous symbol."""
    spectrum = getattr(operator, "spectrum", None)
    pre = getattr(operator, "precondition", None)
    if spectrum is None or getattr(operator, "form", None) != "fft":
        return operator.apply, pre
    n = operator.size
    N = sfft.next_fast_len(2 * n, real=True)
    hat, inv = spectrum(N), operator.inverse_symbol(N)

    def apply(v):
        return sfft.irfft(sfft.rfft(v, N) * hat, N)[:n]

    def precondition(v):
        return sfft.irfft(sfft.rfft(v, N) * inv, N)[:n]
    return apply, precondition


@jit
def _levinson(t, B):
    """Solve ``T X^T = B^T`` for the symmetric Toeplitz ``T`` of first column ``t`` (Levinson, Golub and Van Loan
    algorithm 4.7.2), each row of ``B`` (shape ``(m, n)``) a right-hand side; and False if ``T`` is not positive
    definite (a leading minor's ``beta`` not > 0)."""
    m, n = B.shape
    Y = np.zeros((m, n))
    z = np.zeros(n)
    tmp = np.zeros(n)
    t0 = t[0]
    if not t0 > 0.0:
        return Y, False
    for c in range(m):
        Y[c, 0] = B[c, 0] / t0
    if n == 1:
        return Y, True
    alpha = -t[1] / t0
    beta = 1.0
    z[0] = alpha
    for k in range(1, n):
        beta = (1.0 - alpha * alpha) * beta
        if not beta > 0.0:
            return Y, False
        for c in range(m):
            s = 0.0
            for i in range(k):
                s += t[i + 1] * Y[c, k - 1 - i]
            mu = (B[c, k] - s) / (t0 * beta)
            for i in range(k):
                Y[c, i] += mu * z[k - 1 - i]
            Y[c, k] = mu
        if k < n - 1:
            s = 0.0
            for i in range(k):
                s += t[i + 1] * z[k - 1 - i]
            alpha = -(t[k + 1] + s) / (t0 * beta)
            for i in range(k):
                tmp[i] = z[i] + alpha * z[k - 1 - i]
            for i in range(k):
                z[i] = tmp[i]
            z[k] = alpha
    return Y, True


@jit
def _inverse_columns(g, depth):
    """Columns ``0 .. depth - 1`` of the inverse of a symmetric Toeplitz matrix (as rows) from its first column
    ``g``: Trench's recursion ``A[i, j] = A[i - 1, j - 1] + (g_i g_j - g_(n-i) g_(n-j)) / g_0``."""
    n = g.size
    A = np.empty((depth, n))
    A[0] = g
    for j in range(1, depth):
        A[j, 0] = g[j]
        gj, gnj = g[j], g[n - j]
        for i in range(1, n):
            A[j, i] = A[j - 1, i - 1] + (g[i] * gj - g[n - i] * gnj) / g[0]
    return A


@jit
def _active_set(h, w, t, C, max_sets, max_dense, history):
    """The active-set loop of :func:`_solve_direct` (numba): ``(p, sets tried)``, sets 0 if it failed, -1 if a
    window's matrix is not positive definite.

    ``h`` the profile, ``w = load / dA``, ``t`` the matrix's first column (at least ``n`` entries), ``C`` the
    first contact set (changed in place), ``history`` a ``(max_sets, n)`` bool scratch array (the sets tried,
    to stop at a repeat). Each set is solved on its window (first to last element in contact): with no hole
    (an interval) by Levinson's recursion alone; with fewer holes than elements in contact by a Schur
    complement on the holes (columns of the window's inverse by Trench's recursion), whose multipliers are
    their gaps; else by a dense solve on the contact. It gives up on a set whose dense system (holes or
    contact, the smaller) exceeds ``max_dense``. The gaps out of the window are summed directly.
    """
    n = h.size
    p = np.zeros(n)
    hscale = h.max() - h.min()
    if not hscale > 0.0:
        hscale = 1.0
    lo_w, hi_w = -1, -1
    m = 0
    X = np.zeros((3, 1))
    have_x = False
    left = np.zeros((0, 1))
    for it in range(1, max_sets + 1):
        inside = np.nonzero(C)[0]
        if inside.size == 0:
            return p, 0
        lo, hi = inside[0], inside[-1] + 1
        if lo != lo_w or hi != hi_w:  # a new window
            lo_w, hi_w, m = lo, hi, hi - lo
            have_x = False
            left = np.zeros((0, m))
        holes = np.nonzero(~C[lo:hi])[0]
        k = holes.size
        c = m - k
        if min(k, c) > max_dense:
            return p, 0
        if k <= c and not have_x:  # solve K x = 1, h, e_0 on the window
            B = np.zeros((3, m))
            B[0, :] = 1.0
            B[1, :] = h[lo:hi]
            B[2, 0] = 1.0
            X, ok = _levinson(t[:m].copy(), B)
            if not ok:
                return p, -1
            have_x = True
        gaps = np.zeros(k)  # the gaps of the holes
        lam = np.zeros((k, 2))
        if k == 0:
            p1 = X[0].copy()
            ph = X[1].copy()
        elif k <= c:
            p1 = X[0].copy()
            ph = X[1].copy()
            near = np.minimum(holes, m - 1 - holes)
            need = near.max() + 1
            if need > left.shape[0]:
                left = _inverse_columns(X[2], min(max(2 * need, 16), m))
            AD = np.empty((k, m))
            for a in range(k):
                j = holes[a]
                if j <= m - 1 - j:
                    AD[a, :] = left[j]
                else:
                    AD[a, :] = left[m - 1 - j][::-1]
            S = np.empty((k, k))
            R = np.empty((k, 2))
            for a in range(k):
                for b in range(k):
                    S[a, b] = AD[b, holes[a]]
                R[a, 0] = X[0, holes[a]]
                R[a, 1] = X[1, holes[a]]
            lam = np.linalg.solve(S, R)
            for a in range(k):
                for i in range(m):
                    p1[i] -= lam[a, 0] * AD[a, i]
                    ph[i] -= lam[a, 1] * AD[a, i]
            for a in range(k):
                p1[holes[a]] = 0.0
                ph[holes[a]] = 0.0
        else:  # more holes than contact: the contact's own dense system
            cidx = np.nonzero(C[lo:hi])[0]
            K = np.empty((c, c))
            R = np.empty((c, 2))
            for a in range(c):
                for b in range(c):
                    K[a, b] = t[abs(cidx[a] - cidx[b])]
                R[a, 0] = 1.0
                R[a, 1] = h[lo + cidx[a]]
            Y = np.linalg.solve(K, R)
            p1 = np.zeros(m)
            ph = np.zeros(m)
            for a in range(c):
                p1[cidx[a]] = Y[a, 0]
                ph[cidx[a]] = Y[a, 1]
        s1 = p1.sum()
        if not s1 > 0.0:
            return p, 0
        delta = (w + ph.sum()) / s1
        pw = delta * p1 - ph
        top = pw.max()
        if not top > 0.0:
            return p, 0
        if k > 0 and k <= c:  # the gap of a hole is its multiplier
            for a in range(k):
                gaps[a] = lam[a, 1] - delta * lam[a, 0]
        elif k > 0:
            for a in range(k):
                u = 0.0
                for j in range(m):
                    u += t[abs(holes[a] - j)] * pw[j]
                gaps[a] = u + h[lo + holes[a]] - delta
        changed = False
        for i in range(m):
            if C[lo + i] and pw[i] < -1e-12 * top:
                C[lo + i] = False
                changed = True
        for a in range(k):
            if gaps[a] < -1e-12 * hscale:
                C[lo + holes[a]] = True
                changed = True
        for i in range(n):  # the gaps out of the window
            if lo <= i < hi:
                continue
            u = 0.0
            for j in range(m):
                u += t[abs(i - lo - j)] * pw[j]
            if u + h[i] - delta < -1e-12 * hscale:
                C[i] = True
                changed = True
        if not changed:
            for i in range(m):
                p[lo + i] = pw[i] if pw[i] > 0.0 else 0.0
            return p, it
        history[it - 1, :] = C
        for prev in range(it - 1):
            same = True
            for i in range(n):
                if history[prev, i] != C[i]:
                    same = False
                    break
            if same:
                return p, 0
    return p, 0


def _window_product(t, p, lo, hi):
    """``K p`` on every element for ``p`` zero outside ``lo:hi`` (``K[i, j] = t[|i - j|]``): one direct
    convolution with the symmetric kernel (no FFT set-up)."""
    n = p.size
    return np.convolve(np.concatenate((t[n - 1:0:-1], t[:n])), p[lo:hi])[n - 1 - lo:2 * n - 1 - lo]


@functools.lru_cache(maxsize=32)
def _shared_toeplitz(n, dx, kernel, options):
    """The FFT operator of ``n`` elements of width ``dx`` (``options`` a sorted tuple of the kernel's), kept for
    the grids met last."""
    return elastic_operator(n, dx, kernel, form="fft", **dict(options))


def _coarse_start(h, load, dA, operator, depth=0):
    """A first contact set for the direct solve of a line: the contact of the same problem on elements 4 times
    wider (profile averaged over each group of 4, solved the same way, recursively down to 64 elements), each
    group's elements in contact if it is; every element if there is no coarser grid to solve."""
    n = h.size
    everything = np.ones(n, dtype=bool)
    dx, kernel = getattr(operator, "dx", None), getattr(operator, "kernel", None)
    if n <= 64 or dx is None or kernel is None or depth > 8:
        return everything
    m = -(-n // 4)
    hc = np.concatenate((h, np.full(4 * m - n, h[-1]))).reshape(m, 4).mean(axis=1)
    coarse = _shared_toeplitz(m, 4.0 * dx, kernel, tuple(sorted(getattr(operator, "options", {}).items())))
    start = _coarse_start(hc, load, 4.0 * dA, coarse, depth + 1)
    solved = _solve_direct(hc, load, coarse.column, 4.0 * dA, start, ACTIVE_SET_ITERATIONS)
    if solved is None:
        return everything
    return np.repeat(solved[0] > 0, 4)[:n]


def _solve_direct(h, load, column, dA, start, max_sets):
    """The line problem by an active set on the Toeplitz matrix of first column ``column`` (see the module
    docstring): ``(p, sets tried)``, or None if the sets do not settle in ``max_sets`` (or repeat), or no matrix
    tried is positive definite. ``start``: the first contact set (bool).

    The load fixes ``sum p``, so adding a constant ``c`` to every influence (``K + c 1 1^T``) changes only the
    approach (by ``c sum p``), not the pressures: where a window's matrix is not positive definite (the log
    kernel over a contact wider than 4 times its reference length) the solve is repeated with ``c`` = 1, 2, 4
    and 8 times the self-influence, which makes it so (the reference length multiplied)."""
    n = h.size
    h = np.ascontiguousarray(h, dtype=float)
    t = np.ascontiguousarray(column[:n], dtype=float)
    history = np.zeros((max_sets, n), dtype=bool)
    for shift in (0.0, 1.0, 2.0, 4.0, 8.0):
        C = np.array(start, dtype=bool)
        try:
            p, sets = _active_set(h, float(load / dA), t + shift * abs(t[0]), C, int(max_sets), MAX_HOLES, history)
        except np.linalg.LinAlgError:  # a singular Schur or contact system
            return None
        if sets != -1:
            break
    if sets <= 0 or not np.all(np.isfinite(p)) or not p.sum() > 0:
        return None
    return p, int(sets)


def _solve_cg(h, load, dA, apply, pre, p, tol, maxiter):
    """Polonsky and Keer's constrained (preconditioned) conjugate gradient from the pressure ``p``:
    ``(p, iterations)``; ValueError if it does not converge in ``maxiter`` iterations."""
    shape = h.shape
    t = np.zeros(shape)
    g_old, delta, it = 1.0, 0.0, 0
    err = math.inf
    for it in range(1, maxiter + 1):
        c = p > 0
        g = apply(p) + h
        g -= g[c].mean()
        if pre is None:
            z = g
        else:  # the preconditioned residual, restricted to the contact and projected on zero total load
            z = pre(np.where(c, g, 0.0))
            z -= z[c].mean()
        G = float(np.dot(g[c], z[c]))
        t = np.where(c, z + delta * (G / g_old) * t, 0.0)
        g_old = G if G > 0 else 1.0
        r = apply(t)
        r -= r[c].mean()
        denom = float(np.dot(r[c], t[c]))
        if denom <= 0 and delta != 0:  # the kept direction lost conjugacy as the contact changed: restart from z
            t = np.where(c, z, 0.0)
            r = apply(t)
            r -= r[c].mean()
            denom = float(np.dot(r[c], t[c]))
        tau = float(np.dot(g[c], t[c])) / denom if denom != 0 else 0.0
        p_prev = p
        p = np.where(c, p - tau * t, 0.0)
        p[p < 0] = 0.0
        overlap = (p == 0) & (g < 0)
        if np.any(overlap):
            delta = 0.0
            p[overlap] -= tau * g[overlap]
        else:
            delta = 1.0
        total = p.sum() * dA
        if total <= 0:
            raise ValueError("the normal solve lost all contact: check the profile and the grid")
        p *= load / total
        err = float(np.abs(p - p_prev).sum()) * dA / load
        if err < tol:
            return p, it
    raise ValueError(f"the normal solve did not converge in maxiter = {maxiter} iterations (change {err:.2e})")


def solve_normal(profile, load, operator, element_area, *, tol=NORMAL_TOL, maxiter=None, initial=None,
                 precondition=True, method="auto"):
    """Pressure under a rigid profile pressed by ``load``: Polonsky and Keer's constrained conjugate gradient, or
    on a line an active set solved directly.

    Parameters
    ----------
    profile : array_like
        Gap ``h`` of every element before deformation, the operator's shape
        (any additive constant: the approach absorbs it). Finite.
    load : float
        Total load ``sum p dA``, > 0.
    operator : object
        ``shape`` and ``apply(p)``: the surface displacement of the pressures
        (:func:`line_operator`, :class:`PatchOperator`).
    element_area : float
        ``dA`` of one element (``dx`` on a line, ``h^2`` on a patch), > 0.
    tol : float
        Conjugate gradient: stop when ``sum |p_new - p_old| dA / load`` falls
        below it, in [1e-14, 1e-3]. The direct solve ends at round-off.
    maxiter : int, optional
        Conjugate-gradient iterations allowed, up to 100 000 (default ``max(2000, 20 sqrt(n))``).
    initial : array_like, optional
        Starting pressure (e.g. a neighbouring solution); default uniform. The
        direct solve starts from its contact set (``initial > 0``; default every element).
    precondition : bool
        Precondition the conjugate gradient with the operator's ``precondition``
        (the inverse of the kernel's continuous symbol, by FFT), projected on the
        contact set: 3 to 4 times fewer iterations on fine grids (25 against 56 at
        ``dx = 1/40``, 41 against 172 at ``1/640`` for the cylinder), the same
        solution. Ignored if the operator has none.
    method : {"auto", "cg", "direct"}
        ``"cg"``: the conjugate gradient. ``"direct"``: the active set on the
        operator's symmetric Toeplitz matrix (a line operator with a ``column``:
        :func:`line_operator`), handed to the conjugate gradient if it does not
        settle in :data:`ACTIVE_SET_ITERATIONS` sets. ``"auto"``: direct on a line
        of at most :data:`DIRECT_MAX_ELEMENTS` elements, else the conjugate gradient.

    Returns
    -------
    NormalSolution
        Its ``method`` says which solve gave it.

    Raises
    ------
    ValueError
        For an invalid input, or if it does not converge in ``maxiter`` iterations.

    Examples
    --------
    >>> import numpy as np
    >>> from core.pressure.normal import solve_line
    >>> x = (np.arange(400) + 0.5) * 0.01 - 2.0
    >>> s = solve_line((2 / np.pi) * x**2, 0.01)
    >>> bool(np.max(np.abs(s.pressure - np.sqrt(np.clip(1 - x**2, 0, None)))) < 0.02)
    True
    >>> s.method
    'direct'
    >>> c = solve_line((2 / np.pi) * x**2, 0.01, method="cg")
    >>> c.method, bool(np.abs(c.pressure - s.pressure).max() < 1e-8), bool(np.all(c.contact == s.contact))
    ('cg', True, True)
    """
    h = np.asarray(profile, dtype=float)
    shape = tuple(operator.shape)
    if h.shape != shape:
        raise ValueError(f"profile must have the operator's shape {shape}, got {h.shape}")
    if not np.all(np.isfinite(h)):
        raise ValueError("profile must be finite")
    load = check_scalar("load", load, 0.0, None, lo_closed=False)
    dA = check_scalar("element_area", element_area, 0.0, None, lo_closed=False)
    tol = check_scalar("tol", tol, 1e-14, 1e-3)
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r:.60}")
    n = h.size
    maxiter = check_int("maxiter", max(2000, 20 * int(math.sqrt(n))) if maxiter is None else maxiter, 1, 100_000)
    if initial is None:
        p = np.full(shape, load / (n * dA))
    else:
        p = np.array(initial, dtype=float)
        if p.shape != shape or not np.all(np.isfinite(p)) or np.any(p < 0) or p.sum() <= 0:
            raise ValueError(f"initial must be a non-negative, non-zero array of shape {shape}")
        p *= load / (p.sum() * dA)
    column = getattr(operator, "column", None)
    toeplitz = column is not None and len(shape) == 1 and np.ndim(column) == 1 and np.size(column) >= n
    if method == "direct" and not toeplitz:
        raise ValueError("method='direct' needs a line operator with a symmetric Toeplitz matrix (its column), "
                         f"got {type(operator).__name__}: use method='cg' or 'auto'")
    used = "cg"
    direct = None
    if method == "direct" or (method == "auto" and toeplitz and n <= DIRECT_MAX_ELEMENTS):
        start = _coarse_start(h, load, dA, operator) if initial is None else p > 0
        direct = _solve_direct(h, load, np.asarray(column), dA, start, ACTIVE_SET_ITERATIONS)
        used = "cg-fallback"
    if direct is not None:
        p, it = direct
        used = "direct"
    else:
        apply, pre = _fast_apply(operator)
        p, it = _solve_cg(h, load, dA, apply, pre if precondition else None, p, tol, maxiter)
    c = p > 0
    if used == "direct" and n <= 1024:  # its matrix product on the contact's window (no FFT set-up)
        inside = np.flatnonzero(c)
        u = _window_product(np.ascontiguousarray(column[:n], dtype=float), p, inside[0], inside[-1] + 1) + h
    else:
        u = operator.apply(p) + h
    approach = float(u[c].mean())
    gap = u - approach
    scale = float(np.max(np.abs(h[c] - h[c].min()))) or 1.0
    pen = float(max(0.0, -gap[~c].min())) / scale if np.any(~c) else 0.0
    for a in (p, c):
        a.setflags(write=False)
    return NormalSolution(pressure=p, contact=c, area=float(c.sum() * dA), approach=approach,
                          load=float(p.sum() * dA), iterations=it,
                          gap_residual=float(np.max(np.abs(gap[c]))) / scale, penetration=pen, method=used)


@functools.lru_cache(maxsize=32)
def _shared_line_operator(n, dx):
    """:func:`line_operator`, kept for the grids met last (its kernel column and FFT spectra depend on ``n`` and
    ``dx`` only: the coarse and fine grids of every line body's solve at one ``dx`` share them)."""
    return line_operator(n, dx)


def solve_line(profile, dx, load=LINE_LOAD, **options):
    """:func:`solve_normal` on a line of elements of width ``dx`` [a] (plane strain), load in ``p0 a``.

    Parameters
    ----------
    profile : array_like, shape (n,)
        Gap of every element [P/E*], n >= 3.
    dx : float
        Element width [a], in [1e-5, 1].
    load : float
        ``sum p dx`` [p0 a]; the default ``pi/2`` is the nominal ``P``.
    **options
        Of :func:`solve_normal` (``method``, ``initial``, ``tol``, ...).

    Returns
    -------
    NormalSolution

    Examples
    --------
    Two bumps (a non-convex profile): the contact is two intervals.

    >>> import numpy as np
    >>> from core.pressure.normal import solve_line
    >>> x = (np.arange(200) + 0.5) * 0.02 - 2.0
    >>> s = solve_line((x**2 - 0.8)**2, 0.02)
    >>> s.method, int(np.count_nonzero(np.diff(s.contact.astype(int)) == 1))
    ('direct', 2)
    """
    h = np.asarray(profile, dtype=float)
    if h.ndim != 1 or h.size < 3:
        raise ValueError(f"profile must be a 1-D array of at least 3 elements, got shape {h.shape}")
    dx = check_scalar("dx", dx, 1e-5, 1.0)
    return solve_normal(h, load, _shared_line_operator(h.size, dx), dx, **options)


def solve_patch(profile, h, load=2.0 * math.pi / 3.0, scale=1.5 / math.pi**2, **options):
    """:func:`solve_normal` on a patch of square elements of side ``h`` [a] (3D half-space).

    Defaults: the sphere's point-contact units (load ``2 pi/3`` in ``p0 a^2``, kernel scale ``3/(2 pi^2)``,
    profile in ``P/(E* a)``).
    """
    g = np.asarray(profile, dtype=float)
    if g.ndim != 2 or min(g.shape) < 3:
        raise ValueError(f"profile must be a 2-D array of at least 3 x 3 elements, got shape {g.shape}")
    h = check_scalar("h", h, 1e-5, 1.0)
    return solve_normal(g, load, PatchOperator(*g.shape, h, scale), h * h, **options)
