"""The coupled per-step solver of a line contact of dissimilar materials (Dundurs ``beta != 0``).

With coupling (:mod:`core.elastic.coupling`) the pressure is no longer Hertz's: the
tangential tractions move the surfaces normally, so at every step the normal
and the tangential KKT conditions are solved together. Step ``n`` (centre
``xc``, loads ``P``, ``Q``) asks for the pressure ``p``, the approach
``delta``, the tractions ``q`` and the rigid increment ``lam`` with

* normal: ``gap = h(x - xc) - delta + K p + (2 beta mu/pi) S q >= 0``,
  ``p >= 0``, ``p gap = 0``, ``sum p dx = (pi/2) P`` (``h`` the body's profile);
* tangential, Coulomb on the bound ``mu p``: the slip increment
  ``s = lam - K (q - q_prev) + (2 beta/(pi mu)) S (p - p_prev)`` vanishes where
  ``|q| < p`` [mu p0], ``q = p sign(s)`` where it does not, ``q = 0`` where
  ``p = 0``, ``sum q dx = (pi/2) Q``.

:class:`CoupledSolver` solves a step at once where it can: with the contact and
the tangential sets fixed the step is a linear system, solved from the inverse of
a window's system in full stick and a small correction for the elements that do
not stick, and checked as the full solves check theirs; a wrong set is moved and
the system solved again (:mod:`core.solvers._coupled`: :func:`~core.solvers._coupled.direct`,
:func:`~core.solvers._coupled.check`). Where that does not end the step it goes on
by the Panagiotopoulos alternation, as
CONTACT does (Vollebregt and Kalker): the normal problem with the tractions
fixed (:func:`core.pressure.normal.solve_line`, the existing direct active-set solve,
with the profile shifted by the traction's normal displacement), then the
tangential problem with that pressure as its bound (the existing primal-dual
active set of :mod:`core.solvers._pdas`; the pressure's tangential displacement
``(2 beta/(pi mu)) S dp`` enters through its previous tractions,
``q_prev + K^-1 (2 beta/(pi mu)) S dp``, which gives the same KKT system), until
neither field changes by more than the tolerance. Each step reports the
named residuals of :data:`core.base.states.RESIDUAL_NAMES` (with the true slip)
and three of its own, :data:`COUPLED_RESIDUALS`: ``gap`` (the largest
``|gap|`` in contact and penetration out of it [P/E*]), ``pressure`` (the
most negative pressure [p0]) and ``alternation`` (the last change of ``p`` and
``q`` [p0, mu p0]; 0 for a step the direct solve ended, whose equations hold to
round-off). At ``beta = 0`` the alternation stops after its second pass and the
tangential solve is the dense solver's on the numerical pressure: the same
increments to round-off (``tests/test_coupled.py``).

The pressure of every step is written into the bounds the engine passes
(:func:`core.march.engine.run` keeps them as the result's :attr:`~core.CycleResult.pressures`
and its lowest pressure), so a coupled result shows its own pressure.

References
----------
.. [1] P. D. Panagiotopoulos, "A nonlinear programming approach to the
   unilateral contact- and friction-boundary value problem in the theory of
   elasticity", Ingenieur-Archiv 44 (1975) 421-432.
.. [2] J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*,
   Kluwer 1990 (CONTACT; the alternation between the normal and tangential problems).
.. [3] E. A. H. Vollebregt, *User guide for CONTACT*, Vortech (the coupled 2D problems).
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict

import numpy as np
import scipy.linalg as sla

from . import _coupled, _pdas
from ..elastic.coupling import coupling_factors, cross_apply, cross_matrix
from .dense import RESIDUALS, DenseSolver, Trajectory
from ..pressure.normal import solve_line

__all__ = ["CoupledSolver", "COUPLED_RESIDUALS", "MAX_ALTERNATIONS", "CoupledTrajectory", "window_inverse"]

#: The coupled solver's own residuals, after :data:`core.base.states.RESIDUAL_NAMES`.
COUPLED_RESIDUALS = ("gap", "pressure", "alternation")
#: Alternations of the normal and tangential solves allowed per step.
MAX_ALTERNATIONS = 200
#: Windows' inverses kept (:func:`window_inverse`): the runs of a sweep, a limit search or the explorer's sliders
#: share the operator, the element size and the coupling, and so the inverse (about 4 ms to make at ``a/40``).
WINDOW_CACHE = 4
_windows: "OrderedDict[tuple, np.ndarray]" = OrderedDict()
_windows_lock = threading.Lock()


def window_inverse(K, dx, normal_factor, tangential_factor, Lw):
    """:func:`core.solvers._coupled.window_inverse`, kept for the next run of the same contact (the last
    :data:`WINDOW_CACHE`, least recently used replaced). Read it, never write it: it is shared."""
    key = (K.shape, hashlib.sha1(np.ascontiguousarray(K[:, 0]).tobytes()).hexdigest(), float(dx),
           float(normal_factor), float(tangential_factor), int(Lw))
    with _windows_lock:
        W = _windows.get(key)
        if W is not None:
            _windows.move_to_end(key)
            return W
    W = _coupled.window_inverse(K, dx, normal_factor, tangential_factor, Lw)
    with _windows_lock:
        _windows[key] = W
        while len(_windows) > WINDOW_CACHE:
            _windows.popitem(last=False)
    return W


class CoupledTrajectory(Trajectory):
    """:class:`core.solvers.dense.Trajectory` with the coupled residuals (:data:`COUPLED_RESIDUALS`) and the alternations."""

    def __init__(self, steps: int, n: int):
        super().__init__(steps, n)
        self.worst = np.zeros(len(RESIDUALS) + len(COUPLED_RESIDUALS))
        self.alternations = np.zeros(steps, dtype=np.int64)
        #: of which full tangential solves (the others keep the settled active set: :func:`core.solvers._pdas.fixed_set_stick`)
        self.full_solves = np.zeros(steps, dtype=np.int64)
        #: direct solves of the step with its sets fixed (:func:`core.solvers._coupled.direct`), between the passes
        self.direct_solves = np.zeros(steps, dtype=np.int64)

    def residuals(self) -> dict:
        return dict(zip(RESIDUALS + COUPLED_RESIDUALS, map(float, self.worst)))


class CoupledSolver:
    """The Panagiotopoulos alternation of the normal and the tangential solves (module docstring).

    Parameters
    ----------
    operator : object
        The line's elastic operator with ``matrix()`` (:class:`core.elastic.operators.DenseOperator`):
        ``K`` of both problems.
    element_size : float
        Element width ``dx`` [a].
    tol : float
        KKT tolerance of every step, and of the alternation's change.
    maxiter : int
        Active-set iterations allowed per tangential solve.
    beta : float
        Dundurs' ``beta`` (:mod:`core.theory.materials`' sign), ``|beta| < 0.5``.
    mu : float
        Friction coefficient, in (0, 10].
    grid : object
        The discretised line body (:class:`core.geometry.bodies.Cylinder` on a grid,
        :class:`core.geometry.bodies.LineGrid`): its element centres ``x`` and its body's
        ``profile`` (the gap [P/E*] centred at 0).
    max_alternations : int
        Alternations allowed per step.

    Notes
    -----
    Of the per-step solver protocol (:mod:`core.march.engine`) it has ``march`` but no bound-only ``step``: a coupled
    step solves its own pressure, from the centre and load of the step (:meth:`start`).
    """

    name = "coupled"
    #: Whether a step is solved at once with its sets fixed (:func:`core.solvers._coupled.joint`) before the
    #: alternation's passes, which then only find the sets where that fails (False: the passes alone, as before).
    direct = True
    kernels = DenseSolver.kernels + ("core.solvers._coupled.alternate",)
    form = "dense"
    grid = "line"
    #: :func:`core.march.engine.run` passes the discretised body as ``grid`` and keeps Melan's limit as the uncoupled
    #: reference (Melan's theorem does not hold for a coupled contact).
    coupled = True

    @staticmethod
    def default_maxiter(n):
        """:meth:`core.solvers.dense.DenseSolver.default_maxiter`."""
        return DenseSolver.default_maxiter(n)

    @staticmethod
    def trajectory(history, shape):
        """The :class:`CoupledTrajectory` of ``history`` on a grid of ``shape = (n,)``."""
        return CoupledTrajectory(len(history), shape[0])

    def __init__(self, operator, *, element_size, tol, maxiter, beta, mu, grid, max_alternations=MAX_ALTERNATIONS):
        self.inner = DenseSolver(operator, element_size=element_size, tol=tol, maxiter=maxiter)
        self.K, self.n = self.inner.K, self.inner.n
        self.dx, self.tol, self.maxiter = float(element_size), float(tol), int(maxiter)
        self.beta, self.mu = float(beta), float(mu)
        self.normal_factor, self.tangential_factor = coupling_factors(beta, mu)
        self.max_alternations = int(max_alternations)
        self.x = np.asarray(grid.x, dtype=float)
        if self.x.shape != (self.n,):
            raise ValueError(f"the grid's {self.x.size} elements differ from the operator's {self.n}")
        self.profile = grid.body_spec.profile
        self.load_factor = float(grid.load_factor)
        self._Z = None  # K^-1 (2 beta/(pi mu)) S, for the general solve only (:attr:`Z`)
        self.p_prev = np.zeros(self.n)
        self._interval = None
        # the lower Cholesky factor of K: its leading L x L block factors K on any interval of L elements
        C, ok = _coupled.cholesky(self.K)
        if not ok:
            raise ValueError("the operator's matrix is not positive definite: no coupled solve on it")
        self.C, self.CT = C, np.ascontiguousarray(C.T)
        self._work = np.zeros((_coupled.WORK_ROWS, self.n))
        self._inv = _coupled.new_inverses(self.K)  # K^-1 on the contact's intervals, a few widths at a time
        self._dq_last = np.zeros(self.n)  # the last step's traction increment: the next step's first guess
        self._q_start = np.zeros(self.n)
        self._info = np.zeros(2)
        # the direct solve's inverse of a window in full stick (core.solvers._coupled.window_inverse), made when a
        # contact first needs it and widened when one outgrows it
        self._W = np.zeros((0, 0))
        self._need = np.zeros(1, dtype=np.int64) if self.direct else -np.ones(1, dtype=np.int64)
        self.residual_values = np.zeros(len(RESIDUALS) + len(COUPLED_RESIDUALS))
        self.xc = self.P = None
        self.failure = ""

    def start(self, history):
        """Keep the centres and normal loads of the steps (the normal problem of step ``k`` needs them)."""
        self.xc = np.asarray(history.xc, dtype=float)
        self.P = np.asarray(history.P, dtype=float)
        self.inner._reserve(np.ones((1, self.n)), 1)  # room for a contact anywhere on the grid (it is solved for)

    @property
    def traction(self) -> np.ndarray:
        """Tractions after the last step [mu p0]."""
        return self.inner.state.q_prev

    @property
    def pressure(self) -> np.ndarray:
        """Pressure after the last step [p0]."""
        return self.p_prev

    @property
    def Z(self) -> np.ndarray:
        """``K^-1 (2 beta/(pi mu)) S``: the pressure's tangential displacement as a change of the previous tractions
        on the whole grid (the general solve's, made on first use)."""
        if self._Z is None:
            self._Z = self.tangential_factor * sla.cho_solve((self.C, True), cross_matrix(self.n, self.dx))
        return self._Z

    @property
    def periodic_tol(self) -> float:
        """The KKT tolerance (the alternation converges to it; a repeated period repeats to it)."""
        return self.tol

    @property
    def residuals(self) -> dict:
        """The named residuals of the last step (:data:`core.base.states.RESIDUAL_NAMES` and :data:`COUPLED_RESIDUALS`)."""
        return dict(zip(RESIDUALS + COUPLED_RESIDUALS, map(float, self.residual_values)))

    # ---- one step -----------------------------------------------------------------------------------
    def _normal(self, gap0, load, q, p_start):
        """The pressure under the profile ``gap0`` shifted by the tractions' normal displacement: the contact as
        one interval (:meth:`_interval_normal`), else :func:`core.pressure.normal.solve_line`'s active set."""
        profile = gap0 + self.normal_factor * cross_apply(q, self.dx) if self.normal_factor else gap0
        start = p_start if p_start is not None and p_start.sum() > 0 else None
        self._interval = None
        p = self._interval_normal(profile, load, start)
        if p is None:
            p = np.array(solve_line(profile, self.dx, load=load, initial=start).pressure)
        return p

    def _shift(self, dp):
        """The change ``z`` of the previous tractions that carries the pressure's tangential displacement
        ``r = (2 beta/(pi mu)) S dp``: ``K z = r`` on the contact (what the slips there see). On an interval
        contact ``z`` lives on it (``K_CC^-1 r_C``, from the cached inverse: the increment stays local); else
        ``z = K^-1 r`` on the whole grid."""
        if self._interval is None:
            return self.Z @ dp
        i0, i1 = self._interval
        z = np.zeros(self.n)
        z[i0:i1] = self._inverse(i1 - i0)[0] @ (self.tangential_factor * cross_apply(dp, self.dx)[i0:i1])
        return z

    def _inverse(self, L):
        """``(K_L^-1, K_L^-1 1, 1^T K_L^-1 1)`` of the Toeplitz block of ``L`` elements, from the compiled march's
        cache of interval inverses (:func:`core.solvers._coupled.inverse`; copies: a slot may be replaced)."""
        slot = _coupled.inverse(self._inv, self.C, self.CT, L)
        A, s = self._inv.A[slot, :L, :L].copy(), self._inv.ones[slot, :L].copy()
        return A, s, float(s.sum())

    def _interval_normal(self, h, load, start):
        """The normal problem ``h + K p - delta >= 0``, ``p >= 0``, complementary, ``sum p dx = load``, with the
        contact one interval of elements, by an active set on its ends (the inverse of ``K`` on an interval is
        the same wherever it lies: cached per width). None if the contact is not one interval or the ends do
        not settle (the caller then runs the general solve)."""
        n = self.n
        if start is not None:
            inside = np.flatnonzero(start > 0)
            i0, i1 = int(inside[0]), int(inside[-1]) + 1
        else:  # around the profile's lowest point, Hertz's width
            m = int(np.argmin(h))
            half = int(np.ceil(np.sqrt(max(load, 1e-12) / (0.5 * np.pi)) / self.dx)) + 1
            i0, i1 = max(0, m - half), min(n, m + half + 1)
        seen = set()
        for _ in range(4 * n):
            if i1 - i0 < 3 or (i0, i1) in seen:
                return None
            seen.add((i0, i1))
            A, s, s1 = self._inverse(i1 - i0)
            u = A @ h[i0:i1]
            delta = (load / self.dx + u.sum()) / s1
            p = delta * s - u
            if p.min() < 0.0:
                neg = np.flatnonzero(p < 0.0)
                if neg[0] > 0 and neg[-1] < p.size - 1 and not (neg[0] == 0 or neg[-1] == p.size - 1):
                    return None  # a hole inside the contact: the general solve
                i0 += int(p[0] < 0.0)
                i1 -= int(p[-1] < 0.0)
                continue
            gap = h + self.K[:, i0:i1] @ p - delta
            tol = 1e-12 * max(1.0, float(np.abs(h[i0:i1]).max()))
            grow0 = i0 > 0 and gap[i0 - 1] < -tol
            grow1 = i1 < n and gap[i1] < -tol
            outside = np.concatenate((gap[:i0], gap[i1:]))
            if not (grow0 or grow1):
                if outside.size and outside.min() < -tol:
                    return None  # penetration away from the ends
                out = np.zeros(n)
                out[i0:i1] = p
                self._interval = (i0, i1)
                return out
            i0 -= int(grow0)
            i1 += int(grow1)
        return None

    def _solve_general(self, k, target):
        """Solve step ``k`` (its centre and load from :meth:`start`) from the current state by the Python
        alternation, with the general normal solve (:func:`core.pressure.normal.solve_line`) where the contact is not one
        interval (Anderson's mixing of the last two passes); the tractions ``q_prev`` and pressure are not advanced.
        Returns ``(lam, p, ok, alternations, change)``."""
        st = self.inner.state
        q_true = st.q_prev.copy()
        gap0 = self.profile(self.x - self.xc[k])
        load = self.load_factor * float(self.P[k])
        p = self.p_prev if self.p_prev.any() else None
        q = q_true  # the tractions the normal solve sees
        f_before = q_before = None
        lam, ok, change, it = 0.0, False, np.inf, 0
        try:
            for it in range(1, self.max_alternations + 1):
                # ---- normal: the pressure with the tractions fixed
                p_new = self._normal(gap0, load, q, p)
                # ---- tangential: bound mu p [mu p0] = p [p0]; the pressure's slip through the previous tractions
                st.q_prev[:] = q_true + self._shift(p_new - self.p_prev) if self.tangential_factor else q_true
                lam, ok = _pdas.solve_step(self.K, p_new, float(target), self.dx, self.tol, self.maxiter, st)
                if not ok:
                    break
                q_out = st.q.copy()
                f = q_out - q
                change = max(float(np.abs(p_new - p).max()) if p is not None else np.inf, float(np.abs(f).max()))
                p = p_new
                if self.beta == 0.0:  # uncoupled: one pass solves it
                    change = 0.0
                if change <= self.tol:
                    break
                # ---- the next tractions: Anderson's mixing of the last two passes (a secant step on the fixed
                # point q = T(q); the alternation alone contracts by about 0.08 a pass at beta = 0.25)
                q_next = q_out
                if f_before is not None:
                    df = f - f_before
                    dd = float(df @ df)
                    if dd > 0.0:
                        q_next = q_out - (float(f @ df) / dd) * (q_out - q_before)
                f_before, q_before = f, q_out
                q = q_next
        finally:
            st.q_prev[:] = q_true
        return lam, p, ok and change <= self.tol, it, change

    def _residuals(self, k, p, q, slip_ok, change):
        """The named residuals of a solved step (the tangential ones from the active-set solve)."""
        r = self.residual_values
        r[: len(RESIDUALS)] = self.inner.state.residuals
        r[len(RESIDUALS)] = _coupled.gap_residual(self.K, self.profile(self.x - self.xc[k]), p, q,
                                                  self.normal_factor, self.dx, self._work)
        r[len(RESIDUALS) + 1] = max(0.0, -float(p.min()))
        r[len(RESIDUALS) + 2] = change if np.isfinite(change) else 0.0
        return r

    def _gaps(self, k0, k1):
        """The body's gap [P/E*] of steps ``k0:k1``, one row a step (``profile(x - xc[k])``)."""
        x, xc = self.x, self.xc[k0:k1]
        gaps = np.asarray(self.profile(x[None, :] - xc[:, None]), dtype=float)
        if gaps.shape != (k1 - k0, self.n):  # a profile that does not broadcast: row by row
            gaps = np.array([self.profile(x - c) for c in xc], dtype=float).reshape(k1 - k0, self.n)
        return np.ascontiguousarray(gaps)

    def _record(self, k, k0, lam, p, change, alternations, bounds, out):
        """Check and record one step solved by :meth:`_solve_general`; False if it failed."""
        st = self.inner.state
        q = st.q
        res = self._residuals(k, p, q, True, change)
        worst_step = float(res.max())
        if worst_step > 1e3 * self.tol:
            self.failure = f"the coupled residuals {self.residuals} exceed the tolerance"
            return False
        bounds[k - k0] = p
        st.total[0] += lam
        out.traction[k] = q
        out.state[k] = st.codes
        out.displacement[k] = st.total[0]
        out.dissipation[k] = float(q @ st.slip) * self.dx
        out.iterations[k] = st.counters[_pdas.ITERATIONS]
        out.kkt_residual[k] = worst_step
        np.maximum(out.worst, res, out=out.worst)
        out.alternations[k] = out.full_solves[k] = alternations
        self._dq_last = q - st.q_prev
        st.q_prev[:] = q
        self.p_prev = p
        self._work[4] = self.K @ p  # K p of the last step, as the compiled march leaves it (its direct solves use it)
        return True

    def _unsettled(self, alternations, change):
        """The failure message of a step whose alternation did not settle."""
        return (f"the alternation of the normal and tangential solves did not settle in {alternations} passes "
                f"(change {change:.2g})" if np.isfinite(change) and change < _coupled.UNMEASURED else "")

    def march(self, bounds, Q, period, load_scale, k0, k1, detect_periodic, out):
        """Solve steps ``k0:k1`` in order, writing each step's pressure into ``bounds[k - k0]`` (see
        :meth:`core.solvers.dense.DenseSolver.march`; the periodic test compares the tractions and the pressure).

        The compiled march (:func:`core.solvers._coupled.march`) takes the steps whose contact is one interval; a step it
        hands back is solved here by :meth:`_solve_general`, and the compiled march goes on from the next."""
        st = self.inner.state
        steps = Q.size
        nres = len(RESIDUALS)
        gaps = self._gaps(k0, k1)
        loads = self.load_factor * np.asarray(self.P, dtype=float)
        targets = np.ascontiguousarray(Q * load_scale, dtype=float)
        k = k0
        while k < k1:
            reached, periodic_from, failed, status = _coupled.march(
                self.K, self.C, self.CT, gaps, self.xc, loads, targets, period, k0, k, k1, bool(detect_periodic),
                self.dx, self.normal_factor, self.tangential_factor, self.beta != 0.0, self.tol, self.maxiter,
                self.max_alternations, st, self.p_prev, self._dq_last, self._work, self._inv,
                self._q_start, bounds, out.traction, out.state, out.displacement, out.dissipation, out.iterations,
                out.kkt_residual, out.worst, out.alternations, out.full_solves, out.direct_solves,
                self.residual_values, self._info, self._W, self._need)
            if failed >= 0:
                alternations, change = int(self._info[0]), float(self._info[1])
                self.failure = self._unsettled(alternations, change)
                if status == _coupled.STATUS_DONE and change <= self.tol:
                    self.failure = f"the coupled residuals {self.residuals} exceed the tolerance"
                return failed, -1, failed
            if status == _coupled.STATUS_WINDOW:  # a contact wider than the direct solve's window: widen it
                Lw = min(self.n, int(self._need[0]) + _coupled.WINDOW_MARGIN)
                self._W = window_inverse(self.K, self.dx, self.normal_factor, self.tangential_factor, Lw)
                self._need[0] = 0
                k = reached
                continue
            if status != _coupled.STATUS_GENERAL:
                return reached, periodic_from, -1
            # ---- a contact that is not one interval: the general solve of this step
            k = reached
            lam, p, ok, alternations, change = self._solve_general(k, targets[k])
            if not ok:
                self.residual_values[:nres] = st.residuals
                self.failure = self._unsettled(alternations, change)
                return k, -1, k
            if not self._record(k, k0, lam, p, change, alternations, bounds, out):
                return k, -1, k
            if k + 1 < steps and period[k + 1] != period[k]:
                same = _pdas.block_repeats(st.q, st.q_block_end, self.tol)
                if same and detect_periodic and period[k] >= 0:
                    return k + 1, int(period[k]), -1
            k += 1
        return k1, -1, -1
