"""Pinned runs as figure layers: a pinned run is a :class:`Pin` (the solver result, its contact, its inputs);
the figures of :mod:`app.plots` and :mod:`app.point_view` add the layers of :func:`specs` and :func:`layers`
after their own: always :data:`MAX_PINS` layers, empty where no run of the figure's kind is pinned (their
legend entries are then hidden). No physics here: the curves are the pinned runs' own arrays.

The widgets that pin and unpin runs are :class:`app.compare.Pins`.
"""

from __future__ import annotations

from typing import NamedTuple

import holoviews as hv
import numpy as np

import core

from .live import Layer
from .units import along_ft, make_units, time_axis

__all__ = ["MAX_PINS", "PIN_STYLES", "KINDS", "Pin", "specs", "layers", "pin_units", "label"]

#: At most this many pinned runs are drawn at once.
MAX_PINS = 4
#: Colour and dash of pinned run k (Okabe-Ito colours the current run does not use, and a dash of its own: a
#: second cue besides colour).
PIN_STYLES = (("#56B4E9", "dashed"), ("#009E73", "dotdash"), ("#CC79A7", "dotted"), ("#000000", "dashdot"))
#: The figures that draw pinned runs, and the kind of run each draws.
KINDS = {"displacement": core.LineResult, "increments": core.LineResult, "traction": core.LineResult,
         "point_displacement": core.PointContactResult, "point_increments": core.PointContactResult,
         "point_cut": core.PointContactResult}
_EMPTY = (np.zeros(0), np.zeros(0))


class Pin(NamedTuple):
    """A pinned run: the solver's result, its contact (SI) and the inputs it was solved for."""

    result: core.CycleResult | core.PointContactResult
    contact: core.Contact | None
    inputs: dict

    @property
    def key(self) -> tuple:
        """What makes two pins the same run."""
        return tuple(sorted(self.inputs.items()))


def pin_units(pin: Pin, units):
    """The display units of ``pin`` in the current unit system (its own a, p0 and U0)."""
    geometry = None if pin.contact is None else pin.contact.replace(ft=0.0, w=0.0)
    return make_units(units.system, geometry, getattr(pin.result, "kernel", "plane"), getattr(pin.result, "u0", None))


def label(k: int) -> str:
    return f"pin {k + 1}"


def specs(kind: str, kd, vd) -> list:
    """The pinned runs' layers of figure ``kind`` (one of :data:`KINDS`)."""
    width = 2 if "increments" in kind else 3
    return [Layer(hv.Curve, (kd,), (vd,), label(k), dict(color=c, line_dash=d, line_width=width))
            for k, (c, d) in enumerate(PIN_STYLES)]


_MEMO: dict = {}  # (kind, id(result), units) -> (result, data): a pinned layer is the same object until it changes


def _curve(kind: str, pin: Pin | None, units) -> tuple:
    """The data of ``pin``'s layer in figure ``kind``, memoised by identity (the live figure then skips it);
    empty if the figure does not draw runs of the pin's kind (a sphere's run on the cylinder's figures)."""
    if pin is None or not isinstance(pin.result, KINDS[kind]):
        return _EMPTY
    key = (kind, id(pin.result), units)
    hit = _MEMO.get(key)
    if hit is not None and hit[0] is pin.result:
        return hit[1]
    if len(_MEMO) > 64:
        _MEMO.clear()
    data = _data(kind, pin, units)
    _MEMO[key] = (pin.result, data)
    return data


def _data(kind: str, pin: Pin, units) -> tuple:
    r, u = pin.result, pin_units(pin, units)
    if kind in ("displacement", "point_displacement"):
        return time_axis(r), along_ft(r) * u.u
    if kind in ("increments", "point_increments"):
        inc = np.abs(r.increment_per_period) * abs(u.u)
        top = float(inc.max()) if inc.size and inc.max() > 0 else 1.0
        return np.arange(1, inc.size + 1), np.maximum(inc, top * 1e-12)  # as the current run (log scale)
    if kind == "traction":  # the last step's traction (shaken down, or the last of a ratcheting run), as stairs
        return np.repeat(r.edges * u.x, 2)[1:-1], np.repeat(u.q * r.traction[-1], 2)
    if kind == "point_cut":  # the last step's q_x on y = 0, as stairs
        return np.repeat(r.x_edges * u.x, 2)[1:-1], np.repeat(u.q * r.traction_cut[-1][0], 2)
    raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")


def layers(kind: str, pins: tuple, units) -> tuple:
    """The data of the :data:`MAX_PINS` pinned layers of figure ``kind`` (empty where nothing is pinned)."""
    pins = tuple(pins)[:MAX_PINS]
    return tuple(_curve(kind, pins[k] if k < len(pins) else None, units) for k in range(MAX_PINS))
