"""The exact shakedown limit of any body by name or object: the registry's body, then its closed form or Melan's.

:func:`ft_limit` and :func:`w_limit` are :func:`core.ft_limit` and
:func:`core.w_limit`: a body given by name (:func:`core.registry.resolve`, its
default parameters) or as an object; the cylinder's eq 35 and every
ellipsoid's closed form where the body has one (``closed_limit``), Melan's
integral with the bound ``mu p_min`` otherwise (:mod:`core.melan`). Melan's
limit is computed in :mod:`core.melan` only; this module adds the names.
"""

from __future__ import annotations

from . import melan
from .registry import resolve

__all__ = ["ft_limit", "w_limit"]


def ft_limit(w, body="cylinder", *, normal="auto", dx=None):
    """The exact shakedown limit ``ft_lim(w)`` of a body: closed form where known, Melan's integral otherwise.

    Parameters
    ----------
    w : array_like
        ``W / a`` in [0, 1] (numerical bodies: [0, 1)).
    body : str or body object
        A name of :data:`core.registry.REGISTRY` (default parameters: ``"cylinder"``, eq 35; ``"sphere"``,
        ``"ellipsoid"``, ``(1 - w)^2 (2 + w)/2``; ``"punch"``, ...) or a body object
        (``core.Punch(flat=0.5)``, a height map, a cone).
    normal, dx :
        For the numerical bodies (see :func:`core.melan.lowest_pressure`).

    Returns
    -------
    ndarray
        ``ft_lim`` in [0, 1], decreasing in ``w``.

    Examples
    --------
    >>> import core
    >>> round(float(core.ft_limit(0.26)), 4)
    0.6727
    >>> round(float(core.ft_limit(0.3, body=core.Punch(flat=0.5))), 4)
    0.5527
    """
    return melan.ft_limit(w, resolve(body), normal=normal, dx=dx)


def w_limit(ft, body="cylinder", *, normal="auto", dx=None):
    """Exact inverse of :func:`ft_limit`: the largest amplitude that shakes down at ``ft``.

    Examples
    --------
    >>> import core
    >>> round(float(core.w_limit(0.3)), 4)
    0.5851
    >>> round(float(core.w_limit(0.5527, body=core.Punch(flat=0.5))), 3)
    0.3
    """
    return melan.w_limit(ft, resolve(body), normal=normal, dx=dx)
