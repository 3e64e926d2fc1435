"""The result of a cycle simulation: a frozen record with its diagnostics."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .bodies import get_body
from .states import STATE_NAMES, State, Zone

__all__ = ["CycleResult", "STATE_RELEASED", "STATE_STICK", "STATE_SLIP_FORWARD", "STATE_SLIP_BACKWARD",
           "STATE_NAMES", "SolverError", "SolveCancelled", "read_only", "classify_increments", "SETTLED_RATIO"]

#: Element states recorded per step (``CycleResult.state``): aliases of :class:`core.states.State`.
STATE_RELEASED, STATE_STICK, STATE_SLIP_FORWARD, STATE_SLIP_BACKWARD = (
    State.RELEASED, State.STICK, State.SLIP_FORWARD, State.SLIP_BACKWARD)


def read_only(arr: np.ndarray) -> np.ndarray:
    """``arr`` with its write flag cleared (results are shared between sessions of the app)."""
    arr.setflags(write=False)
    return arr


#: Margin [mu p0] below the traction bound that counts as sticking in the final state.
STICK_MARGIN = 1e-7

#: Ratio of the last increment per period to the one before from which a run that has not shaken down
#: counts as ratcheting (the increment has settled); below it, the run is "undetermined".
SETTLED_RATIO = 0.9


def classify_increments(increments, shakedown_rtol, periodic_from=None, *, floor=0.0, unit="mu P/E*"):
    """The verdict of a run from its increments per period: one rule for every body.

    * ``"shakedown"``: from some period on every increment is at most
      ``shakedown_rtol`` of the largest (or at most ``floor``, the size of
      solver noise); that period is the shakedown period.
    * ``"ratcheting"``: the body keeps walking: the state repeats
      (``periodic_from``) with a non-zero increment, or the last increment is
      at least :data:`SETTLED_RATIO` of the one before (it has settled;
      shakedown increments decay geometrically, by a factor of 2 to 10 per
      period away from the limit, ever more slowly close to it).
    * ``"undetermined"``: the run cannot tell: a single period (one increment
      shows no trend), or increments still decaying but not yet below
      ``shakedown_rtol``. More periods decide it.

    Parameters
    ----------
    increments : array_like
        Rigid-body displacement increment of each period (any sign).
    shakedown_rtol : float
        Relative tolerance of the shakedown verdict.
    periodic_from : int or None
        Period from which the solver found the state repeating.
    floor : float
        Absolute size below which an increment counts as zero (>= 0).
    unit : str
        Unit of the increments, for the reason.

    Returns
    -------
    shakedown_period : int or None
    regime : str
    reason : str
    """
    inc = np.abs(np.asarray(increments, dtype=float))
    if inc.size == 0:
        return None, "undetermined", "no rocking period was run"
    scale = float(inc.max())
    small = inc <= max(shakedown_rtol * scale, float(floor))
    if small[-1]:
        k = inc.size - 1
        while k > 0 and small[k - 1]:
            k -= 1
        return int(k), "shakedown", (f"the increment per period fell to <= {shakedown_rtol:g} of its largest "
                                     f"from period {k}")
    last = float(inc[-1])
    if periodic_from is not None:
        return None, "ratcheting", (f"the state repeats from period {periodic_from}, walking {last:.3g} {unit} "
                                    "per period")
    if inc.size < 2:
        return None, "undetermined", (f"{inc.size} period: one increment cannot show whether it decays "
                                      "(shakedown) or settles (ratcheting); run more periods")
    ratio = last / float(inc[-2]) if inc[-2] > 0 else math.inf
    if ratio >= SETTLED_RATIO:
        return None, "ratcheting", (f"the increment per period settled at {last:.3g} {unit} (last two in ratio "
                                    f"{ratio:.3g})")
    return None, "undetermined", (f"after {inc.size} periods the increment still decays (ratio {ratio:.3g} per "
                                  f"period) but is {last / scale:.3g} of its largest, above shakedown_rtol = "
                                  f"{shakedown_rtol:g}; run more periods")


def below_bound(q, bound):
    """Elements whose traction stays strictly below a positive bound (by :data:`STICK_MARGIN`)."""
    return (bound > 0) & (np.abs(q) < bound - STICK_MARGIN)


def central_halfwidth(mask, edges) -> float:
    """Half-width [a] of the contiguous run of ``mask`` elements closest to x = 0 (0 if none)."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return 0.0
    x = 0.5 * (edges[1:] + edges[:-1])
    lo = hi = idx[np.argmin(np.abs(x[idx]))]
    while lo - 1 >= 0 and mask[lo - 1]:
        lo -= 1
    while hi + 1 < mask.size and mask[hi + 1]:
        hi += 1
    return float(0.5 * (edges[hi + 1] - edges[lo]))


class SolverError(RuntimeError):
    """A step of the incremental tangential problem could not be solved.

    Attributes
    ----------
    step : int
        Index of the failed step in the schedule.
    xc : float
        Contact centre at that step, in units of ``a``.
    residual : float
        Worst KKT residual reached.
    """

    def __init__(self, step: int, xc: float, residual: float, reason: str = ""):
        self.step, self.xc, self.residual = int(step), float(xc), float(residual)
        super().__init__(
            f"tangential increment not solved at step {self.step} (xc = {self.xc:.6g} a): "
            f"KKT residual {self.residual:.3g}{'; ' + reason if reason else ''}"
        )


class SolveCancelled(RuntimeError):
    """A solve was stopped on request or because its time budget ran out; the message says which."""


@dataclass(frozen=True, eq=False)
class CycleResult:
    """The transient of the rocking contact: per step, per period, and its verdict.

    Normalised units throughout: lengths in the nominal half-width ``a``,
    pressure in the nominal ``p0``, tractions in ``mu p0``, loads ``Q`` in
    ``mu P`` (so ``Q = ft`` at constant load), displacements in ``mu P / E*``
    (``P = Fn / L``), positive in the direction of ``Ft``.

    Attributes
    ----------
    edges : ndarray, shape (n + 1,)
        Edges of the world-fixed elements.
    xc, P, Q : ndarray, shape (steps,)
        The schedule: contact centre, normal load (in nominal ``P``) and
        tangential load (in ``mu P``) at each step.
    period : ndarray of int, shape (steps,)
        Period index of each step; -1 for the initial loading.
    traction : ndarray, shape (steps, n)
        Element tractions at the end of each step.
    state : ndarray of int8, shape (steps, n)
        Element state per step: :data:`STATE_RELEASED` (out of contact),
        :data:`STATE_STICK`, :data:`STATE_SLIP_FORWARD` (slip increment in
        +x), :data:`STATE_SLIP_BACKWARD`.
    displacement : ndarray, shape (steps,)
        Rigid-body displacement of the cylinder after each step. For the
        plane-strain kernel only differences are meaningful (a 2D rigid
        displacement is defined up to a constant).
    dissipation : ndarray, shape (steps,)
        Frictional work of each step, ``sum q s dx`` (>= 0).
    iterations : ndarray of int, shape (steps,)
        Active-set iterations of each step (0: nothing slipped).
    cg_iterations : ndarray of int, shape (steps,)
        Conjugate-gradient iterations of each step (``solver="fft"``; 0 for
        ``"dense"``, which solves its stick set directly).
    kkt_residual : ndarray, shape (steps,)
        Worst KKT residual of each step (the largest of :attr:`residuals`' kinds).
    kernel : str
        ``"plane"`` (plane strain) or ``"strip"`` (truncated 3D strip).
    u0 : float or None
        Strip kernel only: ``U0``, the displacement at ``ft = 1``, in ``mu P/E*``.
    periodic_from : int or None
        Period from which the state repeated and later periods were copied
        instead of recomputed (exact to the solver tolerance), or None.
    params : dict
        The inputs of the run.
    tol : float
        KKT tolerance the steps were solved to.
    shakedown_rtol : float
        Relative tolerance on the increment per period for the verdict.
    runtime : float
        Wall time of the solve [s].
    body : str
        Name of the body (:data:`core.bodies.BODIES`), ``"cylinder"``.
    body_spec : core.bodies.Body or None
        The body object with its parameters (e.g. ``core.Punch(flat=0.8)``).
    solver : str
        Per-step solver that ran (``"dense"`` or ``"fft"``).
    residuals : dict
        Worst of each named KKT residual over the steps solved: ``stick_slip``
        (slip on the stick set), ``bound`` (``|q|`` above ``mu p``),
        ``slip_direction`` (slip against the traction), ``out_of_contact``
        (traction outside the contact), ``load_balance`` (``sum q dx`` against
        the load).

    Every array, the cached ones included, is read-only: a result may be
    shared between sessions of the app.
    """

    edges: np.ndarray
    xc: np.ndarray
    P: np.ndarray
    Q: np.ndarray
    period: np.ndarray
    traction: np.ndarray
    state: np.ndarray
    displacement: np.ndarray
    dissipation: np.ndarray
    iterations: np.ndarray
    kkt_residual: np.ndarray
    kernel: str
    u0: float | None
    periodic_from: int | None
    params: dict = field(default_factory=dict)
    tol: float = 1e-10
    shakedown_rtol: float = 1e-3
    runtime: float = 0.0
    body: str = "cylinder"
    solver: str = "dense"
    residuals: dict = field(default_factory=dict)
    cg_iterations: np.ndarray | None = None
    body_spec: object = None

    def __post_init__(self):
        if self.cg_iterations is None:
            object.__setattr__(self, "cg_iterations", np.zeros(self.iterations.shape, dtype=np.int64))
        for name, value in vars(self).items():
            if isinstance(value, np.ndarray):
                read_only(value)

    # ---- grid ------------------------------------------------------------
    @cached_property
    def x(self) -> np.ndarray:
        """Element centres [a]."""
        return read_only(0.5 * (self.edges[1:] + self.edges[:-1]))

    @property
    def dx(self) -> float:
        """Element width [a]."""
        return float(self.edges[1] - self.edges[0])

    @property
    def periods(self) -> int:
        """Number of rocking periods."""
        return int(self.period.max()) + 1 if self.period.size else 0

    # ---- per step ----------------------------------------------------------
    @cached_property
    def pressure(self) -> np.ndarray:
        """Element-mean pressure per step, shape (steps, n) [p0]: the traction bound [mu p0] the solver used."""
        if self.body_spec is not None:
            grid = self.body_spec.on_grid(self.edges, self.params.get("normal", "auto"))
            return read_only(grid.bounds(self.xc, self.P))
        return read_only(get_body(self.body)(self.edges).bounds(self.xc, self.P))

    @property
    def u(self) -> np.ndarray | None:
        """``U / U0`` per step (strip kernel only, else None)."""
        return None if self.u0 is None else read_only(self.displacement / self.u0)

    # ---- per period --------------------------------------------------------
    def _period_ends(self) -> np.ndarray:
        ends = np.flatnonzero(np.diff(self.period) != 0)  # last step of each block
        return np.append(ends, self.period.size - 1)

    @cached_property
    def increment_per_period(self) -> np.ndarray:
        """Rigid-body displacement increment of each period [mu P/E*], positive along Ft."""
        ends = self._period_ends()
        disp = self.displacement[ends]
        if self.period[0] < 0:  # first block is the loading
            return read_only(np.diff(disp))
        return read_only(np.diff(np.concatenate([[0.0], disp])))

    @cached_property
    def shakedown_period(self) -> int | None:
        """First period from which every increment is below the shakedown tolerance, else None."""
        return self._classified[0]

    @cached_property
    def _classified(self):
        return classify_increments(self.increment_per_period, self.shakedown_rtol, self.periodic_from,
                                   floor=10.0 * self.tol, unit="mu P/E*")

    @property
    def verdict(self) -> tuple[str, str]:
        """``(regime, reason)``: what the periods run show about the regime, and why (:func:`classify_increments`)."""
        return self._classified[1:]

    @property
    def regime(self) -> str:
        """``"shakedown"``, ``"ratcheting"`` or ``"undetermined"`` (see :attr:`verdict`)."""
        return self.verdict[0]

    @property
    def regime_reason(self) -> str:
        """Why the run got its :attr:`regime`, in words (see :attr:`verdict`)."""
        return self.verdict[1]

    # ---- the final state ---------------------------------------------------
    @cached_property
    def lowest_pressure(self) -> np.ndarray:
        """Lowest element pressure seen during the last period, shape (n,) [p0]."""
        last = self.period == self.period[-1]
        return read_only(self.pressure[last].min(axis=0))

    @cached_property
    def final_zones(self) -> np.ndarray:
        """Zones of the final traction (:class:`core.states.Zone`): stick (below mu p_min), slip (at the bound), released (zero traction), none (never in contact).

        ``zero traction`` marks the elements that lost contact during the last
        period (their lowest pressure is 0) and were in contact at some step.
        """
        bound = self.lowest_pressure
        ever = (self.pressure > 0).any(axis=0)
        stick = below_bound(self.traction[-1], bound)
        zones = np.where(stick, Zone.STICK, np.where(bound > 0, Zone.SLIP, np.where(ever, Zone.RELEASED, Zone.NONE)))
        return read_only(zones.astype(np.int8))

    @cached_property
    def stick_halfwidth(self) -> float:
        """``c_sd / a``: half-width of the central zone whose final traction stays below mu p_min.

        Outside it the traction sits at ``mu`` times the lowest pressure of the
        last period, or is zero where contact was lost. 0 if there is no such zone.
        """
        return central_halfwidth(self.final_zones == Zone.STICK, self.edges)

    @property
    def max_kkt_residual(self) -> float:
        """Worst KKT residual over all steps."""
        return float(self.kkt_residual.max()) if self.kkt_residual.size else 0.0

    def summary(self) -> dict:
        """Scalar figures of the run (for tables, CSV headers, the CLI)."""
        inc = self.increment_per_period
        return {
            **self.params,
            "regime": self.regime,
            "regime_reason": self.regime_reason,
            "stick_halfwidth": self.stick_halfwidth,
            "shakedown_period": self.shakedown_period,
            "increment_last_period": float(inc[-1]) if inc.size else float("nan"),
            "periods": self.periods,
            "elements": int(self.edges.size - 1),
            "steps": int(self.xc.size),
            "periodic_from": self.periodic_from,
            "max_iterations": int(self.iterations.max()) if self.iterations.size else 0,
            "max_kkt_residual": self.max_kkt_residual,
            "u0": self.u0,
            "runtime_s": self.runtime,
        }
