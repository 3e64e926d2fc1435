"""Loading histories as data: named recipes that build a :class:`~core.loading.schedule.Schedule`.

A history is the list of quasi-static steps a run is driven by: at each step
the contact centre ``xc`` [a], the normal load ``P`` [nominal P] and the
tangential load ``Q`` [mu P_nominal], and the period the step belongs to (-1
for the initial loading). Every recipe validates its inputs (``ValueError``
naming the parameter and its range) and returns a :class:`Schedule`, which a
run takes as it is (:func:`core.solve_schedule`):

* :func:`rocking`: the paper's history (Wetter 2015, section 3: ``Ft``
  applied at ``xc = 0``, then periods of rocking ``0 -> +W -> -W -> 0``, with
  triangle or sine motion), optionally with a normal force oscillating in the
  period with a given amplitude and phase (the paper's outlook);
* :func:`tangential`: a fixed centre under a tangential force oscillating
  about its mean (fretting: Mindlin's hysteresis loop);
* :func:`from_arrays`: any per-step arrays the user gives.

:data:`HISTORIES` maps their names to them, :func:`history` builds one by name. The named recipes take a
loading path (:class:`core.loading.paths.LoadingPath`: the order and steps in which the loads are raised, where, the
first direction of the oscillation, earlier periods at other loads), all of it in the loading block;
:func:`with_path` puts it in front of the periods.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..base._validate import check_int, check_scalar
from .paths import as_path
from .schedule import MAX_STEPS, SHAPES, Schedule, rocking_schedule

__all__ = ["rocking", "tangential", "from_arrays", "history", "HISTORIES", "NAMED", "for_run", "with_path"]


def _phases(schedule: Schedule) -> np.ndarray:
    """Phase in [0, 1] of every step within its period (the loading steps: 0)."""
    rocking_steps = schedule.period >= 0
    m = int(np.count_nonzero(schedule.period == 0))
    phase = np.zeros(len(schedule))
    phase[rocking_steps] = np.tile(np.arange(1, m + 1) / m, schedule.periods)
    return phase


def rocking(ft, w, periods=10, dW=0.025, shape="triangle", load_steps=1, normal_amplitude=0.0, normal_phase=0.0,
            path=None):
    """Rocking under a constant tangential force, optionally with an oscillating normal force.

    Parameters
    ----------
    ft, w, periods, dW, shape, load_steps :
        As in :func:`core.loading.schedule.rocking_schedule` (the centre moves
        ``0 -> W -> -W -> 0`` every period, as a triangle or a sine).
    normal_amplitude : float
        Relative amplitude ``A`` of the normal force, in [0, 1):
        ``P = 1 + A sin(2 pi t + phi)`` with ``t`` the phase of the step in its
        period (``t = 1/4`` where the centre reaches ``+W``); the loading is
        at ``P = 1 + A sin(phi)``. ``|ft| < 1 - A`` keeps every step below
        gross sliding.
    normal_phase : float
        Phase ``phi`` of the normal force [rad], finite.
    path : LoadingPath, str or dict, optional
        The loading path (:class:`core.loading.paths.LoadingPath`, :func:`with_path`): default, the loads applied at
        ``xc = 0`` as above. Its preloads are this history at their ``ft`` and ``w``; ``first_direction = -1``
        mirrors the centre (the normal force keeps its phase).

    Returns
    -------
    Schedule

    Examples
    --------
    >>> import math
    >>> from core.loading.histories import rocking
    >>> s = rocking(0.3, 0.5, periods=2, dW=0.125, normal_amplitude=0.2, normal_phase=math.pi / 2)
    >>> round(float(s.P.max()), 6), round(float(s.P.min()), 6)
    (1.2, 0.8)
    """
    s = rocking_schedule(ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps)
    A = check_scalar("normal_amplitude", normal_amplitude, 0.0, 1.0, hi_closed=False)
    phi = check_scalar("normal_phase", normal_phase)
    if A != 0.0:
        P = 1.0 + A * np.sin(2.0 * np.pi * _phases(s) + phi)
        if np.max(np.abs(s.Q) / P) >= 1.0:
            raise ValueError(f"normal_amplitude = {A:g} with ft = {float(ft):g} reaches gross sliding "
                             f"(|ft| < P at every step needs |ft| < {P.min():.4g}): use a smaller amplitude or ft")
        s = Schedule(xc=s.xc, P=P, Q=s.Q, period=s.period)
    path = as_path(path)
    if path.is_default:
        return s

    def build(f, amplitude, n):  # the same history at a preload's ft and w
        return rocking(f, amplitude, periods=n, dW=dW, shape=shape, load_steps=load_steps, normal_amplitude=A,
                       normal_phase=phi)

    return with_path(s, path, build, float(ft), w=float(w), dW=float(dW), load_steps=int(load_steps))


def tangential(ft, amplitude, periods=10, steps_per_period=40, shape="sine", load_steps=1, path=None):
    """A fixed contact under a tangential force oscillating about its mean ``ft``.

    Parameters
    ----------
    ft : float
        Mean tangential force ``Ft / (mu Fn)``, in (-1, 1).
    amplitude : float
        Amplitude of the oscillation ``Q = ft + amplitude f(t)`` [mu P], >= 0,
        with ``|ft| + amplitude < 1`` (below gross sliding).
    periods : int
        Periods, in [1, 10000].
    steps_per_period : int
        Steps of each period, a multiple of 4 in [4, 100000] (the extremes are steps).
    shape : {"triangle", "sine"}
        ``f(t)``: a triangle or ``sin(2 pi t)``, both with extremes at ``t = 1/4`` and ``3/4``.
    load_steps : int
        Steps of the initial loading to ``ft``, in [1, 10000].
    path : LoadingPath, str or dict, optional
        The loading path (:class:`core.loading.paths.LoadingPath`, :func:`with_path`): default, the force raised to
        ``ft`` then oscillating first up. Its preloads are this history at their ``ft`` and amplitude;
        ``first_direction = -1`` starts every period downwards; ``start_at`` must be 0 (the centre is fixed).

    Returns
    -------
    Schedule
    """
    ft = check_scalar("ft", ft, -1.0, 1.0, lo_closed=False, hi_closed=False)
    amplitude = check_scalar("amplitude", amplitude, 0.0, 1.0 - abs(ft), hi_closed=False)
    periods = check_int("periods", periods, 1, 10_000)
    m = check_int("steps_per_period", steps_per_period, 4, 100_000)
    if m % 4:
        raise ValueError(f"steps_per_period must be a multiple of 4 in [4, 100000], got {m}")
    if shape not in SHAPES:
        raise ValueError(f"shape must be one of {SHAPES}, got {shape!r:.60}")
    load_steps = check_int("load_steps", load_steps, 1, 10_000)
    if load_steps + m * periods > MAX_STEPS:
        raise ValueError(f"the history would have {load_steps + m * periods} steps (> {MAX_STEPS}): "
                         "use fewer periods or fewer steps_per_period")
    t = np.arange(1, m + 1) / m
    if shape == "triangle":
        f = np.where(t <= 0.25, 4 * t, np.where(t <= 0.75, 2 - 4 * t, 4 * t - 4))
    else:
        f = np.sin(2 * np.pi * t)
        f[(4 * np.arange(1, m + 1)) % (2 * m) == 0] = 0.0  # exact zeros at t = 1/2 and 1
    Q = np.concatenate([ft * np.arange(1, load_steps + 1) / load_steps, np.tile(ft + amplitude * f, periods)])
    period = np.concatenate([np.full(load_steps, -1), np.repeat(np.arange(periods), m)])
    s = Schedule(xc=np.zeros(Q.size), P=np.ones(Q.size), Q=Q, period=period)
    path = as_path(path)
    if path.is_default:
        return s

    def build(f, a, n):  # the same history at a preload's ft and amplitude
        return tangential(f, a, periods=n, steps_per_period=m, shape=shape, load_steps=load_steps)

    return with_path(s, path, build, ft, w=0.0, dW=1.0, load_steps=load_steps, oscillates="Q")


def with_path(schedule, path, build, ft, *, w=0.0, dW=0.025, load_steps=1, oscillates="xc"):
    """A named history's schedule with a loading path in front of its periods.

    Every step the path adds is in the loading block (period ``-1``), so that the run's increments, energies
    and verdict are read from the history's own periods, after the path. The steps, in order:

    1. the ramp at the centre ``start_at W``: ``"P-then-Q"``, ``P`` raised in ``ramp_steps`` steps with
       ``Q = 0`` (none when 0), then ``Q`` in ``load_steps`` steps; ``"together"``, both in proportion in
       ``ramp_steps`` steps (``load_steps`` when 0), to the first level of ``Q`` (the first preload's ``ft``,
       else ``ft``) and the loading's ``P``;
    2. the centre back to 0 in steps no larger than ``dW``, under the full loads (when ``start_at != 0``);
    3. each preload's periods (``build(ft_i, amplitude_i, periods_i)``'s periods), ``Q`` moving between the
       levels in ``load_steps`` steps at ``xc = 0``;
    4. ``Q`` to ``ft`` in ``load_steps`` steps, then the schedule's own periods.

    ``first_direction = -1`` mirrors every period: ``xc -> -xc`` (``oscillates="xc"``) or
    ``Q -> 2 ft - Q`` (``oscillates="Q"``: a tangential history).

    Parameters
    ----------
    schedule : Schedule
        The history with the default path (its loading block is replaced; its periods are kept).
    path : LoadingPath, str, dict or None
        The path (:func:`core.loading.paths.as_path`); the default returns ``schedule`` itself.
    build : callable
        ``build(ft, amplitude, periods) -> Schedule``: the same history at other loads (the preloads).
    ft : float
        The history's tangential load, in (-1, 1).
    w : float
        The rocking amplitude [a], in [0, 1) (``start_at`` is a fraction of it).
    dW : float
        Largest step of the centre [a], in (0, 1].
    load_steps : int
        Steps of each change of ``Q``, in [1, 10000].
    oscillates : {"xc", "Q"}
        What the history oscillates (what ``first_direction`` mirrors).

    Returns
    -------
    Schedule

    Raises
    ------
    ValueError
        Naming the parameter or path field out of range (``start_at != 0`` with ``oscillates="Q"``).

    Examples
    --------
    >>> from core.loading.histories import rocking
    >>> s = rocking(0.3, 0.5, periods=1, dW=0.25, path="order=together,ramp=2,start=+W")
    >>> s.xc[:5].tolist(), s.P[:3].tolist(), s.Q[:3].tolist(), s.period[:5].tolist()
    ([0.5, 0.5, 0.25, 0.0, 0.25], [0.5, 1.0, 1.0], [0.15, 0.3, 0.3], [-1, -1, -1, -1, 0])
    """
    path = as_path(path)
    if path.is_default:
        return schedule
    if oscillates not in ("xc", "Q"):
        raise ValueError(f"oscillates must be 'xc' or 'Q', got {oscillates!r:.60}")
    ft = check_scalar("ft", ft, -1.0, 1.0, lo_closed=False, hi_closed=False)
    w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
    dW = check_scalar("dW", dW, 0.0, 1.0, lo_closed=False)
    load_steps = check_int("load_steps", load_steps, 1, 10_000)
    if oscillates == "Q" and path.start_at != 0.0:
        raise ValueError(f"start_at must be 0 for a history at a fixed centre (the tangential one), "
                         f"got {path.start_at:g}")
    loading = schedule.period < 0
    P0 = float(schedule.P[loading][-1] if loading.any() else schedule.P[0])  # the load the periods start at
    xs, Ps, Qs = [], [], []

    def add(xc, P, Q):
        n = max(np.size(xc), np.size(P), np.size(Q))
        for out, arr in ((xs, xc), (Ps, P), (Qs, Q)):
            out.append(np.broadcast_to(np.asarray(arr, dtype=float), (n,)))

    def ramp(n):
        return np.arange(1, n + 1) / n

    def periods_of(s, level):
        rows = s.period >= 0
        xc, P, Q = s.xc[rows], s.P[rows], s.Q[rows]
        if path.first_direction < 0:
            xc, Q = (-xc, Q) if oscillates == "xc" else (xc, 2.0 * level - Q)
        return xc, P, Q

    # 1. the ramp, at the starting centre
    x0 = path.start_at * w
    levels = [f for f, _, _ in path.preload] + [ft]
    if path.order == "P-then-Q":
        if path.ramp_steps:
            r = ramp(path.ramp_steps)
            add(x0, P0 * r, 0.0)
        add(x0, P0, levels[0] * ramp(load_steps))
    else:
        r = ramp(path.ramp_steps or load_steps)
        add(x0, P0 * r, levels[0] * r)
    # 2. the centre back to 0 under the full loads
    if x0 != 0.0:
        add(x0 * (1.0 - ramp(max(1, math.ceil(abs(x0) / dW - 1e-9)))), P0, levels[0])
    # 3. the preloads, then 4. the history's own level and periods
    current = levels[0]
    for i, (f, amplitude, n) in enumerate(path.preload):
        if f != current:
            add(0.0, P0, current + (f - current) * ramp(load_steps))
        try:
            preload = build(f, amplitude, n)
        except ValueError as e:
            raise ValueError(f"preload[{i}] = ({f:g}, {amplitude:g}, {n}) is not a valid history: {e}") from e
        add(*periods_of(preload, f))
        current = f
    if ft != current:
        add(0.0, P0, current + (ft - current) * ramp(load_steps))
    steps = sum(a.size for a in xs)
    xc, P, Q = periods_of(schedule, ft)
    if steps + xc.size > MAX_STEPS:
        raise ValueError(f"the history with its path would have {steps + xc.size} steps (> {MAX_STEPS}): "
                         "use fewer preload periods or fewer periods")
    rows = schedule.period >= 0
    return Schedule(xc=np.concatenate([*xs, xc]), P=np.concatenate([*Ps, P]), Q=np.concatenate([*Qs, Q]),
                    period=np.concatenate([np.full(steps, -1), schedule.period[rows]]))


def from_arrays(xc, P=None, Q=None, period=None):
    """A history from per-step arrays given by the user.

    Parameters
    ----------
    xc : array_like, shape (steps,)
        Contact centre [a], finite.
    P : array_like, optional
        Normal load [nominal P], > 0; default 1.
    Q : array_like, optional
        Tangential load [mu P_nominal], ``|Q| < P``; default 0.
    period : array_like of int, optional
        Period of each step, non-decreasing from -1 or 0; default 0 (one block).

    Returns
    -------
    Schedule
        Validated (the message names the offending array).
    """
    xc = np.atleast_1d(np.asarray(xc, dtype=float) if not isinstance(xc, (str, bytes)) else xc)
    n = xc.shape[0] if xc.ndim >= 1 else 1
    P = np.ones(n) if P is None else P
    Q = np.zeros(n) if Q is None else Q
    period = np.zeros(n, dtype=np.int64) if period is None else np.asarray(period)
    return Schedule(xc=xc, P=P, Q=Q, period=period)


#: The named histories.
HISTORIES = {"rocking": rocking, "tangential": tangential, "arrays": from_arrays}


def history(name, **params):
    """Build the history ``name`` of :data:`HISTORIES` with its parameters.

    Raises
    ------
    ValueError
        If ``name`` is unknown (the message lists the names) or a parameter is invalid.
    """
    if name not in HISTORIES:
        raise ValueError(f"history must be one of {sorted(HISTORIES)}, got {name!r:.60}")
    return HISTORIES[name](**params)


#: The histories :func:`core.simulate_cycles` takes by name (its ``history`` keyword).
NAMED = ("rocking", "normal", "tangential")


def default_amplitude(history, ft, amplitude=None):
    """``amplitude`` of a named history, or its default: 0.2 (``"normal"``), ``(1 - |ft|)/2`` (``"tangential"``)."""
    if amplitude is not None or history not in ("normal", "tangential"):
        return amplitude
    return 0.2 if history == "normal" else 0.5 * (1.0 - abs(float(ft)))


def for_run(history, ft, w, *, periods=10, dW=0.025, shape="triangle", load_steps=1, amplitude=None, phase=0.0,
            path=None):
    """The :class:`Schedule` of :func:`core.simulate_cycles`'s ``history`` keyword.

    Parameters
    ----------
    history : str, Schedule or mapping
        A name of :data:`NAMED`:

        * ``"rocking"``: the paper's (Wetter 2015, section 3): ``Ft`` applied at
          ``xc = 0``, then the centre rocked ``0 -> W -> -W -> 0`` (``shape``:
          triangle or sine) under constant loads; ``amplitude`` must be None or 0;
        * ``"normal"``: the same rocking under the normal force
          ``P = 1 + amplitude sin(2 pi t + phase)`` (``amplitude`` in [0, 1), default 0.2;
          ``phase`` [rad]; see :func:`rocking`);
        * ``"tangential"``: the centre fixed at 0 (``w`` unused) and the tangential force
          ``ft + amplitude f(t)`` with ``f`` of ``shape`` (``amplitude`` default
          ``(1 - |ft|) / 2``), ``4 ceil(1 / (4 dW))`` steps a period (see :func:`tangential`);

        or a :class:`Schedule` (run as it is: ``ft``, ``w`` and the other options are
        unused), or a mapping of per-step arrays ``xc`` and optionally ``P``, ``Q``,
        ``period`` (:func:`from_arrays`).
    ft, w, periods, dW, shape, load_steps :
        As in :func:`core.simulate_cycles`.
    amplitude : float, optional
        Amplitude of the oscillating load (see above).
    phase : float
        Phase of the normal force [rad] (``"normal"``), finite.
    path : LoadingPath, str or dict, optional
        The loading path of a named history (:class:`core.loading.paths.LoadingPath`: ramps, preloads, first
        direction; :func:`with_path`); default, the history's own loading. A schedule or arrays take none.

    Returns
    -------
    Schedule

    Raises
    ------
    ValueError
        Naming ``history`` if it is none of these, or the parameter that is out of range.

    Examples
    --------
    >>> from core.loading.histories import for_run
    >>> s = for_run("tangential", 0.2, 0.0, periods=2, dW=0.05, amplitude=0.3)
    >>> len(s), float(s.Q.max()), float(s.xc.max())
    (41, 0.5, 0.0)
    """
    path = as_path(path)
    if not path.is_default and not isinstance(history, str):
        raise ValueError(f"path must be the default with a history given as a schedule or arrays (its steps are "
                         f"run as they are), got path {str(path)!r:.80}")
    if isinstance(history, Schedule):
        return history
    if isinstance(history, Mapping):
        unknown = sorted(set(map(str, history)) - {"xc", "P", "Q", "period"})
        if unknown or "xc" not in history:
            raise ValueError("history as arrays must be a mapping with 'xc' and optionally 'P', 'Q', 'period', "
                             f"got keys {sorted(map(str, history))!r:.80}")
        return from_arrays(**history)
    if not isinstance(history, str) or history not in NAMED:
        raise ValueError(f"history must be one of {NAMED}, a core.Schedule or a mapping of arrays, "
                         f"got {history!r:.60}")
    phase = check_scalar("phase", phase)
    amplitude = default_amplitude(history, ft, amplitude)
    if history == "rocking":
        if amplitude not in (None, 0, 0.0):
            raise ValueError(f"amplitude must be None or 0 with history='rocking' (use history='normal' or "
                             f"'tangential' for an oscillating load), got {amplitude!r:.60}")
        if path.is_default:
            return rocking_schedule(ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps)
        return rocking(ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps, path=path)
    if history == "normal":
        amplitude = check_scalar("amplitude", amplitude, 0.0, 1.0, hi_closed=False)
        return rocking(ft, w, periods=periods, dW=dW, shape=shape, load_steps=load_steps,
                       normal_amplitude=amplitude, normal_phase=phase, path=path)
    dW = check_scalar("dW", dW, 1e-4, 1.0)
    return tangential(ft, amplitude, periods=periods, steps_per_period=4 * math.ceil(1.0 / (4.0 * dW) - 1e-9),
                      shape=shape, load_steps=load_steps, path=path)

