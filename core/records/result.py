"""The result of a cycle simulation: a frozen record with its diagnostics."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from typing import NamedTuple

import numpy as np

from ..base.states import STATE_NAMES, State, Zone
# the verdict's functions and constants (core/records/verdict.py), kept importable from here
from .verdict import (MIN_FIT_PERIODS, REGIMES, SETTLED_FRACTION, VERDICT_SIGMAS, EnergyVerdict,  # noqa: F401
                      Trend, Verdict, classify_energy, classify_increments, combine_verdicts, fit_trend)

__all__ = ["CycleResult", "PointContactResult", "LineResult", "STATE_RELEASED", "STATE_STICK", "STATE_SLIP_FORWARD", "STATE_SLIP_BACKWARD",
           "STATE_NAMES", "PerStep", "SolverError", "SolveCancelled", "read_only", "classify_increments", "fit_trend", "Trend",
           "Verdict", "EnergyVerdict", "classify_energy", "combine_verdicts", "REGIMES", "FrettingLoop", "VERDICT_SIGMAS", "MIN_FIT_PERIODS", "SETTLED_FRACTION"]

#: Element states recorded per step (``CycleResult.state``): aliases of :class:`core.base.states.State`.
STATE_RELEASED, STATE_STICK, STATE_SLIP_FORWARD, STATE_SLIP_BACKWARD = (
    State.RELEASED, State.STICK, State.SLIP_FORWARD, State.SLIP_BACKWARD)


from ..base._validate import read_only  # noqa: E402 (the one definition, below every layer; kept importable from here)


#: Traction [mu p0] below which an element whose lowest pressure is zero counts as carrying none
#: (:attr:`CycleResult.final_zones`): 1 % of mu p0, above the patch solver's inexactness (a shaken-down
#: sphere at dx = a/10 leaves up to 0.0025 there) and below what a figure of the traction can show.
ZERO_TRACTION = 1e-2

# the static solves' record and the stick test (core/records/static_result.py), kept importable from here
from .static_result import STICK_MARGIN, StaticResult, below_bound, central_halfwidth  # noqa: E402,F401


class PerStep:
    """A per-step array kept as its distinct rows: step ``k`` is ``rows[index[k]]`` (read-only).

    A run's bounds repeat (a rocking history visits the same centres every
    period; a translating patch body is solved once per offset and load), so a
    result keeps each distinct one once. Indexing reads like the full
    ``(steps, ...)`` array: ``p[k]``, ``p[k0:k1]``, ``p[k, i]``, ``len(p)``,
    ``p.shape``; ``np.asarray(p)`` builds the full array. ``p(k)`` is ``p[k]``.
    """

    __slots__ = ("rows", "index")

    def __init__(self, rows: np.ndarray, index: np.ndarray):
        self.rows, self.index = rows, index

    def __len__(self) -> int:
        return int(self.index.size)

    @property
    def shape(self) -> tuple[int, ...]:
        return (len(self), *self.rows.shape[1:])

    @property
    def ndim(self) -> int:
        return self.rows.ndim

    @property
    def dtype(self):
        return self.rows.dtype

    def __getitem__(self, key):
        step, rest = (key[0], key[1:]) if isinstance(key, tuple) else (key, ())
        out = self.rows[self.index[step]]
        if rest:
            out = out[rest] if np.ndim(self.index[step]) == 0 else out[(slice(None), *rest)]
        return read_only(out) if isinstance(out, np.ndarray) else out

    def __call__(self, step) -> np.ndarray:
        return self[step]

    def __iter__(self):
        return (self.rows[i] for i in self.index)

    def __array__(self, dtype=None, copy=None):
        out = self.rows[self.index]
        return out if dtype is None else out.astype(dtype, copy=False)

    def __repr__(self) -> str:
        return f"PerStep(shape={self.shape}, distinct rows={self.rows.shape[0]})"


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


class FrettingLoop(NamedTuple):
    """One period's fretting loop (:meth:`CycleResult.fretting_loop`).

    Attributes
    ----------
    period : int
        The period (from 0).
    Q : ndarray
        Tangential load at the last step of the period before and at each step of this one [``load_unit``].
    displacement : ndarray
        Rigid-body displacement along ``Ft`` at the same steps, from the first [``displacement_unit``].
    work : float
        ``int Q dD`` over the period (trapezoidal) [``energy_unit``]: the loop's area when it closes.
    energy : float
        The energy the solver dissipated in the period (:attr:`CycleResult.dissipation_per_period`).
    load_unit, displacement_unit, energy_unit : str
        ``mu P``, ``mu P/E*``, ``mu^2 P^2/E*`` on a line (per unit length); ``mu Fn``, ``mu Fn/(E* a)``,
        ``mu^2 Fn^2/(E* a)`` on a patch.
    """

    period: int
    Q: np.ndarray
    displacement: np.ndarray
    work: float
    energy: float
    load_unit: str
    displacement_unit: str
    energy_unit: str


#: What a coupled run's cyclic slip adds to its reason: below the coupled limit a steady micro-slip remains whose
#: energy falls with the element size (benchmarks/results/coupled_dissipation_grid.txt, issue 32).
COUPLED_GRID_NOTE = ("; with coupling (beta != 0) part of a steady dissipation is the grid's: below the coupled "
                     "limit of the rocking cylinder it falls like sqrt(dx) (|beta| 0.25: 2.2e-3, 1.0e-3, 7.3e-4, "
                     "5.1e-4 mu^2 P^2/E* at a/20, a/40, a/80, a/160), so run a finer grid before reading it as "
                     "fretting")


class PeriodVerdict:
    """The verdict of a run from its increments per period: the same properties on every result type.

    A result class that has ``increment_per_period``, ``shakedown_rtol``,
    ``periodic_from`` and ``tol`` and names the unit of its increments in
    :attr:`increment_unit` gets its regime, reason, trend fit and shakedown
    period from :func:`classify_increments`, the one rule of every body; one
    that also has ``Q`` and ``melan_limit`` gets the verdict's check against it.
    """

    #: Unit of the increments, as printed in the reason.
    increment_unit = "mu P/E*"

    #: Unit of the energies per period, as printed in the reason.
    energy_unit = "mu^2 P^2/E*"

    @cached_property
    def _walk(self) -> Verdict:
        # Melan's theorem decides only an uncoupled contact: a coupled run's limit is a reference, not a check
        checked = hasattr(type(self), "melan_limit") and self.Q.size > 0 and not getattr(self, "coupled", False)
        return classify_increments(self.increment_per_period, self.shakedown_rtol, self.periodic_from,
                                   floor=10.0 * self.tol, unit=self.increment_unit,
                                   load=float(self.Q[-1]) if checked else None,
                                   limit=(lambda: self.melan_limit) if checked else None)

    @cached_property
    def _energy(self) -> EnergyVerdict | None:
        """The trend of the energy per period (:func:`classify_energy`), None without ``dissipation_per_period``."""
        if not hasattr(type(self), "dissipation_per_period"):
            return None
        return classify_energy(self.dissipation_per_period, self.shakedown_rtol, self.periodic_from,
                               floor=10.0 * self.tol, unit=self.energy_unit)

    @cached_property
    def _classified(self) -> Verdict:
        walk = self._walk
        out = walk if self._energy is None else combine_verdicts(walk, self._energy)
        if out.regime == "cyclic slip" and getattr(self, "coupled", False):
            out = out._replace(reason=out.reason + COUPLED_GRID_NOTE)
        return out

    @property
    def shakedown_period(self) -> int | None:
        """First period from which every increment is below the shakedown tolerance, else None."""
        return self._classified.shakedown_period

    @property
    def verdict(self) -> tuple[str, str]:
        """``(regime, reason)``: what the periods run show about the regime, and why (:func:`classify_increments`)."""
        return self._classified[1:3]

    @property
    def regime(self) -> str:
        """``"shakedown"``, ``"cyclic slip"``, ``"ratcheting"`` or ``"undetermined"`` (:data:`REGIMES`; see
        :attr:`verdict`): read from the walk per period and, when the result has it, the energy per period."""
        return self._classified.regime

    @property
    def regime_reason(self) -> str:
        """Why the run got its :attr:`regime`, in words (see :attr:`verdict`)."""
        return self._classified.reason

    @property
    def trend(self) -> Trend | None:
        """The fit ``D_n = D_inf + C r^n`` of the tail of the increments (:func:`fit_trend`; None below 4 periods)."""
        return self._classified.trend

    @property
    def D_inf(self) -> float:
        """Limit of the increment per period as the periods go on, in :attr:`increment_unit` (NaN below 4 periods)."""
        return math.nan if self.trend is None else self.trend.D_inf

    @property
    def D_inf_error(self) -> float:
        """Standard error of :attr:`D_inf` (NaN below 4 periods)."""
        return math.nan if self.trend is None else self.trend.D_inf_error

    @property
    def decay_ratio(self) -> float:
        """``r``: the factor by which the changing part of the increment shrinks each period (NaN if none)."""
        return math.nan if self.trend is None else self.trend.ratio

    @property
    def periods_to_decide(self) -> int | None:
        """Roughly how many more periods would decide an undetermined run (None otherwise or if unknown)."""
        return self._classified.periods_to_decide

    @property
    def energy_trend(self) -> Trend | None:
        """The fit ``E_n = E_inf + C r^n`` of the tail of the energies per period (None below 4 periods or
        without energies)."""
        return None if self._energy is None else self._energy.trend

    @property
    def E_inf(self) -> float:
        """Limit of the energy dissipated per period, in :attr:`energy_unit` (NaN below 4 periods): zero for a
        shakedown, positive for cyclic slip and ratcheting."""
        return math.nan if self.energy_trend is None else self.energy_trend.D_inf

    @property
    def E_inf_error(self) -> float:
        """Standard error of :attr:`E_inf` (NaN below 4 periods)."""
        return math.nan if self.energy_trend is None else self.energy_trend.D_inf_error


#: The derived attributes of :class:`CycleResult` made with the record (cached properties, in an order in which each
#: finds what it reads made).
_MADE_WITH_THE_RECORD = ("x", "increment_per_period", "twist_per_period", "dissipation_per_period", "_classified",
                         "final_zones", "stick_halfwidth")


@dataclass(frozen=True, eq=False)
class CycleResult(PeriodVerdict):
    """The transient of a rocking contact, on a line or a patch of elements: per step, per period, its verdict.

    One result type for every body and grid shape (:func:`core.march.engine.run`
    builds it). Normalised units throughout: lengths in the nominal half-width
    ``a`` (a point contact: its semi-axis along x), pressure in the nominal
    ``p0``, tractions in ``mu p0``, loads ``Q`` in ``mu P`` (so ``Q = ft`` at
    constant load; a point contact: ``mu Fn``), displacements in ``mu P / E*``
    (``P = Fn / L``; a point contact: ``mu Fn/(E* a)``, :attr:`increment_unit`),
    positive in the direction of ``Ft``.

    On a patch (:attr:`is_patch`) the per-element per-step fields are those of
    the cut ``y = 0`` (the grid's middle row, :attr:`cut_row`): ``traction``
    has both components, ``(steps, 2, nx)``; the full fields are stored at
    ``snapshot_steps`` (the end of the loading, the turning points, the last
    step). The former point-contact names remain: ``x_edges`` (``edges``),
    ``traction_cut`` (``traction``), ``state_cut`` (``state``).

    Attributes
    ----------
    edges : ndarray, shape (n + 1,)
        Edges of the world-fixed elements (along x).
    xc, P, Q : ndarray, shape (steps,)
        The schedule: contact centre, normal load (in nominal ``P``) and
        tangential load (in ``mu P``) at each step.
    period : ndarray of int, shape (steps,)
        Period index of each step; -1 for the initial loading.
    traction : ndarray, shape (steps, n) or (steps, 2, nx)
        Element tractions at the end of each step (a patch: on the cut).
    state : ndarray of int8, shape (steps, n) or (steps, nx)
        Element state per step (:class:`core.base.states.State`): :data:`STATE_RELEASED` (out of contact),
        :data:`STATE_STICK`, :data:`STATE_SLIP_FORWARD` (slip increment in
        +x), :data:`STATE_SLIP_BACKWARD`.
    displacement : ndarray, shape (steps,) or (steps, 2)
        Rigid-body displacement after each step (a patch: both components).
        For the plane-strain kernel only differences are meaningful (a 2D
        rigid displacement is defined up to a constant).
    dissipation : ndarray, shape (steps,)
        Frictional work of each step, ``sum q s dx`` (>= 0).
    iterations : ndarray of int, shape (steps,)
        Active-set iterations of each step (0: nothing slipped, or a copied period).
    cg_iterations : ndarray of int, shape (steps,)
        Conjugate-gradient iterations of each step (0 for ``"dense"``, which
        solves its stick set directly).
    kkt_residual : ndarray, shape (steps,)
        Worst KKT residual of each step (the largest of :attr:`residuals`' kinds).
    kernel : str
        ``"plane"`` (plane strain), ``"strip"`` (truncated 3D strip) or ``"halfspace"`` (a patch).
    u0 : float or None
        Strip kernel only: ``U0``, the displacement at ``ft = 1``, in ``mu P/E*``.
    periodic_from : int or None
        Period from which the state repeated and later periods were copied
        instead of recomputed (the one rule of :mod:`core.march.engine`), or None.
    params : dict
        The inputs of the run.
    tol : float
        KKT tolerance the steps were solved to.
    shakedown_rtol : float
        Relative tolerance on the increment per period for the verdict.
    runtime : float
        Wall time of the solve [s].
    body : object
        The body object with its parameters (``core.Cylinder()``,
        ``core.Punch(flat=0.8)``, ``core.Ellipsoid(2.0)``, a height map...);
        :attr:`body_name` is its name.
    solver : str
        Per-step solver that ran (``"dense"``, ``"fft"`` or ``"pcg3d"``).
    residuals : dict
        Worst of each named KKT residual over the steps
        (:data:`core.base.states.RESIDUAL_NAMES`): ``stick_slip`` (slip on the
        stick set), ``bound`` (``|q|`` above ``mu p``), ``slip_direction``
        (slip against the traction), ``out_of_contact`` (traction outside the
        contact), ``load_balance`` (the tractions' sum against the load).
    lowest_pressure : ndarray, shape (n,) or (ny, nx)
        Lowest element pressure of the last period [p0] (the whole patch).
    y_edges : ndarray or None
        A patch's edges along y (None on a line).
    nu : float or None
        A patch's substrate Poisson ratio.
    angle : float
        Angle of ``Ft`` to the rocking direction x [rad] (0 on a line).
    snapshot_steps, traction_snapshots, state_snapshots : ndarray or None
        A patch's stored full fields: the steps, ``(k, 2, ny, nx)`` and ``(k, ny, nx)``.
    step_residuals : dict or None
        A patch's named residuals of every step.
    rotation : ndarray or None
        A patch body free to turn about the normal (its ``twist_centre``, the
        cone): its rotation about the normal after each step [mu Fn/(E* a^2)
        rad], ``displacement`` then that of the twist centre; None otherwise
        (per period: :attr:`twist_per_period`).
    pressures : ndarray, shape (k, n) or (k, ny, nx), or None
        The distinct element pressures [p0] the run used, its traction bound
        ``mu p`` [mu p0] (:func:`core.march.engine.run` keeps them as it marches;
        a copied period's steps share the rows of the period they repeat, a
        patch's steps with the same centre and load share one field).
    pressure_index : ndarray of int, shape (steps,), or None
        The row of :attr:`pressures` of each step (:attr:`pressure`,
        :meth:`pressure_at`).
    melan_limit : tuple of float or None
        Melan's limit of this run's discrete problem: ``(lo, hi)`` of the
        tangential load [``mu P``, the unit of :attr:`Q`: ``ft``] below which it
        shakes down and above which it ratchets, or None
        (:func:`core.march.engine.melan_limit` computes it when the run ends:
        ``sum mu p_min dA`` over the lowest pressure of the last period with no
        moment to balance, ``lo = hi``; a body free to turn about the normal,
        the cone, solves its linear programme; None when the tangential load
        varies over the last period). A coupled run's (:attr:`coupled`) is the
        uncoupled contact's, a reference only: Melan's theorem does not hold
        with coupling, and the verdict does not use it.
    beta : float
        Dundurs' ``beta`` of the run (:mod:`core.theory.materials`; 0: uncoupled).
    mu : float or None
        The friction coefficient of a coupled run (None when uncoupled: it plays no part).

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
    body: object = None
    solver: str = "dense"
    residuals: dict = field(default_factory=dict)
    cg_iterations: np.ndarray | None = None
    lowest_pressure: np.ndarray | None = None
    y_edges: np.ndarray | None = None
    nu: float | None = None
    angle: float = 0.0
    snapshot_steps: np.ndarray | None = None
    traction_snapshots: np.ndarray | None = None
    state_snapshots: np.ndarray | None = None
    step_residuals: dict | None = None
    rotation: np.ndarray | None = None
    pressures: np.ndarray | None = None
    pressure_index: np.ndarray | None = None
    melan_limit: tuple[float, float] | None = None
    beta: float = 0.0
    mu: float | None = None

    @property
    def coupled(self) -> bool:
        """Whether the normal and tangential problems were solved together (``beta != 0``): then
        :attr:`melan_limit` is the uncoupled reference, not the limit."""
        return self.beta != 0.0

    def __post_init__(self):
        if self.body is None or isinstance(self.body, str):
            raise ValueError(f"body must be a body object (core.make_body(name) builds one from a name), "
                             f"got {self.body!r:.60}")
        if (self.pressures is None) != (self.pressure_index is None):
            raise ValueError("pressures and pressure_index must be given together")
        if self.melan_limit is not None:
            object.__setattr__(self, "melan_limit", tuple(float(v) for v in self.melan_limit))
        if self.cg_iterations is None:
            object.__setattr__(self, "cg_iterations", np.zeros(self.iterations.shape, dtype=np.int64))
        object.__setattr__(self, "residuals", {k: np.float64(v) for k, v in self.residuals.items()})
        for name, value in vars(self).items():
            if isinstance(value, np.ndarray):
                read_only(value)
            elif isinstance(value, dict):
                for v in value.values():
                    if isinstance(v, np.ndarray):
                        read_only(v)
        if self.lowest_pressure is None and self.pressures is not None:
            last = self.period == self.period[-1]
            object.__setattr__(self, "lowest_pressure",
                               read_only(self.pressures[self.pressure_index[last]].min(axis=0)))
        # a record computes nothing after the run: what it derives (the per-period figures, the verdict and its
        # trends, the final zones) is made here, once, when the run builds it, not when it is first read
        for name in _MADE_WITH_THE_RECORD:
            getattr(self, name)

    # ---- grid ------------------------------------------------------------
    @property
    def is_patch(self) -> bool:
        """True for a patch of elements (a point contact), False for a line."""
        return self.y_edges is not None

    @property
    def increment_unit(self) -> str:
        """Unit of the increments (of ``increment_per_period``, ``D_inf`` and the verdict's reason)."""
        return "mu Fn/(E* a)" if self.is_patch else "mu P/E*"

    @property
    def body_name(self) -> str:
        """The body's name (``"cylinder"``, ``"punch"``, ``"sphere"``, ...)."""
        return self.body.name

    @property
    def body_spec(self):
        """The body object: :attr:`body` (the former name, kept for old callers)."""
        return self.body

    @cached_property
    def x(self) -> np.ndarray:
        """Element centres [a] (along x)."""
        return read_only(0.5 * (self.edges[1:] + self.edges[:-1]))

    @property
    def y(self) -> np.ndarray | None:
        """A patch's element centres along y [a] (None on a line)."""
        return None if self.y_edges is None else 0.5 * (self.y_edges[1:] + self.y_edges[:-1])

    @property
    def x_edges(self) -> np.ndarray:
        """The edges along x: :attr:`edges`."""
        return self.edges

    @property
    def cut_row(self) -> int | None:
        """A patch's row on ``y = 0``, where ``traction`` and ``state`` are taken (None on a line)."""
        return None if self.y_edges is None else (self.y_edges.size - 1) // 2

    @property
    def traction_cut(self) -> np.ndarray:
        """Traction per step on the cut ``y = 0`` of a patch (the line's own traction on a line)."""
        return self.traction

    @property
    def state_cut(self) -> np.ndarray:
        """States per step on the cut ``y = 0`` of a patch (the line's own states on a line)."""
        return self.state

    @property
    def dx(self) -> float:
        """Element width [a]."""
        return float(self.edges[1] - self.edges[0])

    @property
    def periods(self) -> int:
        """Number of rocking periods."""
        return int(self.period.max()) + 1 if self.period.size else 0

    @property
    def elements(self) -> int:
        """Number of elements of the grid."""
        n = self.edges.size - 1
        return n if self.y_edges is None else n * (self.y_edges.size - 1)

    # ---- per step ----------------------------------------------------------
    @property
    def pressure(self) -> "PerStep":
        """The element pressure [p0] of every step, the traction bound [mu p0] the solver used, on either grid:
        ``result.pressure[k]`` is step ``k``'s, shape (n,) on a line, (ny, nx) on a patch;
        ``np.asarray(result.pressure)`` all of them, shape (steps, n) or (steps, ny, nx). A :class:`PerStep`
        over the distinct bounds the run kept (``pressures``, ``pressure_index``); ``result.pressure(k)`` (the
        former point-contact call) is ``result.pressure[k]``."""
        if self.pressures is None:
            raise ValueError("this result was built without its pressures (pressures, pressure_index): "
                             "core.march.engine.run keeps them")
        return PerStep(self.pressures, self.pressure_index)

    def pressure_at(self, step) -> np.ndarray:
        """Element pressure [p0] at ``step``: ``result.pressure[step]``."""
        return self.pressure[step]

    @property
    def final_traction(self) -> np.ndarray:
        """Traction after the last step: shape (n,) on a line, (2, ny, nx) on a patch."""
        return self.traction_snapshots[-1] if self.is_patch else self.traction[-1]

    @property
    def final_state(self) -> np.ndarray:
        """States after the last step: shape (n,) on a line, (ny, nx) on a patch."""
        return self.state_snapshots[-1] if self.is_patch else self.state[-1]

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
        """Rigid-body displacement increment of each period [:attr:`increment_unit`], along Ft."""
        ends = self._period_ends()
        along = self.displacement
        if along.ndim == 2:  # a patch: the component along Ft
            along = along @ np.array([math.cos(self.angle), math.sin(self.angle)])
        disp = along[ends]
        if self.period[0] < 0:  # first block is the loading
            return read_only(np.diff(disp))
        return read_only(np.diff(np.concatenate([[0.0], disp])))

    @cached_property
    def twist_per_period(self) -> np.ndarray | None:
        """Rotation about the normal of each period [mu Fn/(E* a^2) rad] of a patch free to turn (a cone's
        :attr:`rotation`; its displacement is then that of the twist centre); None otherwise."""
        if self.rotation is None:
            return None
        rot = self.rotation[self._period_ends()]
        return read_only(np.diff(rot) if self.period[0] < 0 else np.diff(np.concatenate([[0.0], rot])))

    @property
    def energy_unit(self) -> str:
        """Unit of :attr:`dissipation_per_period` (and ``E_inf``): ``mu^2 P^2/E*`` per unit length on a line,
        ``mu^2 Fn^2/(E* a)`` on a patch."""
        return "mu^2 Fn^2/(E* a)" if self.is_patch else "mu^2 P^2/E*"

    @cached_property
    def dissipation_per_period(self) -> np.ndarray:
        """Energy dissipated by friction in each period [:attr:`energy_unit`] (the loading block left out).

        The sum over the period's steps of :attr:`dissipation`. On a line the
        steps store ``sum q s dx`` in ``mu p0 a * mu P/E*``; the nominal load is
        ``P = load_factor * p0 a`` (``pi/2`` for Hertz), so the sum is divided by
        the body's ``load_factor`` to give ``mu^2 P^2/E*`` per unit length. On a
        patch the steps are already divided by the load (``mu^2 Fn^2/(E* a)``).
        Zero in a shakedown, the area of the fretting loop in cyclic slip
        (:meth:`fretting_loop`), ``Q`` times the walk per period when the
        tangential load is constant and the body ratchets.
        """
        periods = self.period
        keep = periods >= 0
        energy = np.bincount(periods[keep], weights=self.dissipation[keep], minlength=self.periods)
        if not self.is_patch:
            energy = energy / float(getattr(self.body, "load_factor", 0.5 * math.pi))
        return read_only(energy)

    def fretting_loop(self, period: int = -1) -> FrettingLoop:
        """The fretting loop of one period: the tangential load against the rigid-body displacement along it.

        What a fretting rig records, from the stored steps (nothing is solved
        again): the last step of the period before (the loading's for the first
        period) and every step of ``period``. Its area, the work ``int Q dD`` of
        the tangential load over the period, is the energy dissipated in it once
        the state is steady (the elastic energy returns; uncoupled contact: the
        normal load does no work on the tangential displacements). Under a
        constant load (the rocking histories) the loop is a horizontal segment
        and its work is ``Q`` times the walk of the period.

        Parameters
        ----------
        period : int
            The period, from 0 (negative: counted from the last, -1 the last one).

        Returns
        -------
        FrettingLoop

        Raises
        ------
        ValueError
            If ``period`` is not a period of the run.

        Examples
        --------
        >>> import core
        >>> r = core.simulate_cycles(0.0, 0.0, periods=3, history="tangential", amplitude=0.5, dx=0.05)
        >>> loop = r.fretting_loop()
        >>> round(loop.work, 3), round(float(r.dissipation_per_period[-1]), 3)
        (0.036, 0.036)
        """
        n = self.periods
        if isinstance(period, bool) or not isinstance(period, (int, np.integer)) or not -n <= period < n:
            raise ValueError(f"period must be an integer in [{-n}, {n - 1}] (the run has {n} periods), "
                             f"got {period!r}")
        period = int(period) % n
        steps = np.flatnonzero(self.period == period)
        if steps[0] > 0:
            steps = np.concatenate([[steps[0] - 1], steps])
        along = self.displacement
        if along.ndim == 2:
            along = along @ np.array([math.cos(self.angle), math.sin(self.angle)])
        Q, D = self.Q[steps], along[steps]
        work = float(np.sum(0.5 * (Q[1:] + Q[:-1]) * np.diff(D)))
        return FrettingLoop(period=period, Q=read_only(Q.copy()), displacement=read_only(D - D[0]), work=work,
                            energy=float(self.dissipation_per_period[period]), load_unit="mu Fn" if self.is_patch
                            else "mu P", displacement_unit=self.increment_unit, energy_unit=self.energy_unit)

    # ---- the final state ---------------------------------------------------
    @cached_property
    def final_zones(self) -> np.ndarray:
        """Zones of the final traction on the line (a patch: its cut) (:class:`core.base.states.Zone`): stick (below
        mu p_min), slip (at or above mu p_min), released (zero traction), none (never in contact).

        The zones are those of the traction at the last step against the lowest pressure of the last period
        (:attr:`lowest_pressure`), the same test as :attr:`stick_halfwidth`. ``zero traction`` marks the
        elements that lose contact during the last period (their lowest pressure is 0), were in contact at
        some step and carry no traction at the last step (below :data:`ZERO_TRACTION`); such an element that
        still carries traction (a run that ratchets: it slips again every period) is in the slip zone.
        """
        if self.is_patch:
            bound = self.lowest_pressure[self.cut_row]
            q = self.traction[-1]
            magnitude = np.hypot(q[0], q[1])
            ever = (self.state != State.RELEASED).any(axis=0)
        else:
            bound, magnitude = self.lowest_pressure, np.abs(self.traction[-1])
            ever = (self.pressure.rows > 0).any(axis=0)  # in contact at any step: any distinct bound positive
        stick = below_bound(magnitude, bound)
        loaded = (bound > 0) | (magnitude > ZERO_TRACTION)
        zones = np.where(stick, Zone.STICK, np.where(loaded, Zone.SLIP, np.where(ever, Zone.RELEASED, Zone.NONE)))
        return read_only(zones.astype(np.int8))

    @cached_property
    def stick_halfwidth(self) -> float:
        """``c_sd / a``: half-width of the central zone whose final traction stays below mu p_min (a patch: on ``y = 0``).

        Outside it the traction sits at ``mu`` times the lowest pressure of the
        last period, or is zero where contact was lost. 0 if there is no such zone.
        """
        return central_halfwidth(self.final_zones == Zone.STICK, self.edges)

    @property
    def max_kkt_residual(self) -> float:
        """Worst KKT residual over all steps."""
        return float(self.kkt_residual.max()) if self.kkt_residual.size else 0.0

    @property
    def max_residual(self) -> float:
        """:attr:`max_kkt_residual` (the former point-contact name)."""
        return self.max_kkt_residual

    def _energy_summary(self) -> dict:
        """The energy figures of :meth:`summary`: the last period's, its limit with its error, their unit."""
        energy = self.dissipation_per_period
        return {"energy_last_period": float(energy[-1]) if energy.size else float("nan"), "E_inf": self.E_inf,
                "E_inf_error": self.E_inf_error, "energy_unit": self.energy_unit}

    def summary(self) -> dict:
        """Scalar figures of the run (for tables, CSV headers, the CLI): the same keys in the same order for every
        body and grid; a figure that does not apply is None (a line's ``ratio`` and ``twist_last_period``, a
        patch's ``u0``)."""
        inc = self.increment_per_period
        twist = None if self.rotation is None else float(self.twist_per_period[-1])
        return {
            "dx": self.dx,
            **self.params,
            "body": self.body_name,
            "solver": self.solver,
            "ratio": getattr(self.body, "ratio", None) if self.is_patch else None,
            "regime": self.regime,
            "regime_reason": self.regime_reason,
            "stick_halfwidth": self.stick_halfwidth,
            "shakedown_period": self.shakedown_period,
            "increment_last_period": float(inc[-1]) if inc.size else float("nan"),
            "D_inf": self.D_inf,
            "D_inf_error": self.D_inf_error,
            "decay_ratio": self.decay_ratio,
            "periods_to_decide": self.periods_to_decide,
            **self._energy_summary(),
            "twist_last_period": twist,
            "periods": self.periods,
            "elements": self.elements,
            "steps": int(self.xc.size),
            "periodic_from": self.periodic_from,
            "max_iterations": int(self.iterations.max()) if self.iterations.size else 0,
            "max_cg_iterations": int(self.cg_iterations.max()) if self.cg_iterations.size else 0,
            "max_kkt_residual": self.max_kkt_residual,
            "max_residual": self.max_residual,
            "u0": self.u0,
            "runtime_s": self.runtime,
        }


class _PatchResultType(type):
    """The type of :class:`PointContactResult`: ``isinstance(r, PointContactResult)`` is ``r.is_patch``."""

    def __instancecheck__(cls, obj):
        return isinstance(obj, CycleResult) and obj.is_patch

    def __subclasscheck__(cls, sub):
        return sub is cls

    def __call__(cls, *, body, x_edges, traction_cut, state_cut, residuals, nu=0.5, angle=0.0, **fields):
        warnings.warn("PointContactResult is CycleResult (one result type for every body): build a CycleResult",
                      DeprecationWarning, stacklevel=2)
        steps = residuals and np.max(np.stack(list(residuals.values())), axis=0)
        worst = {k: float(np.max(v)) for k, v in residuals.items()}
        fields.setdefault("kernel", "halfspace")
        fields.setdefault("u0", None)
        fields.setdefault("solver", "pcg3d")
        return CycleResult(body=body, edges=x_edges, traction=traction_cut, state=state_cut, residuals=worst,
                           step_residuals=dict(residuals), kkt_residual=steps, nu=nu, angle=angle, **fields)


class PointContactResult(metaclass=_PatchResultType):
    """Deprecated: a point contact's result is a :class:`CycleResult` on a patch (``is_patch``).

    Kept importable so that ``isinstance(r, PointContactResult)`` still tells a
    patch result from a line one; building one builds a :class:`CycleResult`
    from the former keywords (``x_edges``, ``traction_cut``, ``state_cut``,
    per-step ``residuals``).
    """


class _LineResultType(type):
    """The type of :class:`LineResult`: ``isinstance(r, LineResult)`` is ``not r.is_patch``."""

    def __instancecheck__(cls, obj):
        return isinstance(obj, CycleResult) and not obj.is_patch

    def __subclasscheck__(cls, sub):
        return sub is cls


class LineResult(metaclass=_LineResultType):
    """A :class:`CycleResult` on a line of elements, for ``isinstance`` checks (the counterpart of
    :class:`PointContactResult`): code that draws only line runs (the cylinder's figures) tests for it."""
