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

A figure with many layers has a module of its own, registered in :data:`FIGURES` by one entry like the others:
the sketch (:mod:`app.sketch`) and the regime map (:mod:`app.regime_map`); the looks they share (fonts, palette,
a regime's colour and marker) are :mod:`app.looks`.
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

from . import pinned, regime_map, sketch
from .live import Layer, overlay
from .looks import EMPTY as _EMPTY, FONT, LINE, OKABE_ITO, REGIME_COLORS, REGIME_MARKERS, memo as _memo
# the map's layers live in app/regime_map.py; these names were plots' and stay importable from here
from .regime_map import grid_boundary, map_base, map_numerical, map_point
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

HEIGHT = 480
#: Height of a figure of the first screen [px] (:data:`app.figures.KEY_FIGURES`): three fit above the fold at
#: 1280x720 and at 1024x768, two or three in a row.
KEY_HEIGHT = 330


#: The major ticks of a log axis, in the browser (a ``CustomJSTicker``'s code; ``fewest``, ``most``: how many
#: labels): powers of ten where they give at least ``fewest`` (every few decades beyond ``most``), else the first
#: of the mantissas 1-3, 1-2-5, 1-2-3-5-7, 1 to 9 in every decade that gives ``fewest`` (or the densest within
#: ``most``), else, on a range narrower than that, a linear step of 1, 2 or 5. Bokeh's own LogTicker ticks a log
#: axis of less than two decades linearly: three ticks labelled only its top, 0.05 and 0.1 over 0.002 to 0.1.
LOG_TICKS_JS = """
const lo = Math.min(cb_data.start, cb_data.end), hi = Math.max(cb_data.start, cb_data.end);
if (!(lo > 0) || !isFinite(hi) || !(hi > lo)) return [];
const e0 = Math.floor(Math.log10(lo)), e1 = Math.ceil(Math.log10(hi));
const inside = (mantissas) => {
  const out = [];
  for (let e = e0; e <= e1; e++)
    for (const k of mantissas) {
      const v = Number((k * Math.pow(10, e)).toPrecision(12));
      if (v >= lo && v <= hi) out.push(v);
    }
  return out;
};
let ticks = inside([1]);
if (ticks.length > most) {
  const step = Math.ceil(ticks.length / most);
  ticks = ticks.filter((v) => Math.round(Math.log10(v)) % step === 0);
}
for (const mantissas of [[1, 3], [1, 2, 5], [1, 2, 3, 5, 7], [1, 2, 3, 4, 5, 6, 7, 8, 9]]) {
  if (ticks.length >= fewest) break;
  const denser = inside(mantissas);
  if (denser.length > most && ticks.length >= 2) break;
  ticks = denser;
}
if (ticks.length < 2) {
  const raw = (hi - lo) / fewest, p = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((k) => k * p).find((s) => s >= raw);
  ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi * (1 + 1e-12); v += step) ticks.push(Number(v.toPrecision(12)));
}
return ticks;
"""
#: The minor ticks of a log axis: 1 to 9 times each power of ten over up to six decades, the powers beyond.
LOG_MINOR_TICKS_JS = """
const lo = Math.min(cb_data.start, cb_data.end), hi = Math.max(cb_data.start, cb_data.end);
if (!(lo > 0) || !isFinite(hi) || !(hi > lo)) return [];
const e0 = Math.floor(Math.log10(lo)), e1 = Math.ceil(Math.log10(hi));
const mantissas = e1 - e0 <= 6 ? [1, 2, 3, 4, 5, 6, 7, 8, 9] : [1];
const out = [];
for (let e = e0; e <= e1; e++)
  for (const k of mantissas) { const v = k * Math.pow(10, e); if (v >= lo && v <= hi) out.push(v); }
return out;
"""
#: A log axis's tick label: the shortest decimal (6 significant digits at most) between 1e-3 and 1e4, else 3e-5.
LOG_LABEL_JS = """
const v = Number(tick.toPrecision(6));
return v !== 0 && (Math.abs(v) < 1e-3 || Math.abs(v) >= 1e4) ? v.toExponential() : String(v);
"""


def log_ticker(fewest: int = 3, most: int = 6):
    """The ticker of a log axis (:data:`LOG_TICKS_JS`): at least ``fewest`` labelled ticks whatever the span, at
    most ``most``; a new Bokeh model (made in a render hook, never at import)."""
    from bokeh.models import CustomJSTicker

    return CustomJSTicker(major_code=LOG_TICKS_JS, minor_code=LOG_MINOR_TICKS_JS,
                          args={"fewest": int(fewest), "most": int(most)})


def readable_ticks(plot, element) -> None:
    """A render hook: few tick labels on a narrow figure's axes, so that they never run into each other (a first
    screen's figure is 240 to 420 px wide: the default six ticks gave "-1.5-1-0.5" on a wide x range), and a log
    axis labelled whatever its span (:func:`log_ticker`: Bokeh's LogTicker, linear below two decades, labelled
    only 0.05 and 0.1 of an axis from 0.002 to 0.1, and its LogTickFormatter can name 0.2 "10^-1")."""
    from bokeh.models import CustomJSTickFormatter, LogTicker

    fig = plot.state
    for axis in (*fig.xaxis, *fig.yaxis):
        ticker = getattr(axis, "ticker", None)
        if isinstance(ticker, LogTicker):
            axis.ticker = log_ticker()
            axis.formatter = CustomJSTickFormatter(code=LOG_LABEL_JS)
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
    and the title over the y axis too (:func:`title_over_axis`). Every label is given 74 px (``label_width``): Bokeh
    sized a column by its shorter labels, and a longer one ("xc = +W", "zero traction") ran into the next column's
    swatch."""
    return dict(height=KEY_HEIGHT, legend_position="bottom", legend_cols=2, legend_offset=(-KEY_SHIFT, 0),
                fontsize={**FONT, "title": 12, "labels": 15, "legend": 11},  # pt: a title fits 240 px
                backend_opts={**_BASE["backend_opts"], "plot.toolbar.autohide": True},  # no toolbar over the title
                legend_opts={"label_text_font_size": "11px", "spacing": 0, "padding": 2, "margin": 0,
                             "label_height": 12, "glyph_height": 12, "glyph_width": 14, "label_standoff": 3, "label_width": 74,
                             "border_line_alpha": 0},
                hooks=[title_over_axis])
_C = OKABE_ITO
#: Colours of the element states released / stick / slip forward / slip backward (the colour bar names them).
STATE_COLORS = ("#eeeeee", _C["blue"], _C["orange"], _C["purple"])
#: Shading of the zones stick / slip / zero traction; slip is also hatched (a cue that needs no colour).
ZONE_COLORS = {"stick": _C["blue"], "slip": _C["orange"], "zero traction": _C["grey"]}
ZONE_HATCH = {"stick": " ", "slip": "/", "zero traction": " "}
_ZONE_CODES = {"stick": core.Zone.STICK, "slip": core.Zone.SLIP, "zero traction": core.Zone.RELEASED}
_NX = 401

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
                specs=regime_map.specs, layers=regime_map.layers, inputs=("ft", "w", "result", "table", "coupled"),
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

