"""The explorer with dissimilar materials (issue 32): a materials picker, a coupled run, its limits labelled as the
uncoupled reference. Headless checks of the state and the cards, and one real-browser run at 1280x720."""

from __future__ import annotations

import math

import holoviews as hv
import numpy as np
import pytest

import core
from app import plots, regime_map
from app.cards import coupled_beta, coupled_prediction, cylinder_rows, strip_html
from app.runs import LimitCurves
from app.state import ExplorerState
from core.maps.coupled_limits import CoupledLimit, CoupledLimitCurve


def _curve(beta=0.25, mu=0.3, amplitudes=(0.3, 0.5)):
    """A coupled limit curve made by hand (no solver): brackets at [0.90, 0.92] x eq 35."""
    pts = tuple(CoupledLimit(w, 0.90 * float(core.ft_limit(w)), 0.92 * float(core.ft_limit(w)),
                             float(core.ft_limit(w)), True, ()) for w in amplitudes)
    return CoupledLimitCurve(beta, mu, 0.05, 0.02, 20, pts)


def _map(curve, ft=0.3, w=0.4) -> dict:
    """The map's layers by legend label (the unlabelled ones as '' + their index)."""
    inputs = plots.Inputs(ft=ft, w=w, units=plots.Units("normalised"), coupled=curve)
    specs, data = plots.specs("map", inputs.units), plots.layers("map", inputs)
    assert len(specs) == len(data)
    return {(s.label or f"#{i}"): d for i, (s, d) in enumerate(zip(specs, data))}


def test_a_materials_pair_sets_both_bodies_and_a_typed_value_makes_it_custom():
    s = ExplorerState()
    assert s.materials == "custom" and s.contact().beta == 0.0 and not s.contact().coupled  # the paper's
    s.materials = "steel/aluminium"
    pair = core.theory.materials.material_pair("steel/aluminium")
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
    # the margins too, and the first screen's strip says which limit its margins are to
    assert rows["margin ft / ft_lim (eq 35, uncoupled)"] == plain["margin ft / ft_lim"]
    assert "margin ft / ft_lim" not in rows and "margin w / w_lim" not in rows
    strip = strip_html(list(rows.items()), "solving…")
    assert "ft/ft_lim (eq 35)" in strip and "w/w_lim (eq 35)" in strip
    assert "ft/ft_lim (eq 35)" not in strip_html(list(plain.items()), "solving…")


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
        assert badge.get_attribute("data-regime") in core.records.verdict.REGIMES, badge.get_attribute("data-regime")
        note = page.locator(".regime-note").first.inner_text()
        beta = core.theory.materials.material_pair("steel/aluminium").beta
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


#: JavaScript for ``page.evaluate``: the legend of the figure titled ``title`` (its items' labels: visible) and how
#: many points each labelled renderer holds.
_LEGEND_JS = """(title) => {
  const find = (pred) => {
    for (const doc of Bokeh.documents) for (const m of doc.all_models) { if (pred(m)) return m; }
    return null;
  };
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  const items = {};
  for (const c of [...fig.center, ...fig.below, ...fig.above, ...fig.left, ...fig.right]) if (c.items) {
    for (const it of c.items) {
      const label = it.label == null ? null : (it.label.value ?? it.label);
      if (label != null) items[label] = it.visible;
    }
  }
  return items;
}"""


@pytest.mark.browser
@pytest.mark.timeout(900)
def test_a_coupled_contact_shows_its_coupled_limit_beside_eq_35_on_the_map(browser, app_url):
    """Steel on aluminium at 1280x720: the map draws the coupled limit (computed off the event loop) beside eq 35,
    labelled the uncoupled reference, with the run's marker; the badge names the coupled limit it compared with."""
    from app.serving import open_page, wait_until

    query = "?materials=steel/aluminium&ft=0.5&w=0.3&mu=0.3&periods=6"
    page = open_page(browser, app_url + query, (1280, 720),
                     ready="[data-regime]:not([data-regime='pending'])", timeout_ms=300_000)
    try:
        note = wait_until(lambda: (lambda t: t if "the coupled limit ft_lim" in t else None)(
            page.locator(".regime-note").first.inner_text()), 600, interval=1.0, message="the badge's coupled limit")
        assert "uncoupled reference" in note and "numerical" in note, note
        badge = page.locator("[data-regime]").first.bounding_box()
        assert badge is not None and badge["y"] + badge["height"] <= 720
        page.locator(".place-map").first.scroll_into_view_if_needed(timeout=60_000)
        title = plots.FIGURES["map"]["opts"]["title"]
        legend = wait_until(lambda: (lambda items: items if items and items.get(regime_map.COUPLED_LIMIT) else None)(
            page.evaluate(_LEGEND_JS, title)), 300, interval=0.5, message="the coupled limit on the map")
        assert legend[regime_map.EQ35_REFERENCE] and legend["current point"], legend
        assert not legend.get("eq 35 (exact)", False), legend  # eq 35 is there, as the reference
        status = page.locator(".coupled-status-text").first
        try:
            wait_until(lambda: "coupled limit: 5 amplitudes" in status.inner_text() or None, 300, interval=0.5,
                       message="the whole coupled limit curve")
        except TimeoutError as e:  # say what the status said (computing, stopped, not computed: why)
            raise AssertionError(f"{e}; the status says {status.inner_text()!r}") from e
        map_box = page.locator(".place-map").first.bounding_box()
        assert map_box is not None and map_box["width"] >= 250
        assert page.problems == [], page.problems
    finally:
        page.close()


def test_the_map_draws_the_coupled_limit_beside_eq_35_as_the_uncoupled_reference():
    plain = _map(None)
    assert plain["eq 35 (exact)"][0].size > 100  # uncoupled: eq 35 is the limit, no coupled layer
    assert all(len(plain[k][0]) == 0 for k in (regime_map.EQ35_REFERENCE, regime_map.COUPLED_LIMIT))
    curve = _curve()
    layers = _map(curve)
    assert len(layers["eq 35 (exact)"][0]) == 0  # the same line, now labelled the uncoupled reference
    np.testing.assert_array_equal(layers[regime_map.EQ35_REFERENCE][0], plain["eq 35 (exact)"][0])
    np.testing.assert_array_equal(layers[regime_map.EQ35_REFERENCE][1], plain["eq 35 (exact)"][1])
    ft, w = layers[regime_map.COUPLED_LIMIT]
    np.testing.assert_allclose(ft, curve.ft_limit, rtol=1e-12)
    np.testing.assert_allclose(w, [0.3, 0.5])
    brackets = next(d for k, d in layers.items() if k.startswith("#") and len(d) == 2 and len(d[0]) == 6)  # NaN apart
    np.testing.assert_allclose(brackets[0][[0, 1, 3, 4]], [p for q in curve.points
                                                           for p in (q.ft_shakedown, q.ft_ratcheting)])
    assert np.isnan(brackets[0][2]) and np.isnan(brackets[1][5])
    partial = _map(CoupledLimitCurve(0.25, 0.3, 0.05, 0.02, 20, ()))  # computing: eq 35 already the reference
    assert len(partial["eq 35 (exact)"][0]) == 0 and len(partial[regime_map.EQ35_REFERENCE][0]) > 100
    assert len(partial[regime_map.COUPLED_LIMIT][0]) == 0


def _closed_form_layers(curve) -> dict:
    """The map's layers of the uncoupled closed forms besides eq 35: the closure's c_sd contours and their labels
    (the unlabelled Contours and the small Labels), the sphere's exact limit and the eq 36 regression."""
    inputs = plots.Inputs(ft=0.3, w=0.4, units=plots.Units("normalised"), coupled=curve)
    specs, data = plots.specs("map", inputs.units), plots.layers("map", inputs)
    by_kind = {}
    for s, d in zip(specs, data):
        if s.kind is hv.Contours:
            by_kind["c_sd contours"] = d
        elif s.kind is hv.Labels and s.opts.get("text_font_size") == "11px":
            by_kind["c_sd labels"] = d
        elif s.label in ("sphere, ellipsoid (exact)", "eq 36 regression"):
            by_kind[s.label] = d
    assert len(by_kind) == 4, sorted(by_kind)
    return by_kind


def _drawn(data) -> bool:
    return len(data) > 0 and len(data[0]) > 0


def test_a_coupled_contacts_map_draws_no_uncoupled_closed_form_but_eq_35_as_its_reference():
    """The closure's stick zone (eq 30), the sphere's limit and the eq 36 regression are closed forms of an
    uncoupled contact: the map of a coupled one (its curve computing or computed) keeps eq 35 as the one uncoupled
    reference, and draws none of them."""
    plain = _closed_form_layers(None)
    assert all(_drawn(d) for d in plain.values()), {k: _drawn(d) for k, d in plain.items()}
    for curve in (_curve(), CoupledLimitCurve(0.25, 0.3, 0.05, 0.02, 20, ())):
        coupled = _closed_form_layers(curve)
        assert not any(_drawn(d) for d in coupled.values()), {k: _drawn(d) for k, d in coupled.items()}
        assert len(_map(curve)[regime_map.EQ35_REFERENCE][0]) > 100
    caption = plots.FIGURES["map"]["caption"]
    assert "c_sd" in caption.split("Dissimilar materials")[1], caption


def test_the_badge_compares_a_coupled_run_with_the_coupled_limit_once_the_curve_reaches_its_w():
    curve = _curve()
    lim = curve.ft_limit_at(0.4)
    eq35 = float(core.ft_limit(0.4))
    ft = 0.5 * (lim + eq35)  # between the coupled limit and eq 35: the two limits disagree
    predicted, rule = coupled_prediction(ft, 0.4, 0.25, "shakedown", "ft_lim(w) (eq 35)", curve)
    assert predicted == "ratcheting" and f"the coupled limit ft_lim = {lim:.3f}" in rule, rule
    assert f"eq 35, the uncoupled reference: {eq35:.3f}, shakedown" in rule, rule
    # below the coupled limit: no ratcheting (a coupled contact may shake down or slip a little every period)
    assert coupled_prediction(0.9 * lim, 0.4, 0.25, "shakedown", "eq 35", curve)[0] == "no ratcheting"
    outside = coupled_prediction(ft, 0.8, 0.25, "shakedown", "ft_lim(w) (eq 35)", curve)
    assert outside[0] == "shakedown" and "known for w in [0.3, 0.5]" in outside[1], outside
    assert "uncoupled reference" in outside[1] and "β = 0.25" in outside[1]
    computing = coupled_prediction(ft, 0.4, 0.25, "shakedown", "eq 35", CoupledLimitCurve(0.25, 0.3, 0.05, 0.02, 20, ()))
    assert "computing the coupled limit" in computing[1]
    assert coupled_prediction(ft, 0.4, 0.25, "shakedown", "eq 35", None) == (
        "shakedown", "eq 35 (the uncoupled reference; this contact is coupled, β = 0.25)")


def test_limit_curves_are_sent_as_they_come_cached_per_beta_and_mu_and_stopped_when_nobody_waits():
    import threading

    curves = LimitCurves(grid=dict(w=(0.4, 0.6), dx=1 / 10, tol=0.2, periods=10))
    got, finished = [], threading.Event()

    def listener(curve, done, error):
        got.append((len(curve.points), done, error))
        if done:
            finished.set()

    key, cached = curves.request(0.25, 0.3, listener)
    assert cached is None and finished.wait(300)
    assert got == [(1, False, ""), (2, False, ""), (2, True, "")], got
    again, cached = curves.request(0.25000001, 0.3, lambda *a: pytest.fail("a cached curve is returned, not sent"))
    assert again == key and cached is not None and cached.w.tolist() == [0.4, 0.6] and cached.beta == 0.25
    # asked for, then left at once: the curve stops at its next run and is not cached (a bigger grid, so that it is
    # still running when left)
    curves.grid = dict(w=(0.2, 0.4, 0.6, 0.8), dx=1 / 10, tol=0.02, periods=10)
    other, _ = curves.request(-0.25, 0.3, listener)
    curves.cancel(other, listener)
    from app.serving import wait_until
    wait_until(lambda: not curves.running(other) or None, 300, message="the curve nobody waits for stopped")
    assert curves.cached(other) is None and curves.cached(key) is not None


@pytest.fixture
def tiny_curves(monkeypatch):
    """The explorer's coupled limit curves on a tiny grid (one w, a/10, brackets 20 % of eq 35): a second's work."""
    from app import runs

    monkeypatch.setattr(runs, "LIMIT_CURVES", LimitCurves(grid=dict(w=(0.3,), dx=1 / 10, tol=0.2, periods=10)))
    return runs.LIMIT_CURVES


def test_the_explorer_follows_a_coupled_contact_with_its_curve_and_an_uncoupled_one_without(tiny_curves):
    from app.explorer import Explorer

    s = ExplorerState()
    e = Explorer(s)
    assert e.coupled_limit is None and e.coupled_status == ""
    s.param.update(materials="steel/aluminium", mu=0.3)
    assert e.coupled_limit is not None and e.coupled_limit.beta == pytest.approx(e.contact.beta, abs=1e-4)
    from app.serving import wait_until
    wait_until(lambda: "coupled limit:" in e.coupled_status or None, 300, message="the coupled limit curve")
    assert len(e.coupled_limit.points) == 1 and e.coupled_limit.points[0].converged, e.coupled_status
    s.loading = "normal"  # another loading: the rocking's coupled curve does not apply
    assert e.coupled_limit is None and e.coupled_status == ""
    s.loading = "rocking"  # back: the cached curve at once
    assert e.coupled_limit is not None and len(e.coupled_limit.points) == 1
    s.materials = "rigid/incompressible"
    assert e.coupled_limit is None


def test_an_uncoupled_map_is_not_drawn_beside_a_coupled_contact_and_its_own_map_is_swept_coupled(tiny_curves):
    import pandas as pd

    from app.mapview import shipped_map

    shipped = shipped_map()
    inputs = dict(ft=0.3, w=0.4, units=plots.Units("normalised"))
    runs_of = lambda inp: sum(len(d.data[0]) for d in plots.layers("map", inp)[:4])  # the four regimes' points
    assert runs_of(plots.Inputs(**inputs, table=shipped)) == len(shipped)  # uncoupled: the shipped map
    assert runs_of(plots.Inputs(**inputs, table=shipped, coupled=_curve(beta=0.117))) == 0
    coupled_table = pd.DataFrame(dict(ft=[0.2, 0.6], w=[0.3, 0.3], beta=[0.117, 0.117], regime=["shakedown", "ratcheting"]))
    assert runs_of(plots.Inputs(**inputs, table=coupled_table, coupled=_curve(beta=0.117))) == 2
    assert runs_of(plots.Inputs(**inputs, table=coupled_table, coupled=_curve(beta=-0.25))) == 0
    assert runs_of(plots.Inputs(**inputs, table=coupled_table)) == 0  # a coupled sweep beside an uncoupled contact

    from app.explorer import Explorer

    s = ExplorerState()
    e = Explorer(s)
    assert "beta" not in e._map_options()
    s.param.update(materials="steel/aluminium", mu=0.4)
    options = e._map_options()
    assert options["beta"] == pytest.approx(e.contact.beta) and options["mu"] == 0.4 and options["kernel"] == "plane"


def test_a_coupled_cyclic_slip_says_its_dissipation_falls_with_the_grid():
    """Below the coupled limit a coupled run keeps a steady micro-slip that falls like sqrt(dx) (issue 32's grid
    study): its reason and the explorer's warnings say so; an uncoupled run's cyclic slip does not get the note."""
    from app.explorer import Explorer

    coupled = core.simulate_cycles(0.168, 0.6, periods=20, dx=1 / 20, beta=0.25, mu=0.3)
    assert coupled.regime == "cyclic slip"
    assert "falls like sqrt(dx)" in coupled.regime_reason
    uncoupled = core.simulate_cycles(0.3, 0.3, periods=6, dx=1 / 20, history="tangential", amplitude=0.4)
    assert uncoupled.regime == "cyclic slip" and "sqrt(dx)" not in uncoupled.regime_reason
    ex = Explorer(ExplorerState(periods=2))
    assert any("falls like sqrt(dx)" in m for m in ex._warnings(0.168, 0.6, None, coupled))
    assert not any("sqrt(dx)" in m for m in ex._warnings(0.3, 0.3, None, uncoupled))
