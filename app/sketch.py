"""A sketch of the rocking cylinder at the cycle player's step, for a lecture: where the cylinder is, which way it
rolls, and which edge of the contact trails (lets go of the substrate).

Not to scale (a real contact's half-width a is a few per cent of R): the cylinder is drawn with radius
:data:`RADIUS` half-widths, its contact patch 2a wide, the Hertz pressure under it, and a spoke that turns as it
rolls without slip. Coordinates are x/a. A figure of :data:`app.plots.FIGURES` ("sketch"): :func:`specs` gives
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
        line("Hertz pressure (below)", _BLUE, 2),
        line("cylinder", "black", 3),
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


def layers(inputs) -> tuple:
    """The sketch at the player's step of ``inputs.result`` (empty layers without a run)."""
    r = inputs.result
    if r is None:
        return (_EMPTY, [], *[_EMPTY] * 5, _EMPTY)
    k = int(np.clip(inputs.frame if inputs.frame is not None else r.xc.size - 1, 0, r.xc.size - 1))
    ground, centre_range = _static(round(float(r.params.get("w", 0.0)), 6))
    xc, load = float(r.xc[k]), float(np.atleast_1d(r.P)[min(k, np.size(r.P) - 1)])
    a = np.sqrt(load)  # the half-width grows with the normal load as sqrt(P) (eq 5)
    t = np.linspace(0, 2 * np.pi, 121)
    circle = (xc + RADIUS * np.cos(t), RADIUS + RADIUS * np.sin(t))
    phi = -np.pi / 2 - xc / RADIUS  # rolling without slip: the spoke turns by xc / R
    spoke = (np.array([xc, xc + RADIUS * np.cos(phi)]), np.array([RADIUS, RADIUS + RADIUS * np.sin(phi)]))
    xs = np.linspace(xc - a, xc + a, 41)
    pressure = (xs, -0.8 * a * core.hertz_pressure((xs - xc) / a))  # p0 grows as sqrt(P) too
    patch = (np.array([xc - a, xc + a]), np.zeros(2))
    s = motion(r, k)
    if s == 0:
        arrow, trailing = _EMPTY, _EMPTY
    else:
        y, tip = 2 * RADIUS + 0.5, xc + s * 1.6
        arrow = (np.array([xc, tip, tip - s * 0.35, np.nan, tip, tip - s * 0.35]),
                 np.array([y, y, y + 0.25, np.nan, y, y - 0.25]))
        trailing = (np.array([xc - s * a]), np.array([0.0]))
    return (ground, centre_range, pressure, circle, spoke, patch, arrow, trailing)
