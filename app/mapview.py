"""The shakedown map's numerical layer: the shipped map, or one computed for the current solver settings.

:class:`MapMixin` builds the map's controls (grid size, compute, stop, progress, outcome) and runs the sweep off
the event loop (:func:`core.sweep`, one map at a time per server).
"""

from __future__ import annotations

import functools
import html
import threading

import numpy as np
import panel as pn

import core

from . import bodies, panes, runs
from .cards import coupled_beta
from .widgets import IntSlider

__all__ = ["MapMixin", "shipped_map"]


@functools.lru_cache(maxsize=1)
def shipped_map():
    """The numerical map shipped with core (read once, shared read-only by all sessions)."""
    return core.load_default_map()


class MapMixin:
    """The numerical map (methods of :class:`app.explorer.Explorer`)."""

    def _build_map(self):
        self.map_points = IntSlider(label="Map grid (points per axis)", start=3,
                                    end=runs.MAP_MAX_POINTS, value=min(12, runs.MAP_MAX_POINTS),
                                    sizing_mode="stretch_width")
        self.map_button = pn.widgets.Button(label="Compute the numerical map", color="primary",
                                            sizing_mode="stretch_width", css_classes=["map-compute"])
        self.map_cancel_button = pn.widgets.Button(label="Stop", color="warning", disabled=True, width=80)
        self.map_bar = pn.indicators.Progress(value=0, max=100, visible=False, sizing_mode="stretch_width")
        self.map_button.on_click(lambda e: self.compute_map())
        self.map_cancel_button.on_click(lambda e: self._map_cancel.set())
        self._map_cancel = threading.Event()
        self.map_scheduler = None  # core.sweep's default: a local process pool
        try:
            self.map_table = shipped_map()
            self.map_label = "shipped 40×40, cylinder, plane kernel (drawn beside cylinder runs only)"
        except (OSError, ValueError) as e:  # pragma: no cover - a broken install
            self.map_status = f"shipped map not available: {e}"
        self.param.watch(self._show_map_progress, ["map_running", "map_progress"])
        self._watch_coupled()

    # ------------------------------------------------------------------ the coupled limit curve
    def _watch_coupled(self) -> None:
        """Follow the contact: a coupled one (Dundurs β ≠ 0) gets its coupled limit curve on the map, computed off
        the event loop (:data:`app.runs.LIMIT_CURVES`, cached per β, μ and grid) and drawn as each amplitude's
        bracket comes."""
        self._coupled_key, self._coupled_listener = None, None
        self.param.watch(lambda e: self._follow_coupled(), "contact")
        self.state.param.watch(lambda e: self._follow_coupled(), ["loading", "body"])
        doc = getattr(self, "_doc", None)
        if doc is not None and doc.session_context is not None:  # a served session: when it ends, it waits no more
            pn.state.on_session_destroyed(lambda ctx: self._stop_waiting_for_coupled())
        self._follow_coupled()

    def _stop_waiting_for_coupled(self) -> None:
        """This session waits for no coupled limit curve any more (it ended): a curve nobody else waits for stops at
        its next run, and none is sent into the ended session."""
        if self._coupled_key is not None:
            runs.LIMIT_CURVES.cancel(self._coupled_key, self._coupled_listener)
        self._coupled_key = None

    def _coupled_request(self) -> tuple | None:
        """``(beta, mu)`` of the coupled limit curve the map draws for the inputs: a coupled contact of the cylinder
        rocked under constant loads (the curve's runs); None otherwise."""
        beta = coupled_beta(self.contact)
        if beta is None or self.state.point or self.state.body != bodies.DEFAULT or self.state.history_options():
            return None
        return beta, float(self.contact.mu)

    def _follow_coupled(self) -> None:
        request = self._coupled_request()
        key = None if request is None else runs.LIMIT_CURVES.key(*request)
        if key == self._coupled_key:
            return
        if self._coupled_key is not None:  # the curve of the former contact: this session no longer waits for it
            runs.LIMIT_CURVES.cancel(self._coupled_key, self._coupled_listener)
        self._coupled_key = key
        if request is None:
            self.param.update(coupled_limit=None, coupled_status="")
            return

        def listener(curve, done, error):  # in the curve's thread
            self._in_session(self._coupled_arrived, key, curve, done, error)

        self._coupled_listener = listener
        beta, mu = key[:2]
        grid = runs.LIMIT_CURVES.grid
        empty = core.CoupledLimitCurve(beta, mu, float(grid["dx"]), float(grid["tol"]), int(grid["periods"]), ())
        self.param.update(coupled_limit=empty, coupled_status=self._coupled_text(empty, False, ""))
        _, curve = runs.LIMIT_CURVES.request(beta, mu, listener)
        if curve is not None:
            self._coupled_arrived(key, curve, True, "")

    def _coupled_arrived(self, key, curve, done: bool, error: str) -> None:
        """A curve's progress, in the session: drawn if it is still the current contact's."""
        if key != self._coupled_key:
            return
        self.param.update(coupled_limit=curve, coupled_status=self._coupled_text(curve, done, error))

    @staticmethod
    def _coupled_text(curve, done: bool, error: str) -> str:
        n = len(runs.LIMIT_CURVES.grid["w"])
        what = (f"β = {curve.beta:.3g}, μ = {curve.mu:.3g}, dx = a/{round(1 / curve.dx)}, brackets "
                f"{100 * curve.tol:.0f} % of eq 35")
        if error:
            return f"coupled limit {error} ({len(curve.points)} of {n} amplitudes; {what})"
        if not done:
            return f"computing the coupled limit… {len(curve.points)} of {n} amplitudes ({what})"
        return (f"coupled limit: {len(curve.points)} amplitudes, {curve.runs} coupled runs, {curve.cpu_s:.0f} s CPU "
                f"({what})")

    def _map_options(self) -> dict:
        """Solver options of a map sweep: the current solver settings; the strip kernel's L/a and ν are the current
        contact's (:func:`core.strip_options`), whatever run is shown."""
        opts = dict(periods=self.state.periods, dx=self.state.dx, kernel=self.state.kernel,
                    shape=self.state.schedule)
        if self.state.point:  # the current body's map: no kernel (the half-space's)
            options = self.state.solver_options()  # a body with a grid of its own: its dx
            body = options.get("body")
            if body is None:  # an ellipsoid: by name, with its ratio
                ratio = (float(self.state.body_object().ratio) if "ratio" in {
                    p.name for p in bodies.parameters(self.state.body)} else None)
                return dict(periods=self.state.periods, dx=self.state.dx, shape=self.state.schedule,
                            body=self.state.body, ratio=ratio)
            return dict(periods=self.state.periods, dx=options["dx"], shape=self.state.schedule, body=body)
        if self.state.body != bodies.DEFAULT:  # another line body: the object, with its parameters
            opts["body"] = self.state.body_object()
        run = self.state.solver_options() if self.contact is not None else {}
        if "beta" in run:  # a coupled contact: its map is swept coupled, as its runs are (plane kernel, its beta, mu)
            opts.update(kernel="plane", beta=run["beta"], mu=run["mu"])
        if opts["kernel"] == "strip":
            if self.contact is None:  # invalid geometry: no strip to take L/a from
                opts["kernel"] = "plane"
            else:
                opts.update(core.strip_options(self.contact))
        return opts

    def _map_history(self) -> tuple[dict, float, str]:
        """The loading history of a map sweep: ``(options, largest ft, note for the label)``.

        The (ft, w) map takes the rocking histories: under the normal loading at the current amplitude A and
        phase, up to ``ft = 0.98 (1 - A)`` (beyond, the lowest normal force reaches gross sliding). Under the
        tangential loading (a fixed centre: w plays no part) the plane is (mean ft, amplitude A): the options
        carry no amplitude, :meth:`compute_map` makes it the sweep's second axis."""
        options = self.state.history_options()
        if not options:
            return {}, 0.95, ""
        if options["history"] == "tangential":
            return ({"history": "tangential"}, 0.95,
                    ", tangential loading: the (mean ft, amplitude) plane, gross sliding beyond |ft| + A = 1")
        A = float(options["amplitude"])
        return options, min(0.95, 0.98 * (1.0 - A)), (f", normal force ±{100 * A:.0f} %, phase "
                                                      f"{self.state.phase:.0f}°")

    def compute_map(self) -> None:
        """Sweep the (ft, w) plane (the tangential loading: (mean ft, amplitude)) with the current solver settings, off the UI thread, and overlay it on the map."""
        if self.map_running:
            return
        if not runs.MAP_SLOT.acquire(blocking=False):
            self.map_status = "another numerical map is being computed on this server; try again shortly."
            return
        n = int(self.map_points.value)
        history, ft_max, note = self._map_history()
        grid = np.linspace(0.02, 0.95, n)
        ft_grid = np.linspace(0.02, ft_max, n)
        if history.get("history") == "tangential":  # the amplitude is the plane's second axis, at a fixed centre;
            history, grid = {**history, "amplitude": grid}, [0.0]  # beyond |ft| + A = 1 the runs are error rows
        opts = {**self._map_options(), **history}
        self._map_cancel = cancel = threading.Event()
        headless = self._doc is None or self._doc.session_context is None

        def progress(done, total):
            self._in_session(setattr, self, "map_progress", int(100 * done / max(total, 1)))

        def work():
            try:
                return core.sweep(ft_grid, grid, self.map_scheduler, max_workers=runs.MAP_WORKERS, progress=progress,
                                  cancel=cancel, timeout=runs.MAP_BUDGET_S, **opts)
            finally:
                runs.MAP_SLOT.release()

        label = (f"computed {n}×{n}, {opts['body']}, {opts['periods']} periods" if "body" in opts
                 else f"computed {n}×{n}, {opts['kernel']} kernel, {opts['periods']} periods") + note

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

    def _show_map_progress(self, *_):
        self.map_bar.param.update(value=self.map_progress, visible=self.map_running)
        self.map_button.disabled = self.map_running
        self.map_cancel_button.disabled = not self.map_running


    def map_controls(self) -> pn.Column:
        """The 'compute the numerical map' action, its progress and its outcome."""
        status = panes.Markdown(pn.bind(lambda s, l: f"Map shown: **{l}**. {s}", self.param.map_status,
                                          self.param.map_label), css_classes=["map-status"],
                                  sizing_mode="stretch_width")
        coupled = panes.HTML(pn.bind(lambda s: f"<span class='coupled-status-text'>{html.escape(s)}</span>" if s else "",
                                     self.param.coupled_status), css_classes=["coupled-status"],
                             sizing_mode="stretch_width", margin=(0, 10))
        self.map_points.param.update(sizing_mode="stretch_width", min_width=200)
        self.map_button.param.update(sizing_mode=None, width=250)
        return pn.Column(pn.FlexBox(self.map_points, self.map_button, self.map_cancel_button, flex_wrap="wrap",
                                    align_items="flex-end", sizing_mode="stretch_width"),
                         self.map_bar, status, coupled, sizing_mode="stretch_width")

