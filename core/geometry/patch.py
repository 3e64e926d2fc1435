"""A point body on a patch of square elements: its grid, its traction bound at every step, its twist field.

The body side of a patch run (:func:`core.march.engine.run`'s body protocol on a
patch): :class:`PatchGrid` (a point body on a grid covering every contact of a
history, its bound ``mu p`` per step, cached by the centre's offset and the
load), the pressure of a Hertz body on the grid (:func:`_pressure`: the
discrete normal problem of :func:`core.pressure.normal.solve_normal` on the grid's
elements, as CONTACT computes it, or the element means of Hertz's closed
form) and :func:`twist_field` (the rigid slip of a unit rotation about the
normal, for a body free to turn: the cone). The per-step solver that runs on
it is :mod:`core.solvers.solver3d`.
"""

from __future__ import annotations

import math
import threading

import numpy as np

from ..base._validate import read_only
from ..pressure.normal import PatchOperator, solve_normal
from ..theory.point_contact import Ellipsoid, gap_curvatures as _gap_curvatures, hertz_element_means

__all__ = ["PatchGrid", "twist_field", "MAX_GRID_ELEMENTS"]

#: Largest grid (elements) a point-contact run accepts.
MAX_GRID_ELEMENTS = 200_000


def twist_field(x_edges, y_edges, centre):
    """The rigid slip ``(-(y - y_c), x - x_c)`` [a] of a unit rotation about the normal through ``centre``.

    At the element centres of the grid ``x_edges``, ``y_edges``: the ``twist``
    argument of :func:`solve_increment` for a body free to turn about the
    normal through ``centre = (x_c, y_c)`` [a] (a point on the line of action
    of the tangential force).

    Returns
    -------
    ndarray, shape (2, ny, nx)
    """
    xc, yc = (float(v) for v in centre)
    x = 0.5 * (np.asarray(x_edges[1:], float) + np.asarray(x_edges[:-1], float))
    y = 0.5 * (np.asarray(y_edges[1:], float) + np.asarray(y_edges[:-1], float))
    out = np.empty((2, y.size, x.size))
    out[0] = -(y - yc)[:, None]
    out[1] = (x - xc)[None, :]
    return out



def _centred_edges(reach, h):
    """Edges of an odd number of elements of side ``h`` centred on 0 (one element at 0) covering ``[-reach, reach]``."""
    half = math.ceil(reach / h - 0.5 - 1e-9) + 1
    return h * (np.arange(2 * half + 2) - half - 0.5)


# Polonsky-Keer iterations: relative change of the load distribution at which the normal solve stops, and its cap
_NORMAL_RTOL = 1e-13
_NORMAL_MAXITER = 2000


class _NormalWindow:
    """The discrete normal problem of a Hertz contact on a window of the grid: :func:`core.pressure.normal.solve_normal`.

    Piecewise-constant pressures on the grid's square elements, gaps
    collocated at their centres, the Boussinesq influence coefficients
    ``(1/(pi E*)) integral of 1/rho`` over each element (exact,
    :func:`core.elastic.halfspace.rectangle_integrals`, in :class:`core.pressure.normal.PatchOperator`),
    the total load prescribed, solved by the one normal solver of the package
    (Polonsky-Keer's constrained CG, preconditioned by the inverse continuous
    symbol). This is CONTACT's normal problem (Kalker; Vollebregt): the traction bound
    ``mu p`` of an element is then the pressure that the same discrete
    elasticity gives it, instead of a mean of the continuous Hertz field.
    """

    def __init__(self, half_y, half_x, h):
        self.shape = (2 * half_y + 1, 2 * half_x + 1)
        self.h = h
        self.op = PatchOperator(*self.shape, h, 1.0 / math.pi)

    def apply(self, p):
        return self.op.apply(p)

    def solve(self, gap, load, guess):
        """Pressures >= 0 with ``sum p h^2 = load``, gap + displacement constant where ``p > 0``, >= it elsewhere."""
        try:
            return solve_normal(gap, load, self.op, self.h * self.h, tol=_NORMAL_RTOL, maxiter=_NORMAL_MAXITER,
                                initial=guess).pressure.copy()
        except ValueError as e:
            raise RuntimeError(f"the normal problem did not converge: {e}") from e


_NORMAL_CACHE = {}
_NORMAL_LOCK = threading.Lock()  # the cache is shared by the threads of a process (the app's solves)


def _pressure(x_edges, y_edges, xc, body, scale=1.0, normal="numerical"):
    """The traction bound's pressure on a point-contact grid at centre ``xc`` and load scale ``scale`` [p0].

    With ``normal="numerical"`` (the default) the pressure of the discrete normal
    problem on the grid (:class:`_NormalWindow`), as CONTACT computes it: on
    the sphere at ft 0.6, w 0.3 it moved the increment per period from 1.6 %
    to 0.3 % below CONTACT's at 40 elements across the contact
    (``docs/guide/numerics.md``). The gap is the body's quadratic profile, so
    the pressure is Hertz's up to the discretization; the solve runs on a
    window around the contact and is cached by the centre's offset from its
    nearest element (a translate serves every aligned centre) and the scale.
    With ``normal="exact"``, the element means of Hertz's pressure
    (:func:`core.theory.point_contact.hertz_element_means`).
    """
    if hasattr(body, "grid_pressure"):  # a body that solves its own normal problem (core.geometry.heightmap.HeightMap)
        return body.grid_pressure(x_edges, y_edges, xc, scale)
    if normal == "exact":
        return hertz_element_means(x_edges, y_edges, xc, body.kappa, scale)
    h = float(x_edges[1] - x_edges[0])
    xs = 0.5 * (x_edges[1:] + x_edges[:-1])
    i0 = int(np.argmin(np.abs(xs - xc)))
    offset = float(xc - xs[i0])
    half_x = math.ceil(scale / h - 0.5) + 1
    half_y = math.ceil(body.kappa * scale / h - 0.5) + 1
    key = (round(h, 12), round(offset / h, 9), round(scale, 12), body.kappa)
    with _NORMAL_LOCK:
        window = _NORMAL_CACHE.get(key)
    if window is None:
        solver = _NormalWindow(half_y, half_x, h)
        X = h * (np.arange(-half_x, half_x + 1) - offset / h)[None, :]
        Y = h * np.arange(-half_y, half_y + 1)[:, None]
        A, B = _gap_curvatures(body.kappa)
        guess = scale * np.sqrt(np.clip(1.0 - (X / scale) ** 2 - (Y / (body.kappa * scale)) ** 2, 0.0, None))
        p = solver.solve(A * X * X + B * Y * Y, body.total_load * scale**3, guess + 1e-3 * (guess > 0))
        p = 0.5 * (p + p[::-1])  # exactly mirror-symmetric in y (the window is centred on y = 0)
        if offset == 0.0:
            p = 0.5 * (p + p[:, ::-1])
        with _NORMAL_LOCK:
            if len(_NORMAL_CACHE) >= 64:  # sine schedules and load steps: a few offsets and scales per run
                _NORMAL_CACHE.clear()
            window = _NORMAL_CACHE[key] = read_only(p)
    out = np.zeros((y_edges.size - 1, x_edges.size - 1))
    ny = out.shape[0]
    c = ny // 2
    rows = slice(max(c - half_y, 0), min(c + half_y + 1, ny))
    cols = slice(max(i0 - half_x, 0), min(i0 + half_x + 1, out.shape[1]))
    out[rows, cols] = window[rows.start - (c - half_y):rows.stop - (c - half_y),
                             cols.start - (i0 - half_x):cols.stop - (i0 - half_x)]
    total = float(out.sum()) * h * h
    if total > 0:  # the load that fell off the grid's edge (none where the grid covers the contact)
        out *= body.total_load * scale**3 / total
    return out


def _normal_mode(normal, body):
    """``"exact"`` or ``"numerical"`` for ``normal`` (``"auto"``: numerical, the discrete bound on the grid)."""
    if normal not in ("auto", "exact", "numerical"):
        raise ValueError(f"normal must be one of ('auto', 'exact', 'numerical'), got {normal!r:.60}")
    if normal == "exact" and not isinstance(body, Ellipsoid):
        raise ValueError(f"normal='exact' needs a closed-form pressure (a sphere or an ellipsoid); "
                         f"{type(body).__name__} has none: use normal='numerical' or 'auto'")
    return "exact" if normal == "exact" else "numerical"


def _grid(body, reach_x, scale, h):
    xe = _centred_edges(reach_x, h)
    ye = _centred_edges(body.kappa * scale, h)
    if (xe.size - 1) * (ye.size - 1) > MAX_GRID_ELEMENTS:
        raise ValueError(f"dx = {h:g} needs {(xe.size - 1) * (ye.size - 1)} elements (> {MAX_GRID_ELEMENTS}): "
                         "use a larger dx")
    return xe, ye


class PatchGrid:
    """A point-contact body on a patch of square elements: what :func:`core.march.engine.run` asks of it.

    The patch-grid side of the engine's body protocol (see :mod:`core.march.engine`):
    ``shape`` ``(ny, nx)``, ``size``, ``dx``, ``dy`` (the element's sides: equal but for a
    body whose ``run_grid`` has longer elements along y, a cone), ``edges`` (along x), ``y_edges``;
    :meth:`bounds` (the traction bound ``mu p`` of each step, one ``(ny, nx)``
    array a step, cached by centre and load scale: a body that only translates
    is solved once per offset from the grid, :func:`_pressure`);
    :meth:`load_target` (``Q`` times the body's total load); ``solver_options``
    (the body's own options of :class:`PatchSolver`, e.g. a cone's twist
    centre); ``body_spec`` (the body).

    The body supplies (duck-typed): ``name``, ``total_load`` [p0 a^2],
    ``kernel_scale`` (the half-space kernel's factor in its units) and either
    ``kappa`` (an ellipsoid: Hertz's pressure, closed form or solved on the
    grid) or ``run_grid(reach_x, scale, h)`` and ``grid_pressure(x_edges,
    y_edges, xc, scale)`` (its own grid and pressure: a height map, a cone);
    optionally ``load_scale(P)`` (the length scale of its contact under the
    normal load ``P``, the ``scale`` above; default ``P^(1/3)``),
    ``default_dx``, ``solver_options`` (a dict of keyword options of
    :func:`solve_increment`, passed through :class:`PatchSolver` and
    :meth:`_Window.solve`) and ``twist_centre`` (``(x_c, y_c)`` [a]: the body
    is free to turn about the normal through it, a cone; its
    :func:`twist_field` on the grid becomes the ``twist`` option of every
    :func:`solve_increment`, and the run records the rotation).

    Parameters
    ----------
    body : object
        The body (:class:`core.theory.point_contact.Ellipsoid`, :class:`core.geometry.heightmap.HeightMap`, ...).
    x_edges, y_edges : ndarray
        Edges of the elements [a], uniform along each axis (square elements
        unless the body's own grid says otherwise); a row centred on ``y = 0``.
    normal : {"exact", "numerical"}
        The Hertz bodies' pressure (see :func:`_pressure`).
    """

    def __init__(self, body, x_edges, y_edges, normal="numerical"):
        self.body_spec = body
        self.name = body.name
        self.normal = normal
        self.x_edges = read_only(np.array(x_edges, dtype=float))
        self.y_edges = read_only(np.array(y_edges, dtype=float))
        self.edges = self.x_edges
        self.dx = float(self.x_edges[1] - self.x_edges[0])
        #: Element side along y [a]: ``dx`` (square elements, exactly, whatever the edges' round-off) unless the
        #: body's grid is longer along y (a cone's, :attr:`core.geometry.cone.Cone.aspect`).
        dy = float(self.y_edges[1] - self.y_edges[0]) if self.y_edges.size > 1 else self.dx
        self.dy = self.dx if abs(dy - self.dx) <= 1e-9 * self.dx else dy
        self.shape = (self.y_edges.size - 1, self.x_edges.size - 1)
        self.size = self.shape[0] * self.shape[1]
        self.solver_options = dict(getattr(body, "solver_options", None) or {})
        centre = getattr(body, "twist_centre", None)  # free to turn about the normal through it (a cone)
        if centre is not None:
            self.solver_options["twist"] = twist_field(self.x_edges, self.y_edges, centre)
        self._cache = {}

    @classmethod
    def for_history(cls, body, history, dx, normal="numerical"):
        """The grid covering every contact of ``history``: the body's ``run_grid`` or the ellipse's box."""
        own = getattr(body, "load_scale", None)
        scales = np.asarray(own(history.P), dtype=float) if own is not None else np.cbrt(history.P)
        if hasattr(body, "run_grid"):  # a body with its own grid (a height map)
            xe, ye = body.run_grid(float(np.max(np.abs(history.xc))), float(scales.max()), dx)
        else:
            xe, ye = _grid(body, float(np.max(np.abs(history.xc) + scales)), float(scales.max()), dx)
        return cls(body, xe, ye, normal)

    def load_scale(self, P):
        """The contact's length scale under the normal load ``P`` [nominal]: the body's ``load_scale(P)`` if it
        has one, else ``P^(1/3)`` (Hertz, point contact)."""
        own = getattr(self.body_spec, "load_scale", None)
        return np.asarray(own(P), dtype=float) if own is not None else np.cbrt(P)

    def pressure(self, xc, scale=1.0):
        """Element pressure [p0], shape (ny, nx), with the centre at ``xc`` and the length scale ``scale`` (cached)."""
        key = (float(xc), float(scale))
        g = self._cache.get(key)
        if g is None:
            g = self._cache[key] = _pressure(self.x_edges, self.y_edges, key[0], self.body_spec, key[1], self.normal)
        return g

    def bounds(self, xc, P, out=None):
        """The traction bound ``mu p`` [mu p0] of each step: a list of ``(ny, nx)`` arrays (shared: do not write)."""
        return [self.pressure(x, s) for x, s in zip(np.asarray(xc, float).tolist(), self.load_scale(P).tolist())]

    def load_target(self, Q):
        """``sum q dA`` [mu p0 a^2] that carries the tangential load ``Q`` [mu Fn]: ``Q`` times the total load."""
        return np.asarray(Q, dtype=float) * self.body_spec.total_load
