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
import re
import threading
from pathlib import Path
from typing import ClassVar

import numpy as np
import panel as pn
import param
from panel.io.state import set_curdoc

import core
from core.export import to_csv, to_json

from . import plots
from . import runs
from .live import LiveFigure
from .paper_figures import paper_figures_tab
from .runs import RESULTS, Generation, run_key, solve, submit
from .state import PRESETS, URL_PARAMETERS, ExplorerState, parse_query

__all__ = ["Explorer"]

_ABOUT = Path(__file__).with_name("about.md")
_SOLVER_INPUTS = [p for p in URL_PARAMETERS if p != "units"]
#: A solve shows the loading indicator only after this long [ms].
_SPINNER_DELAY_MS = 150
_CSS = """
.regime-badge {display: inline-block; padding: 10px 22px; border-radius: 12px; color: white;
               font-size: 26px; font-weight: 700; letter-spacing: 0.04em;}
.regime-shakedown {background: #2ca02c;} .regime-ratcheting {background: #d62728;}
.regime-none {background: #7f7f7f;}
.regime-note {font-size: 15px; color: #444; margin-top: 6px;}
.cards {display: grid; grid-template-columns: repeat(2, minmax(250px, 1fr)); gap: 4px 28px; font-size: 17px;}
.cards .k {color: #444;} .cards .v {font-weight: 600; float: right; margin-left: 10px;}
.cards div {border-bottom: 1px solid #eee; padding: 2px 0;}
"""


def _fmt(v, unit="", digits=4) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    return f"{v:.{digits}g}{(' ' + unit) if unit else ''}"


@functools.lru_cache(maxsize=1)
def _shipped_map():
    """The numerical map shipped with core (read once, shared read-only by all sessions)."""
    return core.load_default_map()


class _Prompt:
    """Mixin: the widget's value changes reach the explorer at once. Panel waits 50 ms for more changes
    by default (half the latency budget of a slider move); the figures' updates are cheap enough not to."""

    _priority_changes: ClassVar[list[str]] = ["value", "value_throttled"]


class FloatSlider(_Prompt, pn.widgets.FloatSlider):
    pass


class IntSlider(_Prompt, pn.widgets.IntSlider):
    pass


class Player(_Prompt, pn.widgets.Player):
    pass


#: The explorer parameter behind each input of the figures (:class:`app.plots.Inputs`).
_FIGURE_INPUTS = {"ft": "ft_live", "w": "w_live", "units": "plot_units", "result": "result", "frame": "frame",
                  "table": "map_table"}
#: Range padding (x, y) of the axes that follow the data; None: the figure's own fixed ranges.
_PADDING = {"states": (0.0, 0.0), "increments": (0.05, 0.1), "map": None}


class Explorer(pn.viewable.Viewer):
    """The shakedown explorer over an :class:`ExplorerState` (one per browser session)."""

    result = param.ClassSelector(class_=core.CycleResult, default=None, allow_None=True,
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
    solving = param.Boolean(default=False, doc="A solve for the current inputs is running.")
    error = param.String(default="", doc="Why the current inputs cannot be solved, if they cannot.")
    notices = param.List(default=[], doc="Messages about rejected URL parameters.")
    map_table = param.DataFrame(default=None, allow_None=True,
                                doc="Sweep table shown on the shakedown map (the shipped map until one is computed).")
    map_label = param.String(default="shipped map", doc="Where the numerical map comes from.")
    map_running = param.Boolean(default=False, doc="A numerical map is being computed.")
    map_progress = param.Integer(default=0, bounds=(0, 100), doc="Progress of the map computation [%].")
    map_status = param.String(default="", doc="Outcome of the last map computation.")

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
        self.param.watch(self._redraw, list(_FIGURE_INPUTS.values()))
        self._update_contact()
        self.solve_now()  # the first run is in the page as it is first sent: no update before the browser connects
        self._map_cancel = threading.Event()
        self.map_scheduler = None  # core.sweep's default: a local process pool
        try:
            self.map_table = _shipped_map()
            self.map_label = "shipped 40×40, plane kernel"
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
        ]
        self.spinner = pn.indicators.LoadingSpinner(value=False, size=30, visible=False,
                                                    css_classes=["solve-spinner"])
        self.status = pn.pane.HTML("", css_classes=["solve-status"], margin=(8, 4))
        # the cycle player: a period, then the steps of that period
        self.period_slider = IntSlider(label="Period", start=0, end=1, value=0, width=260)
        self.player = Player(label="Step in the period", start=0, end=1, value=0, interval=150,
                                        loop_policy="loop", width=430, show_loop_controls=False,
                                        css_classes=["cycle-player"])
        self.period_slider.param.watch(self._update_frame, "value")
        self.player.param.watch(self._update_frame, "value")
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
        self.csv_table.param.watch(lambda e: setattr(self.csv_download, "filename", f"shakedown_{e.new}.csv"),
                                   "value")
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
            self.state.apply_preset(event.new)

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
            self.solving = False
            return
        contact, options = self.contact, self.state.solver_options()
        cached = RESULTS.get(run_key(contact, options))
        doc = self._doc
        if cached is not None or doc is None or doc.session_context is None:
            # cached, or headless (tests, notebooks without a server): solve here
            self._finish(token, contact, options, cached)
            return

        def show_spinner():  # only if the solve is not over in a blink (saves two page updates)
            if self._generation.is_current(token) and self.result_token != token:
                self.solving = True

        doc.add_timeout_callback(show_spinner, _SPINNER_DELAY_MS)

        def stale():
            return not self._generation.is_current(token)

        def failed(message):
            if not stale():  # a stale run was cancelled on purpose: say nothing
                self.param.update(error=f"solver: {message}", solving=False)

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
        m = max(1, int(np.count_nonzero(result.period == 0)))
        with self._held():
            self._player_sync = True  # the widgets follow the run; the frame is set once, below
            try:
                self.period_slider.param.update(end=max(1, result.periods - 1), value=result.periods - 1)
                self.player.param.update(end=max(1, m - 1), value=m - 1)
            finally:
                self._player_sync = False
            self.param.update(result=result, frame=result.xc.size - 1, plot_units=self._compute_units(result),
                              solving=False)

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

    def _update_frame(self, *_):
        r = self.result
        if r is None or self._player_sync:
            return
        starts = np.flatnonzero(r.period == min(self.period_slider.value, r.periods - 1))
        with self._held():
            self.frame = int(min(starts[0] + self.player.value, r.xc.size - 1)) if starts.size else r.xc.size - 1

    # ------------------------------------------------------------------ the numerical map
    def _map_options(self) -> dict:
        """Solver options of a map sweep: the current solver settings; the strip kernel's L/a and ν are the current
        contact's (:func:`core.strip_options`), whatever run is shown."""
        opts = dict(periods=self.state.periods, dx=self.state.dx, kernel=self.state.kernel,
                    shape=self.state.schedule)
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

        label = f"computed {n}×{n}, {opts['kernel']} kernel, {opts['periods']} periods"

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
        return io.StringIO(to_csv(self.result, self.csv_table.value, self.contact))

    def _json(self):
        if self.result is None:
            return io.StringIO("{}")
        return io.StringIO(to_json(self.result, self.contact))

    # ------------------------------------------------------------------ figures
    def _compute_units(self, result=None) -> plots.Units:
        result = self.result if result is None else result
        geometry = None if self.geometry is None else self.geometry.replace(mu=self.mu_slider.value)
        kernel = result.kernel if result is not None else self.state.kernel
        return plots.make_units(self.state.units, geometry, kernel, None if result is None else result.u0)

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

    def figures(self) -> dict[str, pn.pane.Bokeh]:
        """The six figures: Bokeh figures rendered once, then updated in place (:class:`~app.live.LiveFigure`)."""
        inputs = self._inputs()
        self._live = {name: LiveFigure(plots.specs(name, inputs.units), plots.layers(name, inputs), plots.group(name),
                                       padding=_PADDING.get(name, (0.0, 0.1)))
                      for name in plots.FIGURES}
        self._panes = {name: pn.pane.Bokeh(live.figure, sizing_mode="stretch_width")
                       for name, live in self._live.items()}
        return self._panes

    # ------------------------------------------------------------------ cards
    def _badge(self, ft, w, result, error):
        predicted = core.classify_regime(ft, w)
        if error:
            return ('<span class="regime-badge regime-none" data-regime="invalid">INVALID INPUT</span>'
                    f'<div class="regime-note">{html.escape(error)}</div>')
        if result is None:
            return ('<span class="regime-badge regime-none" data-regime="pending">SOLVING…</span>'
                    f'<div class="regime-note">eq 35 predicts {predicted}</div>')
        regime = result.regime
        note = f"solver, {result.periods} periods"
        if result.shakedown_period is not None:
            note += f"; shaken down after period {result.shakedown_period}"
        if regime == "undetermined":  # the periods run cannot tell: say why (regime-none: the neutral colour)
            note += f": {result.regime_reason}"
        note += f" · eq 35 predicts {predicted} for ft = {ft:.2f}, w = {w:.2f}"
        css = "regime-none regime-undetermined" if regime == "undetermined" else f"regime-{regime}"
        return (f'<span class="regime-badge {css}" data-regime="{regime}">{regime.upper()}</span>'
                f'<div class="regime-note">{html.escape(note)}</div>')

    def _cards(self, ft, w, mu, contact, result):
        rows = []
        c = None if contact is None else contact.replace(mu=mu, ft=ft, w=w)
        if c is not None:
            rows += [("a (half-width)", _fmt(c.a * 1e3, "mm")), ("p0 (peak pressure)", _fmt(c.p0 / 1e6, "MPa")),
                     ("d (indentation, eq 6)", _fmt(c.d * 1e3, "mm")), ("Dundurs β", _fmt(c.beta, "", 3))]
        u0 = None if result is None else result.u0
        if u0 is not None and c is not None:
            rows.append(("U0 (strip, ft = 1)", f"{_fmt(u0 * c.displacement_unit * 1e6, 'µm')} = {u0:.3g} μP/E*"))
        csd = float(core.shakedown_stick_halfwidth(ft, w))
        rows += [("c_sd/a closure (eq 30)", _fmt(csd, "", 3) if math.isfinite(csd) else "none (ft > ft_lim)"),
                 ("c_sd/a numerical", "–" if result is None else _fmt(result.stick_halfwidth, "", 3)),
                 ("ft_lim(w) (eq 35)", _fmt(float(core.ft_limit(w)), "", 4)),
                 ("w_lim(ft) (eq 35)", _fmt(float(core.w_limit(ft)), "", 4))]
        if result is not None:
            inc = result.increment_per_period
            unit = "U0" if result.u0 else "μP/E*"
            last = inc[-1] / result.u0 if result.u0 else inc[-1]
            rows.append(("Δu last period", f"{last:.3g} {unit}"))
            rows.append(("solve", f"{result.runtime * 1e3:.0f} ms, {result.edges.size - 1} el., "
                                  f"{result.xc.size} steps"))
        body = "".join(f"<div><span class='k'>{html.escape(k)}</span><span class='v'>{html.escape(v)}</span></div>"
                       for k, v in rows)
        return f"<div class='cards'>{body}</div>"

    def _warnings(self, ft, w, contact, result):
        out = [] if contact is None else list(contact.warnings)
        if w > 0.95:
            out.append(f"w = {w:.2f}: b = a − W = {1 - w:.2f} a is tiny; the always-in-contact band spans "
                       f"{(1 - w) * self.state.resolution * 2:.0f} elements.")
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
        badge = pn.pane.HTML(pn.bind(self._badge, **live, result=self.param.result, error=self.param.error),
                             css_classes=["regime"], margin=(6, 10), min_width=300, height=120, stylesheets=[_CSS])
        cards = pn.pane.HTML(pn.bind(self._cards, **live, mu=self.mu_slider.param.value,
                                     contact=self.param.contact, result=self.param.result),
                             css_classes=["summary-cards"], margin=(0, 10), height=180, stylesheets=[_CSS])
        model_warnings = pn.bind(self._warnings, **live, contact=self.param.contact, result=self.param.result)
        warnings = pn.pane.Alert(pn.bind(lambda m: "\n".join(f"- {html.escape(x)}" for x in m), model_warnings),
                                 visible=pn.bind(bool, model_warnings), alert_type="warning",
                                 sizing_mode="stretch_width", css_classes=["model-warnings"])
        errors = pn.pane.Alert(pn.bind(lambda e: f"**Invalid input:** {html.escape(e)}", self.param.error),
                               alert_type="danger", visible=self.param.error.rx.bool(),
                               sizing_mode="stretch_width", css_classes=["input-error"])
        notices = pn.pane.Alert(pn.bind(lambda n: "**Some URL parameters were not applied:**\n\n"
                                        + "\n".join(f"- {html.escape(m)}" for m in n), self.param.notices),
                                alert_type="warning", visible=self.param.notices.rx.bool(),
                                sizing_mode="stretch_width", css_classes=["url-notice"])
        figs = self.figures()
        player = pn.Row(pn.pane.Markdown("**Cycle player**", margin=(18, 10, 0, 10)), self.period_slider,
                        self.player, sizing_mode="stretch_width")
        explorer = pn.Column(
            player,
            pn.Row(figs["pressure"], figs["traction"], sizing_mode="stretch_width"),
            pn.Row(figs["states"], figs["displacement"], sizing_mode="stretch_width"),
            pn.Row(pn.Column(figs["map"], self.map_controls(), sizing_mode="stretch_width"),
                   figs["increments"], sizing_mode="stretch_width"),
            sizing_mode="stretch_width", name="Explorer",
        )
        tabs = pn.Tabs(explorer, ("Paper's figures", paper_figures_tab()), ("About the model", self.about()),
                       sizing_mode="stretch_width", dynamic=True)  # a tab's models are sent only when shown
        top = pn.Row(pn.Column(badge, pn.Row(self.spinner, self.status), width=360, sizing_mode=None),
                     pn.Column(cards, errors, notices, warnings, sizing_mode="stretch_width"),
                     sizing_mode="stretch_width")
        return pn.Column(top, tabs, sizing_mode="stretch_width")

    def map_controls(self) -> pn.Column:
        """The 'compute the numerical map' action, its progress and its outcome."""
        status = pn.pane.Markdown(pn.bind(lambda s, l: f"Map shown: **{l}**. {s}", self.param.map_status,
                                          self.param.map_label), css_classes=["map-status"])
        return pn.Column(pn.Row(self.map_points, self.map_button, self.map_cancel_button), self.map_bar, status,
                         sizing_mode="stretch_width")

    def sidebar(self) -> list:
        """The input widgets."""
        return [
            self.preset,
            pn.pane.Markdown("### Loads"), self.ft_slider, self.w_slider, self.mu_slider,
            pn.pane.Markdown("### Units"), self.units_toggle,
            pn.Card(*self.geometry_inputs, self.rigid_box, *self.cylinder_inputs,
                    title="Geometry and materials", collapsed=False, sizing_mode="stretch_width"),
            pn.Card(*self.solver_inputs, title="Solver", collapsed=True, sizing_mode="stretch_width"),
            pn.pane.Markdown("### Download the run"), self.csv_table, self.csv_download, self.json_download,
        ]

    @staticmethod
    def about() -> pn.Column:
        """The 'About the model' tab: Markdown with KaTeX equations."""
        parts = re.split(r"^\$\$(.+?)\$\$$", _ABOUT.read_text(encoding="utf-8"), flags=re.M | re.S)
        objs = []
        for i, part in enumerate(parts):
            if i % 2:
                objs.append(pn.pane.LaTeX(f"$${part.strip()}$$", renderer="katex", styles={"font-size": "20px"},
                                          margin=(0, 30)))
            elif part.strip():
                objs.append(pn.pane.Markdown(part, styles={"font-size": "17px"}, sizing_mode="stretch_width"))
        return pn.Column(*objs, name="About the model", max_width=1100, sizing_mode="stretch_width")

    def template(self) -> pn.template.BaseTemplate:
        """The served page."""
        return pn.template.BootstrapTemplate(
            title="Shakedown Explorer: a rocking cylinder with Coulomb friction",
            sidebar=self.sidebar(), main=[self.main_area()], sidebar_width=340,
            header_background="#1f5f99",
        )
