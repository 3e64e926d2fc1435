"""The explorer's state: every input of the model, with bounds, steps, units and docs.

:class:`ExplorerState` is headless: it holds the inputs, turns them into a
:class:`core.Contact` and solver options, applies presets and parses URL query
parameters. The Panel view (:mod:`app.explorer`) is a thin layer over it, so
everything here is testable without a browser.

Units of the parameters are those of the user interface: lengths in mm, forces
in N, moduli in MPa. :meth:`ExplorerState.contact` converts to SI for
:mod:`core`.
"""

from __future__ import annotations

import math
import re
import urllib.parse
from typing import Mapping

import param

import core

from . import bodies
from .limits import MAX_PERIODS, MAX_RESOLUTION

__all__ = ["ExplorerState", "typed_error", "BODIES", "POINT_RESOLUTION", "MAX_POINT_RESOLUTION", "PRESETS", "PRESET_NOTES", "URL_PARAMETERS", "parse_query", "MAX_QUERY_VALUE_LENGTH"]

#: Longest query-string value that is even looked at (longer ones are rejected).
MAX_QUERY_VALUE_LENGTH = 64

_MM, _MPA = 1e-3, 1e6
#: The bodies of the body selector: every body of :data:`core.geometry.registry.REGISTRY`, in its order (:mod:`app.bodies`).
BODIES = bodies.BODIES
#: Default elements per semi-axis of a point-contact run: coarse, so that a run of 10 periods takes seconds.
POINT_RESOLUTION = 10
#: Finest point-contact grid the explorer accepts (elements per semi-axis: up to about 160 x 80 elements at 40).
MAX_POINT_RESOLUTION = 40


class ExplorerState(param.Parameterized):
    """Inputs of the rocking-contact model as shown in the explorer: the body (``body``, one of
    :data:`core.geometry.registry.REGISTRY`; each body's parameters are inputs of their own, added below from the
    registry by :mod:`app.bodies`), with loads, geometry, materials, solver and view settings.

    ``bounds`` are the physical validity of each input (or an operator cap on
    the work a served app accepts); ``softbounds`` are the slider ranges.
    """

    # ---- loads ------------------------------------------------------------
    ft = param.Number(0.3, bounds=(0.0, 1.0), inclusive_bounds=(True, False), softbounds=(0.0, 0.99),
                      step=0.01, label="ft = Ft/(μ Fn)",
                      doc="Tangential load over its sliding limit, Ft/(μ Fn) [-], in [0, 1).")
    w = param.Number(0.5, bounds=(0.0, 1.0), inclusive_bounds=(True, False), softbounds=(0.0, 0.99),
                     step=0.01, label="w = W/a",
                     doc="Rocking amplitude of the contact centre over the half-width, W/a [-], in [0, 1).")
    mu = param.Number(0.58, bounds=(0.0, 10.0), inclusive_bounds=(False, True), softbounds=(0.05, 1.5),
                      step=0.01, label="μ (friction)", doc="Coulomb friction coefficient μ [-], in (0, 10].")
    # ---- the body -------------------------------------------------------------
    body = param.Selector(default="cylinder", objects=list(BODIES), label="Body",
                          doc="The rocking body; its own inputs and a note on it follow below.")
    # ---- geometry and materials --------------------------------------------
    R = param.Number(40.0, bounds=(0.0, 1e5), inclusive_bounds=(False, True), softbounds=(1.0, 200.0),
                     step=1.0, label="R [mm]",
                     doc="Radius of the cylinder R [mm] (of a point contact: its relative radius Rx along the "
                         "rocking direction), in (0, 1e5].")
    L = param.Number(500.0, bounds=(0.0, 1e6), inclusive_bounds=(False, True), softbounds=(1.0, 1000.0),
                     step=1.0, label="L [mm]",
                     doc="Length of the cylinder L [mm], in (0, 1e6]; must exceed the contact width 2a.")
    Fn = param.Number(195.0, bounds=(0.0, 1e9), inclusive_bounds=(False, True), softbounds=(1.0, 1000.0),
                      step=1.0, label="Fn [N]", doc="Normal force Fn [N], in (0, 1e9].")
    E2 = param.Number(5.1, bounds=(0.0, 1e7), inclusive_bounds=(False, True), softbounds=(0.1, 1000.0),
                      step=0.1, label="E substrate [MPa]", doc="Young's modulus of the substrate E2 [MPa], in (0, 1e7].")
    nu2 = param.Number(0.5, bounds=(0.0, 0.5), softbounds=(0.0, 0.5), step=0.01, label="ν substrate",
                       doc="Poisson ratio of the substrate ν2 [-], in [0, 0.5].")
    rigid = param.Boolean(True, label="Rigid cylinder",
                          doc="Treat the cylinder as rigid (E1 = ∞); untick to use E1 and ν1.")
    E1 = param.Number(206e3, bounds=(0.0, 1e7), inclusive_bounds=(False, True), softbounds=(1.0, 1e6),
                      step=1.0, label="E cylinder [MPa]",
                      doc="Young's modulus of the cylinder E1 [MPa], in (0, 1e7]; used when not rigid.")
    nu1 = param.Number(0.3, bounds=(0.0, 0.5), softbounds=(0.0, 0.5), step=0.01, label="ν cylinder",
                       doc="Poisson ratio of the cylinder ν1 [-], in [0, 0.5]; used when not rigid.")
    materials = param.Selector(default="custom", objects=["custom", *core.theory.materials.PAIRS], label="Materials",
                               doc="A pair of common materials, the cylinder's on the substrate's: sets E and ν of "
                                   "both ('custom': the values typed). Dissimilar materials (Dundurs β ≠ 0) couple a "
                                   "line contact's normal and tangential problems: they are then solved together, "
                                   "and eq 35 (Melan's limit) is only the uncoupled reference.")
    # ---- solver -------------------------------------------------------------
    periods = param.Integer(10, bounds=(1, MAX_PERIODS), softbounds=(1, min(30, MAX_PERIODS)), step=1,
                            label="Periods",
                            doc=f"Rocking periods simulated after the loading [-], in [1, {MAX_PERIODS}] "
                                "(this server's cap).")
    resolution = param.Integer(40, bounds=(5, MAX_RESOLUTION), softbounds=(10, min(100, MAX_RESOLUTION)), step=5,
                               label="Elements per a",
                               doc=f"Grid resolution: elements per half-width a [-] (dx = a/resolution), in "
                                   f"[5, {MAX_RESOLUTION}] (this server's cap).")
    point_resolution = param.Integer(
        POINT_RESOLUTION, bounds=(4, MAX_POINT_RESOLUTION), softbounds=(4, MAX_POINT_RESOLUTION), step=1,
        label="Elements per a (point contacts)",
        doc=f"Grid of a point contact: elements per semi-axis a (dx = a/n for n elements; the elements of the 2D grid "
            f"grow as its square, the steps in proportion), in [4, {MAX_POINT_RESOLUTION}]; coarse by default.")
    kernel = param.Selector(default="strip", objects=["strip", "plane"], label="Kernel",
                            doc="Influence kernel: 'strip' (truncated 3D strip of length L, gives U/U0) "
                                "or 'plane' (plane strain; displacement defined up to a constant).")
    schedule = param.Selector(default="triangle", objects=["triangle", "sine"], label="Rocking waveform",
                              doc="Waveform of the rocking motion of the contact centre: 'triangle' (the paper's) or 'sine'.")
    loading = param.Selector(default="rocking", objects=["rocking", "normal", "tangential"], label="Loading",
                             doc="Loading history of every body: 'rocking' under constant loads "
                                 "(the paper's); 'normal': the same rocking under an oscillating normal force "
                                 "Fn (1 + amplitude sin(2 pi t + phase)); 'tangential': the centre fixed and Ft "
                                 "oscillating about its mean (a sphere's is Mindlin-Deresiewicz's fretting loop).")
    amplitude = param.Number(0.2, bounds=(0.0, 1.0), inclusive_bounds=(True, False), softbounds=(0.0, 0.9),
                             step=0.05, label="Load amplitude",
                             doc="Amplitude of the oscillating load [-], in [0, 1): with loading = 'normal' that of "
                                 "the normal force over its mean, ΔFn/Fn; with 'tangential' that of Ft over what is "
                                 "left to full sliding, ΔFt/(μFn − |Ft|).")
    phase = param.Number(0.0, bounds=(-180.0, 180.0), softbounds=(-180.0, 180.0), step=15.0, label="Phase of Fn to the rocking [°]",
                         doc="Phase of the normal force's oscillation to the rocking [deg], in [-180, 180]; "
                             "used with loading = 'normal'.")
    # ---- view -------------------------------------------------------------
    units = param.Selector(default="normalised", objects=["normalised", "physical"], label="Units",
                           doc="Plot units: 'normalised' (x/a, p/p0, q/(μ p0), u in μP/E* or U/U0) "
                               "or 'physical' (mm, MPa, µm).")

    # ---- values without float noise ------------------------------------------
    def __setattr__(self, name, value):
        """Round ft, w, mu and the bodies' numeric parameters to 1e-6 as they are set, whoever sets them (a
        browser's slider steps give 0.44000000000000006, a shared link may carry it): the state, the sliders
        and the URL never hold the noise. Rounded here, before any watcher sees the value: a watcher that
        rounded afterwards left the URL, which is written by a later watcher of the same event, with the
        unrounded value."""
        if name in _ROUNDED and isinstance(value, float) and math.isfinite(value):
            rounded = round(value, 6)
            spec = type(self).param[name]
            if _within(spec, rounded) == _within(spec, value):  # rounding never carries a value across a bound
                value = rounded
        super().__setattr__(name, value)

    # ---- materials ----------------------------------------------------------
    def _pair_values(self, name: str) -> dict:
        """The inputs a materials pair of :data:`core.theory.materials.PAIRS` sets (E in MPa)."""
        pair = core.theory.materials.material_pair(name)
        rigid = math.isinf(pair.body.E)
        return dict(rigid=rigid, E2=pair.substrate.E / _MPA, nu2=pair.substrate.nu,
                    **({} if rigid else dict(E1=pair.body.E / _MPA, nu1=pair.body.nu)))

    @param.depends("materials", watch=True)
    def _apply_materials(self):
        if self.materials != "custom":
            self.param.update(**self._pair_values(self.materials))

    @param.depends("rigid", "E1", "nu1", "E2", "nu2", watch=True)
    def _typed_materials(self):
        """A value typed over a pair's makes the picker say 'custom' (the pair no longer describes the inputs)."""
        if self.materials != "custom" and any(getattr(self, k) != v
                                              for k, v in self._pair_values(self.materials).items()):
            self.materials = "custom"

    def _coupled_beta(self) -> float | None:
        """Dundurs' beta of the contact when its runs are coupled (:attr:`core.Contact.coupled`), else None."""
        try:
            contact = self.contact()
        except ValueError:
            return None
        return float(contact.beta) if contact.coupled else None

    # ---- derived ------------------------------------------------------------
    @property
    def kind(self) -> str:
        """The kind of the current body: ``"line"`` (1D engine, like the cylinder) or ``"point"``."""
        return bodies.kind(self.body)

    @property
    def point(self) -> bool:
        """True for a point contact (the sphere, the ellipsoid, a height map...)."""
        return self.kind == "point"

    def body_values(self, body: str | None = None) -> dict:
        """The parameters of ``body`` (default: the current one) as the inputs hold them, by parameter name."""
        body = self.body if body is None else body
        return {p.name: getattr(self, bodies.state_name(body, p.name)) for p in bodies.parameters(body)}

    def body_object(self):
        """The current body with its parameters (:func:`app.bodies.make`, built by the registry entry).

        Raises
        ------
        ValueError
            If the body cannot be built from the inputs (the message names the parameter).
        """
        return bodies.make(self.body, self.body_values())

    @property
    def refinable(self) -> bool:
        """Whether the point-contact grid input applies (a point body not on a grid of its own)."""
        if not self.point:
            return False
        try:
            return not bodies.own_grid(self.body_object())
        except ValueError:
            return True

    def contact(self) -> core.Contact:
        """The contact in SI units, with this state's ``ft`` and ``w``.

        A line :class:`core.Contact` for a line body (the cylinder's geometry:
        the physical scales of any line body); a point one (``Rx``, ``Ry``) for a
        point body: the sphere (``Rx = Ry = R``), an ellipsoid (``Rx = R``,
        ``Ry = ratio R``), another point body at the scales of the sphere of
        radius R; ``w`` is ``W`` over the contact's semi-axis along x and
        ``L`` and the kernel do not apply.

        Raises
        ------
        ValueError
            If the inputs do not make a valid contact or body (the message names the field).
        """
        rigid = self.rigid
        body = self.body_object()
        if not bodies.runs_cycles(self.body, body):
            raise ValueError(f"limit only: the explorer cannot run the cycles of body {self.body!r} yet "
                             f"({type(body).__name__}); its exact limit is on the cards and the map")
        if self.point:
            ratio = float(body.ratio) if bodies.is_ellipsoid(body) else 1.0
            c = core.Contact(Rx=self.R * _MM, Ry=self.R * ratio * _MM, Fn=self.Fn, mu=self.mu,
                             E2=self.E2 * _MPA, nu2=self.nu2, E1=math.inf if rigid else self.E1 * _MPA,
                             nu1=0.3 if rigid else self.nu1, Ft=self.ft * self.mu * self.Fn)
            return c.replace(w=self.w)
        inputs = dict(R1=self.R * _MM, Fn=self.Fn, mu=self.mu, E2=self.E2 * _MPA, nu2=self.nu2,
                      E1=math.inf if rigid else self.E1 * _MPA, nu1=0.3 if rigid else self.nu1, ft=self.ft, w=self.w)
        try:
            return core.Contact(L=self.L * _MM, **inputs)
        except ValueError as e:  # core's lengths are in metres: say it in the inputs' mm
            raise ValueError(_in_mm(str(e))) from None

    @property
    def dx(self) -> float:
        """Element width over the half-width a [-] (of a point contact: ``1/point_resolution``)."""
        return 1.0 / (self.point_resolution if self.point else self.resolution)

    def solver_options(self) -> dict:
        """Keyword arguments of the run of :meth:`contact`: :func:`core.simulate_contact` for the cylinder,
        :meth:`core.Contact.simulate` for a point contact (no kernel: the half-space's)."""
        if self.point:
            body = self.body_object()
            if bodies.is_ellipsoid(body):
                options = dict(periods=self.periods, dx=self.dx, shape=self.schedule)
            else:
                dx = float(body.default_dx) if bodies.own_grid(body) else self.dx
                options = dict(periods=self.periods, dx=dx, shape=self.schedule, body=body)
        else:
            # the coupled solver (dissimilar materials, Dundurs beta != 0) is plane strain: the strip kernel's U/U0
            # does not apply to it (the model's warnings say so)
            beta = self._coupled_beta()
            options = dict(periods=self.periods, dx=self.dx, kernel=self.kernel, shape=self.schedule)
            if beta is not None:  # solved together, on the coupled solver's plane-strain kernel, with its own mu
                options.update(kernel="plane", beta=beta, mu=self.mu)
            if self.body != bodies.DEFAULT:  # another line body: the cylinder's engine with this body's gap
                options["body"] = self.body_object()
        return dict(options, **self.history_options())

    def history_options(self) -> dict:
        """The loading history's options of :func:`core.simulate_cycles` (none for the paper's rocking): every body
        takes every history."""
        if self.loading == "normal":
            return dict(history="normal", amplitude=self.amplitude, phase=math.radians(self.phase))
        if self.loading == "tangential":  # the amplitude over the headroom to full sliding, so any value is valid
            return dict(history="tangential", amplitude=self.amplitude * (1.0 - abs(self.ft)))
        return {}

    def values(self) -> dict:
        """The URL-synced parameters and their current values."""
        return {name: getattr(self, name) for name in URL_PARAMETERS}

    def apply_preset(self, name: str) -> None:
        """Set the inputs of a named preset (see :data:`PRESETS`); other inputs keep their values.

        Raises
        ------
        ValueError
            If ``name`` is not a preset.
        """
        if name not in PRESETS:
            raise ValueError(f"preset must be one of {sorted(PRESETS)}, got {name!r}")
        self.param.update(**PRESETS[name])


def _in_mm(message: str) -> str:
    """A message of :mod:`core` with its lengths in metres ("2a = 0.04413 m") in the inputs' mm ("44.13 mm")."""
    return re.sub(r"(\d+(?:\.\d*)?(?:[eE][-+]?\d+)?) m\b", lambda m: f"{float(m.group(1)) / _MM:.4g} mm", message)


def typed_error(p: param.Parameter, value) -> str:
    """Why ``value`` typed for input ``p`` is refused, in the input's units (its label's ``[unit]``):
    "R must be in (0, 100000] mm, got -1 mm"."""
    label = str(p.label)
    name, _, unit = label.partition(" [")
    unit = unit.rstrip("]")
    lo, hi = p.bounds
    ilo, ihi = getattr(p, "inclusive_bounds", (True, True))
    space = f" {unit}" if unit else ""
    return (f"{name} must be in {'[' if ilo else '('}{lo:g}, {hi:g}{']' if ihi else ')'}{space}, "
            f"got {float(value):g}{space}")


def _contact_inputs(contact: core.Contact) -> dict:
    """The state's geometry and material inputs (UI units) of a core contact preset."""
    rigid = math.isinf(contact.E1)
    out = dict(R=contact.R1 / _MM, L=contact.L / _MM, Fn=contact.Fn, mu=contact.mu,
               E2=contact.E2 / _MPA, nu2=contact.nu2, rigid=rigid)
    if not rigid:
        out.update(E1=contact.E1 / _MPA, nu1=contact.nu1)
    return out


_SIMULATION = _contact_inputs(core.PAPER_SIMULATION)
_SOLVER_PAPER = dict(body="cylinder", kernel="strip", schedule="triangle", periods=10)

#: Named sets of inputs: the paper's simulation (eq 17), its experiment
#: (Table 1) and the cases of its Figs 6 (shakedown) and 7 (ratcheting).
PRESETS: dict[str, dict] = {
    "Paper simulation (eq 17)": dict(_SIMULATION, **_SOLVER_PAPER),
    "Paper experiment (Table 1)": dict(_contact_inputs(core.PAPER_EXPERIMENT), **_SOLVER_PAPER),
    **{f"Fig 6: ft = 0.08, w = {w}": dict(_SIMULATION, ft=0.08, w=w, **_SOLVER_PAPER) for w in (0.26, 0.52, 0.77)},
    **{f"Fig 7: ft = 0.58, w = {w}": dict(_SIMULATION, ft=0.58, w=w, **_SOLVER_PAPER) for w in (0.26, 0.52, 0.77)},
}

#: What to know beside a preset.
PRESET_NOTES: dict[str, str] = {
    "Fig 7: ft = 0.58, w = 0.26": (
        "**Note:** the paper's Fig. 7 caption lists this case among the ratcheting ones, but eq 35 gives "
        "ft_lim(0.26) = 0.673 > 0.58, and the solver agrees: it shakes down. The badge's SHAKEDOWN is not a bug."),
}

#: Every body's parameters as inputs (from core.geometry.registry, :func:`app.bodies.state_parameters`).
_BODY_INPUTS = bodies.state_parameters()
for _name, _p in _BODY_INPUTS.items():
    ExplorerState.param.add_parameter(_name, _p)
def _within(spec: param.Number, value: float) -> bool:
    """Whether ``value`` lies in the bounds of the number parameter ``spec`` (open or closed ends as declared)."""
    lo, hi = spec.bounds or (None, None)
    lo_closed, hi_closed = spec.inclusive_bounds
    return ((lo is None or value > lo or (lo_closed and value == lo))
            and (hi is None or value < hi or (hi_closed and value == hi)))


#: The inputs whose values are rounded to 1e-6 (see :meth:`ExplorerState.__setattr__`).
_ROUNDED = ("ft", "w", "mu", *(n for n, p in _BODY_INPUTS.items() if isinstance(p, param.Number)))

#: Parameters synced with the URL, each under its own name.
URL_PARAMETERS = tuple(p for p in ExplorerState.param if p != "name")


# --------------------------------------------------------------------------
# URL query parameters
# --------------------------------------------------------------------------
_TRUE, _FALSE = {"true", "1", "yes", "on"}, {"false", "0", "no", "off"}


def _convert(p: param.Parameter, name: str, text: str):
    """Turn one query-string value into a value of parameter ``p``; ValueError if it is not one."""
    if isinstance(p, param.Boolean):
        low = text.strip().lower()
        if low in _TRUE:
            return True
        if low in _FALSE:
            return False
        raise ValueError(f"{name} must be true or false, got {text!r}")
    if isinstance(p, param.Selector):
        if text not in p.objects:
            raise ValueError(f"{name} must be one of {', '.join(map(str, p.objects))}, got {text!r}")
        return text
    if isinstance(p, param.String):
        return text
    if isinstance(p, param.Integer):
        try:
            value = float(text)
        except ValueError:
            raise ValueError(f"{name} must be an integer, got {text!r}") from None
        if not math.isfinite(value) or not value.is_integer():
            raise ValueError(f"{name} must be an integer, got {text!r}")
        return int(value)
    if isinstance(p, param.Number):
        try:
            value = float(text)
        except ValueError:
            raise ValueError(f"{name} must be a number, got {text!r}") from None
        if not math.isfinite(value):
            raise ValueError(f"{name} must be a finite number, got {text!r}")
        return value
    raise ValueError(f"{name} cannot be set from the URL")  # pragma: no cover


def _range_text(p: param.Parameter) -> str:
    if isinstance(p, param.String):
        return "demo or upload-<digest>" if p.regex == bodies.SOURCE_PATTERN.pattern else f"/{p.regex}/"
    lo, hi = p.bounds
    ilo, ihi = getattr(p, "inclusive_bounds", (True, True))
    return f"{'[' if ilo else '('}{lo:g}, {hi:g}{']' if ihi else ')'}"


def parse_query(query: str | Mapping[str, object]) -> tuple[dict, list[str], list[str]]:
    """Validate URL query parameters against :class:`ExplorerState`.

    Parameters
    ----------
    query : str or mapping
        A query string (``"?ft=0.3&w=0.5"``, leading ``?`` optional) or a
        mapping of names to a value or a list of values (repeated keys).

    Returns
    -------
    updates : dict
        Valid values, ready for ``state.param.update(**updates)``.
    errors : list of str
        One message per rejected parameter (naming it, its value and the allowed
        values); rejected parameters are not in ``updates``.
    ignored : list of str
        Names that are not parameters of the explorer.
    """
    if isinstance(query, str):
        pairs = urllib.parse.parse_qsl(query.lstrip("?"), keep_blank_values=True)
        items: dict[str, list[str]] = {}
        for k, v in pairs:
            items.setdefault(k, []).append(v)
    else:
        items = {k: (list(v) if isinstance(v, (list, tuple)) else [v]) for k, v in query.items()}
    updates, errors, ignored = {}, [], []
    scratch = ExplorerState()
    for key, raw in items.items():
        if key not in URL_PARAMETERS:
            ignored.append(str(key)[:MAX_QUERY_VALUE_LENGTH])
            continue
        values = [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in raw]
        if not values:  # a key with no value at all (possible in a mapping): as if absent
            continue
        p = ExplorerState.param[key]
        try:
            if len(set(values)) > 1:
                raise ValueError(f"{key} is given {len(values)} times with different values")
            text = values[0]
            if len(text) > MAX_QUERY_VALUE_LENGTH:
                raise ValueError(f"{key} is too long ({len(text)} characters)")
            value = _convert(p, key, text)
            try:
                scratch.param.update(**{key: value})
            except ValueError:
                raise ValueError(f"{key} must be in {_range_text(p)}, got {text!r}") from None
        except ValueError as e:
            errors.append(str(e))
            continue
        updates[key] = value
    return updates, errors, ignored
