"""Real-browser tests of the registry's bodies in the explorer: pick the punch and the height map in the selector,
change a parameter, see the verdict and the figures follow, and open the shared URL in a second session.

Served ``app/main.py`` and Debian Chromium (fixtures of ``tests/conftest.py``). At ``w = 0.5`` the punch's exact
limit (Melan) is ``ft_lim = 0.383`` with ``flat = 0.5`` and ``0.344`` with ``flat = 0.8``: at ``ft = 0.36`` the
badge's prediction flips from shakedown to ratcheting when the flat slider moves. Short runs (2 periods).
"""

from __future__ import annotations

import pytest

import core
from app.serving import FIND_MODEL_JS, open_page, wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]

VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting'], [data-regime='undetermined']"
#: Set the widget titled ``title`` (a slider: also its release; a number box: its value).
_SET = """([title, v]) => {""" + FIND_MODEL_JS + """
  const m = find((m) => m.title === title && 'value' in m);
  if (m === null) return false;
  m.value = v;
  if ('value_throttled' in m) m.value_throttled = v;
  return true;
}"""
#: The value of the widget titled ``title`` (null if it is not in the page).
_VALUE = "(title) => {" + FIND_MODEL_JS + """
  const m = find((m) => m.title === title && 'value' in m);
  return m === null ? null : m.value;
}"""
#: The active button's label of the body selector.
_ACTIVE_BODY = "() => {" + FIND_MODEL_JS + """
  const m = find((m) => (m.css_classes ?? []).includes('body-select'));
  return m === null ? null : m.labels[m.active];
}"""
#: The data arrays of the figure titled ``title``'s curves (their y columns), to see them change.
_CURVE_DATA = "(title) => {" + FIND_MODEL_JS + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  return fig.renderers.map((r) => { const d = r.data_source && r.data_source.data;
    const y = d && (d.p ?? d.y ?? d.q ?? d.w ?? d.image);
    return y == null ? [] : Array.from(y.length && y[0].length !== undefined ? y[0] : y).slice(0, 400); });
}"""


def _open(browser, url):
    return open_page(browser, url, (1400, 1000), ready=VERDICT)


def _pick(page, body):
    page.locator(".body-select").get_by_text(body, exact=True).first.click()
    page.locator(".regime-note", has_text=f"{body}'s exact limit").first.wait_for(timeout=180_000)
    page.locator(VERDICT).first.wait_for(timeout=180_000)


def _reopen(browser, url, body, label, value) -> dict:
    """Open the shared ``url`` in a second session: it shows ``body`` with the input ``label`` at ``value`` and no
    browser error; its verdict note and badge."""
    page = _open(browser, url)
    try:
        assert page.evaluate(_ACTIVE_BODY) == body
        assert page.evaluate(_VALUE, label) == value
        out = {"note": page.locator(".regime-note").first.inner_text(),
               "badge": page.locator("[data-regime]").first.get_attribute("data-regime")}
        assert page.problems == [], page.problems
        return out
    finally:
        page.close()


def test_the_punch_its_flat_and_the_shared_link(browser, app_url):
    lo, hi = (float(core.ft_limit(0.5, body=core.Punch(flat=f))) for f in (0.8, 0.5))
    assert lo < 0.36 < hi
    page = _open(browser, app_url + "?ft=0.36&w=0.5&periods=2&kernel=plane")
    try:
        _pick(page, "punch")
        note = page.locator(".regime-note").first.inner_text()
        assert "punch's exact limit predicts shakedown" in note, note
        assert "body=punch" in page.evaluate("() => window.location.search")
        title = "Pressure and μ p_min"
        page.wait_for_function(f"() => {{ const d = ({_CURVE_DATA})({title!r}); return d !== null && d[3].length > 0; }}",
                               timeout=30_000)
        before = page.evaluate(_CURVE_DATA, title)
        # the flat slider, built from the registry's parameter (its range [0, 1), its doc as the tooltip)
        assert page.evaluate(_VALUE, "Flat part b/a") == 0.5
        assert page.evaluate(_SET, ["Flat part b/a", 0.8])
        page.locator(".regime-note", has_text="punch's exact limit predicts ratcheting").first.wait_for(timeout=180_000)
        page.locator(VERDICT).first.wait_for(timeout=180_000)
        wait_until(lambda: page.evaluate(_CURVE_DATA, title) != before, 30, message="the pressure figure following the flat")
        wait_until(lambda: "flat=0.8" in page.evaluate("() => window.location.search"), 30, message="flat in the URL")
        url = page.url
        badge = page.locator("[data-regime]").first.get_attribute("data-regime")
        assert page.problems == [], page.problems
    finally:
        page.close()
    # a second session from the shared link: the same body, parameter and verdict
    second = _reopen(browser, url, "punch", "Flat part b/a", 0.8)
    assert "punch's exact limit predicts ratcheting" in second["note"]
    assert second["badge"] == badge


def test_the_height_map_its_maps_a_parameter_and_the_shared_link(browser, app_url):
    page = _open(browser, app_url + "?ft=0.3&w=0.5&periods=2")
    try:
        _pick(page, "heightmap")
        # the built-in demo map, on its own grid: the pressure map shows the contact
        assert page.evaluate(_VALUE, "Height map") == "demo"
        title = "Traction on y = 0"
        page.wait_for_function(f"() => {{ const d = ({_CURVE_DATA})({title!r}); "
                               "return d !== null && d.some((c) => c.length > 20); }", timeout=60_000)
        before = page.evaluate(_CURVE_DATA, title)
        cards_before = page.locator(".strip").first.inner_text()
        # a parameter: the map's height unit (a softer surface: a wider contact, another limit)
        assert page.evaluate(_SET, ["P/(E* a) in the file's height unit", 1.5])
        wait_until(lambda: "height_unit=1.5" in page.evaluate("() => window.location.search"), 60,
                   message="height_unit in the URL")
        page.locator(VERDICT).first.wait_for(timeout=180_000)
        wait_until(lambda: page.evaluate(_CURVE_DATA, title) != before, 120, message="the cut following the map")
        wait_until(lambda: page.locator(".strip").first.inner_text() != cards_before, 60, message="the strip")
        url = page.url
        note = page.locator(".regime-note").first.inner_text()
        assert "heightmap's exact limit" in note, note
        assert page.problems == [], page.problems
    finally:
        page.close()
    assert _reopen(browser, url, "heightmap", "P/(E* a) in the file's height unit", 1.5)["note"] == note
