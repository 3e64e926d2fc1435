"""A contact in physical units, and what follows from it: a line contact (:class:`Contact`) or a point contact
(:class:`PointContact`), and their runs.

:class:`Contact` holds the inputs of the model in SI units (m, N, Pa) and
derives the effective quantities of the two-body problem, the Hertz solution
of the line contact and the normalised loads ``ft`` and ``w`` that the rest of
:mod:`core` works with; :class:`PointContact` the same for a sphere or an
ellipsoid. :func:`simulate_contact` runs a :class:`Contact` (the strip kernel
of its length, :func:`strip_options`), :meth:`PointContact.simulate` a point
contact, both through :func:`core.simulate_cycles`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property

from ._validate import check_scalar
from .point_contact import Ellipsoid, _k_minus_e_over_e2
from .solver import DEFAULT_DX, simulate_cycles, simulate_point_contact

__all__ = ["Contact", "PointContact", "PAPER_SIMULATION", "PAPER_EXPERIMENT", "BETA_WARNING_LEVEL", "simulate_contact",
           "strip_options"]

#: Magnitude of Dundurs' beta above which the uncoupled model (beta = 0) is flagged.
BETA_WARNING_LEVEL = 0.05


def _compliance(E: float, nu: float) -> float:
    """(1 - nu^2) / E of one body; 0 for a rigid body (E = inf)."""
    return 0.0 if math.isinf(E) else (1.0 - nu * nu) / E


def _shear(E: float, nu: float) -> float:
    return math.inf if math.isinf(E) else E / (2.0 * (1.0 + nu))


@dataclass(frozen=True)
class Contact:
    """Rigid or elastic cylinder of length ``L`` on a substrate, loaded by Fn and Ft and rocked by W.

    All inputs in SI units. Give exactly one of ``Ft`` / ``ft`` and exactly one
    of ``W`` / ``w`` (neither: 0).

    Parameters
    ----------
    R1 : float
        Radius of the cylinder [m], > 0.
    L : float
        Length of the cylinder [m], > 0; must exceed the contact width.
    Fn : float
        Normal force [N], > 0.
    mu : float
        Coulomb friction coefficient [-], in (0, 10].
    E2, nu2 : float
        Young's modulus [Pa] (> 0, finite) and Poisson ratio [-] (in [0, 0.5])
        of the substrate.
    R2 : float
        Radius of the substrate [m], default ``inf`` (flat).
    E1, nu1 : float
        Young's modulus [Pa] and Poisson ratio of the cylinder; default
        ``E1 = inf`` (rigid).
    Ft : float, optional
        Tangential force [N], in [0, mu Fn).
    ft : float, optional
        ``Ft / (mu Fn)`` in [0, 1).
    W : float, optional
        Rocking amplitude of the contact centre [m], in [0, a).
    w : float, optional
        ``W / a`` in [0, 1).

    Notes
    -----
    The model assumes uncoupled normal and tangential problems (Dundurs
    ``beta = 0``); :attr:`warnings` says when ``|beta|`` exceeds
    :data:`BETA_WARNING_LEVEL`.

    Examples
    --------
    >>> from core import PAPER_EXPERIMENT as c
    >>> round(c.d * 1e3, 2)  # indentation in mm (Table 1: 0.26)
    0.26
    """

    R1: float
    L: float
    Fn: float
    mu: float
    E2: float
    nu2: float
    R2: float = math.inf
    E1: float = math.inf
    nu1: float = 0.3
    Ft: float = 0.0
    ft: float = 0.0
    W: float = 0.0
    w: float = 0.0

    def __init__(self, R1, L, Fn, mu, E2, nu2, R2=math.inf, E1=math.inf, nu1=0.3,
                 Ft=None, ft=None, W=None, w=None):
        set_ = object.__setattr__
        set_(self, "R1", check_scalar("R1", R1, 0.0, None, lo_closed=False, allow_inf=True))
        set_(self, "R2", check_scalar("R2", R2, 0.0, None, lo_closed=False, allow_inf=True))
        set_(self, "L", check_scalar("L", L, 0.0, None, lo_closed=False))
        set_(self, "Fn", check_scalar("Fn", Fn, 0.0, None, lo_closed=False))
        set_(self, "mu", check_scalar("mu", mu, 0.0, 10.0, lo_closed=False))
        set_(self, "E1", check_scalar("E1", E1, 0.0, None, lo_closed=False, allow_inf=True))
        set_(self, "nu1", check_scalar("nu1", nu1, 0.0, 0.5))
        set_(self, "E2", check_scalar("E2", E2, 0.0, None, lo_closed=False))
        set_(self, "nu2", check_scalar("nu2", nu2, 0.0, 0.5))
        if math.isinf(self.R1) and math.isinf(self.R2):
            raise ValueError("R1 and R2 cannot both be infinite")
        if Ft is not None and ft is not None:
            raise ValueError("give either Ft or ft, not both")
        if W is not None and w is not None:
            raise ValueError("give either W or w, not both")
        if Ft is not None:
            Ft = check_scalar("Ft", Ft, 0.0, self.mu * self.Fn, hi_closed=False)
            ft = Ft / (self.mu * self.Fn)
        else:
            ft = check_scalar("ft", 0.0 if ft is None else ft, 0.0, 1.0, hi_closed=False)
            Ft = ft * self.mu * self.Fn
        set_(self, "Ft", Ft)
        set_(self, "ft", ft)
        a = self.a
        if 2.0 * a >= self.L:
            raise ValueError(f"L must exceed the contact width 2a = {2 * a:.4g} m, got {self.L:.4g} m")
        if W is not None:
            W = check_scalar("W", W, 0.0, a, hi_closed=False)
            w = W / a
        else:
            w = check_scalar("w", 0.0 if w is None else w, 0.0, 1.0, hi_closed=False)
            W = w * a
        set_(self, "W", W)
        set_(self, "w", w)

    # ---- effective two-body quantities -----------------------------------
    @property
    def R(self) -> float:
        """Effective radius ``1/R = 1/R1 + 1/R2`` [m]."""
        return 1.0 / (1.0 / self.R1 + 1.0 / self.R2)

    @property
    def E_star(self) -> float:
        """Effective modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` [Pa]."""
        return 1.0 / (_compliance(self.E1, self.nu1) + _compliance(self.E2, self.nu2))

    @property
    def G1(self) -> float:
        """Shear modulus of the cylinder [Pa] (inf if rigid)."""
        return _shear(self.E1, self.nu1)

    @property
    def G2(self) -> float:
        """Shear modulus of the substrate [Pa]."""
        return _shear(self.E2, self.nu2)

    @property
    def G(self) -> float:
        """Effective shear modulus ``1/G = 1/G1 + 1/G2`` [Pa] (eq 32)."""
        return 1.0 / (1.0 / self.G1 + 1.0 / self.G2)

    @property
    def G_star(self) -> float:
        """Tangential modulus ``1/G* = (2 - nu1)/(4 G1) + (2 - nu2)/(4 G2)`` [Pa].

        The convention of the paper's eq 17 (E* = 6.8, G* = 4.5 N/mm^2 for an
        incompressible substrate).
        """
        return 1.0 / ((2.0 - self.nu1) / (4.0 * self.G1) + (2.0 - self.nu2) / (4.0 * self.G2))

    @property
    def nu(self) -> float:
        """Effective Poisson ratio of the Cerruti kernel ``nu = G (nu1/G1 + nu2/G2)`` [-] (eq 33)."""
        return self.G * (self.nu1 / self.G1 + self.nu2 / self.G2)

    @property
    def beta(self) -> float:
        """Dundurs' second constant [-]; the model assumes 0."""
        num = (1 - 2 * self.nu1) / self.G1 - (1 - 2 * self.nu2) / self.G2
        den = 2.0 * ((1 - self.nu1) / self.G1 + (1 - self.nu2) / self.G2)
        return num / den

    # ---- Hertz line contact (eqs 4-6) -------------------------------------
    @property
    def P(self) -> float:
        """Normal load per unit length ``Fn / L`` [N/m]."""
        return self.Fn / self.L

    @cached_property
    def a(self) -> float:
        """Hertz half-width ``sqrt(4 R P / (pi E*))`` [m] (eq 5)."""
        return math.sqrt(4.0 * self.R * self.P / (math.pi * self.E_star))

    @property
    def p0(self) -> float:
        """Peak pressure ``2 P / (pi a)`` [Pa] (eq 5)."""
        return 2.0 * self.P / (math.pi * self.a)

    @property
    def d(self) -> float:
        """Indentation ``(2P/(pi E*)) [(1 + ln 4)/2 + ln(L/a)]`` [m] (eq 6, reconstructed)."""
        return 2.0 * self.P / (math.pi * self.E_star) * (0.5 * (1.0 + math.log(4.0)) + math.log(self.L / self.a))

    @property
    def displacement_unit(self) -> float:
        """``mu P / E*`` [m], the unit of the solver's displacements."""
        return self.mu * self.P / self.E_star

    @property
    def energy_unit(self) -> float:
        """``mu^2 P^2 / E*`` [J/m], the unit of the energy dissipated per period per unit length
        (:attr:`core.CycleResult.dissipation_per_period` of a line contact)."""
        return self.mu * self.P * self.displacement_unit

    @property
    def traction_unit(self) -> float:
        """``mu p0`` [Pa], the unit of normalised tractions."""
        return self.mu * self.p0

    @property
    def warnings(self) -> tuple[str, ...]:
        """Human-readable reasons to distrust the model for this contact."""
        out = []
        if abs(self.beta) > BETA_WARNING_LEVEL:
            out.append(
                f"Dundurs beta = {self.beta:.3f}: the model assumes uncoupled normal and tangential "
                f"problems (beta = 0); |beta| > {BETA_WARNING_LEVEL} makes the results approximate."
            )
        if self.L < 10 * self.a:
            out.append(f"L/a = {self.L / self.a:.1f}: the strip is short; end effects are not modelled.")
        return tuple(out)

    def replace(self, **changes) -> "Contact":
        """A copy with some inputs changed (``ft``/``Ft`` and ``w``/``W`` replace each other)."""
        kw = dict(R1=self.R1, L=self.L, Fn=self.Fn, mu=self.mu, E2=self.E2, nu2=self.nu2,
                  R2=self.R2, E1=self.E1, nu1=self.nu1)
        kw["ft"], kw["w"] = self.ft, self.w
        if "Ft" in changes:
            kw.pop("ft")
        if "W" in changes:
            kw.pop("w")
        kw.update(changes)
        return Contact(**kw)

    def summary(self) -> dict:
        """The inputs and derived quantities as a flat dict of floats (SI units)."""
        keys = ("R1", "R2", "L", "Fn", "Ft", "mu", "E1", "nu1", "E2", "nu2", "W", "ft", "w",
                "R", "E_star", "G", "G_star", "nu", "beta", "P", "a", "p0", "d")
        return {k: float(getattr(self, k)) for k in keys}


def _paper_simulation() -> Contact:
    # eq 17: R = 40 mm, L = 500 mm, Fn/L = 0.39 N/mm, E* = 6.8 MPa, G* = 4.5 MPa
    # (rigid cylinder on an incompressible substrate: E2 = 0.75 E*), mu = 0.58
    return Contact(R1=0.040, L=0.500, Fn=0.39e3 * 0.500, mu=0.58, E2=0.75 * 6.8e6, nu2=0.5)


def _paper_experiment() -> Contact:
    # Table 1: steel on silicone rubber
    return Contact(R1=0.040, L=0.080, Fn=32.2, mu=0.79, E1=206e9, nu1=0.3, E2=3.6e6, nu2=0.5)


#: The paper's numerical reference case (eq 17), ft = w = 0.
PAPER_SIMULATION = _paper_simulation()
#: The paper's experiment (Table 1), ft = w = 0.
PAPER_EXPERIMENT = _paper_experiment()


def strip_options(contact):
    """The strip-kernel options of :func:`simulate_cycles` for a physical contact.

    Parameters
    ----------
    contact : Contact
        The contact (SI units).

    Returns
    -------
    dict
        ``L_over_a`` (strip length over half-width) and ``nu``, the Poisson
        ratio of a substrate under a rigid cylinder with the same strip kernel:
        ``2 nu / (1 - nu) = E* sum(nu_i / G_i)`` (exact for a rigid cylinder or
        two equal bodies, an equivalent value otherwise).

    Examples
    --------
    >>> import core
    >>> opts = core.strip_options(core.PAPER_SIMULATION)
    >>> round(opts["L_over_a"], 1), opts["nu"]
    (292.6, 0.5)
    """
    if not isinstance(contact, Contact):
        raise ValueError(f"contact must be a core.Contact, got {type(contact).__name__}")
    b = contact.E_star * contact.nu / contact.G
    return {"L_over_a": contact.L / contact.a, "nu": b / (2.0 + b)}  # 2 nu/(1 - nu) = b <=> nu = b/(2 + b)


def simulate_contact(contact, periods=10, dx=DEFAULT_DX, dW=None, *, kernel="strip", **options):
    """Simulate a :class:`~core.contact.Contact` given in physical units.

    Runs :func:`simulate_cycles` with the contact's ``ft``, ``w`` and, for the
    strip kernel, its ``L / a`` and materials. The result stays normalised;
    convert with ``contact.a`` [m], ``contact.traction_unit`` (``mu p0``, Pa)
    and ``contact.displacement_unit`` (``mu P/E*``, m).

    Parameters
    ----------
    contact : Contact
        The contact (``ft`` and ``w`` included).
    periods, dx, dW : see :func:`simulate_cycles`.
    kernel : {"strip", "plane"}
        Default ``"strip"``: the truncated-3D model with the contact's length.
    **options
        Further options of :func:`simulate_cycles`.

    Examples
    --------
    The paper's numerical case (eq 17) at ``ft = 0.08``, ``w = 0.26``, on a coarse grid:

    >>> from core import PAPER_SIMULATION
    >>> r = simulate_contact(PAPER_SIMULATION.replace(ft=0.08, w=0.26), periods=4, dx=1 / 20)
    >>> r.regime, round(float(r.u[-1]), 3)
    ('shakedown', 0.078)
    """
    if not isinstance(contact, Contact):
        raise ValueError(f"contact must be a core.Contact, got {type(contact).__name__}")
    dx = check_scalar("dx", dx, 1e-4, 0.5)
    if kernel == "strip":
        for key, value in strip_options(contact).items():
            options.setdefault(key, value)
    result = simulate_cycles(contact.ft, contact.w, periods, dx, dW, kernel=kernel, **options)
    result.params.update({f"contact_{k}": v for k, v in contact.summary().items()})
    return result


# --------------------------------------------------------------------------
# physical units
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class PointContact:
    """A sphere or ellipsoid on a substrate, in SI units (m, N, Pa), and its normalised loads.

    Parameters
    ----------
    Rx, Ry : float
        Principal relative radii [m] (x: the rocking direction); ``Ry/Rx`` in [0.05, 20].
    Fn : float
        Normal force [N], > 0.
    mu : float
        Friction coefficient, in (0, 10].
    E2, nu2 : float
        Substrate's Young's modulus [Pa] and Poisson ratio (default 0.5), in [0, 0.5].
    E1, nu1 : float
        The body's (default rigid, ``E1 = inf``).
    Ft : float
        Tangential force [N], in [0, mu Fn).
    W : float
        Rocking amplitude of the contact centre [m], in [0, a).
    angle : float
        Angle of ``Ft`` to the rocking direction [rad].

    Examples
    --------
    >>> from core.contact import PointContact
    >>> c = PointContact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
    >>> round(c.ft, 3), round(c.a * 1e3, 3)
    (0.4, 2.657)
    """

    Rx: float
    Ry: float
    Fn: float
    mu: float
    E2: float
    nu2: float = 0.5
    E1: float = math.inf
    nu1: float = 0.3
    Ft: float = 0.0
    W: float = 0.0
    angle: float = 0.0

    def __post_init__(self):
        for name, lo, hi, inf in (("Rx", 0.0, None, False), ("Ry", 0.0, None, False), ("Fn", 0.0, None, False),
                                  ("mu", 0.0, 10.0, False), ("E2", 0.0, None, False), ("E1", 0.0, None, True)):
            object.__setattr__(self, name, check_scalar(name, getattr(self, name), lo, hi, lo_closed=False,
                                                        allow_inf=inf))
        for name in ("nu1", "nu2"):
            object.__setattr__(self, name, check_scalar(name, getattr(self, name), 0.0, 0.5))
        check_scalar("Ry/Rx", self.Ry / self.Rx, 0.05, 20.0)
        object.__setattr__(self, "Ft", check_scalar("Ft", self.Ft, 0.0, self.mu * self.Fn, hi_closed=False))
        object.__setattr__(self, "angle", check_scalar("angle", self.angle, -math.pi, math.pi))
        object.__setattr__(self, "W", check_scalar("W", self.W, 0.0, self.a, hi_closed=False))

    @property
    def body(self) -> Ellipsoid:
        return Ellipsoid(self.Ry / self.Rx)

    @property
    def E_star(self) -> float:
        """``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` [Pa]."""
        return 1.0 / (_compliance(self.E1, self.nu1) + _compliance(self.E2, self.nu2))

    @property
    def nu(self) -> float:
        """Poisson ratio of the equivalent rigid-on-substrate Cerruti kernel: ``2 nu/(1 - nu) = E* sum nu_i/G_i``."""
        g = sum(0.0 if math.isinf(E) else 2.0 * (1.0 + n) * n / E for E, n in ((self.E1, self.nu1), (self.E2, self.nu2)))
        b = self.E_star * g
        return b / (2.0 + b)

    @cached_property
    def a(self) -> float:
        """Semi-axis of the contact along x [m] (Johnson eqs 4.36-4.41)."""
        kappa = self.body.kappa
        major_y = kappa >= 1.0
        m = kappa if major_y else 1.0 / kappa
        C_major = 0.5 / (self.Ry if major_y else self.Rx)
        e2 = 1.0 - 1.0 / (m * m)
        a_major = (3.0 * self.Fn * _k_minus_e_over_e2(e2) / (2.0 * math.pi * self.E_star * C_major)) ** (1.0 / 3.0)
        return a_major / kappa if major_y else a_major

    @property
    def b(self) -> float:
        """Semi-axis along y [m]."""
        return self.body.kappa * self.a

    @property
    def p0(self) -> float:
        """Peak pressure ``3 Fn / (2 pi a b)`` [Pa]."""
        return 3.0 * self.Fn / (2.0 * math.pi * self.a * self.b)

    @property
    def ft(self) -> float:
        return self.Ft / (self.mu * self.Fn)

    @property
    def w(self) -> float:
        return self.W / self.a

    @property
    def traction_unit(self) -> float:
        """``mu p0`` [Pa]."""
        return self.mu * self.p0

    @property
    def displacement_unit(self) -> float:
        """``mu Fn / (E* a)`` [m]."""
        return self.mu * self.Fn / (self.E_star * self.a)

    @property
    def energy_unit(self) -> float:
        """``mu^2 Fn^2 / (E* a)`` [J], the unit of the energy dissipated per period
        (:attr:`core.CycleResult.dissipation_per_period` of a point contact)."""
        return self.mu * self.Fn * self.displacement_unit

    def replace(self, **changes) -> "PointContact":
        """A copy with some inputs changed, as :meth:`core.Contact.replace`: the normalised loads ``ft`` and
        ``w`` stay as they are unless ``ft``/``Ft`` or ``w``/``W`` is given (``ft`` and ``w`` may be given in
        place of ``Ft`` and ``W``; ``W = w a`` with the new contact's ``a``).

        >>> c = PointContact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
        >>> d = c.replace(mu=0.8)
        >>> round(d.ft, 3) == round(c.ft, 3), round(d.Ft, 3)
        (True, 3.2)
        """
        names = {f.name for f in fields(self)}
        for load, normalised in (("Ft", "ft"), ("W", "w")):
            if load in changes and normalised in changes:
                raise ValueError(f"{load}: give {load} or {normalised}, not both")
        unknown = sorted(set(changes) - names - {"ft", "w"})
        if unknown:
            raise ValueError(f"{unknown[0]}: not an input of PointContact (inputs: {', '.join(sorted(names))}, ft, w)")
        ft, w = changes.pop("ft", self.ft), changes.pop("w", self.w)
        geometry = PointContact(**{**{n: getattr(self, n) for n in names}, **changes, "Ft": 0.0, "W": 0.0})
        Ft = changes["Ft"] if "Ft" in changes else ft * geometry.mu * geometry.Fn
        W = changes["W"] if "W" in changes else w * geometry.a
        return PointContact(**{**{n: getattr(geometry, n) for n in names}, "Ft": Ft, "W": W})

    def simulate(self, periods=10, dx=None, **options):
        """Run :func:`core.simulate_point_contact` with this contact's ``ft``, ``w``, body, angle and ``nu``.

        ``options`` are those of :func:`core.simulate_cycles` (``history``, ``amplitude``, ``shape``, ...).

        The result stays normalised: multiply lengths by :attr:`a`, tractions
        by :attr:`traction_unit` and displacements by :attr:`displacement_unit`.
        """
        return simulate_point_contact(self.ft, self.w, periods, dx, body=self.body, angle=self.angle, nu=self.nu,
                                      **options)
