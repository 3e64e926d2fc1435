"""Real-browser tests of what a review at the projector found (1280x720 and 1024x768, every body and loading):
each test keeps one finding fixed.

Served ``app/main.py`` and Debian Chromium (fixtures ``app_url`` and ``browser`` of ``tests/conftest.py``).
"""

from __future__ import annotations

import pytest

from app.scheduling import SPINNER_DELAY_MS
from app.serving import open_page, wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

#: Any verdict, the refusal included: the page has answered.
ANSWERED = "[data-regime]:not([data-regime='pending'])"


def _open(browser, url, size, query):
    return open_page(browser, url + query, size, ready=ANSWERED, timeout_ms=300_000)


def test_a_refused_input_stops_the_spinner_and_the_solving_numbers(browser, app_url):
    """A run the solver refuses at once (the height map's contact reaching the map's edge under three times its
    heights) shows INVALID INPUT; the spinner's delayed start used to switch it on after the refusal had come, so
    "solving…" turned beside INVALID INPUT for good, and the key numbers said "solving…" too."""
    page = _open(browser, app_url, (1280, 720), "?body=heightmap&height_unit=3")
    try:
        page.locator("[data-regime='invalid']").first.wait_for(timeout=60_000)
        strip = page.locator(".strip").first
        wait_until(lambda: "no run" in strip.inner_text(), 30, message="the key numbers say 'no run'")
        page.wait_for_timeout(4 * SPINNER_DELAY_MS)  # past the spinner's delayed start
        assert "solving" not in strip.inner_text(), strip.inner_text()
        status = page.locator(".solve-status")
        assert status.count() == 0 or not status.first.is_visible() or "solving" not in status.first.inner_text(), \
            status.first.inner_text()
        assert page.problems == [], page.problems
    finally:
        page.close()


#: The key figures of the first screen (figures of app.figures.KEY_FIGURES), by their titles.
def _key_titles(body, loading="rocking"):
    from app.figures import key_figures
    from app.plots import FIGURES

    return [FIGURES[name]["opts"]["title"] for name in key_figures(body, loading)]


@pytest.mark.parametrize("body", ["cylinder", "sphere", "cone"])
def test_the_tangential_loading_keeps_the_first_screen(browser, app_url, body):
    """Under the tangential loading the badge's note (what applies instead of the rocking limit, and the closed-form
    energy per cycle) sat in five lines under the CYCLIC SLIP badge and pushed the sphere's key figures 17 px past
    the bottom of a 1280x720 screen: the badge, the three key figures and their legends are on the first screen
    at 1280x720 and 1024x768. (At the explorer's default periods: with 3, a point contact's energy trend cannot
    tell yet, and the badge says UNDETERMINED, not what the review saw.)"""
    from app.slides import FIGURE_VIEWS_JS

    titles = _key_titles(body, "tangential")  # the first screen follows the loading: the loop beside the displacement
    page = _open(browser, app_url, (1280, 720), f"?body={body}&loading=tangential")
    try:
        page.locator("[data-regime='cyclic slip']").first.wait_for(timeout=120_000)
        for width, height in ((1280, 720), (1024, 768)):
            page.set_viewport_size({"width": width, "height": height})

            def boxes():
                found = page.evaluate("(titles) => {" + FIGURE_VIEWS_JS + """
                  const out = {};
                  for (const v of figure_views()) { const t = v.model.title ? v.model.title.text : '';
                    if (titles.includes(t) && v.el.isConnected) { const r = v.el.getBoundingClientRect();
                      out[t] = [r.left, r.top, r.right, r.bottom]; } }
                  return out; }""", titles)
                return found if len(found) == len(titles) else None

            wait_until(boxes, 60, interval=0.2, message=f"the key figures {titles} drawn")
            page.wait_for_timeout(800)  # the layout settles after the resize
            badge = page.locator("[data-regime='cyclic slip']").first.bounding_box()
            assert badge["y"] >= 0 and badge["y"] + badge["height"] <= height, badge
            for title, (left, top, right, bottom) in boxes().items():
                assert left >= 0 and right <= width + 0.5 and top >= 0 and bottom <= height + 0.5, \
                    f"{body} at {width}x{height}: {title!r} spans x {left:.0f}..{right:.0f}, y {top:.0f}..{bottom:.0f}"
        assert page.problems == [], page.problems
    finally:
        page.close()
