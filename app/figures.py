"""Figure lifecycle: the explorer's figures rendered once, drawn when shown, updated in place.

:class:`FiguresMixin` renders each figure of :data:`app.plots.FIGURES` the current body shows as a
:class:`~app.live.LiveFigure` when the browser first scrolls near its place (a :class:`~app.live.WhenShown`
sentinel keeps the place until then), and pushes only the layers whose inputs changed (:meth:`_redraw`).
"""

from __future__ import annotations

import contextlib
import html
import os

import panel as pn

import core

from . import bodies, plots, point_view
from .live import LiveFigure, WhenShown
from .styles import CSS

__all__ = ["FiguresMixin", "FIGURE_INPUTS", "KEY_FIGURES", "KEY_HEIGHT", "ORDER", "key_figures"]

#: The figures of the first screen, by kind of body and loading history. Under the paper's rocking: the pressure
#: with μ p_min, the traction with the stick and slip zones, the displacement per period (a point contact: the cut
#: along y = 0, which shows the pressure bound μ p, μ p_min, the traction and the zones; its displacement and its
#: increment per period). Under an oscillating load (the normal force, the tangential one) the fretting loop is
#: beside the displacement, in place of the figure that tells least there (the pressure, the increment per
#: period), which goes below. The one declaration of the first screen: each figure is one name in a row.
KEY_FIGURES = {
    "line": {"rocking": ("pressure", "traction", "displacement"),
             "normal": ("traction", "displacement", "loop"),
             "tangential": ("traction", "displacement", "loop")},
    "point": {"rocking": ("point_cut", "point_displacement", "point_increments"),
              "normal": ("point_cut", "point_displacement", "loop"),
              "tangential": ("point_cut", "point_displacement", "loop")},
}
#: Height of a first-screen figure [px] (set by its options in :mod:`app.plots`).
KEY_HEIGHT = plots.KEY_HEIGHT
#: Every figure in the order of the page: the first screen shows those of :data:`KEY_FIGURES` for the body and
#: the loading, the grid below the others the body shows, in this order.
ORDER = ("pressure", "traction", "point_cut", "displacement", "point_displacement", "loop", "point_increments",
         "sketch", "states", "increments", "point_pressure", "point_traction", "point_zones", "map")


def key_figures(body: str, loading: str = "rocking") -> tuple[str, ...]:
    """The first-screen figures of ``body`` (any body the app offers) under the loading history ``loading``.

    Parameters
    ----------
    body : str
        A body the app offers (:data:`app.bodies.BODIES`).
    loading : {"rocking", "normal", "tangential"}
        The loading history (:attr:`app.state.ExplorerState.loading`).

    Returns
    -------
    tuple of str
        Names of :data:`app.plots.FIGURES`, left to right.

    Raises
    ------
    ValueError
        If ``loading`` is not one of the histories of :data:`KEY_FIGURES`.
    """
    by_loading = KEY_FIGURES[bodies.kind(body)]
    if loading not in by_loading:
        raise ValueError(f"loading must be one of {sorted(by_loading)}, got {loading!r:.40}")
    return by_loading[loading]


def figure_height(name: str) -> int:
    """The height of figure ``name`` [px] (its options in :data:`app.plots.FIGURES`)."""
    return int(plots.FIGURES[name]["opts"].get("height", plots.HEIGHT))

#: The explorer parameter behind each input of the figures (:class:`app.plots.Inputs`).
FIGURE_INPUTS = {"ft": "ft_live", "w": "w_live", "units": "plot_units", "result": "result", "frame": "frame",
                  "table": "map_table", "pinned": "pinned", "coupled": "coupled_limit"}
#: Range padding (x, y) of the axes that follow the data; None: the figure's own fixed ranges.
_CELL_STYLE = {"flex": "1 1 560px", "min-width": "min(300px, 100%)"}
#: A first-screen figure's cell: three in a row from 3 x 220 px (a 1024 px screen beside the sidebar), two (and
#: one) in a row below.
_KEY_STYLE = {"flex": "1 1 220px", "min-width": "min(220px, 100%)"}
#: The contact maps: no padding (a padding of 10 % on y only made their equal axis scales unequal by 10 %).
#: The loop: padded on x too, so that a loop's ends (under a constant load a short segment: the last period's walk)
#: are not drawn on the frame's edge.
_PADDING = {"states": (0.0, 0.0), "increments": (0.05, 0.1), "loop": (0.05, 0.1), "map": None,
            **dict.fromkeys(("point_pressure", "point_traction", "point_zones"), (0.0, 0.0))}


class FiguresMixin:
    """The explorer's figures (methods of :class:`app.explorer.Explorer`)."""

    def _compute_units(self, result=None) -> plots.Units:
        result = self.result if result is None else result
        g = self.geometry
        geometry = None if g is None else g.replace(mu=self.mu_slider.value)
        kernel = getattr(result, "kernel", self.state.kernel)
        return plots.make_units(self.state.units, geometry, kernel, getattr(result, "u0", None),
                                point=isinstance(result, core.PointContactResult))

    def _update_units(self, *_):
        units = self._compute_units()
        if units != self.plot_units:
            with self._held():
                self.plot_units = units

    def _inputs(self) -> plots.Inputs:
        return plots.Inputs(**{field: getattr(self, name) for field, name in FIGURE_INPUTS.items()})

    def _redraw(self, *events):
        """Push the layers that changed into the figures that depend on the changed inputs."""
        changed = {e.name for e in events}
        inputs, rebuilt = self._inputs(), []
        with self._held():
            for name, live in self._live.items():
                if changed.intersection(FIGURE_INPUTS[i] for i in plots.FIGURES[name]["inputs"]):
                    if live.update(plots.specs(name, inputs.units), plots.layers(name, inputs)):
                        rebuilt.append(name)
            if rebuilt:  # new axis labels (units): new figures, one model-graph recomputation for all
                doc = self._doc
                with (doc.models.freeze() if doc is not None else contextlib.nullcontext()):
                    for name in rebuilt:
                        self._panes[name].object = self._live[name].figure

    def figures(self, when_shown: bool = False) -> dict[str, pn.pane.Bokeh]:
        """The figures: Bokeh figures rendered once, then updated in place (:class:`~app.live.LiveFigure`).

        Only the figures of the current body are drawn (the other body's are
        hidden; they are drawn when the body changes). With ``when_shown``
        (the served page, :meth:`explorer_tab`) only the first screen's figures
        (:func:`key_figures`) are drawn here, with the page; each of the others
        once the browser scrolls near its place (:attr:`sentinels`), so that a
        visitor who never scrolls down costs the server only the figures at the
        top, and the page comes sooner. Without it (notebooks,
        tests of the Python objects) they are drawn here.
        """
        if os.environ.get("SHAKEDOWN_FIGURES") == "dynamicmap":  # the idiomatic path, measured by benchmarks/app.py
            self._live, self.sentinels, self._when_shown = {}, {}, False
            self._panes = {name: pn.pane.HoloViews(plots.dynamic(name, self._inputs, **{
                i: self.param[FIGURE_INPUTS[i]] for i in plots.FIGURES[name]["inputs"]}), sizing_mode="stretch_width")
                for name in plots.FIGURES}
            return self._panes
        self._live = {}
        self._panes = {} if when_shown else {name: pn.pane.Bokeh(None, sizing_mode="stretch_width")
                                             for name in plots.FIGURES}  # (served: made when drawn)
        self.sentinels, self._when_shown = {}, when_shown  # (sentinels: made with the grid, see _slots)
        # the first screen's figures are drawn with the page (they are in view), the others when shown
        self._draw_figures(self._figures_of(self.state.body) if not when_shown else self._key_names())
        self.state.param.watch(lambda *e: self._show_figures(self._figures_of(self.state.body)), ["body", "loading"])
        return self._panes

    @staticmethod
    def _figures_of(body: str) -> list[str]:
        return [name for name in plots.FIGURES if point_view.shown(name, body)]

    def _key_names(self) -> tuple[str, ...]:
        """The first-screen figures of the current body and loading (:func:`key_figures`)."""
        return key_figures(self.state.body, self.state.loading)

    def _draw_figures(self, names) -> None:
        """Render the figures ``names`` not rendered yet and show them in their panes."""
        inputs = self._inputs()
        for name in names:
            if name not in self._live:
                self._live[name] = LiveFigure(plots.specs(name, inputs.units), plots.layers(name, inputs),
                                              plots.group(name), padding=_PADDING.get(name, (0.0, 0.1)))
                if name in self._panes:
                    self._panes[name].object = self._live[name].figure
                else:
                    self._panes[name] = pn.pane.Bokeh(self._live[name].figure, sizing_mode="stretch_width")

    def _show_figures(self, names) -> None:
        """Draw the figures ``names`` that the current body shows and, on the served page, that are on the first
        screen or that the browser has scrolled near; put each in its place in the first screen's grid or in the
        grid below, as the body and the loading have them (one recomputation of the document's model graph for
        all)."""
        body, key = self.state.body, self._key_names()
        names = [n for n in names if point_view.shown(n, body)
                 and (not self._when_shown or n in key or (n in self.sentinels and self.sentinels[n].shown))]
        doc = self._doc
        with (doc.models.freeze() if doc is not None else contextlib.nullcontext()):
            self._draw_figures(names)
            for first, grid in ((True, getattr(self, "_key_grid", None)), (False, getattr(self, "_grid", None))):
                if grid is not None:
                    slots = self._slots(first)
                    if slots != grid.objects:
                        grid.objects = slots

    def _grid_names(self, key: bool) -> list[str]:
        """The figures of the current body in the first-screen grid (``key``: those of :func:`key_figures`, in
        their order) or in the grid below (the others, in the order of :data:`ORDER`)."""
        body, first = self.state.body, self._key_names()
        names = first if key else [n for n in ORDER if n not in first]
        return [n for n in names if point_view.shown(n, body)]

    def _slots(self, key: bool = False) -> list:
        """What a figure grid holds: for each of its figures of the current body, its place (:meth:`_place`),
        holding its cell once drawn, else the sentinel that keeps its place (the other body's figures are not in
        the page). A figure keeps its place and its cell when the loading moves it between the first screen and
        the grid below; its place's size and its caption follow (a first-screen figure's caption is in the list
        under the first screen, :meth:`key_captions`).

        A figure drawn later replaces the sentinel inside its place, not in the grid: replacing the grid's
        children re-rendered all of them, the page was shorter for a moment and the browser's scroll position
        jumped back to the top of the grid each time a figure further down was drawn."""
        places = []
        for name in self._grid_names(key):
            drawn = name in self._live or (not self._when_shown and name in self._panes)
            content = self._cell(name) if drawn else self._sentinel(name)
            place = self._place(name)
            styles = {**(_KEY_STYLE if key else _CELL_STYLE),
                      "min-height": f"{figure_height(name) + (0 if key else 40)}px"}
            if place.styles != styles:
                place.styles = styles
            if name in self._captions and self._captions[name].visible == key:
                self._captions[name].visible = not key
            if place.objects != [content]:
                place.objects = [content]
            places.append(place)
        return places

    def _place(self, name: str) -> pn.Column:
        """The place of figure ``name`` in its grid (made once): a column as tall as the figure will be, that holds
        the figure's sentinel, then the figure's cell (its size is set by :meth:`_slots`)."""
        if name not in self._places:
            self._places[name] = pn.Column(sizing_mode="stretch_width", margin=0, css_classes=[f"place-{name}"])
        return self._places[name]

    def _sentinel(self, name: str) -> WhenShown:
        """The sentinel that keeps figure ``name``'s place until the browser scrolls near it (made once)."""
        if name not in self.sentinels:
            self.sentinels[name] = WhenShown(height=figure_height(name) + 40,
                                             css_classes=[f"figure-{name}"])  # (in its place: _place)
            self.sentinels[name].param.watch(lambda e: self._show_figures([name]), "shown")
        return self.sentinels[name]

    def _cell(self, name: str) -> pn.Column:
        """Figure ``name`` with its caption (and, for the map, its controls), made once and shown while the body
        shows it; the caption is hidden while the figure is on the first screen (:meth:`_slots`), so that the
        first screen's figures start on the same line and the next row starts right below."""
        if name not in self._cells:
            caption = pn.pane.HTML(f"<div class='caption'>{html.escape(plots.FIGURES[name]['caption'])}</div>",
                                   stylesheets=[CSS], sizing_mode="stretch_width", margin=0,
                                   visible=name not in self._key_names())
            self._captions[name] = caption
            extra = [self.map_controls()] if name == "map" else []
            self._cells[name] = pn.Column(self._panes[name], caption, *extra, sizing_mode="stretch_width",
                                          visible=pn.bind(point_view.shown, name, self.state.param.body))
        return self._cells[name]

    @staticmethod
    def _key_captions_html(body: str, loading: str = "rocking") -> str:
        items = "".join(f"<li><b>{html.escape(plots.FIGURES[n]['opts']['title'])}</b>: "
                        f"{html.escape(plots.FIGURES[n]['caption'].removeprefix('What you see: '))}</li>"
                        for n in key_figures(body, loading))
        return f"<div class='caption'><b>What you see</b><ul class='key-captions'>{items}</ul></div>"

    def key_captions(self) -> pn.viewable.Viewable:
        """The first-screen figures' captions, as a list under them (they follow the body and the loading)."""
        return pn.pane.HTML(pn.bind(self._key_captions_html, self.state.param.body, self.state.param.loading),
                            stylesheets=[CSS], sizing_mode="stretch_width", margin=0, css_classes=["key-captions"])
