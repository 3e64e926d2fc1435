"""For slides: every figure of the explorer saves as PNG (the toolbar's save button) or as SVG (here).

Bokeh's save tool saves what the figure is drawn with, the canvas: a PNG. A figure view can also draw
itself once into an SVG context (``view.export("svg")``), whatever its output backend, so SVG needs no
second, slower way of drawing the live figures: :func:`save_svg` is a figure menu and a button that does
this in the browser and downloads the file, named after the figure and the run's ft and w.
"""

from __future__ import annotations

import re

import panel as pn

from . import plots

__all__ = ["SVG_JS", "figure_titles", "save_svg"]

#: Finds the figure view titled ``select.value`` in the page and downloads it as SVG.
SVG_JS = """
const title = select.value;
const seen = new Set(), found = [];
const walk = (v) => {
  if (!v || seen.has(v)) return;
  seen.add(v);
  if (v.model && v.model.title && v.model.title.text === title && v.canvas_view && typeof v.export === 'function')
    found.push(v);
  for (const c of (v.child_views ?? [])) walk(c);
  try { for (const c of v.children()) walk(c); } catch (e) {}
};
const idx = Bokeh.index;
for (const r of (idx.roots ? [...idx.roots] : (idx.values ? [...idx.values()] : Object.values(idx)))) walk(r);
if (!found.length) return;
(async () => {
  const blob = await found[0].export('svg').to_blob();
  const link = document.createElement('a');
  link.href = URL.createObjectURL(blob);
  link.download = `shakedown_${names[title]}_ft${ft.value.toFixed(2)}_w${w.value.toFixed(2)}.svg`;
  link.dispatchEvent(new MouseEvent('click'));
  setTimeout(() => URL.revokeObjectURL(link.href), 10000);
})();
"""


def figure_titles() -> dict[str, str]:
    """Title of each figure of :data:`app.plots.FIGURES` -> the short name its SVG file is given."""
    return {f["opts"]["title"]: re.sub(r"[^a-z0-9]+", "_", name.lower()) for name, f in plots.FIGURES.items()}


def save_svg(explorer) -> pn.FlexBox:
    """A figure menu and a 'Save as SVG' button for ``explorer``'s figures (drawn in the browser, no server work)."""
    names = figure_titles()
    select = pn.widgets.Select(options=list(names), value=next(iter(names)), width=300, margin=(8, 10),
                               css_classes=["svg-figure"], stylesheets=[":host select {font-size: 15px;}"])
    button = pn.widgets.Button(label="Save as SVG", width=120, margin=(8, 10), css_classes=["save-svg"],
                               color="light")
    button.js_on_click(args=dict(select=select, ft=explorer.ft_slider, w=explorer.w_slider, names=names), code=SVG_JS)
    note = pn.pane.HTML("<span style='font-size: 15px'>For slides: the toolbar's ⤓ saves a PNG; as SVG:</span>",
                        margin=(14, 0, 0, 10))
    return pn.FlexBox(note, select, button, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width",
                      css_classes=["save-svg-row"])
