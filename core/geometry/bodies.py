"""Bodies: the contact geometry of a run, its grid, its traction bound per step, and its closed forms.

A body knows everything about the contact that is not elasticity and not
friction law: the grid of world-fixed elements, the normal pressure under a
given centre position and normal load (so the traction bound ``mu p`` of every
element at every step), the Hertz scales, how the tangential load maps to a
sum of element tractions, and its closed-form references.

:class:`Cylinder` is the line contact of Wetter (2015): a 1D grid, the Hertz
pressure of eq 4 averaged exactly over each element, half-width and peak both
scaling as ``sqrt(P)`` (eq 5). Point contacts (sphere, ellipsoid: 2D grids)
are added by writing one module with a class of the same interface and
registering it in :data:`BODIES` (see the developer guide, ``docs/dev/adding-a-body.md``).

Normalised units: lengths in the nominal half-width ``a``, pressure in the
nominal ``p0``, tractions in ``mu p0``, normal load in the nominal ``P``,
tangential load in ``mu P``.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict

import numpy as np

from ..theory import analytical
from ..pressure import melan
from ..base._hertz import element_means
from ..base._jit import jit

__all__ = ["Body", "Cylinder", "Punch", "LineGrid", "BODIES", "get_body", "resolve_body", "NORMAL_CHOICES",
           "MAX_ELEMENTS", "MAX_FFT_ELEMENTS"]

#: The numerical normal problem of a run is solved on elements this many times finer than the run's (once per
#: normal load: cheap), its element means then feed the run (``benchmarks/normal.py``, ``tests/test_punch.py``).
NORMAL_REFINE = 4
#: Pressure tables (:meth:`Body.cumulative`) kept for equal bodies, least recently used dropped first.
MAX_TABLES = 256
_TABLES = OrderedDict()
_TABLES_LOCK = threading.Lock()


def clear_tables():
    """Forget every cached pressure table (the next run of each body solves its normal problem again)."""
    with _TABLES_LOCK:
        _TABLES.clear()


#: The values of the ``normal`` keyword: the closed-form pressure, the numerical normal solve
#: (:mod:`core.pressure.normal`), or the closed form where the body has one.
NORMAL_CHOICES = ("auto", "exact", "numerical")

#: Largest grid of the dense solver (its matrix and interval inverses need 8 n^2 bytes each).
MAX_ELEMENTS = 4000
#: Largest grid of any run: the matrix-free solver (``solver="fft"``) stores no matrix.
MAX_FFT_ELEMENTS = 16384


def _check_edges(edges):
    edges = np.array(edges, dtype=float)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError("edges must be a strictly increasing 1-D array of at least 2 values")
    if edges.size - 1 > MAX_FFT_ELEMENTS:
        raise ValueError(f"the grid has {edges.size - 1} elements (> {MAX_FFT_ELEMENTS}): use a larger dx")
    edges.setflags(write=False)
    return edges


@jit
def _interp_uniform(s, step, x, y, out):
    """``np.interp(s, x, y)`` for knots ``x`` about a uniform ``step`` apart: each point's interval from one
    division, then checked against the knots themselves, so that a point on a knot gets its value exactly (as
    from ``np.interp``: a run's element outside the contact keeps a zero bound, not one of 1e-17)."""
    m = y.size - 1
    for i in range(s.size):
        si = s[i]
        if si <= x[0]:
            out[i] = y[0]
        elif si >= x[m]:
            out[i] = y[m]
        else:
            k = min(max(int((si - x[0]) / step), 0), m - 1)
            while k > 0 and si < x[k]:
                k -= 1
            while k < m - 1 and si >= x[k + 1]:
                k += 1
            out[i] = y[k] + (si - x[k]) * ((y[k + 1] - y[k]) / (x[k + 1] - x[k]))
    return out


@jit
def _table_means(xc, edges, dx, step, x, y, out):
    """``max((C(e_{i+1} - xc) - C(e_i - xc)) / dx, 0)`` for every centre ``xc`` (rows of ``out``) and element of
    the uniform ``edges``, ``C = np.interp(., x, y)`` as in :func:`_interp_uniform`."""
    n = edges.size - 1
    F = np.empty(n + 1)
    s = np.empty(n + 1)
    for r in range(xc.size):
        for i in range(n + 1):
            s[i] = edges[i] - xc[r]
        _interp_uniform(s, step, x, y, F)
        for i in range(n):
            v = (F[i + 1] - F[i]) / dx
            out[r, i] = v if v > 0.0 else 0.0
    return out


class _UniformTable:
    """``C(s)``: ``np.interp(s, knots, values)`` for uniform knots (no search), the cumulative pressure of a
    numerical solve (:meth:`Body.cumulative`)."""

    def __init__(self, knots, values):
        self.knots = np.ascontiguousarray(knots, dtype=float)
        self.values = np.ascontiguousarray(values, dtype=float)
        self.step = float(self.knots[-1] - self.knots[0]) / (self.knots.size - 1)
        for a in (self.knots, self.values):
            a.setflags(write=False)

    def __call__(self, s):
        s = np.ascontiguousarray(s, dtype=float)
        out = np.empty(s.shape)
        _interp_uniform(s.reshape(-1), self.step, self.knots, self.values, out.reshape(-1))
        return out

    def element_means(self, edges, dx, xc, out):
        """The element means ``max(diff(C(edges - xc)) / dx, 0)`` of the ``edges`` (``dx`` apart) for each centre
        ``xc``, written to ``out`` (shape ``(xc.size, edges.size - 1)``): :meth:`LineGrid.bounds` in one pass."""
        return _table_means(np.ascontiguousarray(xc, dtype=float), np.ascontiguousarray(edges, dtype=float),
                            float(dx), self.step, self.knots, self.values, out)


def _edges_for_reach(reach, dx, max_elements):
    max_elements = min(int(max_elements), MAX_FFT_ELEMENTS)
    half = math.ceil(reach / dx - 1e-9) + 1
    n = 2 * half
    if n > max_elements:
        hint = " or solver='fft'" if max_elements < MAX_FFT_ELEMENTS else ""
        raise ValueError(f"dx = {dx:g} needs {n} elements (> {max_elements}): dx must be >= "
                         f"{reach / (max_elements // 2 - 1):.4g} here; use a larger dx{hint}")
    return dx * (np.arange(n + 1) - half)


def _line_grid(edges):
    """``(edges, dx, x, shape)`` of a uniform line grid: checked read-only edges, width, centres, ``(n,)``."""
    edges = _check_edges(edges)
    x = 0.5 * (edges[1:] + edges[:-1])
    x.setflags(write=False)
    return edges, float(edges[1] - edges[0]), x, (edges.size - 1,)


class Body:
    """A line-contact body as an object with parameters (a spec): its profile, its pressure, its grid.

    A subclass sets :attr:`name` and gives its gap :meth:`profile` (always: the
    numerical normal solve, :mod:`core.pressure.normal`, needs only it) and, if it has
    one, its closed-form :meth:`pressure` and :meth:`half_width` (then
    :attr:`closed_form` is True). Everything else (the grid of a run, the
    traction bound per step, the shakedown limit) follows here. The body only
    translates: its contact centre ``xc`` moves and its pressure moves with it,
    so the normal problem is solved once per normal load, not per step.

    Normalised units: lengths in ``a``, the contact half-width at the nominal
    load (for a body without a closed form: the length unit of its profile);
    pressure in ``p0 = 2 P / (pi a)`` (so the nominal load is
    ``integral p dx = pi/2``); the gap in ``P / E*``. Hertz's cylinder is
    ``h = (2/pi) x^2``.

    Attributes
    ----------
    name : str
        Its key in :data:`BODIES`.
    dim : int
        1: a line contact (the 1D engine).
    closed_form : bool
        Whether :meth:`pressure` is known in closed form.
    support : float
        Half-width [a] of the region the numerical normal solve covers at the
        nominal load (scaled by ``max(1, P)``); the contact must stay inside it.
    """

    name = "body"
    dim = 1
    closed_form = False
    support = 2.0
    #: Total load of a unit traction over the nominal area per unit of Q: ``sum q dx = (pi/2) Q``.
    load_factor = 0.5 * math.pi
    #: The closed form of its shaken-down traction ``f(x, ft, w)`` [mu p0] under the paper's rocking and of its
    #: stick half-width ``f(ft, w)`` [a], where it has them (the cylinder's eqs 22-30); None otherwise.
    shakedown_traction = None
    shakedown_stick_halfwidth = None

    @property
    def parameters(self) -> dict:
        """The body's parameters by name (empty: none)."""
        return {}

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self.parameters.items())
        return f"{type(self).__name__}({args})"

    def __eq__(self, other):
        return type(other) is type(self) and other.parameters == self.parameters

    def __hash__(self):
        return hash((type(self).__name__, tuple(sorted(self.parameters.items()))))

    def __getstate__(self):  # its cached pressure tables hold closures: rebuilt after a pickle (process workers)
        return {k: v for k, v in self.__dict__.items() if k != "_tables"}

    # ---- what a body gives ------------------------------------------------------
    def profile(self, x):
        """The gap ``h(x)`` [P/E*] of the unloaded body centred at 0 (lowest point 0)."""
        raise NotImplementedError(f"{type(self).__name__} gives no profile")

    def pressure(self, x, xc=0.0, P=1.0):
        """Closed-form pressure [p0] at ``x`` [a] with the centre at ``xc`` under the load ``P`` [nominal P]."""
        raise NotImplementedError(f"{type(self).__name__} has no closed-form pressure: use normal='numerical'")

    def half_width(self, P=1.0):
        """Closed-form contact half-width [a] under the load ``P`` [nominal P]."""
        raise NotImplementedError(f"{type(self).__name__} has no closed-form half-width")

    # ---- the normal problem -----------------------------------------------------
    def normal_mode(self, normal="auto") -> str:
        """``"exact"`` or ``"numerical"`` for the ``normal`` keyword (:data:`NORMAL_CHOICES`).

        Raises
        ------
        ValueError
            For another value, or ``"exact"`` on a body without a closed form.
        """
        if normal not in NORMAL_CHOICES:
            raise ValueError(f"normal must be one of {NORMAL_CHOICES}, got {normal!r:.60}")
        if normal == "auto":
            return "exact" if self.closed_form else "numerical"
        if normal == "exact" and not self.closed_form:
            raise ValueError(f"normal='exact' needs a closed-form pressure, which {self!r} has not: "
                             "use normal='numerical' or 'auto'")
        return normal

    def solve_normal(self, dx, P=1.0, tol=None, refine=1, method="auto"):
        """The numerical static pressure at ``xc = 0`` (:func:`core.pressure.normal.solve_line`) on elements of width ``dx``.

        The elements' edges are multiples of ``dx`` (those of every run grid of
        the same ``dx``), over ``[-support, support] * max(1, P)``. With
        ``refine > 1`` that solve locates the contact, and the returned one is
        on elements ``refine`` times finer over the contact (and two coarse
        elements more each side), started from the coarse pressure (its
        contact set for the direct solve, which then usually settles at once).

        Parameters
        ----------
        dx : float
            Element width [a].
        P : float
            Normal load [nominal P].
        tol : float, optional
            The conjugate gradient's tolerance (default :data:`core.pressure.normal.NORMAL_TOL`).
        refine : int
            The finer solve's elements per element (1: none).
        method : {"auto", "cg", "direct"}
            Of both solves (:func:`core.pressure.normal.solve_normal`): on lines up to
            :data:`core.pressure.normal.DIRECT_MAX_ELEMENTS` elements ``"auto"`` is the direct one.

        Returns
        -------
        edges : ndarray, shape (n + 1,)
        solution : core.pressure.normal.NormalSolution

        Raises
        ------
        ValueError
            If the contact reaches the edge of that region (raise :attr:`support`).

        Examples
        --------
        >>> import core
        >>> edges, direct = core.Cylinder().solve_normal(1 / 40, refine=4)
        >>> _, cg = core.Cylinder().solve_normal(1 / 40, refine=4, method="cg")
        >>> direct.method, cg.method, bool(abs(direct.pressure - cg.pressure).max() < 1e-8)
        ('direct', 'cg', True)
        """
        from ..pressure.normal import NORMAL_TOL, solve_line
        tol = NORMAL_TOL if tol is None else tol
        reach = self.support * max(1.0, float(P))
        half = math.ceil(reach / dx - 1e-9)
        edges = dx * (np.arange(2 * half + 1) - half)
        x = 0.5 * (edges[1:] + edges[:-1])
        sol = solve_line(self.profile(x), dx, load=self.load_factor * float(P), tol=tol, method=method)
        if sol.contact[0] or sol.contact[-1]:
            raise ValueError(f"the contact of {self!r} reaches the edge of its solve region |x| < {reach:g}: "
                             "raise its support")
        refine = int(refine)
        if refine <= 1:
            return edges, sol
        inside = np.flatnonzero(sol.contact)
        lo, hi = max(inside[0] - 2, 0), min(inside[-1] + 3, x.size)
        fine_dx = dx / refine
        fine_edges = edges[lo] + fine_dx * np.arange((hi - lo) * refine + 1)
        xf = 0.5 * (fine_edges[1:] + fine_edges[:-1])
        fine = solve_line(self.profile(xf), fine_dx, load=self.load_factor * float(P), tol=tol,
                          initial=np.repeat(sol.pressure[lo:hi], refine), method=method)
        if fine.contact[0] or fine.contact[-1]:
            raise ValueError(f"the refined contact of {self!r} reaches the edge of its region: use a smaller dx")
        return fine_edges, fine

    def cumulative(self, dx, P=1.0, normal="auto"):
        """``C(s) = integral_{-inf}^{s} p`` [p0 a] at the centre 0 under ``P``: a callable, and the contact's reach.

        The element means of the pressure centred at ``xc`` are then
        ``(C(e_{i+1} - xc) - C(e_i - xc)) / dx``. ``"numerical"``: the
        piecewise-constant pressure solved on elements :data:`NORMAL_REFINE`
        times finer than ``dx`` (exact means for shifts by whole sub-elements;
        the element means then match the closed form's about 8 times better
        than a solve at ``dx``), ``C`` interpolated linearly between the fine
        edges (uniform: no search), its reach the outer edges of the solved
        contact; ``"exact"``: the closed form integrated in ``x = a sin(phi)``
        (4096 intervals, 4-point Gauss: about 1e-9), its reach the half-width.
        """
        if self.normal_mode(normal) == "numerical":
            edges, sol = self.solve_normal(dx, P, refine=NORMAL_REFINE)
            C = np.concatenate(([0.0], np.cumsum(sol.pressure) * (dx / NORMAL_REFINE)))
            inside = np.flatnonzero(sol.contact)  # the contact's reach: the outer edges of its end elements
            reach = float(max(-edges[inside[0]], edges[inside[-1] + 1]))
            return _UniformTable(edges, C), reach
        a = float(self.half_width(P))
        m = 4096
        g, wts = np.polynomial.legendre.leggauss(4)
        t = np.linspace(-0.5 * math.pi, 0.5 * math.pi, m + 1)
        h = t[1] - t[0]
        nodes = 0.5 * (t[:-1, None] + t[1:, None]) + 0.5 * h * g[None, :]
        vals = self.pressure(a * np.sin(nodes), 0.0, P) * a * np.cos(nodes)
        C = np.concatenate(([0.0], np.cumsum((vals * wts).sum(axis=1) * 0.5 * h)))

        def cum(s):
            return np.interp(np.arcsin(np.clip(np.asarray(s) / a, -1.0, 1.0)), t, C)
        return cum, a

    # ---- the grid of a run --------------------------------------------------------
    def grid(self, history, dx, max_elements=MAX_ELEMENTS, normal="auto"):
        """The discretised body (:class:`LineGrid`) covering every contact of ``history`` with elements ``dx``."""
        Pmax = float(np.max(history.P))
        _, reach = self._table(dx, Pmax, self.normal_mode(normal))
        edges = _edges_for_reach(float(np.max(np.abs(history.xc))) + reach, dx, max_elements)
        return self.on_grid(edges, normal)

    def on_grid(self, edges, normal="auto"):
        """This body on the element ``edges`` (the traction bounds of a run, :class:`LineGrid`)."""
        return LineGrid(self, edges, self.normal_mode(normal))

    def _table(self, dx, P, mode):
        """:meth:`cumulative`, cached: shared by equal bodies (same class and parameters) in this process, so
        the runs of a sweep solve the normal problem once per worker; per object if the body is unhashable."""
        key = (round(float(dx), 15), float(P), mode)
        try:
            shared = (type(self), self, *key)
            hash(shared)
        except TypeError:
            cache = self.__dict__.setdefault("_tables", {})
            if key not in cache:
                if len(cache) > 512:
                    cache.clear()
                cache[key] = self.cumulative(dx, P, mode)
            return cache[key]
        with _TABLES_LOCK:
            found = _TABLES.get(shared)
            if found is not None:
                _TABLES.move_to_end(shared)
                return found
        table = self.cumulative(dx, P, mode)
        with _TABLES_LOCK:
            _TABLES[shared] = table
            while len(_TABLES) > MAX_TABLES:
                _TABLES.popitem(last=False)
        return table

    # ---- its shakedown limit (Melan, core/pressure/melan.py) ---------------------------------
    def ft_limit(self, w):
        """The exact shakedown limit ``ft_lim(w)``: Melan's integral (:func:`core.pressure.melan.ft_limit`)."""
        return melan.ft_limit(w, self)

    def w_limit(self, ft):
        """Its inverse (:func:`core.pressure.melan.w_limit`)."""
        return melan.w_limit(ft, self)


class LineGrid:
    """A line-contact :class:`Body` on a uniform grid: the interface :func:`core.march.engine.run` uses.

    Parameters
    ----------
    body : Body
        The body (spec).
    edges : array_like, shape (n + 1,)
        Uniform, increasing element edges [a].
    normal : {"exact", "numerical"}
        How the pressure is found (see :meth:`Body.cumulative`).

    Attributes
    ----------
    name : str
        The body's name.
    body_spec : Body
        The body.
    edges, x, dx, shape, load_factor :
        As on :class:`Cylinder`.
    """

    def __init__(self, body, edges, normal):
        if normal not in ("exact", "numerical"):
            raise ValueError(f"normal must be 'exact' or 'numerical' here, got {normal!r:.60}")
        self.body_spec = body
        self.name = body.name
        self.normal = normal
        self.load_factor = body.load_factor
        self.edges, self.dx, self.x, self.shape = _line_grid(edges)

    @property
    def size(self) -> int:
        """Number of elements."""
        return self.shape[0]

    def bounds(self, xc, P, out=None):
        """Traction bound ``mu p`` [mu p0] of every element at every step, shape (steps, n): the element means
        of the body's pressure centred at ``xc`` under ``P`` (solved once per distinct ``P``)."""
        xc = np.atleast_1d(np.asarray(xc, dtype=float))
        P = np.broadcast_to(np.asarray(P, dtype=float), xc.shape)
        if out is None:
            out = np.empty((xc.size, self.size))
        for value in np.unique(P):
            rows = np.flatnonzero(P == value)
            cum, _ = self.body_spec._table(self.dx, float(value), self.normal)
            means = getattr(cum, "element_means", None)  # a numerical table's: one pass, no temporaries
            if means is not None:
                if rows.size == xc.size and out.flags.c_contiguous:
                    means(self.edges, self.dx, xc, out)
                else:
                    out[rows] = means(self.edges, self.dx, xc[rows], np.empty((rows.size, self.size)))
                continue
            F = cum(self.edges[None, :] - xc[rows, None])
            out[rows] = np.maximum(np.diff(F, axis=1) / self.dx, 0.0)
        return out

    def load_target(self, Q):
        """``sum q_i`` [mu p0] that carries the tangential load ``Q`` [mu P]."""
        return np.asarray(Q, dtype=float) * (self.load_factor / self.dx)

    def lowest_bound(self, w):
        """``mu p_min`` per element while the centre rocks over ``[-w, w]`` at the nominal load [mu p0]: the
        minimum over centres a quarter element apart (the pressure may have several peaks)."""
        k = max(1, math.ceil(8 * w / self.dx))
        return self.bounds(np.linspace(-w, w, k + 1), np.ones(k + 1)).min(axis=0)


class Cylinder(Body):
    """The rocking cylinder (line contact, plane problem): the body, and on a uniform 1D grid its bounds.

    ``Cylinder()`` is the body (no parameters); ``Cylinder(edges)`` is the
    body on a grid (the interface :func:`core.march.engine.run` uses, with the exact
    element means of the Hertz pressure).

    Parameters
    ----------
    edges : array_like, shape (n + 1,), optional
        Uniform, increasing element edges [a] (see :meth:`for_reach`).

    Attributes
    ----------
    name : str
        ``"cylinder"``, its key in :data:`BODIES`.
    edges, x : ndarray
        Element edges and centres [a] (read-only).
    dx : float
        Element width [a]; also the element measure of the load balance.
    shape : tuple
        ``(n,)``: the shape of a traction field on this body.
    """

    name = "cylinder"
    closed_form = True
    #: Total load of a unit traction over the Hertz area per unit of Q: ``sum q dx = (pi/2) Q`` (eq 5: P = pi a p0 / 2).
    load_factor = 0.5 * math.pi

    def __init__(self, edges=None):
        self.edges = self.dx = self.x = self.shape = None
        if edges is None:
            return
        self.edges, self.dx, self.x, self.shape = _line_grid(edges)

    @property
    def size(self) -> int:
        """Number of elements."""
        return self.shape[0]

    @property
    def body_spec(self):
        """The body without its grid: ``Cylinder()``."""
        return Cylinder()

    def __eq__(self, other):  # the body: grids aside
        return type(other) is Cylinder

    __hash__ = Body.__hash__

    def __repr__(self):
        return "Cylinder()" if self.edges is None else f"Cylinder(<{self.size} elements, dx={self.dx:g}>)"

    def profile(self, x):
        """The gap ``(2/pi) x^2`` [P/E*] (Hertz: contact half-width 1 under the nominal load)."""
        return (2.0 / math.pi) * np.asarray(x, dtype=float) ** 2

    def pressure(self, x, xc=0.0, P=1.0):
        """Hertz's pressure [p0] ``sqrt(P) sqrt(1 - ((x - xc)/sqrt(P))^2)`` (eq 4)."""
        a = math.sqrt(check_positive("P", P))
        t = (np.asarray(x, dtype=float) - xc) / a
        return a * np.sqrt(np.clip(1.0 - t * t, 0.0, None))

    def grid(self, history, dx, max_elements=MAX_ELEMENTS, normal="auto"):
        """``Cylinder.for_history`` (exact element means), or the numerical normal's :class:`LineGrid`."""
        if self.normal_mode(normal) == "exact":
            return Cylinder.for_history(history, dx, max_elements)
        return super().grid(history, dx, max_elements, normal)

    def on_grid(self, edges, normal="auto"):
        """``Cylinder(edges)`` for the exact pressure, else :meth:`Body.on_grid`."""
        return Cylinder(edges) if self.normal_mode(normal) == "exact" else super().on_grid(edges, normal)

    # ---- grid ----------------------------------------------------------------
    @classmethod
    def for_reach(cls, reach, dx, max_elements=MAX_ELEMENTS):
        """The uniform grid symmetric about 0 that covers ``[-reach, reach]`` with one spare element each side.

        Parameters
        ----------
        reach : float
            Largest distance from 0 that the contact reaches [a].
        dx : float
            Element width [a].
        max_elements : int
            Largest grid allowed: :data:`MAX_ELEMENTS` (the dense solver's, the default)
            or up to :data:`MAX_FFT_ELEMENTS` (the matrix-free solver's).

        Raises
        ------
        ValueError
            If the grid would exceed ``max_elements`` elements (names ``dx`` and the smallest it may be).
        """
        return cls(_edges_for_reach(reach, dx, max_elements))

    @classmethod
    def for_history(cls, history, dx, max_elements=MAX_ELEMENTS):
        """The grid covering every contact of a loading history (:class:`~core.loading.schedule.Schedule`)."""
        return cls.for_reach(cls.reach(history.xc, history.P), dx, max_elements)

    # ---- Hertz scales (eq 5) -------------------------------------------------
    @staticmethod
    def half_width(P=1.0):
        """Contact half-width [a] under the normal load ``P`` [nominal P]: ``a ~ sqrt(P)``."""
        return np.sqrt(P)

    @staticmethod
    def peak_pressure(P):
        """Peak pressure [nominal p0] under ``P``: ``p0 = 2 P / (pi a) ~ sqrt(P)``."""
        return np.sqrt(P)

    @classmethod
    def reach(cls, xc, P) -> float:
        """Largest distance from 0 that any contact of the steps ``(xc, P)`` reaches [a]."""
        return float(np.max(np.abs(xc) + cls.half_width(P)))

    # ---- the traction bound --------------------------------------------------
    def bounds(self, xc, P, out=None):
        """Traction bound ``mu p`` of every element at every step [mu p0], shape (steps, n).

        The exact element mean of the Hertz pressure (eq 4) centred at ``xc``
        under the normal load ``P``; 0 out of contact. The one definition used
        by the solvers and by :attr:`core.CycleResult.pressure`.
        """
        if self.edges is None:
            raise ValueError("Cylinder() is the body without a grid: use Cylinder(edges) or Cylinder().on_grid(edges)")
        P = np.asarray(P, dtype=float)
        return element_means(self.edges, xc, self.half_width(P), self.peak_pressure(P), out)

    def load_target(self, Q):
        """``sum q_i`` [mu p0] that carries the tangential load ``Q`` [mu P]."""
        return np.asarray(Q, dtype=float) * (self.load_factor / self.dx)

    def lowest_bound(self, w):
        """``mu p_min`` per element while the centre rocks over ``[-w, w]`` at the nominal load [mu p0].

        The element mean of the concave Hertz profile is quasi-concave in the
        centre position, so its minimum over the period is at a turning point.
        """
        turning = self.bounds(np.array([-w, w]), np.ones(2))
        return turning.min(axis=0)

    # ---- closed-form references (Wetter 2015) ---------------------------------
    #: Its limit is in closed form (eq 35): :func:`core.pressure.melan.ft_limit` takes it from :meth:`ft_limit`.
    closed_limit = True
    #: How its limit is cited.
    limit_citation = "eq 35"

    @staticmethod
    def ft_limit(w):
        """Eq 35 (:func:`core.theory.analytical.ft_limit`)."""
        return analytical.ft_limit(w)

    @staticmethod
    def w_limit(ft):
        """The inverse of eq 35 (:func:`core.theory.analytical.w_limit`)."""
        return analytical.w_limit(ft)

    @staticmethod
    def fretting_energy(amplitude, nu=0.5):
        """Energy dissipated per cycle of an oscillating tangential load of amplitude ``amplitude`` [mu P]
        (:func:`core.theory.analytical.fretting_energy_line`; plane strain: ``nu`` plays no part)."""
        return analytical.fretting_energy_line(amplitude)

    cattaneo_stick_halfwidth = staticmethod(analytical.cattaneo_stick_halfwidth)  # eq 7
    cattaneo_traction = staticmethod(analytical.cattaneo_traction)        # eqs 8-12
    shakedown_stick_halfwidth = staticmethod(analytical.shakedown_stick_halfwidth)  # eq 30
    shakedown_traction = staticmethod(analytical.shakedown_traction)      # eqs 22-26


def check_positive(name, value):
    value = float(value)
    if not (value > 0 and math.isfinite(value)):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


class Punch(Body):
    """The rounded flat punch (plane strain): a flat of half-width ``b`` with rounded edges (:mod:`core.theory.punch`).

    Parameters
    ----------
    flat : float
        ``b / a`` in [0, 1), ``a`` the contact half-width at the nominal load
        (0: the cylinder). Default 0.5.

    Examples
    --------
    >>> import core
    >>> core.Punch(flat=0.5)
    Punch(flat=0.5)
    >>> round(float(core.Punch(flat=0.0).ft_limit(0.26)), 4) == round(float(core.ft_limit(0.26)), 4)
    True
    """

    name = "punch"
    closed_form = True

    def __init__(self, flat=None):
        from ..theory.punch import DEFAULT_FLAT, _check_flat
        self.flat = _check_flat(DEFAULT_FLAT if flat is None else flat)

    @property
    def parameters(self) -> dict:
        return {"flat": self.flat}

    def profile(self, x):
        """0 over the flat, ``(2/G)(|x| - flat)^2`` beyond [P/E*] (:func:`core.theory.punch.punch_profile`)."""
        from ..theory.punch import punch_profile
        return punch_profile(x, self.flat)

    def pressure(self, x, xc=0.0, P=1.0):
        """Ciavarella, Hills and Monno's closed form (:func:`core.theory.punch.punch_pressure`)."""
        from ..theory.punch import punch_pressure
        return punch_pressure(x, self.flat, xc, P)

    def half_width(self, P=1.0):
        """Contact half-width [a] under ``P`` [nominal P] (:func:`core.theory.punch.punch_half_width`)."""
        from ..theory.punch import punch_half_width
        return punch_half_width(P, self.flat)


#: The bodies a run can use, by name: the class whose no-argument instance is the body with default
#: parameters. The point contacts (``"sphere"``, ``"ellipsoid"``) run on :mod:`core.solvers.solver3d`;
#: :mod:`core.geometry.registry` lists every body with its parameters.
BODIES = {"cylinder": Cylinder, "punch": Punch}


def get_body(name):
    """The body class registered under ``name`` (a class passes through).

    Raises
    ------
    ValueError
        If ``name`` is not in :data:`BODIES` (the message lists them).
    """
    if isinstance(name, type):
        return name
    if name not in BODIES:
        raise ValueError(f"body must be one of {', '.join(sorted(BODIES))}, got {name!r:.60}")
    return BODIES[name]


def resolve_body(body, **parameters):
    """A line-contact body object from a name in :data:`BODIES` (with ``parameters``), a class or an object.

    Raises
    ------
    ValueError
        For an unknown name, parameters given with an object, or a body that is not a line contact.

    Examples
    --------
    >>> from core.geometry.bodies import resolve_body
    >>> resolve_body("punch", flat=0.8), resolve_body("cylinder")
    (Punch(flat=0.8), Cylinder())
    """
    if isinstance(body, Body):
        if parameters:
            raise ValueError(f"parameters {sorted(parameters)} given with the body object {body!r}")
        return body
    if isinstance(body, type) and issubclass(body, Body):
        return body(**parameters)
    cls = get_body(body)
    try:
        return cls(**parameters)
    except TypeError:
        raise ValueError(f"body {body!r} takes no parameters {sorted(parameters)}") from None
