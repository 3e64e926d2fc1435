"""Compare runs: pin the current run and overlay up to four pinned runs on the figures of their body (the
cylinder's displacement, increment and traction; a point contact's displacement, increment and cut along
``y = 0``; the paper's Figs 6 and 7 show three amplitudes at once), with a table of the pinned runs'
parameters and verdicts.

:class:`Pins` (a ``pn.viewable.Viewer``: the pin / clear buttons and the table, with an unpin menu) keeps
the session's :class:`~app.pinned.Pin` list; the layers they add to the figures are :mod:`app.pinned`'s.
"""

from __future__ import annotations

import html
import math

import panel as pn
import param

import core

from . import bodies, panes
from .cards import body_name, input_digits, prediction
from .pinned import MAX_PINS, PIN_STYLES, Pin, label

__all__ = ["MAX_PINS", "PIN_STYLES", "Pin", "Pins", "table_html"]

_CSS = """
.pins {border-collapse: collapse; font-size: 15px; margin: 4px 0; max-width: 100%;}
.pins-wrap {overflow-x: auto; max-width: 100%;}
.pins th, .pins td {padding: 2px 6px; border-bottom: 1px solid #eee; text-align: right;}
.pins small {color: #444;}
.pins th:first-child, .pins td:first-child {text-align: left;}
.pins .swatch {display: inline-block; width: 26px; height: 0; border-top-width: 4px; vertical-align: middle;
               margin-right: 6px;}
.pins-empty {font-size: 15px; color: #444;}
"""


def _fmt(v, digits=3) -> str:
    return "–" if v is None or not math.isfinite(v) else f"{v:.{digits}g}"


def _spec(result):
    """The body of a run as an object (a point run's body; a line run's ``body_spec``), or its name."""
    if isinstance(result, core.PointContactResult):
        return result.body
    return getattr(result, "body_spec", None) or result.body


def _body(result) -> str:
    """The body of a run, with its parameters (a line run: its kernel too)."""
    spec = _spec(result)
    text = body_name(spec)
    params = {} if isinstance(spec, str) else bodies.shown_parameters(text, spec)
    if params:
        text += " (" + ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in params.items()) + ")"
    return text if isinstance(result, core.PointContactResult) else f"{text}, {result.kernel}"


def table_html(pins) -> str:
    """The pinned runs' parameters and verdicts, one row each, with the swatch of their curves."""
    if not pins:
        return ("<div class='pins-empty'>No run pinned: pinned runs stay on the displacement, increment and "
                "traction figures.</div>")
    head = ("<tr><th>run</th><th>ft, w</th><th>μ</th><th>periods</th><th>solver</th>"
            "<th>exact limit</th><th>c_sd / a</th><th>|Δu| last</th></tr>")
    rows = []
    for k, p in enumerate(pins):
        r, i = p.result, p.inputs
        color, dash = PIN_STYLES[k]
        style = {"dashed": "dashed", "dotted": "dotted"}.get(dash, "dashed" if "dash" in dash else "solid")
        inc = abs(float(r.increment_per_period[-1])) if r.increment_per_period.size else math.nan
        u0 = getattr(r, "u0", None)
        point = isinstance(r, core.PointContactResult)
        inc_text = f"{inc / u0:.3g} U0" if u0 else f"{inc:.3g} {'μFn/(E*a)' if point else 'μP/E*'}"
        predicted, rule = prediction(i["ft"], i["w"], _spec(r))
        rows.append(
            f"<tr data-pin='{k + 1}'><td><span class='swatch' style='border-top: 4px {style} {color}'></span>"
            f"{label(k)} <small>{html.escape(_body(r))}</small></td><td>{', '.join(input_digits(i['ft'], i['w'], _spec(r)))}</td>"
            f"<td>{i['mu']:.2f}</td><td>{r.periods}</td><td><b>{html.escape(str(r.regime))}</b></td>"
            f"<td title='{html.escape(rule)}'>{html.escape(predicted)}</td>"
            f"<td>{_fmt(r.stick_halfwidth)}</td><td>{inc_text}</td></tr>")
    return f"<div class='pins-wrap'><table class='pins'>{head}{''.join(rows)}</table></div>"


class Pins(pn.viewable.Viewer):
    """The pinned runs of one session, with their controls: pin the current run, unpin one, clear all.

    Parameters
    ----------
    explorer : app.explorer.Explorer
        The session's explorer: its current run is what :meth:`pin` pins, and its ``pinned`` parameter
        (an input of the figures) follows :attr:`pins`.
    """

    pins = param.List(default=[], item_type=Pin, doc="The pinned runs, in the order they were pinned.")
    message = param.String(default="", doc="Why the last pin was refused, if it was.")

    def __init__(self, explorer, **params):
        self.explorer = explorer
        super().__init__(**params)
        self.pin_button = pn.widgets.Button(label="Pin this run", width=150, css_classes=["pin-run"],
)
        self.clear_button = pn.widgets.Button(label="Clear pins", width=110, css_classes=["clear-pins"],
                                              disabled=True)
        self.unpin = pn.widgets.Select(label="Unpin", options=["–"], value="–", width=110, disabled=True,
                                       css_classes=["unpin"])
        self.pin_button.on_click(lambda e: self.pin())
        self.clear_button.on_click(lambda e: self.clear())
        self.unpin.param.watch(self._unpin_selected, "value")
        self.table = panes.HTML(table_html([]), stylesheets=[_CSS], sizing_mode="stretch_width",
                                  css_classes=["pins-table"], margin=(0, 10))
        self.note = panes.HTML("", margin=(0, 10), visible=False, css_classes=["pins-message"])
        self._show()

    def pin(self) -> bool:
        """Pin the explorer's current run; False (and a message) if there is none, it is pinned, or four are."""
        ex = self.explorer
        r = ex.result
        if r is None or ex.pending or not ex._shows(r, ex.state.ft, ex.state.w, ex.state.point):
            self.message = "No finished run of the current inputs to pin yet."
            return False
        pin = Pin(r, ex.contact, dict(ft=float(r.params.get("ft", ex.state.ft)),
                                      w=float(r.params.get("w", ex.state.w)), mu=float(ex.state.mu),
                                      body=_body(r), periods=int(r.periods), dx=float(r.dx),
                                      R=ex.state.R, L=ex.state.L, Fn=ex.state.Fn, E2=ex.state.E2))
        if any(p.key == pin.key for p in self.pins):
            self.message = "This run is pinned already."
            return False
        if len(self.pins) >= MAX_PINS:
            self.message = f"{MAX_PINS} runs are pinned: unpin one first."
            return False
        self.message = ""
        self.pins = [*self.pins, pin]
        return True

    def remove(self, k: int) -> None:
        """Unpin the ``k``-th pinned run (from 0)."""
        if 0 <= k < len(self.pins):
            self.pins = [p for i, p in enumerate(self.pins) if i != k]

    def clear(self) -> None:
        """Unpin every run."""
        self.message = ""
        self.pins = []

    def _unpin_selected(self, event):
        if event.new != "–":
            self.remove(int(event.new.split()[-1]) - 1)

    @param.depends("pins", watch=True)
    def _show(self):
        n = len(self.pins)
        self.explorer.pinned = tuple(self.pins)
        self.table.object = table_html(self.pins)
        self.clear_button.disabled = n == 0
        self.unpin.param.update(options=["–", *[label(k) for k in range(n)]], value="–", disabled=n == 0)

    @param.depends("message", watch=True)
    def _show_message(self):
        self.note.param.update(object=f"<i>{html.escape(self.message)}</i>", visible=bool(self.message))

    def __panel__(self):
        return pn.Column(
            pn.FlexBox(pn.pane.Markdown("**Compare runs**", margin=(12, 10, 0, 10), width=130, sizing_mode=None),
                       self.pin_button, self.unpin, self.clear_button, self.note,
                       flex_wrap="wrap", align_items="center", sizing_mode="stretch_width"),
            self.table, sizing_mode="stretch_width", css_classes=["compare-runs"])
