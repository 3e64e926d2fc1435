"""The default grid of every body, in one place.

A run's element width ``dx`` (in the contact's semi-axis ``a`` along the
rocking) defaults to the grid of its body: the line contact (the cylinder)
runs at ``a/40``, the point contacts (sphere, ellipsoid and every other body
the 3D solver runs) at ``a/20``, where the increment per period of a
ratcheting sphere (ft 0.4, w 0.6) is 0.4 % below ``a/40``'s at an eighth of its
cost, and (ft 0.6, w 0.3) within 0.25 % of CONTACT's at the same grid (see
:data:`core.solver3d.DEFAULT_DX_3D` and ``benchmarks/solver3d.py``).
:func:`core.simulate_cycles`, :func:`core.simulate_point_contact`,
:func:`core.sweep`, the limit searches, :func:`core.converged_increment` and
the command line all take their default from :func:`default_dx`; every
result reports the ``dx`` it ran at (``summary()["dx"]``).

This module imports nothing heavy (the command line reads it to print its help).
"""

from __future__ import annotations

__all__ = ["default_dx", "DEFAULT_DX_LINE", "DEFAULT_DX_POINT", "LINE_BODIES"]

#: Default element width [a] of the line contact (the cylinder): 80 elements across the contact.
DEFAULT_DX_LINE = 1.0 / 40.0
#: Default element side [a] of the point contacts: 40 elements across the contact.
DEFAULT_DX_POINT = 1.0 / 20.0
#: Names of the bodies run by the line-contact (2D) solver.
LINE_BODIES = ("cylinder", "punch")


def default_dx(body="cylinder") -> float:
    """The default element width [a] of a body's runs.

    Parameters
    ----------
    body : str or object
        A body name (``"cylinder"``, ``"sphere"``, ``"ellipsoid"``, ...) or a
        body object. An object with a ``default_dx`` attribute gives its own;
        otherwise the line contacts (their names, or an object with
        ``dim == 1`` such as any :class:`core.bodies.Body`) get
        :data:`DEFAULT_DX_LINE` and every other body (a point contact)
        :data:`DEFAULT_DX_POINT`.

    Returns
    -------
    float

    Examples
    --------
    >>> from core.resolution import default_dx
    >>> default_dx("cylinder"), default_dx("sphere"), default_dx("ellipsoid")
    (0.025, 0.05, 0.05)
    """
    own = getattr(body, "default_dx", None)
    if own is not None and not isinstance(body, str):
        return float(own)
    if body is None or getattr(body, "dim", None) == 1 or (isinstance(body, str) and body in LINE_BODIES):
        return DEFAULT_DX_LINE
    return DEFAULT_DX_POINT
