"""Real-browser test of the body selector: a link to a sphere shows the sphere's verdict and its maps.

Served ``app/main.py`` and Debian Chromium (fixtures ``app_url`` and ``browser``
of ``tests/conftest.py``). At ``ft = 0.6, w = 0.3`` the two bodies disagree:
the cylinder's exact limit (eq 35) is ``ft_lim = 0.624``, the sphere's
``(1 - w)^2 (2 + w)/2 = 0.5635``, so the sphere ratchets where the cylinder
shakes down; the page must show the sphere's verdict, from its own solver run
(the app's default coarse point-contact grid, dx = a/10, 10 periods).
"""

import os

import pytest

import core
from app.serving import FIND_MODEL_JS, scroll_through

pytestmark = [pytest.mark.browser, pytest.mark.timeout(300)]


_FIND = FIND_MODEL_JS
#: Per figure title: the shapes of its images (rows x columns) and how many of their values are finite and > 0.
_IMAGES = "(title) => {" + _FIND + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  const out = [];
  for (const r of fig.renderers) {
    const d = r.data_source == null ? null : r.data_source.data;
    if (d == null || d.image == null) continue;
    const img = d.image[0];
    const values = Array.from(img);
    out.push({shape: img.shape, positive: values.filter((v) => Number.isFinite(v) && v > 0).length});
  }
  return out;
}"""
#: The lengths of the data columns of a figure's layers.
_COLUMN_SIZES = "(title) => {" + _FIND + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  const out = [];
  for (const r of fig.renderers) {
    const d = r.data_source == null ? null : r.data_source.data;
    if (d != null && d.q != null) out.push(d.q.length);
  }
  return out;
}"""
#: Whether a legend item has this label.
_LEGEND = "(text) => {" + _FIND + """
  return find((m) => m.label != null && (m.label === text || m.label.value === text)) !== null;
}"""


def test_a_link_to_a_sphere_shows_its_verdict_and_maps(browser, app_url):
    assert float(core.ft_limit(0.3, body="sphere")) < 0.6 < float(core.ft_limit(0.3))  # the bodies disagree here
    ctx = browser.new_context(viewport={"width": 1600, "height": 1300})
    try:
        page = ctx.new_page()
        errors = []
        page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(app_url + "?body=sphere&ft=0.6&w=0.3", timeout=180_000)
        # the page comes at once (the run is off the event loop), then the sphere's own verdict
        page.locator("[data-regime]").first.wait_for(timeout=60_000)
        page.locator("[data-regime='ratcheting']").first.wait_for(timeout=180_000)
        scroll_through(page)  # the figures are drawn as the page is scrolled to them
        note = page.locator(".regime-note").first.inner_text()
        assert "sphere's exact limit" in note and "predicts ratcheting" in note, note
        page.get_by_text("all numbers ▾").first.click()  # every number is one click away
        cards = page.locator(".cards").first.inner_text()
        assert "0.5635" in cards and "0.6238" in cards, cards  # the sphere's and the cylinder's limits
        # the maps: pressure and traction over the contact plane, with values inside the contact
        for title in ("Pressure at the player's step (uncoupled)",
                      "Traction |q| at the last turning point",
                      "Stick, slip, released at the last turning point"):
            page.wait_for_function(f"() => {{ const i = ({_IMAGES})({title!r}); "
                                   "return i !== null && i.length === 1 && i[0].positive > 20; }", timeout=30_000)
        # the body selector shows the sphere; the URL keeps the body
        assert "body=sphere" in page.evaluate("() => window.location.search")
        # the cut along y = 0 draws the step's traction as stairs; the map draws both bodies' exact limits
        cut = page.evaluate(_COLUMN_SIZES, "Traction on y = 0")
        assert cut is not None and max(cut) >= 2 * 20, cut
        assert page.evaluate(_LEGEND, "sphere, ellipsoid (exact)") and page.evaluate(_LEGEND, "eq 35 (exact)")
        shot = os.environ.get("SHAKEDOWN_SCREENSHOT")
        if shot:
            page.screenshot(path=shot, full_page=True)
        assert errors == [], errors
    finally:
        ctx.close()
