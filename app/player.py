"""The cycle player: a period, a step in it, step back / play / step forward, the speed, and where the body is.

:class:`PlayerMixin` builds the player's widgets (:meth:`~PlayerMixin._build_player`), keeps them in step with
the run shown and moves the explorer's ``frame`` (the step every figure draws).
"""

from __future__ import annotations

import numpy as np
import panel as pn

import core

from . import panes
from .styles import CSS
from .units import time_axis
from .widgets import IntSlider

__all__ = ["PlayerMixin", "PLAY", "PAUSE"]

#: The play button's label when stopped, and while it plays (it says what a click will do).
PLAY, PAUSE = "▶ Play", "❚❚ Pause"


class PlayerMixin:
    """The cycle player (methods of :class:`app.explorer.Explorer`)."""

    def _build_player(self):
        # the cycle player: a period (0 = the loading, then 1, 2, ...), then the steps of that period
        # compact: the player sits in one row above the figures it drives (two rows on a 1024 px screen)
        self.period_slider = IntSlider(label="Period (0 = loading)", start=0, end=1, value=1, width=140,
                                       margin=(2, 8))
        self.step_slider = IntSlider(label="Step in the period", start=0, end=1, value=0, css_classes=["step-slider"],
                                     width=160, margin=(2, 8))
        self.step_back = pn.widgets.Button(label="◀ Step", width=70, css_classes=["step-back"], margin=(2, 3))
        self.play = pn.widgets.Toggle(label=PLAY, width=82, css_classes=["play-period"], margin=(2, 3))
        self.step_forward = pn.widgets.Button(label="Step ▶", width=70, css_classes=["step-forward"], margin=(2, 3))
        self.speed = pn.widgets.Select(options={"slow": 400, "normal": 150, "fast": 60}, value=150, width=96,
                                       margin=(2, 8), description="Player speed: 400, 150 or 60 ms a step",
                                       css_classes=["player-speed"], stylesheets=[":host select {font-size: 14px;}"])
        self.readout = panes.HTML("", css_classes=["readout"], sizing_mode="stretch_width", stylesheets=[CSS],
                                  margin=(8, 6))
        self._autoplay = None
        self.period_slider.param.watch(self._period_changed, "value")
        self.step_slider.param.watch(self._update_frame, "value")
        self.step_back.on_click(lambda e: self.step(-1))
        self.step_forward.on_click(lambda e: self.step(+1))
        self.play.param.watch(self._toggle_play, "value")
        # the label flips in the browser at the click, before the server answers (and the server sets it too)
        self.play.jscallback(value=f"cb_obj.label = cb_obj.active ? {PAUSE!r} : {PLAY!r};")
        self.speed.param.watch(self._toggle_play, "value")

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
        self.play.label = PAUSE if self.play.value else PLAY
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
        """Where the player is: step, period, time [periods], the centre's position and the rolling direction."""
        if result is None:
            return "<div class='readout'>no run yet</div>"
        k = int(np.clip(frame, 0, result.xc.size - 1))
        period = int(result.period[k]) + 1
        xc = float(result.xc[k])
        dx = xc - float(result.xc[k - 1]) if k > 0 else 0.0
        where = f"xc = {xc * units.x:.3g} {'mm' if units.system == 'physical' else 'a'}"
        if dx > 0:
            moving = "rolling to +x"
        elif dx < 0:
            moving = "rolling to −x"
        else:
            moving = "at rest (loading)"
        phase = "loading" if period == 0 else f"period {period} of {result.periods}"
        t = time_axis(result)[k]
        return (f"<div class='readout' title='t = {t:.3f} periods'>Step <b>{k + 1}</b>/{result.xc.size} · {phase} · "
                f"centre <b>{where}</b> · {moving}</div>")

    def player_controls(self) -> pn.FlexBox:
        """The cycle player: period, step, step back / play / step forward, speed, and where the cylinder is."""
        readout = pn.bind(self._readout, self.param.result, self.param.frame, self.param.plot_units)
        self.readout.object = readout
        return pn.FlexBox(
            self.period_slider, self.step_slider,
            pn.Row(self.step_back, self.play, self.step_forward, sizing_mode=None, margin=(16, 0, 0, 0)),
            pn.Row(self.speed, self.readout, sizing_mode="stretch_width", margin=0),
            flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width", css_classes=["cycle-player"],
            margin=(4, 0, 0, 0))

