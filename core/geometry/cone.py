"""The rocking cone (a cone or tapered roller, a frustum, on its side): its shakedown limit from Melan's theorem.

A rigid cone of half-angle ``alpha`` lies on its side on an elastic
half-space, touching it along a generatrix from the distance ``r1`` to ``r2``
from its apex (``r1 = 0``: a full cone; ``r1 > 0``: a frustum, a tapered
roller). It rocks by rolling back and forth without slip, so it turns about
the vertical axis through its apex: the contact line sweeps the angle
``[-Theta, Theta]`` and each of its points moves along a circle about the apex,
by ``r Theta`` at the distance ``r``. A constant tangential force ``Ft`` acts
perpendicular to the cone's axis (across the contact line) at the distance
``r_F`` from the apex; the body is free to translate and to turn about the
normal (no applied twisting moment). Uncoupled (Dundurs beta = 0).

Slices. Across the contact line at ``r`` the cone's surface has the radius of
curvature ``R(r) = r tan(alpha)`` (zero curvature along the generatrix), so
each slice is a Hertz line contact (the strip or slice theory of rollers,
valid while the contact is long against its width). With a uniform line load
``P`` (this module's assumption), its half-width is
``a(r) = sqrt(4 R(r) P / (pi E*)) = a_m sqrt(r / r_m)``, ``r_m = (r1 + r2)/2``.
A rotation about the apex keeps every point's distance from the apex, so a
point at ``(r, phi)`` sees only the slice at ``r``, whose contact centre passes
it at the arc distance ``r (phi - theta)``: the slice rocks with the amplitude
``W(r) = r Theta``.

Normalised parameters: ``inner = r1 / r2`` in [0, 1) (0: the full cone; near
1: a frustum far from its apex, i.e. a cylinder); ``w = W_m / a_m``, the
amplitude over the half-width both at the mid-length ``r_m``; ``ft = Ft / (mu
Fn)``. The local amplitude is then ``w(r) = w sqrt(r / r_m)``: it grows along
the contact, and the slices with ``w(r) >= 1`` lose contact once a period.

Limit (Melan, :mod:`core.pressure.melan`). The lowest pressure over the cycle at
``(r, phi)`` is that of slice ``r`` at its own amplitude ``w(r)``, so its
line density is ``m(r) = mu P ft_cyl(w(r))`` with eq 35's
``ft_cyl``. Shakedown needs a traction field ``|q| <= mu p_min`` carrying
``Ft`` with no moment about the normal through ``r_F``:
maximise ``integral f dr`` over ``|f| <= m``, ``integral (r - r_F) f dr = 0``.
If ``r_F`` is the centroid of ``m`` the answer is ``integral m dr`` (the body's
rotation plays no part); otherwise the optimum is ``f = +-m`` with one switch
of sign (the Lagrange condition ``f = m sign(1 - lambda (r - r_F))``), which
this module finds. ``load_point=None`` drops the moment condition (the
rotation about the normal restrained): an upper bound.

What is new against the cylinder: the local amplitude varies along the contact
(``w sqrt(r / r_m)``), so the outer end reaches release first, and the moment
condition couples the slices: with ``Ft`` at the mid-length the lowest-pressure
centroid lies nearer the apex, and part of the contact must carry traction
against ``Ft`` to balance the moment, which lowers the limit.

Examples
--------
>>> from core.geometry.cone import cone_ft_limit
>>> round(float(cone_ft_limit(0.3, inner=0.999)), 3)  # a frustum far from its apex: the cylinder's 0.624
0.624
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.optimize import brentq

from ..base._validate import check_scalar

__all__ = ["Cone", "cone_ft_limit", "cone_w_limit", "slice_amplitude", "lowest_pressure_density", "DEFAULT_LENGTH",
           "LENGTH_RANGE", "DEFAULT_DX"]


def _quad(inner, n=4000):
    """Gauss-Legendre nodes and weights on [inner, 1] (lengths in r2), in panels."""
    g, wts = np.polynomial.legendre.leggauss(8)
    edges = np.linspace(inner, 1.0, n // 8 + 1)
    h = np.diff(edges)
    r = (0.5 * (edges[:-1] + edges[1:]))[:, None] + 0.5 * h[:, None] * g[None, :]
    return r.ravel(), (0.5 * h[:, None] * wts[None, :]).ravel()


def slice_amplitude(r, w, inner):
    """The local amplitude ``w(r) = w sqrt(r / r_m)`` (``r`` in ``r2``, ``r_m = (1 + inner)/2``)."""
    return w * np.sqrt(np.asarray(r, dtype=float) / (0.5 * (1.0 + inner)))


def lowest_pressure_density(r, w, inner):
    """``m(r) / (mu P)``: eq 35 at the slice's own amplitude (0 where ``w(r) >= 1``)."""
    from ..theory.analytical import ft_limit
    return ft_limit(np.minimum(slice_amplitude(r, w, inner), 1.0))


def cone_ft_limit(w, inner=0.5, load_point="centre"):
    """The shakedown limit ``ft_lim = Ft_lim / (mu Fn)`` of the rocking cone (slices, uniform line load).

    Parameters
    ----------
    w : float
        ``W_m / a_m`` at the mid-length, in [0, 10].
    inner : float
        ``r1 / r2`` in [0, 1) (0: the full cone).
    load_point : "centre", float or None
        Where ``Ft`` acts: ``"centre"`` (the mid-length, where a uniform
        normal load acts), a distance from the apex in ``r2`` (in
        ``[inner, 1]``), or None (no moment condition: the rotation about the
        normal restrained; an upper bound).

    Returns
    -------
    float
    """
    w = check_scalar("w", w, 0.0, 10.0)
    inner = check_scalar("inner", inner, 0.0, 1.0, hi_closed=False)
    r, wq = _quad(inner)
    m = lowest_pressure_density(r, w, inner)
    length = 1.0 - inner
    total = float(np.dot(wq, m))
    if load_point is None or total == 0.0:
        return float(total / length)
    rF = 0.5 * (1.0 + inner) if (isinstance(load_point, str) and load_point == "centre") else check_scalar(
        "load_point", load_point, inner, 1.0)
    arm = r - rF
    moment = float(np.dot(wq, m * arm))
    if abs(moment) <= 1e-15:
        return float(total / length)
    # one switch of sign at c (the Lagrange condition): f = +-m for r < c, -+m beyond, with zero moment:
    # 2 M(c) = M(1), M(c) the moment of m over [inner, c] (cumulative over the quadrature nodes, linear
    # between: continuous in c). Of the switch points (where 2 M - M(1) changes sign) the one carrying most.
    M = np.concatenate(([0.0], np.cumsum(wq * m * arm)))
    F = np.concatenate(([0.0], np.cumsum(wq * m)))
    g = 2.0 * M - M[-1]
    best = 0.0
    for k in np.flatnonzero(np.sign(g[1:]) != np.sign(g[:-1])) + 1:
        t = g[k - 1] / (g[k - 1] - g[k])
        Fc = F[k - 1] + t * (F[k] - F[k - 1])
        best = max(best, abs(2.0 * Fc - F[-1]))
    return float(best / length)


def cone_w_limit(ft, inner=0.5, load_point="centre"):
    """The inverse of :func:`cone_ft_limit` in ``w`` (the largest amplitude that shakes down at ``ft``)."""
    ft = check_scalar("ft", ft, 0.0, 1.0)
    if ft >= 1.0:
        return 0.0
    hi = 10.0
    if cone_ft_limit(hi, inner, load_point) >= ft:
        return hi
    return brentq(lambda v: cone_ft_limit(v, inner, load_point) - ft, 0.0, hi, xtol=1e-10)


#: Default slenderness ``L / a_m`` (contact length over the half-width at the mid-length) of a cone's runs.
DEFAULT_LENGTH = 10.0
#: Range of ``length`` (``L / a_m``): long enough for the slice model, short enough for the run's grid.
LENGTH_RANGE = (4.0, 200.0)
#: Default element width [a_m] of a cone's runs, across the contact line: a/10, 20 elements across the contact at
#: the mid-length (and ``4 L/a_m`` along it, :data:`ASPECT`). Measured (benchmarks/solver3d.py --convergence, issue
#: 31, results in benchmarks/results/solver3d_cone_s4.txt): at one ft (0.4041, inner 0.5, w 0.5, a ratcheting cone)
#: the increment per period is 0.004278, 0.004393, 0.004408 and 0.004518 at a/5, a/8, a/10 and a/20 (elements 2.5
#: times as long along the line), 0.004463 and 0.004564 at a/10 and a/20 with square elements: the default is 3.4 %
#: below a/20 square (the energy per period 6.2 %, the turn 4.0 %); a coarser default would not be converged.
DEFAULT_DX = 0.1
#: Element length along the contact line over its width across it (``dy = ASPECT dx``, :meth:`Cone.run_grid`).
#: The contact is 4 to 200 half-widths long and its slices' pressure varies slowly along it, so the elements are
#: longer along the line than across it: at the explorer's first run (a/10, ft 0.32, w 0.5, 10 periods) 43 x 39
#: elements (a 41 x 26 window, an 81 x 54 FFT grid) instead of 103 x 39 (101 x 26, 216 x 54), 1.24 s CPU a run
#: against 2.82 s (issue 31 item 15; medians of 10 interleaved runs, benchmarks/results/app_bodies_s4.txt). The
#: increment per period of a ratcheting cone (inner 0.5, w 0.5, ft 0.4041) at a/10 is 0.004408 against 0.004463
#: with square elements (-1.2 %) and 0.004564 at a/20 square (-3.4 %, against -2.2 % for a/10 square); the full
#: cone's (w 0.3, ft 0.6373) 0.008053 against 0.008231 square and 0.00808 at a/20 square (-0.3 %, +1.9 %). Longer
#: elements are not consistently worse or better beyond 2.5 (0.004414, 0.004335, 0.004658 at 2, 3, 4): the rows at
#: the cone's ends, which cut the contact's ends, decide.
ASPECT = 2.5
#: The default rocking step over the element width across the line (:meth:`Cone.rocking_step`;
#: :func:`core.geometry.resolution.default_dW`). Measured at a/10 (inner 0.5, w 0.5, 10 periods, CPU of one run at load ~5,
#: issue 31 item 15): ft 0.4041 (ratcheting) the increment per period 0.0043796 against 0.0044084 with the step
#: dx (-0.7 %; the grid's own error against a/20 square is -3.4 %), the energy per period 0.00153604 against
#: 0.00156349 (-1.8 %, grid error -6.2 %); the explorer's first run (ft 0.32) 1.068e-4 against 1.052e-4 (+1.5 %),
#: same regime; 81 steps instead of 201, 0.50-0.56 s CPU against 1.03-1.04 s. (dW 0.05, 0.125, 0.2 at ft 0.4041:
#: 0.004420, 0.004404, 0.004380; the schedule rounds the step to divide W: 0.25 at w 0.5.)
STEP_RATIO = 2.0
#: Sub-rows per element row in the element means of the slice pressure (:meth:`Cone.grid_pressure`).
_SUB_ROWS = 8


def _half_integral(s):
    """``integral_0^s sqrt(1 - t^2) dt`` for ``s`` clipped to [-1, 1]."""
    s = np.clip(s, -1.0, 1.0)
    return 0.5 * (s * np.sqrt(1.0 - s * s) + np.arcsin(s))


class Cone:
    """The rocking cone or frustum: its limit (slices) and its cycles on the 3D solver.

    Units of a run: lengths in ``a_m`` (the half-width at the mid-length
    ``r_m``), pressures in ``p0m = 2 P/(pi a_m)`` (the peak there), tractions
    in ``mu p0m``, loads in ``mu Fn`` (``Fn = P L``), the displacement of the
    load point in ``mu Fn/(E* a_m)`` and the rotation about the normal in
    ``mu Fn/(E* a_m^2)`` [rad]. The run's grid (:meth:`run_grid`) has ``x``
    across the contact line (the rocking direction, along ``Ft``) and ``y``
    along it, with ``y = 0`` at the mid-length and the apex at ``(0, -r_m)``;
    the rocking position ``xc`` of a schedule is the arc ``W_m = r_m theta``
    the contact line moves at the mid-length (so ``w = W_m / a_m``), and the
    line is at the angle ``theta = xc / r_m`` about the apex.

    Parameters
    ----------
    inner : float
        ``r1 / r2`` in [0, 1) (0: a full cone). Default 0.5.
    load_point : "centre", float or None
        Where ``Ft`` acts (see :func:`cone_ft_limit`): the mid-length, a
        distance from the apex in ``r2``, or None (the rotation about the normal
        restrained: no moment condition, and a run without the twist).
    length : float
        The slenderness ``L / a_m``, the contact length ``r2 - r1`` over the
        half-width at the mid-length, in [4, 200] (default 10). The slice model
        needs it large; the limit does not depend on it (only on ``inner``),
        the increments do (through the elastic coupling of the slices), and the
        run's grid grows with it.

    Examples
    --------
    >>> from core.geometry.cone import Cone
    >>> c = Cone(inner=0.5)
    >>> bool(c.ft_limit(0.3) < c.ft_limit(0.3, restrained=True))
    True
    >>> import core
    >>> r = core.simulate_cycles(0.3, 0.3, periods=6, dx=0.25, body=c)
    >>> r.regime, r.twist_per_period.size
    ('shakedown', 6)
    """

    name = "cone"
    #: A patch of elements (the 3D solver).
    dim = 2
    #: No semi-axis ratio (a point body's summary field).
    ratio = None

    def __init__(self, inner=0.5, load_point="centre", length=DEFAULT_LENGTH):
        self.inner = check_scalar("inner", inner, 0.0, 1.0, hi_closed=False)
        if not (load_point is None or (isinstance(load_point, str) and load_point == "centre")):
            load_point = check_scalar("load_point", load_point, self.inner, 1.0)
        self.load_point = load_point
        self.length = check_scalar("length", length, *LENGTH_RANGE)

    @property
    def parameters(self) -> dict:
        return {"inner": self.inner, "load_point": self.load_point, "length": self.length}

    def __repr__(self):
        return f"Cone(inner={self.inner!r}, load_point={self.load_point!r}, length={self.length!r})"

    def __eq__(self, other):
        return isinstance(other, Cone) and self.parameters == other.parameters

    def __hash__(self):
        return hash(("cone", self.inner, self.load_point, self.length))

    def ft_limit(self, w, restrained=False):
        """:func:`cone_ft_limit` (``restrained``: no moment condition)."""
        return cone_ft_limit(w, self.inner, None if restrained else self.load_point)

    def w_limit(self, ft, restrained=False):
        """:func:`cone_w_limit`."""
        return cone_w_limit(ft, self.inner, None if restrained else self.load_point)

    # ---- the run's geometry, in a_m -------------------------------------------
    @property
    def r2(self) -> float:
        """Distance from the apex to the outer end [a_m]."""
        return self.length / (1.0 - self.inner)

    @property
    def r1(self) -> float:
        """Distance from the apex to the inner end [a_m] (0 for a full cone)."""
        return self.inner * self.r2

    @property
    def r_m(self) -> float:
        """Distance from the apex to the mid-length [a_m]: ``(r1 + r2)/2``."""
        return 0.5 * (self.r1 + self.r2)

    @property
    def total_load(self) -> float:
        """``Fn`` in ``p0m a_m^2``: ``(pi/2) L / a_m`` (each slice carries ``P = (pi/2) p0m a_m`` per length)."""
        return 0.5 * math.pi * self.length

    load = total_load

    @property
    def kernel_scale(self) -> float:
        """``p0m a_m^2 / (pi Fn) = 2 / (pi^2 L/a_m)``: the half-space kernel's factor for displacements in
        ``mu Fn/(E* a_m)``."""
        return 2.0 / (math.pi**2 * self.length)

    @property
    def default_dx(self) -> float:
        """A run's element side [a_m]: :data:`DEFAULT_DX` (``a_m/10``; see there)."""
        return DEFAULT_DX

    @staticmethod
    def rocking_step(dx: float) -> float:
        """A run's default rocking step at element width ``dx`` [a_m]: :data:`STEP_RATIO` ``dx`` (see there)."""
        return STEP_RATIO * float(dx)

    @property
    def twist_centre(self):
        """The point ``(0, r_F - r_m)`` [a_m] on the line of action of ``Ft``, about which the body is free to turn
        (the run's ``displacement`` is that point's); None when the rotation is restrained (``load_point=None``)."""
        if self.load_point is None:
            return None
        rF = self.r_m if isinstance(self.load_point, str) else self.load_point * self.r2
        return (0.0, rF - self.r_m)

    @staticmethod
    def load_scale(P):
        """The contact's length scale under the normal load ``P`` [nominal Fn]: ``sqrt(P)`` (a line contact's
        half-width grows as the square root of its line load; the ``scale`` of :meth:`run_grid` and
        :meth:`grid_pressure`)."""
        return np.sqrt(np.asarray(P, dtype=float))

    def profile(self, x, y=0.0):
        """The gap [P/E*] at ``(x, y)`` [a_m] with the contact line on ``x = 0`` (``y`` along it, 0 at the
        mid-length): ``(2/pi) x^2 r_m / (y + r_m)``, each slice's Hertz gap ``x^2 / (2 R(r))`` with ``R(r) = r
        tan(alpha)``, the cylinder's ``(2/pi) x^2`` at the mid-length (``inf`` beyond the ends)."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        r = y + self.r_m
        inside = (r >= self.r1) & (r <= self.r2) & (r > 0)
        return np.where(inside, (2.0 / math.pi) * x * x * self.r_m / np.where(inside, r, 1.0), np.inf)

    def run_grid(self, reach_x, scale, h):
        """The edges ``(x_edges, y_edges)`` [a_m] of a run whose mid-length arc reaches ``|xc| <= reach_x``.

        An odd number of elements each way, centred on the mid-length
        (``y = 0``) and on the unrotated contact line (``x = 0``), covering the
        contact at every angle ``|theta| <= reach_x / r_m``: ``h`` across the
        line and ``ASPECT h`` along it (:data:`ASPECT`).
        """
        from .patch import MAX_GRID_ELEMENTS
        theta = reach_x / self.r_m
        hy = ASPECT * h
        wide = self.r2 * math.sin(theta) + scale * math.sqrt(self.r2 / self.r_m) * 1.01 + h
        long = 0.5 * self.length + hy
        xe = h * (np.arange(2 * math.ceil(wide / h - 0.5) + 2) - math.ceil(wide / h - 0.5) - 0.5)
        ye = hy * (np.arange(2 * math.ceil(long / hy - 0.5) + 2) - math.ceil(long / hy - 0.5) - 0.5)
        n = (xe.size - 1) * (ye.size - 1)
        if n > MAX_GRID_ELEMENTS:
            raise ValueError(f"dx = {h:g} needs {n} elements for a cone of length {self.length:g} "
                             f"(> {MAX_GRID_ELEMENTS}): use a larger dx or a shorter cone")
        return xe, ye

    def grid_pressure(self, x_edges, y_edges, xc, scale=1.0):
        """Element means of the slice pressure [p0m] on a run's grid, the contact line at ``theta = xc / r_m``.

        Each slice at the distance ``u`` from the apex (along the rotated line,
        ``r1 <= u <= r2``) is a Hertz line contact of half-width ``a(u) =
        s sqrt(u / r_m)`` and peak ``s sqrt(r_m / u)`` (``s = scale =
        sqrt(P)``, :meth:`load_scale`, ``P`` the normal load over the nominal
        one; uniform along the line). Across an
        element the distance ``v`` from the rotated line is linear in ``x``,
        so each of :data:`_SUB_ROWS` sub-rows of an element row is integrated
        exactly across; the means are scaled to the load ``P Fn`` (a fraction of
        a per cent at the ends, which the sub-rows resolve to an eighth of an
        element's length ``dy = ASPECT dx`` along the line).
        """
        P = float(scale) ** 2
        theta = float(xc) / self.r_m
        h = float(x_edges[1] - x_edges[0])
        hy = float(y_edges[1] - y_edges[0])
        x = 0.5 * (np.asarray(x_edges[1:]) + np.asarray(x_edges[:-1]))
        ys = (np.asarray(y_edges[:-1])[:, None] + hy * (np.arange(_SUB_ROWS) + 0.5)[None, :] / _SUB_ROWS).ravel()
        c, s = math.cos(theta), math.sin(theta)
        Y = (ys + self.r_m)[:, None]  # from the apex
        u = Y * c + x[None, :] * s
        inside = (u >= self.r1) & (u <= self.r2) & (u > 0)
        us = np.where(inside, u, 1.0)
        a = float(scale) * np.sqrt(us / self.r_m)
        v0 = (x[None, :] - 0.5 * h) * c - Y * s
        v1 = (x[None, :] + 0.5 * h) * c - Y * s
        # p0(u) a(u) = P: the integral across is P [F(v1/a) - F(v0/a)] / cos(theta)
        band = np.where(inside, P * (_half_integral(v1 / a) - _half_integral(v0 / a)) / (c * h), 0.0)
        p = band.reshape(y_edges.size - 1, _SUB_ROWS, x.size).mean(axis=1)
        total = float(p.sum()) * h * hy
        if total > 0:
            p *= P * self.total_load / total
        return p

    def grid_limit(self, w, dx=None, dW=None, polygon=32):
        """Melan's limit on a run's grid: the largest ``ft`` a traction ``|q| <= mu p_min`` carries with no force
        across and no moment about the normal through the load point, a linear programme.

        ``p_min`` is the lowest element pressure over the positions of one
        rocking period (:func:`core.loading.schedule.rocking_schedule` with step ``dW``,
        default ``dx``), exactly those a run at ``dx``, ``dW`` sees. The Coulomb
        disk ``|q| <= mu p_min`` is replaced by the regular ``polygon``-gon
        around it (an upper bound ``hi``) and inside it (``hi cos(pi/polygon)``,
        a lower bound); ``along`` is the programme with ``q_y = 0`` (the slice
        model's, a lower bound).

        Returns
        -------
        dict
            ``lo``, ``hi``, ``along`` (ft = Ft/(mu Fn)), ``elements`` (in contact at every position).
        """
        w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
        dx = check_scalar("dx", self.default_dx if dx is None else dx, 0.005, 1.0)
        dW = self.rocking_step(dx) if dW is None else check_scalar("dW", dW, 1e-4, 1.0)
        polygon = int(check_scalar("polygon", polygon, 4, 4096))
        # every run's verdict may ask for it (CycleResult.melan_limit): equal cones share the programme's answer
        return dict(_grid_limit(self, w, dx, dW, polygon))

    def _grid_limit(self, w, dx, dW, polygon):
        from scipy.optimize import linprog
        from scipy.sparse import coo_matrix, hstack, vstack, csr_matrix
        from ..loading.schedule import rocking_schedule
        from .patch import twist_field

        xe, ye = self.run_grid(w, 1.0, dx)
        xcs = np.unique(rocking_schedule(0.0, w, periods=1, dW=dW).xc)
        p_min = None
        for xc in xcs:
            p = self.grid_pressure(xe, ye, xc)
            p_min = p if p_min is None else np.minimum(p_min, p)
        on = p_min.ravel() > 0
        g = p_min.ravel()[on]
        n = g.size
        dA = dx * (ASPECT * dx)
        cost = -np.concatenate([np.full(n, dA), np.zeros(n)]) / self.total_load
        if self.twist_centre is None:
            A_eq = csr_matrix(np.concatenate([np.zeros(n), np.ones(n)])[None, :])
        else:
            t = twist_field(xe, ye, self.twist_centre).reshape(2, -1)[:, on]
            A_eq = csr_matrix(np.vstack([np.concatenate([np.zeros(n), np.ones(n)]), np.concatenate([t[0], t[1]])]))
        b_eq = np.zeros(A_eq.shape[0])
        ang = 2.0 * math.pi * (np.arange(polygon) + 0.5) / polygon
        eye = coo_matrix((np.ones(n), (np.arange(n), np.arange(n))), shape=(n, n))
        A_ub = vstack([hstack([math.cos(al) * eye, math.sin(al) * eye]) for al in ang]).tocsr()
        b_ub = np.tile(g, polygon)
        res = linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=(None, None), method="highs")
        if not res.success:
            raise RuntimeError(f"the Melan programme did not solve: {res.message}")
        hi = -float(res.fun)
        # q_y = 0: |q_x| <= g with the moment of q_x alone
        A1 = A_eq[:, :n] if self.twist_centre is not None else None
        res1 = linprog(cost[:n], A_eq=A1[1:] if A1 is not None else None, b_eq=np.zeros(1) if A1 is not None else None,
                       bounds=np.column_stack([-g, g]), method="highs")
        if not res1.success:
            raise RuntimeError(f"the Melan programme (q_y = 0) did not solve: {res1.message}")
        return {"lo": hi * math.cos(math.pi / polygon), "hi": hi, "along": -float(res1.fun), "elements": int(n)}


@functools.lru_cache(maxsize=64)
def _grid_limit(cone, w, dx, dW, polygon):
    """:meth:`Cone.grid_limit` (validated inputs), cached by the cone's parameters and the grid's."""
    return tuple(cone._grid_limit(w, dx, dW, polygon).items())
