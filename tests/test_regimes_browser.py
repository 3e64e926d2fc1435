"""Real-browser test of issue 30: the tangential loading's run is CYCLIC SLIP on its own badge colour, and the
fretting loop is drawn, at 1280x720, without the two overlapping (served app/main.py, Debian Chromium; the
fixtures ``app_url`` and ``browser`` of ``tests/conftest.py``)."""

import pytest

from app.serving import CURVE_POINTS_JS, wait_until
from app.slides import FIGURE_BOX_JS, FIGURE_VIEWS_JS
from app.styles import BADGE_COLORS

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]

#: Scrolls the figure titled ``title`` to the middle of the viewport.
_SCROLL_TO = "(title) => {" + FIGURE_VIEWS_JS + """
  const v = figure_views().find((v) => v.model.title && v.model.title.text === title);
  v.el.scrollIntoView({block: 'center'});
}"""


def _box(locator):
    box = locator.bounding_box()
    assert box is not None and box["width"] > 0 and box["height"] > 0
    return box


def _overlap(a, b) -> bool:
    return not (a["x"] + a["width"] <= b["x"] or b["x"] + b["width"] <= a["x"]
                or a["y"] + a["height"] <= b["y"] or b["y"] + b["height"] <= a["y"])


def _luminance(hex_colour: str) -> float:
    c = [int(hex_colour[i:i + 2], 16) / 255 for i in (1, 3, 5)]
    c = [v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4 for v in c]
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def test_badge_colours_read_in_greyscale():
    """The three regimes (and undetermined) differ in lightness, not only in hue, and their text contrasts."""
    lum = {k: _luminance(bg) for k, (bg, _) in BADGE_COLORS.items()}
    values = sorted(lum.values())
    assert min(b - a for a, b in zip(values, values[1:])) > 0.08, lum
    for regime, (bg, text) in BADGE_COLORS.items():
        fg = 1.0 if text == "white" else 0.0
        hi, lo = max(fg, lum[regime]), min(fg, lum[regime])
        assert (hi + 0.05) / (lo + 0.05) >= 4.5, regime


def test_tangential_loading_shows_cyclic_slip_and_the_fretting_loop(browser, app_url):
    ctx = browser.new_context(viewport={"width": 1280, "height": 720})
    try:
        page = ctx.new_page()
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(app_url + "?loading=tangential&amplitude=0.5&ft=0.3&periods=4", timeout=180_000)
        badge = page.locator("[data-regime='cyclic slip']").first
        badge.wait_for(timeout=180_000)
        assert badge.inner_text().strip() == "CYCLIC SLIP"
        colour = badge.evaluate("(el) => getComputedStyle(el).backgroundColor")
        assert colour == "rgb(230, 159, 0)", colour  # BADGE_COLORS["cyclic slip"]
        # the loop: on the first screen under this loading (issue 30 item 3), in its place; apart from the badge
        page.locator(".place-loop").first.scroll_into_view_if_needed(timeout=60_000)
        points = wait_until(lambda: page.evaluate(CURVE_POINTS_JS, "Fretting loop"), 120, message="the fretting loop drawn")
        assert points >= 2 * 40  # the first and the last period, 40 steps each
        # the loop scrolled into view: all of it inside the 1280x720 viewport, not under the badge (the page
        # scrolls under the header; the badge, at the top of the main area, scrolls away or stays clear)
        page.evaluate(_SCROLL_TO, "Fretting loop")
        loop_box = wait_until(lambda: page.evaluate(FIGURE_BOX_JS, "Fretting loop"), 30, message="the loop's box")
        badge_box = _box(badge)
        assert loop_box["y"] >= 0 and loop_box["y"] + loop_box["height"] <= 720, loop_box
        assert loop_box["x"] >= 0 and loop_box["x"] + loop_box["width"] <= 1280 and loop_box["width"] > 250, loop_box
        assert not _overlap(badge_box, loop_box), (badge_box, loop_box)
        assert page.get_by_text("Traceback").count() == 0
        assert errors == [], errors
    finally:
        ctx.close()
