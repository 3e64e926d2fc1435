"""Display units of the figures and the time axis of a run (scales and labels only: no physics)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import core

__all__ = ["Units", "make_units", "time_axis", "along_ft"]


@dataclass(frozen=True)
class Units:
    """Scales from the normalised results of :mod:`core` to the displayed units, and axis labels."""

    system: str
    x: float = 1.0
    x_label: str = "x / a"
    p: float = 1.0
    p_label: str = "p / p0"
    q: float = 1.0
    q_label: str = "q / (μ p0)"
    u: float = 1.0
    u_label: str = "U [μ P/E*]"
    mu: float = 1.0


def make_units(system: str, contact: core.Contact | None, kernel: str, u0: float | None = None,
               point: bool = False) -> Units:
    """Units of the plots.

    Parameters
    ----------
    system : {"normalised", "physical"}
        Physical units need ``contact``; without one they fall back to normalised.
    contact : Contact or None
        The current contact (SI units).
    kernel : {"strip", "plane"}
        With the strip kernel, normalised displacements are shown as ``U/U0``.
    u0 : float, optional
        ``U0`` of the strip kernel [μ P/E*].
    point : bool
        A point contact's run: its normalised displacements are in μ Fn/(E* a).
    """
    mu = 1.0 if contact is None else contact.mu
    if system == "physical" and contact is not None:
        return Units("physical", x=contact.a * 1e3, x_label="x [mm]", p=contact.p0 / 1e6, p_label="p [MPa]",
                     q=contact.traction_unit / 1e6, q_label="q [MPa]", u=contact.displacement_unit * 1e6,
                     u_label="U [µm]", mu=mu)
    if point:
        return Units("normalised", u_label="u [μ Fn/(E* a)]", mu=mu)
    if kernel == "strip" and u0:
        return Units("normalised", u=1.0 / u0, u_label="u = U / U0", mu=mu)
    return Units("normalised", mu=mu)



def time_axis(result: core.CycleResult) -> np.ndarray:
    """Time of each step in periods: period ``p`` spans ``(p, p + 1]``, the loading ends at 0."""
    m = max(1, int(np.count_nonzero(result.period == 0)))
    n_load = int(np.count_nonzero(result.period < 0))
    return (np.arange(result.xc.size) + 1 - n_load) / m


def along_ft(result) -> np.ndarray:
    """The rigid-body displacement of each step along Ft: a cylinder's own, a point contact's projected on the
    direction of Ft (``result.angle``) [the run's displacement unit]."""
    if isinstance(result, core.PointContactResult):
        return result.displacement @ np.array([math.cos(result.angle), math.sin(result.angle)])
    return result.displacement
