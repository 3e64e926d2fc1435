"""The 3D incremental tangential problem of a rocking point contact, matrix-free.

At each step the pressure ``p`` is the body's at the current centre (uncoupled,
Dundurs beta = 0: Hertz's for the sphere and ellipsoids, solved on the grid or
sampled, ``normal=``; a height map's solved numerically, :mod:`core.heightmap`) and the unknowns are the element tractions ``q`` (a vector
per element) and the rigid-body displacement increment ``lam = (lam_x,
lam_y)``. With ``K`` the half-space operator (:mod:`core.halfspace`) and
``dq = q - q_prev``, the slip increment of an element is ``s = lam - K dq``
(the sign convention of :mod:`core.solver`), and Coulomb's law reads

* ``|q_i| <= g_i = mu p_i`` (the Coulomb disk), ``q_i = 0`` out of contact;
* stick (``s_i = 0``) where ``|q_i| < g_i``;
* where ``s_i != 0``: ``q_i = g_i s_i/|s_i|`` (friction dissipates, ``q.s >= 0``);
* ``sum q_i dA = Ft`` (both components; ``lam`` their multipliers).

These are the KKT conditions of ``min 1/2 dq^T K dq`` over the disks and the
two force balances (a second-order-cone programme). :func:`solve_increment`
solves them by a semismooth Newton / active-set loop: stick elements are
free, slipping elements are held on the disk at their slip direction ``d``
with the tangential correction ``t d_perp`` free and the Newton curvature
``|s|/g`` on it (the linearisation of ``q = g s/|s|``); the linear system of
each iteration is solved by conjugate gradients projected on the force
balances, with FFT products and the inverse continuous symbol as
preconditioner (:meth:`core.halfspace.HalfSpaceOperator.precondition`), and
warm-started from the previous iteration and step. The zero increment is
checked first (it is the unique solution whenever it is feasible). A return
to an active set already solved (a cycle, from decisions taken on the noise
of inexact linear solves) switches to exact linear solves, then to one change
of kind per iteration; a step that still cannot settle raises an error naming
the KKT condition it cannot meet (:func:`_increment_kernel`).

The traction bound ``g = mu p`` of an element is the pressure of the discrete
normal problem on the same grid (same elements, collocation and Boussinesq
coefficients; :func:`_pressure`), as in CONTACT, rather than a sample of
Hertz's continuous pressure: the increments per period then agree with
CONTACT's to 0.25 % at 40 elements across the contact
(``docs/guide/numerics.md``).

Speed: each step is solved on the rectangle of elements that carry traction
before or after it (:class:`_Window`; the operator is a convolution, so its
block there is a smaller grid's operator), and the whole loop, FFT products
included, is compiled with numba (FFTs through ``rocket-fft``). In a
periodic history a step is warm-started from the same phase of the previous
period (kinds, slip directions, curvatures, correction), which predicts it
better than the step before: a third fewer active-set and CG iterations.
When the increment is mirror-symmetric in y (Ft along the rocking direction
x, an ellipsoid with its axes on the grid, ``nu > 0``: ``q_x`` even and
``q_y`` odd about ``y = 0``, since the solution is unique), every FFT product
is taken at half cost (:func:`core.halfspace.convolve_mirror`) and the
iterates are kept exactly symmetric, which also removes the asymmetric
round-off directions from CG (fewer CG iterations per step); the result equals
the full solver's to its tolerance (``tests/test_solver3d.py``).
Measured figures and iterations per step: ``benchmarks/solver3d.py``.

References
----------
.. [1] J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990.
.. [2] E. A. H. Vollebregt, J. Comput. Phys. 257 (2014) 333-351; I. A. Polonsky,
   L. M. Keer, Wear 231 (1999) 206-219 (CG with FFT products).
.. [3] M. Hintermueller, K. Ito, K. Kunisch, SIAM J. Optim. 13 (2003) 865-888.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy.special import ellipe, ellipk

from ._validate import check_int, check_scalar
from ._jit import jit
from .halfspace import HalfSpaceOperator, convolve, convolve_mirror
from .normal import PatchOperator, solve_normal
from .point_contact import Ellipsoid, hertz_element_means, resolve_body
from .resolution import DEFAULT_DX_POINT, default_dx
from .result import PeriodVerdict, SolveCancelled, SolverError, STICK_MARGIN, central_halfwidth
from .schedule import Schedule, rocking_schedule

__all__ = ["solve_increment", "twist_field", "simulate_point_contact", "solve_point_schedule", "solve_static_3d", "mindlin_state",
           "shakedown_state_3d", "PointContactResult", "StaticResult3D", "RESIDUAL_NAMES", "TOL_3D", "PERIODIC_TOL",
           "DEFAULT_DX_3D", "MAX_GRID_ELEMENTS"]

#: Names of the per-step residuals (see :func:`solve_increment`).
RESIDUAL_NAMES = ("stick_slip", "bound", "slip_direction", "out_of_contact", "load_balance")
#: Default KKT tolerance of the 3D steps (tractions in mu p0, slips in mu Fn/(E* a), loads in mu Fn).
TOL_3D = 1e-8
#: Change of the traction [mu p0] between the ends of two periods below which the state counts as periodic.
PERIODIC_TOL = 1e-6
#: Default element side [a] of point-contact runs. The increment per period of a ratcheting sphere (ft = 0.4,
#: w = 0.6) is 0.1742, 0.1779, 0.1790, 0.1797 at a/5, a/10, a/20, a/40 with the discrete normal bound
#: (benchmarks/solver3d.py): a/20 is 0.4 % below a/40, at an eighth of its cost.
DEFAULT_DX_3D = DEFAULT_DX_POINT  # one place for every body's default grid: core/resolution.py
#: Largest grid (elements) a point-contact run accepts.
MAX_GRID_ELEMENTS = 200_000
#: Largest number of stored full-field values (snapshots at the turning points).
MAX_SNAPSHOT_VALUES = 2e7

# element kinds (internal)
_OUT, _STICK, _SLIP = 0, 1, 2
# active-set iterations that move every violator before moving only the worst ones
_FULL_MOVES = 6
# |s|/g, in units of the self-influence, above which slip directions take the Newton update
_NEWTON_CURV = 1.0
# warm-start each step from the same phase of the previous period (see solve_point_schedule)
_PHASE_WARM = True
# step of the sizes of the windows (see _Window)
_WINDOW_QUANTUM = 1
# inexact Newton: each linear solve reduces its residual to this fraction of the last KKT violation
_CG_FORCING = 1e-2
# active sets remembered for the detection of a cycle (see _increment_kernel)
_CYCLE_MEMORY = 16
# solve increments that are mirror-symmetric in y with half-cost FFT products (see _mirror_symmetric)
_MIRROR = True
# asymmetry [relative to the largest value] below which the inputs count as mirror-symmetric (round-off)
_MIRROR_RTOL = 1e-12


@dataclass
class _WarmStart:
    """Solver state carried from step to step: kinds, slip directions, Newton curvatures, last increment."""

    kind: np.ndarray
    d: np.ndarray
    curv: np.ndarray
    x: np.ndarray

    @classmethod
    def empty(cls, shape):
        return cls(np.zeros(shape, np.int8), np.zeros((2,) + shape), np.zeros(shape), np.zeros((2,) + shape))


@jit
def _symmetrize(v):
    """Make ``v[2, ny, nx]`` exactly mirror-symmetric about its centre row (``v_x`` even, ``v_y`` odd, so 0 on it).

    The products of :func:`~core.halfspace.convolve_mirror` read the upper half
    only, so the lower half's round-off would sit in a direction the operator
    does not see; keeping every iterate symmetric removes it.
    """
    ny, nx = v.shape[1], v.shape[2]
    m = ny // 2
    for j in range(nx):
        v[1, m, j] = 0.0
    for k in range(1, m + 1):
        for j in range(nx):
            v[0, m - k, j] = v[0, m + k, j]
            v[1, m - k, j] = -v[1, m + k, j]


@jit
def _project(pxx, pyy, pxy, minv, v, out, mirror, tv=None):
    """``out = P v``: the orthogonal projection on {x in V, C x = 0}, compiled.

    V holds both components on stick elements and ``d_perp`` on slipping ones:
    ``P_i = [[pxx, pxy], [pxy, pyy]]`` per element (the identity, ``d_perp
    d_perp^T`` or 0). ``C`` holds the constraints: the two force sums, and with
    the twist (``tv``, the rigid slip ``(-(y - y_c), x - x_c)`` of a unit
    rotation about the normal at each element) the moment ``sum tv . x``;
    ``minv`` is the inverse of ``M = C P C^T`` (2 x 2, or 3 x 3 with the
    twist) and ``P C^T M^-1 C P v`` is removed from ``P v``.
    """
    ny, nx = pxx.shape
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(ny):
        for j in range(nx):
            a, b = v[0, i, j], v[1, i, j]
            y0 = pxx[i, j] * a + pxy[i, j] * b
            y1 = pxy[i, j] * a + pyy[i, j] * b
            out[0, i, j] = y0
            out[1, i, j] = y1
            s0 += y0
            s1 += y1
            if tv is not None:
                s2 += tv[0, i, j] * y0 + tv[1, i, j] * y1
    if tv is None:
        m0 = minv[0, 0] * s0 + minv[0, 1] * s1
        m1 = minv[1, 0] * s0 + minv[1, 1] * s1
        for i in range(ny):
            for j in range(nx):
                out[0, i, j] -= pxx[i, j] * m0 + pxy[i, j] * m1
                out[1, i, j] -= pxy[i, j] * m0 + pyy[i, j] * m1
    else:
        m0 = minv[0, 0] * s0 + minv[0, 1] * s1 + minv[0, 2] * s2
        m1 = minv[1, 0] * s0 + minv[1, 1] * s1 + minv[1, 2] * s2
        m2 = minv[2, 0] * s0 + minv[2, 1] * s1 + minv[2, 2] * s2
        for i in range(ny):
            for j in range(nx):
                c0 = m0 + m2 * tv[0, i, j]
                c1 = m1 + m2 * tv[1, i, j]
                out[0, i, j] -= pxx[i, j] * c0 + pxy[i, j] * c1
                out[1, i, j] -= pxy[i, j] * c0 + pyy[i, j] * c1
    if mirror:
        _symmetrize(out)


@jit
def _convolve(q, hxx, hyy, hxy, py, px, mirror):
    """:func:`~core.halfspace.convolve`, or its half-cost form for a field mirror-symmetric in y."""
    if mirror:
        return convolve_mirror(q, hxx, hyy, hxy, py, px)
    return convolve(q, hxx, hyy, hxy, py, px)


@jit
def _precondition(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, mirror, tv=None):
    """``z = P M r``: the inverse continuous symbol on the stick set, ``r/(curv + K_ii)`` on slip corrections."""
    ny, nx = stick.shape
    w = np.empty((2, ny, nx))
    for c in range(2):
        for i in range(ny):
            for j in range(nx):
                w[c, i, j] = r[c, i, j] if stick[i, j] else 0.0
    zs = _convolve(w, spec[5], spec[6], spec[7], spec[8], spec[9], mirror)
    for c in range(2):
        for i in range(ny):
            for j in range(nx):
                if not stick[i, j]:
                    zs[c, i, j] = r[c, i, j] * slip_diag[i, j]
    _project(pxx, pyy, pxy, minv, zs, z, mirror, tv)


@jit
def _pcg_kernel(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x, Kdq, tol, maxiter, mirror, tv=None):
    """Projected preconditioned CG for ``P (K dq + curv x) = 0``, ``dq = dq_fixed + x``, ``x`` in V.

    ``Kdq`` is ``K dq`` of the starting ``x``; both are updated in place.
    ``spec`` holds the spectra of the operator and of its preconditioner
    (:meth:`core.halfspace.HalfSpaceOperator.spectra`). Preconditioner: the
    inverse continuous symbol on the stick set, the inverse diagonal
    ``1/(curv + K_ii)`` on the tangential corrections of slipping elements.
    With ``tv`` (the twist's rigid slip field) the projection also holds the
    moment (:func:`_project`). Returns the iterations and the largest residual component.
    """
    ny, nx = stick.shape
    r = np.empty((2, ny, nx))
    z = np.empty((2, ny, nx))
    Ap = np.empty((2, ny, nx))
    tmp = np.empty((2, ny, nx))
    for c in range(2):
        tmp[c] = -Kdq[c] - curv * x[c]
    _project(pxx, pyy, pxy, minv, tmp, r, mirror, tv)
    _precondition(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, mirror, tv)
    p = z.copy()
    rz = np.sum(r * z)
    rmax = np.abs(r).max()
    its = 0
    # the vector updates in fused loops (no temporaries): a third of a step's time went to them
    # rz == 0: the preconditioned residual vanishes (a zero residual, or one so small that r.z underflows, as with
    # the huge Newton curvatures of elements whose bound is a tiny numerically solved pressure): CG can make no
    # progress and beta = rz_new / rz would divide by zero, so it stops (the caller checks the KKT conditions)
    while its < maxiter and rmax > tol and rz != 0.0:
        its += 1
        Kp = _convolve(p, spec[0], spec[1], spec[2], spec[3], spec[4], mirror)
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    tmp[c, i, j] = Kp[c, i, j] + curv[i, j] * p[c, i, j]
        _project(pxx, pyy, pxy, minv, tmp, Ap, mirror, tv)
        pAp = 0.0
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    pAp += p[c, i, j] * Ap[c, i, j]
        if not pAp > 0.0:
            break
        alpha = rz / pAp
        rmax = 0.0
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    x[c, i, j] += alpha * p[c, i, j]
                    Kdq[c, i, j] += alpha * Kp[c, i, j]
                    r[c, i, j] -= alpha * Ap[c, i, j]
                    rmax = max(rmax, abs(r[c, i, j]))
        _precondition(spec, stick, slip_diag, pxx, pyy, pxy, minv, r, z, mirror, tv)
        rz_new = 0.0
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    rz_new += r[c, i, j] * z[c, i, j]
        if rz_new == 0.0:
            break
        beta = rz_new / rz
        for c in range(2):
            for i in range(ny):
                for j in range(nx):
                    p[c, i, j] = z[c, i, j] + beta * p[c, i, j]
        rz = rz_new
    return its, rmax


@jit
def _inverse3(m00, m01, m02, m11, m12, m22, out):
    """``out`` = the inverse of the symmetric 3 x 3 matrix ``[[m00, m01, m02], [m01, m11, m12], [m02, m12, m22]]``."""
    c00 = m11 * m22 - m12 * m12
    c01 = m02 * m12 - m01 * m22
    c02 = m01 * m12 - m02 * m11
    c11 = m00 * m22 - m02 * m02
    c12 = m01 * m02 - m00 * m12
    c22 = m00 * m11 - m01 * m01
    det = m00 * c00 + m01 * c01 + m02 * c02
    out[0, 0], out[0, 1], out[0, 2] = c00 / det, c01 / det, c02 / det
    out[1, 0], out[1, 1], out[1, 2] = c01 / det, c11 / det, c12 / det
    out[2, 0], out[2, 1], out[2, 2] = c02 / det, c12 / det, c22 / det


@jit
def _signature(kind):
    """A 64-bit FNV-1a hash of the element kinds: equal active sets give equal signatures."""
    h = np.uint64(14695981039346656037)
    prime = np.uint64(1099511628211)
    for i in range(kind.shape[0]):
        for j in range(kind.shape[1]):
            h = (h ^ np.uint64(kind[i, j] + 1)) * prime
    return h


@jit
def _increment_kernel(spec, k_self, g, q_prev, target, dA, kind, d, wcurv, x, tol, maxiter, cg_maxiter, measure,
                      mirror, tv=None):
    """The active-set / semismooth Newton loop of :func:`solve_increment`, compiled.

    Updates ``kind``, ``d`` and ``wcurv`` in place; returns the final traction
    (slipping elements on the disk), the slips (0 where sticking), ``lam``,
    ``K dq``, the stick part of the last correction, the stick mask, the
    iterations, the CG iterations, the status (0 converged, 1 out of
    iterations, 2 a cycle that the last fallback did not break), the fallback
    stage reached and the last violations (bound, slip direction, tangential
    correction, linear residual).

    Cycles. The linear solves are inexact (inexact Newton: CG stops at
    :data:`_CG_FORCING` times the last violation), so near the solution an
    element whose traction is at its bound with a slip close to zero (a weakly
    active element) can be tested against the noise of the linear solve: it
    slips with a slip against its traction of the size of that noise, sticks
    with a traction above its bound, and so on for ever (seen at ft 0.65, w 0.3,
    a/40, step 77: violations 9e-8 against CG residuals of 3e-6). Every active
    set solved is remembered (a hash, :func:`_signature`); coming back to one
    is a cycle, and the loop falls back, one stage per cycle: (1) exact linear
    solves (CG to a tenth of ``tol``), so that every decision is taken on a
    solution accurate to the tolerance; (2) in addition, only the worst
    violator changes its kind per iteration (a least-violation pivoting rule,
    as Murty's for P-matrix LCPs), with the slip directions iterated to
    convergence between changes. A cycle in stage 2 stops with status 2.

    Twist. With ``tv`` (shape ``(2, ny, nx)``: the rigid slip ``(-(y - y_c),
    x - x_c)`` of a unit rotation about the normal at each element) the
    increment has a third rigid unknown, the rotation ``phi`` about the
    normal through ``(x_c, y_c)``: the slip is ``s = lam + phi tv - K dq``,
    and the moment ``sum tv . q dA`` is held at ``target[2]`` (its
    multiplier is ``phi``; ``lam`` is then the translation of the point
    ``(x_c, y_c)``). Returned ``lam`` has three entries, ``phi`` last (0
    without the twist). Without ``tv`` numba compiles the kernel without the
    twist's terms (the ``tv is None`` branches are pruned).
    """
    ny, nx = g.shape
    contact = g > 0.0
    for i in range(ny):
        for j in range(nx):
            if not contact[i, j]:
                kind[i, j] = _OUT
            elif kind[i, j] == _OUT:
                kind[i, j] = _STICK
            mag = math.hypot(q_prev[0, i, j], q_prev[1, i, j])
            # predicted active set: what is above its new bound slips back along its traction
            if contact[i, j] and kind[i, j] == _STICK and mag > g[i, j]:
                kind[i, j] = _SLIP
                d[0, i, j] = q_prev[0, i, j] / mag
                d[1, i, j] = q_prev[1, i, j] / mag
                wcurv[i, j] = 0.0
    pxx = np.empty((ny, nx))
    pyy = np.empty((ny, nx))
    pxy = np.empty((ny, nx))
    base = np.empty((2, ny, nx))
    curv = np.empty((ny, nx))
    slip_diag = np.empty((ny, nx))
    x0 = np.empty((2, ny, nx))
    s = np.zeros((2, ny, nx))
    q = np.empty((2, ny, nx))
    Kdq = np.empty((2, ny, nx))
    stick = np.zeros((ny, nx), np.bool_)
    slip = np.zeros((ny, nx), np.bool_)
    minv = np.zeros((3, 3))  # the 2 x 2 block without the twist
    lam = np.zeros(3)
    cg_total = 0
    worst = np.inf
    over_max = wrong_max = tangent = cg_res = np.inf
    status = 1
    stage = 0
    seen = np.zeros(_CYCLE_MEMORY, np.uint64)
    nseen = 0
    it = 0
    while it < maxiter:
        it += 1
        nstick = 0
        for i in range(ny):
            for j in range(nx):
                if kind[i, j] == _STICK:
                    nstick += 1
        if nstick == 0:  # the force balances need at least one free element
            bi, bj, bg = 0, 0, -1.0
            for i in range(ny):
                for j in range(nx):
                    if contact[i, j] and g[i, j] > bg:
                        bi, bj, bg = i, j, g[i, j]
            kind[bi, bj] = _STICK
            nstick = 1
        if tv is not None:
            if nstick == 1:  # the moment needs a second free element (two positions make M regular)
                bi, bj, bg = -1, -1, -1.0
                for i in range(ny):
                    for j in range(nx):
                        if contact[i, j] and kind[i, j] != _STICK and g[i, j] > bg:
                            bi, bj, bg = i, j, g[i, j]
                if bi >= 0:
                    kind[bi, bj] = _STICK
        # ---- the projector of this active set and the fixed part of the traction
        m00 = m01 = m11 = m02 = m12 = m22 = 0.0
        b0 = b1 = b2 = 0.0
        for i in range(ny):
            for j in range(nx):
                st = kind[i, j] == _STICK
                sl = kind[i, j] == _SLIP
                stick[i, j], slip[i, j] = st, sl
                if sl:
                    e0, e1 = -d[1, i, j], d[0, i, j]  # d_perp
                    pxx[i, j], pyy[i, j], pxy[i, j] = e0 * e0, e1 * e1, e0 * e1
                    base[0, i, j], base[1, i, j] = g[i, j] * d[0, i, j], g[i, j] * d[1, i, j]
                    curv[i, j] = wcurv[i, j]
                else:
                    f = 1.0 if st else 0.0
                    pxx[i, j], pyy[i, j], pxy[i, j] = f, f, 0.0
                    base[0, i, j], base[1, i, j] = f * q_prev[0, i, j], f * q_prev[1, i, j]
                    curv[i, j] = 0.0
                slip_diag[i, j] = 1.0 / (curv[i, j] + k_self)
                m00 += pxx[i, j]
                m11 += pyy[i, j]
                m01 += pxy[i, j]
                b0 += base[0, i, j]
                b1 += base[1, i, j]
                if tv is not None:
                    t0, t1 = tv[0, i, j], tv[1, i, j]
                    m02 += pxx[i, j] * t0 + pxy[i, j] * t1
                    m12 += pxy[i, j] * t0 + pyy[i, j] * t1
                    m22 += t0 * (pxx[i, j] * t0 + pxy[i, j] * t1) + t1 * (pxy[i, j] * t0 + pyy[i, j] * t1)
                    b2 += t0 * base[0, i, j] + t1 * base[1, i, j]
        D0, D1, D2 = target[0] / dA - b0, target[1] / dA - b1, 0.0
        if tv is None:
            det = m00 * m11 - m01 * m01  # > 0: at least one stick element
            minv[0, 0], minv[0, 1], minv[1, 0], minv[1, 1] = m11 / det, -m01 / det, -m01 / det, m00 / det
        else:  # M = C P C^T with the moment's row: regular with two stick elements at different places
            D2 = target[2] / dA - b2
            _inverse3(m00, m01, m02, m11, m12, m22, minv)
        c0 = minv[0, 0] * D0 + minv[0, 1] * D1 + minv[0, 2] * D2
        c1 = minv[1, 0] * D0 + minv[1, 1] * D1 + minv[1, 2] * D2
        c2 = minv[2, 0] * D0 + minv[2, 1] * D1 + minv[2, 2] * D2
        # ---- the linear problem of this active set (warm start projected on its space, plus the particular part)
        _project(pxx, pyy, pxy, minv, x, x0, False, tv)
        for i in range(ny):
            for j in range(nx):
                e0, e1 = c0, c1
                if tv is not None:
                    e0 += c2 * tv[0, i, j]
                    e1 += c2 * tv[1, i, j]
                x0[0, i, j] += pxx[i, j] * e0 + pxy[i, j] * e1
                x0[1, i, j] += pxy[i, j] * e0 + pyy[i, j] * e1
        if mirror:
            _symmetrize(x0)
        Kdq = _convolve(base - q_prev + x0, spec[0], spec[1], spec[2], spec[3], spec[4], mirror)
        cg_tol = 0.1 * tol if stage > 0 else max(0.1 * tol, _CG_FORCING * measure)
        its, cg_res = _pcg_kernel(spec, pxx, pyy, pxy, minv, stick, curv, slip_diag, x0, Kdq, cg_tol, cg_maxiter,
                                  mirror, tv)
        x = x0.copy()
        cg_total += its
        # ---- the multipliers, the traction and the slips
        y0 = y1 = y2 = 0.0
        for i in range(ny):
            for j in range(nx):
                v0 = Kdq[0, i, j] + curv[i, j] * x[0, i, j]
                v1 = Kdq[1, i, j] + curv[i, j] * x[1, i, j]
                w0 = pxx[i, j] * v0 + pxy[i, j] * v1
                w1 = pxy[i, j] * v0 + pyy[i, j] * v1
                y0 += w0
                y1 += w1
                if tv is not None:
                    y2 += tv[0, i, j] * w0 + tv[1, i, j] * w1
        lam[0] = minv[0, 0] * y0 + minv[0, 1] * y1 + minv[0, 2] * y2
        lam[1] = minv[1, 0] * y0 + minv[1, 1] * y1 + minv[1, 2] * y2
        lam[2] = minv[2, 0] * y0 + minv[2, 1] * y1 + minv[2, 2] * y2
        # ---- check: bounds on the stick set, slip direction on the slip set
        over_max = -np.inf
        wrong_max = -np.inf
        tangent = 0.0
        over = np.full((ny, nx), -np.inf)
        wrong = np.full((ny, nx), -np.inf)
        for i in range(ny):
            for j in range(nx):
                for c in range(2):
                    q[c, i, j] = base[c, i, j] + x[c, i, j]
                    rigid = lam[c]
                    if tv is not None:
                        rigid += lam[2] * tv[c, i, j]
                    s[c, i, j] = rigid - Kdq[c, i, j] if contact[i, j] else 0.0
                if stick[i, j]:
                    over[i, j] = math.hypot(q[0, i, j], q[1, i, j]) - g[i, j]
                    over_max = max(over_max, over[i, j])
                elif slip[i, j]:
                    wrong[i, j] = -(d[0, i, j] * s[0, i, j] + d[1, i, j] * s[1, i, j])
                    wrong_max = max(wrong_max, wrong[i, j])
                    t = -d[1, i, j] * x[0, i, j] + d[0, i, j] * x[1, i, j]
                    # off the disk by t; the slip then has the normal component curv t
                    tangent = max(tangent, abs(t * max(1.0, curv[i, j])))
        worst = max(over_max, wrong_max)
        measure = max(worst, tangent)
        if worst <= tol and tangent <= tol and cg_res <= 0.5 * tol:
            status = 0
            break
        if stage == 2 and tangent > tol and worst <= max(tol, tangent):
            worst = -np.inf  # stage 2: converge the slip directions before the next change of kind
        if worst > tol:
            # this active set is about to change: remember it, and detect a return to an earlier one
            sig = _signature(kind)
            if nseen < _CYCLE_MEMORY:
                seen[nseen] = sig
                nseen += 1
            else:
                for k in range(_CYCLE_MEMORY - 1):
                    seen[k] = seen[k + 1]
                seen[_CYCLE_MEMORY - 1] = sig
            level = tol if it <= _FULL_MOVES and stage == 0 else max(tol, 0.5 * worst)
            if stage == 2:
                level = max(tol, (1.0 - 1e-12) * worst)
            for i in range(ny):
                for j in range(nx):
                    if over[i, j] > level:
                        kind[i, j] = _SLIP
                        mag = math.hypot(q[0, i, j], q[1, i, j])
                        mag = mag if mag > 0 else 1.0
                        d[0, i, j], d[1, i, j] = q[0, i, j] / mag, q[1, i, j] / mag
                        wcurv[i, j] = 0.0
                    if wrong[i, j] > level:
                        kind[i, j] = _STICK
                        x[0, i, j] = x[1, i, j] = 0.0
            sig = _signature(kind)
            for k in range(nseen):
                if seen[k] == sig:  # a cycle: next fallback stage, or give up
                    if stage == 2:
                        status = 2
                    stage += 1
                    nseen = 0
                    break
            if status == 2:
                break
        # ---- Newton update of the slip directions and their curvature |s|/g: where the slip dominates (|s|/g
        # above the self-influence) linearise q = g s/|s| about the slip direction (semismooth Newton); elsewhere
        # follow the corrected traction
        for i in range(ny):
            for j in range(nx):
                if slip[i, j] and kind[i, j] == _SLIP:
                    nq = math.hypot(q[0, i, j], q[1, i, j])
                    ns = math.hypot(s[0, i, j], s[1, i, j])
                    cn = ns / g[i, j]
                    if cn > _NEWTON_CURV * k_self:
                        ns = ns if ns > 0 else 1.0
                        d[0, i, j], d[1, i, j] = s[0, i, j] / ns, s[1, i, j] / ns
                    else:
                        nq = nq if nq > 0 else 1.0
                        d[0, i, j], d[1, i, j] = q[0, i, j] / nq, q[1, i, j] / nq
                    wcurv[i, j] = cn
                    x[0, i, j] = x[1, i, j] = 0.0
    # ---- the final traction: slipping elements exactly on the disk; slips where slipping only
    for i in range(ny):
        for j in range(nx):
            if slip[i, j]:
                q[0, i, j], q[1, i, j] = g[i, j] * d[0, i, j], g[i, j] * d[1, i, j]
            if not contact[i, j]:
                q[0, i, j] = q[1, i, j] = 0.0
            if not (slip[i, j] and math.hypot(s[0, i, j], s[1, i, j]) > tol):
                s[0, i, j] = s[1, i, j] = 0.0
            if not stick[i, j]:
                x[0, i, j] = x[1, i, j] = 0.0
    return q, s, lam, Kdq, x, stick, it, cg_total, status, min(stage, 2), over_max, wrong_max, tangent, cg_res


def _mirror(a, sign):
    """Copy the rows above the centre row of ``a[..., ny, nx]`` onto those below, times ``sign``, in place."""
    m = a.shape[-2] // 2
    a[..., :m, :] = sign * a[..., :m:-1, :]


def _mirror_symmetric(g, q_prev, target, warm):
    """Whether an increment is mirror-symmetric in y about the grid's centre row; if so, symmetrise its inputs.

    The bound, the previous traction (``q_x`` even, ``q_y`` odd) and the
    load (no y component) symmetric, to round-off, make the solution
    symmetric too, since it is unique: the Ft-along-x, rocking-along-x
    problem of an ellipsoid with its axes on the grid (the centre row on
    ``y = 0``). Then ``g``, ``q_prev`` (copies, returned) and the warm start
    (in place; a guess only) are made exactly symmetric, so that the solver
    may use :func:`~core.halfspace.convolve_mirror` throughout.

    Returns
    -------
    g, q_prev : ndarray or None
        Symmetrised copies, or None when the increment is not symmetric.
    """
    ny = g.shape[0]
    if not _MIRROR or ny % 2 == 0 or target[1] != 0.0:
        return None, None
    gs = max(float(g.max()), 1e-300)
    qs = max(float(np.abs(q_prev).max()), gs)
    if (np.abs(g - g[::-1]).max() > _MIRROR_RTOL * gs
            or np.abs(q_prev[0] - q_prev[0, ::-1]).max() > _MIRROR_RTOL * qs
            or np.abs(q_prev[1] + q_prev[1, ::-1]).max() > _MIRROR_RTOL * qs):
        return None, None
    g, q_prev = g.copy(), q_prev.copy()
    m = ny // 2
    q_prev[1, m] = 0.0
    warm.d[1, m] = 0.0
    warm.d[0, m] = np.sign(warm.d[0, m])
    warm.x[1, m] = 0.0
    for a, sign in ((g, 1.0), (q_prev[0], 1.0), (q_prev[1], -1.0), (warm.kind, 1), (warm.curv, 1.0),
                    (warm.d[0], 1.0), (warm.d[1], -1.0), (warm.x[0], 1.0), (warm.x[1], -1.0)):
        _mirror(a, sign)
    return g, q_prev


def _failure(status, stage, it, maxiter, cg_maxiter, tol, over, wrong, tangent, cg_res):
    """The message of an increment that did not settle: which KKT condition is not met, by how much, and why."""
    parts = []
    if over > tol:
        parts.append(f"a sticking traction above its bound by {over:.3g} [mu p0]")
    if wrong > tol:
        parts.append(f"a slip against its traction of {wrong:.3g}")
    if tangent > tol:
        parts.append(f"a slipping traction off its disk or a slip not parallel to it by {tangent:.3g}")
    if stage > 0 and cg_res > 0.5 * tol:  # stage 0 stops CG early on purpose (inexact Newton)
        parts.append(f"the linear solve of the last active set reaching only {cg_res:.3g} in {cg_maxiter} CG iterations")
    unmet = "; ".join(parts) or "no single condition above the tolerance in the last iterate"
    stages = ("inexact linear solves", "exact linear solves", "exact linear solves and one change of kind per iteration")
    if status == 2:
        why = (f"the active set cycled even with {stages[2]} (the last fallback): the problem is degenerate to "
               f"the tolerance {tol:g}; a larger tol would accept it")
    else:
        why = f"the active set did not settle in {maxiter} iterations (last stage: {stages[stage]})"
    return f"{why}; unmet: {unmet} (worst violation {max(over, wrong):.3g})"


def twist_field(x_edges, y_edges, centre):
    """The rigid slip ``(-(y - y_c), x - x_c)`` [a] of a unit rotation about the normal through ``centre``.

    At the element centres of the grid ``x_edges``, ``y_edges``: the ``twist``
    argument of :func:`solve_increment` for a body free to turn about the
    normal through ``centre = (x_c, y_c)`` [a] (a point on the line of action
    of the tangential force).

    Returns
    -------
    ndarray, shape (2, ny, nx)
    """
    xc, yc = (float(v) for v in centre)
    x = 0.5 * (np.asarray(x_edges[1:], float) + np.asarray(x_edges[:-1], float))
    y = 0.5 * (np.asarray(y_edges[1:], float) + np.asarray(y_edges[:-1], float))
    out = np.empty((2, y.size, x.size))
    out[0] = -(y - yc)[:, None]
    out[1] = (x - xc)[None, :]
    return out


def _moment_residual(q, twist, target, dA):
    """``|sum twist . q dA - target[2]|`` over the largest arm: the moment balance as a force [mu p0 a^2]."""
    arm = max(float(np.abs(twist).max()), 1e-300)
    moment = float(np.sum(twist * q)) * dA
    return abs(moment - (float(target[2]) if len(target) > 2 else 0.0)) / arm


def solve_increment(op, g, q_prev, target, dA, warm, tol=TOL_3D, maxiter=200, cg_maxiter=500, twist=None):
    """Solve one increment of the 3D tangential problem (see the module docstring).

    Parameters
    ----------
    op : HalfSpaceOperator
        The elastic operator of the grid.
    g : ndarray, shape (ny, nx)
        Traction bounds ``mu p`` [mu p0]; 0 out of contact.
    q_prev : ndarray, shape (2, ny, nx)
        Tractions after the previous step [mu p0].
    target : ndarray, shape (2,) or (3,)
        Required ``sum q dA`` [mu p0 a^2]; with ``twist``, a third entry: the
        required moment ``sum twist . q dA`` [mu p0 a^3] (0 if omitted).
    dA : float
        Element area [a^2].
    warm : _WarmStart
        Kinds, slip directions, curvatures and last increment; updated in place.
    tol : float
        KKT tolerance (tractions [mu p0], slips [displacement unit]).
    maxiter, cg_maxiter : int
        Largest numbers of active-set and CG iterations.
    twist : ndarray, shape (2, ny, nx), optional
        The body is also free to turn about the normal: the rigid slip of a
        unit rotation at each element (:func:`twist_field`, ``(-(y - y_c), x -
        x_c)`` [a]). The increment then has a third rigid unknown, the rotation
        ``phi`` [displacement unit / a], with the slip ``lam + phi twist - K
        dq`` and the moment balance above; ``lam`` is the translation of
        ``(x_c, y_c)``. Default None: no rotation (the two force balances only).

    Returns
    -------
    q : ndarray, shape (2, ny, nx)
        Tractions.
    s : ndarray, shape (2, ny, nx)
        Slip increments (0 where sticking or out of contact).
    lam : ndarray, shape (2,)
        Rigid-body displacement increment.
    info : dict
        ``iterations`` (active set), ``cg_iterations``, ``fallback`` (the
        stage of the cycle fallback reached: 0 none, 1 exact linear solves, 2
        one change of kind per iteration; see :func:`_increment_kernel`),
        ``twist`` (``phi``, 0 without ``twist``) and the residuals of
        :data:`RESIDUAL_NAMES` (``load_balance`` in ``sum q dA`` units; with
        the twist, also the moment's residual over the largest arm).

    Raises
    ------
    RuntimeError
        If the iteration does not settle within ``maxiter``, or cycles in the
        last fallback stage; the message names the KKT condition not met, by
        how much, and the stage.
    """
    # one compiled specialisation: C-contiguous, writeable float64 (int8 kinds) arrays
    g, q_prev = (np.require(a, np.float64, ["C", "W"]) for a in (g, q_prev))
    warm.kind = np.require(warm.kind, np.int8, ["C", "W"])
    warm.d, warm.curv, warm.x = (np.require(a, np.float64, ["C", "W"]) for a in (warm.d, warm.curv, warm.x))
    target = np.asarray(target, dtype=float)
    if twist is not None:
        twist = np.require(twist, np.float64, ["C", "W"])
        if twist.shape != q_prev.shape:
            raise ValueError(f"twist must have the shape {q_prev.shape} of q_prev, got {twist.shape}")
        target = np.concatenate([target[:3], np.zeros(3 - min(target.size, 3))])
    contact = g > 0
    kind, d = warm.kind, warm.d
    kind[~contact] = _OUT
    kind[contact & (kind == _OUT)] = _STICK
    mag_prev = np.hypot(q_prev[0], q_prev[1])
    # ---- the zero increment, if feasible, is the unique solution
    balance = np.abs(q_prev.sum(axis=(1, 2)) * dA - target[:2]).max()
    if twist is not None:
        balance = max(balance, _moment_residual(q_prev, twist, target, dA))
    if (not np.any(q_prev[:, ~contact])) and np.all(mag_prev <= g + tol) and balance <= tol:
        kind[(kind == _SLIP) & (mag_prev < g - tol)] = _STICK
        warm.x[:] = 0.0
        zero = np.zeros_like(q_prev)
        info = dict(iterations=0, cg_iterations=0, stick_slip=0.0, bound=max(float((mag_prev - g).max()), 0.0),
                    slip_direction=0.0, out_of_contact=0.0, load_balance=float(balance))
        info["fallback"] = 0
        info["twist"] = 0.0
        return q_prev.copy(), zero, np.zeros(2), info
    measure = max(float((mag_prev - g).max()), balance)
    # at nu = 0 the y problem decouples and the full products keep q_y exactly 0 (the half-cost ones to round-off)
    tv = twist
    mirror_ok = op.nu > 0
    if twist is not None and mirror_ok:
        # a mirror-symmetric increment has no moment about a point on the centre row (q_x even, q_y odd against
        # twist_x odd, twist_y even): the rotation is 0 by symmetry and the half-cost path drops it; a centre off
        # that row (or a moment required) breaks the symmetry
        ny = g.shape[0]
        ts = max(float(np.abs(twist).max()), 1e-300)
        mirror_ok = (ny % 2 == 1 and target[2] == 0.0
                     and np.abs(twist[0] + twist[0, ::-1]).max() <= _MIRROR_RTOL * ts
                     and np.abs(twist[1] - twist[1, ::-1]).max() <= _MIRROR_RTOL * ts)
    gm, qm = _mirror_symmetric(g, q_prev, target[:2], warm) if mirror_ok else (None, None)
    mirror = gm is not None
    if mirror:
        g, q_prev = gm, qm
        tv = None
    q, s, lam, Kdq, x, stick, it, cg_total, status, stage, over, wrong, tangent, cg_res = _increment_kernel(
        op.spectra(), op.self_influence, g, q_prev, target, float(dA), kind, d, warm.curv, warm.x,
        float(tol), int(maxiter), int(cg_maxiter), float(measure), mirror, tv)
    if status != 0:
        raise RuntimeError(_failure(status, stage, it, maxiter, cg_maxiter, tol, over, wrong, tangent, cg_res))
    if mirror:  # exactly symmetric results (the solver's sums leave round-off in the lower half)
        for a, sign in ((q[0], 1.0), (q[1], -1.0), (s[0], 1.0), (s[1], -1.0), (Kdq[0], 1.0), (Kdq[1], -1.0),
                        (x[0], 1.0), (x[1], -1.0), (stick, True)):
            _mirror(a, sign)
        lam[1] = 0.0
    warm.x = x
    slipping = np.hypot(s[0], s[1]) > 0
    qn = np.hypot(q[0], q[1])
    e = q / np.where(qn > 0, qn, 1.0)
    along = e[0] * s[0] + e[1] * s[1]
    direction = np.where(slipping, np.maximum(np.abs(e[0] * s[1] - e[1] * s[0]), -along), 0.0)
    rigid = lam[:2, None, None] + (lam[2] * tv if tv is not None else 0.0)
    load = float(np.abs(q.sum(axis=(1, 2)) * dA - target[:2]).max())
    if twist is not None:
        load = max(load, _moment_residual(q, twist, target, dA))
    info = dict(
        iterations=it, cg_iterations=cg_total, fallback=int(stage), twist=float(lam[2]),
        stick_slip=float(np.abs(np.where(stick, rigid - Kdq, 0.0)).max()),
        bound=max(float((np.hypot(q[0], q[1]) - g).max()), 0.0),
        slip_direction=float(direction.max()),
        out_of_contact=float(np.abs(q[:, ~contact]).max()) if (~contact).any() else 0.0,
        load_balance=load,
    )
    return q, s, lam[:2].copy(), info


class _Window:
    """Solve each increment on the rectangle of elements that carry traction before or after it.

    The operator is a convolution, so the block of the whole grid's operator on
    a rectangle of elements is the operator of a grid of the rectangle's size,
    wherever the rectangle sits: out of it the tractions are zero before and
    after the step, and slips there are not needed. The FFTs shrink from the
    whole rocking range to the contact's size. Widths are rounded up to a
    multiple of :data:`_WINDOW_QUANTUM` elements so that a few operators serve a run.
    """

    def __init__(self, ny, nx, h, nu, scale):
        self.shape, self.args = (ny, nx), (h, nu, scale)
        self.ops = {}

    def operator(self, shape):
        op = self.ops.get(shape)
        if op is None:
            op = self.ops[shape] = HalfSpaceOperator(*shape, *self.args)
        return op

    @staticmethod
    def _span(used, n):
        idx = np.flatnonzero(used)
        i0, i1 = (int(idx[0]), int(idx[-1]) + 1) if idx.size else (0, 1)
        width = min(n, -(-(i1 - i0) // _WINDOW_QUANTUM) * _WINDOW_QUANTUM)
        lo = min(max(i0 - (width - (i1 - i0)) // 2, 0), n - width)
        return slice(lo, lo + width)

    def solve(self, g, q_prev, target, dA, warm, tol, twist=None):
        used = (g > 0) | (q_prev != 0).any(axis=0)
        win = (self._span(used.any(axis=1), self.shape[0]), self._span(used.any(axis=0), self.shape[1]))
        part = _WarmStart(*(np.ascontiguousarray(a[(Ellipsis,) + win]) for a in (warm.kind, warm.d, warm.curv, warm.x)))
        try:
            q, s, lam, info = solve_increment(self.operator(part.kind.shape), np.ascontiguousarray(g[win]),
                                              np.ascontiguousarray(q_prev[(slice(None),) + win]), target, dA, part, tol,
                                              twist=None if twist is None else twist[(slice(None),) + win])
        finally:
            warm.kind[win], warm.d[(slice(None),) + win], warm.curv[win] = part.kind, part.d, part.curv
        warm.x = np.zeros_like(warm.x)
        warm.x[(slice(None),) + win] = part.x
        q_full, s_full = np.zeros_like(q_prev), np.zeros_like(q_prev)
        q_full[(slice(None),) + win], s_full[(slice(None),) + win] = q, s
        return q_full, s_full, lam, info


def _state_codes(q, s, g, tol):
    """Element states: 0 released, 1 stick, 2 slip forward (+x), 3 slip backward (the codes of core.result)."""
    codes = np.where(g > 0, 1, 0).astype(np.int8)
    slipping = (np.hypot(s[0], s[1]) > tol) & (g > 0)
    codes[slipping & (s[0] >= 0)] = 2
    codes[slipping & (s[0] < 0)] = 3
    return codes


# --------------------------------------------------------------------------
# grids
# --------------------------------------------------------------------------
def _centred_edges(reach, h):
    """Edges of an odd number of elements of side ``h`` centred on 0 (one element at 0) covering ``[-reach, reach]``."""
    half = math.ceil(reach / h - 0.5 - 1e-9) + 1
    return h * (np.arange(2 * half + 2) - half - 0.5)


# Polonsky-Keer iterations: relative change of the load distribution at which the normal solve stops, and its cap
_NORMAL_RTOL = 1e-13
_NORMAL_MAXITER = 2000


def _gap_curvatures(kappa):
    """``(A, B)`` of the gap ``A x^2 + B y^2`` whose Hertz contact has semi-axes 1 (x) and ``kappa`` (y).

    Units: lengths in ``a``, pressure in ``p0``, ``E* = 1`` (the kernel
    ``1/(pi E*)`` of :func:`_normal_kernel`). Johnson eqs 3.57-3.61: with the
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


class _NormalWindow:
    """The discrete normal problem of a Hertz contact on a window of the grid: :func:`core.normal.solve_normal`.

    Piecewise-constant pressures on the grid's square elements, gaps
    collocated at their centres, the Boussinesq influence coefficients
    ``(1/(pi E*)) integral of 1/rho`` over each element (exact,
    :func:`core.halfspace.rectangle_integrals`, in :class:`core.normal.PatchOperator`),
    the total load prescribed, solved by the one normal solver of the package
    (Polonsky-Keer's constrained CG, preconditioned by the inverse continuous
    symbol). This is CONTACT's normal problem (Kalker; Vollebregt): the traction bound
    ``mu p`` of an element is then the pressure that the same discrete
    elasticity gives it, instead of a mean of the continuous Hertz field.
    """

    def __init__(self, half_y, half_x, h):
        self.shape = (2 * half_y + 1, 2 * half_x + 1)
        self.h = h
        self.op = PatchOperator(*self.shape, h, 1.0 / math.pi)

    def apply(self, p):
        return self.op.apply(p)

    def solve(self, gap, load, guess):
        """Pressures >= 0 with ``sum p h^2 = load``, gap + displacement constant where ``p > 0``, >= it elsewhere."""
        try:
            return solve_normal(gap, load, self.op, self.h * self.h, tol=_NORMAL_RTOL, maxiter=_NORMAL_MAXITER,
                                initial=guess).pressure.copy()
        except ValueError as e:
            raise RuntimeError(f"the normal problem did not converge: {e}") from e


_NORMAL_CACHE = {}


def _pressure(x_edges, y_edges, xc, body, scale=1.0, normal="numerical"):
    """The traction bound's pressure on a point-contact grid at centre ``xc`` and load scale ``scale`` [p0].

    With ``normal="numerical"`` (the default) the pressure of the discrete normal
    problem on the grid (:class:`_NormalWindow`), as CONTACT computes it: on
    the sphere at ft 0.6, w 0.3 it moved the increment per period from 1.6 %
    to 0.3 % below CONTACT's at 40 elements across the contact
    (``docs/guide/numerics.md``). The gap is the body's quadratic profile, so
    the pressure is Hertz's up to the discretization; the solve runs on a
    window around the contact and is cached by the centre's offset from its
    nearest element (a translate serves every aligned centre) and the scale.
    With ``normal="exact"``, the element means of Hertz's pressure
    (:func:`core.point_contact.hertz_element_means`).
    """
    if hasattr(body, "grid_pressure"):  # a body that solves its own normal problem (core.heightmap.HeightMap)
        return body.grid_pressure(x_edges, y_edges, xc, scale)
    if normal == "exact":
        return hertz_element_means(x_edges, y_edges, xc, body.kappa, scale)
    h = float(x_edges[1] - x_edges[0])
    xs = 0.5 * (x_edges[1:] + x_edges[:-1])
    i0 = int(np.argmin(np.abs(xs - xc)))
    offset = float(xc - xs[i0])
    half_x = math.ceil(scale / h - 0.5) + 1
    half_y = math.ceil(body.kappa * scale / h - 0.5) + 1
    key = (round(h, 12), round(offset / h, 9), round(scale, 12), body.kappa)
    window = _NORMAL_CACHE.get(key)
    if window is None:
        if len(_NORMAL_CACHE) >= 64:  # sine schedules and load steps: a few offsets and scales per run
            _NORMAL_CACHE.clear()
        solver = _NormalWindow(half_y, half_x, h)
        X = h * (np.arange(-half_x, half_x + 1) - offset / h)[None, :]
        Y = h * np.arange(-half_y, half_y + 1)[:, None]
        A, B = _gap_curvatures(body.kappa)
        guess = scale * np.sqrt(np.clip(1.0 - (X / scale) ** 2 - (Y / (body.kappa * scale)) ** 2, 0.0, None))
        p = solver.solve(A * X * X + B * Y * Y, body.total_load * scale**3, guess + 1e-3 * (guess > 0))
        p = 0.5 * (p + p[::-1])  # exactly mirror-symmetric in y (the window is centred on y = 0)
        if offset == 0.0:
            p = 0.5 * (p + p[:, ::-1])
        window = _NORMAL_CACHE[key] = p
    out = np.zeros((y_edges.size - 1, x_edges.size - 1))
    ny = out.shape[0]
    c = ny // 2
    rows = slice(max(c - half_y, 0), min(c + half_y + 1, ny))
    cols = slice(max(i0 - half_x, 0), min(i0 + half_x + 1, out.shape[1]))
    out[rows, cols] = window[rows.start - (c - half_y):rows.stop - (c - half_y),
                             cols.start - (i0 - half_x):cols.stop - (i0 - half_x)]
    total = float(out.sum()) * h * h
    if total > 0:  # the load that fell off the grid's edge (none where the grid covers the contact)
        out *= body.total_load * scale**3 / total
    return out


def _normal_mode(normal, body):
    """``"exact"`` or ``"numerical"`` for ``normal`` (``"auto"``: numerical, the discrete bound on the grid)."""
    if normal not in ("auto", "exact", "numerical"):
        raise ValueError(f"normal must be one of ('auto', 'exact', 'numerical'), got {normal!r:.60}")
    if normal == "exact" and not isinstance(body, Ellipsoid):
        raise ValueError(f"normal='exact' needs a closed-form pressure (a sphere or an ellipsoid); "
                         f"{type(body).__name__} has none: use normal='numerical' or 'auto'")
    return "exact" if normal == "exact" else "numerical"


def _grid(body, reach_x, scale, h):
    xe = _centred_edges(reach_x, h)
    ye = _centred_edges(body.kappa * scale, h)
    if (xe.size - 1) * (ye.size - 1) > MAX_GRID_ELEMENTS:
        raise ValueError(f"dx = {h:g} needs {(xe.size - 1) * (ye.size - 1)} elements (> {MAX_GRID_ELEMENTS}): "
                         "use a larger dx")
    return xe, ye


# --------------------------------------------------------------------------
# results
# --------------------------------------------------------------------------
def _freeze(obj):
    for name, value in vars(obj).items():
        if isinstance(value, np.ndarray):
            value.setflags(write=False)
        elif isinstance(value, dict):
            for v in value.values():
                if isinstance(v, np.ndarray):
                    v.setflags(write=False)


class _GridFields:
    """Grid helpers shared by the point-contact results (``x_edges``, ``y_edges``; arrays frozen on creation)."""

    def __post_init__(self):
        _freeze(self)

    @property
    def x(self):
        """Element centres along x [a]."""
        return 0.5 * (self.x_edges[1:] + self.x_edges[:-1])

    @property
    def y(self):
        """Element centres along y [a]."""
        return 0.5 * (self.y_edges[1:] + self.y_edges[:-1])

    @property
    def cut_row(self) -> int:
        """Index of the grid row on ``y = 0``."""
        return (self.y_edges.size - 1) // 2


@dataclass(frozen=True, eq=False)
class PointContactResult(PeriodVerdict, _GridFields):
    """The transient of a rocking point contact: per step, per period, and its verdict.

    Normalised units: lengths in ``a`` (semi-axis along x), pressure in ``p0``,
    tractions in ``mu p0``, loads in ``mu Fn``, displacements in
    ``mu Fn/(E* a)``, dissipation in ``(mu Fn)^2/(E* a)``. Arrays are read-only.

    Attributes
    ----------
    body : Ellipsoid
        The body (``body.kappa = b/a``).
    nu, angle : float
        Substrate's Poisson ratio; angle of ``Ft`` to the rocking direction [rad].
    x_edges, y_edges : ndarray
        Grid edges; the grid has a row centred on ``y = 0`` (the cut).
    xc, P, Q, period : ndarray, shape (steps,)
        The schedule (``P`` in nominal ``Fn``, ``Q = Ft/(mu Fn0)``).
    displacement : ndarray, shape (steps, 2)
        Rigid-body displacement (x, y) after each step.
    traction_cut : ndarray, shape (steps, 2, nx)
        Traction (both components) on the row ``y = 0`` after each step.
    state_cut : ndarray of int8, shape (steps, nx)
        Element states on that row (0 released, 1 stick, 2 slip +x, 3 slip -x).
    snapshot_steps : ndarray of int
        Steps whose full fields are stored: the end of the loading, the turning
        points, the last step.
    traction_snapshots : ndarray, shape (k, 2, ny, nx)
    state_snapshots : ndarray of int8, shape (k, ny, nx)
    lowest_pressure : ndarray, shape (ny, nx)
        Lowest element pressure of the last period [p0].
    dissipation, iterations, cg_iterations : ndarray, shape (steps,)
        Frictional work (>= 0), active-set and CG iterations of each step.
    residuals : dict of ndarray
        Per-step residuals named in :data:`RESIDUAL_NAMES`.
    periodic_from : int or None
        Period from which the state repeated to the tolerance, later periods copied.
    rotation : ndarray, shape (steps,), or None
        A body free to turn about the normal (``body.twist_centre``, the cone):
        its rigid rotation about the normal after each step [mu Fn/(E* a^2)
        rad]; ``displacement`` is then that of the twist centre. None otherwise.
    """

    increment_unit = "mu Fn/(E* a)"  # of increment_per_period, D_inf and the verdict's reason

    body: Ellipsoid
    nu: float
    angle: float
    x_edges: np.ndarray
    y_edges: np.ndarray
    xc: np.ndarray
    P: np.ndarray
    Q: np.ndarray
    period: np.ndarray
    displacement: np.ndarray
    traction_cut: np.ndarray
    state_cut: np.ndarray
    snapshot_steps: np.ndarray
    traction_snapshots: np.ndarray
    state_snapshots: np.ndarray
    lowest_pressure: np.ndarray
    dissipation: np.ndarray
    iterations: np.ndarray
    cg_iterations: np.ndarray
    residuals: dict
    periodic_from: int | None
    params: dict = field(default_factory=dict)
    tol: float = TOL_3D
    shakedown_rtol: float = 1e-3
    runtime: float = 0.0
    rotation: np.ndarray | None = None

    @property
    def dx(self) -> float:
        return float(self.x_edges[1] - self.x_edges[0])

    @property
    def periods(self) -> int:
        return int(self.period.max()) + 1 if self.period.size else 0

    def pressure(self, step):
        """Element pressure at ``step`` [p0], shape (ny, nx): the traction bound in mu p0 (:func:`_pressure`)."""
        return _pressure(self.x_edges, self.y_edges, float(self.xc[step]), self.body, float(self.P[step]) ** (1.0 / 3.0),
                         self.params.get("normal", "numerical"))

    @property
    def final_traction(self):
        """Traction after the last step, shape (2, ny, nx)."""
        return self.traction_snapshots[-1]

    @property
    def final_state(self):
        return self.state_snapshots[-1]

    # ---- per period --------------------------------------------------------
    @cached_property
    def increment_per_period(self):
        """Rigid-body displacement increment of each period along Ft [mu Fn/(E* a)]."""
        ends = np.append(np.flatnonzero(np.diff(self.period) != 0), self.period.size - 1)
        along = self.displacement @ np.array([math.cos(self.angle), math.sin(self.angle)])
        disp = along[ends]
        return np.diff(disp) if self.period[0] < 0 else np.diff(np.concatenate([[0.0], disp]))

    @cached_property
    def twist_per_period(self):
        """Rigid rotation about the normal in each period [mu Fn/(E* a^2) rad] (a body free to turn; else None)."""
        if self.rotation is None:
            return None
        ends = np.append(np.flatnonzero(np.diff(self.period) != 0), self.period.size - 1)
        rot = self.rotation[ends]
        return np.diff(rot) if self.period[0] < 0 else np.diff(np.concatenate([[0.0], rot]))

    # ---- the final state ---------------------------------------------------
    @cached_property
    def stick_halfwidth(self) -> float:
        """Half-extent along x [a] of the central zone on ``y = 0`` whose final ``|q|`` stays below mu p_min."""
        q = self.traction_cut[-1]
        bound = self.lowest_pressure[self.cut_row]
        mask = (bound > 0) & (np.hypot(q[0], q[1]) < bound - STICK_MARGIN)
        return central_halfwidth(mask, self.x_edges)

    @property
    def max_residual(self) -> float:
        return max(float(v.max()) for v in self.residuals.values()) if self.xc.size else 0.0

    @property
    def max_kkt_residual(self) -> float:
        """Worst KKT residual over all steps (the name the cylinder's result and the sweep tables use)."""
        return self.max_residual

    def summary(self) -> dict:
        inc = self.increment_per_period
        return {"dx": self.dx, **self.params, "body": self.body.name, "ratio": self.body.ratio, "regime": self.regime,
                "regime_reason": self.regime_reason, "stick_halfwidth": self.stick_halfwidth,
                "increment_last_period": float(inc[-1]) if inc.size else float("nan"),
                "D_inf": self.D_inf, "D_inf_error": self.D_inf_error, "decay_ratio": self.decay_ratio,
                "periods_to_decide": self.periods_to_decide,
                "shakedown_period": self.shakedown_period, "max_kkt_residual": self.max_kkt_residual,
                "elements": int((self.x_edges.size - 1) * (self.y_edges.size - 1)), "steps": int(self.xc.size),
                "periodic_from": self.periodic_from, "max_iterations": int(self.iterations.max()),
                "max_cg_iterations": int(self.cg_iterations.max()), "max_residual": self.max_residual,
                "runtime_s": self.runtime,
                **({} if self.rotation is None else {"twist_last_period": float(self.twist_per_period[-1])})}


# --------------------------------------------------------------------------
# a run over a schedule
# --------------------------------------------------------------------------
def _turning_points(schedule):
    xc, per = schedule.xc, schedule.period
    steps = []
    for k in range(1, xc.size - 1):
        if per[k] >= 0 and ((xc[k] > xc[k - 1] and xc[k] >= xc[k + 1]) or (xc[k] < xc[k - 1] and xc[k] <= xc[k + 1])):
            steps.append(k)
    return steps


def solve_point_schedule(schedule, dx, body, *, nu=0.5, angle=0.0, tol=TOL_3D, detect_periodic=True,
                         periodic_tol=PERIODIC_TOL, shakedown_rtol=1e-3, params=None, time_budget=None, cancel=None,
                         progress=None, chunk=50, normal="auto"):
    """Solve a loading :class:`~core.schedule.Schedule` for a point contact, step by step.

    Parameters
    ----------
    schedule : Schedule
        Steps (``xc`` [a], ``P`` [nominal Fn], ``Q = Ft/(mu Fn0)``, period).
    dx : float
        Element side [a], in [0.005, 0.5].
    body : Ellipsoid or core.heightmap.HeightMap
        The body (a height map runs on its own grid: ``dx`` its spacing).
    nu : float
        Substrate's Poisson ratio, in [0, 0.5].
    angle : float
        Angle of Ft to the rocking direction x [rad].
    tol : float
        KKT tolerance of every step.
    detect_periodic : bool
        When the traction at the end of a period repeats the previous one to
        ``periodic_tol`` [mu p0], copy the remaining periods (same steps every
        period only; a shaken-down period repeats exactly, a ratcheting one
        converges geometrically to its periodic state).
    shakedown_rtol : float
        Relative size of the last increment for the shakedown verdict.
    params : dict, optional
        Recorded on the result.
    time_budget, cancel, progress, chunk :
        As in :func:`core.solver.solve_schedule`.
    normal : {"auto", "exact", "numerical"}
        The traction bound's pressure: ``"numerical"`` (and ``"auto"``, the
        default) the discrete normal problem on the run's grid, solved by
        :func:`core.normal.solve_normal` (CONTACT's bound); ``"exact"`` the
        element means of Hertz's closed form. A height map has no closed form:
        ``"exact"`` is refused for it.

    Returns
    -------
    PointContactResult

    Raises
    ------
    SolverError
        If a step does not settle (names the step, ``xc`` and the residual).
    SolveCancelled
        On request or when the time budget ran out.
    """
    if not isinstance(schedule, Schedule):
        raise ValueError(f"schedule must be a core.Schedule, got {type(schedule).__name__}")
    if not (isinstance(body, Ellipsoid) or hasattr(body, "grid_pressure")):
        raise ValueError(f"body must be a core.Ellipsoid or a core.heightmap.HeightMap, got {type(body).__name__}")
    dx = check_scalar("dx", dx, 0.005, 0.5)
    nu = check_scalar("nu", nu, 0.0, 0.5)
    angle = check_scalar("angle", angle, -math.pi, math.pi)
    tol = check_scalar("tol", tol, 1e-13, 1e-4)
    periodic_tol = check_scalar("periodic_tol", periodic_tol, 0.0, 1e-2)
    chunk = check_int("chunk", chunk, 1, 10**7)
    normal = _normal_mode(normal, body)
    params = dict(params or {}, normal=normal)
    t0 = time.perf_counter()
    scales = np.cbrt(schedule.P)
    if hasattr(body, "run_grid"):  # a height map: its own grid
        xe, ye = body.run_grid(float(np.max(np.abs(schedule.xc))), float(scales.max()), dx)
    else:
        xe, ye = _grid(body, float(np.max(np.abs(schedule.xc) + scales)), float(scales.max()), dx)
    ny, nx = ye.size - 1, xe.size - 1
    window = _Window(ny, nx, dx, nu, body.kernel_scale)
    centre = getattr(body, "twist_centre", None)  # a body free to turn about the normal (core.cone.Cone)
    twist = None if centre is None else twist_field(xe, ye, centre)
    turned = 0.0
    dA = dx * dx
    direction = np.array([math.cos(angle), math.sin(angle)])
    steps = len(schedule)
    rot = np.zeros(steps) if twist is not None else None
    turning = set(_turning_points(schedule))
    load_end = int(np.flatnonzero(schedule.period < 0)[-1]) if (schedule.period < 0).any() else -1
    snap_all = sorted(turning | {load_end, steps - 1} - {-1})
    if len(snap_all) * 3 * ny * nx > MAX_SNAPSHOT_VALUES:  # keep the last period's turning points only
        last = set(np.flatnonzero(schedule.period == schedule.period[-1]).tolist())
        snap_all = sorted((turning & last) | {load_end, steps - 1} - {-1})
    snap_index = {k: i for i, k in enumerate(snap_all)}
    row = ny // 2
    disp = np.zeros((steps, 2))
    tcut = np.zeros((steps, 2, nx))
    scut = np.zeros((steps, nx), np.int8)
    tsnap = np.zeros((len(snap_all), 2, ny, nx))
    ssnap = np.zeros((len(snap_all), ny, nx), np.int8)
    diss = np.zeros(steps)
    iters = np.zeros(steps, np.int64)
    cg = np.zeros(steps, np.int64)
    res = {name: np.zeros(steps) for name in RESIDUAL_NAMES}
    pressure_cache = {}
    warm = _WarmStart.empty((ny, nx))
    q = np.zeros((2, ny, nx))
    periodic = bool(detect_periodic) and schedule.is_periodic()
    # warm starts by phase: the state of a step one period earlier (same pressure, same load)
    period_steps = int(np.count_nonzero(schedule.period == 0)) if _PHASE_WARM and schedule.is_periodic() else 0
    phase_warm = {}
    period_start_q = None
    periodic_from = None
    pmin = {}
    total = 0.0 * direction
    budget_end = None if time_budget is None else t0 + float(time_budget)
    k = 0
    while k < steps:
        key = (float(schedule.xc[k]), float(scales[k]))
        g = pressure_cache.get(key)
        if g is None:
            g = pressure_cache[key] = _pressure(xe, ye, key[0], body, key[1], normal)
        per = int(schedule.period[k])
        pmin[per] = g if per not in pmin else np.minimum(pmin[per], g)
        target = schedule.Q[k] * body.total_load * direction
        if k - period_steps in phase_warm:  # the same phase one period earlier predicts this step best
            warm = phase_warm.pop(k - period_steps)
        try:
            q_new, s, lam, info = window.solve(g, q, target, dA, warm, tol, twist)
        except RuntimeError as e:
            raise SolverError(k, schedule.xc[k], float("inf"), str(e)) from e
        worst = max(info[name] for name in RESIDUAL_NAMES)
        if not worst <= 10.0 * tol:
            raise SolverError(k, schedule.xc[k], worst, "residual above tolerance")
        diss[k] = float(np.vdot(q_new, s)) * dA / body.total_load
        if period_steps and per >= 0:
            phase_warm[k] = _WarmStart(warm.kind.copy(), warm.d.copy(), warm.curv.copy(), warm.x.copy())
        q = q_new
        total = total + lam
        disp[k] = total
        if rot is not None:
            turned += info["twist"]
            rot[k] = turned
        codes = _state_codes(q, s, g, tol)
        tcut[k], scut[k] = q[:, row], codes[row]
        iters[k], cg[k] = info["iterations"], info["cg_iterations"]
        for name in RESIDUAL_NAMES:
            res[name][k] = info[name]
        if k in snap_index:
            tsnap[snap_index[k]], ssnap[snap_index[k]] = q, codes
        k += 1
        # ---- periodic detection at the end of each period
        if k < steps and schedule.period[k] != schedule.period[k - 1] and per >= 0 and periodic:
            if period_start_q is not None and np.abs(q - period_start_q).max() <= periodic_tol:
                periodic_from = per
                break
            period_start_q = q.copy()
        if k % chunk == 0 and k < steps:
            if cancel is not None and cancel():
                raise SolveCancelled(f"solve cancelled after {k} of {steps} steps")
            if budget_end is not None and time.perf_counter() > budget_end:
                raise SolveCancelled(f"solve stopped after {time_budget:g} s (its time budget) at step {k} of {steps}")
            if progress is not None:
                progress(k / steps)
    if k < steps:  # copy the repeating period
        block = np.flatnonzero(schedule.period == periodic_from)
        m, start = block.size, block[0]
        before = disp[start - 1]
        inc = disp[block[-1]] - before
        rest = np.arange(k, steps)
        src = start + (rest - k) % m
        rep = 1 + (rest - k) // m
        disp[rest] = disp[src] + rep[:, None] * inc
        if rot is not None:
            rot[rest] = rot[src] + rep * (rot[block[-1]] - rot[start - 1])
        for arr in (tcut, scut, diss):
            arr[rest] = arr[src]
        for name in RESIDUAL_NAMES:
            res[name][rest] = res[name][src]
        for kk in snap_all:
            if kk >= k:
                tsnap[snap_index[kk]] = tsnap[snap_index[src[kk - k]]] if src[kk - k] in snap_index else q
                ssnap[snap_index[kk]] = ssnap[snap_index[src[kk - k]]] if src[kk - k] in snap_index else ssnap[0]
    if progress is not None:
        progress(1.0)
    last_period = int(schedule.period[-1]) if periodic_from is None else periodic_from
    return PointContactResult(
        body=body, nu=nu, angle=angle, x_edges=xe, y_edges=ye, xc=np.array(schedule.xc), P=np.array(schedule.P),
        Q=np.array(schedule.Q), period=np.array(schedule.period), displacement=disp, traction_cut=tcut,
        state_cut=scut, snapshot_steps=np.array(snap_all, dtype=np.int64), traction_snapshots=tsnap,
        state_snapshots=ssnap, lowest_pressure=pmin[last_period], dissipation=diss, iterations=iters,
        cg_iterations=cg, residuals=res, periodic_from=periodic_from, params=params, tol=tol,
        shakedown_rtol=shakedown_rtol, runtime=time.perf_counter() - t0, rotation=rot)


def simulate_point_contact(ft, w, periods=10, dx=None, dW=None, *, body="sphere", ratio=None, angle=0.0, nu=0.5,
                           shape="triangle", load_steps=1, tol=None, detect_periodic=True, periodic_tol=PERIODIC_TOL,
                           shakedown_rtol=1e-3, time_budget=None, cancel=None, progress=None, normal="auto"):
    """Simulate a rocking sphere or ellipsoid in normalised units: loading at ``xc = 0``, then ``periods`` periods.

    Parameters
    ----------
    ft : float
        ``Ft / (mu Fn)`` in [0, 1).
    w : float
        Rocking amplitude ``W / a`` in [0, 1) (``a`` the semi-axis along x).
    periods : int
        Rocking periods, in [1, 10000].
    dx : float, optional
        Element side over ``a``, in [0.005, 0.5]; default: the body's grid,
        :func:`core.resolution.default_dx` (:data:`DEFAULT_DX_3D` = 1/20: 40
        elements across the contact; the increment per period is 0.4 % below
        a/40's there, ``benchmarks/solver3d.py``).
    dW : float, optional
        Rocking step over ``a``; defaults to ``dx``.
    body : {"sphere", "ellipsoid"} or Ellipsoid
        The body; ``"ellipsoid"`` takes ``ratio = Ry/Rx`` (x: the rocking direction).
    ratio : float, optional
        ``Ry / Rx`` of the ellipsoid, in [0.05, 20].
    angle : float
        Angle of Ft to the rocking direction [rad], in [-pi, pi].
    nu : float
        Substrate's Poisson ratio under a rigid body, in [0, 0.5] (default 0.5: beta = 0).
    shape, load_steps :
        As in :func:`core.schedule.rocking_schedule`.
    tol : float, optional
        KKT tolerance of every step; default :data:`TOL_3D`.
    detect_periodic, periodic_tol, shakedown_rtol, time_budget, cancel, progress, normal :
        As in :func:`solve_point_schedule`.

    Returns
    -------
    PointContactResult
        With ``increment_per_period`` [mu Fn/(E* a)], ``regime``, ``stick_halfwidth`` [a].

    Examples
    --------
    >>> import core
    >>> r = core.simulate_cycles(0.2, 0.3, periods=6, dx=0.2, body="sphere")
    >>> r.regime
    'shakedown'
    """
    if isinstance(body, str) and body not in ("sphere", "ellipsoid"):  # another registered point body, e.g. "cone"
        from .registry import REGISTRY, make_body
        if body in REGISTRY and REGISTRY[body].kind == "point":
            body = make_body(body)
    if hasattr(body, "grid_pressure"):  # a height map, a cone: its own grid
        if ratio is not None:
            raise ValueError(f"ratio is the ellipsoid's, not a {type(body).__name__}'s: got ratio={ratio!r}")
    else:
        body = resolve_body(body, ratio)
    tol = TOL_3D if tol is None else tol
    dx = check_scalar("dx", default_dx(body) if dx is None else dx, 0.005, 0.5)
    dW = dx if dW is None else check_scalar("dW", dW, 1e-4, 1.0)
    schedule = rocking_schedule(ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps)
    params = dict(ft=float(ft), w=float(w), periods=int(periods), dx=dx, dW=dW, body=body.name,
                  ratio=getattr(body, "ratio", None), angle=float(angle), nu=float(nu), shape=shape,
                  load_steps=int(load_steps))
    return solve_point_schedule(schedule, dx, body, nu=nu, angle=angle, tol=tol, detect_periodic=detect_periodic,
                                periodic_tol=periodic_tol, shakedown_rtol=shakedown_rtol, params=params, time_budget=time_budget,
                                cancel=cancel, progress=progress, normal=normal)


# --------------------------------------------------------------------------
# static references: Mindlin and the shaken-down state
# --------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class StaticResult3D(_GridFields):
    """A static partial-slip solution on a point-contact grid (read-only arrays).

    Attributes
    ----------
    x_edges, y_edges : ndarray
    bound : ndarray, shape (ny, nx)
        Traction bound [mu p0].
    traction : ndarray, shape (2, ny, nx)
        Traction [mu p0].
    state : ndarray of int8
        0 out of contact, 1 stick (below the bound), 2 at the bound.
    displacement : ndarray, shape (2,)
        Rigid-body displacement [mu Fn/(E* a)].
    residuals : dict
    """

    x_edges: np.ndarray
    y_edges: np.ndarray
    bound: np.ndarray
    traction: np.ndarray
    state: np.ndarray
    displacement: np.ndarray
    residuals: dict

    @property
    def stick_halfwidth(self) -> float:
        """Half-extent along x [a] of the central stick zone on ``y = 0``."""
        return central_halfwidth(self.state[self.cut_row] == 1, self.x_edges)

    @property
    def stick_halfwidth_y(self) -> float:
        """Half-extent along y [a] of the central stick zone on ``x = 0``."""
        return central_halfwidth(self.state[:, (self.x_edges.size - 1) // 2] == 1, self.y_edges)


def solve_static_3d(bound, ft, x_edges, y_edges, body, *, nu=0.5, angle=0.0, tol=TOL_3D):
    """Static partial slip under a traction bound, loaded from zero in one step.

    With ``bound = mu p`` it is Mindlin's problem; with ``mu p_min`` the
    shaken-down state of a rocking contact.

    Parameters
    ----------
    bound : ndarray, shape (ny, nx)
        Traction bound [mu p0], >= 0.
    ft : float
        ``Ft / (mu Fn)``, below what the bound carries.
    x_edges, y_edges : ndarray
        The grid (square elements).
    body : Ellipsoid
    nu, angle, tol :
        As in :func:`solve_point_schedule`.

    Returns
    -------
    StaticResult3D
    """
    h = float(x_edges[1] - x_edges[0])
    dA = h * h
    carried = float(bound.sum()) * dA / body.total_load
    ft = check_scalar("ft", ft, 0.0, carried, hi_closed=False)
    op = HalfSpaceOperator(y_edges.size - 1, x_edges.size - 1, h, nu, body.kernel_scale)
    warm = _WarmStart.empty(bound.shape)
    target = ft * body.total_load * np.array([math.cos(angle), math.sin(angle)])
    q, s, lam, info = solve_increment(op, bound, np.zeros((2,) + bound.shape), target, dA, warm, tol)
    mag = np.hypot(q[0], q[1])
    state = np.where(bound > 0, np.where(mag < bound - STICK_MARGIN, 1, 2), 0).astype(np.int8)
    return StaticResult3D(x_edges, y_edges, bound, q, state, lam,
                          {name: info[name] for name in RESIDUAL_NAMES})


def mindlin_state(ft, dx=0.05, body="sphere", *, ratio=None, nu=0.5, angle=0.0, tol=TOL_3D):
    """Mindlin's partial slip of a point contact loaded from rest to ``ft`` (numerical, on the grid).

    Mindlin's solution (exact for ``nu = 0``) has ``c/a = (1 - ft)^(1/3)``; for
    ``nu > 0`` the x-y coupling adds a small ``q_y`` and a slightly
    non-circular stick zone, which this solution contains.

    Returns
    -------
    StaticResult3D
    """
    body = resolve_body(body, ratio)
    dx = check_scalar("dx", dx, 0.005, 0.5)
    xe, ye = _grid(body, 1.0, 1.0, dx)
    return solve_static_3d(_pressure(xe, ye, 0.0, body), ft, xe, ye, body, nu=nu, angle=angle, tol=tol)


def shakedown_state_3d(ft, w, dx=0.05, body="sphere", *, ratio=None, nu=0.5, angle=0.0, tol=TOL_3D):
    """The shaken-down state of a rocking point contact, computed directly as one static problem.

    The bound is ``mu p_min``, the lowest pressure of a period (that of the
    farther turning point); below the exact limit
    (:func:`core.point_contact.ft_limit_point`) the transient's end state
    equals it (``tests/test_solver3d.py``).

    Returns
    -------
    StaticResult3D
    """
    body = resolve_body(body, ratio)
    dx = check_scalar("dx", dx, 0.005, 0.5)
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    xe, ye = _grid(body, 1.0 + w, 1.0, dx)
    pmin = np.minimum(_pressure(xe, ye, -w, body), _pressure(xe, ye, w, body))
    return solve_static_3d(pmin, ft, xe, ye, body, nu=nu, angle=angle, tol=tol)
