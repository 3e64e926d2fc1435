"""Widgets the explorer's modules share: sliders that report at once, and holders filled when first needed."""

from __future__ import annotations

from typing import ClassVar

import panel as pn

__all__ = ["FloatSlider", "IntSlider", "filled_when"]


class _Prompt:
    """Mixin: the widget's value changes reach the explorer at once. Panel waits 50 ms for more changes
    by default (half the latency budget of a slider move); the figures' updates are cheap enough not to."""

    _priority_changes: ClassVar[list[str]] = ["value", "value_throttled"]


class FloatSlider(_Prompt, pn.widgets.FloatSlider):
    pass


class IntSlider(_Prompt, pn.widgets.IntSlider):
    pass


def filled_when(holder: pn.layout.ListLike, ready, build) -> pn.layout.ListLike:
    """``holder``, empty until the reactive boolean ``ready`` first holds, then filled with ``build()``, once.

    What a visitor does not see is not built nor sent with the page (every
    component costs the server milliseconds per session).
    """
    def fill(value):
        if value and not holder.objects:
            holder.objects = list(build())

    fill(ready.rx.value)
    ready.rx.watch(fill)
    return holder

