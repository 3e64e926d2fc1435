"""The data of the paper's parametric figures (Figs 10-16), from the solver beside the paper's formulas.

Every function here returns plain, JSON-ready data (dicts of lists of
floats): what the solver gives and what the paper's closed form or regression
gives at the same points, and the largest difference between them. The app
(``app/paper_figures.py``) draws the shipped copy of this data and can
recompute it; the command line writes it::

    python -m core.maps.paper_figures --out app/data/paper_figures.json

The solver runs in the paper's own numerical model (eq 17: the truncated-3D
strip of length ``L`` of :data:`core.PAPER_SIMULATION`, ``L/a = 292.6``,
``nu = 0.5``), so that displacements are ``u = U/U0`` (eq 20) as in the
paper. The shaken-down states (Figs 10-13, 15) are computed directly as one
static partial-slip problem with the bound ``mu p_min``
(:func:`core.api.solver.shakedown_state`; it equals the end of the transient,
``tests/test_solver.py`` and ``tests/test_paper_figures.py``); the limit
(Fig 14) and the ratcheting increments (Fig 16) come from transients
(:func:`core.simulate_cycles`).

References
----------
.. [1] R. Wetter, Physical Mesomechanics 18 (2015): eqs 13, 20, 22-26, 30,
   31, 34-38 and Figs 10-16.
"""

from __future__ import annotations

import argparse
import json
import platform
import shlex
import sys
import threading
import time
from pathlib import Path

import numpy as np

from ..theory import approximations
from ..base._validate import check_int, check_scalar
from ..theory.analytical import ft_limit, shakedown_stick_halfwidth, shakedown_traction, w_limit
from ..bounds.limits import w_limit as body_w_limit
from ..api.contact import PAPER_SIMULATION, strip_options
from ..elastic.kernels import strip_b_coefficient, strip_influence, strip_u0
from ..api.solver import make_grid, shakedown_state, simulate_cycles
from .sweeps import SweepCancelled, numerical_limit_curve

__all__ = ["FIGURES", "FiguresCancelled", "PAPER_W", "COMMAND", "paper_model", "time_in_periods", "stick_halfwidth_curves", "traction_profiles",
           "shakedown_displacement_curves", "limit_curve", "limit_lines", "limit_displacement_curve",
           "ratchet_increment_curves", "compute", "save", "load", "main"]

#: The amplitudes of the paper's Figs 6, 7, 12, 13 and 16.
PAPER_W = (0.26, 0.52, 0.77)
#: The command that makes the shipped data (run from the repository root).
COMMAND = "python -m core.maps.paper_figures --out app/data/paper_figures.json"
#: Significant digits kept in the data (the solver is converged far beyond them).
DIGITS = 7


class FiguresCancelled(RuntimeError):
    """A computation of the figures was stopped on request."""


def paper_model() -> dict:
    """The solver options of the paper's numerical model (eq 17): the strip kernel of its ``L / a`` and ``nu``.

    Returns
    -------
    dict
        ``kernel="strip"``, ``L_over_a`` and ``nu`` (:func:`core.strip_options`
        of :data:`core.PAPER_SIMULATION`).

    Examples
    --------
    >>> m = paper_model()
    >>> m["kernel"], round(m["L_over_a"], 1), m["nu"]
    ('strip', 292.6, 0.5)
    """
    return {"kernel": "strip", **strip_options(PAPER_SIMULATION)}


def time_in_periods(result) -> np.ndarray:
    """The time of each step of a run in periods, the abscissa of the paper's Figs 6 and 7.

    Period ``p``'s steps fill ``(p, p + 1]``; the loading (period -1) is drawn in ``(-1, 0]``.

    Parameters
    ----------
    result : CycleResult
        A run (its ``period`` array numbers each step's period).

    Returns
    -------
    ndarray, shape (steps,)

    Examples
    --------
    >>> import core
    >>> from core.maps.paper_figures import time_in_periods
    >>> t = time_in_periods(core.simulate_cycles(0.3, 0.5, periods=2, dx=0.1))
    >>> float(t[0]) > -1.0, float(t[-1])
    (True, 2.0)
    """
    period = np.asarray(result.period)
    t = np.empty(period.size)
    for p in np.unique(period):
        idx = np.flatnonzero(period == p)
        t[idx] = p + np.arange(1, idx.size + 1) / idx.size
    return t


def _u0(model: dict) -> float:
    """``U0`` of the model [mu P/E*] (the strip's displacement at ``ft = 1``, eq 14)."""
    return strip_u0(model["L_over_a"], strip_b_coefficient(model["nu"]))


def _round(v):
    """Plain floats (lists for arrays) with :data:`DIGITS` significant digits; NaN becomes None."""
    a = np.asarray(v, dtype=float)
    out = [None if not np.isfinite(t) else float(f"{t:.{DIGITS}g}") for t in a.ravel()]
    return out[0] if a.ndim == 0 else out


def _max_abs(*pairs) -> float:
    """Largest ``|a - b|`` over pairs of arrays (NaN ignored)."""
    diffs = [np.abs(np.asarray(a, float) - np.asarray(b, float)) for a, b in pairs]
    finite = np.concatenate([d[np.isfinite(d)] for d in diffs]) if diffs else np.zeros(0)
    return float(finite.max()) if finite.size else float("nan")


class _Steps:
    """Progress ``progress(done, total)`` and cancellation (``cancel.is_set()``) of one figure's points."""

    def __init__(self, total: int, progress=None, cancel=None):
        self.total, self.done = int(total), 0
        self.progress, self.cancel = progress, cancel
        self.report()

    def report(self):
        if self.progress is not None:
            self.progress(self.done, self.total)

    def check(self):
        if self.cancel is not None and self.cancel.is_set():
            raise FiguresCancelled(f"cancelled after {self.done} of {self.total} points")

    def step(self):
        self.done += 1
        self.report()


def _ft_grid(ft_max: float, points: int, lo: float = 0.02) -> np.ndarray:
    """``points`` values of ``ft`` in ``[lo, 0.99 ft_max]``, denser near the top (where the curves bend)."""
    s = np.linspace(0.0, 1.0, points)
    return lo + (0.99 * ft_max - lo) * (1.0 - (1.0 - s) ** 1.5)


# --------------------------------------------------------------------------
# Fig 10: c_sd / a against ft
# --------------------------------------------------------------------------
def stick_halfwidth_curves(w_values=(0.0, *PAPER_W), points=16, dx=1 / 400, *, progress=None, cancel=None) -> dict:
    """Fig 10: the stick half-width after shakedown ``c_sd / a`` against ``ft``, solver and eq 30.

    Parameters
    ----------
    w_values : sequence of float
        Amplitudes ``W / a`` in [0, 1) (``w = 0``: Cattaneo, ``c/a = sqrt(1 - ft)``).
    points : int
        Values of ``ft`` per amplitude, in [2, 200], up to 0.99 ``ft_lim(w)`` (eq 35).
    dx : float
        Element width [a]; the solver's ``c_sd`` is resolved to one element.
    progress : callable, optional
        ``progress(done, total)`` after every point.
    cancel : threading.Event, optional
        Set to stop (:class:`FiguresCancelled`).

    Returns
    -------
    dict
        ``curves``: per ``w``, ``ft``, ``solver`` (c_sd/a of the direct
        shaken-down state) and ``eq30`` (:func:`core.shakedown_stick_halfwidth`);
        ``max_difference`` [a] over all points.
    """
    points = check_int("points", points, 2, 200)
    dx = check_scalar("dx", dx, 1e-3, 0.1)
    model = paper_model()
    steps = _Steps(len(w_values) * points, progress, cancel)
    curves = []
    for w in map(float, w_values):
        ft = _ft_grid(float(ft_limit(w)), points)
        solver = []
        for f in ft:
            steps.check()
            solver.append(shakedown_state(f, w, dx, **model).stick_halfwidth)
            steps.step()
        curves.append({"w": w, "ft": ft, "solver": np.array(solver), "eq30": shakedown_stick_halfwidth(ft, w)})
    diff = _max_abs(*[(c["solver"], c["eq30"]) for c in curves])
    return {"settings": {"w_values": list(map(float, w_values)), "points": points, "dx": dx, **model},
            "curves": [{k: _round(v) for k, v in c.items()} for c in curves], "max_difference": _round(diff)}


# --------------------------------------------------------------------------
# Figs 11 and 12: the traction after shakedown
# --------------------------------------------------------------------------
#: Fig 11: w = 0.26 and ft = 0.22, 0.44, 0.66; Fig 12: ft = 0.08 and the three amplitudes.
FIG11_CASES = ((0.22, 0.26), (0.44, 0.26), (0.66, 0.26))
FIG12_CASES = tuple((0.08, w) for w in PAPER_W)


def traction_profiles(cases, dx=1 / 100, *, progress=None, cancel=None) -> dict:
    """Figs 11, 12: the traction after shakedown, solver and the paper's ansatz (eqs 22-26 with c_sd of eq 30).

    Parameters
    ----------
    cases : sequence of (ft, w)
        Each below the limit of eq 35.
    dx : float
        Element width of the direct shaken-down states [a].
    progress, cancel :
        Progress and cancellation, as in :func:`stick_halfwidth_curves`.

    Returns
    -------
    dict
        ``curves``: per case ``ft``, ``w``, ``x`` [a] (element centres in
        the contact), ``solver`` and ``ansatz`` (``q / (mu p0)``, the ansatz
        at the same ``x``), ``bound`` (``mu p_min``, element means),
        ``c_solver`` and ``c_eq30`` [a], and ``max_difference`` [mu p0].
    """
    dx = check_scalar("dx", dx, 1e-3, 0.1)
    model = paper_model()
    steps = _Steps(len(cases), progress, cancel)
    curves = []
    for ft, w in cases:
        steps.check()
        state = shakedown_state(ft, w, dx, **model)
        x, q, bound, c = state.x, state.traction, state.bound, state.stick_halfwidth
        keep = np.abs(x) < 1.0  # the contact at the centre of the rocking; the rest carries nothing
        x, q, bound = x[keep], q[keep], bound[keep]
        curves.append({"ft": float(ft), "w": float(w), "x": x, "solver": q, "ansatz": shakedown_traction(x, ft, w),
                       "bound": bound, "c_solver": c, "c_eq30": shakedown_stick_halfwidth(ft, w)})
        steps.step()
    diff = _max_abs(*[(c["solver"], c["ansatz"]) for c in curves])
    for c in curves:
        c["max_difference"] = _max_abs((c["solver"], c["ansatz"]))
    return {"settings": {"cases": [list(map(float, c)) for c in cases], "dx": dx, **model},
            "curves": [{k: _round(v) for k, v in c.items()} for c in curves], "max_difference": _round(diff)}


# --------------------------------------------------------------------------
# Fig 13: u_sd against ft
# --------------------------------------------------------------------------
def _centre_displacement(q, dx, w, model) -> float:
    """Displacement at ``x = 0`` [mu P/E*] of the tractions ``q`` on the grid of :func:`shakedown_state`.

    In the shaken-down state every stick point has the rigid-body displacement,
    so this is ``U_sd`` (eq 31, integrated with the strip's exact element influences).
    """
    edges = make_grid(1.0 + w, dx)
    centres = 0.5 * (edges[1:] + edges[:-1])
    return float(strip_influence(-centres, dx, model["L_over_a"], strip_b_coefficient(model["nu"])) @ q)


def shakedown_displacement_curves(w_values=(0.0, *PAPER_W), points=16, dx=1 / 200, check_ft=(0.1, 0.3),
                                  check_dx=1 / 40, periods=30, *, progress=None, cancel=None) -> dict:
    """Fig 13: the shakedown displacement ``u_sd = U_sd / U0`` against ``ft``, solver and eq 34.

    The solver's ``u_sd`` is the displacement of the direct shaken-down state
    at the contact centre (eq 31 with the strip's exact influences), divided by
    ``U0``; a few transients (``check_ft`` per amplitude, ``periods`` periods)
    check it.

    Parameters
    ----------
    w_values : sequence of float
        Amplitudes ``W / a`` in [0, 1); ``w = 0`` is the static case, compared with eq 13.
    points : int
        Values of ``ft`` per amplitude, in [2, 200].
    dx : float
        Element width of the direct states [a].
    check_ft : sequence of float
        Values of ``ft`` of the transients (those below the limit of each ``w`` are run).
    check_dx : float
        Element width (and rocking step) of the transients [a].
    periods : int
        Periods of each transient.
    progress, cancel :
        As in :func:`stick_halfwidth_curves`.

    Returns
    -------
    dict
        ``curves``: per ``w``, ``ft``, ``solver``, ``eq34`` (and ``eq13`` at
        ``w = 0``), ``check_ft`` and ``check_transient`` (``u`` at the end of
        the transients); ``max_difference`` (solver - eq 34) and
        ``max_transient_difference`` (transient - direct state at the same ``ft``).
    """
    points = check_int("points", points, 2, 200)
    dx = check_scalar("dx", dx, 1e-3, 0.1)
    check_dx = check_scalar("check_dx", check_dx, 1e-3, 0.1)
    periods = check_int("periods", periods, 1, 200)
    model = paper_model()
    u0 = _u0(model)
    checks = {w: [f for f in check_ft if f < 0.99 * float(ft_limit(w))] for w in map(float, w_values)}
    steps = _Steps(len(w_values) * points + sum(2 * len(v) for v in checks.values()), progress, cancel)
    curves, tdiff = [], []

    def direct(f, w):
        steps.check()
        q = shakedown_state(f, w, dx, **model).traction
        steps.step()
        return _centre_displacement(q, dx, w, model) / u0

    for w in map(float, w_values):
        ft = _ft_grid(float(ft_limit(w)), points, lo=0.0)
        curve = {"w": w, "ft": ft, "solver": np.array([direct(f, w) for f in ft]),
                 "eq34": approximations.shakedown_displacement_approx(ft, w)}
        if w == 0.0:
            curve["eq13"] = approximations.static_displacement_approx(ft)
        transient = []
        for f in checks[w]:
            steps.check()
            r = simulate_cycles(f, w, periods, check_dx, **model)
            steps.step()
            transient.append(float(r.u[-1]))
            tdiff.append(transient[-1] - direct(f, w))
        curve.update(check_ft=np.array(checks[w], float), check_transient=np.array(transient))
        curves.append(curve)
    diff = _max_abs(*[(c["solver"], c["eq34"]) for c in curves])
    return {"settings": {"w_values": list(map(float, w_values)), "points": points, "dx": dx,
                         "check_ft": list(map(float, check_ft)), "check_dx": check_dx, "periods": periods,
                         "u0": u0, **model},
            "curves": [{k: _round(v) for k, v in c.items()} for c in curves], "max_difference": _round(diff),
            "max_transient_difference": _round(np.max(np.abs(tdiff)) if tdiff else np.nan)}


# --------------------------------------------------------------------------
# Fig 14: the limit curve
# --------------------------------------------------------------------------
def limit_curve(ft_values=tuple(np.round(np.linspace(0.1, 0.9, 9), 6)), tol=1e-3, dx=1 / 40, periods=30,
                scheduler="serial", *, progress=None, cancel=None) -> dict:
    """Fig 14: the shakedown limit ``w_lim`` against ``ft_lim``: the transients' bracket, eq 35 and eq 36.

    For every ``ft`` the bisection of :func:`core.numerical_limit_curve`
    brackets the regime change in ``w`` (the last amplitude that shook down,
    the first that ratcheted), as the paper did with CONTACT.

    Parameters
    ----------
    ft_values : sequence of float
        Tangential loads in (0, 1).
    tol : float
        Half-width of the final bracket in ``w``.
    dx : float
        Element width and rocking step of the transients [a].
    periods : int
        Periods of each transient.
    scheduler : str
        ``"serial"`` (in this process) or ``"processes"`` (all cores), see :func:`core.sweep`.
    progress, cancel :
        As in :func:`stick_halfwidth_curves` (``progress`` counts ``ft`` values).

    Returns
    -------
    dict
        ``points``: ``ft``, ``w_shakedown``, ``w_ratcheting``, ``w_solver``
        (the bracket's midpoint), ``w_eq35`` and ``w_eq36`` at the same ``ft``;
        ``line``: eq 35, eq 36 and the sphere's exact limit on a fine grid
        (:func:`limit_lines`); ``max_difference`` (solver -
        eq 35), ``eq35_in_bracket`` (how many brackets contain eq 35, of how
        many) and ``max_regression_difference`` (eq 36 - eq 35 on the line).
    """
    periods = check_int("periods", periods, 1, 200)
    model = paper_model()
    try:
        table = numerical_limit_curve(list(ft_values), tol, scheduler, progress=progress, cancel=cancel,
                                      dx=dx, periods=periods, **model)
    except SweepCancelled as e:
        raise FiguresCancelled(str(e)) from e
    ft = table["ft"].to_numpy(float)
    points = {"ft": ft, "w_shakedown": table["w_shakedown"].to_numpy(float),
              "w_ratcheting": table["w_ratcheting"].to_numpy(float), "w_solver": table["w_limit"].to_numpy(float),
              "w_eq35": w_limit(ft), "w_eq36": approximations.w_limit_regression(ft)}
    line = limit_lines()
    return {"settings": {"ft_values": list(map(float, ft_values)), "tol": float(tol), "dx": float(dx),
                         "periods": periods, "k_eq36": approximations.W_LIMIT_REGRESSION_EXPONENT, **model},
            "points": {k: _round(v) for k, v in points.items()}, "line": {k: _round(v) for k, v in line.items()},
            "max_difference": _round(_max_abs((points["w_solver"], points["w_eq35"]))),
            "eq35_in_bracket": [int(np.sum((points["w_shakedown"] <= points["w_eq35"])
                                           & (points["w_eq35"] <= points["w_ratcheting"]))), len(ft)],
            "max_regression_difference": _round(_max_abs((line["w_eq36"], line["w_eq35"])))}


def limit_lines(points: int = 101) -> dict:
    """The limit lines of Fig 14 on ``points`` values of ``ft`` in [0, 1]: the cylinder's exact eq 35, the paper's
    regression eq 36, and the sphere's exact limit ``ft_lim = (1 - w)^2 (2 + w)/2`` (that of every ellipsoid
    rocked along a principal axis, :func:`core.theory.point_contact.ft_limit_point`), which the paper's Fig 14 compares
    with the cylinder's.

    Examples
    --------
    >>> line = limit_lines(3)
    >>> [round(float(v), 4) for v in line["w_sphere"]]
    [1.0, 0.3473, 0.0]
    """
    points = check_int("points", points, 2, 10_001)
    ft = np.linspace(0.0, 1.0, points)
    return {"ft": ft, "w_eq35": w_limit(ft), "w_eq36": approximations.w_limit_regression(ft),
            "w_sphere": body_w_limit(ft, body="sphere")}


# --------------------------------------------------------------------------
# Fig 15: u_lim against ft_lim
# --------------------------------------------------------------------------
def limit_displacement_curve(w_values=tuple(np.round(np.linspace(0.0, 0.95, 20), 6)), dx=1 / 400,
                             *, progress=None, cancel=None) -> dict:
    """Fig 15: the largest shakedown displacement ``u_lim`` against ``ft_lim``, solver and eq 34 at the limit.

    ``u_lim(w)`` is the shakedown displacement ``u_sd`` as ``ft -> ft_lim(w)``
    (eq 35): the stick zone shrinks to the centre and the whole contact
    carries ``mu p_min``, so ``u_lim`` is the centre displacement of that
    traction (eq 31, strip model) over ``U0``. The paper's own formula (eq 37)
    is unreadable in the text; the nearest readable formula is eq 34 at
    ``(ft_lim(w), w)``.

    Parameters
    ----------
    w_values : sequence of float
        Amplitudes in [0, 1).
    dx : float
        Element width [a].
    progress, cancel :
        As in :func:`stick_halfwidth_curves`.

    Returns
    -------
    dict
        ``w``, ``ft_lim`` (eq 35), ``solver`` and ``eq34_at_limit``, and
        ``max_difference``.
    """
    dx = check_scalar("dx", dx, 1e-3, 0.1)
    model = paper_model()
    u0 = _u0(model)
    steps = _Steps(len(w_values), progress, cancel)
    w = np.asarray(w_values, float)
    solver = []
    for wi in w:
        steps.check()
        # the shaken-down bound mu p_min (element means), carried in full at the limit
        bound = shakedown_state(0.0, wi, dx, **model).bound
        solver.append(_centre_displacement(bound, dx, wi, model) / u0)
        steps.step()
    ftl = ft_limit(w)
    eq34 = approximations.shakedown_displacement_approx(np.minimum(ftl, 1 - 1e-12), w)
    solver = np.array(solver)
    return {"settings": {"w_values": list(map(float, w)), "dx": dx, "u0": u0, **model},
            "w": _round(w), "ft_lim": _round(ftl), "solver": _round(solver), "eq34_at_limit": _round(eq34),
            "max_difference": _round(_max_abs((solver, eq34)))}


# --------------------------------------------------------------------------
# Fig 16: the increment per period against ft
# --------------------------------------------------------------------------
def ratchet_increment_curves(w_values=PAPER_W, points=10, dx=1 / 40, periods=30, *, progress=None,
                             cancel=None) -> dict:
    """Fig 16: the ratcheting increment per period ``du`` against ``ft``: transients and eq 38.

    Parameters
    ----------
    w_values : sequence of float
        Amplitudes in (0, 1).
    points : int
        Values of ``ft`` per amplitude, from just above ``ft_lim(w)`` to 0.95.
    dx : float
        Element width and rocking step [a].
    periods : int
        Periods of each transient; ``du`` is the last period's increment of
        ``u = U / U0`` (the increment is constant once the state repeats).
    progress, cancel :
        As in :func:`stick_halfwidth_curves`.

    Returns
    -------
    dict
        ``curves``: per ``w``, ``ft``, ``solver``, ``eq38`` (with the exact
        ``w_lim``, eq 35), ``regime``; ``max_difference`` and
        ``max_relative_difference`` ((eq 38 - solver) / solver).
    """
    points = check_int("points", points, 2, 200)
    dx = check_scalar("dx", dx, 1e-3, 0.1)
    periods = check_int("periods", periods, 2, 200)
    model = paper_model()
    steps = _Steps(len(w_values) * points, progress, cancel)
    curves = []
    for w in map(float, w_values):
        ft = np.linspace(float(ft_limit(w)) + 0.01, 0.95, points)
        du, regime = [], []
        for f in ft:
            steps.check()
            r = simulate_cycles(f, w, periods, dx, **model)
            du.append(float(r.increment_per_period[-1] / r.u0))
            regime.append(r.regime)
            steps.step()
        curves.append({"w": w, "ft": ft, "solver": np.array(du),
                       "eq38": approximations.ratchet_increment_approx(ft, w), "regime": regime})
    pairs = [(c["solver"], c["eq38"]) for c in curves]
    rel = [(np.asarray(b) - a) / a for a, b in pairs]
    return {"settings": {"w_values": list(map(float, w_values)), "points": points, "dx": dx, "periods": periods,
                         **model},
            "curves": [{k: (v if k == "regime" else _round(v)) for k, v in c.items()} for c in curves],
            "max_difference": _round(_max_abs(*pairs)),
            "max_relative_difference": _round(float(np.max(np.abs(np.concatenate(rel)))))}


# --------------------------------------------------------------------------
# all of them
# --------------------------------------------------------------------------
#: The figures by key: (the paper's figure numbers, the function, its keyword arguments).
FIGURES = {
    "fig10": ("10", stick_halfwidth_curves, {}),
    "fig11": ("11", traction_profiles, {"cases": FIG11_CASES}),
    "fig12": ("12", traction_profiles, {"cases": FIG12_CASES}),
    "fig13": ("13", shakedown_displacement_curves, {}),
    "fig14": ("14", limit_curve, {}),
    "fig15": ("15", limit_displacement_curve, {}),
    "fig16": ("16", ratchet_increment_curves, {}),
}


def compute(names=None, *, progress=None, cancel=None, **overrides) -> dict:
    """Compute the data of the figures ``names`` (default all of :data:`FIGURES`).

    Parameters
    ----------
    names : sequence of str, optional
        Keys of :data:`FIGURES`.
    progress : callable, optional
        ``progress(name, done, total)`` as each figure's points finish.
    cancel : threading.Event, optional
        Set to stop (:class:`FiguresCancelled`).
    **overrides
        Per figure, a dict of keyword arguments that replace the defaults
        (e.g. ``fig14={"scheduler": "processes"}``).

    Returns
    -------
    dict
        ``meta`` (the command, versions, the model, seconds per figure) and
        ``figures`` (key -> that figure's data).
    """
    names = list(FIGURES) if names is None else list(names)
    unknown = [n for n in names if n not in FIGURES]
    if unknown or set(overrides) - set(FIGURES):
        raise ValueError(f"figures must be among {sorted(FIGURES)}, got {sorted(set(unknown) | set(overrides))}")
    figures, seconds = {}, {}
    for name in names:
        _, fn, kwargs = FIGURES[name]
        report = None if progress is None else (lambda d, t, _n=name: progress(_n, d, t))
        t0 = time.perf_counter()
        figures[name] = fn(**{**kwargs, **overrides.get(name, {})}, progress=report, cancel=cancel)
        seconds[name] = round(time.perf_counter() - t0, 2)
    model = paper_model()
    meta = {"command": COMMAND, "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "python": platform.python_version(), "numpy": np.__version__,
            "model": {**model, "u0": _u0(model), "contact": "core.PAPER_SIMULATION (eq 17)"},
            "seconds": seconds}
    return {"meta": meta, "figures": figures}


def save(data: dict, path) -> None:
    """Write ``data`` (from :func:`compute`) as JSON to ``path``."""
    Path(path).write_text(json.dumps(data, indent=None, separators=(",", ":"), allow_nan=False) + "\n")


def load(path) -> dict:
    """Read data written by :func:`save`; ``None`` stands for NaN in the arrays."""
    return json.loads(Path(path).read_text())


def main(argv=None) -> int:
    """``python -m core.maps.paper_figures --out FILE [--only fig10,fig14] [--serial]``."""
    parser = argparse.ArgumentParser(prog="python -m core.maps.paper_figures", description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="JSON file to write")
    parser.add_argument("--only", default=None, help=f"comma-separated subset of {','.join(FIGURES)}")
    parser.add_argument("--serial", action="store_true", help="run Fig 14's bisections in this process")
    args = parser.parse_args(argv)
    names = None if args.only is None else [s.strip() for s in args.only.split(",") if s.strip()]
    lock = threading.Lock()

    tty = sys.stderr.isatty()

    def progress(name, done, total):
        if tty or done == total:
            with lock:
                print(f"\r{name}: {done}/{total}", end="\n" if done == total else "", file=sys.stderr, flush=True)

    t0 = time.perf_counter()
    try:
        data = compute(names, progress=progress,
                       **({} if args.serial or (names and "fig14" not in names) else
                          {"fig14": {"scheduler": "processes"}}))
    except ValueError as e:
        parser.error(str(e))
    data["meta"]["command"] = "python -m core.maps.paper_figures " + shlex.join(sys.argv[1:] if argv is None else argv)
    data["meta"]["total_seconds"] = round(time.perf_counter() - t0, 1)
    save(data, args.out)
    for name, fig in data["figures"].items():
        print(f"{name}: max |solver - paper| = {fig['max_difference']}  ({data['meta']['seconds'][name]} s)")
    print(f"wrote {args.out} in {data['meta']['total_seconds']} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
