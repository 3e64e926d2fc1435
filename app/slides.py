"""For slides: every figure of the explorer saves as PNG or as SVG.

Bokeh's save tool (the toolbar's download button) saves what the figure is drawn with: a PNG from the
canvas, an SVG when the figure is drawn as SVG (``output_backend="svg"``). Drawing every figure as SVG
costs the browser more on each update, so it is a switch, off by default: :func:`save_format` gives the
switch of one session's explorer.
"""

from __future__ import annotations

import panel as pn

__all__ = ["BACKENDS", "save_format", "apply_backend"]

#: The switch's labels and the Bokeh output backend each stands for.
BACKENDS = {"PNG": "canvas", "SVG": "svg"}


def apply_backend(explorer, backend: str) -> None:
    """Draw every live figure of ``explorer`` with ``backend`` ("canvas" or "svg")."""
    if backend not in BACKENDS.values():
        raise ValueError(f"backend must be one of {sorted(BACKENDS.values())}, got {backend!r}")
    for live in explorer._live.values():
        if live.figure.output_backend != backend:
            live.figure.output_backend = backend


def save_format(explorer) -> pn.FlexBox:
    """The switch 'figures save as PNG / SVG' of ``explorer``'s figures (kept when a unit switch rebuilds them)."""
    switch = pn.widgets.RadioButtonGroup(options=BACKENDS, value="canvas", width=130, button_type="light",
                                         css_classes=["save-format"], margin=(8, 10))

    def apply(*_):
        apply_backend(explorer, switch.value)
    switch.param.watch(apply, "value")
    explorer.param.watch(apply, "plot_units")  # after the explorer's own redraw: rebuilt figures start as canvas
    note = pn.pane.HTML("<span style='font-size: 15px'>Figures save (toolbar ⤓) as</span>", margin=(14, 0, 0, 10))
    return pn.FlexBox(note, switch, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width",
                      css_classes=["save-format-row"])
