"""The dense per-step solver: one increment of the tangential contact problem, by a primal-dual active set.

At each step ``n`` the unknowns are the element tractions ``q_n`` and the
rigid-body displacement increment ``lam``. With ``K`` the influence matrix of
the elastic operator and ``dq = q_n - q_{n-1}``, the slip increment of an
element in contact is ``s = lam - K dq`` and Coulomb's law (Wetter 2015,
section 2; Kalker's incremental problem) reads

* ``|q_i| <= g_i = mu p_i``, ``q_i = 0`` out of contact (``g_i = 0``);
* stick (``s_i = 0``) where ``|q_i| < g_i``;
* where ``s_i != 0``, ``q_i = g_i sign(s_i)``: friction opposes slip, so the
  dissipation ``sum q_i s_i dx`` is never negative;
* ``sum q_i dx = (pi/2) Q`` (load balance, eq 5: ``P = pi a p0 / 2``).

These are the KKT conditions of the strictly convex quadratic programme
``min 1/2 dq^T K dq`` over the box and the load equality, ``lam`` its
multiplier. :class:`DenseSolver` solves it exactly by a primal-dual active set
iteration [2] warm-started from the previous step, keeping the inverse of ``K``
on the stick set up to date by rank-one updates (the numba kernels are in
``core.solvers._pdas``); it stops on the KKT residuals, not on an iteration count, and
reports failure. Most steps of a shaken-down period are settled by the zero
increment, which is checked first (it is the unique solution whenever it is
feasible).

On a Toeplitz ``K`` (a uniform grid and a translation-invariant kernel:
the operators of :mod:`core.elastic.operators`) the block of ``K`` on the contact
interval is the same matrix wherever the contact lies, so its inverse
``A_L`` is computed once per contact width ``L``; with ``H`` the ``h``
elements of the interval that are not sticking, the stick solve is
``K_FF^-1 = A_FF - A_FH (A_HH)^-1 A_HF`` (block elimination), ``O(L h + h^3)``
per iteration instead of ``O(m^2)`` updates of the stick-set inverse. The
rank-one updated inverse takes over while ``h`` is large (wide slip zones,
:func:`core.solvers._pdas.hmax`) and for any other operator. Both solve the same
equations: the iterations are the same and the increments equal to round-off
(``tests/test_engine.py``).

It needs the dense ``n x n`` matrix: the solver of choice for line contacts
up to a few thousand elements.

References
----------
.. [1] J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*,
   Kluwer 1990 (the incremental tangential problem; program CONTACT).
.. [2] M. Hintermueller, K. Ito, K. Kunisch, "The primal-dual active set
   strategy as a semismooth Newton method", SIAM J. Optim. 13 (2003) 865-888.
.. [3] R. Wetter, Physical Mesomechanics 18 (2015).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _pcg, _pdas
from ..elastic.operators import fft_size
from ..records.result import read_only
from ..base.states import RESIDUAL_NAMES

__all__ = ["DenseSolver", "StepReport", "Trajectory", "RESIDUALS"]

#: Names of the KKT residuals every per-step solver reports (:data:`core.base.states.RESIDUAL_NAMES`, in the order
#: of the compiled kernels' residual arrays).
RESIDUALS = RESIDUAL_NAMES
if _pdas.RESIDUALS != RESIDUAL_NAMES:  # pragma: no cover - the kernels index their residuals in this order
    raise ImportError("core.solvers._pdas.RESIDUALS must equal core.base.states.RESIDUAL_NAMES")


@dataclass(frozen=True)
class StepReport:
    """What one increment gave: the tractions, the rigid-body increment and how well the KKT conditions hold.

    Attributes
    ----------
    traction : ndarray
        Element tractions after the step [mu p0] (read-only).
    state : ndarray of int8
        Element states (:class:`core.base.states.State`) (read-only).
    displacement : float
        Rigid-body displacement increment ``lam`` [mu P/E*].
    iterations : int
        Active-set iterations (0: the zero increment solved the step).
    residuals : dict
        The named KKT residuals (:data:`RESIDUALS`).
    converged : bool
        Whether every residual is within the tolerance.
    cg_iterations : int
        Conjugate-gradient iterations (the matrix-free solver; 0 for the dense one, which solves directly).
    """

    traction: np.ndarray
    state: np.ndarray
    displacement: float
    iterations: int
    residuals: dict
    converged: bool
    cg_iterations: int = 0

    @property
    def kkt_residual(self) -> float:
        """The worst of the named residuals."""
        return max(self.residuals.values())


class Trajectory:
    """The per-step outputs of a march (all (steps,) or (steps, n) arrays), and the worst named residuals.

    ``cg_iterations`` stays 0 for a solver without conjugate gradients (the dense one).
    """

    def __init__(self, steps: int, n: int):
        self.traction = np.empty((steps, n))
        self.state = np.empty((steps, n), dtype=np.int8)
        self.displacement = np.empty(steps)
        self.dissipation = np.empty(steps)
        self.iterations = np.empty(steps, dtype=np.int64)
        self.cg_iterations = np.zeros(steps, dtype=np.int64)
        self.kkt_residual = np.empty(steps)
        self.worst = np.zeros(len(RESIDUALS))

    def residuals(self) -> dict:
        """Worst of each named residual so far."""
        return dict(zip(RESIDUALS, map(float, self.worst)))

    def result_fields(self) -> dict:
        """The per-step fields of a :class:`core.records.result.CycleResult` on a line."""
        return dict(traction=self.traction, state=self.state, displacement=self.displacement,
                    dissipation=self.dissipation, iterations=self.iterations, cg_iterations=self.cg_iterations,
                    kkt_residual=self.kkt_residual)

    def copied(self):
        """The per-step arrays a repeated period copies as they are (the displacement advances, iterations are 0)."""
        return [self.traction, self.state, self.dissipation, self.kkt_residual]

    def advancing(self):
        """The per-step arrays a repeated period advances by its increment: the displacement."""
        return [self.displacement]


class DenseSolver:
    """The primal-dual active-set solver on the dense influence matrix (see the module docstring).

    Parameters
    ----------
    operator : object
        Elastic operator with ``matrix()`` (the dense ``(n, n)`` influence matrix).
    element_size : float
        Element measure of the load balance (``dx`` [a] in 1D).
    tol : float
        KKT tolerance of every step.
    maxiter : int
        Active-set iterations allowed per step.
    """

    name = "dense"
    #: Its main compiled kernel (:data:`core.base._jit.KERNELS`): a run says once that it compiles it if it is not cached.
    kernels = ("core.solvers._pdas.march", "core.solvers._pdas.solve_step")
    #: The operator form :func:`core.api.solver.solve_schedule` builds for this solver (it needs the matrix).
    form = "dense"
    #: The grid shape it solves (:func:`core.march.engine.grid_shape`).
    grid = "line"

    @staticmethod
    def default_maxiter(n):
        """Active-set iterations per step: ``50 + 2 n`` (an active set changes one element at least per iteration)."""
        return 50 + 2 * n

    @staticmethod
    def trajectory(history, shape):
        """The :class:`Trajectory` of ``history`` on a grid of ``shape = (n,)``."""
        return Trajectory(len(history), shape[0])

    def __init__(self, operator, *, element_size, tol, maxiter):
        self.K = np.ascontiguousarray(operator.matrix(), dtype=float)
        if self.K.ndim != 2 or self.K.shape[0] != self.K.shape[1]:
            raise ValueError(f"the operator's matrix must be square, got shape {self.K.shape}")
        self.n = self.K.shape[0]
        self.element_size = float(element_size)
        self.tol = float(tol)
        self.maxiter = int(maxiter)
        # a Toeplitz operator (uniform grid, translation-invariant kernel) gives its column: then the stick
        # solves use inverses of K on the contact interval (see core.solvers._pdas), which do not change as it rolls
        column = getattr(operator, "column", None)
        if column is not None:
            column = np.asarray(column, dtype=float)
            if column.shape != (self.n,) or not (np.array_equal(self.K[0], column)
                                                  and np.array_equal(self.K[:, 0], column)):
                column = None
        spectrum, N = None, 0
        if column is not None and hasattr(operator, "spectrum") and _pcg.HAVE_FFT:
            N = fft_size(self.n)
            spectrum = operator.spectrum(N)
        self.state = _pdas.new_state(self.n, column, spectrum=spectrum, N=N)

    def _reserve(self, bounds, rows):
        """Room in the state for the widest contact of the first ``rows`` rows of ``bounds``."""
        if self.state.kfull.size:
            self.state = _pdas.with_capacity(self.state, _pdas.max_span(bounds, rows))

    @property
    def traction(self) -> np.ndarray:
        """Tractions after the last step (the start of the next one)."""
        return self.state.q_prev

    @property
    def periodic_tol(self) -> float:
        """Traction tolerance [mu p0] of the periodic detection (:mod:`core.march.engine`): the KKT tolerance (an exact
        solve repeats a period to round-off)."""
        return self.tol

    @property
    def residuals(self) -> dict:
        """The named residuals of the last step."""
        return dict(zip(RESIDUALS, map(float, self.state.residuals)))

    def step(self, bound, target) -> StepReport:
        """Solve one increment from the current tractions and advance to it.

        Parameters
        ----------
        bound : ndarray, shape (n,)
            Traction bound ``mu p`` of each element [mu p0]; 0 out of contact.
        target : float
            Required ``sum q_i`` [mu p0] (the load over the element size).
        """
        # a writable copy: a read-only bound (core.solve_static's) compiled solve_step and six of its kernels once
        # more, for the read-only array type (15 s of CPU, cold); march passes writable rows
        bound = np.array(bound, dtype=float, order="C")
        self._reserve(bound[None, :], 1)
        st = self.state
        lam, ok = _pdas.solve_step(self.K, bound, float(target),
                                   self.element_size, self.tol, self.maxiter, st)
        report = StepReport(traction=read_only(st.q.copy()), state=read_only(st.codes.copy()),
                            displacement=float(lam), iterations=int(st.counters[_pdas.ITERATIONS]),
                            residuals=self.residuals, converged=bool(ok))
        if ok:
            st.q_prev[:] = st.q
            st.total[0] += lam
        return report

    def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out: Trajectory):
        """Solve steps ``k0:k1`` in order (``bounds[k - k0]``: bound of step ``k``; target ``Q[k] load_scale``).

        Returns
        -------
        (reached, periodic_from, failed) : tuple of int
            ``reached``: steps done; ``periodic_from >= 0``: that period
            repeats for ever (stop marching); ``failed >= 0``: the step that
            could not be solved (:attr:`residuals` holds its residuals).
        """
        self._reserve(bounds, int(k1) - int(k0))
        return _pdas.march(self.K, bounds, Q, period, float(load_scale), self.element_size, self.tol,
                           self.maxiter, bool(detect_periodic), int(k0), int(k1), self.state,
                           out.traction, out.state, out.displacement, out.dissipation, out.iterations,
                           out.kkt_residual, out.worst)
