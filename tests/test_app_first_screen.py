"""Real-browser tests of issue 22: the first screen shows the contact, the wheel scrolls the page over a figure,
and every feature works for every body the app offers.

Served ``app/main.py`` and Debian Chromium (fixture ``browser`` of ``tests/conftest.py``; the app is served
here with room for point-contact runs on a busy machine). The bodies come from ``app.state.BODIES``: a body
added there is tested by the same tests.
"""

from __future__ import annotations

import json

import pytest

from app.figures import key_figures
from app.plots import FIGURES
from app.serving import open_page, wait_until
from app.slides import FIGURE_BOX_JS, FIGURE_VIEWS_JS
from app import bodies
from app.state import BODIES

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

VERDICT = "[data-regime='shakedown'], [data-regime='cyclic slip'], [data-regime='ratcheting'], [data-regime='undetermined']"
SIZES = [(1280, 720), (1024, 768)]
#: How much of each key figure must be inside the first viewport [px].
VISIBLE = 150
#: The data objects of the figure titled ``title``'s sources (to see them replaced).
_DATA_IDS = "(title) => {" + FIGURE_VIEWS_JS + """
  const v = figure_views().find((v) => v.model.title && v.model.title.text === title);
  if (!v) return null;
  window._seen = window._seen || new Map();
  const out = [];
  for (const r of v.model.renderers) {
    const d = r.data_source && r.data_source.data;
    if (!d) continue;
    if (!window._seen.has(d)) window._seen.set(d, window._seen.size);
    out.push(window._seen.get(d));
  }
  return out;
}"""
#: Sets the slider titled TITLE (value and, with a release, value_throttled) on its Bokeh model.
_SET = """([title, v, release]) => { for (const d of Bokeh.documents) for (const m of d.all_models)
    if (m.title === title && 'value_throttled' in m) { m.value = v; if (release) m.value_throttled = v; return true; }
    return false; }"""
#: The sizes of the non-empty curves of the figure titled ``title`` (its own run and the pinned runs).
_CURVES = "(title) => {" + FIGURE_VIEWS_JS + """
  const v = figure_views().find((v) => v.model.title && v.model.title.text === title);
  if (!v) return null;
  const out = [];
  for (const r of v.model.renderers) {
    const d = r.data_source && r.data_source.data;
    const y = d && (d.u ?? d.du ?? d.q);
    if (y != null && y.length > 1) out.push(y.length);
  }
  return out;
}"""


def _open(browser, url, size, query):
    return open_page(browser, url + query, size, ready=VERDICT)


def _titles(body):
    return [FIGURES[name]["opts"]["title"] for name in key_figures(body)]


@pytest.mark.parametrize("body", ["cylinder", "sphere"])
def test_the_first_screen_shows_the_verdict_and_three_live_figures(browser, app_url, body):
    """At 1280x720 and 1024x768 (one page, resized): the badge and the top of each key figure (150 px of it) are
    inside the first viewport, unscrolled; the sliders and the player update them in place."""
    page = _open(browser, app_url, SIZES[0], f"?body={body}&ft=0.3&w=0.5&point_resolution=6&periods=4")
    try:
        titles = _titles(body)
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            page.evaluate("() => { for (const el of document.querySelectorAll('*')) if (el.scrollTop) el.scrollTop = 0;"
                          " window.scrollTo(0, 0); }")
            boxes = wait_until(lambda: (lambda b: b if all(b) else None)([page.evaluate(FIGURE_BOX_JS, t) for t in titles]),
                               60, message=f"the key figures of the {body} drawn")
            page.wait_for_timeout(500)  # the layout settles after the resize
            boxes = [page.evaluate(FIGURE_BOX_JS, t) for t in titles]
            badge = page.locator("[data-regime]").first.bounding_box()
            assert badge is not None and 0 <= badge["y"] and badge["y"] + badge["height"] <= height
            for title, box in zip(titles, boxes):
                shown = min(box["y"] + box["height"], height) - max(box["y"], 0)
                assert box["y"] >= 0 and shown >= VISIBLE, f"{body} at {width}x{height}: {title!r} at {box}"
                assert box["height"] >= VISIBLE and box["width"] >= 240, (title, box)  # three in a row at 1024 (issue 31)
            print(f"{body} {width}x{height}: badge y = {badge['y']:.0f}; "
                  + "; ".join(f"{t} y = {b['y']:.0f}" for t, b in zip(titles, boxes)))
        # live: a slider move replaces the first key figure's data (analytical layers), the player too
        first = titles[0]
        before = page.evaluate(_DATA_IDS, first)
        assert page.evaluate(_SET, ["w = W/a", 0.45, False])
        wait_until(lambda: page.evaluate(_DATA_IDS, first) != before, 30, message="the figure following the slider")
        assert page.evaluate(_SET, ["w = W/a", 0.45, True])  # the release: the new run
        page.locator(".regime-note", has_text="w = 0.45").first.wait_for(timeout=180_000)
        page.locator(VERDICT).first.wait_for(timeout=180_000)
        before = page.evaluate(_DATA_IDS, first)
        assert page.evaluate(_SET, ["Step in the period", 1, True])
        wait_until(lambda: page.evaluate(_DATA_IDS, first) != before, 30, message="the figure following the player")
        assert page.problems == [], page.problems
    finally:
        page.close()


def test_the_wheel_over_a_figure_scrolls_the_page(browser, app_url):
    """Over a figure's title, its middle and its lower part, a wheel turn scrolls the page (no wheel tool is active;
    zoom is one click away in the toolbar)."""
    page = _open(browser, app_url, (1280, 720), "?ft=0.3&w=0.5")
    try:
        title = _titles("cylinder")[1]
        box = wait_until(lambda: page.evaluate(FIGURE_BOX_JS, title), 60, message="the figure drawn")
        scrolled = """() => Math.max(window.scrollY, document.scrollingElement.scrollTop,
                                     ...[...document.querySelectorAll('*')].map((e) => e.scrollTop))"""
        for frac in (0.04, 0.5, 0.8):
            page.evaluate("() => { for (const el of document.querySelectorAll('*')) if (el.scrollTop) el.scrollTop = 0;"
                          " window.scrollTo(0, 0); }")
            page.wait_for_timeout(200)
            box = page.evaluate(FIGURE_BOX_JS, title)
            before = page.evaluate(scrolled)
            page.mouse.move(box["x"] + box["width"] / 2, box["y"] + frac * box["height"])
            page.mouse.wheel(0, 400)
            wait_until(lambda: page.evaluate(scrolled) > before, 10,
                       message=f"the page scrolled by a wheel turn at {frac:.0%} of the figure's height")
        # the element that scrolls is the template's main area
        assert page.evaluate("() => document.getElementById('main').scrollTop") > 0
        assert page.problems == [], page.problems
    finally:
        page.close()


@pytest.mark.parametrize("body", BODIES)
def test_pin_compare_download_and_svg_for_every_body(browser, app_url, body, tmp_path):
    page = _open(browser, app_url, (1600, 1000), f"?body={body}&ft=0.3&w=0.5&point_resolution=4&periods=3")
    try:
        page.get_by_text("Pin this run", exact=True).first.click()
        page.locator("[data-pin='1']").first.wait_for(timeout=30_000)
        assert page.evaluate(_SET, ["w = W/a", 0.4, True])
        page.locator(".regime-note", has_text="w = 0.40").first.wait_for(timeout=180_000)
        page.locator(VERDICT).first.wait_for(timeout=180_000)
        page.get_by_text("Pin this run", exact=True).first.click()
        page.locator("[data-pin='2']").first.wait_for(timeout=30_000)
        table = page.locator(".pins").first.inner_text()
        assert body in table, table
        # compare: the displacement figure draws the run and both pins
        displacement = next(FIGURES[n]["opts"]["title"] for n in key_figures(body) if "displacement" in n)
        wait_until(lambda: len(page.evaluate(_CURVES, displacement) or []) >= 3, 30,
                   message="the pinned runs on the displacement figure")
        # downloads, written by core.api.export
        for label, check in (("Download CSV", lambda text: "# regime = " in text and (
                                 f"# body = {body}" in text if bodies.kind(body) == "point"
                                 else "displacement_muP_Estar" in text)),
                             ("Download JSON", lambda text: json.loads(text)["parameters"]["regime"] in
                              ("shakedown", "ratcheting", "undetermined"))):
            with page.expect_download(timeout=60_000) as info:
                page.get_by_text(label, exact=True).first.click()
            path = tmp_path / info.value.suggested_filename
            info.value.save_as(path)
            text = path.read_text(encoding="utf-8")
            assert check(text), (label, text[:400])
            if body != "cylinder":
                assert body in info.value.suggested_filename
        # SVG: the menu offers the body's own figures; a drawn one downloads as SVG
        menu = page.locator(".svg-figure select").first
        offered = menu.locator("option").all_inner_texts()
        assert "The body at the player's step" in offered, offered  # every body has its sketch
        menu.select_option(label=displacement)
        with page.expect_download(timeout=60_000) as info:
            page.get_by_text("Save as SVG", exact=True).first.click()
        path = tmp_path / info.value.suggested_filename
        info.value.save_as(path)
        assert path.read_text(encoding="utf-8").lstrip().startswith("<svg"), path
        assert page.problems == [], page.problems
    finally:
        page.close()
