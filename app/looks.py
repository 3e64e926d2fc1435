"""The looks every figure module of the explorer shares: the fonts, the line width, the colour-blind-safe
palette, a regime's colour and marker, the empty layer and the memo of layer data.

A module of its own so that :mod:`app.plots` (the figures and their registry, :data:`app.plots.FIGURES`) and the
figure modules it registers (:mod:`app.regime_map`) read the same looks without importing each other. No
physics and no Bokeh model here.
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = ["FONT", "LINE", "OKABE_ITO", "REGIME_COLORS", "REGIME_MARKERS", "EMPTY", "memo"]

#: Font sizes readable on a projector.
FONT = {"title": 17, "labels": 16, "xticks": 14, "yticks": 14, "legend": 14, "cticks": 13}
#: Line width of a curve [px].
LINE = 3
#: Okabe and Ito's colour-blind-safe palette (distinct under deuteranopia, protanopia and tritanopia).
OKABE_ITO = {"orange": "#E69F00", "sky": "#56B4E9", "green": "#009E73", "yellow": "#F0E442", "blue": "#0072B2",
             "vermillion": "#D55E00", "purple": "#CC79A7", "black": "#000000", "grey": "#999999"}
#: Colour and marker of a point on the map, by numerical regime (None: not solved yet): shape is the second cue.
REGIME_COLORS = {"shakedown": OKABE_ITO["blue"], "cyclic slip": OKABE_ITO["orange"],
                 "ratcheting": OKABE_ITO["vermillion"], "undetermined": OKABE_ITO["grey"], None: OKABE_ITO["grey"]}
REGIME_MARKERS = {"shakedown": "circle", "cyclic slip": "hex", "ratcheting": "triangle", "undetermined": "diamond",
                  None: "square"}
#: The data of an empty curve or points layer (a layer that does not apply to the inputs).
EMPTY = (np.zeros(0), np.zeros(0))


def memo(fn):
    """Keep the last few outputs: an unchanged layer is returned as the same object, so the figure skips it."""
    return functools.lru_cache(maxsize=4)(fn)
