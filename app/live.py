"""Live figures: a Bokeh figure rendered once by HoloViews, then updated by replacing its layers' data.

Re-rendering a HoloViews overlay on every change rebuilds every element,
recomputes its ranges, restyles every glyph and axis and sends all of it to the
browser (about 35 ms a figure on the server, more in the browser). A
:class:`LiveFigure` renders the overlay once per process (the template, which
no session holds), gives each session a copy of its Bokeh models with new ids
(decoding a copy costs a quarter of rendering it: the figures of a session
went from 1.5-1.9 s to 0.5 s of CPU), and on
:meth:`LiveFigure.update` writes only the layers whose data changed (by
identity: the layer functions of :mod:`app.plots` are memoised, so an
unchanged layer is the same object) into their ``ColumnDataSource``, one
``data`` assignment each. Lines, markers, spans and rectangles are written
directly (their columns are the element's dimensions); images go through
their HoloViews plot's own ``get_data``. A test checks that the result equals
a fresh render.

Axes that follow the data are ``DataRange1d``: the browser fits them to the new
data and, once the user zooms or pans, keeps the user's view until *reset*.

A served page draws a figure only when the browser scrolls near it
(:class:`WhenShown`, a sentinel that keeps the figure's place): a visitor who
never scrolls costs the server the figure at the top only.

Why this layer and not the idiomatic path (issue 11, item 13; measured then, with every figure drawn
as the page opened). The idiomatic
path, one ``hv.DynamicMap`` per figure fed by ``pn.bind``
(:func:`app.plots.dynamic`, served with ``SHAKEDOWN_FIGURES=dynamicmap``), was
measured against this one with ``python benchmarks/app.py --figures both
--repeats 8`` (both in one run, on a quiet machine, load average about 1; the
output is in ``benchmarks/results/app_figures_both.txt``):

==============================  ===============  ====================
median (n = 8)                  LiveFigure       DynamicMap
==============================  ===============  ====================
slider -> plot data             71 ms            1097 ms
new solve -> plot data          406 ms           4068 ms
player step -> traction data    82 ms            1918 ms
first load (later sessions)     4.0 s            10.0 s
server CPU per session          1.86 s           6.42 s
Bokeh models per session        880              1382
==============================  ===============  ====================

The slider meets its 100 ms target only on this layer; a new solve misses
300 ms on both (the solve is 5 ms and the server's update 25-30 ms; the rest
is the round trip and the browser redrawing seven figures), by ten times
without it.

HoloViews re-renders every element of an overlay, recomputes its ranges and
restyles its glyphs on each change; this layer writes only the changed
layers' arrays. Every figure updates on the slider and the solve, so every
figure misses the 100 ms / 300 ms targets by more without it: all of them
keep it. A session also costs the server a third of the CPU (1.86 s against 6.42 s). Adding a figure
is one entry of :data:`app.plots.FIGURES` (specs, layers, inputs) and one
layout line in :meth:`app.explorer.Explorer.explorer_tab`, on both paths.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import NamedTuple

import holoviews as hv
import numpy as np
import param
from panel.reactive import ReactiveHTML
from bokeh.core.has_props import HasProps
from bokeh.core.property.descriptors import (DataSpecPropertyDescriptor, PropertyDescriptor,
                                              UnitsSpecPropertyDescriptor)
from bokeh.core.property.wrappers import PropertyValueContainer
from bokeh.core.serialization import Deserializer, Serializer
from bokeh.models import AllIndices, ColumnDataSource, DataRange1d, GlyphRenderer, UnionRenderers
from bokeh.util.serialization import make_id

__all__ = ["Layer", "Styled", "overlay", "LiveFigure", "WhenShown"]

def _columns(spec: Layer, data) -> dict | None:
    """The data-source columns of a layer whose glyph takes its data as they are (lines, markers, spans,
    rectangles), written without HoloViews; None for the others (images)."""
    names = [d.name if isinstance(d, hv.Dimension) else d for d in (*spec.kdims, *spec.vdims)]
    if spec.kind in (hv.Curve, hv.Scatter, hv.Points):
        return {n: np.asarray(c) for n, c in zip(names, data)}
    if spec.kind in (hv.HLines, hv.VLines):
        return {names[0]: np.asarray(data, dtype=float)}
    if spec.kind is hv.Rectangles:
        r = np.asarray(data, dtype=float).reshape(-1, 4)
        return {"left": r[:, 0], "bottom": r[:, 1], "right": r[:, 2], "top": r[:, 3]}
    return None


def _is_empty(data) -> bool:
    """Whether layer data draws nothing (its legend entry is then hidden)."""
    if isinstance(data, Styled):
        data = data.data
    if data is None:
        return False
    if isinstance(data, tuple) and len(data) == 2 and not isinstance(data[1], tuple) and np.ndim(data[0]) == 2:
        return False  # an image (array, bounds)
    if isinstance(data, tuple):
        return all(np.size(c) == 0 for c in data)
    return np.size(data) == 0


class Styled(NamedTuple):
    """Layer data with glyph properties that change with it (e.g. a colour that encodes a regime)."""

    data: object
    glyph: dict


@dataclass(frozen=True, eq=False)
class Layer:
    """How one layer of a figure is drawn: element type, dimensions (with units), legend label, style.

    Layer data by element type: ``Curve``, ``Scatter``, ``Points``: a tuple of
    columns ``(x, y)``; ``Rectangles``: rows ``(x0, y0, x1, y1)``; ``HLines``,
    ``VLines``: positions; ``Image``: ``(array, bounds)``; or a :class:`Styled`
    of these.
    """

    kind: type
    kdims: tuple
    vdims: tuple = ()
    label: str = ""
    opts: dict = field(default_factory=dict)

    def element(self, data) -> hv.Element:
        """The HoloViews element of this layer showing ``data``."""
        opts = self.opts
        if isinstance(data, Styled):
            data, opts = data.data, {**opts, **data.glyph}
        kw = dict(kdims=list(self.kdims), vdims=list(self.vdims), label=self.label)
        if self.kind is hv.Image:
            array, bounds = data
            return hv.Image(array, bounds=bounds, **kw).opts(**opts)
        return self.kind(data, **kw).opts(**opts)

    @property
    def labels(self) -> tuple:
        return tuple(getattr(d, "pprint_label", d) for d in (*self.kdims, *self.vdims))


def overlay(specs, data, group: str) -> hv.Overlay:
    """The overlay of layers ``specs`` showing ``data``; a spec that is a HoloViews element is static."""
    return hv.Overlay([s.element(d) if isinstance(s, Layer) else s for s, d in zip(specs, data)], group=group)


def _labels(specs) -> tuple:
    return tuple(s.labels if isinstance(s, Layer) else None for s in specs)


class _Render:
    """A figure rendered by HoloViews once per process: the template its sessions' figures are copied from.

    HoloViews spends most of a session's build on its figures (about 0.2 s
    each: options, ranges, glyphs, axes, legends, for every layer). What it
    produces depends on the layers' specs (shared by every session, see
    :func:`app.plots.specs`), not on their data, which :class:`LiveFigure`
    writes in anyway. So the figure is rendered once, kept encoded (never
    shown: no session ever holds it), and each session gets a copy decoded
    with new model ids: its own models, nothing shared between sessions.
    """

    def __init__(self, specs, data, group: str, padding):
        plot = hv.renderer("bokeh").get_plot(overlay(specs, data, group))
        subplots = list(plot.subplots.values())  # in the overlay's order
        if len(subplots) != len(specs):  # pragma: no cover - a HoloViews change
            raise RuntimeError(f"{len(specs)} layers but {len(subplots)} subplots")
        figure = plot.state
        if padding is not None:
            px, py = padding
            figure.x_range = DataRange1d(range_padding=px)
            figure.y_range = DataRange1d(range_padding=py)
        items = [item for legend in figure.legend for item in legend.items]
        legend = {}
        for i, sub in enumerate(subplots):
            renderer = sub.handles.get("glyph_renderer")
            for item in items:
                if renderer is not None and renderer in item.renderers:
                    legend[i] = item.id
                    item.visible = not _is_empty(data[i])  # empty layers get no legend entry
        self.specs, self.labels, self.data = specs, _labels(specs), tuple(data)
        self.subplots = subplots  # their get_data draws images; their models are never shown
        self.layers = tuple((sub.handles["source"].id, sub.handles["glyph"].id) for sub in subplots)
        self.legend = legend
        every, union = AllIndices(), UnionRenderers()  # what all layers' views and sources share, see below
        selected = None
        for renderer in figure.renderers:
            if isinstance(renderer, GlyphRenderer):
                # no figure has a selection tool, so HoloViews' selection and non-selection glyphs are never
                # drawn: Bokeh's automatic ones (the glyph itself) save two models a layer
                renderer.selection_glyph = renderer.nonselection_glyph = "auto"
                # no legend mutes a layer (no click policy): Bokeh's automatic muted glyph, one model a layer less
                renderer.muted_glyph = "auto"
                # a view's filter "all indices" and a source's selection policy hold no state: one of each for
                # the figure instead of one per layer (two models a layer less to build, copy and send)
                if isinstance(renderer.view.filter, AllIndices):
                    renderer.view.filter = every
                source = renderer.data_source
                if isinstance(getattr(source, "selection_policy", None), UnionRenderers):
                    source.selection_policy = union
                # nor does a selection (the browser only reads it, to paint; no tool ever sets one): one empty
                # Selection for all the figure's sources, one model a layer less (Bokeh's property is read-only
                # to Python, as a browser's change it is set)
                if isinstance(source, ColumnDataSource):
                    if selected is None:
                        selected = source.selected
                    elif source.selected is not selected:
                        source.set_from_json("selected", selected)
        models = figure.references()
        self.model_ids = frozenset(m.id for m in models)
        # the data sources' columns are handed over as they are, not encoded and decoded: decoding a property
        # formats its value for a trace log, which for arrays costs more than the rest of the copy
        self._columns = {}
        for m in models:
            if isinstance(m, ColumnDataSource):
                self._columns[m.id] = {k: _read_only(v) for k, v in m.data.items()}
                m.data = {}
        self._rep = Serializer().encode(figure)

    def copy(self):
        """A new figure equal to the template, every model with a new id; and its models by the template's ids."""
        new = {old: make_id() for old in self.model_ids}

        def renamed(x):
            if isinstance(x, dict):
                out = {k: renamed(v) for k, v in x.items()}
                ident = x.get("id")
                if isinstance(ident, str) and ident in new and (x.get("type") == "object" or len(x) == 1):
                    out["id"] = new[ident]
                return out
            if isinstance(x, list):
                return [renamed(v) for v in x]
            return x

        decoder = _Copier()
        figure = decoder.deserialize(renamed(self._rep))
        by_new = decoder._references  # every model of the copy, by id (no walk of its graph)
        models = {old: by_new[n] for old, n in new.items()}
        for source, columns in self._columns.items():
            models[source].data = {k: list(v) if isinstance(v, tuple) else v for k, v in columns.items()}  # the template's arrays, read-only: replaced, never written
        return figure, models


class _Copier(Deserializer):
    """Bokeh's decoder of a model graph, writing the template's (valid, not default) values straight in.

    Bokeh's own decoder sets each property as a change: it first reads the old value, which builds the
    property's default (a new model for some), and notifies; a copy that no one watches yet needs neither (a
    third of a figure's copy). Data specs keep the format Bokeh's own path gives them (a value, a field, a dict).
    """

    def _decode_object_ref(self, obj):
        cls = self._resolve_type(obj["name"])
        instance = cls.__new__(cls, id=obj["id"])
        self._references[instance.id] = instance
        # HasProps.__init__ without building the default of every property with a mutable default (a new
        # Selection for each source, a new view for each renderer...) that the template's values then replace
        super(HasProps, instance).__init__()
        instance._property_values, instance._unstable_default_values = values, defaults = {}, {}
        instance._unstable_themed_values = {}
        attributes = obj.get("attributes") or {}
        for key, rep in attributes.items():
            value = self._decode(rep)
            descriptor = cls.lookup(key)
            if type(descriptor) is PropertyDescriptor:
                values[key] = _valid(descriptor.property, value)
                defaults.pop(key, None)  # (as Bokeh's setter: a value set, not a default)
            elif isinstance(descriptor, DataSpecPropertyDescriptor):  # its set_from_json, minus the validation
                if isinstance(descriptor, UnitsSpecPropertyDescriptor):
                    value = descriptor._extract_units(instance, value)
                old = descriptor._get(instance)
                if isinstance(value, dict) and old is not None:  # keeps the spec's format (value, field, dict)
                    try:
                        descriptor.property.value_type.validate(old, False)
                        value = value.get("value", value)
                    except ValueError:
                        if isinstance(old, str) and "field" in value:
                            value = value["field"]
                descriptor._set(instance, old, _valid(descriptor.property, value))
            else:
                descriptor.set_from_json(instance, value)
        for key in _unstable_keys(cls):  # the others' mutable defaults, as HasProps.__init__
            if key not in attributes:
                cls.lookup(key)._get(instance)
        instance._initialized = True
        return instance


def _valid(prop, value):
    """Bokeh's ``Property.prepare_value`` for a value validated already (the template's, when it was rendered):
    its transform and its container, without validating it again (a third of a figure's copy).

    Not Bokeh's ``validate(False)``: that switch is the process's, and a thread that builds models meanwhile
    (a session's page while the warm-up copies a figure) would skip validation too, with it the conversions
    that validation drives: a HoloViews figure got its title as a ``str`` instead of a ``Title`` and failed.
    """
    return prop.wrap(prop.transform(value))


_UNSTABLE_KEYS: dict = {}


def _unstable_keys(cls) -> tuple:
    """The properties of Bokeh model class ``cls`` whose default is built anew for each instance (a model, a
    list...), in Bokeh's order: what ``HasProps.__init__`` builds. (A class's property, not an instance's: Bokeh
    asks each instance, for every property, 40 % of a figure's copy.)"""
    keys = _UNSTABLE_KEYS.get(cls)
    if keys is None:
        # (has_unstable_default reads only the class: its overridden defaults and its properties)
        keys = _UNSTABLE_KEYS[cls] = tuple(key for key in cls.properties(_with_props=True)
                                           if cls.lookup(key).has_unstable_default(cls))
    return keys


_BOKEH = {"query_properties_with_values": HasProps.query_properties_with_values,
          "themed_values": HasProps.themed_values}


def _query_properties_with_values(self, query, *, include_defaults: bool = True, include_undefined: bool = False):
    """``HasProps.query_properties_with_values`` that, for what is serialized (``include_defaults=False``), reads
    only the properties it returns: those set, those whose default was built for the instance, the themed ones.

    Bokeh's own reads every property first, which builds and validates the default of each property left at
    its default (an axis has a hundred): 70 % of the time to send a page's document (``Document.to_json``), half
    of it for the figures' models. The result is the same dict, in the same order; only a required property
    never set, which Bokeh would report here, is reported later, by the browser.
    """
    if include_defaults or include_undefined:
        return _BOKEH["query_properties_with_values"](self, query, include_defaults=include_defaults,
                                                      include_undefined=include_undefined)
    themed = self.themed_values()
    themed_keys = themed.keys() if themed is not None else set()
    unstable = self._unstable_default_values
    selected = self._property_values.keys() | unstable.keys() | themed_keys
    result = {}
    for key in self.properties(_with_props=True):
        if key in selected:
            descriptor = self.lookup(key)
            if query(descriptor):
                value = descriptor.get_value(self)
                if key in themed_keys or not (key in unstable and isinstance(value, PropertyValueContainer)):
                    result[key] = value
    return result


def _themed_values(self) -> dict | None:
    """``HasProps.themed_values`` without an exception: Bokeh's reads an attribute that most models never get
    (no theme sets any of their properties) through ``HasProps.__getattr__``, which raises twice; Bokeh asks for
    it before building any default (20 % of a figure's copy and of the walks of its model graph)."""
    return self.__dict__.get("__themed_values__")


def faster_bokeh(on: bool = True) -> bool:
    """Replace two methods of Bokeh's ``HasProps`` in this process by equivalents that do less work
    (:func:`_query_properties_with_values`, :func:`_themed_values`); ``on=False``: Bokeh's own again.

    Installed by the served app (``app/main.py``), not on import: a notebook that imports :mod:`app` keeps
    Bokeh's own methods for its other plots. A served page's document is then encoded for the browser in a
    fifth of the time (``Document.to_json``, the same JSON: ``tests/test_app_live.py`` compares them), and the
    page costs the server about 0.1 s of CPU less. Returns whether ours were installed before.
    """
    before = HasProps.themed_values is _themed_values
    ours = {"query_properties_with_values": _query_properties_with_values, "themed_values": _themed_values}
    for name, method in (ours if on else _BOKEH).items():
        setattr(HasProps, name, method)
    return before


def _read_only(column):
    if isinstance(column, np.ndarray):
        column = column.view()
        column.flags.writeable = False
        return column
    if isinstance(column, (list, tuple)):  # e.g. an image column: a list of 2D arrays
        return tuple(_read_only(c) for c in column)
    return column


_RENDERS: OrderedDict = OrderedDict()  # (group, padding, id(specs)) -> _Render, the most recent last
_RENDERS_MAX = 48  # figures x unit systems in use; each holds its specs, so an id is never reused while cached
_RENDERS_LOCK = threading.Lock()


def _render(specs, data, group: str, padding) -> _Render:
    """The template of a figure of layers ``specs`` (rendered with ``data`` the first time it is asked for)."""
    key = (group, padding, id(specs))
    with _RENDERS_LOCK:
        render = _RENDERS.get(key)
        if render is None or render.specs is not specs:
            render = _RENDERS[key] = _Render(specs, data, group, padding)
        _RENDERS.move_to_end(key)
        while len(_RENDERS) > _RENDERS_MAX:
            _RENDERS.popitem(last=False)
    return render


class LiveFigure:
    """A Bokeh figure over a list of layers, updated in place.

    The figure is a copy of a template rendered once per process by
    HoloViews (:class:`_Render`), with the given data written in; it shares
    no model with any other :class:`LiveFigure`.

    Parameters
    ----------
    specs : list of Layer or hv.Element
        The figure's layers (an element is a static layer).
    data : sequence
        The data of each layer.
    group : str
        HoloViews group of the overlay (it carries the figure's title and options).
    padding : tuple of float or None
        Range padding (x, y) of axes fitted to the data in the browser, as a
        fraction of the data's span; None keeps the overlay's own fixed ranges.
    """

    def __init__(self, specs, data, group: str, padding: tuple[float, float] | None = (0.0, 0.1)):
        self.group, self.padding = group, padding
        self._build(specs, data)

    def _build(self, specs, data) -> None:
        render = _render(specs, data, self.group, self.padding)
        self.figure, models = render.copy()
        self._render, self._specs, self._labels = render, specs, render.labels
        self._sources = [models[source] for source, _ in render.layers]
        self._glyphs = [models[glyph] for _, glyph in render.layers]
        self._legend = {i: models[item] for i, item in render.legend.items()}
        self._data = list(render.data)
        self.update(specs, data)

    def _show_in_legend(self, i, data) -> None:
        item = self._legend.get(i)
        if item is not None:
            visible = not _is_empty(data)
            if item.visible != visible:
                item.visible = visible

    def update(self, specs, data) -> bool:
        """Show ``data``: replace the data of the layers that changed.

        Returns
        -------
        bool
            True if the figure had to be rebuilt (``specs`` with other axis
            labels, e.g. another unit system): :attr:`figure` is then a new
            Bokeh model to show.
        """
        if specs is not self._specs and _labels(specs) != self._labels:
            self._build(specs, data)
            return True
        self._specs = specs
        for i, new in enumerate(data):
            if new is self._data[i]:
                continue
            self._write(i, specs[i], new)
            self._show_in_legend(i, new)
            self._data[i] = new
        return False

    def _write(self, i, spec, new) -> None:
        glyph = {}
        if isinstance(new, Styled):
            new, glyph = new.data, new.glyph
        data = _columns(spec, new)
        if data is None:
            sub = self._render.subplots[i]  # the template's plot computes an image's columns
            data, _, _ = sub.get_data(spec.element(new), sub.current_ranges or {}, sub.style[sub.cyclic_index])
        if glyph:
            self._glyphs[i].update(**glyph)
        self._sources[i].data = data

    def sources(self) -> list:
        """The ``ColumnDataSource`` of each layer, in order."""
        return list(self._sources)

    def glyphs(self) -> list:
        """The glyph of each layer, in order."""
        return list(self._glyphs)


class WhenShown(ReactiveHTML):
    """A sentinel that reports, once, when the browser scrolls it near the visible part of the page.

    Put it where something costly to build goes (a figure), as tall as that
    thing, so that what is below keeps its place; watch :attr:`shown` and put
    the thing in its place when it becomes True. The browser's
    ``IntersectionObserver`` sets it as soon as the sentinel comes within
    :attr:`ahead` pixels below the view (so the figure is ready when the
    reader gets there), or is in view when the page opens. A sentinel in a
    hidden layout is not in view: it reports when its layout is shown and
    scrolled to. Without a browser (a notebook's kernel alone, a test driving
    the Python objects) it never reports: build eagerly there.
    """

    shown = param.Boolean(default=False, doc="The sentinel has come near the view (set by the browser, once).")
    ahead = param.Integer(default=600, bounds=(0, 10_000), doc="How far below the view it already counts [px].")

    _template = '<div id="sentinel" class="when-shown" style="height: 1px; width: 100%;"></div>'
    _scripts = {"render": """
        if (data.shown) { return; }
        const seen = new IntersectionObserver((entries) => {
          if (entries.some((e) => e.isIntersecting)) { data.shown = true; seen.disconnect(); }
        }, {rootMargin: `0px 0px ${data.ahead}px 0px`});
        seen.observe(sentinel);
    """}

    def __init__(self, **params):
        params.setdefault("margin", 0)
        params.setdefault("height", 1)
        params.setdefault("sizing_mode", "stretch_width")
        params["css_classes"] = [*params.get("css_classes", []), "when-shown"]  # (app.serving.scroll_through)
        super().__init__(**params)
