"""HoloViews figures of the explorer: pure functions of the inputs and of a solver result.

Every function returns an element or overlay of the same structure whatever
its inputs (empty layers where a curve does not apply), so that a
``hv.DynamicMap`` over it updates the Bokeh figure in place. No physics here:
every curve comes from :mod:`core`; this module only scales, labels and styles.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from functools import lru_cache

import holoviews as hv
import holoviews.plotting.bokeh  # noqa: F401 - registers the Bokeh backend and its options
import numpy as np
from bokeh.models import FixedTicker

import core
from core import approximations as approx

__all__ = ["Units", "make_units", "pressure_plot", "traction_plot", "state_map", "state_marks",
           "frame_marks", "displacement_plot", "displacement_step", "increment_plot", "pressure_step",
           "traction_closure", "traction_run", "style", "FIGURES", "pressure_figure", "states_figure",
           "displacement_figure", "increments_figure", "map_figure", "map_base", "map_point", "map_numerical",
           "grid_boundary",
           "time_axis", "ZONE_COLORS", "STATE_COLORS", "FONT"]

hv.Store.set_current_backend("bokeh")
# Plain canvas: these figures are small, and WebGL without a GPU (projector laptops, headless
# browsers) spends seconds copying its buffers into the page on every update.
hv.plotting.bokeh.BokehRenderer.webgl = False

#: Font sizes readable on a projector.
FONT = {"title": 17, "labels": 16, "xticks": 14, "yticks": 14, "legend": 14, "cticks": 13}
LINE = 3
HEIGHT = 480
#: Colours of the element states released / stick / slip forward / slip backward.
STATE_COLORS = ("#e6e6e6", "#2ca02c", "#d62728", "#1f77b4")
#: Shading of the zones stick / slip / zero traction.
ZONE_COLORS = {"stick": "#2ca02c", "slip": "#ff7f0e", "zero traction": "#9e9e9e"}
_ZONE_CODES = {"stick": 1, "slip": 2, "zero traction": 3}
_NX = 401

_BASE = dict(fontsize=FONT, responsive=True, height=HEIGHT, show_grid=True, framewise=True,
             toolbar="above", default_tools=["pan", "wheel_zoom", "box_zoom", "reset", "save"],
             backend_opts={"plot.toolbar.autohide": True})
_ELEMENTS = ("Curve", "Scatter", "Points", "Rectangles", "HLines", "VLines", "Image")


#: Title and extra options of each figure.
FIGURES = {
    "pressure": dict(title="Pressure (Hertz, uncoupled)"),
    "traction": dict(title="Traction: numerical vs closure"),
    "states": dict(title="Element states over the run"),
    "displacement": dict(title="Displacement of the cylinder"),
    "increments": dict(title="Increment per period (log scale)", logy=True),
    "map": dict(title="Shakedown map in the (ft, w) plane", xlim=(0, 1), ylim=(0, 1)),
}


def _group(figure: str) -> str:
    return figure.capitalize()


# Styles are registered once, by overlay group, rather than applied to every new frame (which costs
# more than drawing it); every element recomputes its ranges on each update (framewise).
hv.opts.defaults(
    *[getattr(hv.opts, name)(framewise=True) for name in _ELEMENTS],
    *[hv.opts.Overlay(_group(name), legend_position="bottom", legend_cols=2, **_BASE, **opts)
      for name, opts in FIGURES.items()],
)


def style(layers, figure: str) -> hv.Overlay:
    """The overlay of a figure, styled by its group (see :data:`FIGURES`)."""
    items = []
    for layer in layers:
        items.extend(layer if isinstance(layer, hv.Overlay) else [layer])
    return hv.Overlay(items, group=_group(figure))


def _memo(fn):
    """Keep the last few outputs: an unchanged layer is returned as the same object, so the plot skips it."""
    return functools.lru_cache(maxsize=4)(fn)


@dataclass(frozen=True)
class Units:
    """Scales from the normalised results of :mod:`core` to the displayed units, and axis labels."""

    system: str
    x: float = 1.0
    x_label: str = "x / a"
    p: float = 1.0
    p_label: str = "p / p0"
    q: float = 1.0
    q_label: str = "q / (μ p0)"
    u: float = 1.0
    u_label: str = "U [μ P/E*]"
    mu: float = 1.0


def make_units(system: str, contact: core.Contact | None, kernel: str, u0: float | None = None) -> Units:
    """Units of the plots.

    Parameters
    ----------
    system : {"normalised", "physical"}
        Physical units need ``contact``; without one they fall back to normalised.
    contact : Contact or None
        The current contact (SI units).
    kernel : {"strip", "plane"}
        With the strip kernel, normalised displacements are shown as ``U/U0``.
    u0 : float, optional
        ``U0`` of the strip kernel [μ P/E*].
    """
    mu = 1.0 if contact is None else contact.mu
    if system == "physical" and contact is not None:
        return Units("physical", x=contact.a * 1e3, x_label="x [mm]", p=contact.p0 / 1e6, p_label="p [MPa]",
                     q=contact.traction_unit / 1e6, q_label="q [MPa]", u=contact.displacement_unit * 1e6,
                     u_label="U [µm]", mu=mu)
    if kernel == "strip" and u0:
        return Units("normalised", u=1.0 / u0, u_label="u = U / U0", mu=mu)
    return Units("normalised", mu=mu)


def _x_grid(w: float) -> np.ndarray:
    reach = 1.0 + w
    return np.linspace(-1.08 * reach, 1.08 * reach, _NX)


def _curve(x, y, label, color, units_kdims, vdim, dash="solid", width=LINE, alpha=1.0):
    return hv.Curve((x, y), kdims=[units_kdims], vdims=[vdim], label=label).opts(
        color=color, line_dash=dash, line_width=width, alpha=alpha)


# --------------------------------------------------------------------------
# pressure
# --------------------------------------------------------------------------
@_memo
def pressure_plot(w: float, units: Units) -> hv.Overlay:
    """Hertz pressure at the centre and at the reversal points ``±W``, and μ times the lowest pressure.

    Parameters
    ----------
    w : float
        ``W / a``.
    units : Units
        Display units.
    """
    x = _x_grid(w)
    X, P = x * units.x, units.p
    kd, vd = hv.Dimension("x", label=units.x_label), hv.Dimension("p", label=units.p_label)
    return hv.Overlay([
        _curve(X, P * core.hertz_pressure(x, 0.0), "centre, xc = 0", "#7f7f7f", kd, vd, dash="dashed", width=2),
        _curve(X, P * core.hertz_pressure(x, w), "reversal xc = +W", "#1f77b4", kd, vd),
        _curve(X, P * core.hertz_pressure(x, -w), "reversal xc = −W", "#ff7f0e", kd, vd),
        _curve(X, P * units.mu * core.lowest_pressure(x, w), "μ p_min (over the cycle)", "black", kd, vd,
               width=LINE + 1),
    ])


@_memo
def pressure_step(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> hv.Curve:
    """Hertz pressure at the player's step (empty without a run)."""
    kd, vd = hv.Dimension("x", label=units.x_label), hv.Dimension("p", label=units.p_label)
    data = ([], [])
    if result is not None:
        k = result.xc.size - 1 if frame is None else int(np.clip(frame, 0, result.xc.size - 1))
        xc = float(result.xc[k])
        x = np.linspace(xc - 1.0, xc + 1.0, 201)
        data = (x * units.x, units.p * core.hertz_pressure(x, xc))
    return _curve(*data, "current step", "#d62728", kd, vd, dash="dotdash")


# --------------------------------------------------------------------------
# traction
# --------------------------------------------------------------------------
def _zone_rectangles(x_edges, codes, ylim, scale, kdims):
    """One Rectangles element per zone kind: contiguous runs of equal zone code."""
    out = []
    for name, code in _ZONE_CODES.items():
        mask = codes == code
        rects = []
        if mask.any():
            d = np.diff(np.concatenate([[0], mask.astype(int), [0]]))
            starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
            rects = [(x_edges[s] * scale, -ylim, x_edges[e] * scale, ylim) for s, e in zip(starts, ends)]
        out.append(hv.Rectangles(rects, kdims=[*kdims, "x1", "y1"], label=f"zone: {name}").opts(
            color=ZONE_COLORS[name], alpha=0.16, line_alpha=0))
    return out


def traction_zones(result: core.CycleResult, frame: int) -> np.ndarray:
    """Zone code per element at ``frame``: 1 stick, 2 slip, 3 zero traction (lost contact), 0 none.

    At the last step these are the shaken-down zones of :attr:`core.CycleResult.final_zones`
    (relative to the lowest pressure of the last period); at other steps, the
    element states of that step.
    """
    if frame >= result.xc.size - 1:
        return result.final_zones
    s = result.state[frame]
    ever = (result.state != 0).any(axis=0)
    return np.where(s == 1, 1, np.where(s >= 2, 2, np.where(ever, 3, 0)))


@_memo
def traction_closure(ft: float, w: float, units: Units) -> hv.Overlay:
    """The paper's closure for the shaken-down traction (eqs 22–30) and the bounds ±μ p_min.

    Parameters
    ----------
    ft, w : float
        Current inputs (these layers follow a slider while it moves).
    units : Units
        Display units.
    """
    Q, X = units.q, units.x
    kd, vd = hv.Dimension("x", label=units.x_label), hv.Dimension("q", label=units.q_label)
    x = _x_grid(w)
    low = Q * core.lowest_pressure(x, w)
    return hv.Overlay([
        _curve(x * X, low, "±μ p_min", "black", kd, vd, dash="dotted", width=2),
        _curve(x * X, -low, "", "black", kd, vd, dash="dotted", width=2),
        _curve(x * X, Q * core.shakedown_traction(x, ft, w), "closure (paper, eqs 22–30)", "#9467bd", kd, vd,
               dash="dashed", width=LINE + 1),
    ])


@_memo
def traction_run(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> hv.Overlay:
    """Numerical traction at the player's step, its bounds ±μ p, and the zones shaded.

    Parameters
    ----------
    units : Units
        Display units.
    result : CycleResult, optional
        The solver run (empty layers without one).
    frame : int, optional
        Step of ``result`` to show (default: the last).
    """
    Q, X = units.q, units.x
    kd, vd = hv.Dimension("x", label=units.x_label), hv.Dimension("q", label=units.q_label)
    ylim = 1.15 * Q
    if result is not None:
        k = result.xc.size - 1 if frame is None else int(np.clip(frame, 0, result.xc.size - 1))
        layers = _zone_rectangles(result.edges, traction_zones(result, k), ylim, X, [kd, vd])
        xe = result.x * X
        bound = result.pressure[k]
        num = (xe, Q * result.traction[k])
        upper, lower = (xe, Q * bound), (xe, -Q * bound)
    else:
        layers = _zone_rectangles(np.zeros(1), np.zeros(0), ylim, X, [kd, vd])
        num = upper = lower = ([], [])
    return hv.Overlay(layers + [
        _curve(*upper, "±μ p (this step)", "#555555", kd, vd, dash="dashed", width=2),
        _curve(*lower, "", "#555555", kd, vd, dash="dashed", width=2),
        hv.Curve(num, kdims=[kd], vdims=[vd], label="numerical").opts(
            color="#d62728", line_width=LINE, interpolation="steps-mid"),
    ])


def traction_plot(ft: float, w: float, units: Units, result: core.CycleResult | None = None,
                  frame: int | None = None) -> hv.Overlay:
    """The traction figure: zones and bounds of :func:`traction_run`, then :func:`traction_closure`, then the
    numerical traction on top."""
    *zones_and_bounds, numerical = list(traction_run(units, result, frame))
    return style([*zones_and_bounds, traction_closure(ft, w, units), numerical], "traction")


def pressure_figure(w: float, units: Units, result: core.CycleResult | None = None,
                    frame: int | None = None) -> hv.Overlay:
    """The pressure figure: :func:`pressure_plot` and :func:`pressure_step`."""
    return style([pressure_plot(w, units), pressure_step(units, result, frame)], "pressure")


def states_figure(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> hv.Overlay:
    """The space-time map: :func:`state_map`, :func:`state_marks` and :func:`frame_marks`."""
    return style([state_map(result, units), state_marks(result, units), frame_marks(result, frame)], "states")


def displacement_figure(units: Units, result: core.CycleResult | None = None,
                        frame: int | None = None) -> hv.Overlay:
    """The displacement figure: :func:`displacement_plot` and :func:`displacement_step`."""
    return style([displacement_plot(result, units), displacement_step(units, result, frame)], "displacement")


def increments_figure(units: Units, result: core.CycleResult | None = None) -> hv.Overlay:
    """The increment-per-period figure (:func:`increment_plot`)."""
    return style([increment_plot(result, units)], "increments")


# --------------------------------------------------------------------------
# the space-time map of element states
# --------------------------------------------------------------------------
_MAX_ROWS = 1500


def time_axis(result: core.CycleResult) -> np.ndarray:
    """Time of each step in periods: period ``p`` spans ``(p, p + 1]``, the loading ends at 0."""
    m = max(1, int(np.count_nonzero(result.period == 0)))
    n_load = int(np.count_nonzero(result.period < 0))
    return (np.arange(result.xc.size) + 1 - n_load) / m


@_memo
def state_map(result: core.CycleResult | None, units: Units) -> hv.Image:
    """Element states over the run: released / stick / slip forward / slip backward, x against time."""
    kd = [hv.Dimension("x", label=units.x_label), hv.Dimension("t", label="time [periods]")]
    vd = hv.Dimension("state", range=(-0.5, 3.5))
    if result is None:
        img = hv.Image(np.zeros((2, 2)), bounds=(-1, 0, 1, 1), kdims=kd, vdims=[vd])
    else:
        t = time_axis(result)
        stride = max(1, int(np.ceil(t.size / _MAX_ROWS)))
        rows = result.state[::stride].astype(np.uint8)
        dt = (t[1] - t[0]) if t.size > 1 else 1.0
        y0, y1 = t[0] - dt, t[0] - dt + rows.shape[0] * stride * dt
        e = result.edges * units.x
        img = hv.Image(np.flipud(rows), bounds=(e[0], y0, e[-1], y1), kdims=kd, vdims=[vd])
    labels = {i: name for i, name in enumerate(core.STATE_NAMES)}
    return img.opts(
        cmap=list(STATE_COLORS), clim=(-0.5, 3.5), colorbar=True,
        colorbar_opts={"ticker": FixedTicker(ticks=[0, 1, 2, 3]), "major_label_overrides": labels,
                       "title": "element state"})


@_memo
def state_marks(result: core.CycleResult | None, units: Units) -> hv.Overlay:
    """Marks of the state map: contact edges xc ± a, ±b = ±(a − W), ±c_sd (numerical and closure)."""
    kd = [hv.Dimension("x", label=units.x_label), hv.Dimension("t", label="time [periods]")]
    X = units.x
    if result is None:
        edges_l = edges_r = ([], [])
        b = c_num = c_cl = np.nan
    else:
        t = time_axis(result)
        a_now = np.sqrt(result.P)
        edges_l, edges_r = ((result.xc - a_now) * X, t), ((result.xc + a_now) * X, t)
        ft, w = float(result.params.get("ft", 0.0)), float(result.params.get("w", 0.0))
        b = (1.0 - w) * X
        c_num = result.stick_halfwidth * X
        c_cl = float(core.shakedown_stick_halfwidth(abs(ft), w)) * X
    def vlines(v, label, color, dash):
        xs = [] if not np.isfinite(v) else [-v, v]
        return hv.VLines(xs, kdims=kd[:1], label=label).opts(color=color, line_dash=dash, line_width=LINE)
    return hv.Overlay([
        hv.Curve(edges_l, kdims=kd[:1], vdims=kd[1:], label="contact edges xc ± a").opts(
            color="black", line_width=2),
        hv.Curve(edges_r, kdims=kd[:1], vdims=kd[1:]).opts(color="black", line_width=2),
        vlines(b, "±b = ±(a − W)", "#8c564b", "dashed"),
        vlines(c_num, "±c_sd numerical", "#b000b0", "solid"),
        vlines(c_cl, "±c_sd closure", "#4b0082", "dotted"),
    ])


@_memo
def frame_marks(result: core.CycleResult | None, frame: int | None) -> hv.HLines:
    """A horizontal line at the player's step on the state map."""
    ys = []
    if result is not None and frame is not None:
        ys = [float(time_axis(result)[int(np.clip(frame, 0, result.xc.size - 1))])]
    return hv.HLines(ys, kdims=[hv.Dimension("t", label="time [periods]")], label="player step").opts(
        color="#ffbf00", line_width=LINE + 1)


# --------------------------------------------------------------------------
# displacement
# --------------------------------------------------------------------------
@_memo
def displacement_plot(result: core.CycleResult | None, units: Units) -> hv.Overlay:
    """Rigid-body displacement over time (the paper's Figs 6 and 7), with the paper's u_sd (eq 34)."""
    kd = hv.Dimension("t", label="time [periods]")
    vd = hv.Dimension("u", label=units.u_label)
    curve = ([], [])
    usd = []
    if result is not None:
        curve = (time_axis(result), result.displacement * units.u)
        ft, w = float(result.params.get("ft", 0.0)), float(result.params.get("w", 0.0))
        if result.u0 and 0 <= ft < 1 and ft <= float(core.ft_limit(w)):
            usd = [float(approx.shakedown_displacement_approx(ft, w)) * result.u0 * units.u]
    return hv.Overlay([
        hv.Curve(curve, kdims=[kd], vdims=[vd], label="numerical").opts(color="#d62728", line_width=LINE),
        hv.HLines(usd, kdims=[vd], label="u_sd, eq 34 (paper's regression)").opts(
            color="#9467bd", line_dash="dashed", line_width=2),
    ])


@_memo
def displacement_step(units: Units, result: core.CycleResult | None = None, frame: int | None = None) -> hv.Scatter:
    """The player's step on the displacement curve."""
    kd = hv.Dimension("t", label="time [periods]")
    vd = hv.Dimension("u", label=units.u_label)
    pt = ([], [])
    if result is not None and frame is not None:
        k = int(np.clip(frame, 0, result.xc.size - 1))
        pt = ([time_axis(result)[k]], [result.displacement[k] * units.u])
    return hv.Scatter(pt, kdims=[kd], vdims=[vd], label="player step").opts(color="#ffbf00", size=12,
                                                                            line_color="black")


@_memo
def increment_plot(result: core.CycleResult | None, units: Units) -> hv.Overlay:
    """|Increment per period| on a log scale, with the paper's ratcheting regression (eq 38)."""
    kd = hv.Dimension("period", label="period")
    vd = hv.Dimension("du", label=f"|ΔU| per period [{units.u_label.split('[')[-1].rstrip(']')}]"
                      if "[" in units.u_label else "|Δu| per period [U0]")
    pts = ([], [])
    eq38 = []
    floor = 1e-12
    if result is not None:
        inc = np.abs(result.increment_per_period) * abs(units.u)
        top = float(inc.max()) if inc.size and inc.max() > 0 else 1.0
        floor = top * 1e-12
        pts = (np.arange(1, inc.size + 1), np.maximum(inc, floor))
        ft, w = float(result.params.get("ft", 0.0)), float(result.params.get("w", 0.0))
        if result.u0 and 0 <= ft < 1:
            d = float(approx.ratchet_increment_approx(ft, w)) * result.u0 * abs(units.u)
            if d > 0:
                eq38 = [d]
    return hv.Overlay([
        hv.Curve(pts, kdims=[kd], vdims=[vd], label="numerical").opts(color="#d62728", line_width=2),
        hv.Scatter(pts, kdims=[kd], vdims=[vd]).opts(color="#d62728", size=9),
        hv.HLines(eq38, kdims=[vd], label="eq 38 (paper's regression)").opts(
            color="#9467bd", line_dash="dashed", line_width=2),
    ])


# --------------------------------------------------------------------------
# the shakedown map
# --------------------------------------------------------------------------
_CSD_LEVELS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]


@lru_cache(maxsize=1)
def map_base() -> hv.Overlay:
    """The (ft, w) plane: exact limit (eq 35), the paper's regression (eq 36) and c_sd/a contours of the closure."""
    kd = [hv.Dimension("ft", label="ft = Ft / (μ Fn)", range=(0, 1)),
          hv.Dimension("w", label="w = W / a", range=(0, 1))]
    ft = np.linspace(0.0, 1.0, 401)
    n = 161
    g = (np.arange(n) + 0.5) / n
    FT, W = np.meshgrid(g, g)
    csd = core.shakedown_stick_halfwidth(FT * 0.999, W * 0.999)
    img = hv.Image((g, g, csd), kdims=kd, vdims=["c_sd"])
    contours = hv.operation.contours(img, levels=_CSD_LEVELS, filled=False).opts(
        cmap="viridis", line_width=2, colorbar=True, show_legend=False,
        colorbar_opts={"title": "c_sd / a (closure)"})
    return hv.Overlay([
        contours.opts(framewise=False),
        hv.Curve((ft, core.w_limit(ft)), kdims=kd[:1], vdims=kd[1:], label="eq 35 exact limit").opts(
            color="black", line_width=LINE + 1),
        hv.Curve((ft, approx.w_limit_regression(ft)), kdims=kd[:1], vdims=kd[1:],
                 label="eq 36 regression (approx.)").opts(color="#ff7f0e", line_dash="dashed",
                                                                       line_width=LINE),
        hv.Text(0.2, 0.25, "shakedown", fontsize=16).opts(color="#2ca02c"),
        hv.Text(0.8, 0.5, "ratcheting", fontsize=16).opts(color="#d62728"),
    ]).opts(_FIXED_RANGES)


def grid_boundary(table) -> tuple[np.ndarray, np.ndarray]:
    """The numerical boundary of a sweep table: per ``ft``, midway between the largest ``w`` that shook
    down and the next ``w`` of the grid (the grid's resolution of the numerical limit)."""
    fts, ws = [], []
    if table is None or len(table) == 0:
        return np.array(fts), np.array(ws)
    for ft, group in table.sort_values(["ft", "w"]).groupby("ft", sort=True):
        w = group["w"].to_numpy(float)
        ok = (group["regime"] == "shakedown").to_numpy()
        if ok.all() or not ok.any():
            continue
        k = int(np.argmin(ok))  # first grid w that did not shake down
        fts.append(float(ft))
        ws.append(0.5 * (w[k - 1] + w[k]) if k > 0 else 0.5 * w[0])
    return np.array(fts), np.array(ws)


def map_numerical(table, label: str = "solver") -> hv.Overlay:
    """Sweep results in the (ft, w) plane: each run coloured by its regime, and the grid's boundary."""
    kd = [hv.Dimension("ft", label="ft = Ft / (μ Fn)"), hv.Dimension("w", label="w = W / a")]
    layers = []
    for regime, color in (("shakedown", "#2ca02c"), ("ratcheting", "#d62728")):
        pts = ([], []) if table is None else (
            table.loc[table["regime"] == regime, "ft"].to_numpy(float),
            table.loc[table["regime"] == regime, "w"].to_numpy(float))
        layers.append(hv.Points(pts, kdims=kd, label=f"{regime} ({label})").opts(
            color=color, marker="square", size=5, alpha=0.35, line_alpha=0))
    layers.append(hv.Curve(grid_boundary(table), kdims=kd[:1], vdims=kd[1:],
                           label=f"numerical limit ({label})").opts(color="#1f77b4", line_width=LINE,
                                                                    line_dash="dotdash"))
    return hv.Overlay(layers)


def map_point(ft: float, w: float, regime: str | None = None) -> hv.Points:
    """The current (ft, w), coloured by the numerical regime when known."""
    kd = [hv.Dimension("ft", label="ft = Ft / (μ Fn)"), hv.Dimension("w", label="w = W / a")]
    color = {"shakedown": "#2ca02c", "ratcheting": "#d62728"}.get(regime, "#7f7f7f")
    return hv.Points([(ft, w)], kdims=kd, label="current point").opts(
        color=color, size=18, marker="circle", line_color="black", line_width=2)


#: The map's axes are fixed: its layers need no range recomputation on update.
_FIXED_RANGES = [getattr(hv.opts, name)(framewise=False) for name in ("Curve", "Points", "Contours", "Text")]
_NUMERICAL_MEMO: list = [None, None]  # (table, its layers): the map's numerical layers for the last table


def map_figure(table, ft: float, w: float, regime: str | None = None) -> hv.Overlay:
    """The shakedown map: numerical runs (:func:`map_numerical`), :func:`map_base` and :func:`map_point`."""
    table_seen, layers = _NUMERICAL_MEMO
    if table_seen is not table or layers is None:
        layers = map_numerical(table).opts(_FIXED_RANGES)
        _NUMERICAL_MEMO[:] = [table, layers]
    return style([layers, map_base(), _point(ft, w, regime)], "map")


@_memo
def _point(ft, w, regime):
    return map_point(ft, w, regime).opts(framewise=False)
