"""The matrix-free per-step solver: active set with preconditioned conjugate gradients and FFT products.

It solves the same KKT conditions of one increment as the dense solver of
:mod:`core.solvers.dense` (see its docstring for the signs): with ``K`` the elastic
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
   (:meth:`core.elastic.operators.FFTOperator.precondition`), so every iterate keeps
   the load balance and CG needs a number of iterations nearly independent of
   the grid. CG stops when the displacement on the stick set is constant to
   within the tolerance; ``lam`` is that constant.

Products with ``K`` and ``M`` are real FFTs of the zero-padded circulant
embedding of size ``N >= 2 n`` (one per solver), on the window of elements in
contact now or loaded before (the only ones where ``dq`` can be non-zero or a
slip is needed), so a product costs O(n log n). The whole loop, FFTs
included, is compiled (:mod:`core.solvers._pcg`, ``np.fft`` in numba by the
``rocket-fft`` extension): no Python runs between two steps.

Every step reports named residuals (:class:`StepResiduals`) and its active-set
and CG iterations; :class:`FFTSolver` (``solver="fft"`` in
:data:`core.march.engine.STEP_SOLVERS`) carries the state between steps and its
march fills the same per-step arrays as the dense march of :mod:`core.solvers.dense`.

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

from . import _pcg
from .dense import RESIDUALS, DenseSolver, StepReport, Trajectory
from ..elastic.operators import fft_size
from ..records.result import read_only

__all__ = ["StepResiduals", "solve_increment_fft", "FFTSolver"]


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


def _embedding(op):
    """The circulant size ``N`` of an operator's grid and the spectra of ``K`` and of the preconditioner on it."""
    if not (hasattr(op, "spectrum") and hasattr(op, "inverse_symbol")):
        raise ValueError(f"solver='fft' needs a 1D Toeplitz operator of core.elastic.operators, got {type(op).__name__}")
    if not _pcg.HAVE_FFT:
        raise ImportError("solver='fft' needs the rocket-fft package (numpy.fft inside numba): "
                          "pip install rocket-fft")
    N = fft_size(int(op.size))
    return N, np.ascontiguousarray(op.spectrum(N), dtype=float), np.ascontiguousarray(op.inverse_symbol(N),
                                                                                      dtype=float)


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
    g = np.ascontiguousarray(g, dtype=float)
    n = g.size
    maxiter = 50 + 2 * n if maxiter is None else maxiter
    maxcg = n + 50 if maxcg is None else maxcg
    N, spec, pre = _embedding(op)
    guess = np.zeros(n) if guess is None else np.ascontiguousarray(guess, dtype=float)
    q, dq, slip, codes = np.empty(n), np.empty(n), np.empty(n), np.empty(n, np.int8)
    res, counters = np.empty(len(RESIDUALS)), np.zeros(3, np.int64)
    lam, ok = _pcg.solve_step(spec, pre, N, g, np.ascontiguousarray(q_prev, dtype=float), float(target), float(dx),
                              kind, float(tol), int(maxiter), int(maxcg), guess, q, dq, slip, codes, res, counters)
    residuals = None if not np.all(np.isfinite(res)) else StepResiduals(*map(float, res))
    return (q, dq, slip, codes, float(lam),
            dict(iterations=int(counters[_pcg.ITERATIONS]), cg_iterations=int(counters[_pcg.CG]),
                 products=int(counters[_pcg.PRODUCTS]), residuals=residuals,
                 residual=math.inf if residuals is None else residuals.worst, ok=bool(ok)))


class FFTSolver:
    """The matrix-free per-step solver behind ``solver="fft"`` (:data:`core.march.engine.STEP_SOLVERS`).

    The interface of :class:`core.solvers.dense.DenseSolver`: it carries the tractions,
    the active-set guess and the rigid-body displacement from step to step;
    :meth:`step` solves one increment, :meth:`march` a run of steps into a
    :class:`~core.solvers.dense.Trajectory` (with the CG iterations of every step in
    ``cg_iterations``), detecting a periodic steady state as the dense march
    does: a period that ends where the previous one ended repeats for ever.

    Parameters
    ----------
    operator : FFTOperator or DenseOperator
        Elastic operator of :mod:`core.elastic.operators` (only its circulant
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
    #: Its main compiled kernel (:data:`core.base._jit.KERNELS`): a run says once that it compiles it if it is not cached.
    kernels = ("core.solvers._pcg.march", "core.solvers._pcg.solve_step")
    #: The operator form :func:`core.api.solver.solve_schedule` builds for this solver.
    form = "fft"
    #: The grid shape it solves (:func:`core.march.engine.grid_shape`).
    grid = "line"
    default_maxiter = staticmethod(DenseSolver.default_maxiter)
    trajectory = staticmethod(DenseSolver.trajectory)

    def __init__(self, operator, *, element_size, tol, maxiter, warm_increment=True):
        self._N, self._spec, self._pre = _embedding(operator)
        self.op = operator
        self.n = n = int(operator.size)
        self.element_size = float(element_size)
        self.tol = float(tol)
        self.maxiter = int(maxiter)
        self.maxcg = n + 50
        self.warm_increment = bool(warm_increment)
        self.q_prev = np.zeros(n)
        self.dq_prev = np.zeros(n)
        self.kind = np.zeros(n, np.int8)
        self.q_block_end = np.zeros(n)
        self._total = np.zeros(1)
        self._residuals = np.zeros(len(RESIDUALS))
        self._counters = np.zeros(3, np.int64)
        self._scratch = (np.empty(n), np.empty(n), np.empty(n), np.empty(n, np.int8))  # q, dq, slip, codes

    @property
    def total(self) -> float:
        """Rigid-body displacement so far [mu P/E*]."""
        return float(self._total[0])

    @property
    def periodic_tol(self) -> float:
        """Traction tolerance [mu p0] of the periodic detection (:mod:`core.march.engine`): the KKT tolerance, as the
        dense solver's (the compiled march compares with it)."""
        return self.tol

    @property
    def traction(self) -> np.ndarray:
        """Tractions after the last step (the start of the next one)."""
        return self.q_prev

    @property
    def residuals(self) -> dict:
        """The named residuals of the last step (inf if it found no feasible active set)."""
        return dict(zip(RESIDUALS, map(float, self._residuals)))

    def step(self, bound, target) -> StepReport:
        """Solve one increment from the current tractions and advance to it (see :meth:`core.solvers.dense.DenseSolver.step`)."""
        q, dq, slip, codes = self._scratch
        # a writable copy, as DenseSolver.step: one compiled signature of the kernel, not one more for read-only bounds
        lam, ok = _pcg.solve_step(self._spec, self._pre, self._N, np.array(bound, dtype=float, order="C"),
                                  self.q_prev, float(target), self.element_size, self.kind, self.tol, self.maxiter,
                                  self.maxcg, self.dq_prev, q, dq, slip, codes, self._residuals, self._counters)
        iterations = int(self._counters[_pcg.ITERATIONS])
        if ok:
            self.q_prev[:] = q
            self._total[0] += lam
            if self.warm_increment and iterations > 0:
                self.dq_prev[:] = dq
        return StepReport(traction=read_only(q.copy()), state=read_only(codes.copy()), displacement=float(lam),
                          iterations=iterations, residuals=self.residuals, converged=bool(ok),
                          cg_iterations=int(self._counters[_pcg.CG]))

    def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out: Trajectory):
        """Solve steps ``k0:k1`` in order (``bounds[k - k0]``: bound of step ``k``; target ``Q[k] load_scale``).

        Returns
        -------
        (reached, periodic_from, failed) : tuple of int
            As :meth:`core.solvers.dense.DenseSolver.march`.
        """
        q, dq, slip, codes = self._scratch
        reached, periodic_from, failed = _pcg.march(
            self._spec, self._pre, self._N, bounds, Q, period, float(load_scale), self.element_size, self.tol,
            self.maxiter, self.maxcg, self.warm_increment, bool(detect_periodic), int(k0), int(k1), self.kind,
            self.q_prev, self.dq_prev, self.q_block_end, self._total, self._residuals, self._counters, q, dq, slip,
            codes, out.traction, out.state, out.displacement, out.dissipation, out.iterations, out.cg_iterations,
            out.kkt_residual, out.worst)
        return int(reached), int(periodic_from), int(failed)
