"""The default grid of every body, and every grid kind's solver defaults, in one place.

A run's element width ``dx`` (in the contact's semi-axis ``a`` along the
rocking) defaults to the grid of its body: the line contact (the cylinder)
runs at ``a/40``, the point contacts (sphere, ellipsoid and every other body
the 3D solver runs) at ``a/20``, where the increment per period of a
ratcheting sphere (ft 0.4, w 0.6) is 0.4 % below ``a/40``'s at an eighth of its
cost, and (ft 0.6, w 0.3) within 0.25 % of CONTACT's at the same grid (see
:data:`core.solvers.solver3d.DEFAULT_DX_3D` and ``benchmarks/solver3d.py``).
:func:`core.simulate_cycles`, :func:`core.simulate_point_contact`,
:func:`core.sweep`, the limit searches, :func:`core.converged_increment` and
the command line all take their default from :func:`default_dx`; every
result reports the ``dx`` it ran at (``summary()["dx"]``).

Each grid kind (``"line"``: a line contact's elements on the 1D engine;
``"patch"``: a point contact's square elements) has its defaults in
:data:`GRID_DEFAULTS` (:class:`GridDefaults`): the element width, the
smallest one a run accepts, the KKT tolerance of every step, the periodic
tolerance and the steps run between checks of the budget. Every entry point
(:func:`core.simulate_cycles`, :func:`core.api.solver.solve_schedule`,
:func:`core.api.point_runs.solve_point_schedule`, the static solves) reads them here.

This module imports nothing heavy (the command line reads it to print its help).
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["default_dx", "default_dW", "DEFAULT_DX_LINE", "DEFAULT_DX_POINT", "GridDefaults", "GRID_DEFAULTS"]

#: Default element width [a] of the line contact (the cylinder): 80 elements across the contact.
DEFAULT_DX_LINE = 1.0 / 40.0
#: Default element side [a] of the point contacts: 40 elements across the contact.
DEFAULT_DX_POINT = 1.0 / 20.0


class GridDefaults(NamedTuple):
    """The defaults of one grid kind's runs (see :data:`GRID_DEFAULTS`)."""

    #: Default element width [a].
    dx: float
    #: Smallest element width [a] a run accepts.
    min_dx: float
    #: KKT tolerance of every step (tractions in mu p0, slips in mu P/E*, loads in mu P).
    tol: float
    #: Change of the traction [mu p0] between the ends of two periods below which the state repeats
    #: (None: the KKT tolerance, exact for the line solvers).
    periodic_tol: float | None
    #: Steps run between checks of the time budget, ``cancel`` and ``progress``.
    chunk: int


#: Every grid kind's defaults: ``"line"`` (the exact active-set solvers, solved to round-off) and ``"patch"``
#: (the inexact 3D projected CG: a looser tolerance, a periodic tolerance of 100 tol, since a period repeats
#: to about 10 tol, and shorter chunks, since a patch step costs far more than a line step).
GRID_DEFAULTS = {
    "line": GridDefaults(dx=DEFAULT_DX_LINE, min_dx=1e-4, tol=1e-10, periodic_tol=None, chunk=256),
    "patch": GridDefaults(dx=DEFAULT_DX_POINT, min_dx=0.005, tol=1e-8, periodic_tol=1e-6, chunk=50),
}


def default_dx(body="cylinder") -> float:
    """The default element width [a] of a body's runs.

    Parameters
    ----------
    body : str or object
        A body name (``"cylinder"``, ``"sphere"``, ``"ellipsoid"``, ...) or a
        body object. An object with a ``default_dx`` attribute gives its own;
        otherwise the line contacts (their names, or an object with
        ``dim == 1`` such as any :class:`core.geometry.bodies.Body`) get
        :data:`DEFAULT_DX_LINE` and every other body (a point contact)
        :data:`DEFAULT_DX_POINT`.

    Returns
    -------
    float

    Examples
    --------
    >>> from core.geometry.resolution import default_dx
    >>> default_dx("cylinder"), default_dx("sphere"), default_dx("ellipsoid")
    (0.025, 0.05, 0.05)
    """
    own = getattr(body, "default_dx", None)
    if own is not None and not isinstance(body, str):
        return float(own)
    from .registry import kind  # the one code that knows body names

    return GRID_DEFAULTS["line" if kind(body) == "line" else "patch"].dx


def default_dW(body, dx: float) -> float:
    """The default rocking step [a] of a body's runs at element width ``dx``.

    The body's own ``rocking_step(dx)`` where it has one (the cone: its elements are longer along the contact
    line than across it, and its increment hardly moves with a step of two elements), else ``dx``: the contact's
    edges cross one element a step.

    Parameters
    ----------
    body : str or object
        A body name or a body object.
    dx : float
        The run's element width [a].

    Returns
    -------
    float

    Examples
    --------
    >>> from core.geometry.resolution import default_dW
    >>> default_dW("cylinder", 0.025)
    0.025
    """
    own = getattr(body, "rocking_step", None)
    return float(dx) if own is None or isinstance(body, str) else float(own(dx))
