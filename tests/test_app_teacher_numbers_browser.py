"""Real-browser tests of issue 31's numbers, state and behaviour (items 3, 4, 6, 9, 10, 17): what a teacher sees
in the served explorer at a projector's 1280x720 and 1024x768 (headless Chromium, fixtures of tests/conftest.py).

- item 3: the traction figure's shading agrees with its curve and with the strip's c_sd, read from the page's
  Bokeh models (the zone rectangles by their legend label, the numerical curve);
- item 4: ``?ft=0.206&w=0.678`` reads ft = 0.206 on the slider and in the verdict's note (ft_lim = 0.2084);
- item 6: a noisy link opens rounded, and a slider moved to a noisy value leaves a clean address;
- item 9: the cone's inputs and the body selector's tooltip speak a user's words, inside the window;
- item 10: a typed L below the contact width is named in mm under INVALID INPUT, and no run stays on show;
- item 17: closing a tab while the player plays or a solve runs leaves no traceback in the server's log.
"""

from __future__ import annotations

import json
import re
import urllib.request

import pytest

import core
from app.plots import FIGURES
from app.serving import FIND_MODEL_JS, open_page, wait_until

TRACTION = FIGURES["traction"]["opts"]["title"]

pytestmark = [pytest.mark.browser, pytest.mark.timeout(900)]

VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting'], [data-regime='undetermined']"
SIZES = [(1280, 720), (1024, 768)]

#: The zone rectangles (by legend label) and the numerical traction of the figure titled ``title``.
_SHADING = "(title) => {" + FIND_MODEL_JS + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  const out = {zones: {}, curve: null};
  // the legend sits in or beside the plot (under it since the layout work of issue 31)
  const panels = [...fig.center, ...(fig.below ?? []), ...(fig.right ?? []), ...(fig.above ?? [])];
  const legend = panels.find((c) => c.items !== undefined);
  const ZONES = ['stick', 'slip', 'zero traction'];
  for (const item of legend ? legend.items : []) {
    let label = item.label && (item.label.value ?? item.label);
    if (typeof label === 'string' && label.startsWith('zone: ')) label = label.slice(6);
    for (const r of item.renderers) {
      const d = r.data_source.data;
      if (ZONES.includes(label)) {
        const left = d.left ?? d.x0, right = d.right ?? d.x1;
        out.zones[label] = Array.from(left ?? []).map((l, i) => [l, right[i]]);
      } else if (label === 'numerical' || label === 'q_x numerical' || label === 'q_x') {
        out.curve = [Array.from(d.x ?? []), Array.from(d.y ?? [])];
      }
    }
  }
  return out;
}"""
#: The value of the widget titled ``title`` (null if it is not in the page).
_VALUE = "(title) => {" + FIND_MODEL_JS + """
  const m = find((m) => m.title === title && 'value' in m);
  return m === null ? null : m.value;
}"""
#: Set the widget titled ``title`` (a slider: also its release; a number box: its value).
_SET = """([title, v]) => {""" + FIND_MODEL_JS + """
  const m = find((m) => m.title === title && 'value' in m);
  if (m === null) return false;
  m.value = v;
  if ('value_throttled' in m) m.value_throttled = v;
  return true;
}"""


def _open(browser, url, size=(1280, 720)):
    return open_page(browser, url, size, ready=VERDICT)


# ---------------------------------------------------------------- item 17: no traceback when a tab closes
def _liveness(app_url: str) -> dict:
    """The served app's ``/liveness`` body (its solves in flight and ended among it)."""
    with urllib.request.urlopen(app_url.rsplit("/", 1)[0] + "/liveness", timeout=10) as r:  # noqa: S310 - loopback
        return json.loads(r.read())


def test_closing_a_tab_mid_update_leaves_no_traceback_in_the_server_log(browser, app_url, app_log):
    """What the shared server logs while this test's tabs close (its log from the test's start; the other tests
    of this worker run before or after, never meanwhile). The solves that run when the tabs close are waited for
    on ``/liveness`` (none in flight, and at least the two asked for ended), not for a fixed time."""
    start = app_log.stat().st_size
    url = app_url
    for _ in range(2):  # the player playing at its fastest when the tab closes
        page = _open(browser, url + "?periods=4")
        page.locator(".player-speed select").first.select_option(index=2)
        page.locator(".play-period button").first.click()
        page.wait_for_timeout(700)
        page.close()
    ended = _liveness(app_url)["solves_ended"]
    for ft in (0.41, 0.43):  # a solve running (a point contact's: seconds) when the tab closes
        page = _open(browser, url + "?body=sphere&periods=6")
        assert page.evaluate(_SET, ["ft = Ft/(μ Fn)", ft])
        page.wait_for_timeout(400)
        page.close()
    # the solves end and their updates find the sessions gone
    wait_until(lambda: (body := _liveness(app_url))["solves"] == 0 and body["solves_ended"] >= ended + 2, 120,
               interval=0.2, message="the closed tabs' solves to end (/liveness)")
    page = _open(browser, url)  # the server still serves
    page.close()
    # the server's last lines reach the file: the five tabs' closings logged
    opened, closed = "WebSocket connection opened", "WebSocket connection closed"
    wait_until(lambda: app_log.read_bytes()[start:].decode(errors="replace").count(closed) >= 5, 30,
               interval=0.2, message="the five tabs' closings in the server's log")
    text = app_log.read_bytes()[start:].decode(errors="replace")
    assert text.count(opened) == 5, text[-3000:]  # this test's five tabs, read from the log
    assert "Task exception was never retrieved" not in text, text[-3000:]
    assert "WebSocketClosedError" not in text and "Traceback" not in text, text[-3000:]


def _strip_csd(page) -> float:
    """The strip's c_sd [a] (the cylinder's 'c_sd', a point contact's 'c_sd (y = 0)')."""
    text = page.locator(".strip").first.inner_text()
    return float(re.search(r"c_sd(?: \(y = 0\))?\s+([-\d.e]+) a", text).group(1))


# ---------------------------------------------------------------- item 3: shading agrees with curve and numbers
@pytest.mark.parametrize("query, title", [("?ft=0.74&w=0.8", TRACTION),
                                          ("?body=sphere&ft=0.35", "Traction on y = 0"),
                                          ("?body=sphere", "Traction on y = 0")],
                         ids=["cylinder-ratcheting", "sphere-ratcheting", "sphere-default"])
def test_the_shading_at_the_last_step_agrees_with_the_curve_and_the_strip(browser, app_url, query, title):
    """At 1280x720 and 1024x768 (one page, resized)."""
    page = _open(browser, app_url + query, SIZES[0])
    try:
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            shading = wait_until(lambda: (d := page.evaluate(_SHADING, title)) and d["curve"]
                                 and len(d["curve"][0]) > 10 and d, 120, message=f"the figure {title!r} drawn")
            x, q = shading["curve"]
            zero = shading["zones"].get("zero traction", [])
            loaded = [(xi, qi) for xi, qi in zip(x, q) if abs(qi) > core.records.result.ZERO_TRACTION]
            crossing = [(xi, qi) for xi, qi in loaded for lo, hi in zero if lo < xi < hi]
            assert not crossing, f"{width}x{height}: 'zero traction' shaded under traction: {crossing[:5]}"
            stick = shading["zones"].get("stick", [])
            csd = _strip_csd(page)
            central = [(lo, hi) for lo, hi in stick if lo <= 0.0 <= hi]
            half = 0.5 * (central[0][1] - central[0][0]) if central else 0.0
            assert abs(half - csd) <= 0.01, \
                f"{width}x{height}: stick shaded over ±{half:.3f} a, the strip says c_sd = {csd} a"
        assert page.problems == [], page.problems
    finally:
        page.close()


# ---------------------------------------------------------------- item 4: digits that keep their side
def test_ft_near_the_limit_reads_on_its_side_of_it(browser, app_url):
    """At 1280x720 and 1024x768 (one page, resized)."""
    assert float(core.ft_limit(0.678)) == pytest.approx(0.2084, abs=5e-5)
    page = _open(browser, app_url + "?ft=0.206&w=0.678", SIZES[0])
    try:
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            note = page.locator(".regime-note").first.inner_text()
            assert "ft = 0.206" in note and "ft = 0.21," not in note, (width, note)
            slider = page.locator(".bk-slider-title", has_text="ft = Ft/(μ Fn)").first.inner_text()
            assert "0.206" in slider, (width, slider)
            assert page.evaluate(_VALUE, "ft = Ft/(μ Fn)") == 0.206
    finally:
        page.close()


# ---------------------------------------------------------------- item 6: clean URLs
def test_noisy_links_open_rounded_and_sliders_leave_clean_urls(browser, app_url):
    page = _open(browser, app_url + "?w=0.45000000000000007&ft=0.3")
    try:
        assert page.evaluate(_VALUE, "w = W/a") == 0.45
        wait_until(lambda: "w=0.45&" in page.evaluate("() => window.location.search") + "&", 30,
                   message="the address bar rounded")
        assert "0.4500000" not in page.evaluate("() => window.location.search")
        assert page.evaluate(_SET, ["ft = Ft/(μ Fn)", 0.23000000000000004])  # what a slider's steps give
        wait_until(lambda: "ft=0.23&" in page.evaluate("() => window.location.search") + "&", 30,
                   message="ft in the URL")
        search = page.evaluate("() => window.location.search")
        assert not re.search(r"=\d+\.\d{7,}", search), search
        assert page.evaluate(_VALUE, "ft = Ft/(μ Fn)") == 0.23
    finally:
        page.close()


# ---------------------------------------------------------------- item 9: user words
_TEXTS = "() => {" + FIND_MODEL_JS + """
  const out = [];
  for (const doc of Bokeh.documents) for (const m of doc.all_models) {
    for (const k of ['title', 'label', 'description', 'text']) {
      const v = m[k];
      if (typeof v === 'string') out.push(v);
      else if (v != null && typeof v.text === 'string') out.push(v.text);  // a Tooltip's content
    }
    if (m.type === 'TooltipIcon' || (m.description == null && typeof m.value === 'string' && m.value.length < 400
                                       && m.constructor.name === 'TooltipIcon')) out.push(m.value);
  }
  return out;
}"""


def test_the_cone_s_inputs_and_the_body_tooltip_speak_a_users_words(browser, app_url):
    """At 1280x720 and 1024x768 (one page, resized)."""
    page = _open(browser, app_url + "?body=cone&periods=2", SIZES[0])
    try:
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            page.locator(".body-inputs").first.wait_for(timeout=60_000)
            texts = " | ".join(page.evaluate(_TEXTS)) + page.locator("body").inner_text()
            for word in ("load_at (cone)", "core/geometry/cone.py", "core.geometry.registry", "(core/", "SHAKEDOWN_MAX"):
                assert word not in texts, (width, word)
            assert "Where Ft acts (0 inner end, 1 outer end)" in texts, width
            # the body selector's tooltip: one short sentence (it listed the registry's bodies with their docs, ran
            # off the screen over the player and the tabs)
            tip = page.evaluate("() => {" + FIND_MODEL_JS + """
              const m = find((m) => (m.css_classes ?? []).includes('body-select'));
              const t = m && m.tooltip;  // Panel's description becomes a Bokeh Tooltip on the button group
              const c = t && t.content;
              return c == null ? null : (typeof c === 'string' ? c : (c.text ?? JSON.stringify(c)));
            }""")
            assert tip is not None and len(tip) < 80 and "core" not in tip, (width, tip)
    finally:
        page.close()


# ---------------------------------------------------------------- item 10: typed geometry
def test_a_typed_length_below_the_contact_is_named_in_mm_and_no_run_stays(browser, app_url):
    """At 1280x720, then at 1024x768 (one page, resized: the whole sequence again)."""
    page = _open(browser, app_url + "?ft=0.25&w=0.37", SIZES[0])
    try:
        page.get_by_text("Geometry and materials").first.click()
        wait_until(lambda: page.evaluate(_VALUE, "L [mm]") is not None, 30, message="the geometry's boxes")
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            assert page.evaluate(_SET, ["R [mm]", 0.5])  # beyond the old slider range: taken, solved
            wait_until(lambda: "R=0.5" in page.evaluate("() => window.location.search"), 60, message="R taken")
            page.locator(VERDICT).first.wait_for(timeout=120_000)
            assert page.evaluate(_SET, ["R [mm]", 40.0])
            assert page.evaluate(_SET, ["L [mm]", 3.0])
            page.locator("[data-regime='invalid']").first.wait_for(timeout=60_000)
            note = page.locator(".regime-note").first.inner_text()
            assert re.search(r"L must exceed the contact width 2a = [\d.]+ mm, got 3 mm", note), (width, note)
            wait_until(lambda: not any(len(c[1] or []) > 0 for c in [page.evaluate(_SHADING, TRACTION)
                                                                      ["curve"] or [[], []]]), 30,
                       message="the old run's traction gone")
            assert page.evaluate(_SET, ["L [mm]", 500.0])
            page.locator(VERDICT).first.wait_for(timeout=120_000)
        assert page.problems == [], page.problems
    finally:
        page.close()
