"""An engineer's view of the inputs: the tangential force Ft in N and the rocking amplitude W in µm (or the rocking
angle W/R), instead of ft = Ft/(μ Fn) and w = W/a, and the number of cycles the creep is extrapolated to.

Shown in physical units. The physical inputs and the normalised sliders are two views of one state
(:class:`app.state.ExplorerState`): an edit of either moves the other. The conversions are the paper's
definitions: ft = Ft/(μ Fn), w = W/a, and a rocking angle θ moves the contact centre by W = R θ (rolling
without slip).
"""

from __future__ import annotations

import math

import panel as pn
import param

__all__ = ["EngineerInputs"]

_HELP = ("Physical inputs: they set the ft and w sliders (ft = Ft/(μ Fn), w = W/a, and W = R θ for a cylinder "
         "rocking by ±θ without slip).")


class EngineerInputs(pn.viewable.Viewer):
    """Ft [N], W [µm], the rocking angle θ [mrad] and the cycles N of one session's explorer.

    Parameters
    ----------
    explorer : app.explorer.Explorer
        The session's explorer: its state's ``ft``, ``w``, ``mu``, ``Fn`` and ``R``, and its contact's
        half-width ``a``.
    """

    cycles = param.Integer(default=10**6, bounds=(1, 10**12), doc="Cycles the creep per period is extrapolated to.")

    def __init__(self, explorer, **params):
        super().__init__(**params)
        self.explorer = explorer
        kw = dict(sizing_mode="stretch_width", format="0,0.[000]")
        self.force = pn.widgets.FloatInput(label="Ft, tangential force [N]", start=0.0, step=1.0, **kw)
        self.amplitude = pn.widgets.FloatInput(label="W, rocking amplitude [µm]", start=0.0, step=10.0, **kw)
        self.angle = pn.widgets.FloatInput(label="θ, rocking angle ±[mrad] (W = R θ)", start=0.0, step=0.1, **kw)
        self.cycles_input = pn.widgets.IntInput.from_param(self.param.cycles, label="N, cycles for the creep",
                                                           sizing_mode="stretch_width", step=1000)
        self._syncing = False
        self.force.param.watch(self._force_edited, "value")
        self.amplitude.param.watch(self._amplitude_edited, "value")
        self.angle.param.watch(self._angle_edited, "value")
        s = explorer.state
        s.param.watch(self._show, ["ft", "w", "mu", "Fn", "R"])
        explorer.param.watch(self._show, "geometry")
        self._show()

    # ---- the state's values in physical units -------------------------------------------------------------------
    def _a(self) -> float | None:
        """The contact's half-width [m] (None if the geometry is invalid)."""
        g = self.explorer.geometry
        return None if g is None else float(g.a)

    def _show(self, *_):
        s, a = self.explorer.state, self._a()
        self._syncing = True
        try:
            self.force.value = round(s.ft * s.mu * s.Fn, 6)
            if a is not None:
                self.amplitude.value = round(s.w * a * 1e6, 3)
                self.angle.value = round(s.w * a / (s.R * 1e-3) * 1e3, 6)
        finally:
            self._syncing = False

    # ---- edits ----------------------------------------------------------------------------------------------------
    def _set(self, **values):
        """Set the normalised inputs, within the sliders' ranges."""
        s = self.explorer.state
        clipped = {k: min(max(round(v, 6), 0.0), s.param[k].softbounds[1]) for k, v in values.items()
                   if v is not None and math.isfinite(v)}
        if clipped:
            s.param.update(**clipped)
        self._show()  # a clipped value shows what was applied

    def _force_edited(self, event):
        s = self.explorer.state
        if not self._syncing and event.new is not None:
            self._set(ft=event.new / (s.mu * s.Fn))

    def _amplitude_edited(self, event):
        a = self._a()
        if not self._syncing and event.new is not None and a:
            self._set(w=event.new * 1e-6 / a)

    def _angle_edited(self, event):
        a, s = self._a(), self.explorer.state
        if not self._syncing and event.new is not None and a:
            self._set(w=event.new * 1e-3 * s.R * 1e-3 / a)

    def __panel__(self):
        visible = self.explorer.state.param.units.rx() == "physical"
        return pn.Column(pn.pane.Markdown("### Loads in physical units", margin=(0, 10)), self.force,
                         self.amplitude, self.angle, self.cycles_input,
                         pn.pane.Markdown(_HELP, styles={"font-size": "14px"}, margin=(0, 10)),
                         visible=visible, sizing_mode="stretch_width", css_classes=["engineer-inputs"])
