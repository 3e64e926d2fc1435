"""The explorer in a notebook: ``from app import Explorer; Explorer()`` in JupyterLab or Jupyter.

The served page (``app/main.py``) wraps :class:`app.explorer.Explorer` in a
page template; a notebook cell has no template, so :class:`Explorer` here lays
out the same explorer's input widgets (:meth:`app.explorer.Explorer.sidebar`)
beside its main area (:meth:`app.explorer.Explorer.main_area`: the verdict,
the cards, the cycle player and the figures). Nothing is built until an
``Explorer`` is made, and no Panel model exists at import time. Run
``pn.extension("katex")`` in the notebook first (the "About the model" tab
typesets equations with KaTeX).

Examples
--------
In a notebook cell::

    import panel as pn
    from app import Explorer

    pn.extension("katex")
    ex = Explorer(ft=0.3, w=0.5)
    ex                       # the explorer; ex.result is the run shown, ex.state its inputs
"""

from __future__ import annotations

import panel as pn
import param

from app.explorer import Explorer as _PageExplorer
from app.state import ExplorerState

__all__ = ["Explorer"]

#: Width of the input column [px], as the served page's sidebar.
SIDEBAR_WIDTH = 340


class Explorer(pn.viewable.Viewer):
    """The shakedown explorer for a notebook: the served page's inputs beside its figures.

    Parameters
    ----------
    state : app.state.ExplorerState, optional
        The inputs to start from (default: the app's defaults).
    query : str, optional
        URL-style parameters (``"?ft=0.3&w=0.5"``), applied and validated as
        the served page does.
    **inputs
        Input values set on the state (``ft=0.3, w=0.5, mu=0.58, ...``: any
        parameter of :class:`app.state.ExplorerState`).

    Attributes
    ----------
    explorer : app.explorer.Explorer
        The explorer itself (its ``result``, its widgets and figures).
    state : app.state.ExplorerState
        Its inputs: set them from code (``ex.state.ft = 0.2``) and the view follows.
    """

    sidebar_width = param.Integer(default=SIDEBAR_WIDTH, bounds=(200, 800), doc="Width of the input column [px].")

    def __init__(self, state: ExplorerState | None = None, query: str | None = None, **inputs):
        own = {k: inputs.pop(k) for k in list(inputs) if k in self.param}
        super().__init__(**own)
        state = state if state is not None else ExplorerState()
        if inputs:
            state.param.update(**inputs)
        self.explorer = _PageExplorer(state=state, query=query)
        self.state = self.explorer.state
        self._layout = None

    @property
    def result(self):
        """The solver run shown (a :class:`core.CycleResult` or :class:`core.PointContactResult`)."""
        return self.explorer.result

    def __panel__(self) -> pn.viewable.Viewable:
        if self._layout is None:
            inputs = pn.Column(*self.explorer.sidebar(), width=self.sidebar_width,
                               css_classes=["explorer-inputs"])
            self._layout = pn.Row(inputs, self.explorer.main_area(), sizing_mode="stretch_width")
            self._draw_all()
            self.explorer.state.param.watch(lambda e: self._draw_all(), "body")
        return self._layout

    def _draw_all(self) -> None:
        """Draw every figure of the current body now. The served page draws a figure when the browser scrolls
        near it (a sentinel per figure); a notebook's output is drawn at once, and a static copy of it (an
        exported or documentation page) has no kernel to ask for the rest later."""
        for sentinel in list(self.explorer.sentinels.values()):
            sentinel.shown = True
