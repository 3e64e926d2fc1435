"""The shakedown map's numerical layer: the shipped map, or one computed for the current solver settings.

:class:`MapMixin` builds the map's controls (grid size, compute, stop, progress, outcome) and runs the sweep off
the event loop (:func:`core.sweep`, one map at a time per server).
"""

from __future__ import annotations

import functools
import threading

import numpy as np
import panel as pn

import core

from . import bodies, panes, runs
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
        if opts["kernel"] == "strip":
            if self.contact is None:  # invalid geometry: no strip to take L/a from
                opts["kernel"] = "plane"
            else:
                opts.update(core.strip_options(self.contact))
        return opts

    def _map_history(self) -> tuple[dict | None, float, str]:
        """The loading history of a map sweep: ``(options, largest ft, note for the label)``; options None (and the
        note says why) for the tangential loading, whose plane is not (ft, w).

        The (ft, w) map takes the rocking histories: under the normal loading at the current amplitude A and
        phase, up to ``ft = 0.98 (1 - A)`` (beyond, the lowest normal force reaches gross sliding)."""
        options = self.state.history_options()
        if not options:
            return {}, 0.95, ""
        if options["history"] == "tangential":
            return None, 0.0, ("no (ft, w) map for the tangential loading (a fixed centre: w plays no part); below "
                               "gross sliding, |ft| + amplitude < 1, it is cyclic slip at any amplitude > 0 "
                               "(user guide: the three regimes)")
        A = float(options["amplitude"])
        return options, min(0.95, 0.98 * (1.0 - A)), (f", normal force ±{100 * A:.0f} %, phase "
                                                      f"{self.state.phase:.0f}°")

    def compute_map(self) -> None:
        """Sweep the (ft, w) plane with the current solver settings, off the UI thread, and overlay it on the map."""
        if self.map_running:
            return
        if not runs.MAP_SLOT.acquire(blocking=False):
            self.map_status = "another numerical map is being computed on this server; try again shortly."
            return
        n = int(self.map_points.value)
        history, ft_max, note = self._map_history()
        if history is None:
            runs.MAP_SLOT.release()
            self.map_status = note
            return
        grid = np.linspace(0.02, 0.95, n)
        ft_grid = np.linspace(0.02, ft_max, n)
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
        self.map_points.param.update(sizing_mode="stretch_width", min_width=200)
        self.map_button.param.update(sizing_mode=None, width=250)
        return pn.Column(pn.FlexBox(self.map_points, self.map_button, self.map_cancel_button, flex_wrap="wrap",
                                    align_items="flex-end", sizing_mode="stretch_width"),
                         self.map_bar, status, sizing_mode="stretch_width")

