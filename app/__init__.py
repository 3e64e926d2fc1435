"""Shakedown Explorer: the Panel app over :mod:`core` (widgets, layout and plots only).

``from app import Explorer`` gives the explorer for a notebook (:mod:`app.notebook`); it is imported
on first use, so importing :mod:`app` (or :mod:`core`) imports no Panel.
"""

__all__ = ["Explorer"]


def __getattr__(name):
    if name == "Explorer":
        from .notebook import Explorer

        return Explorer
    raise AttributeError(f"module 'app' has no attribute {name!r}")
