"""Real-browser tests of what a review at the projector found (1280x720 and 1024x768, every body and loading):
each test keeps one finding fixed.

Served ``app/main.py`` and Debian Chromium (fixtures ``app_url`` and ``browser`` of ``tests/conftest.py``).
"""

from __future__ import annotations

import pytest

from app.scheduling import SPINNER_DELAY_MS
from app.serving import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

#: Any verdict, the refusal included: the page has answered.
ANSWERED = "[data-regime]:not([data-regime='pending'])"


def _open(browser, url, size, query):
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    page.problems = []
    page.on("console", lambda m: page.problems.append(f"console: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: page.problems.append(f"page error: {e}"))
    page.goto(url + query, timeout=300_000)
    page.locator(ANSWERED).first.wait_for(timeout=300_000)
    return page


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
