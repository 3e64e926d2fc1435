"""A contact in physical units over any body, and what follows from it: :class:`Contact` and its runs.

:class:`Contact` holds the inputs of the model in SI units (m, N, Pa) and
derives the effective quantities of the two-body problem, the Hertz solution
of the contact and the normalised loads ``ft`` and ``w`` that the rest of
:mod:`core` works with, for a line body (a cylinder of length ``L``: its radii
``R1``, ``R2``; the scales of any line body) or a point body (a sphere or an
ellipsoid of principal relative radii ``Rx``, ``Ry``; the scales of any point
body). :meth:`Contact.simulate` runs it through :func:`core.simulate_cycles`
(:func:`simulate_contact`: a line contact on the strip kernel of its length,
:func:`strip_options`). :class:`PointContact` is its former point-contact name,
deprecated.
"""

from __future__ import annotations

import math
import warnings as _warnings
from dataclasses import dataclass
from functools import cached_property

from ..base._validate import check_scalar
from ..theory.materials import COUPLING_THRESHOLD, dundurs_beta, material_pair
from ..theory.point_contact import Ellipsoid, _k_minus_e_over_e2
from ..geometry.bodies import Cylinder
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


#: The inputs of a line contact and of a point contact, in the order of :meth:`Contact.summary`'s first keys.
_LINE_INPUTS = ("R1", "L", "Fn", "mu", "E2", "nu2", "R2", "E1", "nu1")
_POINT_INPUTS = ("Rx", "Ry", "Fn", "mu", "E2", "nu2", "E1", "nu1", "angle")


@dataclass(frozen=True, init=False)
class Contact:
    """A body on a substrate in SI units (m, N, Pa), loaded by Fn and Ft and rocked by W: a line or a point contact.

    A line contact (:attr:`is_point` False) is a rigid or elastic cylinder of
    length ``L`` (``R1``, ``L``; the physical scales of any line body given
    as ``body``); a point contact (``Rx`` and ``Ry`` given, :attr:`is_point`
    True) a sphere or an ellipsoid (the scales of any point body given as
    ``body``). Give exactly one of ``Ft`` / ``ft`` and exactly one of ``W`` /
    ``w`` (neither: 0).

    Parameters
    ----------
    R1 : float
        A line contact: radius of the cylinder [m], > 0.
    L : float
        A line contact: length of the cylinder [m], > 0; must exceed the contact width.
    Fn : float
        Normal force [N], > 0.
    mu : float
        Coulomb friction coefficient [-], in (0, 10].
    E2, nu2 : float
        Young's modulus [Pa] (> 0, finite) and Poisson ratio [-] (in [0, 0.5])
        of the substrate (a point contact: ``nu2`` default 0.5).
    R2 : float
        A line contact: radius of the substrate [m], default ``inf`` (flat).
    E1, nu1 : float
        Young's modulus [Pa] and Poisson ratio of the body; default
        ``E1 = inf`` (rigid).
    Ft : float, optional
        Tangential force [N], in [0, mu Fn).
    ft : float, optional
        ``Ft / (mu Fn)`` in [0, 1).
    W : float, optional
        Rocking amplitude of the contact centre [m], in [0, a).
    w : float, optional
        ``W / a`` in [0, 1).
    Rx, Ry : float, optional
        A point contact: principal relative radii [m] (x: the rocking direction), ``Ry/Rx`` in [0.05, 20].
    angle : float
        A point contact: angle of ``Ft`` to the rocking direction [rad], in [-pi, pi] (a line: 0).
    body : object, optional
        The body the runs use (:meth:`simulate`), at these scales: a line body
        object for a line contact (default :class:`core.Cylinder`), a point
        body object for a point contact (default :class:`core.Ellipsoid` of
        ``Ry/Rx``); kept as :attr:`body`.
    materials : str or core.theory.materials.MaterialPair, optional
        A preset of :data:`core.theory.materials.PAIRS` (``"steel/aluminium"``) or
        ``"body/substrate"``: sets ``E1, nu1, E2, nu2`` (then give none of them).

    Notes
    -----
    :attr:`beta` is Dundurs' with body 1 the rocking body (``> 0`` for a rigid
    body on a compressible substrate, :mod:`core.theory.materials`). A line contact's
    :meth:`simulate` runs coupled (:mod:`core.solvers.coupled`) when ``beta != 0``;
    a point contact assumes uncoupled problems, and :attr:`warnings` says when
    ``|beta|`` exceeds :data:`BETA_WARNING_LEVEL`. ``core.PointContact(Rx, Ry, Fn, mu, E2, ...)``,
    the former point-contact class, builds a point :class:`Contact` with a
    DeprecationWarning, and ``isinstance(c, core.PointContact)`` is ``c.is_point``.

    Examples
    --------
    >>> from core import PAPER_EXPERIMENT as c
    >>> round(c.d * 1e3, 2)  # indentation in mm (Table 1: 0.26)
    0.26
    >>> s = Contact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
    >>> s.is_point, round(s.ft, 3), round(s.a * 1e3, 3)
    (True, 0.4, 2.657)
    """

    R1: float | None
    L: float | None
    Fn: float
    mu: float
    E2: float
    nu2: float
    R2: float
    E1: float
    nu1: float
    Ft: float
    ft: float
    W: float
    w: float
    Rx: float | None
    Ry: float | None
    angle: float
    body: object

    def __init__(self, R1=None, L=None, Fn=None, mu=None, E2=None, nu2=None, R2=math.inf, E1=math.inf, nu1=0.3,
                 Ft=None, ft=None, W=None, w=None, *, Rx=None, Ry=None, angle=0.0, body=None, materials=None):
        set_ = object.__setattr__
        if materials is not None:
            if E2 is not None or nu2 is not None or E1 != math.inf or nu1 != 0.3:
                raise ValueError("materials: give the materials or E1, nu1, E2, nu2, not both")
            pair = material_pair(materials)
            E1, nu1, E2, nu2 = pair.body.E, pair.body.nu, pair.substrate.E, pair.substrate.nu
        point = Rx is not None or Ry is not None
        if point:
            if R1 is not None or L is not None or R2 != math.inf:
                raise ValueError("give a line contact's R1, L (and R2) or a point contact's Rx, Ry, not both")
            set_(self, "Rx", check_scalar("Rx", Rx, 0.0, None, lo_closed=False))
            set_(self, "Ry", check_scalar("Ry", Ry, 0.0, None, lo_closed=False))
            check_scalar("Ry/Rx", self.Ry / self.Rx, 0.05, 20.0)
            set_(self, "R1", None), set_(self, "L", None), set_(self, "R2", math.inf)
            nu2 = 0.5 if nu2 is None else nu2
        else:
            set_(self, "R1", check_scalar("R1", R1, 0.0, None, lo_closed=False, allow_inf=True))
            set_(self, "R2", check_scalar("R2", R2, 0.0, None, lo_closed=False, allow_inf=True))
            set_(self, "L", check_scalar("L", L, 0.0, None, lo_closed=False))
            set_(self, "Rx", None), set_(self, "Ry", None)
            if nu2 is None:
                raise ValueError("nu2 must be given for a line contact (the substrate's Poisson ratio, in [0, 0.5])")
        set_(self, "Fn", check_scalar("Fn", Fn, 0.0, None, lo_closed=False))
        set_(self, "mu", check_scalar("mu", mu, 0.0, 10.0, lo_closed=False))
        set_(self, "E1", check_scalar("E1", E1, 0.0, None, lo_closed=False, allow_inf=True))
        set_(self, "nu1", check_scalar("nu1", nu1, 0.0, 0.5))
        set_(self, "E2", check_scalar("E2", E2, 0.0, None, lo_closed=False))
        set_(self, "nu2", check_scalar("nu2", nu2, 0.0, 0.5))
        set_(self, "angle", check_scalar("angle", angle, -math.pi, math.pi) if point else
             check_scalar("angle", angle, 0.0, 0.0))
        if body is None:
            body = Ellipsoid(self.Ry / self.Rx) if point else Cylinder()
        set_(self, "body", body)
        if not point and math.isinf(self.R1) and math.isinf(self.R2):
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
        if not point and 2.0 * a >= self.L:
            raise ValueError(f"L must exceed the contact width 2a = {2 * a:.4g} m, got {self.L:.4g} m")
        if W is not None:
            W = check_scalar("W", W, 0.0, a, hi_closed=False)
            w = W / a
        else:
            w = check_scalar("w", 0.0 if w is None else w, 0.0, 1.0, hi_closed=False)
            W = w * a
        set_(self, "W", W)
        set_(self, "w", w)

    @property
    def is_point(self) -> bool:
        """True for a point contact (``Rx``, ``Ry``), False for a line contact (``R1``, ``L``)."""
        return self.Rx is not None

    # ---- effective two-body quantities -----------------------------------
    @property
    def R(self) -> float:
        """A line contact's effective radius ``1/R = 1/R1 + 1/R2`` [m] (None for a point contact)."""
        return None if self.is_point else 1.0 / (1.0 / self.R1 + 1.0 / self.R2)

    @property
    def E_star(self) -> float:
        """Effective modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` [Pa]."""
        return 1.0 / (_compliance(self.E1, self.nu1) + _compliance(self.E2, self.nu2))

    @property
    def G1(self) -> float:
        """Shear modulus of the body [Pa] (inf if rigid)."""
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
    def kernel_nu(self) -> float:
        """Poisson ratio of a substrate under a rigid body with the same tangential kernel [-]:
        ``2 nu/(1 - nu) = E* sum(nu_i / G_i)`` (exact for a rigid body or two equal bodies, an equivalent value
        otherwise): the ``nu`` of a point contact's run and of a line contact's strip kernel (:func:`strip_options`)."""
        b = self.E_star * sum(0.0 if math.isinf(E) else 2.0 * (1.0 + n) * n / E
                              for E, n in ((self.E1, self.nu1), (self.E2, self.nu2)))
        return b / (2.0 + b)

    @property
    def nu(self) -> float:
        """A line contact: the effective Poisson ratio of the Cerruti kernel ``nu = G (nu1/G1 + nu2/G2)`` [-]
        (eq 33); a point contact: :attr:`kernel_nu`, the ``nu`` of its half-space run."""
        return self.kernel_nu if self.is_point else self.G * (self.nu1 / self.G1 + self.nu2 / self.G2)

    @property
    def beta(self) -> float:
        """Dundurs' second constant [-] with body 1 the rocking body (:func:`core.theory.materials.dundurs_beta`: ``> 0``
        for a rigid body on a compressible substrate)."""
        return dundurs_beta(self.E1, self.nu1, self.E2, self.nu2)

    @property
    def coupled(self) -> bool:
        """A line contact whose ``|beta|`` reaches :data:`core.theory.materials.COUPLING_THRESHOLD`: its runs solve the
        normal and tangential problems together (:func:`simulate_contact`)."""
        return not self.is_point and abs(self.beta) >= COUPLING_THRESHOLD

    # ---- Hertz (line: eqs 4-6; point: Johnson eqs 4.36-4.41) ----------------
    @property
    def P(self) -> float:
        """A line contact's normal load per unit length ``Fn / L`` [N/m] (None for a point contact)."""
        return None if self.is_point else self.Fn / self.L

    @cached_property
    def a(self) -> float:
        """Hertz half-width ``sqrt(4 R P / (pi E*))`` [m] (eq 5); a point contact: the semi-axis along x
        (Johnson eqs 4.36-4.41)."""
        if not self.is_point:
            return math.sqrt(4.0 * self.R * self.P / (math.pi * self.E_star))
        kappa = Ellipsoid(self.Ry / self.Rx).kappa
        major_y = kappa >= 1.0
        m = kappa if major_y else 1.0 / kappa
        C_major = 0.5 / (self.Ry if major_y else self.Rx)
        e2 = 1.0 - 1.0 / (m * m)
        a_major = (3.0 * self.Fn * _k_minus_e_over_e2(e2) / (2.0 * math.pi * self.E_star * C_major)) ** (1.0 / 3.0)
        return a_major / kappa if major_y else a_major

    @property
    def b(self) -> float:
        """A point contact's semi-axis along y [m] (None for a line contact)."""
        return Ellipsoid(self.Ry / self.Rx).kappa * self.a if self.is_point else None

    @property
    def p0(self) -> float:
        """Peak pressure [Pa]: ``2 P / (pi a)`` (eq 5); a point contact: ``3 Fn / (2 pi a b)``."""
        if self.is_point:
            return 3.0 * self.Fn / (2.0 * math.pi * self.a * self.b)
        return 2.0 * self.P / (math.pi * self.a)

    @property
    def d(self) -> float:
        """A line contact's indentation ``(2P/(pi E*)) [(1 + ln 4)/2 + ln(L/a)]`` [m] (eq 6, reconstructed; None
        for a point contact)."""
        if self.is_point:
            return None
        return 2.0 * self.P / (math.pi * self.E_star) * (0.5 * (1.0 + math.log(4.0)) + math.log(self.L / self.a))

    @property
    def displacement_unit(self) -> float:
        """The unit of the solver's displacements [m]: ``mu P / E*``; a point contact: ``mu Fn / (E* a)``."""
        if self.is_point:
            return self.mu * self.Fn / (self.E_star * self.a)
        return self.mu * self.P / self.E_star

    @property
    def energy_unit(self) -> float:
        """The unit of the energy dissipated per period (:attr:`core.CycleResult.dissipation_per_period`):
        ``mu^2 P^2 / E*`` [J/m] per unit length of a line contact, ``mu^2 Fn^2 / (E* a)`` [J] of a point contact."""
        return self.mu * (self.Fn if self.is_point else self.P) * self.displacement_unit

    @property
    def traction_unit(self) -> float:
        """``mu p0`` [Pa], the unit of normalised tractions."""
        return self.mu * self.p0

    @property
    def warnings(self) -> tuple[str, ...]:
        """Human-readable reasons to distrust the model for this contact."""
        out = []
        if not self.is_point and self.coupled and abs(self.beta) > BETA_WARNING_LEVEL:
            out.append(f"Dundurs beta = {self.beta:.3f}: simulate() solves the normal and tangential problems together "
                       "(plane strain), where Melan's limit (eq 35) is only the uncoupled reference; a run with "
                       "a kernel given (and no beta) assumes them uncoupled.")
        elif abs(self.beta) > BETA_WARNING_LEVEL:
            out.append(
                f"Dundurs beta = {self.beta:.3f}: the model assumes uncoupled normal and tangential "
                f"problems (beta = 0); |beta| > {BETA_WARNING_LEVEL} makes the results "
                f"approximate."
            )
        if not self.is_point and self.L < 10 * self.a:
            out.append(f"L/a = {self.L / self.a:.1f}: the strip is short; end effects are not modelled.")
        return tuple(out)

    def replace(self, **changes) -> "Contact":
        """A copy with some inputs changed: the normalised loads ``ft`` and ``w`` stay as they are unless
        ``ft``/``Ft`` or ``w``/``W`` is given (``W = w a`` with the new contact's ``a``).

        >>> c = Contact(Rx=0.01, Ry=0.01, Fn=10.0, mu=0.5, E2=3e6, Ft=2.0, W=1e-4)
        >>> d = c.replace(mu=0.8)
        >>> round(d.ft, 3) == round(c.ft, 3), round(d.Ft, 3)
        (True, 3.2)
        """
        names = (_POINT_INPUTS if self.is_point else _LINE_INPUTS) + ("body",)
        for load, normalised in (("Ft", "ft"), ("W", "w")):
            if load in changes and normalised in changes:
                raise ValueError(f"{load}: give {load} or {normalised}, not both")
        unknown = sorted(set(changes) - set(names) - {"Ft", "ft", "W", "w"})
        if unknown:
            raise ValueError(f"{unknown[0]}: not an input of this {'point' if self.is_point else 'line'} contact "
                             f"(inputs: {', '.join(sorted(names))}, Ft, ft, W, w)")
        kw = {n: getattr(self, n) for n in names}
        kw["ft"], kw["w"] = self.ft, self.w
        if "Ft" in changes:
            kw.pop("ft")
        if "W" in changes:
            kw.pop("w")
        kw.update(changes)
        return Contact(**kw)

    def summary(self) -> dict:
        """The inputs and derived quantities as a flat dict of floats (SI units)."""
        if self.is_point:
            keys = _POINT_INPUTS[:-1] + ("Ft", "W", "angle", "a", "b", "p0", "E_star", "ft", "w")
        else:
            keys = ("R1", "R2", "L", "Fn", "Ft", "mu", "E1", "nu1", "E2", "nu2", "W", "ft", "w",
                    "R", "E_star", "G", "G_star", "nu", "beta", "P", "a", "p0", "d")
        return {k: float(getattr(self, k)) for k in keys}

    def simulate(self, periods=10, dx=None, **options):
        """Run this contact: :func:`simulate_contact` (line: the strip kernel of its length by default), or on a
        point contact :func:`core.simulate_cycles` with its ``ft``, ``w``, body, angle and ``nu``.

        ``options`` are those of :func:`core.simulate_cycles` (``history``, ``amplitude``, ``shape``, ...).
        The result stays normalised: multiply lengths by :attr:`a`, tractions by :attr:`traction_unit` and
        displacements by :attr:`displacement_unit`.
        """
        if not self.is_point:
            return simulate_contact(self, periods, dx, **options)
        options.setdefault("body", self.body)
        return simulate_point_contact(self.ft, self.w, periods, dx, angle=self.angle, nu=self.kernel_nu, **options)


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
        A line contact (SI units).

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
    if not isinstance(contact, Contact) or contact.is_point:
        raise ValueError(f"contact must be a line core.Contact (R1, L), got "
                         f"{'a point contact' if isinstance(contact, Contact) else type(contact).__name__}")
    b = contact.E_star * contact.nu / contact.G
    return {"L_over_a": contact.L / contact.a, "nu": b / (2.0 + b)}  # 2 nu/(1 - nu) = b <=> nu = b/(2 + b)


def simulate_contact(contact, periods=10, dx=None, dW=None, *, kernel=None, **options):
    """Simulate a :class:`~core.api.contact.Contact` given in physical units.

    Runs :func:`simulate_cycles` with the contact's ``ft``, ``w``, body and, for
    the strip kernel, its ``L / a`` and materials (a point contact: its
    :meth:`Contact.simulate`, on the half-space). The result stays normalised;
    convert with ``contact.a`` [m], ``contact.traction_unit`` (``mu p0``, Pa)
    and ``contact.displacement_unit`` (``mu P/E*``, m).

    Parameters
    ----------
    contact : Contact
        The contact (``ft`` and ``w`` included).
    periods, dx, dW : see :func:`simulate_cycles` (``dx`` None: a line's ``DEFAULT_DX``, a point body's default).
    kernel : {"strip", "plane"}, optional
        Default ``"strip"``: the truncated-3D model with the contact's length (a line contact only); a
        coupled line contact (:attr:`Contact.coupled`: ``|beta| >= COUPLING_THRESHOLD``) runs with its
        ``beta`` and ``mu`` on the plane-strain kernel (the coupled solver's, :mod:`core.solvers.coupled`) when no
        kernel is given (or ``beta`` is given in ``options``). A kernel given without ``beta`` runs the
        uncoupled model, as before coupling existed (the explorer's runs, which name their kernel).
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
    if contact.is_point:
        if kernel not in (None, "strip"):
            raise ValueError(f"kernel does not apply to a point contact (the half-space's), got {kernel!r:.60}")
        return contact.simulate(periods, dx, dW=dW, **options)
    dx = check_scalar("dx", DEFAULT_DX if dx is None else dx, 1e-4, 0.5)
    options.setdefault("body", contact.body)
    if contact.coupled and (kernel is None or "beta" in options):
        options.setdefault("beta", contact.beta)
        options.setdefault("mu", contact.mu)
        kernel = "plane" if kernel is None else kernel
    kernel = "strip" if kernel is None else kernel
    if kernel == "strip":
        for key, value in strip_options(contact).items():
            options.setdefault(key, value)
    result = simulate_cycles(contact.ft, contact.w, periods, dx, dW, kernel=kernel, **options)
    result.params.update({f"contact_{k}": v for k, v in contact.summary().items()})
    return result


class _PointContactType(type):
    """The type of :class:`PointContact`: ``isinstance(c, PointContact)`` is ``c.is_point``."""

    def __instancecheck__(cls, obj):
        return isinstance(obj, Contact) and obj.is_point

    def __subclasscheck__(cls, sub):
        return sub is cls

    def __call__(cls, Rx, Ry, Fn, mu, E2, nu2=0.5, E1=math.inf, nu1=0.3, Ft=0.0, W=0.0, angle=0.0):
        _warnings.warn("PointContact is Contact (one class over any body): use core.Contact(Rx=..., Ry=..., ...)",
                       DeprecationWarning, stacklevel=2)
        return Contact(Fn=Fn, mu=mu, E2=E2, nu2=nu2, E1=E1, nu1=nu1, Ft=Ft, W=W, Rx=Rx, Ry=Ry, angle=angle)


class PointContact(metaclass=_PointContactType):
    """Deprecated: a point contact is a :class:`Contact` with ``Rx`` and ``Ry`` (:attr:`Contact.is_point`).

    ``PointContact(Rx, Ry, Fn, mu, E2, nu2=0.5, E1=inf, nu1=0.3, Ft=0, W=0, angle=0)`` builds that
    :class:`Contact` with a DeprecationWarning; ``isinstance(c, PointContact)`` still tells a point contact from
    a line one.
    """
