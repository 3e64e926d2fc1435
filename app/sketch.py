"""A sketch of the rocking body at the cycle player's step, for a lecture: where the body is, which way it
moves, and which edge of the contact trails (lets go of the substrate).

Not to scale (a real contact's half-width a is a few per cent of R): the cylinder (and a sphere's or an
ellipsoid's section on y = 0) is drawn with radius :data:`RADIUS` half-widths, its contact patch 2a wide, the
Hertz pressure under it, and a spoke that turns as it rolls without slip. Another body is drawn from its gap
(its profile: a line body's ``profile(x)``, a height map's row on y = 0), stretched so that its shape shows,
with the pressure of the run under it. Coordinates are x/a. A figure of :data:`app.plots.FIGURES` ("sketch"): :func:`specs` gives
its layers' looks, :func:`layers` their data, from the run and the player's step.
"""

from __future__ import annotations

import functools

import holoviews as hv
import numpy as np

import core

from .live import Layer

__all__ = ["RADIUS", "specs", "layers", "motion"]

#: Radius of the drawn cylinder, in contact half-widths (not to scale).
RADIUS = 2.0
_EMPTY = (np.zeros(0), np.zeros(0))
_VERMILLION, _BLUE, _GREY = "#D55E00", "#0072B2", "#999999"


def _round_circles(plot, element) -> None:
    """Keep the circle round: equal data units per pixel on both axes."""
    plot.state.match_aspect = True


def specs(units=None) -> list:
    """The sketch's layers: ground, centre range ±W, pressure, cylinder, spoke, contact patch, direction, trailing
    edge."""
    kx, ky = hv.Dimension("x", label="x / a (sketch, not to scale)"), hv.Dimension("y", label="y")

    def line(label, color, width=2, dash="solid", **kw):
        return Layer(hv.Curve, (kx,), (ky,), label, dict(color=color, line_width=width, line_dash=dash, **kw))
    return [
        line("", "#444444", 2, hooks=[_round_circles]),
        Layer(hv.VLines, (kx,), (), "centre range ±W", dict(color=_GREY, line_dash="dotted", line_width=2)),
        line("pressure (below)", _BLUE, 2),
        line("body", "black", 3),
        line("", "black", 2),
        line("contact 2a", _VERMILLION, 6),
        line("rolling direction", "black", 3),
        Layer(hv.Scatter, (kx,), (ky,), "trailing edge",
              dict(color=_VERMILLION, marker="triangle", size=16, line_color="black")),
    ]


def motion(result: core.CycleResult, k: int) -> int:
    """Which way the contact centre moves at step ``k``: +1, -1, or 0 at rest (the loading)."""
    if k <= 0:
        return 0
    return int(np.sign(float(result.xc[k]) - float(result.xc[k - 1])))


@functools.lru_cache(maxsize=8)
def _static(w: float) -> tuple:
    reach = 1.0 + w + RADIUS + 0.5
    return (np.array([-reach, reach]), np.zeros(2)), [-w, w]


def _body(result):
    """The body of a run when it is drawn from its gap (None: the cylinder or an ellipsoid, drawn as a circle)."""
    body = result.body
    if body is None or isinstance(body, core.Cylinder) or isinstance(body, core.Ellipsoid):
        return None
    return body


def _gap(body, x: np.ndarray) -> np.ndarray:
    """The body's gap along x on y = 0 (a line body's profile; a height map's row through its centre)."""
    heights = getattr(body, "heights", None)
    if heights is not None and np.ndim(heights) == 2:
        row = np.asarray(heights)[heights.shape[0] // 2]
        xs = (np.arange(row.size) - row.size // 2) * float(body.spacing)
        return np.interp(x, xs, row - row.min())
    if getattr(body, "dim", 1) == 2:  # a point body's profile(x, y), on y = 0
        return np.asarray(body.profile(x, np.zeros_like(x)), dtype=float)
    return np.asarray(body.profile(x), dtype=float)


def _outline(body, xc: float) -> tuple:
    """A closed outline of ``body`` at ``xc``: its gap stretched so that it rises by ``RADIUS`` at ``±RADIUS``,
    then straight sides and a flat top (not to scale, like the circle)."""
    x = np.linspace(-RADIUS, RADIUS, 161)
    try:
        g = _gap(body, x)
    except (AttributeError, TypeError, ValueError):  # a body without a profile on y = 0: its pressure only
        return _EMPTY
    top = float(max(g[0], g[-1]))
    y = RADIUS * g / top if top > 0 else np.zeros_like(g)
    h = 2 * RADIUS
    return (np.concatenate([x, [RADIUS, -RADIUS, -RADIUS]]) + xc, np.concatenate([y, [h, h, y[0]]]))


def _run_pressure(result, k: int) -> tuple:
    """The run's own pressure at step ``k`` on y = 0 (x [a], p [p0]): a cylinder-kind run's per element, a point
    run's on its row through y = 0."""
    if not result.is_patch:
        return np.asarray(result.x), np.asarray(result.pressure[k])
    row = int(np.clip(np.searchsorted(result.y_edges, 0.0) - 1, 0, result.y_edges.size - 2))
    return 0.5 * (result.x_edges[1:] + result.x_edges[:-1]), np.asarray(result.pressure(k)[row])


def _circle(xc: float) -> tuple:
    """The drawn circle of radius :data:`RADIUS` at ``xc`` and its spoke, turned by ``xc / R`` (rolling without slip)."""
    t = np.linspace(0, 2 * np.pi, 121)
    circle = (xc + RADIUS * np.cos(t), RADIUS + RADIUS * np.sin(t))
    phi = -np.pi / 2 - xc / RADIUS
    return circle, (np.array([xc, xc + RADIUS * np.cos(phi)]), np.array([RADIUS, RADIUS + RADIUS * np.sin(phi)]))


def layers(inputs) -> tuple:
    """The sketch at the player's step of ``inputs.result`` (empty layers without a run)."""
    r = inputs.result
    if r is None:
        return (_EMPTY, [], *[_EMPTY] * 5, _EMPTY)
    k = int(np.clip(inputs.frame if inputs.frame is not None else r.xc.size - 1, 0, r.xc.size - 1))
    ground, centre_range = _static(round(float(r.params.get("w", 0.0)), 6))
    xc, load = float(r.xc[k]), float(np.atleast_1d(r.P)[min(k, np.size(r.P) - 1)])
    body = _body(r)
    if body is None:
        point = r.is_patch
        a = load ** (1.0 / 3.0) if point else np.sqrt(load)  # the half-width grows as P^(1/3) or sqrt(P) (eq 5)
        outline, spoke = _circle(xc)
        xs = np.linspace(xc - a, xc + a, 41)
        pressure = (xs, -0.8 * a * core.hertz_pressure((xs - xc) / a))  # p0 grows with the load too
        patch = (np.array([xc - a, xc + a]), np.zeros(2))
    else:  # drawn from its gap, with the run's own pressure; the contact: where it presses
        outline, spoke = _outline(body, xc), _EMPTY
        if not len(outline[0]):  # no profile on y = 0 (the cone: its section there is a circle): a rolling circle
            outline, spoke = _circle(xc)
        xs, p = _run_pressure(r, k)
        pressure = (xs, -0.8 * p)
        pressed = xs[p > 0]
        a = 0.5 * float(pressed.max() - pressed.min()) if pressed.size else 0.0
        patch = (np.array([pressed.min(), pressed.max()]), np.zeros(2)) if pressed.size else _EMPTY
    circle = outline
    s = motion(r, k)
    if s == 0:
        arrow, trailing = _EMPTY, _EMPTY
    else:
        y, tip = 2 * RADIUS + 0.5, xc + s * 1.6
        arrow = (np.array([xc, tip, tip - s * 0.35, np.nan, tip, tip - s * 0.35]),
                 np.array([y, y, y + 0.25, np.nan, y, y - 0.25]))
        trailing = (np.array([(patch[0][0] if s > 0 else patch[0][-1]) if body is not None and len(patch[0])
                              else xc - s * a]), np.array([0.0]))
    return (ground, centre_range, pressure, circle, spoke, patch, arrow, trailing)
