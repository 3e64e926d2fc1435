"""The Panel view of the explorer: widgets, live figures, summary cards, downloads.

:class:`Explorer` is a ``pn.viewable.Viewer`` over an :class:`~app.state.ExplorerState`.
Analytical layers follow the sliders while they move (bound to the widgets'
``value``); the solver runs when a slider is released (the state is linked to
``value_throttled``), in a bounded worker pool, with a loading indicator; a
result that arrives for stale inputs is dropped. The figures are rendered once
and updated in place (:class:`~app.live.LiveFigure`): a change sends the browser
only the arrays of the layers that depend on it, in one held document patch.
"""

from __future__ import annotations

import contextlib
import functools
import html
import io
import math
import os
import re
import threading
from pathlib import Path
from typing import ClassVar

import numpy as np
import panel as pn
import param
from panel.io.state import set_curdoc
from panel.models.katex import KaTeX as KaTeXModel

import core
from core.export import to_csv, to_json

from . import panes, plots, point_view
from .point_view import _count, _fmt
from . import runs
from . import slides
from .compare import Pins
from .engineer import EngineerInputs
from .live import LiveFigure, WhenShown
from .paper_figures import paper_figures_tab
from .runs import RESULTS, Generation, run_key, solve, submit
from .state import PRESET_NOTES, PRESETS, URL_PARAMETERS, ExplorerState, parse_query

__all__ = ["Explorer"]

_ABOUT = Path(__file__).with_name("about.md")
_ASSETS = Path(__file__).with_name("assets")
_SOLVER_INPUTS = [p for p in URL_PARAMETERS if p != "units"]
#: A solve shows the loading indicator only after this long [ms].
_SPINNER_DELAY_MS = 150
_CSS = """
.regime-badge {display: inline-block; padding: 8px 20px; border-radius: 12px; color: white;
               font-size: 26px; font-weight: 700; letter-spacing: 0.04em;}
.regime-shakedown {background: #0072B2;} .regime-ratcheting {background: #D55E00;}
.regime-none, .regime-undetermined {background: #6b6b6b;}
.regime-note {font-size: 15px; color: #333; margin-top: 6px; line-height: 1.35;}
.cards {display: grid; grid-template-columns: repeat(auto-fill, minmax(235px, 1fr)); gap: 0 22px;
        font-size: 15px;}
.cards div {display: flex; justify-content: space-between; gap: 10px; border-bottom: 1px solid #eee;
            padding: 2px 0;}
.cards .k {color: #444;} .cards .v {font-weight: 600; text-align: right;}
.cards .pending {color: #6b6b6b; font-style: italic; font-weight: 400;}
.readout {font-size: 15px; color: #222;}
.caption {font-size: 14px; color: #333; margin: 0 10px 14px 10px;}
"""
#: When the model applies (one sentence, under the inputs).
_APPLIES = ("*When the model applies:* a long cylinder (L ≫ a) rocking without macroscopic sliding "
            "(Ft < μ Fn) on an elastic half-space, slowly (no inertia), with one constant friction coefficient, "
            "elastic bodies whose normal and tangential problems are uncoupled (Dundurs β ≈ 0).")
#: Document-level CSS (outside every shadow root). The math fonts are declared here because Chromium
#: ignores @font-face inside a shadow root, where Panel renders the equations; presentation mode
#: (sidebar folded, larger type) is a class on the document.
_PAGE_CSS = """
html.presenting {zoom: 1.25;}
html.presenting #sidebar {display: none !important;}
@media (max-width: 1100px) {  /* the full-size title pushed the busy indicator off a 1024 px screen */
  #header .title {font-size: 1.3em;}
}
@media (max-width: 700px) {
  #header .title {font-size: 1.05em; white-space: normal; line-height: 1.3em;}
  #header-items {display: none;}
  #content {flex-wrap: nowrap; flex-direction: column; overflow-y: auto !important;}
  #sidebar {max-width: 100% !important; width: 100% !important; height: auto; border-right: 0;}
  #main {flex: 1 0 auto; overflow: visible; padding: 6px;}
}
"""


def _renumber_periods(text: str) -> str:
    """A CSV of :func:`core.export.to_csv` with its ``period`` column numbered as the player and the increment
    plot number them (0 the loading, 1 the first rocking period; core counts from -1)."""
    lines = text.splitlines()
    k = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    col = lines[k].split(",").index("period")
    for i in range(k + 1, len(lines)):
        cells = lines[i].split(",")
        cells[col] = str(int(cells[col]) + 1)
        lines[i] = ",".join(cells)
    lines.insert(k, "# period: 0 = the loading, 1 = the first rocking period (as on the player)")
    return "\n".join(lines) + "\n"


@functools.lru_cache(maxsize=1)
def _shipped_map():
    """The numerical map shipped with core (read once, shared read-only by all sessions)."""
    return core.load_default_map()


#: KaTeX's layout rules, inside each equation's shadow root (Panel puts them only in the document's head, where
#: they do not reach the equations); the fonts they name are declared at document level (:class:`MathFonts`).
_KATEX_CSS = [css for css in getattr(KaTeXModel, "__css__", []) if "katex" in css]


class MathFonts:
    """The KaTeX fonts shipped in ``app/assets/katex`` (MIT licence), served by Panel's component-resource
    route (``/components/app.explorer/MathFonts/__css__/<file>``: only the files listed here are served)."""

    __css__: ClassVar[list[str]] = sorted(str(p.relative_to(_ASSETS.parent)) for p in (_ASSETS / "katex").iterdir()
                                          if p.suffix in (".css", ".woff2"))
    #: The stylesheet, relative to the page.
    url = "components/app.explorer/MathFonts/__css__/assets/katex/fonts.css"


#: Declares the math fonts last in the document, and labels every slider handle and unnamed button with an accessible name (Bokeh gives the handles none), in
#: every shadow root, now and when tabs and cards render later.
_A11Y_JS = """
function label(root) {
  for (const el of root.querySelectorAll('*')) {
    if (el.shadowRoot) label(el.shadowRoot);
  }
  const title = root.querySelector('.bk-slider-title');
  for (const h of root.querySelectorAll('.noUi-handle')) {
    if (!h.getAttribute('aria-label') && title) h.setAttribute('aria-label', title.textContent.split(':')[0].trim());
  }
  for (const i of root.querySelectorAll('input')) {  // a checkbox's text is a sibling, not its <label>
    if (i.getAttribute('aria-label') || (i.labels && i.labels.length)) continue;
    const text = (i.nextElementSibling || i.parentNode.querySelector('span, label') || {}).textContent;
    if (text && text.trim()) i.setAttribute('aria-label', text.trim());
  }
  for (const b of root.querySelectorAll('button')) {
    if (b.getAttribute('aria-label') || b.textContent.trim()) continue;
    const spin = b.classList.contains('bk-spin-btn-up') ? 'Increase' : b.classList.contains('bk-spin-btn-down')
      ? 'Decrease' : null;
    const name = b.title || spin;
    if (name) b.setAttribute('aria-label', name);
  }
}
label(document);
// a phone: the figures' legends in one column (two do not fit in 390 px), and no toolbar (it does not fit);
// also for the figures drawn later (each is drawn when the page is scrolled to it)
function phone() {
  if (window.innerWidth > 700) return;
  for (const d of Bokeh.documents) for (const m of d.all_models) {
    if ('ncols' in m && 'items' in m && m.ncols !== 1) m.ncols = 1;
    if ('toolbar_location' in m && 'renderers' in m && m.toolbar_location !== null) m.toolbar_location = null;
  }
}
phone();
if (!window._shakedownPhone) {
  window._shakedownPhone = true;
  for (const d of Bokeh.documents) d.on_change(() => setTimeout(phone, 0));
}
// the math fonts: Panel's KaTeX stylesheet in the document's head names font files that Panel does not ship
// (404s, then the system font); it is replaced by one that names the fonts shipped in app/assets/katex
for (const l of document.querySelectorAll('link[href*="katex.min.css"]')) l.remove();
if (!document.getElementById('shakedown-math-fonts')) {
  const link = document.createElement('link');
  link.id = 'shakedown-math-fonts'; link.rel = 'stylesheet'; link.href = '%s';
  document.head.appendChild(link);
}
// a phone starts with the inputs folded away (the menu button opens them above the results)
const sidebar = document.getElementById('sidebar');
if (sidebar && window.innerWidth <= 700 && !window._shakedownA11y) sidebar.classList.remove('show');
if (!window._shakedownA11y) { window._shakedownA11y = setInterval(() => label(document), 1000); }
"""


class _Prompt:
    """Mixin: the widget's value changes reach the explorer at once. Panel waits 50 ms for more changes
    by default (half the latency budget of a slider move); the figures' updates are cheap enough not to."""

    _priority_changes: ClassVar[list[str]] = ["value", "value_throttled"]


class FloatSlider(_Prompt, pn.widgets.FloatSlider):
    pass


class IntSlider(_Prompt, pn.widgets.IntSlider):
    pass


#: The explorer parameter behind each input of the figures (:class:`app.plots.Inputs`).
_FIGURE_INPUTS = {"ft": "ft_live", "w": "w_live", "units": "plot_units", "result": "result", "frame": "frame",
                  "table": "map_table", "pinned": "pinned"}
#: Range padding (x, y) of the axes that follow the data; None: the figure's own fixed ranges.
_CELL_STYLE = {"flex": "1 1 560px", "min-width": "min(300px, 100%)"}
_PADDING = {"states": (0.0, 0.0), "increments": (0.05, 0.1), "map": None}


@functools.lru_cache(maxsize=4096)
def _closure(ft: float, w: float) -> tuple[float, float, float]:
    """The cylinder's closed forms the cards show: c_sd (eq 30), ft_lim(w) and w_lim(ft) (eq 35). Memoised:
    the cards are redrawn several times per slider move, and w_lim is a root search (about 1 ms)."""
    return (float(core.shakedown_stick_halfwidth(ft, w)), float(core.ft_limit(w)), float(core.w_limit(ft)))


def _filled_when(holder: pn.layout.ListLike, ready, build) -> pn.layout.ListLike:
    """``holder``, empty until the reactive boolean ``ready`` first holds, then filled with ``build()``, once.

    What a visitor does not see is not built nor sent with the page (every
    component costs the server milliseconds per session).
    """
    def fill(value):
        if value and not holder.objects:
            holder.objects = list(build())

    fill(ready.rx.value)
    ready.rx.watch(fill)
    return holder


class Explorer(pn.viewable.Viewer):
    """The shakedown explorer over an :class:`ExplorerState` (one per browser session)."""

    result = param.ClassSelector(class_=(core.CycleResult, core.PointContactResult), default=None, allow_None=True,
                                 doc="The solver run of the current inputs (None until solved, or if they are invalid).")
    contact = param.ClassSelector(class_=(core.Contact, core.PointContact), default=None, allow_None=True,
                                  doc="The current contact (None if the inputs are invalid).")
    geometry = param.ClassSelector(class_=(core.Contact, core.PointContact), default=None, allow_None=True,
                                   doc="The current contact at ft = w = 0: what the plot units depend on.")
    plot_units = param.ClassSelector(class_=plots.Units, default=plots.Units("normalised"),
                                     doc="Scales and labels of the figures.")
    frame = param.Integer(default=0, bounds=(0, None), doc="Step of the run shown by the cycle player.")
    ft_live = param.Number(default=0.3, doc="ft while its slider moves (the analytical layers follow it) [-].")
    w_live = param.Number(default=0.5, doc="w while its slider moves (the analytical layers follow it) [-].")
    solving = param.Boolean(default=False, doc="A solve for the current inputs is running (spinner shown).")
    pending = param.Boolean(default=False, doc="The run shown is not the current inputs' run (a solve is on its way).")
    error = param.String(default="", doc="Why the current inputs cannot be solved, if they cannot.")
    notices = param.List(default=[], doc="Messages about rejected URL parameters.")
    map_table = param.DataFrame(default=None, allow_None=True,
                                doc="Sweep table shown on the shakedown map (the shipped map until one is computed).")
    map_label = param.String(default="shipped map", doc="Where the numerical map comes from.")
    map_running = param.Boolean(default=False, doc="A numerical map is being computed.")
    map_progress = param.Integer(default=0, bounds=(0, 100), doc="Progress of the map computation [%].")
    map_status = param.String(default="", doc="Outcome of the last map computation.")
    pinned = param.Parameter(default=(), doc="Pinned runs overlaid on the figures (app.compare.Pins).")

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
        self.param.update(ft_live=self.state.ft, w_live=self.state.w)
        self.ft_slider.param.watch(self._live_changed, "value")
        self.w_slider.param.watch(self._live_changed, "value")
        self.state.param.watch(self._inputs_changed, _SOLVER_INPUTS)
        self.state.param.watch(self._update_units, "units")
        self.mu_slider.param.watch(self._update_units, "value")
        self.param.watch(self._update_units, "geometry")
        self._live: dict[str, LiveFigure] = {}  # built with the layout (figures())
        self._panes: dict[str, pn.pane.Bokeh] = {}
        self.sentinels: dict[str, WhenShown] = {}  # the served page's: a figure is drawn when shown
        self._when_shown = False
        self._cells: dict[str, pn.Column] = {}  # the served page's figures with their captions, once drawn
        self.param.watch(self._redraw, list(_FIGURE_INPUTS.values()))
        self._update_contact()
        if self.state.point and self._doc is not None and self._doc.session_context is not None:
            # a point contact's run takes seconds: off the event loop once the page is shown (updates sent
            # before the browser has built the page could be lost); until then the badge says 'solving'
            self.pending = True
            pn.state.onload(self._request_solve)
        else:
            self.solve_now()  # the first run is in the page as it is first sent: no update before the browser connects
        self._map_cancel = threading.Event()
        self.map_scheduler = None  # core.sweep's default: a local process pool
        try:
            self.map_table = _shipped_map()
            self.map_label = "shipped 40×40, cylinder, plane kernel (drawn beside cylinder runs only)"
        except (OSError, ValueError) as e:  # pragma: no cover - a broken install
            self.map_status = f"shipped map not available: {e}"

    # ------------------------------------------------------------------ inputs
    def _build_widgets(self):
        s = self.state
        slider = dict(sizing_mode="stretch_width", throttled=True)
        self.ft_slider = FloatSlider.from_param(s.param.ft, **slider)
        self.w_slider = FloatSlider.from_param(s.param.w, **slider)
        self.mu_slider = FloatSlider.from_param(s.param.mu, **slider)
        self.units_toggle = pn.widgets.RadioButtonGroup.from_param(s.param.units, color="primary",
                                                                   sizing_mode="stretch_width")
        self.preset = pn.widgets.Select(label="Preset", options=["(custom)", *PRESETS], value="(custom)",
                                        sizing_mode="stretch_width")
        self.preset.param.watch(self._apply_preset, "value")
        self.preset_note = panes.Markdown("", css_classes=["preset-note"], visible=False, margin=(0, 10),
                                            styles={"font-size": "14px"})
        s.param.watch(self._preset_edited, list(URL_PARAMETERS))
        geometry = ["R", "L", "Fn", "E2", "nu2"]
        self.geometry_inputs = [pn.widgets.FloatInput.from_param(s.param[p], sizing_mode="stretch_width")
                                for p in geometry]
        self.rigid_box = pn.widgets.Checkbox.from_param(s.param.rigid)
        self.cylinder_inputs = [pn.widgets.FloatInput.from_param(s.param[p], sizing_mode="stretch_width")
                                for p in ("E1", "nu1")]
        for w in self.cylinder_inputs:
            w.disabled = s.rigid
        s.param.watch(lambda e: [setattr(w, "disabled", e.new) for w in self.cylinder_inputs], "rigid")
        self.solver_inputs = [
            IntSlider.from_param(s.param.periods, **slider),
            IntSlider.from_param(s.param.resolution, **slider),
            pn.widgets.RadioButtonGroup.from_param(s.param.kernel, sizing_mode="stretch_width"),
            pn.widgets.RadioButtonGroup.from_param(s.param.schedule, sizing_mode="stretch_width"),
            pn.widgets.RadioButtonGroup.from_param(s.param.loading, sizing_mode="stretch_width"),
            FloatSlider.from_param(s.param.amplitude, visible=s.param.loading.rx() == "normal", **slider),
            FloatSlider.from_param(s.param.phase, visible=s.param.loading.rx() == "normal", **slider),
        ]
        self.spinner = pn.indicators.LoadingSpinner(value=False, size=30, visible=False,
                                                    css_classes=["solve-spinner"])
        self.status = panes.HTML("", css_classes=["solve-status"], margin=(8, 4))
        # the cycle player: a period (0 = the loading, then 1, 2, ...), then the steps of that period
        grow = dict(width=250, margin=(5, 12))
        self.period_slider = IntSlider(label="Period (0 = loading)", start=0, end=1, value=1, **grow)
        self.step_slider = IntSlider(label="Step in the period", start=0, end=1, value=0, css_classes=["step-slider"],
                                     **grow)
        self.step_back = pn.widgets.Button(label="◀ Step", width=80, css_classes=["step-back"])
        self.play = pn.widgets.Toggle(label="▶ Play the period", width=150, css_classes=["play-period"])
        self.step_forward = pn.widgets.Button(label="Step ▶", width=80, css_classes=["step-forward"])
        self.speed = pn.widgets.Select(label="Speed", options={"slow (400 ms a step)": 400,
                                                              "normal (150 ms a step)": 150,
                                                              "fast (60 ms a step)": 60}, value=150, width=190)
        self.readout = panes.HTML("", css_classes=["readout"], sizing_mode="stretch_width", stylesheets=[_CSS])
        self._autoplay = None
        self.period_slider.param.watch(self._period_changed, "value")
        self.step_slider.param.watch(self._update_frame, "value")
        self.step_back.on_click(lambda e: self.step(-1))
        self.step_forward.on_click(lambda e: self.step(+1))
        self.play.param.watch(self._toggle_play, "value")
        self.speed.param.watch(self._toggle_play, "value")
        # downloads
        self.csv_table = pn.widgets.Select(label="CSV table", options={
            "per step (displacement)": "steps", "per period (increments)": "periods",
            "final traction and zones": "final"}, value="steps", sizing_mode="stretch_width")
        self.csv_download = pn.widgets.FileDownload(callback=self._csv, filename="shakedown_steps.csv",
                                                    label="Download CSV", color="success",
                                                    sizing_mode="stretch_width", css_classes=["csv-download"])
        self.json_download = pn.widgets.FileDownload(callback=self._json, filename="shakedown_run.json",
                                                     label="Download JSON", color="success",
                                                     sizing_mode="stretch_width", css_classes=["json-download"])
        self.csv_table.param.watch(lambda e: self._name_downloads(), "value")
        # the numerical map
        self.map_points = IntSlider(label="Map grid (points per axis)", start=3,
                                               end=runs.MAP_MAX_POINTS, value=min(12, runs.MAP_MAX_POINTS),
                                               sizing_mode="stretch_width")
        self.map_button = pn.widgets.Button(label="Compute the numerical map", color="primary",
                                            sizing_mode="stretch_width", css_classes=["map-compute"])
        self.map_cancel_button = pn.widgets.Button(label="Stop", color="warning", disabled=True, width=80)
        self.map_bar = pn.indicators.Progress(value=0, max=100, visible=False, sizing_mode="stretch_width")
        self.map_button.on_click(lambda e: self.compute_map())
        self.map_cancel_button.on_click(lambda e: self._map_cancel.set())

    @contextlib.contextmanager
    def _held(self):
        """Batch the updates of one change: apply them now, in this session's document, held, and send them
        to the browser together when the block ends. (Not a model freeze: leaving a freeze recomputes the
        document's whole model graph, 40 ms, even when only data changed.)"""
        doc = self._doc
        if doc is None or doc.session_context is None:
            yield
            return
        with set_curdoc(doc), pn.io.hold(doc):
            yield

    def _in_session(self, fn, *args, **kwargs) -> None:
        """Run ``fn`` in a Bokeh callback of this session (document locked), so its changes are sent at once.

        Work finished in a thread or a coroutine must come back this way: changes made outside a
        locked callback wait for the next one before they reach the browser. Thread-safe.
        """
        doc = self._doc
        if doc is None or doc.session_context is None:
            fn(*args, **kwargs)
        else:
            doc.add_next_tick_callback(functools.partial(fn, *args, **kwargs))

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

    # ------------------------------------------------------------------ solving
    def _inputs_changed(self, *events):
        with self._held():
            self._update_contact()
            self._request_solve()

    def _update_contact(self):
        try:
            contact = self.state.contact()
        except ValueError as e:
            self.param.update(contact=None, error=str(e))
            return
        geometry = contact.replace(ft=0.0, w=0.0)
        self.param.update(contact=contact, error="",
                          **({} if geometry == self.geometry else {"geometry": geometry}))

    def _request_solve(self):
        """Solve the current inputs (cached, else in the worker pool); drop the answer if the inputs moved on."""
        token = self._generation.next()
        if self.contact is None:
            self.param.update(solving=False, pending=False)
            return
        contact, options = self.contact, self.state.solver_options()
        cached = RESULTS.get(run_key(contact, options))
        doc = self._doc
        if cached is not None or doc is None or doc.session_context is None:
            # cached, or headless (tests, notebooks without a server): solve here
            self._finish(token, contact, options, cached)
            return

        self.pending = True  # every card and the badge say so at once: no old verdict beside new inputs

        def show_spinner():  # only if the solve is not over in a blink (saves two page updates)
            if self._generation.is_current(token) and self.result_token != token:
                self.solving = True

        doc.add_timeout_callback(show_spinner, _SPINNER_DELAY_MS)

        def stale():
            return not self._generation.is_current(token)

        def failed(message):
            if not stale():  # a stale run was cancelled on purpose: say nothing
                self.param.update(error=f"solver: {message}", solving=False, pending=False)

        def done(future):  # in the solver thread
            try:
                result = future.result()
            except (core.SolverError, core.SolveCancelled, ValueError) as e:
                self._in_session(failed, str(e))
            else:
                self._in_session(self._finish, token, contact, options, result)

        submit(contact, options, cancel=stale).add_done_callback(done)

    def _finish(self, token, contact, options, result=None):
        if result is None:
            try:
                result = solve(contact, options)
            except (core.SolverError, core.SolveCancelled, ValueError) as e:
                self.error = f"solver: {e}"
                return
        if not self._generation.is_current(token):
            return  # a newer request is pending: never overwrite it with this stale run
        self.result_token = token
        with self._held():
            self.play.value = False
            self._sync_player(result)  # the widgets follow the run (ranges too); the frame is set once, below
            self.param.update(result=result, frame=result.xc.size - 1, plot_units=self._compute_units(result),
                              solving=False, pending=False)
            self._name_downloads()

    def solve_now(self) -> core.CycleResult | None:
        """Solve the current inputs synchronously (headless use) and return the result."""
        self._update_contact()
        if self.contact is not None:
            self._finish(self._generation.next(), self.contact, self.state.solver_options())
        return self.result

    @param.depends("solving", watch=True)
    def _show_spinner(self):
        self.spinner.param.update(value=self.solving, visible=self.solving)
        self.status.object = "solving…" if self.solving else ""

    # ------------------------------------------------------------------ the cycle player
    @staticmethod
    def _steps_of(r: core.CycleResult, period: int) -> np.ndarray:
        """Steps of the period numbered ``period`` on the player: 0 the loading, k >= 1 the k-th rocking period
        (core numbers them from 0; the player, the increment plot and the readout from 1)."""
        return np.flatnonzero(r.period == period - 1)

    def _sync_player(self, r: core.CycleResult, period: int | None = None, step: int | None = None) -> None:
        """Set the ranges and values of the player's sliders for run ``r`` (default: its last step)."""
        period = r.periods if period is None else int(period)
        n = max(1, self._steps_of(r, period).size)
        step = n - 1 if step is None else int(np.clip(step, 0, n - 1))
        self._player_sync = True
        try:
            self.period_slider.param.update(start=0 if (r.period < 0).any() else 1, end=max(1, r.periods),
                                            value=period)
            self.step_slider.param.update(end=max(1, n - 1), value=step)
        finally:
            self._player_sync = False

    def _period_changed(self, event):
        r = self.result
        if r is None or self._player_sync:
            return
        with self._held():
            self._sync_player(r, event.new, self.step_slider.value)
            self._update_frame()

    def _update_frame(self, *_):
        r = self.result
        if r is None or self._player_sync:
            return
        steps = self._steps_of(r, self.period_slider.value)
        with self._held():
            self.frame = int(steps[min(self.step_slider.value, steps.size - 1)]) if steps.size else r.xc.size - 1

    def step(self, delta: int) -> None:
        """Move the player by ``delta`` steps, across period boundaries (the loading included)."""
        r = self.result
        if r is None:
            return
        k = int(np.clip(self.frame + delta, 0, r.xc.size - 1))
        period = int(r.period[k]) + 1
        with self._held():
            self._sync_player(r, period, int(k - self._steps_of(r, period)[0]))
            self.frame = k

    def _toggle_play(self, *_):
        """Autoplay the current period at the chosen speed (a periodic callback of this session)."""
        if self._autoplay is not None:
            self._autoplay.stop()
            self._autoplay = None
        if not self.play.value or self._doc is None or self._doc.session_context is None:
            return
        r = self.result
        if r is not None and self.step_slider.value >= self._steps_of(r, self.period_slider.value).size - 1:
            self.step_slider.value = 0  # from the start of the period
        self._autoplay = pn.state.add_periodic_callback(self._tick, period=int(self.speed.value))

    def _tick(self):
        r = self.result
        if r is None or self.step_slider.value >= self._steps_of(r, self.period_slider.value).size - 1:
            self.play.value = False  # the period is over
            return
        self.step_slider.value += 1

    def _readout(self, result, frame, units) -> str:
        """Where the player is: step, period, time, the centre's position and the rolling direction."""
        if result is None:
            return "<div class='readout'>no run yet</div>"
        k = int(np.clip(frame, 0, result.xc.size - 1))
        period = int(result.period[k]) + 1
        xc = float(result.xc[k])
        dx = xc - float(result.xc[k - 1]) if k > 0 else 0.0
        where = f"xc = {xc * units.x:.3g} {'mm' if units.system == 'physical' else 'a'}"
        if dx > 0:
            moving = "rolling towards +x; trailing edge at xc − a"
        elif dx < 0:
            moving = "rolling towards −x; trailing edge at xc + a"
        else:
            moving = "at rest (loading)"
        phase = "loading" if period == 0 else f"period {period} of {result.periods}"
        return (f"<div class='readout'>Step <b>{k + 1}</b> of {result.xc.size} · {phase} · "
                f"t = {plots.time_axis(result)[k]:.3f} periods · centre <b>{where}</b> · {moving}</div>")

    # ------------------------------------------------------------------ the numerical map
    def _map_options(self) -> dict:
        """Solver options of a map sweep: the current solver settings; the strip kernel's L/a and ν are the current
        contact's (:func:`core.strip_options`), whatever run is shown."""
        opts = dict(periods=self.state.periods, dx=self.state.dx, kernel=self.state.kernel,
                    shape=self.state.schedule)
        if self.state.point:  # the current body's map: no kernel (the half-space's)
            ratio = self.state.ratio if self.state.body == "ellipsoid" else None
            return dict(periods=self.state.periods, dx=self.state.dx, shape=self.state.schedule,
                        body=self.state.body, ratio=ratio)
        if opts["kernel"] == "strip":
            if self.contact is None:  # invalid geometry: no strip to take L/a from
                opts["kernel"] = "plane"
            else:
                opts.update(core.strip_options(self.contact))
        return opts

    def compute_map(self) -> None:
        """Sweep the (ft, w) plane with the current solver settings, off the UI thread, and overlay it on the map."""
        if self.map_running:
            return
        if not runs.MAP_SLOT.acquire(blocking=False):
            self.map_status = "another numerical map is being computed on this server; try again shortly."
            return
        n = int(self.map_points.value)
        grid = np.linspace(0.02, 0.95, n)
        opts = self._map_options()
        self._map_cancel = cancel = threading.Event()
        headless = self._doc is None or self._doc.session_context is None

        def progress(done, total):
            self._in_session(setattr, self, "map_progress", int(100 * done / max(total, 1)))

        def work():
            try:
                return core.sweep(grid, grid, self.map_scheduler, max_workers=runs.MAP_WORKERS, progress=progress,
                                  cancel=cancel, timeout=runs.MAP_BUDGET_S, **opts)
            finally:
                runs.MAP_SLOT.release()

        label = (f"computed {n}×{n}, {opts['body']}, {opts['periods']} periods" if "body" in opts
                 else f"computed {n}×{n}, {opts['kernel']} kernel, {opts['periods']} periods")

        def done(table=None, error=None):
            if table is not None:
                self.map_table, self.map_label = table, label
                self.map_status = f"{label}: {len(table)} runs in {table.attrs.get('wall_s', float('nan')):.1f} s"
            else:
                self.map_status = error
            self.map_running = False

        self.map_progress, self.map_running, self.map_status = 0, True, "computing…"
        if headless:  # compute here
            try:
                done(work())
            except (core.SweepCancelled, ValueError) as e:
                done(error=f"map not computed: {e}")
            return

        def finished(future):  # in the map thread
            try:
                table = future.result()
            except (core.SweepCancelled, ValueError, RuntimeError) as e:
                self._in_session(done, error=f"map not computed: {e}")
            else:
                self._in_session(done, table)

        runs.submit_map(work).add_done_callback(finished)

    @param.depends("map_running", "map_progress", watch=True)
    def _show_map_progress(self):
        self.map_bar.param.update(value=self.map_progress, visible=self.map_running)
        self.map_button.disabled = self.map_running
        self.map_cancel_button.disabled = not self.map_running

    # ------------------------------------------------------------------ downloads
    def _csv(self):
        if self.result is None:
            return io.StringIO("# no run yet\n")
        if isinstance(self.result, core.PointContactResult):
            return io.StringIO(point_view.to_csv(self.result, self.csv_table.value))
        text = to_csv(self.result, self.csv_table.value, self.contact)
        if self.csv_table.value in ("steps", "periods"):  # periods numbered as on the player and the increment plot
            text = _renumber_periods(text)
        if self.csv_table.value == "final":  # beside the numerical traction, the paper's closure (eqs 22-30)
            r = self.result
            ft, w = float(r.params.get("ft", 0.0)), float(r.params.get("w", 0.0))
            closure = core.shakedown_traction(r.x, ft, w)
            lines = text.splitlines()
            k = next(i for i, line in enumerate(lines) if not line.startswith("#"))
            lines[k] += ",closure_traction_mu_p0"
            lines[k + 1:] = [f"{line},{c:.10g}" for line, c in zip(lines[k + 1:], closure)]
            text = "\n".join(lines) + "\n"
        return io.StringIO(text)

    def _name_downloads(self) -> None:
        """Download names that carry the run's parameters (a folder of downloads stays readable)."""
        r = self.result
        tag = "" if r is None else "_ft{:.2f}_w{:.2f}_mu{:.2f}_{}p".format(
            float(r.params.get("ft", 0)), float(r.params.get("w", 0)), self.state.mu, r.periods)
        self.csv_download.filename = f"shakedown_{self.csv_table.value}{tag}.csv"
        self.json_download.filename = f"shakedown_run{tag}.json"

    def _json(self):
        if self.result is None:
            return io.StringIO("{}")
        if isinstance(self.result, core.PointContactResult):
            return io.StringIO(point_view.to_json(self.result))
        return io.StringIO(to_json(self.result, self.contact))

    # ------------------------------------------------------------------ figures
    def _compute_units(self, result=None) -> plots.Units:
        result = self.result if result is None else result
        g = self.geometry
        geometry = None if g is None else g.replace(mu=self.mu_slider.value)
        kernel = getattr(result, "kernel", self.state.kernel)
        return plots.make_units(self.state.units, geometry, kernel, getattr(result, "u0", None))

    def _update_units(self, *_):
        units = self._compute_units()
        if units != self.plot_units:
            with self._held():
                self.plot_units = units

    def _inputs(self) -> plots.Inputs:
        return plots.Inputs(**{field: getattr(self, name) for field, name in _FIGURE_INPUTS.items()})

    def _redraw(self, *events):
        """Push the layers that changed into the figures that depend on the changed inputs."""
        changed = {e.name for e in events}
        inputs, rebuilt = self._inputs(), []
        with self._held():
            for name, live in self._live.items():
                if changed.intersection(_FIGURE_INPUTS[i] for i in plots.FIGURES[name]["inputs"]):
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
        (the served page, :meth:`explorer_tab`) none is drawn here: each is
        drawn once the browser scrolls near its place (:attr:`sentinels`), so
        that a visitor who never scrolls down costs the server only the
        figures at the top, and the page comes sooner. Without it (notebooks,
        tests of the Python objects) they are drawn here.
        """
        if os.environ.get("SHAKEDOWN_FIGURES") == "dynamicmap":  # the idiomatic path, measured by benchmarks/app.py
            self._live, self.sentinels, self._when_shown = {}, {}, False
            self._panes = {name: pn.pane.HoloViews(plots.dynamic(name, self._inputs, **{
                i: self.param[_FIGURE_INPUTS[i]] for i in plots.FIGURES[name]["inputs"]}), sizing_mode="stretch_width")
                for name in plots.FIGURES}
            return self._panes
        self._live = {}
        self._panes = {} if when_shown else {name: pn.pane.Bokeh(None, sizing_mode="stretch_width")
                                             for name in plots.FIGURES}  # (served: made when drawn)
        self.sentinels, self._when_shown = {}, when_shown  # (sentinels: made with the grid, see _slots)
        if not when_shown:
            self._draw_figures(self._figures_of(self.state.body))
        self.state.param.watch(lambda e: self._show_figures(self._figures_of(e.new)), "body")
        return self._panes

    @staticmethod
    def _figures_of(body: str) -> list[str]:
        return [name for name in plots.FIGURES if point_view.shown(name, body)]

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
        """Draw the figures ``names`` that the current body shows and, on the served page, that the browser has
        scrolled near; put each in the page in place of its sentinel (one recomputation of the document's model
        graph for all)."""
        body = self.state.body
        names = [n for n in names if point_view.shown(n, body)
                 and (not self._when_shown or (n in self.sentinels and self.sentinels[n].shown))]
        doc = self._doc
        with (doc.models.freeze() if doc is not None else contextlib.nullcontext()):
            self._draw_figures(names)
            grid = getattr(self, "_grid", None)
            if grid is not None and self._when_shown:
                slots = self._slots()
                if slots != grid.objects:
                    grid.objects = slots

    def _slots(self) -> list:
        """What the figure grid holds: for each figure of the current body, its cell once drawn, else the
        sentinel that keeps its place (the other body's figures are not in the page)."""
        for name in self._live:
            if name not in self._cells:
                self._cells[name] = self._cell(name)
        return [self._cells.get(name) or self._sentinel(name)
                for name in self._GRID if point_view.shown(name, self.state.body)]

    def _sentinel(self, name: str) -> WhenShown:
        """The sentinel that keeps figure ``name``'s place until the browser scrolls near it (made once)."""
        if name not in self.sentinels:
            self.sentinels[name] = WhenShown(height=plots.HEIGHT + 40, styles=_CELL_STYLE,
                                             css_classes=[f"figure-{name}"])
            self.sentinels[name].param.watch(lambda e: self._show_figures([name]), "shown")
        return self.sentinels[name]

    @functools.cached_property
    def engineer(self) -> EngineerInputs:
        """The loads in physical units (Ft, W or the rocking angle) and the cycles the creep is extrapolated to."""
        return EngineerInputs(self)

    # ------------------------------------------------------------------ cards
    @staticmethod
    def _shows(result, ft, w, point: bool | None = None) -> bool:
        """Whether ``result`` is the run of the inputs ``ft``, ``w`` the sliders show and, if ``point`` is given,
        of a point contact or not (a body switch changes the contact before the new body's run is there)."""
        return (result is not None and abs(float(result.params.get("ft", math.nan)) - ft) < 1e-9
                and abs(float(result.params.get("w", math.nan)) - w) < 1e-9
                and (point is None or isinstance(result, core.PointContactResult) == point))

    def _badge(self, ft, w, result, error, pending=False):
        body = getattr(getattr(self, "state", None), "body", "cylinder")  # (also called on the class, headless)
        predicted, rule = point_view.prediction(ft, w, body)
        if error:
            return ('<span class="regime-badge regime-none" data-regime="invalid">INVALID INPUT</span>'
                    f'<div class="regime-note">{html.escape(error)}</div>')
        point = getattr(getattr(self, "state", None), "point", None)
        if pending or not self._shows(result, ft, w, point):
            what = "SOLVING…" if pending or result is None else "RELEASE TO SOLVE"
            return (f'<span class="regime-badge regime-none" data-regime="pending">{what}</span>'
                    f'<div class="regime-note">{rule} predicts {predicted} for ft = {ft:.2f}, w = {w:.2f}</div>')
        regime = str(result.regime)
        note = f"solver, {result.periods} periods"
        if result.shakedown_period is not None:
            note += f"; shaken down after period {result.shakedown_period}"
        if regime == "undetermined":  # the periods run cannot tell: say why
            note += f": {html.escape(str(result.regime_reason))}"
        note += f"<br>{html.escape(rule)} predicts {html.escape(str(predicted))} for ft = {ft:.2f}, w = {w:.2f}"
        css = re.sub(r"[^a-z]", "", regime.lower()) or "none"
        return (f'<span class="regime-badge regime-{css}" data-regime="{html.escape(regime)}">'
                f'{html.escape(regime.upper())}</span><div class="regime-note">{note}</div>')

    def _cards(self, ft, w, mu, contact, result, pending=False, units="normalised", cycles=10**6):
        """The summary cards: inputs in physical units, the closure's and the solver's numbers, the margins.
        Numerical values are shown only when the run shown is the current inputs' run (else 'solving…')."""
        rows = []
        physical = units == "physical"
        fresh = not pending and self._shows(result, ft, w, self.state.point)
        wait = None if fresh else ("solving…" if pending or result is None else "release the slider")
        if isinstance(contact, core.PointContact) or self.state.point:
            return point_view.cards(ft, w, mu, contact, result, wait, units, cycles, self.state.body)
        c = None if contact is None else contact.replace(mu=mu, ft=ft, w=w)
        if c is not None:
            rows += [("Ft (tangential force)", _fmt(ft * mu * c.Fn, "N")), ("W (rocking amplitude)", _fmt(w * c.a * 1e6, "µm")),
                     ("a (half-width)", _fmt(c.a * 1e3, "mm")), ("p0 (peak pressure)", _fmt(c.p0 / 1e6, "MPa")),
                     ("d (indentation, eq 6)", _fmt(c.d * 1e3, "mm")), ("Dundurs β", _fmt(c.beta, "", 3))]
        u0 = result.u0 if fresh else None  # (after a body switch, the run may still be the other body's)
        if u0 is not None and c is not None and fresh:
            rows.append(("U0 (ft = 1, strip)", _fmt(u0 * c.displacement_unit * 1e6, "µm")))
        csd, ft_lim, w_lim = _closure(ft, w)
        scale, unit = (c.a * 1e3, "mm") if (physical and c is not None) else (1.0, "a")
        rows += [("c_sd closure (eq 30)", _fmt(csd * scale, unit, 3) if math.isfinite(csd) else "none (ft > ft_lim)"),
                 ("c_sd numerical", wait or _fmt(result.stick_halfwidth * scale, unit, 3)),
                 ("ft_lim(w) (eq 35)", _fmt(ft_lim, "", 4)),
                 ("w_lim(ft) (eq 35)", _fmt(w_lim, "", 4)),
                 ("margin ft / ft_lim", _fmt(ft / ft_lim, "", 3) if ft_lim > 0 else "–"),
                 ("margin w / w_lim", _fmt(w / w_lim, "", 3) if w_lim > 0 else "–")]
        if wait:
            rows += [("Δu last period", wait), ("solve", wait)]
        else:
            inc = float(result.increment_per_period[-1])
            if physical and c is not None:
                um = inc * c.displacement_unit * 1e6
                rows.append(("creep per period (last)", _fmt(um, "µm", 3)))
                rows.append((f"creep after {_count(cycles)} periods", _fmt(um * cycles / 1e3, "mm", 3)))
            else:
                unit_u = "U0" if result.u0 else "μP/E*"
                rows.append(("Δu last period", f"{(inc / result.u0 if result.u0 else inc):.3g} {unit_u}"))
            rows.append(("solve", f"{result.runtime * 1e3:.0f} ms, {result.edges.size - 1} el., "
                                  f"{result.xc.size} steps"))
        return point_view.cards_html(rows, wait)

    def _warnings(self, ft, w, contact, result):
        out = [] if contact is None else list(getattr(contact, "warnings", ()))
        if result is not None and isinstance(result, core.PointContactResult) != self.state.point:
            result = None  # the other body's run, until the new body's comes (a body switch)
        if w > 0.95:
            out.append(f"w = {w:.2f}: b = a − W = {1 - w:.2f} a is tiny; the always-in-contact band spans "
                       f"{(1 - w) / self.state.dx * 2:.0f} elements.")
        if result is not None and result.params.get("history") == "normal":
            out.append(f"the normal force oscillates by ±{100 * float(result.params.get('amplitude', 0)):.0f} %: "
                       "eq 35, the closure and the Hertz curves are those of the mean force; the solver's "
                       "verdict is the one to trust.")
        if result is not None:
            n_b = 2 * (1 - float(result.params.get("w", w))) / result.dx
            if n_b < 8:
                out.append(f"only {n_b:.0f} elements resolve b = a − W: raise the resolution.")
            inc = np.abs(result.increment_per_period)
            if result.regime == "ratcheting" and inc.size >= 2 and inc[-1] < 0.7 * inc[-2]:
                out.append("the increment per period is still falling: run more periods to tell slow "
                           "shakedown from ratcheting.")
        return out

    # ------------------------------------------------------------------ layout
    def __panel__(self):
        return self.template()

    def main_area(self) -> pn.viewable.Viewable:
        """The badge, cards, player and figures, without the sidebar (for notebooks)."""
        live = dict(ft=self.param.ft_live, w=self.param.w_live)
        badge = panes.HTML(pn.bind(self._badge, **live, result=self.param.result, error=self.param.error,
                                     pending=self.param.pending),
                             css_classes=["regime"], margin=(6, 10), sizing_mode="stretch_width", stylesheets=[_CSS])
        cards = panes.HTML(pn.bind(self._cards, **live, mu=self.mu_slider.param.value,
                                     contact=self.param.contact, result=self.param.result,
                                     pending=self.param.pending, units=self.state.param.units,
                                     cycles=self.engineer.param.cycles),
                             css_classes=["summary-cards"], margin=(0, 10), sizing_mode="stretch_width",
                             stylesheets=[_CSS])
        model_warnings = pn.bind(self._warnings, **live, contact=self.param.contact, result=self.param.result)
        warnings = panes.Alert(pn.bind(lambda m: "\n".join(f"- {html.escape(x)}" for x in m), model_warnings),
                                 visible=pn.bind(bool, model_warnings), alert_type="warning",
                                 sizing_mode="stretch_width", css_classes=["model-warnings"])
        errors = panes.Alert(pn.bind(lambda e: f"**Invalid input:** {html.escape(e)}", self.param.error),
                               alert_type="danger", visible=self.param.error.rx.bool(),
                               sizing_mode="stretch_width", css_classes=["input-error"])
        notices = panes.Alert(pn.bind(lambda n: "**Some URL parameters were not applied:**\n\n"
                                        + "\n".join(f"- {html.escape(m)}" for m in n), self.param.notices),
                                alert_type="warning", visible=self.param.notices.rx.bool(),
                                sizing_mode="stretch_width", css_classes=["url-notice"])
        top = pn.FlexBox(
            pn.Column(badge, pn.Row(self.spinner, self.status), sizing_mode="stretch_width",
                      styles={"flex": "0 1 300px", "min-width": "260px"}),
            pn.Column(cards, errors, notices, warnings, sizing_mode="stretch_width",
                      styles={"flex": "1 1 500px", "min-width": "260px"}),
            flex_wrap="wrap", sizing_mode="stretch_width")
        tabs = pn.Tabs(("Explorer", self.explorer_tab()), *self._lazy_tabs(), sizing_mode="stretch_width",
                       dynamic=True)  # a tab's models are sent only when shown
        tabs.param.watch(lambda e: self._fill_tab(tabs, e.new), "active")
        return pn.Column(top, tabs, sizing_mode="stretch_width")

    #: The tabs built only when first shown (most visitors never open them): title, builder.
    _LAZY_TABS: ClassVar[dict] = {"Paper's figures": lambda self: paper_figures_tab(),
                                  "About the model": lambda self: self.about()}

    def _lazy_tabs(self) -> list:
        self._unbuilt = dict(self._LAZY_TABS)
        return [(title, pn.Column(name=title, sizing_mode="stretch_width")) for title in self._LAZY_TABS]

    def _fill_tab(self, tabs: pn.Tabs, index: int) -> None:
        holder = tabs[index]
        build = self._unbuilt.pop(holder.name, None)
        if build is not None:
            holder.objects = [build(self)]

    def player_controls(self) -> pn.FlexBox:
        """The cycle player: period, step, step back / play / step forward, speed, and where the cylinder is."""
        readout = pn.bind(self._readout, self.param.result, self.param.frame, self.param.plot_units)
        self.readout.object = readout
        return pn.FlexBox(
            pn.pane.Markdown("**Cycle player**", margin=(18, 10, 0, 10), width=130, sizing_mode=None),
            self.period_slider, self.step_slider,
            pn.Row(self.step_back, self.play, self.step_forward, sizing_mode=None, margin=(14, 0, 0, 0)),
            self.speed, self.readout,
            flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width", css_classes=["cycle-player"])

    #: The figures in the order they are laid out.
    _GRID = ("sketch", "pressure", "traction", "states", "displacement", "point_pressure", "point_traction",
             "point_zones", "point_cut", "point_displacement", "map", "increments", "point_increments")

    def explorer_tab(self) -> pn.Column:
        """The player and the figures, each with a one-line caption; the figures wrap to one column when narrow.
        A figure, its caption and its controls are built when the browser first scrolls near their place."""
        self.figures(when_shown=True)
        self._grid = pn.FlexBox(*(self._slots() if self._when_shown else [self._cell(name) for name in self._GRID]),
                                flex_wrap="wrap", sizing_mode="stretch_width")
        self.pins = Pins(self)
        svg = slides.save_svg(slides.figure_titles(), run=dict(ft=self.ft_slider, w=self.w_slider))
        return pn.Column(self.player_controls(), self.pins, svg, self._grid, sizing_mode="stretch_width", name="Explorer")

    def _cell(self, name: str) -> pn.Column:
        """Figure ``name`` with its caption (and, for the map, its controls), shown while the body shows it."""
        caption = pn.pane.HTML(f"<div class='caption'>{html.escape(plots.FIGURES[name]['caption'])}</div>",
                               stylesheets=[_CSS], sizing_mode="stretch_width", margin=0)
        extra = [self.map_controls()] if name == "map" else []
        return pn.Column(self._panes[name], caption, *extra, sizing_mode="stretch_width", styles=_CELL_STYLE,
                         visible=pn.bind(point_view.shown, name, self.state.param.body))

    def map_controls(self) -> pn.Column:
        """The 'compute the numerical map' action, its progress and its outcome."""
        status = panes.Markdown(pn.bind(lambda s, l: f"Map shown: **{l}**. {s}", self.param.map_status,
                                          self.param.map_label), css_classes=["map-status"],
                                  sizing_mode="stretch_width")
        self.map_points.param.update(sizing_mode="stretch_width", min_width=200)
        self.map_button.param.update(sizing_mode=None, width=250)
        return pn.Column(pn.FlexBox(self.map_points, self.map_button, self.map_cancel_button, flex_wrap="wrap",
                                    align_items="flex-end", sizing_mode="stretch_width"),
                         self.map_bar, status, sizing_mode="stretch_width")

    def sidebar(self) -> list:
        """The input widgets."""
        physical = self.state.param.units.rx() == "physical"
        solver_card = pn.Card(title="Solver", collapsed=True, sizing_mode="stretch_width")
        return [
            self.preset, self.preset_note, *point_view.body_inputs(self.state),
            pn.pane.Markdown("### Loads"), self.ft_slider, self.w_slider, self.mu_slider,
            pn.pane.Markdown("### Units"), self.units_toggle,
            # the loads in physical units are shown with the physical units, the solver's options when their
            # card is opened: both are sent to the browser only then (most visitors never open them)
            _filled_when(pn.Column(sizing_mode="stretch_width", margin=0, visible=physical), physical,
                         lambda: [self.engineer]),
            pn.Card(*self.geometry_inputs, self.rigid_box, *self.cylinder_inputs,
                    title="Geometry and materials", collapsed=False, sizing_mode="stretch_width"),
            _filled_when(solver_card, solver_card.param.collapsed.rx.not_(), lambda: self.solver_inputs),
            pn.pane.Markdown("### Download the run"), self.csv_table, self.csv_download, self.json_download,
            pn.pane.Markdown(_APPLIES, styles={"font-size": "14px"}, css_classes=["model-applies"]),
        ]

    @staticmethod
    def about() -> pn.Column:
        """The 'About the model' tab: Markdown with KaTeX equations."""
        parts = re.split(r"^\$\$(.+?)\$\$$", _ABOUT.read_text(encoding="utf-8"), flags=re.M | re.S)
        objs = []
        for i, part in enumerate(parts):
            if i % 2:
                objs.append(pn.pane.LaTeX(f"$${part.strip()}$$", renderer="katex", styles={"font-size": "20px"},
                                          margin=(0, 30), stylesheets=_KATEX_CSS, sizing_mode="stretch_width"))
            elif part.strip():
                objs.append(pn.pane.Markdown(part, styles={"font-size": "17px"}, sizing_mode="stretch_width"))
        return pn.Column(*objs, name="About the model", max_width=1100, sizing_mode="stretch_width")

    def template(self) -> pn.template.BaseTemplate:
        """The served page: sidebar, header with the presentation-mode switch, the main area."""
        present = pn.widgets.Toggle(label="Presentation mode", width=170, css_classes=["presentation-toggle"],
                                    button_type="light", margin=(8, 10))
        present.jscallback(value="""
            const on = cb_obj.active;
            document.documentElement.classList.toggle('presenting', on);
            window.dispatchEvent(new Event('resize'));
        """)
        template = pn.template.BootstrapTemplate(
            title="Shakedown Explorer: rocking contacts with Coulomb friction",
            # the sidebar is one root, not one per input: the template renders each root in a `config.set`
            # block that reads and restores every Panel setting (15% of a page's build with 20 roots)
            sidebar=[pn.Column(*self.sidebar(), sizing_mode="stretch_width", margin=0)], main=[self.main_area()],
            header=[present], sidebar_width=340,
            header_background="#1f5f99",
            # Panel's busy indicator follows the whole process (any session's callback) and is updated in every
            # session on every event: with 10 sessions sliding it took a third of the server's CPU. The run's
            # own spinner (beside the verdict) says when this session's solve is running.
            busy_indicator=None,
        )
        template.config.raw_css.append(_PAGE_CSS)
        doc = self._doc
        if doc is not None:
            from bokeh.models import CustomJS

            doc.js_on_event("document_ready", CustomJS(code=_A11Y_JS % MathFonts.url))
        return template
