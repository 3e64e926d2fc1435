"""The exact shakedown limit of any body by name or object: the registry's body, then its closed form or Melan's.

:func:`ft_limit` and :func:`w_limit` are :func:`core.ft_limit` and
:func:`core.w_limit`: a body given by name (:func:`core.geometry.registry.resolve`, its
default parameters) or as an object; the cylinder's eq 35 and every
ellipsoid's closed form where the body has one (``closed_limit``), Melan's
integral with the bound ``mu p_min`` otherwise (:mod:`core.pressure.melan`). Melan's
limit is computed in :mod:`core.pressure.melan` only; this module adds the names.
"""

from __future__ import annotations

from ..pressure import melan
from ..geometry.registry import resolve

__all__ = ["ft_limit", "w_limit", "fretting_energy"]


def ft_limit(w, body="cylinder", *, normal="auto", dx=None):
    """The exact shakedown limit ``ft_lim(w)`` of a body: closed form where known, Melan's integral otherwise.

    Parameters
    ----------
    w : array_like
        ``W / a`` in [0, 1] (numerical bodies: [0, 1)).
    body : str or body object
        A name of :data:`core.geometry.registry.REGISTRY` (default parameters: ``"cylinder"``, eq 35; ``"sphere"``,
        ``"ellipsoid"``, ``(1 - w)^2 (2 + w)/2``; ``"punch"``, ...) or a body object
        (``core.Punch(flat=0.5)``, a height map, a cone).
    normal, dx :
        For the numerical bodies (see :func:`core.pressure.melan.lowest_pressure`).

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


def fretting_energy(amplitude, body="cylinder", nu=0.5):
    """Energy dissipated per cycle by a contact under a constant normal load and an oscillating tangential one.

    Cattaneo-Mindlin partial slip with Masing's rule: the unloading branch from
    ``Qmax`` is the monotone curve doubled and scaled by 2, ``d(Q) = d(Qmax) -
    2 d_m((Qmax - Q)/2)``, so the steady loop depends on the range of ``Q``
    only, not on its mean. With ``f = Q/(mu P)`` between ``-A`` and ``A``
    (``A`` the amplitude) its area is ``E = 4 A d_m(A) - 8 int_0^A d_m``:

    * cylinder (plane strain, per unit length), from the hysteretic part
      ``d_m(f) = (1/pi) (1 - f) ln(1 - f) mu P/E*`` of the monotone
      displacement: ``E = (2/pi) [1 - (1 - A)^2 + 2 (1 - A) ln(1 - A)]``
      ``mu^2 P^2/E*``;
    * rigid sphere on a half-space of Poisson ratio ``nu`` (Mindlin and
      Deresiewicz, neglecting the transverse traction), from
      ``d_m(f) = 3 (2 - nu)/(8 (1 - nu)) [1 - (1 - f)^(2/3)] mu Fn/(E* a)``:
      ``E = 9 (2 - nu)/(5 (1 - nu)) [1 - (1 - A)^(5/3) - (5A/6) (1 + (1 - A)^(2/3))]``
      ``mu^2 Fn^2/(E* a)``.

    Parameters
    ----------
    amplitude : float or array_like
        ``A``: the amplitude of ``Q/(mu P)`` (a sphere: ``Q/(mu Fn)``), in [0, 1).
    body : str or body object
        The contact: a body with a closed-form loop (``fretting_energy``): the
        cylinder, the sphere (a name of :data:`core.geometry.registry.REGISTRY` or the object).
    nu : float
        The half-space's Poisson ratio (the sphere only), in [0, 0.5].

    Returns
    -------
    float or ndarray
        ``E``, in ``mu^2 P^2/E*`` per unit length (cylinder) or ``mu^2 Fn^2/(E* a)`` (sphere).

    References
    ----------
    K.L. Johnson, Contact Mechanics (1985), sections 7.2 and 7.4; R.D. Mindlin and
    H. Deresiewicz, J. Appl. Mech. 20 (1953) 327-344.

    Examples
    --------
    >>> from core import fretting_energy
    >>> round(float(fretting_energy(0.5)), 6), round(float(fretting_energy(0.35, "sphere")), 7)
    (0.036194, 0.0093676)
    """
    spec = resolve(body)
    own = getattr(spec, "fretting_energy", None)
    if own is None:
        raise ValueError(f"body must have a closed-form fretting loop (cylinder, sphere), got {body!r:.60}")
    return own(amplitude, nu)
