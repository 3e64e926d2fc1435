"""For slides: every figure of the explorer saves as PNG (the toolbar's save button) or as SVG (here).

Bokeh's save tool saves what the figure is drawn with, the canvas: a PNG. A figure view can also draw
itself once into an SVG context (``view.export("svg")``), whatever its output backend, so SVG needs no
second, slower way of drawing the live figures: :func:`save_svg` is a figure menu and a button that does
this in the browser and downloads the file, named after the figure (and, for the explorer's figures, the
run's ft and w). The explorer's tab and the paper's figures tab each have one, for their own figures.
"""

from __future__ import annotations

import re

import panel as pn

from . import plots
from .serving import VIEWS_JS  # (the page's views: the browser tests find figures with it too)

__all__ = ["VIEWS_JS", "FIGURE_VIEWS_JS", "FIGURE_BOX_JS", "SVG_JS", "stem", "figure_titles", "save_svg"]

#: JavaScript: ``figure_views()``, the view of every Bokeh figure drawn in the page.
FIGURE_VIEWS_JS = VIEWS_JS + """
const figure_views = () => all_views().filter((v) => v.model && v.canvas_view && typeof v.export === 'function');
"""

#: JavaScript for ``page.evaluate(FIGURE_BOX_JS, title)``: the viewport box (x, y, width, height) of the figure
#: titled ``title`` once drawn, null before.
FIGURE_BOX_JS = "(title) => {" + FIGURE_VIEWS_JS + """
  const v = figure_views().find((v) => v.model.title && v.model.title.text === title);
  if (!v) return null;
  const r = v.el.getBoundingClientRect();
  return {x: r.x, y: r.y, width: r.width, height: r.height};
}"""

#: Finds the figure view titled ``select.value`` in the page and downloads it as SVG, named
#: ``shakedown_<names[title]>`` and SUFFIX, a JavaScript expression (:func:`save_svg` puts the run's values there).
SVG_JS = FIGURE_VIEWS_JS + """
const title = select.value;
const found = figure_views().filter((v) => v.model.title && v.model.title.text === title);
if (!found.length) {  // the explorer draws a figure when the page is scrolled to it
  window.alert(`"${title}" is not drawn yet: scroll to it, then save it.`);
  return;
}
const get = (d, k) => (d instanceof Map ? d.get(k) : d[k]);
const suffix = SUFFIX;
(async () => {
  const blob = await found[0].export('svg').to_blob();
  const link = document.createElement('a');
  link.href = URL.createObjectURL(blob);
  link.download = `shakedown_${get(names, title)}${suffix}.svg`;
  link.dispatchEvent(new MouseEvent('click'));
  setTimeout(() => URL.revokeObjectURL(link.href), 10000);
})();
"""


def stem(text: str) -> str:
    """``text`` as a file-name part: lower case, runs of anything but letters and digits as one ``_``."""
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def figure_titles() -> dict[str, str]:
    """Title of each figure of :data:`app.plots.FIGURES` -> the short name its SVG file is given."""
    return {f["opts"]["title"]: stem(name) for name, f in plots.FIGURES.items()}


def save_svg(names: dict[str, str], run: dict | None = None, offered: list[str] | None = None) -> pn.FlexBox:
    """A figure menu and a 'Save as SVG' button (drawn in the browser, no server work).

    Parameters
    ----------
    names : dict
        Title of each figure offered -> the name its file is given (``shakedown_<name>.svg``).
    run : dict, optional
        File-name key -> a widget with a numeric ``value`` (e.g. ``{"ft": slider}``): appended to the
        name as ``_ft0.30``, so a file says which run it shows.
    offered : list of str, optional
        The titles the menu offers (default: all of ``names``); the menu is the box's ``figure_menu`` attribute,
        whose options can change later (e.g. with the body shown) within ``names``.

    Returns
    -------
    panel.FlexBox
    """
    if not names:
        raise ValueError("names: at least one figure title is needed")
    offered = list(names) if offered is None else list(offered)
    if not offered or not set(offered) <= set(names):
        raise ValueError(f"offered: a non-empty subset of the names' titles is needed, got {offered}")
    # wide enough for the longest title (about 9 px a character at 15 px), so the menu does not cut it
    width = min(480, max(300, 9 * max(map(len, names)) + 40))
    select = pn.widgets.Select(options=offered, value=offered[0], width=width, margin=(8, 10),
                               css_classes=["svg-figure"], stylesheets=[":host select {font-size: 15px;}"])
    button = pn.widgets.Button(label="Save as SVG", width=120, margin=(8, 10), css_classes=["save-svg"],
                               color="light")
    run = dict(run or {})
    if not all(key.isidentifier() and key not in ("select", "names") for key in run):
        raise ValueError(f"run: keys must be identifiers other than select and names, got {list(run)}")
    # each widget is an argument of its own (Panel links only top-level arguments to their Bokeh models)
    suffix = " + ".join(f"'_{key}' + {key}.value.toFixed(2)" for key in run) or "''"
    button.js_on_click(args=dict(select=select, names=dict(names), **run), code=SVG_JS.replace("SUFFIX", suffix))
    note = pn.pane.HTML("<span style='font-size: 15px'>For slides: the toolbar's ⤓ saves a PNG; as SVG:</span>",
                        margin=(14, 0, 0, 10))
    box = pn.FlexBox(note, select, button, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width",
                     css_classes=["save-svg-row"])
    box.figure_menu = select
    return box
