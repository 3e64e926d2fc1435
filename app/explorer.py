"""The Panel view of the explorer: one :class:`Explorer` per browser session.

:class:`Explorer` is a ``pn.viewable.Viewer`` over an :class:`~app.state.ExplorerState`: it holds the
session's parameters (the run shown, the contact, the player's frame, the live slider values) and the input
widgets; the other jobs are modules of their own, mixed in here:

* :mod:`app.scheduling`: solving the inputs in the worker pool, stale answers dropped;
* :mod:`app.player`: the cycle player;
* :mod:`app.figures`: the figures' lifecycle (drawn when shown, updated in place);
* :mod:`app.cards`: the verdict badge, the cards and the warnings;
* :mod:`app.mapview`: the numerical map;
* :mod:`app.downloads`: CSV and JSON of the run (written by :mod:`core.api.export`);
* :mod:`app.layout`: the page.

Analytical layers follow the sliders while they move (bound to the widgets' ``value``); the solver runs when
a slider is released (the state is linked to ``value_throttled``).
"""

from __future__ import annotations

import functools

import panel as pn
import param

import core

from . import panes, plots, runs
from .cards import CardsMixin
from .downloads import DownloadsMixin
from .engineer import EngineerInputs
from .figures import FIGURE_INPUTS, FiguresMixin
from .layout import LayoutMixin
from .mapview import MapMixin
from .player import PlayerMixin
from .runs import Generation
from .scheduling import SolveMixin
from .state import PRESET_NOTES, PRESETS, URL_PARAMETERS, ExplorerState, parse_query, typed_error
from .widgets import FloatSlider, IntSlider

__all__ = ["Explorer"]

_SOLVER_INPUTS = [p for p in URL_PARAMETERS if p != "units"]
#: The number format of the ft and w sliders (numbro): at least two decimals, up to six.
SLIDER_FORMAT = "0.00[0000]"


class Explorer(LayoutMixin, CardsMixin, FiguresMixin, DownloadsMixin, MapMixin, PlayerMixin, SolveMixin,
               pn.viewable.Viewer):
    """The shakedown explorer over an :class:`ExplorerState` (one per browser session)."""

    result = param.ClassSelector(class_=(core.CycleResult, core.PointContactResult), default=None, allow_None=True,
                                 doc="The solver run of the current inputs (None until solved, or if they are invalid).")
    contact = param.ClassSelector(class_=core.Contact, default=None, allow_None=True,
                                  doc="The current contact (None if the inputs are invalid).")
    geometry = param.ClassSelector(class_=core.Contact, default=None, allow_None=True,
                                   doc="The current contact at ft = w = 0: what the plot units depend on.")
    plot_units = param.ClassSelector(class_=plots.Units, default=plots.Units("normalised"),
                                     doc="Scales and labels of the figures.")
    frame = param.Integer(default=0, bounds=(0, None), doc="Step of the run shown by the cycle player.")
    ft_live = param.Number(default=0.3, doc="ft while its slider moves (the analytical layers follow it) [-].")
    w_live = param.Number(default=0.5, doc="w while its slider moves (the analytical layers follow it) [-].")
    solving = param.Boolean(default=False, doc="A solve for the current inputs has run for longer than "
                                                 "app.cards.SPINNER_DELAY_MS.")
    pending = param.Boolean(default=False, doc="The run shown is not the current inputs' run (a solve is on its way).")
    error = param.String(default="", doc="Why the current inputs cannot be solved, if they cannot.")
    notices = param.List(default=[], doc="Messages about rejected URL parameters.")
    typed_errors = param.Dict(default={}, doc="Numbers typed into the geometry's boxes that are not valid, by input "
                                              "name: why (in the input's units); the state keeps its last valid value.")
    map_table = param.DataFrame(default=None, allow_None=True,
                                doc="Sweep table shown on the shakedown map (the shipped map until one is computed).")
    map_label = param.String(default="shipped map", doc="Where the numerical map comes from.")
    map_running = param.Boolean(default=False, doc="A numerical map is being computed.")
    map_progress = param.Integer(default=0, bounds=(0, 100), doc="Progress of the map computation [%].")
    map_status = param.String(default="", doc="Outcome of the last map computation.")
    coupled_limit = param.Parameter(default=None, doc="The coupled limit curve of the current contact "
                                    "(core.CoupledLimitCurve, as far as it is computed), None for an uncoupled one.")
    coupled_status = param.String(default="", doc="Where the coupled limit curve is: computing, done, or why not.")
    pinned = param.Parameter(default=(), doc="Pinned runs overlaid on the figures (app.compare.Pins).")
    grid_error = param.Parameter(default=None, doc="The estimated discretisation error of the point-contact run "
                                                   "shown (core.ConvergedIncrement), once estimated.")

    def __init__(self, state: ExplorerState | None = None, query: str | None = None, **params):
        super().__init__(**params)
        self.state = state if state is not None else ExplorerState()
        if query:
            self.apply_query(query)
        self._generation = Generation()
        self._build_widgets()
        self._player_sync = False
        self.result_token = 0  # the request whose result is shown
        self._doc = pn.state.curdoc  # the session's document (None when headless)
        self._loop = runs.session_loop()  # its event loop: the only thread that touches the document
        self.param.update(ft_live=self.state.ft, w_live=self.state.w)
        self.ft_slider.param.watch(self._live_changed, "value")
        self.w_slider.param.watch(self._live_changed, "value")
        self.state.param.watch(self._inputs_changed, _SOLVER_INPUTS)
        self.state.param.watch(self._update_units, "units")
        self.mu_slider.param.watch(self._update_units, "value")
        self.param.watch(self._update_units, "geometry")
        # the status line follows the spinner and goes when the run (or an error) arrives: a solve over before the
        # spinner's delay never sets solving, and the compiling line stayed up to its next tick (a second)
        self.param.watch(self._show_spinner, ["solving", "result", "error"])
        self._live = {}  # name -> app.live.LiveFigure, built with the layout (figures())
        self._panes: dict[str, pn.pane.Bokeh] = {}
        self.sentinels = {}  # name -> app.live.WhenShown, the served page's: a figure is drawn when shown
        self._when_shown = False
        self._cells: dict[str, pn.Column] = {}  # the served page's figures with their captions, once drawn
        self._places: dict[str, pn.Column] = {}  # the served page's places of the figures in their grids
        self._captions: dict[str, pn.pane.HTML] = {}  # each cell's caption (hidden on the first screen)
        self.param.watch(self._redraw, list(FIGURE_INPUTS.values()))
        self._update_contact()
        served = self._doc is not None and self._doc.session_context is not None
        if served and (self.state.point or not runs.warmed(self._solver_group())):
            # a point contact's run takes seconds, and the first run of a fresh install waits for the server's
            # warm-up to compile the solver (a minute or more): off the event loop once the page is shown
            # (updates sent before the browser has built the page could be lost); until then the badge says
            # 'solving' and, while the solver compiles, the status line says so with the seconds spent (the
            # sliders, the sketch, the exact limits and the closure curves need no solver: the page works at once)
            self.pending = True
            pn.state.onload(self._request_solve)
            if self._compiling_line() is not None:
                self._follow_compiling()
        else:
            self.solve_now()  # the first run is in the page as it is first sent: no update before the browser connects
        self._build_map()

    # ------------------------------------------------------------------ inputs
    def _build_widgets(self):
        s = self.state
        slider = dict(sizing_mode="stretch_width", throttled=True)
        # two decimals, and up to six when the value has them (a link's ft = 0.206 must not read 0.21, across the
        # limit ft_lim = 0.2084 of w = 0.678); the inputs are held to 1e-6 (ExplorerState.__setattr__)
        self.ft_slider = FloatSlider.from_param(s.param.ft, format=SLIDER_FORMAT, **slider)
        self.w_slider = FloatSlider.from_param(s.param.w, format=SLIDER_FORMAT, **slider)
        self.mu_slider = FloatSlider.from_param(s.param.mu, **slider)
        # outlined: the selected unit is the filled button (solid buttons all had the same blue background)
        self.units_toggle = pn.widgets.RadioButtonGroup.from_param(s.param.units, color="primary",
                                                                   button_style="outline",
                                                                   sizing_mode="stretch_width",
                                                                   css_classes=["units-toggle"])
        self.preset = pn.widgets.Select(label="Preset", options=["(custom)", *PRESETS], value="(custom)",
                                        sizing_mode="stretch_width")
        self.preset.param.watch(self._apply_preset, "value")
        self.preset_note = panes.Markdown("", css_classes=["preset-note"], visible=False, margin=(0, 10),
                                            styles={"font-size": "14px"})
        s.param.watch(self._preset_edited, list(URL_PARAMETERS))
        geometry = ["R", "L", "Fn", "E2", "nu2"]
        self.geometry_inputs = [self._typed_input(p) for p in geometry]
        self.materials_select = pn.widgets.Select.from_param(s.param.materials, sizing_mode="stretch_width")
        self.rigid_box = pn.widgets.Checkbox.from_param(s.param.rigid)
        self.cylinder_inputs = [self._typed_input(p) for p in ("E1", "nu1")]
        for w in self.cylinder_inputs:
            w.disabled = s.rigid
        s.param.watch(lambda e: [setattr(w, "disabled", e.new) for w in self.cylinder_inputs], "rigid")
        self.solver_inputs = [
            IntSlider.from_param(s.param.periods, **slider),
            IntSlider.from_param(s.param.resolution, **slider),
            pn.widgets.RadioButtonGroup.from_param(s.param.kernel, sizing_mode="stretch_width"),
            pn.widgets.RadioButtonGroup.from_param(s.param.schedule, sizing_mode="stretch_width"),
            pn.widgets.RadioButtonGroup.from_param(s.param.loading, sizing_mode="stretch_width"),
            FloatSlider.from_param(s.param.amplitude, visible=s.param.loading.rx() != "rocking", **slider),
            FloatSlider.from_param(s.param.phase, visible=s.param.loading.rx() == "normal", **slider),
        ]
        # the solve's status line (while the server's warm-up compiles the solver): always in the page and empty
        # when there is nothing to say, so that it changes only its text. Toggling a model's ``visible`` (or a
        # LoadingSpinner's value, which sets its CSS classes) made the browser recompute the whole page's layout,
        # six times a solve (0.3 to 2.4 s each on a loaded machine); the running solve's spinner is in the badge
        # (app.cards.SOLVING_BADGE), a CSS animation that shows after SPINNER_DELAY_MS
        self.status = panes.HTML("", css_classes=["solve-status"], margin=0)
        self._build_player()
        self._build_downloads()

    def _typed_input(self, name: str) -> pn.widgets.FloatInput:
        """A number box for input ``name`` that takes any number typed: a valid one goes to the state, another
        one is named in the badge (INVALID INPUT, in the input's units, the figures cleared) until it is
        corrected. (A box bounded by the slider range of the input silently put back the old value.)"""
        p = self.state.param[name]
        box = pn.widgets.FloatInput(label=p.label, value=getattr(self.state, name), start=None, end=None,
                                    step=p.step, description=p.doc, sizing_mode="stretch_width")

        def typed(event):
            if event.new is None:
                return
            value, had = float(event.new), name in self.typed_errors
            try:
                p._validate(value)
            except ValueError:
                self.typed_errors = {**self.typed_errors, name: typed_error(p, value)}
            else:
                self.typed_errors = {k: v for k, v in self.typed_errors.items() if k != name}
                if getattr(self.state, name) != value:
                    setattr(self.state, name, value)  # the state's watchers solve the new inputs
                    return
                if not had:
                    return
            with self._held():  # an error named or corrected, the state unchanged: the badge and the figures follow
                self._update_contact()
                self._request_solve()

        def held(event):  # the state changed (a preset, a link): the box shows it, and it is valid
            box.value = event.new
            if name in self.typed_errors:
                self.typed_errors = {k: v for k, v in self.typed_errors.items() if k != name}

        box.param.watch(typed, "value")
        self.state.param.watch(held, name)
        return box

    def _live_changed(self, *_):
        with self._held():
            self.param.update(ft_live=self.ft_slider.value, w_live=self.w_slider.value)

    def _apply_preset(self, event):
        if event.new in PRESETS:
            self._applying_preset = True
            try:
                self.state.apply_preset(event.new)
            finally:
                self._applying_preset = False
        self.preset_note.param.update(object=PRESET_NOTES.get(event.new, ""), visible=event.new in PRESET_NOTES)

    def _preset_edited(self, *events):
        """An input changed: the preset box says "(custom)" once the inputs are no longer the preset's."""
        name = self.preset.value
        if getattr(self, "_applying_preset", False) or name not in PRESETS:
            return
        if any(getattr(self.state, k) != v for k, v in PRESETS[name].items()):
            self.preset.value = "(custom)"

    def apply_query(self, query: str) -> None:
        """Apply URL query parameters; rejected ones are listed in :attr:`notices` and not applied."""
        updates, errors, ignored = parse_query(query)
        if ignored:
            errors = errors + [f"unknown URL parameter(s) ignored: {', '.join(sorted(ignored)[:10])}"]
        self.notices = errors
        if updates:
            self.state.param.update(**updates)


    @functools.cached_property
    def engineer(self) -> EngineerInputs:
        """The loads in physical units (Ft, W or the rocking angle) and the cycles the creep is extrapolated to."""
        return EngineerInputs(self)

