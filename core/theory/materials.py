"""Materials of a contact: the effective modulus ``E*``, Dundurs' ``beta`` and the pairs users meet.

Two elastic bodies in plane strain meet through two combinations of their
constants (Dundurs 1969): the effective modulus

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2

(a rigid body, ``E = inf``, adds nothing) and the second Dundurs constant

    beta = [(1 - 2 nu2)/G2 - (1 - 2 nu1)/G1] / (2 [(1 - nu1)/G1 + (1 - nu2)/G2]),

``G_i = E_i / (2 (1 + nu_i))``. **Body 1 is the rocking body** (the
cylinder), body 2 the substrate; with this sign a rigid body on a compressible
substrate (``nu2 < 0.5``) has ``beta > 0``: under pressure the substrate's
surface is drawn in towards the contact more than the body's, so friction on
the substrate points outwards. ``beta`` vanishes for identical materials and
for a rigid body on an incompressible substrate (the uncoupled contact of the
paper), and ``|beta| < 0.5`` for every pair. Its sign is the opposite of
Johnson's (Contact Mechanics, eq 5.4b: body 1 the indenter, ``beta < 0`` for
a rigid one); only the direction of the coupled tractions and of the pressure's
shift depends on it.

With ``beta != 0`` the pressure moves the surfaces tangentially and the
tangential traction moves them normally (:mod:`core.elastic.coupling`), so the normal
and tangential problems are solved together (:mod:`core.solvers.coupled`). This
module also holds the closed forms the coupled operator is checked against:
Spence's central stick zone under a growing normal load (:func:`spence_stick_ratio`)
and Bufler's sliding pressure (:func:`bufler_exponent`, :func:`bufler_pressure`).

References
----------
.. [1] J. Dundurs, "Discussion of edge-bonded dissimilar orthogonal elastic
   wedges under normal and shear loading", J. Appl. Mech. 36 (1969) 650-652.
.. [2] K. L. Johnson, *Contact Mechanics*, CUP 1985, sections 5.4 and 7.1.
.. [3] D. A. Spence, "The Hertz contact problem with finite friction",
   J. Elasticity 5 (1975) 297-319.
.. [4] H. Bufler, "Zur Theorie der rollenden Reibung", Ingenieur-Archiv 27
   (1959) 137-152.
.. [5] D. A. Hills, D. Nowell, A. Sackfield, *Mechanics of Elastic Contacts*,
   Butterworth-Heinemann 1993.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base._validate import check_scalar

__all__ = ["Material", "MaterialPair", "MATERIALS", "PAIRS", "MAX_BETA", "COUPLING_THRESHOLD", "effective_modulus", "dundurs_beta",
           "check_beta", "material_pair", "spence_stick_ratio", "bufler_exponent", "bufler_pressure"]

#: ``|beta|`` of every real pair is below 0.5 (it is 0.5 for a rigid body on a substrate with ``nu = 0``).
MAX_BETA = 0.5
#: ``|beta|`` from which a physical line contact (:class:`core.Contact`) runs coupled: below it (steel on rubber,
#: ``|beta| ~ 1e-5``) the coupling's effect is far below the grid's error (Spence's stick zone is then the whole
#: contact to double precision up to ``|beta|/mu ~ 0.07``), and the uncoupled solvers run, as before.
COUPLING_THRESHOLD = 1e-3


@dataclass(frozen=True)
class Material:
    """An isotropic elastic material.

    Parameters
    ----------
    E : float
        Young's modulus [Pa], > 0; ``math.inf`` for a rigid body.
    nu : float
        Poisson ratio [-], in [0, 0.5].
    name : str
        How it is printed.
    """

    E: float
    nu: float
    name: str = ""

    def __post_init__(self):
        object.__setattr__(self, "E", check_scalar("E", self.E, 0.0, None, lo_closed=False, allow_inf=True))
        object.__setattr__(self, "nu", check_scalar("nu", self.nu, 0.0, 0.5))

    @property
    def G(self) -> float:
        """Shear modulus ``E / (2 (1 + nu))`` [Pa] (inf if rigid)."""
        return math.inf if math.isinf(self.E) else self.E / (2.0 * (1.0 + self.nu))

    @property
    def compliance(self) -> float:
        """Plane-strain compliance ``(1 - nu^2) / E`` [1/Pa] (0 if rigid)."""
        return 0.0 if math.isinf(self.E) else (1.0 - self.nu * self.nu) / self.E


#: Common materials (room temperature, handbook values).
MATERIALS = {
    "steel": Material(210e9, 0.30, "steel"),
    "aluminium": Material(70e9, 0.33, "aluminium"),
    "titanium": Material(110e9, 0.34, "titanium"),
    "PMMA": Material(3.0e9, 0.35, "PMMA"),
    "rubber": Material(3.6e6, 0.50, "rubber"),  # the paper's silicone rubber (Table 1)
    "rigid": Material(math.inf, 0.30, "rigid"),
    "incompressible": Material(3.6e6, 0.50, "incompressible"),
}


def effective_modulus(E1, nu1, E2, nu2) -> float:
    """``E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`` [Pa] of body 1 on body 2.

    Raises
    ------
    ValueError
        An ``E <= 0`` or a Poisson ratio outside [0, 0.5] (naming it), or two rigid bodies.
    """
    b1, b2 = Material(_named("E1", E1), _named_nu("nu1", nu1)), Material(_named("E2", E2), _named_nu("nu2", nu2))
    c = b1.compliance + b2.compliance
    if c == 0.0:
        raise ValueError("E1 and E2 cannot both be infinite (two rigid bodies have no contact compliance)")
    return 1.0 / c


def dundurs_beta(E1, nu1, E2, nu2) -> float:
    """Dundurs' ``beta`` of the rocking body 1 on the substrate 2 (the module's sign: ``> 0`` rigid on compressible).

    Parameters
    ----------
    E1, nu1 : float
        The rocking body's Young's modulus [Pa] (> 0, ``inf``: rigid) and Poisson ratio (in [0, 0.5]).
    E2, nu2 : float
        The substrate's, likewise.

    Returns
    -------
    float
        ``beta`` in (-0.5, 0.5].

    Examples
    --------
    >>> round(dundurs_beta(float("inf"), 0.3, 1e9, 0.2), 4)   # rigid on nu = 0.2: (1 - 2 nu)/(2 (1 - nu))
    0.375
    >>> dundurs_beta(210e9, 0.3, 210e9, 0.3), dundurs_beta(float("inf"), 0.3, 5e6, 0.5)
    (0.0, 0.0)
    """
    effective_modulus(E1, nu1, E2, nu2)  # validates, and refuses two rigid bodies
    b1, b2 = Material(E1, nu1), Material(E2, nu2)
    num = _over(1.0 - 2.0 * b2.nu, b2.G) - _over(1.0 - 2.0 * b1.nu, b1.G)
    den = 2.0 * (_over(1.0 - b1.nu, b1.G) + _over(1.0 - b2.nu, b2.G))
    return num / den


def _over(a, G):
    return 0.0 if math.isinf(G) else a / G


def _named(name, E):
    return check_scalar(name, E, 0.0, None, lo_closed=False, allow_inf=True)


def _named_nu(name, nu):
    return check_scalar(name, nu, 0.0, 0.5)


def check_beta(beta) -> float:
    """``beta`` as a float if ``|beta| < 0.5`` (:data:`MAX_BETA`), else ValueError naming it."""
    return check_scalar("beta", beta, -MAX_BETA, MAX_BETA, lo_closed=False, hi_closed=False)


@dataclass(frozen=True)
class MaterialPair:
    """The rocking body's material on the substrate's: ``E*``, ``beta`` and the shear moduli.

    Parameters
    ----------
    body, substrate : Material
        Body 1 (the rocking body) and body 2.
    """

    body: Material
    substrate: Material

    def __post_init__(self):
        effective_modulus(self.body.E, self.body.nu, self.substrate.E, self.substrate.nu)

    @property
    def name(self) -> str:
        """``"body/substrate"``."""
        return f"{self.body.name or 'body'}/{self.substrate.name or 'substrate'}"

    @property
    def E_star(self) -> float:
        """Effective modulus [Pa]."""
        return effective_modulus(self.body.E, self.body.nu, self.substrate.E, self.substrate.nu)

    @property
    def beta(self) -> float:
        """Dundurs' ``beta`` (:func:`dundurs_beta`)."""
        return dundurs_beta(self.body.E, self.body.nu, self.substrate.E, self.substrate.nu)

    def contact_inputs(self) -> dict:
        """``E1, nu1, E2, nu2`` for :class:`core.Contact`."""
        return dict(E1=self.body.E, nu1=self.body.nu, E2=self.substrate.E, nu2=self.substrate.nu)


#: The presets: rocking body / substrate.
PAIRS = {
    "steel/steel": MaterialPair(MATERIALS["steel"], MATERIALS["steel"]),
    "steel/aluminium": MaterialPair(MATERIALS["steel"], MATERIALS["aluminium"]),
    "steel/titanium": MaterialPair(MATERIALS["steel"], MATERIALS["titanium"]),
    "steel/PMMA": MaterialPair(MATERIALS["steel"], MATERIALS["PMMA"]),
    "steel/rubber": MaterialPair(MATERIALS["steel"], MATERIALS["rubber"]),
    "rigid/incompressible": MaterialPair(MATERIALS["rigid"], MATERIALS["incompressible"]),
}


def material_pair(materials) -> MaterialPair:
    """A :class:`MaterialPair` from a preset name of :data:`PAIRS` (``"steel/aluminium"``, case-insensitive), from
    ``"body/substrate"`` with names of :data:`MATERIALS`, or a pair itself.

    Examples
    --------
    >>> p = material_pair("steel/aluminium")
    >>> round(p.beta, 3), round(p.E_star / 1e9, 1)
    (0.117, 58.6)
    """
    if isinstance(materials, MaterialPair):
        return materials
    if isinstance(materials, str):
        key = {k.lower(): k for k in PAIRS}.get(materials.strip().lower())
        if key is not None:
            return PAIRS[key]
        names = {k.lower(): k for k in MATERIALS}
        parts = [names.get(s.strip().lower()) for s in materials.split("/")]
        if len(parts) == 2 and None not in parts:
            return MaterialPair(MATERIALS[parts[0]], MATERIALS[parts[1]])
    raise ValueError(f"materials must be one of {sorted(PAIRS)} or 'body/substrate' with materials of "
                     f"{sorted(MATERIALS)}, got {materials!r:.60}")


# ---- the closed forms of coupled contact (checks of core.elastic.coupling and core.solvers.coupled) ----------------------
def spence_stick_ratio(beta_over_mu) -> float:
    """Spence's central stick zone ``c/a`` of a cylinder pressed by a growing normal load with friction.

    Under a monotonically growing load the contact of a Hertzian profile grows
    self-similarly; with ``beta != 0`` its edges slip outwards (on the
    substrate, for ``beta > 0``) and a central zone ``|x| < c`` sticks, with
    ``c/a`` fixed by ``|beta|/mu`` alone:

        K'(c/a) / K(c/a) = |beta| / mu,

    ``K`` the complete elliptic integral of the first kind of modulus ``c/a``
    and ``K'`` that of the complementary modulus. It follows from the
    incremental flat-punch problem (each load increment of a Hertzian contact
    is a flat punch of the current width) whose tractions must be bounded at
    ``x = +-c``, with the pressure Hertz's (the effect of the shear traction on
    the pressure neglected: Goodman's approximation, error ``O(beta mu)``).
    ``|beta|/mu -> 0`` gives full stick (``c -> a``); ``|beta|/mu = 1`` gives
    ``c/a = 1/sqrt(2)``.

    Parameters
    ----------
    beta_over_mu : float
        ``|beta| / mu``, > 0.

    Returns
    -------
    float
        ``c/a`` in (0, 1).

    Examples
    --------
    >>> round(spence_stick_ratio(1.0), 6)
    0.707107
    """
    from scipy.optimize import brentq
    from scipy.special import ellipk

    r = check_scalar("beta_over_mu", beta_over_mu, 0.0, None, lo_closed=False)

    def f(k):
        return ellipk(1.0 - k * k) / ellipk(k * k) - r

    lo, hi = 1e-300, 1.0 - 1e-16
    if f(hi) > 0.0:  # |beta|/mu below about 0.075: the stick zone is the contact to double precision
        return hi
    return float(brentq(f, lo, hi, xtol=1e-15, rtol=1e-15))


def bufler_exponent(beta, mu, direction=1) -> float:
    """The exponent ``gamma`` of Bufler's sliding pressure, ``tan(pi gamma) = mu beta`` times the sliding direction.

    A cylinder sliding on a substrate (every point slipping, the substrate's
    traction ``q = direction mu p`` along x) carries the pressure of
    :func:`bufler_pressure`; ``gamma > 0`` shifts it towards ``-x``.

    Parameters
    ----------
    beta : float
        Dundurs' ``beta`` (this module's sign), ``|beta| < 0.5``.
    mu : float
        Friction coefficient, > 0.
    direction : {1, -1}
        Sign of the substrate's traction (the direction the body slides in).
    """
    beta = check_beta(beta)
    mu = check_scalar("mu", mu, 0.0, None, lo_closed=False)
    if direction not in (1, -1):
        raise ValueError(f"direction must be 1 or -1, got {direction!r:.40}")
    return math.atan(direction * mu * beta) / math.pi


def bufler_pressure(x, gamma):
    """Bufler's sliding pressure of a Hertzian profile [its peak's Hertz unit, ``p0``], on its own contact.

    ``p(t) = b cos(pi gamma) (1 - t)^(1/2 + gamma) (1 + t)^(1/2 - gamma)`` with ``t = (x - e)/b``: the
    contact is ``|x - e| < b`` with ``b = 1/sqrt(1 - 4 gamma^2)`` (its half-width under the nominal load, in
    ``a``) and ``e = -2 gamma b`` (its centre, from the profile's lowest point). It solves
    ``PV integral p(s)/(x - s) ds - pi tan(pi gamma) p(x) = pi x`` (the normal problem of a sliding
    Hertzian profile, in the units of :mod:`core.pressure.normal`) with ``integral p dx = pi/2``, bounded at both edges
    (Bufler 1959; checked by quadrature in ``tests/test_materials.py``); ``gamma = 0`` is Hertz's ``sqrt(1 - x^2)``.

    Parameters
    ----------
    x : array_like
        Positions [a] from the profile's lowest point.
    gamma : float
        :func:`bufler_exponent`, in (-1/2, 1/2).

    Returns
    -------
    ndarray
        The pressure [p0]; 0 out of contact.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1.2, 1.2, 240001)
    >>> p = bufler_pressure(x, 0.05)
    >>> round(float(np.trapezoid(p, x)), 5) == round(np.pi / 2, 5)
    True
    """
    gamma = check_scalar("gamma", gamma, -0.5, 0.5, lo_closed=False, hi_closed=False)
    b, e = _bufler_geometry(gamma)
    t = (np.asarray(x, dtype=float) - e) / b
    inside = np.abs(t) < 1.0
    tt = np.where(inside, t, 0.0)
    p = b * math.cos(math.pi * gamma) * (1.0 - tt) ** (0.5 + gamma) * (1.0 + tt) ** (0.5 - gamma)
    return np.where(inside, p, 0.0)


def _bufler_geometry(gamma):
    """Half-width ``b`` and centre ``e`` [a] of the sliding contact under the nominal load."""
    b = 1.0 / math.sqrt(1.0 - 4.0 * gamma * gamma)
    return b, -2.0 * gamma * b
