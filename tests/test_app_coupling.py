"""The explorer with dissimilar materials (issue 32): a materials picker, a coupled run, its limits labelled as the
uncoupled reference. Headless checks of the state and the cards, and one real-browser run at 1280x720."""

from __future__ import annotations

import math

import pytest

import core
from app.cards import coupled_beta, cylinder_rows
from app.state import ExplorerState


def test_a_materials_pair_sets_both_bodies_and_a_typed_value_makes_it_custom():
    s = ExplorerState()
    assert s.materials == "custom" and s.contact().beta == 0.0 and not s.contact().coupled  # the paper's
    s.materials = "steel/aluminium"
    pair = core.materials.material_pair("steel/aluminium")
    assert (s.rigid, s.E1, s.nu1, s.E2, s.nu2) == (False, 210e3, 0.30, 70e3, 0.33)
    c = s.contact()
    options = s.solver_options()  # solved together, on the coupled solver's plane kernel, with the contact's beta
    assert options["kernel"] == "plane" and options["beta"] == pytest.approx(c.beta) and options["mu"] == s.mu
    assert c.coupled and c.beta == pytest.approx(pair.beta, rel=1e-12) and 0.0 < abs(c.beta) < 0.5
    assert s.materials == "steel/aluminium"  # the values it set keep it selected
    s.E2 = 71e3
    assert s.materials == "custom"
    s.materials = "rigid/incompressible"
    assert s.rigid and s.nu2 == 0.5 and s.contact().beta == 0.0 and not s.contact().coupled


def test_a_coupled_contacts_limits_are_labelled_the_uncoupled_reference():
    s = ExplorerState()
    plain = dict(cylinder_rows(0.3, 0.3, 0.58, s.contact(), None, "solving…"))
    assert "ft_lim(w) (eq 35)" in plain and coupled_beta(s.contact()) is None
    s.materials = "steel/PMMA"
    rows = dict(cylinder_rows(0.3, 0.3, 0.58, s.contact(), None, "solving…"))
    assert "ft_lim(w) (eq 35, uncoupled)" in rows and "w_lim(ft) (eq 35, uncoupled)" in rows
    assert rows["ft_lim(w) (eq 35, uncoupled)"] == plain["ft_lim(w) (eq 35)"]  # the same number, named for what it is
    assert coupled_beta(s.contact()) == pytest.approx(s.contact().beta) and math.isfinite(coupled_beta(s.contact()))


@pytest.mark.browser
@pytest.mark.timeout(900)
def test_the_explorer_runs_a_coupled_contact_and_says_its_limit_is_a_reference(browser, app_url):
    """Steel on aluminium by its link: the badge gives a verdict and says that eq 35 is the uncoupled reference, and
    the run behind it is coupled (the explorer's run of that state has the contact's beta)."""
    from app.serving import open_page

    query = "?rigid=false&E1=210000&nu1=0.3&E2=70000&nu2=0.33&ft=0.4&w=0.3"
    page = open_page(browser, app_url + query, (1280, 720),
                     ready="[data-regime]:not([data-regime='pending'])", timeout_ms=300_000)
    try:
        badge = page.locator("[data-regime]").first
        assert badge.get_attribute("data-regime") in core.verdict.REGIMES, badge.get_attribute("data-regime")
        note = page.locator(".regime-note").first.inner_text()
        beta = core.materials.material_pair("steel/aluminium").beta
        assert "uncoupled reference" in note and f"β = {beta:.3g}" in note, note
        box = badge.bounding_box()
        assert box is not None and box["y"] + box["height"] <= 720
        assert page.problems == [], page.problems
    finally:
        page.close()
    state = ExplorerState()
    state.param.update(rigid=False, E1=210e3, nu1=0.3, E2=70e3, nu2=0.33, ft=0.4, w=0.3)
    run = state.contact().simulate(**state.solver_options())  # what app.runs solves for the page
    assert run.coupled and run.beta == pytest.approx(beta) and run.solver == "coupled"
