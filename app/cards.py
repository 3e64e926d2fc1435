"""The verdict badge, the summary cards and the model's warnings, as HTML (no physics: numbers from :mod:`core`).

The cards come in two forms: :func:`strip_html`, a one-line strip of the few numbers a class looks at
(the margins, the stick zone, the last increment), always on the first screen, and :func:`cards_html`, every
number, one click away. :class:`CardsMixin` gives the explorer its ``_badge``, ``_cards`` and ``_warnings``.
"""

from __future__ import annotations

import functools
import html
import math
import re

import numpy as np

import core
from core.records.result import COUPLED_GRID_NOTE

from . import bodies

__all__ = ["CardsMixin", "prediction", "limit_name", "body_limits", "body_name", "cards_html", "strip_html", "point_rows", "cylinder_rows",
           "fmt", "count", "coupled_beta", "coupled_prediction", "STRIP_KEYS", "on_side", "input_digits", "inputs_text", "NO_WALK",
           "energy_row", "SOLVING_BADGE", "SPINNER_DELAY_MS"]

#: A solve shows its spinner only after this long [ms] (one not over in a blink shows none).
SPINNER_DELAY_MS = 150
#: The badge's words while the current inputs' run is on its way, with a spinner that the browser shows after
#: :data:`SPINNER_DELAY_MS` (a CSS animation, ``.solve-spinner`` of :data:`app.styles.CSS`: the server sends nothing
#: to start or stop it, and the page's layout never changes for it).
SOLVING_BADGE = (f'<span class="solve-spinner" style="animation-delay: 0s, {SPINNER_DELAY_MS}ms" '
                 'aria-hidden="true"></span>SOLVING…')

#: The rows of the cards shown in the strip, in its order, with their short names there (the first row of each
#: group that is present).
STRIP_KEYS = ((("margin ft / ft_lim", "ft/ft_lim"), ("margin ft / ft_lim (eq 35, uncoupled)", "ft/ft_lim (eq 35)")),
              (("margin w / w_lim", "w/w_lim"), ("margin w / w_lim (eq 35, uncoupled)", "w/w_lim (eq 35)")),
              (("c_sd numerical", "c_sd"), ("c_sd numerical (y = 0)", "c_sd (y = 0)")),
              (("Δu last period", "Δu/period"), ("creep per period (last)", "creep/period")),
              (("energy per period (last)", "energy/period"),), (("grid error of Δu", "grid error"),))


@functools.lru_cache(maxsize=4096)
def _closure(ft: float, w: float) -> tuple[float, float, float]:
    """The cylinder's closed forms the cards show: c_sd (eq 30), ft_lim(w) and w_lim(ft) (eq 35). Memoised:
    the cards are redrawn several times per slider move, and w_lim is a root search (about 1 ms)."""
    return (float(core.shakedown_stick_halfwidth(ft, w)), float(core.ft_limit(w)), float(core.w_limit(ft)))


def body_name(body) -> str:
    """The name of a body given by name or object (a height map is the registry's 'heightmap')."""
    if isinstance(body, str):
        return body
    name = str(getattr(body, "name", type(body).__name__))
    return "heightmap" if name.startswith("heightmap") else name


def limit_name(body) -> str:
    """How the exact limit of ``body`` (a name or a body object) is cited."""
    from core.geometry.registry import resolve

    try:
        citation = getattr(resolve(body), "limit_citation", None)
    except ValueError:  # a body that needs inputs to be built (a height map's file)
        citation = None
    return citation or f"the {body_name(body)}'s exact limit"


@functools.lru_cache(maxsize=4096)
def body_limits(ft: float, w: float, body) -> tuple[float, float]:
    """``ft_lim(w)`` and ``w_lim(ft)`` of ``body`` (a name or a body object; :func:`core.ft_limit`,
    :func:`core.w_limit`), memoised (the cards are redrawn several times per slider move); NaN where the limit
    cannot be evaluated."""
    try:
        return float(core.ft_limit(w, body=body)), float(core.w_limit(ft, body=body))
    except (ValueError, TypeError, NotImplementedError):
        return math.nan, math.nan


def prediction(ft: float, w: float, body) -> tuple[str, str]:
    """The regime the exact limit of ``body`` (a name or a body object) predicts for ``ft``, ``w``, and how that
    limit is cited."""
    if bodies.has_closure(body):  # the paper's closed forms (eq 35)
        return str(core.classify_regime(ft, w)), limit_name(body)
    lim = body_limits(ft, w, body)[0]
    if not math.isfinite(lim):
        return "unknown", limit_name(body)
    return ("shakedown" if ft <= lim else "ratcheting"), limit_name(body)


def coupled_prediction(ft: float, w: float, beta: float, predicted: str, rule: str, curve) -> tuple[str, str]:
    """What a coupled contact's verdict is compared with: the coupled limit curve's ``ft_lim`` at ``w`` once the
    curve reaches ``w`` (:meth:`core.CoupledLimitCurve.ft_limit_at`), with eq 35's prediction beside it as the
    uncoupled reference; until then (or outside the curve's amplitudes) eq 35, named the uncoupled reference.

    Returns
    -------
    (predicted, rule)
        As :func:`prediction`: the regime predicted and the limit it comes from, in words.
    """
    reference = f"{rule} (the uncoupled reference; this contact is coupled, β = {beta:.3g})"
    lim = math.nan if curve is None or not curve.points else curve.ft_limit_at(min(max(w, 0.0), 0.999))
    if not math.isfinite(lim):
        if curve is None:  # no coupled curve for this run (another body, another loading)
            return predicted, reference
        ws = [p.w for p in curve.points if p.converged]
        why = (f"the coupled limit is known for w in [{min(ws):.2g}, {max(ws):.2g}]" if ws
               else "computing the coupled limit…")
        return predicted, f"{reference}; {why}"
    # the coupled limit parts the runs that ratchet from those that do not: below it a coupled contact shakes down
    # or slips a little every period (cyclic micro-slip), which the limit does not tell apart
    coupled = "no ratcheting" if ft <= lim else "ratcheting"
    # short: the note sits under the badge, above the first screen's figures
    return coupled, (f"the coupled limit ft_lim = {lim:.3f} (numerical, β = {beta:.3g}, μ = {curve.mu:.3g}; "
                     f"eq 35, the uncoupled reference: {float(core.ft_limit(w)):.3f}, {predicted})")


def tangential_note(history: dict, body) -> str | None:
    """What applies under the tangential loading (a fixed centre, ``Q/(mu P) = ft + A sin``) in place of the
    rocking limit's prediction, with the closed-form energy per cycle (:func:`core.fretting_energy`) of a body
    that has it; None under the other loadings (``history``: :meth:`app.state.ExplorerState.history_options`)."""
    if history.get("history") != "tangential":
        return None
    A = float(history["amplitude"])
    # short: the note sits under the badge, above the first screen's figures (five lines pushed the sphere's
    # figures 17 px past the bottom of a 1280x720 screen)
    note = (f"tangential loading, fixed centre, A = {A:.3g}: the rocking limit does not apply; cyclic slip below "
            f"gross sliding (|ft| + A < 1)")
    try:
        E = float(core.fretting_energy(A, body=body))
    except (ValueError, TypeError, NotImplementedError):  # no closed-form loop for this body
        return note
    point = bodies.kind(body) == "point" if isinstance(body, str) else not isinstance(body, core.Body)
    unit, source = (("μ² Fn²/(E* a)", "Mindlin-Deresiewicz") if point
                    else ("μ² P²/E* per unit length", "Cattaneo-Mindlin"))
    return note + f"; energy per cycle, closed form ({source}): {E:.4g} {unit}"


def fmt(v, unit="", digits=4) -> str:
    """``v`` to ``digits`` significant digits with its unit; '–' for None and non-finite values."""
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    return f"{v:.{digits}g}{(' ' + unit) if unit else ''}"


def on_side(x: float, ref: float, decimals: int = 2) -> str:
    """``x`` with at least ``decimals`` decimals, and as many more (up to 6: the inputs are held to 1e-6) as it
    takes for the printed value to stay on ``x``'s side of ``ref`` (ft = 0.206 against ft_lim = 0.2084 prints
    0.206, not 0.21: a rounded number must not cross a limit)."""
    x, ref = float(x), float(ref)
    if not (math.isfinite(x) and math.isfinite(ref)) or x == ref:
        return f"{x:.{decimals}f}"
    for d in range(decimals, 7):
        printed = round(x, d)
        if (printed - ref) * (x - ref) > 0:
            break
    return f"{x:.{d}f}"


def input_digits(ft: float, w: float, body="cylinder") -> tuple[str, str]:
    """``ft`` and ``w`` as text, each to enough digits to stay on its side of the exact limit of ``body``: ft
    against ft_lim(w), w against w_lim(ft) (:func:`on_side`)."""
    if bodies.has_closure(body):  # the paper's closed forms (eq 35)
        _, ft_lim, w_lim = _closure(ft, w)
    else:
        ft_lim, w_lim = body_limits(ft, w, body)
    return on_side(ft, ft_lim), on_side(w, w_lim)


def inputs_text(ft: float, w: float, body="cylinder") -> str:
    """"ft = …, w = …" for a note (:func:`input_digits`)."""
    ft_text, w_text = input_digits(ft, w, body)
    return f"ft = {ft_text}, w = {w_text}"


def count(n: int) -> str:
    """A number of cycles, short: 1000, 2.5×10⁶."""
    if n < 10**4:
        return str(n)
    e = int(math.floor(math.log10(n)))
    m = n / 10**e
    power = "10" + str(e).translate(str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return power if abs(m - 1) < 1e-9 else f"{m:.3g}×{power}"


#: Regimes whose body stops walking: the last increment is the solver's noise, an error relative to it means nothing.
NO_WALK = ("shakedown", "cyclic slip")


def energy_row(result, energy_unit=None) -> tuple[str, str]:
    """The card row of the energy dissipated in the last period (:attr:`core.CycleResult.dissipation_per_period`):
    normalised, or in J/m (a line) or J (a point contact) given the contact's ``energy_unit`` [J/m or J]."""
    energy = result.dissipation_per_period
    last = float(energy[-1]) if energy.size else math.nan
    if energy_unit is not None:
        si = "J" if result.is_patch else "J/m"
        return ("energy per period (last)", fmt(last * energy_unit, si, 3))
    unit = "μ²Fn²/(E*a)" if result.is_patch else "μ²P²/E*"
    return ("energy per period (last)", fmt(last, unit, 3))


def point_rows(ft, w, mu, contact, result, wait, units="normalised", cycles=10**6, body="sphere",
               grid_error=None) -> list:
    """The rows of a point contact's cards: the inputs in physical units, the exact limits of this body and of
    the cylinder (eq 35), and the run's numbers (``wait``: why they are not shown, or None). ``grid_error``:
    the estimated discretisation error of the last increment (a :class:`core.ConvergedIncrement`), if known."""
    rows = []
    c = None
    if contact is not None:
        c = contact.replace(mu=mu, ft=ft, w=w)
        rows += [("Ft (tangential force)", fmt(c.Ft, "N")), ("W (rocking amplitude)", fmt(c.W * 1e6, "µm")),
                 ("a (semi-axis along x)", fmt(c.a * 1e3, "mm")), ("b (semi-axis along y)", fmt(c.b * 1e3, "mm")),
                 ("p0 (peak pressure)", fmt(c.p0 / 1e6, "MPa")), ("ν of the half-space kernel", fmt(c.nu, "", 3))]
    lim, wlim = body_limits(ft, w, body)
    name = body_name(body)
    rows += [(f"ft_lim(w), {name} (exact)", _limit(lim, ft)), (f"w_lim(ft), {name} (exact)", _limit(wlim, w)),
             ("ft_lim(w), cylinder (eq 35)", _limit(float(core.ft_limit(w)), ft)),
             ("margin ft / ft_lim", _margin(ft, lim)), ("margin w / w_lim", _margin(w, wlim))]
    if wait:
        rows += [("c_sd numerical (y = 0)", wait), ("Δu last period", wait), ("energy per period (last)", wait),
                 ("solve", wait)]
        return rows
    physical = units == "physical" and c is not None
    scale, unit = (c.a * 1e3, "mm") if physical else (1.0, "a")
    rows.append(("c_sd numerical (y = 0)", fmt(result.stick_halfwidth * scale, unit, 3)))
    inc = float(result.increment_per_period[-1])
    if physical:
        um = inc * c.displacement_unit * 1e6
        rows += [("creep per period (last)", fmt(um, "µm", 3)),
                 (f"creep after {count(cycles)} periods", fmt(um * cycles / 1e3, "mm", 3))]
    else:
        rows.append(("Δu last period", f"{inc:.3g} μFn/(E*a)"))
    rows.append(energy_row(result, c.energy_unit if physical else None))
    scale, unit = (c.displacement_unit * 1e6, "µm") if physical else (1.0, "μFn/(E*a)")
    rows.append(("grid error of Δu", "estimating…" if grid_error is None
                 else grid_error_text(grid_error, inc, scale, unit, relative=result.regime not in NO_WALK)))
    rows.append(grid_limit_row(result))
    nx, ny = result.x_edges.size - 1, result.y_edges.size - 1
    rows.append(("solve", f"{result.runtime:.1f} s, {nx}×{ny} el. (dx = a/{1 / result.dx:.3g}), "
                          f"{result.xc.size} steps"))
    return rows


def _margin(x: float, limit: float) -> str:
    """The margin ``x / limit`` of a card, on its side of 1 (:func:`on_side`); '–' without a positive limit."""
    return on_side(x / limit, 1.0, 3) if limit > 0 and math.isfinite(limit) else "–"


def _limit(limit: float, x: float) -> str:
    """A limit on a card (4 decimals), on its side of the input ``x`` it is the limit of (:func:`on_side`)."""
    return on_side(limit, x, 4) if math.isfinite(limit) else "–"


def grid_limit_row(result) -> tuple[str, str]:
    """The card row of Melan's limit on the run's own grid (:attr:`core.CycleResult.melan_limit`, in ft): the
    limit the run's verdict is checked against, beside the body's exact one."""
    limit = result.melan_limit
    if limit is None:
        return ("ft_lim on this grid (Melan)", "– (the tangential load varies over a period)")
    lo, hi = limit
    return ("ft_lim on this grid (Melan)", fmt(lo, "", 4) if hi - lo <= 1e-12 * hi else f"{lo:.4f} – {hi:.4f}")


def grid_error_text(estimate, inc: float, scale: float = 1.0, unit: str = "", relative: bool = True) -> str:
    """The estimated discretisation error of the last increment ``inc`` (relative, and in ``unit``: the error
    times ``scale``), as the cards show it. ``relative=False`` (a run that shook down: its last increment is the
    solver's noise, and the error relative to it means nothing): in ``unit`` only."""
    err = float(estimate.error)
    if not math.isfinite(err):
        return "not estimated"
    rel = err / abs(inc) if inc and relative else math.inf
    absolute = f"±{err * scale:.2g} {unit}".rstrip()
    return f"±{100 * rel:.0f} % ({absolute})" if math.isfinite(rel) else absolute


def coupled_beta(contact) -> float | None:
    """Dundurs' β of a contact whose runs are coupled (:attr:`core.Contact.coupled`), else None."""
    return float(contact.beta) if getattr(contact, "coupled", False) else None


def _limit_label(label: str, contact) -> str:
    """A limit's row label, marked as the uncoupled reference when the contact is coupled."""
    return label if coupled_beta(contact) is None else f"{label[:-1]}, uncoupled)"  # "... (eq 35, uncoupled)"


def cylinder_rows(ft, w, mu, contact, result, wait, units="normalised", cycles=10**6, body="cylinder") -> list:
    """The rows of a line body's cards: inputs in physical units (the cylinder's Hertz scales), the closure's
    (the cylinder's only) and the solver's numbers, the exact limits and the margins (``wait``: why the solver's
    are not shown, or None). ``body``: the cylinder, or another line body (a name or an object)."""
    if not bodies.has_closure(body):
        return _line_rows(ft, w, mu, contact, result, wait, units, cycles, body)
    rows = []
    physical = units == "physical"
    c = None if contact is None else contact.replace(mu=mu, ft=ft, w=w)
    if c is not None:
        rows += [("Ft (tangential force)", fmt(ft * mu * c.Fn, "N")), ("W (rocking amplitude)", fmt(w * c.a * 1e6, "µm")),
                 ("a (half-width)", fmt(c.a * 1e3, "mm")), ("p0 (peak pressure)", fmt(c.p0 / 1e6, "MPa")),
                 ("d (indentation, eq 6)", fmt(c.d * 1e3, "mm")), ("Dundurs β", fmt(c.beta, "", 3))]
    u0 = None if wait else result.u0
    if u0 is not None and c is not None:
        rows.append(("U0 (ft = 1, strip)", fmt(u0 * c.displacement_unit * 1e6, "µm")))
    csd, ft_lim, w_lim = _closure(ft, w)
    scale, unit = (c.a * 1e3, "mm") if (physical and c is not None) else (1.0, "a")
    rows += [("c_sd closure (eq 30)", fmt(csd * scale, unit, 3) if math.isfinite(csd) else "none (ft > ft_lim)"),
             ("c_sd numerical", wait or fmt(result.stick_halfwidth * scale, unit, 3)),
             (_limit_label("ft_lim(w) (eq 35)", c), _limit(ft_lim, ft)),
             (_limit_label("w_lim(ft) (eq 35)", c), _limit(w_lim, w))]
    return rows + _line_tail(ft, w, ft_lim, w_lim, result, wait, c if physical else None, cycles, c)


def _line_rows(ft, w, mu, contact, result, wait, units, cycles, body) -> list:
    """The cards of a line body other than the cylinder: its exact limits (Melan, :func:`core.ft_limit`), no closure."""
    rows = []
    c = None if contact is None else contact.replace(mu=mu, ft=ft, w=w)
    if c is not None:
        rows += [("Ft (tangential force)", fmt(ft * mu * c.Fn, "N")),
                 ("W (rocking amplitude)", fmt(w * c.a * 1e6, "µm")),
                 ("a (the cylinder of R's half-width)", fmt(c.a * 1e3, "mm"))]
    lim, wlim = body_limits(ft, w, body)
    name = body_name(body)
    physical = units == "physical" and c is not None
    scale, unit = (c.a * 1e3, "mm") if physical else (1.0, "a")
    rows += [("c_sd numerical", wait or fmt(result.stick_halfwidth * scale, unit, 3)),
             (_limit_label(f"ft_lim(w), {name} (exact)", c), _limit(lim, ft)),
             (_limit_label(f"w_lim(ft), {name} (exact)", c), _limit(wlim, w)),
             (_limit_label("ft_lim(w), cylinder (eq 35)", c), _limit(float(core.ft_limit(w)), ft))]
    return rows + _line_tail(ft, w, lim, wlim, result, wait, c if physical else None, cycles)


def _line_tail(ft, w, ft_lim, w_lim, result, wait, physical_contact, cycles, contact=None) -> list:
    """The rows every line body's cards end with: the margins to its limits, the creep of the last period (in
    physical units when ``physical_contact`` is the contact, else in U0 or mu P/E*) and the solve. A coupled
    ``contact``'s margins are to eq 35, named the uncoupled reference (its own limit is the map's coupled curve)."""
    uncoupled = "" if coupled_beta(contact) is None else " (eq 35, uncoupled)"
    rows = [(f"margin ft / ft_lim{uncoupled}", _margin(ft, ft_lim)), (f"margin w / w_lim{uncoupled}", _margin(w, w_lim))]
    if wait:
        return rows + [("Δu last period", wait), ("energy per period (last)", wait), ("solve", wait)]
    inc = float(result.increment_per_period[-1])
    if physical_contact is not None:
        um = inc * physical_contact.displacement_unit * 1e6
        rows += [("creep per period (last)", fmt(um, "µm", 3)),
                 (f"creep after {count(cycles)} periods", fmt(um * cycles / 1e3, "mm", 3))]
    else:
        unit_u = "U0" if result.u0 else "μP/E*"
        rows.append(("Δu last period", f"{(inc / result.u0 if result.u0 else inc):.3g} {unit_u}"))
    rows.append(energy_row(result, None if physical_contact is None else physical_contact.energy_unit))
    rows.append(grid_limit_row(result))
    rows.append(("solve", f"{result.runtime * 1e3:.0f} ms, {result.edges.size - 1} el., {result.xc.size} steps"))
    return rows


def cards_html(rows, wait=None) -> str:
    """Summary cards (HTML) of ``(name, value)`` rows; values equal to ``wait`` are shown as pending."""
    body = "".join(
        f"<div><span class='k'>{html.escape(k)}</span><span class='v{' pending' if v == wait else ''}'>"
        f"{html.escape(v)}</span></div>" for k, v in rows)
    return f"<div class='cards'>{body}</div>"


def strip_html(rows, wait=None) -> str:
    """The compact strip (HTML): the rows named in :data:`STRIP_KEYS` on one line, that wraps when narrow."""
    found = dict(rows)
    items = []
    for names in STRIP_KEYS:
        for name, short in names:
            if name in found:
                v = found[name] if name != "grid error of Δu" else found[name].split(" (")[0]  # short: relative
                items.append(f"<span class='item' title='{html.escape(name)}'><span class='k'>{html.escape(short)}</span> "
                             f"<span class='v{' pending' if v == wait else ''}'>{html.escape(v)}</span></span>")
                break
    solve = found.get("solve")  # the run's size, as a tooltip (and what a load test's client reads)
    tip = f" title='every number; solve: {html.escape(solve)}'" if solve and solve != wait else ""
    items.append(f"<span class='more'{tip}>all numbers ▾</span>")
    return f"<div class='strip'>{''.join(items)}</div>"


class CardsMixin:
    """The explorer's badge, cards and warnings (methods of :class:`app.explorer.Explorer`)."""

    @staticmethod
    def _shows(result, ft, w, point: bool | None = None) -> bool:
        """Whether ``result`` is the run of the inputs ``ft``, ``w`` the sliders show and, if ``point`` is given,
        of a point contact or not (a body switch changes the contact before the new body's run is there)."""
        return (result is not None and abs(float(result.params.get("ft", math.nan)) - ft) < 1e-9
                and abs(float(result.params.get("w", math.nan)) - w) < 1e-9
                and (point is None or isinstance(result, core.PointContactResult) == point))

    def _body_spec(self):
        """The current body as an object (its parameters), or its name if it cannot be built from the inputs."""
        state = getattr(self, "state", None)  # (also called on the class, headless)
        if state is None:
            return "cylinder"
        try:
            return state.body if state.body == bodies.DEFAULT else state.body_object()
        except ValueError:
            return state.body

    def _badge(self, ft, w, result, error, pending=False, coupled=None):
        spec = CardsMixin._body_spec(self)  # self may be the class (headless tests)
        predicted, rule = prediction(ft, w, spec)
        beta = coupled_beta(getattr(self, "contact", None))
        if beta is not None:  # Melan's theorem does not decide a coupled contact: its limit is a reference
            predicted, rule = coupled_prediction(ft, w, beta, predicted, rule, coupled)
        state = getattr(self, "state", None)
        instead = tangential_note(state.history_options() if state is not None else {}, spec)
        if error.startswith("limit only"):  # a body whose cycles the explorer cannot run yet: its limit only
            return ('<span class="regime-badge regime-none" data-regime="limit-only">LIMIT ONLY</span>'
                    f'<div class="regime-note">{html.escape(rule)} predicts {html.escape(predicted)} for '
                    f'{inputs_text(ft, w, spec)}<br>{html.escape(error)}</div>')
        if error:
            return ('<span class="regime-badge regime-none" data-regime="invalid">INVALID INPUT</span>'
                    f'<div class="regime-note">{html.escape(error)}</div>')
        point = getattr(getattr(self, "state", None), "point", None)
        if pending or not self._shows(result, ft, w, point):
            what = SOLVING_BADGE if pending or result is None else "RELEASE TO SOLVE"
            text = html.escape(instead) if instead else f"{rule} predicts {predicted} for {inputs_text(ft, w, spec)}"
            return (f'<span class="regime-badge regime-none" data-regime="pending">{what}</span>'
                    f'<div class="regime-note">{text}</div>')
        regime = str(result.regime)
        note = f"solver, {result.periods} periods"
        if result.shakedown_period is not None:
            note += f"; shaken down after period {result.shakedown_period}"
        if regime == "undetermined":  # the periods run cannot tell: why, one click away
            note += f" <details class='why'><summary>why undetermined</summary>{html.escape(str(result.regime_reason))}</details>"
        else:
            note += "<br>"
        note += (html.escape(instead) if instead else
                 f"{html.escape(rule)} predicts {html.escape(str(predicted))} for {inputs_text(ft, w, spec)}")
        css = re.sub(r"[^a-z]", "", regime.lower()) or "none"
        return (f'<span class="regime-badge regime-{css}" data-regime="{html.escape(regime)}">'
                f'{html.escape(regime.upper())}</span><div class="regime-note">{note}</div>')

    def _card_rows(self, ft, w, mu, contact, result, pending=False, units="normalised", cycles=10**6,
                   grid_error=None) -> tuple[list, str | None]:
        """The cards' rows and why the run's numbers are not shown (None when they are)."""
        point = self.state.point
        fresh = not pending and self._shows(result, ft, w, point)
        if fresh:
            wait = None
        elif result is None and not pending and self.error:
            wait = "no run"  # the inputs were refused: nothing is being solved (the badge says why)
        else:
            wait = "solving…" if pending or result is None else "release the slider"
        if (contact is not None and contact.is_point) or point:
            error = grid_error if (grid_error is not None and fresh and grid_error.result is result) else None
            return point_rows(ft, w, mu, contact, result, wait, units, cycles, self._body_spec(), error), wait
        return cylinder_rows(ft, w, mu, contact, result, wait, units, cycles, self._body_spec()), wait

    def _cards(self, ft, w, mu, contact, result, pending=False, units="normalised", cycles=10**6, grid_error=None):
        """Every summary card (HTML). Numerical values are shown only when the run shown is the current inputs'
        run (else 'solving…')."""
        return cards_html(*self._card_rows(ft, w, mu, contact, result, pending, units, cycles, grid_error))

    def _strip(self, ft, w, mu, contact, result, pending=False, units="normalised", cycles=10**6, grid_error=None):
        """The compact strip of the key numbers (HTML)."""
        return strip_html(*self._card_rows(ft, w, mu, contact, result, pending, units, cycles, grid_error))

    def _warnings(self, ft, w, contact, result):
        out = [] if contact is None else list(getattr(contact, "warnings", ()))
        if result is not None and isinstance(result, core.PointContactResult) != self.state.point:
            result = None  # the other body's run, until the new body's comes (a body switch)
        if w > 0.95:
            out.append(f"w = {w:.2f}: b = a − W = {1 - w:.2f} a is tiny; the always-in-contact band spans "
                       f"{(1 - w) / self.state.dx * 2:.0f} elements.")
        if result is not None and result.params.get("history") == "normal":
            out.append(f"the normal force oscillates by ±{100 * float(result.params.get('amplitude', 0)):.0f} %: "
                       "eq 35 and the Hertz curves at xc = 0, ±W are those of the mean force; the figures draw "
                       "the run's own lowest pressure and no closure; the solver's verdict is the one to trust.")
        if result is not None and getattr(result, "coupled", False) and result.regime == "cyclic slip":
            out.append(COUPLED_GRID_NOTE.lstrip("; ") + ".")
        if result is not None:
            n_b = 2 * (1 - float(result.params.get("w", w))) / result.dx
            if n_b < 8:
                out.append(f"only {n_b:.0f} elements resolve b = a − W: raise the resolution.")
            inc = np.abs(result.increment_per_period)
            if result.regime == "ratcheting" and inc.size >= 2 and inc[-1] < 0.7 * inc[-2]:
                out.append("the increment per period is still falling: run more periods to tell slow "
                           "shakedown from ratcheting.")
        return out
