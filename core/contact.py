"""A cylindrical contact in physical units, and what follows from it.

:class:`Contact` holds the inputs of the model in SI units (m, N, Pa) and
derives the effective quantities of the two-body problem, the Hertz solution
of the line contact and the normalised loads ``ft`` and ``w`` that the rest of
:mod:`core` works with.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from ._validate import check_scalar

__all__ = ["Contact", "PAPER_SIMULATION", "PAPER_EXPERIMENT", "BETA_WARNING_LEVEL"]

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
