"""The matrix-free per-step solver: active set with preconditioned conjugate gradients and FFT products.

It solves the same KKT conditions of one increment as the dense solver of
:mod:`core.dense` (see its docstring for the signs): with ``K`` the elastic
operator, ``dq = q_n - q_{n-1}`` and ``lam`` the rigid-body displacement
increment, the slip increment is ``s = lam - K dq`` and

* ``|q_i| <= g_i = mu p_i``, ``q_i = 0`` out of contact;
* stick (``s_i = 0``) where ``|q_i| < g_i``;
* where ``s_i != 0``, ``q_i = g_i sign(s_i)``;
* ``sum q_i dx = Q`` (load balance, ``lam`` its multiplier).

but never forms a matrix. Each step:

1. the zero increment is tried first: whenever it is feasible it is the unique
   solution (most steps of a shaken-down period);
2. otherwise a primal-dual active-set loop (a semismooth Newton method,
   Hintermueller, Ito and Kunisch 2003), warm-started from the previous step's
   sets, fixes ``dq`` on the elements at a bound or released, and solves the
   stick set ``F`` for ``dq_F`` and ``lam``:
   ``K_FF dq_F + K_F,fixed dq_fixed = lam 1``, ``sum dq_F = D``. That is the
   minimum of ``1/2 dq^T K dq`` on the plane ``sum dq_F = D``, solved by
   projected preconditioned conjugate gradients (Gould, Hribar and Nocedal
   2001): the residual is projected with ``z = M r - M 1 (1^T M r)/(1^T M 1)``,
   ``M`` the inverse of the kernel's continuous symbol
   (:meth:`core.operators.FFTOperator.precondition`), so every iterate keeps
   the load balance and CG needs a number of iterations nearly independent of
   the grid. CG stops when the displacement on the stick set is constant to
   within the tolerance; ``lam`` is that constant.

Products with ``K`` and ``M`` are real FFTs of the zero-padded circulant
embedding, restricted to the window of elements in contact now or loaded
before (the only ones where ``dq`` can be non-zero or a slip is needed), so a
step costs O(w log w) for a contact ``w`` elements wide.

Every step reports named residuals (:class:`StepResiduals`) and its active-set
and CG iterations; :class:`FFTSolver` (``solver="fft"`` in
:data:`core.engine.STEP_SOLVERS`) carries the state between steps and its
march fills the same per-step arrays as the dense march of :mod:`core.dense`.

Units: lengths in ``a``, tractions in ``mu p0``, loads in ``mu P``,
displacements in ``mu P / E*``.

References
----------
.. [1] M. Hintermueller, K. Ito, K. Kunisch, "The primal-dual active set
   strategy as a semismooth Newton method", SIAM J. Optim. 13 (2003) 865-888.
.. [2] N. I. M. Gould, M. E. Hribar, J. Nocedal, "On the solution of equality
   constrained quadratic programming problems arising in optimization",
   SIAM J. Sci. Comput. 23 (2001) 1376-1395 (projected CG).
.. [3] I. A. Polonsky, L. M. Keer, "A numerical method for solving rough contact
   problems based on the multi-level multi-summation and conjugate gradient
   techniques", Wear 231 (1999) 206-219.
.. [4] E. A. H. Vollebregt, J. Comput. Phys. 257 (2014) 333 (FFT-preconditioned CG).
.. [5] R. Wetter, Physical Mesomechanics 18 (2015) (the rocking contact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .dense import RESIDUALS, StepReport, Trajectory
from .operators import FFTOperator, circulant_product, fft_size
from .result import read_only

__all__ = ["StepResiduals", "solve_increment_fft", "FFTSolver"]

# active-set kinds of an element, and the iterations moving every violator at once: as in the dense solver
from ._pdas import FREE as _FREE, LOWER as _LOWER, OUT as _OUT, PDAS_FULL_STEPS as _PDAS_FULL_STEPS, UPPER as _UPPER  # noqa: E402
# CG stops when the stick-set displacement is constant to this fraction of the KKT tolerance: tight
# enough that tractions repeat to the tolerance at the ends of a periodic state (periodic detection)
_CG_TOL_FRACTION = 0.001
# restarts of CG from its iterate when the recomputed residual misses the tolerance
_CG_RESTARTS = 3


@dataclass(frozen=True)
class StepResiduals:
    """Named residuals of the KKT conditions of one increment (all >= 0).

    Attributes
    ----------
    stick_slip : float
        Largest ``|s_i|`` on sticking elements (``|q_i| < g_i``) [mu P/E*].
    bound : float
        Largest ``|q_i| - g_i`` [mu p0].
    slip_direction : float
        Largest slip against the traction at a bound, ``max(0, -s_i sign(q_i))`` [mu P/E*].
    out_of_contact : float
        Largest ``|q_i|`` out of contact [mu p0].
    load_balance : float
        ``|sum q_i dx - Q|`` [mu P], in the solver's scaling ``|sum q_i - target| dx``.
    """

    stick_slip: float
    bound: float
    slip_direction: float
    out_of_contact: float
    load_balance: float

    @property
    def worst(self) -> float:
        """The largest of the five (the step's KKT residual)."""
        return max(self.stick_slip, self.bound, self.slip_direction, self.out_of_contact, self.load_balance)


class _Window:
    """FFT products with ``K`` and ``M`` on a window of ``m`` contiguous elements."""

    __slots__ = ("m", "N", "spec", "pre", "products")

    def __init__(self, op: FFTOperator, m: int):
        self.m = m
        self.N = fft_size(m)
        self.spec = op.spectrum(self.N)
        self.pre = op.inverse_symbol(self.N)
        self.products = 0

    def K(self, v):
        self.products += 1
        return circulant_product(v, self.spec, self.N)

    def M(self, v):
        self.products += 1
        return circulant_product(v, self.pre, self.N)


def _project(win, r, f, fb, Mf, c):
    """Projected preconditioned residual ``z = M r - M 1 (1^T M r) / (1^T M 1)`` on ``F``, and ``r . z``.

    ``z`` ignores any constant part of ``r``, which is removed first (its mean
    on ``F``): ``r`` tends to ``lam 1``, and without the shift ``r . z`` would
    be lost to cancellation long before the tolerance.
    """
    rs = (r - r[fb].mean()) * f
    z = win.M(rs) * f
    z -= z.sum() / c * Mf
    return z, rs @ z


def _stick_solve(win, dq, f, D, tol, maxit):
    """Projected PCG for ``dq`` on the stick set (mask ``f``): ``(K dq)_F = lam 1``, ``sum dq_F = D``.

    ``dq`` holds the prescribed increments off ``F`` and the initial guess on
    ``F``; it is updated in place. Returns ``(lam, u, cg_iterations)`` with
    ``u = K dq`` recomputed from the final ``dq`` (not the CG recurrence).
    """
    Mf = win.M(f) * f
    c = Mf.sum()
    # the initial guess, moved onto the load-balance plane along M 1
    dq += (D - dq[f > 0].sum()) / c * Mf
    fb = f > 0
    cg = 0
    u = win.K(dq)
    for _ in range(_CG_RESTARTS + 1):
        r = u * f
        rF = r[fb]
        if rF.max() - rF.min() <= 2.0 * _CG_TOL_FRACTION * tol:
            break
        z, rz = _project(win, r, f, fb, Mf, c)
        p = -z
        while cg < maxit:
            if rz <= 0.0:
                break
            Ap = win.K(p) * f
            pAp = p @ Ap
            if not pAp > 0.0:
                break
            alpha = rz / pAp
            dq += alpha * p
            r += alpha * Ap
            cg += 1
            rF = r[fb]
            if rF.max() - rF.min() <= 2.0 * _CG_TOL_FRACTION * tol:
                break
            z, rz_new = _project(win, r, f, fb, Mf, c)
            p *= rz_new / rz
            p -= z
            rz = rz_new
        u = win.K(dq)  # the true displacement, free of the recurrence's drift
    uF = u[fb]
    return 0.5 * (uF.max() + uF.min()), u, cg


def _residuals(q, g, slip, kind, total, target, dx):
    contact = g > 0
    out = np.abs(q[~contact]).max(initial=0.0)
    bound = max(float((np.abs(q) - g)[contact].max(initial=0.0)), 0.0)
    free = kind == _FREE
    stick = float(np.abs(slip[free]).max(initial=0.0))
    fixed = (kind == _UPPER) | (kind == _LOWER)
    direction = float(np.maximum(-slip[fixed] * np.sign(q[fixed]), 0.0).max(initial=0.0))
    return StepResiduals(stick, bound, direction, float(out), abs(total - target) * dx)


def solve_increment_fft(op, g, q_prev, target, dx, kind, tol=1e-10, maxiter=None, guess=None, maxcg=None):
    """Solve one increment without a matrix (see the module docstring).

    Parameters
    ----------
    op : FFTOperator
        The elastic operator of the grid.
    g : (n,) float array
        Traction bounds ``mu p`` of this step [mu p0]; 0 out of contact.
    q_prev : (n,) float array
        Tractions after the previous step [mu p0].
    target : float
        Required ``sum q_i`` (the load over ``dx``) [mu p0].
    dx : float
        Element width [a].
    kind : (n,) int8 array
        Active-set guess per element (0 out, 1 stick, 2 upper bound, 3 lower
        bound), warm start from the previous step; updated in place.
    tol : float
        KKT tolerance.
    maxiter : int, optional
        Largest number of active-set iterations (default ``50 + 2 n``).
    guess : (n,) float array, optional
        Initial guess of the increment on the stick set (e.g. the previous step's).
    maxcg : int, optional
        Largest number of CG iterations per stick-set solve (default ``n + 50``).

    Returns
    -------
    q, dq, slip : ndarray
        Tractions, increments and slip increments (``lam - K dq`` at a bound, 0 elsewhere).
    codes : ndarray of int8
        Element states 0-3 (released, stick, slip forward, slip backward).
    lam : float
        Rigid-body displacement increment [mu P/E*].
    info : dict
        ``iterations`` (active set), ``cg_iterations``, ``products`` (FFT products),
        ``residuals`` (:class:`StepResiduals`), ``residual`` (the worst) and ``ok``.
    """
    n = g.size
    maxiter = 50 + 2 * n if maxiter is None else maxiter
    maxcg = n + 50 if maxcg is None else maxcg
    kind[g <= 0] = _OUT
    kind[(g > 0) & (kind == _OUT)] = _FREE
    q_prev = np.asarray(q_prev, dtype=float)
    total_prev = q_prev.sum()
    # ---- the zero increment, if feasible, is the unique solution
    contact = kind != _OUT
    if (abs(total_prev - target) * dx <= tol and not np.any(q_prev[~contact])
            and np.all(np.abs(q_prev[contact]) <= g[contact] + tol)):
        kind[contact & (kind != _FREE) & (np.abs(q_prev) < g - tol)] = _FREE
        codes = contact.astype(np.int8)
        zero = np.zeros(n)
        res = _residuals(q_prev, g, zero, np.where(contact, _FREE, _OUT), total_prev, target, dx)
        return (q_prev.copy(), zero, zero.copy(), codes, 0.0,
                dict(iterations=0, cg_iterations=0, products=0, residuals=res, residual=res.worst, ok=True))
    # ---- the window: elements in contact now or loaded before
    live = np.flatnonzero(contact | (q_prev != 0.0))
    lo, hi = int(live[0]), int(live[-1]) + 1
    win = _Window(op, hi - lo)
    gw, qp, kw = g[lo:hi], q_prev[lo:hi], kind[lo:hi]  # kw is a view: kind updates in place
    dq = np.zeros(hi - lo) if guess is None else np.array(guess[lo:hi], dtype=float)
    slip = np.zeros(hi - lo)
    lam, it, cg, res, ok, tightened = 0.0, 0, 0, None, False, False
    cg_tol = tol
    while it < maxiter:
        it += 1
        # ---- prescribed increments off the stick set
        dq = np.where(kw == _OUT, -qp, np.where(kw == _UPPER, gw - qp, np.where(kw == _LOWER, -gw - qp, dq)))
        free = kw == _FREE
        if not free.any():
            inside = np.flatnonzero(kw != _OUT)
            kw[inside[np.argmax(gw[inside])]] = _FREE
            continue
        D = target - total_prev - dq[~free].sum()
        lam, u, c = _stick_solve(win, dq, free.astype(float), D, cg_tol, maxcg)
        cg += c
        q = qp + dq
        slip = np.where(free | (kw == _OUT), 0.0, lam - u)
        # ---- violators: bounds on the stick set, slip direction on the fixed set
        up_bad = free & (np.abs(q) - gw > tol)
        back_bad = ((kw == _UPPER) & (slip < -tol)) | ((kw == _LOWER) & (slip > tol))
        if up_bad.any() or back_bad.any():
            if it <= _PDAS_FULL_STEPS:
                kw[up_bad] = np.where(q[up_bad] > 0, _UPPER, _LOWER)
                kw[back_bad] = _FREE
            elif up_bad.any():
                i = int(np.argmax(np.where(up_bad, np.abs(q) - gw, -np.inf)))
                kw[i] = _UPPER if q[i] > 0 else _LOWER
            else:
                i = int(np.argmax(np.where(back_bad, np.abs(slip), -np.inf)))
                kw[i] = _FREE
            continue
        stick = np.where(free, lam - u, 0.0)
        res = _residuals(q, gw, stick + slip, kw, q.sum() + q_prev[:lo].sum() + q_prev[hi:].sum(), target, dx)
        if res.worst <= tol:
            ok = True
            break
        if tightened:  # the sets are settled but CG cannot reach the tolerance
            break
        cg_tol, tightened = 0.1 * tol, True
    qfull = q_prev.copy()
    dqfull = np.zeros(n)
    slipfull = np.zeros(n)
    if res is not None:
        qfull[lo:hi] = q
        dqfull[lo:hi] = dq
        slipfull[lo:hi] = slip
    codes = np.where(kind == _OUT, 0, 1).astype(np.int8)
    codes[(kind == _UPPER) & (slipfull > tol)] = 2
    codes[(kind == _LOWER) & (slipfull < -tol)] = 3
    return (qfull, dqfull, slipfull, codes, float(lam),
            dict(iterations=it, cg_iterations=cg, products=win.products, residuals=res,
                 residual=math.inf if res is None else res.worst, ok=ok))


class FFTSolver:
    """The matrix-free per-step solver behind ``solver="fft"`` (:data:`core.engine.STEP_SOLVERS`).

    The interface of :class:`core.dense.DenseSolver`: it carries the tractions,
    the active-set guess and the rigid-body displacement from step to step;
    :meth:`step` solves one increment, :meth:`march` a run of steps into a
    :class:`~core.dense.Trajectory` (with the CG iterations of every step in
    ``cg_iterations``), detecting a periodic steady state as the dense march
    does: a period that ends where the previous one ended repeats for ever.

    Parameters
    ----------
    operator : FFTOperator or DenseOperator
        Elastic operator of :mod:`core.operators` (only its circulant
        embedding is used: ``spectrum`` and ``inverse_symbol``; no matrix is formed).
    element_size : float
        Element width ``dx`` [a] (the element measure of the load balance).
    tol : float
        KKT tolerance of every step.
    maxiter : int
        Active-set iterations allowed per step.
    warm_increment : bool
        Start each step's CG from the previous step's increment (default) rather than from zero.
    """

    name = "fft"
    #: The operator form :func:`core.solver.solve_schedule` builds for this solver.
    form = "fft"

    def __init__(self, operator, *, element_size, tol, maxiter, warm_increment=True):
        if not (hasattr(operator, "spectrum") and hasattr(operator, "inverse_symbol")):
            raise ValueError(f"solver='fft' needs a 1D Toeplitz operator of core.operators, "
                             f"got {type(operator).__name__}")
        self.op = operator
        self.n = int(operator.size)
        self.element_size = float(element_size)
        self.tol = float(tol)
        self.maxiter = int(maxiter)
        self.warm_increment = bool(warm_increment)
        self.q_prev = np.zeros(self.n)
        self.dq_prev = np.zeros(self.n)
        self.kind = np.zeros(self.n, np.int8)
        self.q_block_end = np.zeros(self.n)
        self.total = 0.0
        self._residuals = np.zeros(len(RESIDUALS))

    @property
    def traction(self) -> np.ndarray:
        """Tractions after the last step (the start of the next one)."""
        return self.q_prev

    @property
    def residuals(self) -> dict:
        """The named residuals of the last step (inf if it found no feasible active set)."""
        return dict(zip(RESIDUALS, map(float, self._residuals)))

    def _solve(self, bound, target):
        """Solve one increment from the current state; advance to it if it converged."""
        out = solve_increment_fft(self.op, np.ascontiguousarray(bound, dtype=float), self.q_prev, float(target),
                                  self.element_size, self.kind, self.tol, self.maxiter,
                                  guess=self.dq_prev if self.warm_increment else None)
        q, dq, _, _, lam, info = out
        res = info["residuals"]
        self._residuals[:] = math.inf if res is None else [getattr(res, name) for name in RESIDUALS]
        if info["ok"]:
            self.q_prev = q
            self.total += lam
            if info["iterations"] > 0:
                self.dq_prev = dq
        return out

    def step(self, bound, target) -> StepReport:
        """Solve one increment from the current tractions and advance to it (see :meth:`core.dense.DenseSolver.step`)."""
        q, _, _, codes, lam, info = self._solve(bound, target)
        return StepReport(traction=read_only(q.copy()), state=read_only(codes), displacement=lam,
                          iterations=int(info["iterations"]), residuals=self.residuals, converged=bool(info["ok"]),
                          cg_iterations=int(info["cg_iterations"]))

    def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out: Trajectory):
        """Solve steps ``k0:k1`` in order (``bounds[k - k0]``: bound of step ``k``; target ``Q[k] load_scale``).

        Returns
        -------
        (reached, periodic_from, failed) : tuple of int
            As :meth:`core.dense.DenseSolver.march`.
        """
        tol, dx = self.tol, self.element_size
        steps = Q.size
        for k in range(k0, k1):
            q, _, slip, codes, _, info = self._solve(bounds[k - k0], Q[k] * load_scale)
            if not info["ok"]:
                return k, -1, k
            out.traction[k] = q
            out.state[k] = codes
            out.displacement[k] = self.total
            out.dissipation[k] = (q @ slip) * dx
            out.iterations[k] = info["iterations"]
            out.cg_iterations[k] = info["cg_iterations"]
            out.kkt_residual[k] = info["residual"]
            np.maximum(out.worst, self._residuals, out=out.worst)
            if k + 1 < steps and period[k + 1] != period[k]:
                # end of a block: a period that ends where the previous one ended repeats for ever
                if detect_periodic and period[k] >= 0 and np.all(np.abs(q - self.q_block_end) <= tol):
                    return k + 1, int(period[k]), -1
                self.q_block_end = q.copy()
        return k1, -1, -1
