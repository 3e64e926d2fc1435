"""Numbers, shading and state a class can trust (issue 31, items 3, 4, 6, 9, 10), without a browser.

- item 3: the traction figure's shading is computed from the states its curve and the numbers come from, for
  every body of :data:`core.geometry.registry.REGISTRY`: at a step inside the run, slip is shaded where the traction is
  on ±μ p and stick where it is below; at the last step, the zones are the final zones the strip's c_sd is
  measured on (its stick width is c_sd), and nothing is shaded 'zero traction' where traction is left;
- item 4: a printed ft or w never crosses its limit (notes, cards, pins, sliders);
- item 6: the inputs never hold float noise, however they are set;
- item 9: the inputs' labels and tooltips are in a user's words;
- item 10: a typed geometry is checked with a message in the inputs' units, and no old run stays on show.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import core
from app import bodies, plots
from app import runs
from app.cards import inputs_text, on_side
from app.explorer import SLIDER_FORMAT, Explorer
from app.state import URL_PARAMETERS, ExplorerState
from core.records.result import STICK_MARGIN, ZERO_TRACTION

#: Every body the explorer runs, with inputs that give a short run (the heightmap: the built-in demo map).
RUNNABLE = [b for b in core.geometry.registry.REGISTRY if bodies.runs_cycles(b, ExplorerState(body=b).body_object())]


def _run(**inputs):
    """The run the explorer shows for ``inputs`` (Contact.simulate: each body the way the app runs it)."""
    state = ExplorerState(**inputs)
    options = state.solver_options()
    return state.contact().simulate(**options)


def _magnitude(result, k):
    q = result.traction[k]
    return np.hypot(q[0], q[1]) if result.is_patch else np.abs(q)


def _bound(result, k):
    p = result.pressure[k]
    return p[result.cut_row] if result.is_patch else p


def _check_shading(result):
    """The zones shaded at a mid-run step and at the last step agree with the curve and the numbers."""
    Zone = core.Zone
    last = result.xc.size - 1
    # a step inside the last period: the element states of that step, those the curve shows
    k = last - max(1, (result.period == result.period[-1]).sum() // 4)
    zones, q, bound = plots.traction_zones(result, k), _magnitude(result, k), _bound(result, k)
    slip, stick = zones == Zone.SLIP, zones == Zone.STICK
    np.testing.assert_allclose(q[slip], bound[slip], atol=1e-6, err_msg=f"slip shaded off ±μ p at step {k}")
    assert np.all(q[stick] <= bound[stick] + 1e-9), f"stick shaded above μ p at step {k}"
    assert np.all(q[zones == Zone.RELEASED] == 0), f"zero traction shaded under traction at step {k}"
    # the last step: the final zones, the ones the numbers' c_sd is measured on
    zones, q = plots.traction_zones(result, last), _magnitude(result, last)
    low = result.lowest_pressure[result.cut_row] if result.is_patch else result.lowest_pressure
    np.testing.assert_array_equal(zones, result.final_zones)
    assert core.records.result.central_halfwidth(zones == Zone.STICK, result.edges) == result.stick_halfwidth
    assert np.all(q[zones == Zone.STICK] < low[zones == Zone.STICK]), "stick shaded at or above μ p_min"
    assert np.all(q[zones == Zone.SLIP] >= low[zones == Zone.SLIP] - STICK_MARGIN), "slip shaded below μ p_min"
    assert np.all(q[zones == Zone.RELEASED] <= ZERO_TRACTION), "zero traction shaded under traction"


@pytest.mark.parametrize("body", RUNNABLE)
def test_every_body_shades_what_its_curve_and_numbers_say(body):
    _check_shading(_run(body=body, periods=3))


@pytest.mark.parametrize("inputs", [dict(ft=0.74, w=0.8), dict(body="sphere", ft=0.35)], ids=["cylinder", "sphere"])
def test_a_ratcheting_run_is_not_shaded_zero_traction_where_traction_is_left(inputs):
    # the issue's cases: the cylinder at ft = 0.74, w = 0.8 showed -1..-0.2 and 0.2..1 as 'zero traction' at the
    # last step where its traction lies on μ p; the sphere at ft = 0.35 shaded 'stick' where c_sd (y = 0) = 0
    result = _run(**inputs)
    assert result.regime == "ratcheting"
    _check_shading(result)
    last = result.xc.size - 1
    zones, q = plots.traction_zones(result, last), _magnitude(result, last)
    assert np.all(zones[q > ZERO_TRACTION] != core.Zone.RELEASED)
    assert result.stick_halfwidth == 0 and not np.any(zones == core.Zone.STICK)


def test_the_default_sphere_shades_its_stick_zone_as_wide_as_its_c_sd():
    result = _run(body="sphere")
    zones = plots.traction_zones(result, result.xc.size - 1)
    stick = result.x[zones == core.Zone.STICK]
    half = 0.5 * (stick.max() - stick.min()) + 0.5 * result.dx
    assert result.stick_halfwidth > 0
    np.testing.assert_allclose(half, result.stick_halfwidth, rtol=1e-12)


# ---------------------------------------------------------------- item 4: digits
@pytest.mark.parametrize("x, ref, text", [(0.206, 0.2084, "0.206"), (0.3, 0.6727, "0.30"), (0.2099, 0.21, "0.2099"),
                                          (0.2101, 0.21, "0.2101"), (0.999996, 1.0, "0.999996"), (0.5, 0.5, "0.50")])
def test_a_printed_number_stays_on_its_side_of_the_limit(x, ref, text):
    assert on_side(x, ref) == text


def test_the_issue_case_prints_the_digits_that_keep_ft_below_its_limit():
    ft, w = 0.206, 0.678
    lim = float(core.ft_limit(w))
    assert ft < lim < 0.21  # 0.21 would read as ratcheting
    text = inputs_text(ft, w)
    printed = float(re.search(r"ft = ([\d.]+)", text).group(1))
    assert printed < lim, text
    ex = Explorer(query=f"?ft={ft}&w={w}")
    badge = ex._badge(ft, w, ex.result, ex.error)
    assert "ft = 0.206" in badge and "ft = 0.21," not in badge, badge
    cards = ex._cards(ft, w, ex.state.mu, ex.contact, ex.result)
    assert "0.2084" in cards and ">0.988<" in cards, cards  # ft_lim and the margin, on their sides
    assert ex.ft_slider.format == ex.w_slider.format == SLIDER_FORMAT == "0.00[0000]"


# ---------------------------------------------------------------- item 6: clean values
@pytest.mark.parametrize("noisy, clean", [(0.45000000000000007, 0.45), (0.23000000000000004, 0.23),
                                          (0.4200000000000001, 0.42)])
def test_inputs_never_hold_float_noise(noisy, clean):
    s = ExplorerState(w=noisy)
    assert s.w == clean
    seen = []
    s.param.watch(lambda e: seen.append(e.new), ["ft", "w"])
    s.param.update(ft=noisy)
    s.w = noisy + 0.1
    assert s.ft == clean and seen[0] == clean  # every watcher sees the clean value (the URL's too)
    assert s.w == round(noisy + 0.1, 6)


# ---------------------------------------------------------------- item 9: user words
def test_inputs_speak_a_users_words():
    developer = re.compile(r"core[./]|app\.|registry|SHAKEDOWN_|\.py\b|\b[a-z]+_[a-z]+\b")
    for name in URL_PARAMETERS:
        p = ExplorerState.param[name]
        if name in ("name",):
            continue
        assert not developer.search(str(p.label)), (name, p.label)
        assert not re.search(r"core[./]|app\.|registry|SHAKEDOWN_|\.py\b", p.doc or ""), (name, p.doc)
    assert len(ExplorerState.param.body.doc) < 80  # a tooltip that fits beside the body buttons
    assert ExplorerState.param["load_at"].label == "Where Ft acts (0 inner end, 1 outer end)"


# ---------------------------------------------------------------- item 10: typed geometry
def _boxes(ex):
    return {b.label: b for b in [*ex.geometry_inputs, *ex.cylinder_inputs]}


def test_typed_geometry_is_checked_in_the_inputs_units():
    ex = Explorer()
    box = _boxes(ex)
    assert ex.result is not None
    # valid values beyond the slider ranges are taken (they snapped back before)
    box["R [mm]"].value = 0.5
    box["E substrate [MPa]"].value = 0.01
    assert (ex.state.R, ex.state.E2, ex.error) == (0.5, 0.01, "") and ex.result is not None
    # a contact wider than L: said in mm, and no run on show under INVALID INPUT
    box["L [mm]"].value = 3.0
    assert ex.result is None and ex.contact is None
    assert re.fullmatch(r"L must exceed the contact width 2a = [\d.]+ mm, got 3 mm", ex.error), ex.error
    assert "INVALID INPUT" in ex._badge(ex.state.ft, ex.state.w, ex.result, ex.error)
    box["L [mm]"].value = 500.0
    assert ex.error == "" and ex.result is not None
    # out of its range: named with its range and units; the state keeps its last valid value
    box["R [mm]"].value = -1.0
    assert ex.error == "R must be in (0, 100000] mm, got -1 mm" and ex.state.R == 0.5 and ex.result is None
    box["ν substrate"].value = 0.7
    assert "ν substrate must be in [0, 0.5], got 0.7" in ex.error
    box["R [mm]"].value = 40.0
    box["ν substrate"].value = 0.5
    assert ex.error == "" and ex.result is not None


# ---------------------------------------------------------------- item 15: μ does not re-solve
@pytest.mark.parametrize("body", RUNNABLE)
def test_a_normalised_run_does_not_depend_on_mu(body):
    # what lets the app keep the run when μ moves (app.runs.run_key leaves μ out of an uncoupled run's key)
    a, b = _run(body=body, mu=0.58, periods=2), _run(body=body, mu=0.2, periods=2)
    for name in ("traction", "state", "displacement", "xc", "increment_per_period"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=f"{body}: {name}")
    s1, s2 = ExplorerState(body=body, mu=0.58), ExplorerState(body=body, mu=0.2)
    assert runs.run_key(s1.contact(), s1.solver_options()) == runs.run_key(s2.contact(), s2.solver_options())


def test_moving_mu_keeps_the_run_and_rescales_the_physical_figures():
    ex = Explorer(query="?units=physical")
    before, units = ex.result, ex.plot_units
    solved = []
    original = runs._BACKEND.run
    runs._BACKEND.run = lambda *a, **k: solved.append(a) or original(*a, **k)
    try:
        ex.mu_slider.value = ex.state.mu = 0.8
    finally:
        runs._BACKEND.run = original
    assert solved == [] and ex.result is before
    assert ex.plot_units != units and ex.contact.mu == 0.8  # the physical scales follow μ
    # a coupled contact (β != 0) keeps μ in its key
    coupled = ExplorerState(rigid=False, E1=5.1, nu1=0.2)
    assert coupled.contact().beta != 0
    assert (runs.run_key(coupled.contact(), {}) != runs.run_key(ExplorerState(rigid=False, E1=5.1, nu1=0.2, mu=0.3)
                                                                .contact(), {}))


# ---------------------------------------------------------------- item 5: 'Refine grid' ends in a result
def test_refine_is_offered_only_when_it_fits_the_budget(monkeypatch):
    from app import layout

    ex = Explorer(query="?body=sphere&periods=2")
    button = ex._grid_action()
    assert ex.result.is_patch and ex.result.runtime < layout.SOLVE_BUDGET_S / layout.REFINE_COST
    assert button.label == "Refine grid: a/10 → a/20" and not button.disabled
    monkeypatch.setattr(layout, "SOLVE_BUDGET_S", layout.REFINE_COST * ex.result.runtime / 2)
    ex.param.trigger("result")
    assert button.label == "Finest grid in time (a/10)" and button.disabled
    assert "a/20 would take about" in button.description


def test_a_refined_run_that_runs_out_of_time_goes_back_with_a_notice(monkeypatch):
    ex = Explorer(query="?body=sphere&periods=2")
    coarse = ex.result
    original = runs._BACKEND.run

    def budget_runs_out(contact, options, *args, **kwargs):
        if options["dx"] < coarse.dx:
            raise core.SolveCancelled("solve stopped after 20 s (its time budget) at step 40 of 81")
        return original(contact, options, *args, **kwargs)

    monkeypatch.setattr(runs._BACKEND, "run", budget_runs_out)
    ex.refine_grid()
    assert ex.state.point_resolution == 10 and ex.error == "" and ex.result is coarse
    assert any("a/20 did not finish in time" in n and "back to a/10" in n for n in ex.notices), ex.notices


def test_rounding_to_1e6_never_carries_a_value_across_a_bound():
    """A link's -1.7e-17 is below ft's range and stays refused (rounded, it would read 0); 0.9999997 is in it and stays
    accepted (rounded, it would read 1, outside)."""
    from app.state import parse_query

    updates, errors, _ = parse_query({"ft": "-1.7e-17", "w": "0.9999997"})
    assert "ft" not in updates and len(errors) == 1 and errors[0].startswith("ft must be in")
    assert updates["w"] == 0.9999997
    s = ExplorerState()
    s.w = 0.45000000000000007
    assert s.w == 0.45
