"""HoloViews figures of the explorer: pure functions of the inputs and of a solver result.

Each figure is a list of layers. Its *layer data* (plain numpy arrays) come
from memoised pure functions of the inputs (``*_layers``), its *look*
(element type, dimensions with units, legend label, style) from a list of
:class:`Layer` (``*_specs``), and ``*_figure`` joins them into a
``hv.Overlay``. The explorer renders that overlay once and afterwards pushes
only the layer data that changed into the live Bokeh figure
(:class:`app.live.LiveFigure`): an unchanged layer is the same object (memoised),
so it is skipped. Every figure has the same layers whatever its inputs (empty
data where a curve does not apply). No physics here: every curve comes from
:mod:`core`; this module only scales, labels and styles.

Layer data by element type: ``Curve``, ``Scatter``, ``Points``: a tuple of
columns ``(x, y)``; ``Rectangles``: rows ``(x0, y0, x1, y1)``; ``HLines``,
``VLines``: positions; ``Image``: ``(array, bounds)``; a static layer: None.
A layer whose glyph colour encodes a state is a :class:`~app.live.Styled`.
"""

from __future__ import annotations

import functools
import math
from functools import lru_cache
from typing import NamedTuple

import holoviews as hv
import holoviews.plotting.bokeh  # noqa: F401 - registers the Bokeh backend and its options
import numpy as np

import core
from core.theory import approximations as approx

from . import pinned, sketch
from .live import Layer, Styled, overlay
from .units import Units, along_ft, make_units, time_axis

__all__ = ["Units", "make_units", "Inputs", "FIGURES", "figure", "layers", "specs", "group",
           "pressure_curves", "pressure_step", "traction_zones", "traction_run", "traction_bounds",
           "traction_closure", "state_image", "state_marks", "frame_marks", "time_axis", "displacement_curves",
           "displacement_step", "loop_curves", "increment_layers", "map_base", "map_numerical", "map_point", "grid_boundary",
           "ZONE_COLORS", "STATE_COLORS", "REGIME_COLORS", "REGIME_MARKERS", "OKABE_ITO", "FONT"]

hv.Store.set_current_backend("bokeh")
# Plain canvas: these figures are small, and WebGL without a GPU (projector laptops, headless
# browsers) spends seconds copying its buffers into the page on every update.
hv.plotting.bokeh.BokehRenderer.webgl = False

#: Font sizes readable on a projector.
FONT = {"title": 17, "labels": 16, "xticks": 14, "yticks": 14, "legend": 14, "cticks": 13}
LINE = 3
HEIGHT = 480
#: Height of a figure of the first screen [px] (:data:`app.figures.KEY_FIGURES`): three fit above the fold at
#: 1280x720 and at 1024x768, two or three in a row.
KEY_HEIGHT = 330


def readable_ticks(plot, element) -> None:
    """A render hook: few tick labels on a narrow figure's axes, so that they never run into each other (a first
    screen's figure is 240 to 420 px wide: the default six ticks gave "-1.5-1-0.5" on a wide x range, and a log
    axis spanning less than two decades, where Bokeh ticks linearly, piled 0.04 to 0.09 at its top)."""
    from bokeh.models import LogTicker

    fig = plot.state
    for axis in (*fig.xaxis, *fig.yaxis):
        ticker = getattr(axis, "ticker", None)
        if isinstance(ticker, LogTicker):
            ticker.desired_num_ticks = 3
        elif ticker is not None and hasattr(ticker, "desired_num_ticks"):
            ticker.desired_num_ticks = 4


def title_over_axis(plot, element) -> None:
    """A render hook: the title starts over the y axis, not over the frame, so that a narrow figure's title is
    not cut at its right edge (the y axis of a first-screen figure is at least :data:`KEY_SHIFT` px wide); the
    legend under the x axis is shifted as far (``legend_offset`` of :func:`key_opts`)."""
    readable_ticks(plot, element)
    title = plot.state.title
    if title is not None:
        title.offset = -KEY_SHIFT


def few_x_ticks(plot, element) -> None:
    """A render hook after :func:`title_over_axis`: three ticks on the x axis, for an axis whose tick labels are long
    (the fretting loop's displacements, e.g. 0.032 to 0.036 on a narrow first-screen figure: four ran together)."""
    for axis in plot.state.xaxis:
        ticker = getattr(axis, "ticker", None)
        if ticker is not None and hasattr(ticker, "desired_num_ticks"):
            ticker.desired_num_ticks = 3


#: How far left of the frame a first-screen figure's title and legend start [px] (:func:`title_over_axis`).
KEY_SHIFT = 45


def key_opts() -> dict:
    """Options of a first-screen figure: lower, its legend outside the frame, under the x axis, in two columns of
    small type (inside the frame it covered the curves: the traction's 6 to 9 entries half the plot), few ticks
    and the title over the y axis too (:func:`title_over_axis`)."""
    return dict(height=KEY_HEIGHT, legend_position="bottom", legend_cols=2, legend_offset=(-KEY_SHIFT, 0),
                fontsize={**FONT, "title": 12, "labels": 15, "legend": 11},  # pt: a title fits 240 px
                backend_opts={**_BASE["backend_opts"], "plot.toolbar.autohide": True},  # no toolbar over the title
                legend_opts={"label_text_font_size": "11px", "spacing": 0, "padding": 2, "margin": 0,
                             "label_height": 12, "glyph_height": 12, "glyph_width": 14, "label_standoff": 3,
                             "border_line_alpha": 0},
                hooks=[title_over_axis])
#: Okabe and Ito's colour-blind-safe palette (distinct under deuteranopia, protanopia and tritanopia).
OKABE_ITO = {"orange": "#E69F00", "sky": "#56B4E9", "green": "#009E73", "yellow": "#F0E442", "blue": "#0072B2",
             "vermillion": "#D55E00", "purple": "#CC79A7", "black": "#000000", "grey": "#999999"}
_C = OKABE_ITO
#: Colours of the element states released / stick / slip forward / slip backward (the colour bar names them).
STATE_COLORS = ("#eeeeee", _C["blue"], _C["orange"], _C["purple"])
#: Shading of the zones stick / slip / zero traction; slip is also hatched (a cue that needs no colour).
ZONE_COLORS = {"stick": _C["blue"], "slip": _C["orange"], "zero traction": _C["grey"]}
ZONE_HATCH = {"stick": " ", "slip": "/", "zero traction": " "}
_ZONE_CODES = {"stick": core.Zone.STICK, "slip": core.Zone.SLIP, "zero traction": core.Zone.RELEASED}
#: Colour and marker of a point on the map, by numerical regime (None: not solved yet): shape is the second cue.
REGIME_COLORS = {"shakedown": _C["blue"], "cyclic slip": _C["orange"], "ratcheting": _C["vermillion"],
                 "undetermined": _C["grey"], None: _C["grey"]}
REGIME_MARKERS = {"shakedown": "circle", "cyclic slip": "hex", "ratcheting": "triangle", "undetermined": "diamond",
                  None: "square"}
_NX = 401
_EMPTY = (np.zeros(0), np.zeros(0))

# legend_offset: HoloViews puts a legend at the bottom of its panel, its margin below the canvas, where the border
# was cut off; 20 px up centres it in the panel
_BASE = dict(fontsize=FONT, responsive=True, height=HEIGHT, show_grid=True, legend_offset=(0, 20),
             toolbar="above", default_tools=["pan", "wheel_zoom", "box_zoom", "reset", "save"],
             # no tool active: the wheel scrolls the page and a finger scrolls a phone's page; zoom and pan are
             # one click away in the toolbar
             active_tools=[],
             backend_opts={"plot.toolbar.autohide": False, "plot.toolbar.active_scroll": None,
                           "plot.toolbar.active_drag": None},
             hooks=[readable_ticks])


def _memo(fn):
    """Keep the last few outputs: an unchanged layer is returned as the same object, so the figure skips it."""
    return functools.lru_cache(maxsize=4)(fn)


def _line(label, color, kd, vd, dash="solid", width=LINE, alpha=1.0) -> Layer:
    return Layer(hv.Curve, (kd,), (vd,), label, dict(color=color, line_dash=dash, line_width=width, alpha=alpha))


def _dim(name: str, label: str) -> hv.Dimension:
    return hv.Dimension(name, label=label)


def _x_grid(w: float) -> np.ndarray:
    reach = 1.0 + w
    return np.linspace(-1.08 * reach, 1.08 * reach, _NX)


def _step(result: core.CycleResult, frame: int | None) -> int:
    """The step shown: ``frame`` within the run, or the last step."""
    last = result.xc.size - 1
    return last if frame is None else int(np.clip(frame, 0, last))


def line_body(result):
    """The line body of a cylinder-kind run when it is not the cylinder (a punch...), else None: the cylinder's
    figures draw its closed forms (Hertz, eq 35, the closure) for the cylinder and the body's own curves otherwise."""
    body = getattr(result, "body_spec", None)
    return None if body is None or isinstance(body, core.Cylinder) else body


@lru_cache(maxsize=16)
def _body_pressure(body, w: float) -> tuple:
    """A line body's pressure at ``xc = 0`` and its lowest over the cycle ``[-w, w]`` (:func:`core.pressure.melan.lowest_pressure`)."""
    from core.pressure.melan import lowest_pressure
    x, p, p_min = lowest_pressure(body, min(max(w, 0.0), 0.999))
    return x, p, p_min


class Inputs(NamedTuple):
    """Everything the figures depend on."""

    ft: float
    w: float
    units: Units
    result: core.CycleResult | None = None
    frame: int | None = None
    table: object = None  # sweep table (pandas DataFrame) shown on the map
    pinned: tuple = ()  # pinned runs (app.compare.Pin) overlaid on the displacement, increment and traction
    coupled: object = None  # the coupled limit curve (core.CoupledLimitCurve, maybe partial) drawn on the map


# --------------------------------------------------------------------------
# pressure
# --------------------------------------------------------------------------
def _pressure_specs(units: Units) -> list:
    kd, vd = _dim("x", units.x_label), _dim("p", units.p_label)
    return [
        # short labels: the legend is inside a first-screen figure (the caption says what they are)
        _line("xc = 0", "#7f7f7f", kd, vd, dash="dashed", width=2),
        _line("xc = +W", _C["blue"], kd, vd),
        _line("xc = −W", _C["orange"], kd, vd),
        _line("μ p_min (cycle)", "black", kd, vd, width=LINE + 1),
        _line("this step", _C["vermillion"], kd, vd, dash="dotdash"),
    ]


@_memo
def pressure_curves(w: float, units: Units, body=None) -> tuple:
    """Hertz pressure at the centre and at the reversal points ``±W``, and μ times the lowest pressure.

    Parameters
    ----------
    w : float
        ``W / a``.
    units : Units
        Display units.
    body : core.geometry.bodies.Body, optional
        A line body other than the cylinder: its own pressure (:func:`core.pressure.melan.lowest_pressure`).
    """
    x = _x_grid(w)
    X, P = x * units.x, units.p
    if body is not None:
        xs, p, low = _body_pressure(body, w)
        return ((X, P * np.interp(x, xs, p)), (X, P * np.interp(x - w, xs, p)), (X, P * np.interp(x + w, xs, p)),
                (X, P * units.mu * np.interp(x, xs, low)))
    return ((X, P * core.hertz_pressure(x, 0.0)), (X, P * core.hertz_pressure(x, w)),
            (X, P * core.hertz_pressure(x, -w)), (X, P * units.mu * core.lowest_pressure(x, w)))


@_memo
def pressure_step(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> tuple:
    """The pressure at the player's step (empty without a run): the body's closed form at the step's centre where
    :func:`closed_forms_apply`, the run's own element pressures otherwise."""
    if result is None:
        return _EMPTY
    k = _step(result, frame)
    if not closed_forms_apply(result):  # coupled, or an oscillating normal force: the run's own pressure
        return _run_stairs(result, result.pressure[k], units.x, units.p)
    xc = float(result.xc[k])
    body = line_body(result)
    if body is not None:
        xs, p, _ = _body_pressure(body, float(result.params.get("w", 0.0)))
        x = np.linspace(xc - 1.05, xc + 1.05, 211)
        return (x * units.x, units.p * np.interp(x - xc, xs, p))
    x = np.linspace(xc - 1.0, xc + 1.0, 201)
    return (x * units.x, units.p * core.hertz_pressure(x, xc))


def _tangential(result) -> bool:
    """Whether ``result`` is a run of the tangential loading (a fixed centre: no reversal points, no eq 34/35)."""
    return result is not None and result.params.get("history") == "tangential"


def closed_forms_apply(result, rocking: bool = False) -> bool:
    """Whether the closed forms drawn as references describe ``result``: no run yet (they follow the sliders), or
    a run of an uncoupled contact under a constant normal force (the body's pressure, its lowest over the cycle);
    with ``rocking``, also rocked (the paper's closure and u_sd of eq 34 are the rocking's). Under the
    oscillating normal force the lowest pressure is lower, and with coupling (beta != 0) the pressure is not
    Hertz's: the figures then draw the run's own pressures."""
    if result is None:
        return True
    history = result.params.get("history", "rocking")
    constant = history in ("rocking", "tangential") or (
        history == "normal" and float(result.params.get("amplitude", 0.0)) == 0.0)
    uncoupled = float(getattr(result, "beta", 0.0) or 0.0) == 0.0
    return constant and uncoupled and not (rocking and history == "tangential")


def _run_stairs(result, values, scale_x: float, scale_v: float) -> tuple:
    """Element values of a line run drawn as stairs over its elements."""
    return (np.repeat(result.edges * scale_x, 2)[1:-1], np.repeat(scale_v * np.asarray(values), 2))


def _run_lowest(result, scale_x: float, scale_v: float) -> tuple:
    """The run's own lowest pressure of its last period (:attr:`core.CycleResult.lowest_pressure`), as stairs."""
    if result is None or result.lowest_pressure is None or np.ndim(result.lowest_pressure) != 1:
        return _EMPTY
    return _run_stairs(result, result.lowest_pressure, scale_x, scale_v)


def _pressure_layers(i: Inputs) -> tuple:
    if _tangential(i.result):  # a fixed centre: no reversal points ±W
        centre, _, _, low = pressure_curves(0.0, i.units, line_body(i.result))
        side = (_EMPTY, _EMPTY)
    else:
        centre, *side, low = pressure_curves(i.w, i.units, line_body(i.result))
    if not closed_forms_apply(i.result):  # the run's own lowest pressure: the closed form's is not its
        low = _run_lowest(i.result, i.units.x, i.units.p * i.units.mu)
    return (centre, *side, low, pressure_step(i.units, i.result, i.frame))


# --------------------------------------------------------------------------
# traction
# --------------------------------------------------------------------------
def _zone_rectangles(x_edges, codes, ylim, scale) -> tuple:
    """Rows (x0, y0, x1, y1) per zone kind: contiguous runs of equal zone code."""
    out = []
    for code in _ZONE_CODES.values():
        mask = codes == code
        rects = []
        if mask.any():
            d = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
            starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
            rects = [(x_edges[s] * scale, -ylim, x_edges[e] * scale, ylim) for s, e in zip(starts, ends)]
        out.append(rects)
    return tuple(out)


def traction_zones(result: core.CycleResult, frame: int) -> np.ndarray:
    """Zone code per element at ``frame`` (:class:`core.Zone`: stick, slip, zero traction (lost contact), none);
    a patch: on its cut ``y = 0``.

    At the last step these are :attr:`core.CycleResult.final_zones`: the final traction against μ p_min, the
    zones the cards' ``c_sd`` is measured on (stick below μ p_min, slip at or above it, zero traction where
    contact is lost once a period and no traction is left); at other steps, what each element does in that
    step (stick, slip at μ p, out of contact), the states the curve of that step shows.
    """
    if frame >= result.xc.size - 1:
        return result.final_zones
    State, Zone = core.State, core.Zone
    s = result.state[frame]
    ever = (result.state != State.RELEASED).any(axis=0)
    slipping = (s == State.SLIP_FORWARD) | (s == State.SLIP_BACKWARD)
    return np.where(s == State.STICK, Zone.STICK, np.where(slipping, Zone.SLIP,
                                                           np.where(ever, Zone.RELEASED, Zone.NONE))).astype(np.int8)


def _hatch(pattern: str, color: str):
    """A render hook that hatches a layer's glyph (HoloViews has no hatch options for rectangles)."""
    def hook(plot, element):
        plot.handles["glyph"].update(hatch_pattern=pattern, hatch_color=color, hatch_alpha=0.45)
    return hook


def _traction_specs(units: Units) -> list:
    kd, vd = _dim("x", units.x_label), _dim("q", units.q_label)
    zones = [Layer(hv.Rectangles, (kd, vd, "x1", "y1"), (), name,
                   dict(color=ZONE_COLORS[name], alpha=0.18, line_alpha=0, hooks=[_hatch(ZONE_HATCH[name], ZONE_COLORS[name])]))
             for name in _ZONE_CODES]
    return [
        *zones,
        _line("±μ p (step)", "#555555", kd, vd, dash="dashed", width=2),
        _line("", "#555555", kd, vd, dash="dashed", width=2),
        _line("±μ p_min", "black", kd, vd, dash="dotted", width=2),
        _line("", "black", kd, vd, dash="dotted", width=2),
        _line("closure (paper)", _C["blue"], kd, vd, dash="dashed", width=LINE + 1),
        _line("numerical", _C["vermillion"], kd, vd),
        *pinned.specs("traction", kd, vd),
    ]


@_memo
def traction_bounds(w: float, units: Units, body=None) -> tuple:
    """The bounds ±μ p_min of the shaken-down traction (they follow the w slider; a line body other than the
    cylinder: its own p_min)."""
    x = _x_grid(w)
    if body is not None:
        xs, _, p_min = _body_pressure(body, w)
        low = units.q * np.interp(x, xs, p_min)
    else:
        low = units.q * core.lowest_pressure(x, w)
    return ((x * units.x, low), (x * units.x, -low))


@_memo
def traction_closure(ft: float, w: float, units: Units, body=None) -> tuple:
    """The paper's closure for the shaken-down traction (eqs 22–30); it follows the ft and w sliders.

    Parameters
    ----------
    ft, w : float
        Current inputs.
    units : Units
        Display units.
    """
    if body is not None:  # the paper's closure is the cylinder's
        return _EMPTY
    x = _x_grid(w)
    return (x * units.x, units.q * core.shakedown_traction(x, ft, w))


@_memo
def traction_run(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> tuple:
    """Zones (stick, slip, zero traction), the bounds ±μ p and the numerical traction at the player's step.

    Parameters
    ----------
    units : Units
        Display units.
    result : CycleResult, optional
        The solver run (empty layers without one).
    frame : int, optional
        Step of ``result`` to show (default: the last).

    Returns
    -------
    tuple
        Three zone layers, the upper and lower bound, and the numerical traction,
        drawn as stairs over the elements.
    """
    Q, X = units.q, units.x
    if result is None:
        return (*_zone_rectangles(np.zeros(1), np.zeros(0), 1.15 * Q, X), _EMPTY, _EMPTY, _EMPTY)
    k = _step(result, frame)
    zones = _zone_rectangles(result.edges, traction_zones(result, k), 1.15 * Q, X)
    xe, bound = result.x * X, Q * result.pressure[k]
    return (*zones, (xe, bound), (xe, -bound), _run_stairs(result, result.traction[k], X, Q))


def _traction_layers(i: Inputs) -> tuple:
    *zones_and_bounds, numerical = traction_run(i.units, i.result, i.frame)
    body = line_body(i.result)
    if closed_forms_apply(i.result):  # (a fixed centre under the tangential loading: its pressure's bound)
        bounds = traction_bounds(0.0 if _tangential(i.result) else i.w, i.units, body)
        closure = traction_closure(i.ft, i.w, i.units, body) if closed_forms_apply(i.result, rocking=True) else _EMPTY
    else:  # the paper's closure is the constant-load rocking's; the bounds are the run's own lowest pressure
        low = _run_lowest(i.result, i.units.x, i.units.q)
        bounds, closure = (low, (low[0], -low[1])), _EMPTY
    return (*zones_and_bounds, *bounds, closure, numerical, *pinned.layers("traction", i.pinned, i.units))


# --------------------------------------------------------------------------
# the space-time map of element states
# --------------------------------------------------------------------------
_MAX_ROWS = 1500


def _state_colorbar(plot, element) -> None:
    """Name the four states on the colour bar. A hook, so that its ticker is a new Bokeh model in every render:
    a ticker in the (shared, cached) options would be one model for all sessions, emptied when the first expires."""
    from bokeh.models import FixedTicker

    bar = plot.handles.get("colorbar")
    if bar is not None:
        bar.ticker = FixedTicker(ticks=[0, 1, 2, 3])
        bar.major_label_overrides = {i: name for i, name in enumerate(core.STATE_NAMES)}


def _states_specs(units: Units) -> list:
    kx, kt = _dim("x", units.x_label), _dim("t", "time [periods]")
    image = Layer(hv.Image, (kx, kt), (hv.Dimension("state", label="element state", range=(-0.5, 3.5)),), "",
                  dict(cmap=list(STATE_COLORS), clim=(-0.5, 3.5), colorbar=True, hooks=[_state_colorbar],
                       colorbar_opts={"title": "element state"}))

    def vlines(label, color, dash):
        return Layer(hv.VLines, (kx,), (), label, dict(color=color, line_dash=dash, line_width=LINE))
    return [
        image,
        Layer(hv.Curve, (kx,), (kt,), "contact edges xc ± a", dict(color="black", line_width=2)),
        Layer(hv.Curve, (kx,), (kt,), "", dict(color="black", line_width=2)),
        vlines("±b = ±(a − W)", _C["green"], "dashed"),
        vlines("±c_sd numerical", _C["purple"], "solid"),
        vlines("±c_sd closure", "#4b0082", "dotted"),
        Layer(hv.HLines, (kt,), (), "player step", dict(color=_C["yellow"], line_width=LINE + 1)),
    ]


@_memo
def state_image(result: core.CycleResult | None, units: Units) -> tuple:
    """Element states over the run (released / stick / slip forward / slip backward), x against time:
    ``(array, bounds)`` of an image."""
    if result is None:
        return np.zeros((2, 2)), (-1, 0, 1, 1)
    t = time_axis(result)
    stride = max(1, int(np.ceil(t.size / _MAX_ROWS)))
    rows = result.state[::stride].astype(np.uint8)
    dt = (t[1] - t[0]) if t.size > 1 else 1.0
    y0, y1 = t[0] - dt, t[0] - dt + rows.shape[0] * stride * dt
    e = result.edges * units.x
    return np.flipud(rows), (e[0], y0, e[-1], y1)


@_memo
def state_marks(result: core.CycleResult | None, units: Units) -> tuple:
    """Marks of the state map: contact edges xc ± a, ±b = ±(a − W), ±c_sd (numerical and closure)."""
    if result is None:
        return _EMPTY, _EMPTY, [], [], []
    X = units.x
    t = time_axis(result)
    body = line_body(result)
    ft, w = float(result.params.get("ft", 0.0)), float(result.params.get("w", 0.0))
    if body is None:
        a_now = np.sqrt(result.P)
        c_closure = float(core.shakedown_stick_halfwidth(abs(ft), w)) * X
    else:  # another line body: its own half-width, no closure
        a_now = np.full(np.shape(result.P), float(body.half_width(1.0))) * np.sqrt(result.P)
        c_closure = math.nan

    def pair(v):
        return [] if not np.isfinite(v) else [-v, v]
    return (((result.xc - a_now) * X, t), ((result.xc + a_now) * X, t),
            pair((1.0 - w) * X), pair(result.stick_halfwidth * X), pair(c_closure))


@_memo
def frame_marks(result: core.CycleResult | None, frame: int | None) -> list:
    """The time of the player's step on the state map (a horizontal line)."""
    if result is None or frame is None:
        return []
    return [float(time_axis(result)[_step(result, frame)])]


def _states_layers(i: Inputs) -> tuple:
    return (state_image(i.result, i.units), *state_marks(i.result, i.units), frame_marks(i.result, i.frame))


# --------------------------------------------------------------------------
# displacement
# --------------------------------------------------------------------------
def _displacement_specs(units: Units) -> list:
    kd, vd = _dim("t", "time [periods]"), _dim("u", units.u_label)
    return [
        Layer(hv.Curve, (kd,), (vd,), "numerical", dict(color=_C["vermillion"], line_width=LINE)),
        Layer(hv.HLines, (vd,), (), "u_sd (eq 34)",
              dict(color=_C["blue"], line_dash="dashed", line_width=2)),
        *pinned.specs("displacement", kd, vd),
        Layer(hv.Scatter, (kd,), (vd,), "player step", dict(color=_C["yellow"], size=12, line_color="black")),
    ]


@_memo
def displacement_curves(result: core.CycleResult | None, units: Units) -> tuple:
    """Rigid-body displacement over time (the paper's Figs 6 and 7), with the paper's u_sd (eq 34)."""
    if result is None:
        return _EMPTY, []
    usd = []
    ft, w = float(result.params.get("ft", 0.0)), float(result.params.get("w", 0.0))
    if (line_body(result) is None and result.u0 and 0 <= ft < 1 and ft <= float(core.ft_limit(w))
            and closed_forms_apply(result, rocking=True)):  # eq 34 is the rocking cylinder's, under constant loads, uncoupled
        usd = [float(approx.shakedown_displacement_approx(ft, w)) * result.u0 * units.u]
    return (time_axis(result), result.displacement * units.u), usd


@_memo
def displacement_step(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> tuple:
    """The player's step on the displacement curve."""
    if result is None or frame is None:
        return _EMPTY
    k = _step(result, frame)
    return [time_axis(result)[k]], [result.displacement[k] * units.u]


def _displacement_layers(i: Inputs) -> tuple:
    return (*displacement_curves(i.result, i.units), *pinned.layers("displacement", i.pinned, i.units),
            displacement_step(i.units, i.result, i.frame))


# --------------------------------------------------------------------------
# fretting loop
# --------------------------------------------------------------------------
def _loop_x_label(units: Units) -> str:
    """The loop's horizontal axis, short enough for a first-screen figure: the displacement along Ft less ``k Q``
    (the shear of :func:`loop_curves`), in the displacement's unit of ``units``."""
    if units.system == "physical":
        return "U − k·Ft [µm]"
    unit = units.u_label.split("[")[-1].rstrip("]") if "[" in units.u_label else "U0"
    return f"u − k·Q [{unit}]"


def _loop_specs(units: Units) -> list:
    kd, vd = _dim("u", _loop_x_label(units)), _dim("Q", "Ft / (μ Fn)")
    return [
        Layer(hv.Curve, (kd,), (vd,), "first period", dict(color=_C["sky"], line_dash="dashed", line_width=2)),
        Layer(hv.Curve, (kd,), (vd,), "last period", dict(color=_C["vermillion"], line_width=LINE)),
    ]


@_memo
def loop_curves(result: core.CycleResult | None, units: Units) -> tuple:
    """The fretting loops of the first and the last period (:meth:`core.CycleResult.fretting_loop`): the
    tangential load against the rigid-body displacement along it (a point contact's projected on Ft), from the
    stored steps, for a run of any body."""
    if result is None or result.periods == 0:
        return _EMPTY, _EMPTY
    # the hysteresis is thin beside the elastic compliance (a strip kernel's especially): both loops are sheared by
    # the secant k of the last one (through its extreme loads), which keeps their areas (the integral of Q dQ over a
    # closed loop is 0) and opens them; under a constant load k = 0
    last = result.fretting_loop(-1)
    span = float(np.ptp(last.Q))
    k = 0.0
    if span > 1e-12:
        hi, lo = int(np.argmax(last.Q)), int(np.argmin(last.Q))
        k = float((last.displacement[hi] - last.displacement[lo]) / (last.Q[hi] - last.Q[lo]))
    along = along_ft(result)
    out = []
    for period in (0, -1):
        loop = result.fretting_loop(period)
        start = float(along[result.period == loop.period][0]) if loop.Q.size else 0.0
        out.append(((loop.displacement + start - k * loop.Q) * units.u, loop.Q))
    return tuple(out)


def _loop_layers(i: Inputs) -> tuple:
    return loop_curves(i.result, i.units)


# --------------------------------------------------------------------------
# increment per period
# --------------------------------------------------------------------------
def _increments_specs(units: Units) -> list:
    kd = _dim("period", "period")
    vd = _dim("du", f"|ΔU| per period [{units.u_label.split('[')[-1].rstrip(']')}]"
              if "[" in units.u_label else "|Δu| per period [U0]")
    return [
        Layer(hv.Curve, (kd,), (vd,), "numerical", dict(color=_C["vermillion"], line_width=2)),
        Layer(hv.Scatter, (kd,), (vd,), "", dict(color=_C["vermillion"], size=9)),
        Layer(hv.HLines, (vd,), (), "eq 38 (regression)",
              dict(color=_C["blue"], line_dash="dashed", line_width=2)),
        *pinned.specs("increments", kd, vd),
    ]


@_memo
def increment_layers(result: core.CycleResult | None, units: Units) -> tuple:
    """|Increment per period| (curve and markers, for a log scale), and the paper's ratcheting regression (eq 38)."""
    if result is None:
        return _EMPTY, _EMPTY, []
    inc = np.abs(result.increment_per_period) * abs(units.u)
    top = float(inc.max()) if inc.size and inc.max() > 0 else 1.0
    pts = (np.arange(1, inc.size + 1), np.maximum(inc, top * 1e-12))
    eq38 = []
    ft, w = float(result.params.get("ft", 0.0)), float(result.params.get("w", 0.0))
    if result.u0 and 0 <= ft < 1:
        d = float(approx.ratchet_increment_approx(ft, w)) * result.u0 * abs(units.u)
        if d > 0:
            eq38 = [d]
    return pts, pts, eq38


def _increments_layers(i: Inputs) -> tuple:
    return (*increment_layers(i.result, i.units), *pinned.layers("increments", i.pinned, i.units))


# --------------------------------------------------------------------------
# the shakedown map
# --------------------------------------------------------------------------
_CSD_LEVELS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
#: Axis labels that read for both planes: (ft, w) of the rocking loadings, (mean ft, A) of the tangential one
_MAP_X, _MAP_Y = "ft = Ft / (μ Fn) (tangential: its mean)", "w = W / a (tangential: amplitude A)"
_MAP_DIMS = (hv.Dimension("ft", label=_MAP_X), hv.Dimension("w", label=_MAP_Y))


@lru_cache(maxsize=1)
def map_base() -> hv.Overlay:
    """The (ft, w) plane of the rocking under constant loads: exact limits (the cylinder's eq 35, the sphere's and
    ellipsoid's ``(1 - w)^2 (2 + w)/2``, the paper's Fig 14), the paper's regression (eq 36) and c_sd/a contours of
    the closure (the map draws them under the rocking loading: :func:`map_lines`)."""
    kd = [hv.Dimension("ft", label=_MAP_X, range=(0, 1)), hv.Dimension("w", label=_MAP_Y, range=(0, 1))]
    ft = np.linspace(0.0, 1.0, 401)
    n = 161
    g = (np.arange(n) + 0.5) / n
    FT, W = np.meshgrid(g, g)
    csd = core.shakedown_stick_halfwidth(FT * 0.999, W * 0.999)
    img = hv.Image((g, g, csd), kdims=kd, vdims=[hv.Dimension("c_sd", label="c_sd / a (closure)")])
    contours = hv.operation.contours(img, levels=_CSD_LEVELS, filled=False).opts(
        cmap="viridis", line_width=2, colorbar=True, show_legend=False,
        colorbar_opts={"title": "c_sd / a (closure)"})
    return hv.Overlay([
        contours,
        hv.Curve((ft, core.w_limit(ft)), kdims=kd[:1], vdims=kd[1:], label="eq 35 (exact)").opts(
            color="black", line_width=LINE + 1),
        hv.Curve((ft, core.w_limit(ft, body="sphere")), kdims=kd[:1], vdims=kd[1:],
                 label="sphere, ellipsoid (exact)").opts(color=_C["purple"], line_dash="dotdash", line_width=LINE),
        hv.Curve((ft, approx.w_limit_regression(ft)), kdims=kd[:1], vdims=kd[1:],
                 label="eq 36 regression").opts(color=_C["orange"], line_dash="dashed",
                                                                       line_width=LINE),
    ])


def grid_boundary(table) -> tuple[np.ndarray, np.ndarray]:
    """The numerical boundary of a sweep table: per ``ft``, midway between the largest ``w`` that shook
    down and the next ``w`` of the grid (the grid's resolution of the numerical limit)."""
    fts, ws = [], []
    if table is None or len(table) == 0:
        return np.array(fts), np.array(ws)
    for ft, group in table.sort_values(["ft", "w"]).groupby("ft", sort=True):
        w = group["w"].to_numpy(float)
        ok = group["regime"].isin(("shakedown", "cyclic slip")).to_numpy()  # not ratcheting, as the limit search
        if ok.all() or not ok.any():
            continue
        k = int(np.argmin(ok))  # first grid w that did not shake down
        fts.append(float(ft))
        ws.append(0.5 * (w[k - 1] + w[k]) if k > 0 else 0.5 * w[0])
    return np.array(fts), np.array(ws)


_MAP_REGIMES = ("shakedown", "cyclic slip", "ratcheting", "undetermined")
#: The fretting map's gross-sliding boundary |ft| + A = 1 (|Q| reaches μ P) in the (mean ft, amplitude) plane.
GROSS_SLIDING = (np.array([0.0, 1.0]), np.array([1.0, 0.0]))


def is_tangential(table) -> bool:
    """Whether a sweep table is of the tangential loading: its plane is (mean ft, amplitude), not (ft, w)."""
    return table is not None and "history" in table.columns and bool((table["history"] == "tangential").any())


#: The region names of each history's map: (x, y, name) in its plane (the normal loading's x scaled by 1 - A).
_REGION_NAMES = {"rocking": ((0.2, 0.25, "shakedown"), (0.8, 0.5, "ratcheting")),
                 "normal": ((0.2, 0.25, "shakedown"), (0.8, 0.5, "ratcheting")),
                 "tangential": ((0.15, 0.12, "cyclic slip"), (0.72, 0.62, "gross sliding"))}
_REGION_DIMS = (*_MAP_DIMS, hv.Dimension("name"))


def _map_specs(label: str = "solver") -> list:
    kd = _MAP_DIMS
    base = {e.label: e for e in map_base() if isinstance(e, hv.Curve)}

    def curve(name, **style):
        return Layer(hv.Curve, kd[:1], kd[1:], name, style)

    return [
        *[Layer(hv.Points, kd, (), f"{regime}, {label}",
                dict(color=REGIME_COLORS[regime], marker=REGIME_MARKERS[regime], size=8, alpha=0.7, line_alpha=0))
          for regime in _MAP_REGIMES],
        # the grid resolves the limit to half a grid step: markers, not a line that would look like a staircase
        Layer(hv.Points, kd, (), "numerical limit ±½ step",
              dict(color="black", fill_color="white", marker="diamond", size=11, line_width=2)),
        # each history's lines (:func:`map_lines`): the rocking's limits, the normal loading's Melan limit at its
        # amplitude and phase, the gross-sliding boundary of the oscillating loads
        curve("gross sliding: |Q| reaches μ Fn", color="black", line_width=LINE + 1, line_dash="dashed"),
        Layer(hv.Contours, kd, (hv.Dimension("c_sd", label="c_sd / a (closure)"),), "",
              dict(cmap="viridis", line_width=2, color="c_sd", clim=(0.0, 1.0), show_legend=False)),
        *[curve(name, **dict(base[name].opts.get().kwargs)) for name in _ROCKING_LINES],
        curve("Melan's limit, oscillating Fn (this body)", color=_C["green"], line_width=LINE + 1,
              line_dash="dotdash"),
        Layer(hv.Labels, kd, _REGION_DIMS[2:], "", dict(text_font_size="11px", text_color="#444444")),
        Layer(hv.Labels, kd, _REGION_DIMS[2:], "", dict(text_font_size="16px", text_color="black")),
        curve("this body's exact limit (Melan)", color=_C["green"], line_width=LINE + 1, line_dash="solid"),
        # a coupled contact (Dundurs β ≠ 0): eq 35 is only the uncoupled reference; the coupled limit is the
        # solver's, found by bisection at a few w (:func:`map_coupled`): each w's bracket, and a line through them
        curve(EQ35_REFERENCE, color="black", line_width=LINE, line_dash="dashed"),
        curve(COUPLED_LIMIT, color=_C["vermillion"], line_width=LINE + 1, line_dash="solid"),
        Layer(hv.Curve, kd[:1], kd[1:], "", dict(color=_C["vermillion"], line_width=LINE + 6, alpha=0.6)),
        Layer(hv.Points, kd, (), "current point", dict(size=18, marker="circle", line_color="black", line_width=2)),
    ]


#: Legend labels of a coupled contact's limits on the map: eq 35 as the reference, the solver's coupled limit.
EQ35_REFERENCE = "eq 35 (uncoupled reference)"
COUPLED_LIMIT = "coupled limit (numerical, β ≠ 0)"


@_memo
def map_coupled(curve) -> tuple:
    """The map's layers of a coupled contact's limit curve (a :class:`core.CoupledLimitCurve`, maybe still partial:
    the amplitudes found so far): eq 35 as the uncoupled reference, a line through the brackets' midpoints, and the
    brackets themselves (one segment per w, NaN between them); empty layers for an uncoupled contact (None)."""
    if curve is None:
        return _EMPTY, _EMPTY, _EMPTY
    reference = tuple(e.dimension_values(i) for e in map_base() if isinstance(e, hv.Curve)
                      and e.label == "eq 35 (exact)" for i in (0, 1))
    ok = [p for p in curve.points if p.converged]
    line = (np.array([p.ft_limit for p in ok]), np.array([p.w for p in ok]))
    nan = [math.nan] * len(ok)
    brackets = (np.ravel(np.column_stack([[p.ft_shakedown for p in ok], [p.ft_ratcheting for p in ok], nan])),
                np.ravel(np.column_stack([[p.w for p in ok], [p.w for p in ok], nan])))
    return reference, line, brackets


#: The rocking plane's lines (of :func:`map_base`), drawn under the rocking loading only.
_ROCKING_LINES = ("eq 35 (exact)", "sphere, ellipsoid (exact)", "eq 36 regression")


def map_history(result) -> tuple:
    """The loading history of a run as its map reads it: ``(name, amplitude, phase, shape)`` (rocking without a
    run)."""
    if result is None:
        return ("rocking", 0.0, 0.0, "triangle")
    p = result.params
    history = str(p.get("history", "rocking"))
    if history == "normal" and float(p.get("amplitude", 0.0)) == 0.0:
        history = "rocking"  # no oscillation: the rocking's plane and limits
    return (history, float(p.get("amplitude", 0.0)), float(p.get("phase", 0.0)), str(p.get("shape", "triangle")))


@lru_cache(maxsize=8)
def _normal_limit(body, amplitude: float, phase: float, shape: str) -> tuple:
    """Melan's limit ``(ft_lim(w), w)`` of ``body`` rocked under the oscillating normal force
    (:func:`core.pressure.melan.ft_limit_oscillating`), or empty for a body it has no pressure of (a point contact: its
    integral over the plane takes seconds a point; the run's own limit is in its cards)."""
    from core.pressure.melan import ft_limit_oscillating

    if not isinstance(body, core.Body):
        return _EMPTY
    w = np.linspace(0.0, 0.98, 50)
    return ft_limit_oscillating(w, body, amplitude, phase, shape=shape, dx=1 / 500, samples=200), w


@_memo
def map_lines(history: tuple, body=None) -> tuple:
    """The data of the map's lines for a history (:func:`map_history`), in the order of their layers: the
    gross-sliding boundary, the c_sd contours, the rocking limits (eq 35, the sphere's, eq 36), Melan's limit
    under the oscillating normal force, the contours' values and the region names.

    * rocking: the (ft, w) plane of the constant loads: eq 35, the sphere's and ellipsoid's exact limit, the
      regression and the closure's c_sd contours;
    * normal (amplitude ``A > 0``): the (ft, w) plane at the run's amplitude and phase: Melan's limit of
      ``body`` (a line body; None: not drawn) under the oscillating force and gross sliding at the lowest
      force, ``ft = 1 - A``;
    * tangential: the (mean ft, amplitude A) plane: the gross-sliding boundary ``|ft| + A = 1``, below which
      every run slips cyclically; no limit of the rocking applies.
    """
    name, A, phase, shape = history
    base = {e.label: e for e in map_base() if isinstance(e, hv.Curve)}
    contours = next(e for e in map_base() if isinstance(e, hv.Contours))
    rocking = name == "rocking"
    if name == "tangential":
        gross = GROSS_SLIDING
    elif name == "normal":
        gross = (np.array([1.0 - A, 1.0 - A]), np.array([0.0, 1.0]))
    else:
        gross = _EMPTY
    curves = [tuple(base[n].dimension_values(i) for i in (0, 1)) if rocking else _EMPTY for n in _ROCKING_LINES]
    melan = _normal_limit(body, A, phase, shape) if name == "normal" and body is not None else _EMPTY
    scale = 1.0 - A if name == "normal" else 1.0
    names = tuple(np.array(c) for c in zip(*[(x * scale, y, t) for x, y, t in _REGION_NAMES[name]]))
    return (gross, contours.data if rocking else [], *curves, melan, _csd_levels() if rocking else (_EMPTY + ([],)),
            names)


@lru_cache(maxsize=1)
def _csd_levels() -> tuple:
    """The c_sd / a value of each contour of :func:`map_base`, written at its point nearest w = 0.15 (where the
    contours are furthest apart)."""
    contours = next(e for e in map_base() if isinstance(e, hv.Contours))
    xs, ys, texts = [], [], []
    for path in contours.split():
        ft, w = path.dimension_values(0), path.dimension_values(1)
        k = int(np.argmin(np.abs(w - 0.15)))
        xs.append(float(ft[k]))
        ys.append(float(w[k]))
        texts.append(f"{float(path.dimension_values(2)[0]):.1f}")
    return np.array(xs), np.array(ys), np.array(texts)


_NUMERICAL_MEMO: list = [None, None]  # (table, its layers): the map's numerical layers for the last table


def map_numerical(table) -> tuple:
    """Sweep results in the (ft, w) plane: each regime's runs and the grid's boundary between shakedown and
    ratcheting (:func:`grid_boundary`); a tangential loading's table in the (mean ft, amplitude) plane, without a
    boundary (its gross-sliding line is the history's: :func:`map_lines`)."""
    table_seen, layers = _NUMERICAL_MEMO
    if table_seen is table and layers is not None:
        return layers
    n = 1 if table is None else max(1.0, np.sqrt(len(table)))
    size = float(np.clip(260.0 / n, 6.0, 24.0))  # a small map's markers fill their grid cells
    tangential = is_tangential(table)
    y = "amplitude" if tangential else "w"
    runs = [Styled(_EMPTY if table is None else tuple(table.loc[table["regime"] == regime, c].to_numpy(float)
                                                     for c in ("ft", y)), {"size": size})
            for regime in _MAP_REGIMES]
    layers = (*runs, _EMPTY if tangential else grid_boundary(table))
    _NUMERICAL_MEMO[:] = [table, layers]
    return layers


@_memo
def map_point(ft: float, w: float, regime: str | None = None) -> Styled:
    """The current (ft, w), coloured and shaped by the numerical regime when known."""
    return Styled(([ft], [w]), {"fill_color": REGIME_COLORS.get(regime, REGIME_COLORS[None]),
                                "marker": REGIME_MARKERS.get(regime, REGIME_MARKERS[None])})


def _body_of(run) -> str:
    """The body of a run or a sweep table (a table without a 'body' column is the cylinder's)."""
    if isinstance(run, (core.PointContactResult, core.CycleResult)):
        spec = run.body if isinstance(run, core.PointContactResult) else (getattr(run, "body_spec", None) or run.body)
        if isinstance(spec, str) or isinstance(spec, (core.Cylinder, core.Ellipsoid)):
            return spec if isinstance(spec, str) else str(spec.name)
        return repr(spec)  # a body with parameters, as core.sweep names it: Punch(flat=0.8)
    columns = getattr(run, "columns", ())
    return str(run["body"].iloc[0]) if "body" in columns and len(run) else "cylinder"


def _map_layers(i: Inputs) -> tuple:
    regime = None if i.result is None else i.result.regime
    # a sweep of another body than the run's is not drawn (the cylinder's shipped map beside a sphere's run)
    table = i.table if i.result is None or _body_of(i.result) == _body_of(i.table) else None
    tangential = i.result is not None and i.result.params.get("history") == "tangential"
    if tangential != is_tangential(table):  # a (ft, w) map beside a tangential run, or the other way round
        table = None
    if i.result is not None and not _same_loading(table, map_history(i.result)):
        table = None  # a sweep under another loading (the shipped constant-load map beside a 'normal' run)
    if not _same_coupling(table, 0.0 if i.coupled is None else i.coupled.beta):
        table = None  # an uncoupled sweep (the shipped map) beside a coupled contact, or the other way round
    # the current point: (mean ft, amplitude) under the tangential loading
    y = float(i.result.params.get("amplitude", 0.0)) if tangential else i.w
    history = map_history(i.result)
    body = None if i.result is None else getattr(i.result, "body_spec", None) or getattr(i.result, "body", None)
    lines = map_lines(history, body if isinstance(body, core.Body) else None)
    coupled = i.coupled if history[0] == "rocking" else None
    if coupled is not None:
        lines = _coupled_lines(lines)
    return (*map_numerical(table), *lines, body_limit(i.result) if history[0] == "rocking" else _EMPTY,
            *map_coupled(coupled), map_point(i.ft, y, regime))


def _coupled_lines(lines: tuple) -> tuple:
    """The rocking lines (:func:`map_lines`) of a coupled contact: none of the uncoupled closed forms. eq 35 is drawn
    as the one uncoupled reference by :func:`map_coupled`; the closure's c_sd contours (and their labels), the
    sphere's limit and the eq 36 regression are not drawn: the closure's stick zone is the uncoupled one (the
    traction figure draws no closure for a coupled run either), the point contacts take no β ≠ 0, and eq 36 fits
    eq 35."""
    gross, _, *curves, melan, _, names = lines
    return (gross, [], *[_EMPTY] * len(curves), melan, _EMPTY + ([],), names)


def _same_coupling(table, beta: float) -> bool:
    """Whether a sweep table was run with Dundurs' ``beta`` (to 1e-4, the coupled curve's rounding; a table without
    a 'beta' column is uncoupled, as the shipped map)."""
    if table is None or len(table) == 0:
        return True
    own = float(table["beta"].iloc[0]) if "beta" in getattr(table, "columns", ()) else 0.0
    return math.isclose(0.0 if math.isnan(own) else own, beta, abs_tol=1e-4)


def _same_loading(table, history: tuple) -> bool:
    """Whether a sweep table was run under the loading ``history`` (:func:`map_history`; a table without a
    'history' column is the rocking's, the shipped map's), the normal force's amplitude and phase included."""
    if table is None or len(table) == 0:
        return True
    name, A, phase, _ = history
    columns = getattr(table, "columns", ())
    own = str(table["history"].iloc[0]) if "history" in columns else "rocking"
    if own == "normal" and "amplitude" in columns and float(table["amplitude"].iloc[0]) == 0.0:
        own = "rocking"
    if own != name:
        return False
    if name != "normal":
        return True
    return (math.isclose(float(table["amplitude"].iloc[0]), A, abs_tol=1e-9)
            and math.isclose(float(table["phase"].iloc[0]), phase, abs_tol=1e-9))


def body_limit(result) -> tuple:
    """The exact limit of the run's body when it is neither the cylinder nor an ellipsoid (their closed forms are
    drawn already), as ``(ft_lim(w), w)`` (:func:`app.bodies.limit_curve`)."""
    from . import bodies

    body = None if result is None else getattr(result, "body_spec", None) or getattr(result, "body", None)
    if body is None or isinstance(body, (str, core.Cylinder)) or bodies.is_ellipsoid(body):
        return _EMPTY
    return bodies.limit_curve(body)


# --------------------------------------------------------------------------
# the figures
# --------------------------------------------------------------------------
#: Each figure: its title and options, a one-line "what you see" caption, its layers' looks (a function of the units), its layers' data (a function
#: of :class:`Inputs`), and the inputs these depend on.
FIGURES = {
    "sketch": dict(opts=dict(title="The body at the player's step", yaxis=None, show_grid=False,
                             legend_position="right", legend_cols=1),
                   caption="What you see: the rocking body (not to scale; a point contact: its section on y = 0) at "
                           "the player's step: its contact 2a, its pressure, the way it moves and the trailing edge, "
                           "where the contact lets go.",
                   specs=sketch.specs, layers=sketch.layers, inputs=("result", "frame"),
                   result=(core.CycleResult, core.PointContactResult)),
    "pressure": dict(opts=dict(title="Pressure and μ p_min", **key_opts()),
                caption="What you see: the body's pressure (the cylinder's: Hertz's) moves with the rocking centre xc (at the centre, at the reversals xc = ±W and at the player's step); its lowest value over the cycle (black) bounds the traction that can stay.", specs=_pressure_specs,
                     layers=_pressure_layers, inputs=("w", "units", "result", "frame")),
    # the title says what every run's figure draws: the closure is the uncoupled cylinder's under the constant-load
    # rocking only (closed_forms_apply), and the title is the figure's name for the slides, screenshots and benchmarks
    "traction": dict(opts=dict(title="Traction and its bounds", **key_opts()),
                caption="What you see: the solver's traction (solid) inside its bounds ±μ p, against the paper's closure (dashed) where it applies (the cylinder of an uncoupled contact rocked under constant loads); shaded: what each element does at the player's step (stick, slip on ±μ p, hatched, zero traction); at the last step, the final zones against ±μ p_min that the c_sd of the numbers is measured on.", specs=_traction_specs,
                     layers=_traction_layers, inputs=("ft", "w", "units", "result", "frame", "pinned")),
    "states": dict(opts=dict(title="Element states over the run"),
                caption="What you see: each element's state (colour bar) against time; the stick zone narrows to ±c_sd if the contact shakes down.", specs=_states_specs,
                   layers=_states_layers, inputs=("units", "result", "frame")),
    "displacement": dict(opts=dict(title="Rigid-body displacement", **key_opts()),
                caption="What you see: the body's rigid-body displacement over the periods: it levels off (shakedown) or keeps walking (ratcheting).", specs=_displacement_specs,
                         layers=_displacement_layers, inputs=("units", "result", "frame", "pinned")),
    "loop": dict(opts=dict(title="Fretting loop", **{**key_opts(), "hooks": [title_over_axis, few_x_ticks]}),
                 caption="What you see: the tangential force against the rigid-body displacement along it in the "
                         "first and the last period, sheared by the last loop's secant k so that its thin "
                         "hysteresis shows (the shear keeps the area); its area is the energy dissipated per "
                         "period (the cards give it). A closed loop in cyclic slip (loading 'tangential'), a "
                         "horizontal segment under a constant force (rocking, 'normal': the walk).",
                 specs=_loop_specs, layers=_loop_layers, inputs=("units", "result"),
                 result=(core.CycleResult,)),  # every body's run
    "increments": dict(opts=dict(title="Increment per period (log scale)", logy=True),
                caption="What you see: how far the body walks in each period (periods numbered from 1); it falls to zero at shakedown.", specs=_increments_specs,
                       layers=_increments_layers, inputs=("units", "result", "pinned")),
    "map": dict(opts=dict(title="Regime map: (ft, w) or (ft, A)", xlim=(0, 1),
                          ylim=(0, 1)),
                caption="What you see: the lines of the run's loading. Rocking: below the black curve (eq 35, the "
                        "cylinder), the purple one (sphere, ellipsoid) or the green one (the run's body, Melan's exact "
                        "limit) the contact shakes down; thin coloured curves: the closure's c_sd/a (labelled). "
                        "Oscillating normal force: Melan's limit at the run's amplitude and phase (green, dot-dash; a "
                        "line body's) and gross sliding at the lowest force, ft = 1 − A (dashed). Tangential loading: "
                        "the plane of the mean ft and the amplitude A (read the vertical axis as A): cyclic slip below "
                        "the dashed gross-sliding line |ft| + A = 1, no run beyond it. Dissimilar materials (Dundurs β ≠ 0, rocking): eq 35 "
                        "is only the uncoupled reference (black, dashed); the coupled limit (vermillion) is the "
                        "solver's, bisected at a few w (thick: each w's bracket), drawn as it is computed; the "
                        "uncoupled closed forms (the closure's c_sd/a, the sphere's limit, eq 36) are not drawn. "
                        "The big marker is the current "
                        "run (circle: shakedown, hexagon: cyclic slip, triangle: ratcheting).",
                specs=lambda units: _map_specs(), layers=_map_layers, inputs=("ft", "w", "result", "table", "coupled"),
                result=(core.CycleResult, core.PointContactResult)),
}


def group(name: str) -> str:
    """The HoloViews overlay group of figure ``name`` (it carries the figure's title and options)."""
    return name.capitalize()


hv.opts.defaults(*[hv.opts.Overlay(group(name), **{"legend_position": "bottom", "legend_cols": 2, **_BASE, **f["opts"]})
                   for name, f in FIGURES.items()])


@functools.lru_cache(maxsize=32)
def specs(name: str, units: Units) -> list:
    """How the layers of figure ``name`` are drawn in ``units`` (read-only, shared)."""
    return FIGURES[name]["specs"](units)


def layers(name: str, inputs: Inputs) -> tuple:
    """The data of each layer of figure ``name`` (a run of a kind the figure does not draw, see its ``result``
    entry, is not handed to it: the cylinder's figures draw no sphere run, and the other way round)."""
    figure_ = FIGURES[name]
    if inputs.result is not None and not isinstance(inputs.result, figure_.get("result", core.LineResult)):
        inputs = inputs._replace(result=None)
    return figure_["layers"](inputs)


def figure(name: str, inputs: Inputs) -> hv.Overlay:
    """Figure ``name`` as a HoloViews overlay (for a notebook, an export, or the first render)."""
    return overlay(specs(name, inputs.units), layers(name, inputs), group(name))


def dynamic(name: str, current, **streams) -> hv.DynamicMap:
    """Figure ``name`` as a ``hv.DynamicMap`` that HoloViews re-renders when one of ``streams`` changes.

    The idiomatic path, kept to be measured against :class:`app.live.LiveFigure`
    (``benchmarks/app.py --figures dynamicmap``; the explorer uses it when
    ``SHAKEDOWN_FIGURES=dynamicmap``).

    Parameters
    ----------
    name : str
        A key of :data:`FIGURES`.
    current : callable
        Returns the current :class:`Inputs` (the fields not in ``streams``).
    **streams
        Parameters (``param.Parameter`` of a Parameterized) by :class:`Inputs` field: the figure's inputs.
    """
    import panel as pn

    def draw(**values):
        return figure(name, current()._replace(**values))

    return hv.DynamicMap(pn.bind(draw, **streams))

