"""The explorer's view of point contacts (the rocking sphere and ellipsoid): figures, cards, body inputs.

The figures join :data:`app.plots.FIGURES` (so the explorer renders and
updates them like its own, :class:`app.live.LiveFigure`): the pressure and
the traction as maps over the contact plane at the player's step, the
element zones (stick, slip, released) as a map, the cut along ``y = 0``
beside the closed forms, the displacement over the run and per period.
Adding a figure is one layers function under :func:`_figure` (with its
specs) here and its name in the page's order, :data:`app.figures.ORDER`
(and in :data:`app.figures.KEY_FIGURES` for the loadings whose first
screen shows it).

A figure's ``result`` entry names the kind of run it draws
(:class:`core.CycleResult` for the cylinder's figures, by default,
:class:`core.PointContactResult` here): :func:`app.plots.layers` hands it no
run of another kind, and :func:`shown` tells the layout which figures a body
shows.

Full fields of a point-contact run are stored by :mod:`core.solvers.solver3d` at the
end of the loading, at every turning point and at the last step; the maps of
the traction and of the zones show the last stored step at or before the
player's (their title says which), while the pressure map and the cut along
``y = 0`` are those of the player's step itself.

No physics here: every number comes from :mod:`core`.
"""

from __future__ import annotations

import functools

import holoviews as hv
import numpy as np
import panel as pn

import core
from core.theory.point_contact import hertz_pressure_3d

from . import bodies, pinned, plots
from .live import Layer
from .plots import LINE, OKABE_ITO as _C, ZONE_COLORS, ZONE_HATCH, Units
from .state import POINT_RESOLUTION
from .units import along_ft
from .widgets import FloatSlider, IntSlider

__all__ = ["FIGURES", "shown", "body_inputs", "stored_step", "zone_codes", "pressure_map", "traction_map",
           "zone_map", "cut_layers", "displacement_layers", "increment_layers", "ZONE_NAMES"]

#: Zones of the zone map, by code: never in contact, released (in contact earlier, not now), stick, slip.
ZONE_NAMES = ("never in contact", "released", "stick", "slip +x", "slip −x")
_ZONE_PALETTE = ("#ffffff", ZONE_COLORS["zero traction"], ZONE_COLORS["stick"], ZONE_COLORS["slip"], _C["purple"])
_EMPTY = (np.zeros(0), np.zeros(0))
_NO_IMAGE = (np.zeros((2, 2)), (-1.0, -1.0, 1.0, 1.0))
#: maps: a little lower than the curves (they have a colour bar); equal scales on x and y (Bokeh widens one of the
#: ranges to the frame's shape), so that a sphere's circular contact is drawn round
_MAP = {"height": 430, "backend_opts": {**plots._BASE["backend_opts"], "plot.match_aspect": True,
                                        "plot.aspect_scale": 1.0}}

#: The figures of point contacts (merged into :data:`app.plots.FIGURES` on import).
FIGURES: dict = {}


def _figure(name, title, caption, inputs, specs, **opts):
    """Register the decorated layers function as figure ``name`` (drawn for point-contact runs)."""
    def register(layers):
        FIGURES[name] = dict(opts=dict(title=title, **opts), caption=caption, specs=specs, layers=layers,
                             inputs=inputs, result=core.PointContactResult)
        return layers
    return register


def shown(name: str, body: str) -> bool:
    """Whether figure ``name`` of :data:`app.plots.FIGURES` applies to ``body`` (its ``result`` kind)."""
    kinds = plots.FIGURES[name].get("result", core.LineResult)
    kinds = kinds if isinstance(kinds, tuple) else (kinds,)
    own = core.PointContactResult if bodies.kind(body) == "point" else core.LineResult
    return any(k is own or k is core.CycleResult for k in kinds)  # CycleResult: every run


# --------------------------------------------------------------------------
# labels and steps
# --------------------------------------------------------------------------
def _labels(units: Units) -> dict:
    """Axis labels of point-contact figures (lengths in a, tractions in mu p0, displacements in mu Fn/(E* a))."""
    physical = units.system == "physical"
    return dict(x=units.x_label, y="y [mm]" if physical else "y / a", p=units.p_label, q=units.q_label,
                u="U along Ft [µm]" if physical else "u along Ft [μ Fn/(E* a)]")


def _step(result, frame) -> int:
    last = result.xc.size - 1
    return last if frame is None else int(np.clip(frame, 0, last))


def stored_step(result: core.PointContactResult, step: int) -> int:
    """Index into ``result.snapshot_steps`` of the last stored full field at or before ``step``."""
    return max(0, int(np.searchsorted(result.snapshot_steps, step, side="right")) - 1)


def _bounds(result, units: Units) -> tuple:
    X = units.x
    return (result.x_edges[0] * X, result.y_edges[0] * X, result.x_edges[-1] * X, result.y_edges[-1] * X)


def _outline(result, step, units: Units) -> tuple:
    """The contact ellipse at ``step`` (semi-axes ``s`` and ``kappa s``, ``s`` the load scale); none for a body
    that is not an ellipsoid (its contact is where the map shows pressure)."""
    if not bodies.is_ellipsoid(result.body):
        return _EMPTY
    t = np.linspace(0.0, 2.0 * np.pi, 121)
    s = float(result.P[step]) ** (1.0 / 3.0)
    return ((float(result.xc[step]) + s * np.cos(t)) * units.x, result.body.kappa * s * np.sin(t) * units.x)


def _image_spec(units, name, label, cmap, clim=None, **opts) -> Layer:
    lab = _labels(units)
    vd = hv.Dimension(name, label=label, range=clim or (None, None))
    style = dict(cmap=cmap, colorbar=True, colorbar_opts={"title": label}, **opts)
    if clim is not None:
        style["clim"] = clim
    return Layer(hv.Image, (hv.Dimension("x", label=lab["x"]), hv.Dimension("y", label=lab["y"])), (vd,), "", style)


def _outline_spec(units) -> Layer:
    lab = _labels(units)
    return Layer(hv.Curve, (hv.Dimension("x", label=lab["x"]),), (hv.Dimension("y", label=lab["y"]),),
                 "contact edge (this step)", dict(color="black", line_width=2))


# --------------------------------------------------------------------------
# the maps
# --------------------------------------------------------------------------
@functools.lru_cache(maxsize=8)
def pressure_map(units: Units, result=None, frame=None) -> tuple:
    """The element pressure at the player's step [``units.p``] as an image, and the contact edge."""
    if result is None:
        return _NO_IMAGE, _EMPTY
    k = _step(result, frame)
    p = result.pressure(k)
    p = np.where(p > 0, p * units.p, np.nan)
    return (np.flipud(p), _bounds(result, units)), _outline(result, k, units)


@functools.lru_cache(maxsize=8)
def traction_map(units: Units, result=None, frame=None) -> tuple:
    """``|q|`` of the last stored step at or before the player's [``units.q``], and that step's contact edge."""
    if result is None:
        return _NO_IMAGE, _EMPTY
    j = stored_step(result, _step(result, frame))
    q = result.traction_snapshots[j]
    mag = np.hypot(q[0], q[1])
    mag = np.where(result.state_snapshots[j] > 0, mag * units.q, np.nan)
    return (np.flipud(mag), _bounds(result, units)), _outline(result, int(result.snapshot_steps[j]), units)


def zone_codes(result: core.PointContactResult, j: int) -> np.ndarray:
    """Zone code per element of stored field ``j`` (see :data:`ZONE_NAMES`): 0 never in contact at a stored
    step, 1 released, 2 stick, 3 slip +x, 4 slip −x."""
    states = result.state_snapshots
    ever = (states != 0).any(axis=0)
    s = states[j]
    return np.where(s > 0, s + 1, np.where(ever, 1, 0)).astype(np.int8)


@functools.lru_cache(maxsize=8)
def zone_map(units: Units, result=None, frame=None) -> tuple:
    """Zones of the last stored step at or before the player's, as an image, and that step's contact edge."""
    if result is None:
        return (np.zeros((2, 2)), (-1.0, -1.0, 1.0, 1.0)), _EMPTY
    j = stored_step(result, _step(result, frame))
    return ((np.flipud(zone_codes(result, j)), _bounds(result, units)),
            _outline(result, int(result.snapshot_steps[j]), units))


def _zone_colorbar(plot, element) -> None:
    """Name the zones on the colour bar (a hook: a new ticker model in every render, none shared)."""
    from bokeh.models import FixedTicker

    bar = plot.handles.get("colorbar")
    if bar is not None:
        bar.ticker = FixedTicker(ticks=list(range(len(ZONE_NAMES))))
        bar.major_label_overrides = dict(enumerate(ZONE_NAMES))


def _pressure_specs(units):
    return [_image_spec(units, "p", units.p_label, "viridis", clim=(0.0, units.p)), _outline_spec(units)]


def _traction_specs(units):
    return [_image_spec(units, "q", f"|q|, {units.q_label}", "magma", clim=(0.0, units.q)), _outline_spec(units)]


def _zone_specs(units):
    n = len(ZONE_NAMES)
    return [_image_spec(units, "zone", "zone", list(_ZONE_PALETTE), clim=(-0.5, n - 0.5), hooks=[_zone_colorbar]),
            _outline_spec(units)]


_COARSE = (f"Point contacts run on a coarse grid by default (dx = a/{POINT_RESOLUTION}, so that a run stays "
           "short); refine it under 'Body'.")


@_figure("point_pressure", "Pressure at the player's step (uncoupled)",
         "What you see: the body's pressure over the contact plane at the player's step (Hertz's for a sphere or "
         "an ellipsoid, solved numerically for a height map); the rocking moves it along x. " + _COARSE, ("units", "result", "frame"), _pressure_specs, **_MAP)
def _pressure_layers(i):
    return pressure_map(i.units, i.result, i.frame)


@_figure("point_traction", "Traction |q| at the last turning point",
         "What you see: the size of the tangential traction at the last stored step (loading end, turning "
         "points, last step) at or before the player's; it stays inside μ p.", ("units", "result", "frame"),
         _traction_specs, **_MAP)
def _traction_layers(i):
    return traction_map(i.units, i.result, i.frame)


@_figure("point_zones", "Stick, slip, released at the last turning point",
         "What you see: where the contact sticks, slips (+x or −x) or has been released, at the same stored "
         "step as the traction map; at shakedown nothing slips any more.", ("units", "result", "frame"),
         _zone_specs, **_MAP)
def _zone_layers(i):
    return zone_map(i.units, i.result, i.frame)


# --------------------------------------------------------------------------
# the cut along y = 0
# --------------------------------------------------------------------------
def _cut_specs(units):
    lab = _labels(units)
    kd, vd = hv.Dimension("x", label=lab["x"]), hv.Dimension("q", label=f"q on y = 0, {units.q_label}")
    zones = [Layer(hv.Rectangles, (kd, vd, "x1", "y1"), (), name,
                   dict(color=ZONE_COLORS[name], alpha=0.18, line_alpha=0,
                        hooks=[plots._hatch(ZONE_HATCH[name], ZONE_COLORS[name])]))
             for name in ("stick", "slip", "zero traction")]

    def line(label, color, dash="solid", width=LINE):
        return Layer(hv.Curve, (kd,), (vd,), label, dict(color=color, line_dash=dash, line_width=width))
    return [*zones,
            line("±μ p (step)", "#555555", "dashed", 2), line("", "#555555", "dashed", 2),
            line("±μ p_min (exact)", "black", "dotted", 2), line("", "black", "dotted", 2),
            line("q_y", _C["sky"], width=2), line("q_x", _C["vermillion"]),
            *pinned.specs("point_cut", kd, vd)]


@functools.lru_cache(maxsize=8)
def cut_layers(units: Units, result=None, frame=None) -> tuple:
    """On ``y = 0`` at the player's step: zones (stick, slip, released: :func:`app.plots.traction_zones`, the
    final zones at the last step, those the strip's ``c_sd (y = 0)`` is measured on), ±μ p (Hertz, closed form),
    and the numerical ``q_y`` and ``q_x`` as stairs over the elements."""
    if result is None:
        return ([], [], [], _EMPTY, _EMPTY, _EMPTY, _EMPTY)
    k = _step(result, frame)
    Q, X = units.q, units.x
    codes = plots.traction_zones(result, k)  # the cut's (same codes as a line's)
    zones = plots._zone_rectangles(result.x_edges, codes, 1.15 * Q, X)
    edges = np.repeat(result.x_edges * X, 2)[1:-1]
    if bodies.is_ellipsoid(result.body):  # Hertz's closed form
        x = np.linspace(result.x_edges[0], result.x_edges[-1], 401)
        scale = float(result.P[k]) ** (1.0 / 3.0)
        p = scale * hertz_pressure_3d(x / scale, 0.0, float(result.xc[k]) / scale, result.body.kappa)
    else:  # the run's own element pressure on the row of y = 0, as stairs
        x, p = edges / X, np.repeat(result.pressure(k)[_centre_row(result)], 2)
    q = result.traction_cut[k]
    return (*zones, (x * X, Q * p), (x * X, -Q * p), (edges, np.repeat(Q * q[1], 2)), (edges, np.repeat(Q * q[0], 2)))


@functools.lru_cache(maxsize=8)
def _pmin_cut(w: float, units: Units, reach: float) -> tuple:
    """±μ p_min on ``y = 0``: the lower of the Hertz pressures at the turning points ``±w`` (closed form)."""
    x = np.linspace(-reach, reach, 401)
    low = units.q * np.minimum(hertz_pressure_3d(x, 0.0, -w), hertz_pressure_3d(x, 0.0, w))
    return (x * units.x, low), (x * units.x, -low)


def _centre_row(result) -> int:
    """The row of elements on ``y = 0`` (the one whose y-range holds 0)."""
    return int(np.clip(np.searchsorted(result.y_edges, 0.0) - 1, 0, result.y_edges.size - 2))


@functools.lru_cache(maxsize=8)
def _pmin_run(units: Units, result) -> tuple:
    """±μ p_min on ``y = 0`` of a run: the lowest element pressure over its cycle (``result.lowest_pressure``)."""
    edges = np.repeat(result.x_edges * units.x, 2)[1:-1]
    low = units.q * np.repeat(result.lowest_pressure[_centre_row(result)], 2)
    return (edges, low), (edges, -low)


@_figure("point_cut", "Traction on y = 0",
         "What you see: the traction on the line y = 0 at the player's step (stairs: elements) inside ±μ p, and "
         "±μ p_min, the exact bound a shaken-down traction stays within; shaded: what each element does at the player's step (stick, slip, hatched, released); at the last step, the final zones against ±μ p_min that the c_sd (y = 0) of the numbers is measured on.",
         ("w", "units", "result", "frame", "pinned"), _cut_specs, **plots.key_opts())
def _cut_layers(i):
    *zones, up, down, qy, qx = cut_layers(i.units, i.result, i.frame)
    if i.result is not None and not bodies.is_ellipsoid(i.result.body):
        pmin = _pmin_run(i.units, i.result)  # the run's own p_min (no closed form)
    else:
        reach = 1.0 + i.w if i.result is None else float(max(abs(i.result.x_edges[0]), i.result.x_edges[-1]))
        pmin = _pmin_cut(float(i.w), i.units, reach)
    return (*zones, up, down, *pmin, qy, qx,
            *pinned.layers("point_cut", i.pinned, i.units))


# --------------------------------------------------------------------------
# displacement and increments
# --------------------------------------------------------------------------
def _displacement_specs(units):
    lab = _labels(units)
    kd, vd = hv.Dimension("t", label="time [periods]"), hv.Dimension("u", label=lab["u"])
    return [Layer(hv.Curve, (kd,), (vd,), "numerical", dict(color=_C["vermillion"], line_width=LINE)),
            *pinned.specs("point_displacement", kd, vd),
            Layer(hv.Scatter, (kd,), (vd,), "player step", dict(color=_C["yellow"], size=12, line_color="black"))]


@functools.lru_cache(maxsize=8)
def displacement_layers(units: Units, result=None, frame=None) -> tuple:
    """The displacement along Ft over the run, and the player's step on it."""
    if result is None:
        return _EMPTY, _EMPTY
    t, u = plots.time_axis(result), along_ft(result) * units.u
    k = _step(result, frame)
    return (t, u), ([t[k]], [u[k]])


@_figure("point_displacement", "Displacement along Ft",
         "What you see: the body's rigid-body displacement along Ft over the periods: it levels off (shakedown) "
         "or keeps walking (ratcheting).", ("units", "result", "frame", "pinned"), _displacement_specs,
         **plots.key_opts())
def _displacement_layers(i):
    curve, step = displacement_layers(i.units, i.result, i.frame)
    return (curve, *pinned.layers("point_displacement", i.pinned, i.units), step)


def _increments_specs(units):
    lab = _labels(units)
    kd, vd = hv.Dimension("period", label="period"), hv.Dimension("du", label=f"|Δu| per period [{lab['u'].split('[')[-1]}")
    return [Layer(hv.Curve, (kd,), (vd,), "numerical", dict(color=_C["vermillion"], line_width=2)),
            Layer(hv.Scatter, (kd,), (vd,), "", dict(color=_C["vermillion"], size=9)),
            *pinned.specs("point_increments", kd, vd)]


@functools.lru_cache(maxsize=8)
def increment_layers(units: Units, result=None) -> tuple:
    """|Displacement increment per period| along Ft (curve and markers; floored for the log scale)."""
    if result is None:
        return _EMPTY, _EMPTY
    inc = np.abs(result.increment_per_period) * abs(units.u)
    top = float(inc.max()) if inc.size and inc.max() > 0 else 1.0
    pts = (np.arange(1, inc.size + 1), np.maximum(inc, top * 1e-12))
    return pts, pts


@_figure("point_increments", "Increment per period",
         "What you see: how far the body walks along Ft in each period (from 1); it falls to zero at shakedown "
         "and settles at a constant step when it ratchets.", ("units", "result", "pinned"), _increments_specs, logy=True,
         **plots.key_opts())
def _increment_layers(i):
    return (*increment_layers(i.units, i.result), *pinned.layers("point_increments", i.pinned, i.units))


plots.FIGURES.update(FIGURES)
hv.opts.defaults(*[hv.opts.Overlay(plots.group(name), **{
    "legend_position": "bottom", "legend_cols": 2, **plots._BASE, **f["opts"]}) for name, f in FIGURES.items()])


# --------------------------------------------------------------------------
# the inputs
# --------------------------------------------------------------------------
def _parameter_widget(state, body: str, p):
    """The input of parameter ``p`` of ``body`` (:mod:`app.bodies`): a slider, a number box for a scale, or the
    choice of a file (the built-in demo, or an upload) with its upload button; the registry's doc as tooltip."""
    name = bodies.state_name(body, p.name)
    if p.path:
        return _source_input(state, body, p, name)
    spec = state.param[name]
    if bodies.wide(p):
        return pn.widgets.FloatInput.from_param(spec, sizing_mode="stretch_width", description=spec.doc)
    slider = FloatSlider.from_param(spec, sizing_mode="stretch_width", throttled=True,
                                    css_classes=[f"body-param-{name}"])
    return pn.Row(slider, pn.widgets.TooltipIcon(value=spec.doc, margin=(20, 0, 0, 0)), sizing_mode="stretch_width",
                  margin=0)


def _source_input(state, body, p, name):
    """A file parameter: a menu of the sources (the built-in demo, files uploaded in this session) and an upload."""
    def options(current):
        out = {"built-in demo": "demo"} if (body, p.name) in bodies.DEMO_FILES else {}
        if current != "demo":
            out[f"uploaded ({current[7:15]})"] = current
        return out

    select = pn.widgets.Select(label=bodies.label(body, p.name), options=options(getattr(state, name)),
                               value=getattr(state, name), sizing_mode="stretch_width", description=p.doc,
                               css_classes=[f"body-source-{name}"])
    upload = pn.widgets.FileInput(sizing_mode="stretch_width", multiple=False, css_classes=[f"body-upload-{name}"])
    message = pn.pane.Markdown("", visible=False, margin=(0, 10), styles={"font-size": "13px"})

    def chosen(event):
        if event.new is not None:
            setattr(state, name, event.new)

    def followed(event):
        select.param.update(options=options(event.new), value=event.new)

    def uploaded(event):
        if not event.new:
            return
        try:
            source = bodies.store_upload(event.new, upload.filename or "")
        except ValueError as e:
            message.param.update(object=f"*{e}*", visible=True)
            return
        message.param.update(object="", visible=False)
        setattr(state, name, source)

    select.param.watch(chosen, "value")
    state.param.watch(followed, name)
    upload.param.watch(uploaded, "value")
    return pn.Column(select, upload, message, sizing_mode="stretch_width", margin=0)


def _body_note(state, body: str) -> str:
    text = bodies.note(body)
    try:
        obj = bodies.make(body, state.body_values(body))
    except ValueError as e:
        return text + f" *{e}*"
    if not bodies.runs_cycles(body, obj):
        text += (" **Limit only:** the explorer cannot run this body's cycles yet; its exact limit (Melan) is on "
                 "the cards and the map.")
    elif bodies.own_grid(obj):
        text += f" It runs on its own grid (dx = {float(obj.default_dx):g} a, its samples)."
    elif bodies.kind(body) == "point":
        text += f" A coarse grid by default (dx = a/{POINT_RESOLUTION}) keeps a run short; refine it for converged numbers."
    return text


#: The body selector wraps onto a second row when the registry's bodies do not fit the sidebar's width.
_SELECT_CSS = """
.bk-btn-group { flex-wrap: wrap; row-gap: 4px; }
.bk-btn-group > .bk-btn { flex: 1 0 auto; border-radius: 4px !important; margin-left: 0 !important; }
"""


def _body_widgets(state, body: str) -> list:
    """The inputs of ``body``'s parameters and its note (which follows them)."""
    names = [bodies.state_name(body, p.name) for p in bodies.parameters(body)]
    note = pn.pane.Markdown(_body_note(state, body), styles={"font-size": "13px"}, margin=(0, 10),
                            css_classes=["body-note"])
    if names:
        state.param.watch(lambda e: setattr(note, "object", _body_note(state, body)), names)
    return [*[_parameter_widget(state, body, p) for p in bodies.parameters(body)], note]


def body_inputs(state) -> list:
    """The body selector (every body of :data:`core.geometry.registry.REGISTRY`), the current body's parameters and note,
    and the point-contact grid (widgets over ``state``). A body's inputs are built when it is first chosen and
    kept (one holder shows the current body's; plain watchers, no reactive expressions: a page of the default
    cylinder builds only the selector and two empty holders)."""
    select = pn.widgets.RadioButtonGroup.from_param(state.param.body, color="primary", variant="outline",
                                                    sizing_mode="stretch_width", css_classes=["body-select"],
                                                    stylesheets=[_SELECT_CSS])
    holder = pn.Column(sizing_mode="stretch_width", margin=0, css_classes=["body-inputs"])
    grid = pn.Column(sizing_mode="stretch_width", margin=0, visible=False)
    built: dict = {}

    def show(body):
        if body not in built:  # the paper's cylinder: no parameters, and the page says what it is already
            built[body] = [] if body == bodies.DEFAULT else _body_widgets(state, body)
        holder.objects = built[body]
        refinable = state.refinable
        if refinable and not grid.objects:
            grid.objects = [IntSlider.from_param(state.param.point_resolution, sizing_mode="stretch_width",
                                                 throttled=True)]
        grid.visible = refinable

    show(state.body)
    state.param.watch(lambda e: show(e.new), "body")
    return [pn.pane.Markdown("### Body"), select, holder, grid]
