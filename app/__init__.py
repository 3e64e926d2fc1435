"""Shakedown Explorer: the Panel app over :mod:`core` (widgets, layout and plots only)."""
