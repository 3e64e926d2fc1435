"""Real-browser tests of issue 31's layout and visuals (items 1, 2, 7, 8, 11, 12, 13, 14, 16): what a teacher sees
on a projector, at 1280x720 and 1024x768.

Served ``app/main.py`` and Debian Chromium (fixture ``browser`` of ``tests/conftest.py``). Geometry is read from
the page: the figures' Bokeh views (frame, legend, title, axes, in canvas pixels), the elements' bounding boxes
(Playwright's locators reach into Panel's shadow DOM). The bodies come from ``app.state.BODIES``.
"""

from __future__ import annotations

import pytest

from app.figures import key_figures
from app.player import PAUSE, PLAY
from app.plots import FIGURES
from app.serving import FIND_MODEL_JS, open_page, scroll_through, wait_until
from app.slides import FIGURE_VIEWS_JS
from app.state import BODIES

pytestmark = [pytest.mark.browser, pytest.mark.timeout(1500)]

VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting'], [data-regime='undetermined']"
SIZES = [(1280, 720), (1024, 768)]
#: A small run of every body (its first screen is what is tested, not its numbers); the cylinder at w = 0.8 (the
#: widest x range) and at ft 0.25, w 0.37 (a title that was cut) is tested beside.
QUERIES = {body: f"?body={body}&ft=0.3&w=0.5&point_resolution=4&periods=3" for body in BODIES}
QUERIES["cone"] = "?body=cone&ft=0.3&w=0.3&point_resolution=4&periods=3"

#: Every drawn figure's geometry, in its canvas's pixels: canvas size, frame, legends, the title's text extent and
#: the tick labels of each axis (screen position and text width), the page's box of the figure and, for figures
#: with equal axis scales, pixels per data unit along x and y.
_GEOMETRY = "() => {" + FIGURE_VIEWS_JS + """
  const box = (b) => ({left: b.left, top: b.top, right: b.right, bottom: b.bottom});
  const ctx = document.createElement('canvas').getContext('2d');
  const width = (text, font) => { ctx.font = font; return ctx.measureText(text).width; };
  const out = [];
  for (const v of figure_views()) {
    if (!v.el.isConnected || !v.el.getClientRects().length) continue;
    const m = v.model, f = v.frame.bbox, r = v.el.getBoundingClientRect();
    const fig = {title: m.title ? m.title.text : '', canvas: [v.canvas_view.bbox.width, v.canvas_view.bbox.height],
                 frame: box(f), page: {x: r.x, y: r.y, width: r.width, height: r.height}, legends: [], axes: []};
    for (const [model, rv] of v.renderer_views) {
      if (model.type === 'Legend' && model.items.length && rv.bbox) fig.legends.push(box(rv.bbox));
      if (model.type === 'Title' && model.text && rv.bbox) {
        const font = `${model.text_font_style} ${model.text_font_size} ${model.text_font}`;
        const left = rv.bbox.left + (model.align === 'left' ? model.offset : 0);
        fig.title_extent = [left, left + width(model.text, font)];
      }
      if (model.type && model.type.endsWith('Axis') && rv.tick_coords) {
        const vertical = rv.dimension === 1;
        const ticks = rv.tick_coords.major[vertical ? 1 : 0];
        const scale = vertical ? v.frame.y_scale : v.frame.x_scale;
        const font = `${model.major_label_text_font_style} ${model.major_label_text_font_size} ${model.major_label_text_font}`;
        fig.axes.push({vertical, size: parseFloat(model.major_label_text_font_size),
                       ticks: ticks.map((t) => [scale.compute(t), width(String(+t.toPrecision(4)), font)])});
      }
    }
    const xr = m.x_range, yr = m.y_range;
    if (m.match_aspect) fig.aspect = [f.width / Math.abs(xr.end - xr.start), f.height / Math.abs(yr.end - yr.start)];
    out.push(fig);
  }
  return out;
}"""


#: Sets the slider titled TITLE (value and, with a release, value_throttled) on its Bokeh model.
_SET = """([title, v, release]) => { for (const d of Bokeh.documents) for (const m of d.all_models)
    if (m.title === title && 'value_throttled' in m) { m.value = v; if (release) m.value_throttled = v; return true; }
    return false; }"""


#: Moves the player's step slider ``steps`` steps before the end of the period (value and value_throttled, as a
#: release does); returns the step, null if there is no such slider.
_NEAR_THE_END = "(steps) => {" + FIND_MODEL_JS + """
  const m = find((m) => m.title === 'Step in the period' && 'value_throttled' in m);
  if (m === null) return null;
  const v = Math.max(m.start, m.end - steps); m.value = v; m.value_throttled = v; return v;
}"""
#: Steps the player plays in the Play / Pause check: 1 s at the fast speed (60 ms a step).
_LAST_STEPS = 16


def _open(browser, url, size, query):
    return open_page(browser, url + query, size, ready=VERDICT, timeout_ms=300_000)


def _titles(body):
    return [FIGURES[name]["opts"]["title"] for name in key_figures(body)]


def _figures(page, titles=None, timeout=90):
    """The geometry of the figures titled ``titles`` once all are drawn (else of every drawn figure)."""
    def ready():
        figs = {f["title"]: f for f in page.evaluate(_GEOMETRY)}
        return figs if titles is None or all(t in figs for t in titles) else None
    figs = wait_until(ready, timeout, interval=0.2, message=f"the figures {titles} drawn")
    return figs if titles is None else {t: figs[t] for t in titles}


def _overlap(a, b, pad=0.0):
    return a["left"] < b["right"] - pad and b["left"] < a["right"] - pad and a["top"] < b["bottom"] - pad \
        and b["top"] < a["bottom"] - pad


def _check_figure(fig, where):
    """Legends outside the frame and inside the canvas (item 7), the title inside the canvas (item 11), the tick
    labels of every axis apart (item 8)."""
    name = f"{where}: {fig['title']!r}"
    cw, ch = fig["canvas"]
    for legend in fig["legends"]:
        assert not _overlap(legend, fig["frame"]), f"{name}: legend {legend} over the frame {fig['frame']}"
        assert legend["left"] >= -0.5 and legend["right"] <= cw + 0.5 and legend["bottom"] <= ch + 0.5, \
            f"{name}: legend {legend} cut by the canvas {cw}x{ch}"
    left, right = fig["title_extent"]
    assert left >= -0.5 and right <= cw + 0.5, f"{name}: title spans {left:.0f}..{right:.0f} px of {cw:.0f}"
    for axis in fig["axes"]:
        ticks = sorted(axis["ticks"])
        for (p0, w0), (p1, w1) in zip(ticks, ticks[1:]):
            need = axis["size"] if axis["vertical"] else (w0 + w1) / 2 + 3
            assert p1 - p0 >= need, f"{name}: tick labels {ticks} overlap ({p1 - p0:.1f} px < {need:.1f})"


#: The bodies whose page is also checked in presentation mode (:func:`_check_presentation_mode`), and those whose
#: every figure below the first screen is (:func:`_check_every_figure_below`): on the page of the first-screen test,
#: after its checks (each was a test of its own that opened the same page again; a page costs the server a document
#: and Chromium a render).
PRESENTATION_BODIES = ("cylinder", "sphere")
BELOW_BODIES = ("sphere", "ellipsoid")


@pytest.mark.parametrize("body", BODIES)
def test_first_screen_figures_fit_with_legends_ticks_and_titles_readable(browser, app_url, body):
    """Items 7, 8, 11 and 16, every body, at 1280x720 and 1024x768 (one page, resized): the three key figures are
    wholly inside the first viewport, unscrolled; their legends are outside the frame (they cover no data) and not
    cut; their titles are not cut; their tick labels do not run into each other. Then, on the same page, item 1
    for :data:`PRESENTATION_BODIES` and items 8 and 11 below the first screen for :data:`BELOW_BODIES`."""
    page = _open(browser, app_url, SIZES[0], QUERIES[body])
    try:
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            page.wait_for_timeout(800)  # the layout settles after the resize
            figs = _figures(page, _titles(body))
            for title, fig in figs.items():
                box = fig["page"]
                assert box["x"] >= 0 and box["x"] + box["width"] <= width + 0.5, f"{body} {width}: {title!r} {box}"
                assert box["y"] >= 0 and box["y"] + box["height"] <= height + 0.5, f"{body} {width}: {title!r} {box}"
                _check_figure(fig, f"{body} at {width}x{height}")
        assert page.problems == [], page.problems
        if body in PRESENTATION_BODIES:  # (it ends as it began: presentation mode off, the sidebar shown)
            _check_presentation_mode(page, body)
        if body in BELOW_BODIES:  # (it scrolls: last)
            _check_every_figure_below(page, body)
        assert page.problems == [], page.problems
    finally:
        page.close()


@pytest.mark.parametrize("query", ["?ft=0.25&w=0.37", "?ft=0.3&w=0.8"])
def test_cylinder_titles_and_ticks_with_pins(browser, app_url, query):
    """Items 7, 8, 11: the title cut at ft 0.25, w 0.37, the x ticks at w = 0.8; with two pinned runs the traction
    legend has nine entries and the displacement's the pins: still outside the frame, at both sizes."""
    page = _open(browser, app_url, SIZES[1], query)
    try:
        for k, w in ((1, 0.4), (2, None)):  # two runs pinned (the same run is pinned once)
            page.get_by_text("Pin this run", exact=True).first.click()
            page.locator(f"[data-pin='{k}']").first.wait_for(timeout=60_000)
            if w is not None:
                assert page.evaluate(_SET, ["w = W/a", w, True])
                page.locator(".regime-note", has_text=f"w = {w:.2f}").first.wait_for(timeout=300_000)
                page.locator(VERDICT).first.wait_for(timeout=300_000)
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            page.wait_for_timeout(800)
            for fig in _figures(page, _titles("cylinder")).values():
                _check_figure(fig, f"cylinder {query} at {width}x{height}")
        assert page.problems == [], page.problems
    finally:
        page.close()


def _check_every_figure_below(page, body):
    """Items 8 and 11 below the first screen: every figure's title, legend and ticks at 1024x768 (the zones title
    was cut there) and 1280x720; the contact maps have equal scales on x and y (a sphere's contact is round). The
    page is scrolled through at 1024x768."""
    page.set_viewport_size({"width": SIZES[1][0], "height": SIZES[1][1]})
    scroll_through(page, timeout=180)
    for width, height in SIZES:
        page.set_viewport_size({"width": width, "height": height})
        page.wait_for_timeout(1000)
        figs = _figures(page)
        maps = [figs[FIGURES[n]["opts"]["title"]] for n in ("point_pressure", "point_traction", "point_zones")]
        assert all("aspect" in f for f in maps), maps
        for fig in figs.values():
            _check_figure(fig, f"{body} at {width}x{height}")
        for fig in maps:
            px, py = fig["aspect"]
            assert px == pytest.approx(py, rel=0.02), f"{fig['title']!r}: {px:.2f} px per a along x, {py:.2f} along y"


#: The element that scrolls the page (the template's main area) and its position.
_SCROLLED = "() => document.getElementById('main').scrollTop"


def _check_presentation_mode(page, body):
    """Item 1, at 1280x720 and 1024x768 (one page, resized; the switch on and off at each): the switch is not cut;
    switched on, the sidebar folds, the key figures are wholly in the viewport and the captions under them (nothing
    over a plot); the menu button opens the sidebar, so the loads are one click away; switched off, the sidebar is
    back."""
    sidebar = page.locator("#sidebar")
    for width, height in SIZES:
        page.set_viewport_size({"width": width, "height": height})
        toggle = page.locator(".presentation-toggle button").first
        wait_until(lambda: (sidebar.bounding_box() or {}).get("width", 0) > 200, 10, message="the sidebar shown")
        page.wait_for_timeout(800)  # the layout settles after the resize
        fits = toggle.evaluate("(b) => b.scrollWidth <= b.clientWidth + 1")
        box = toggle.bounding_box()
        assert fits and box["x"] >= 0 and box["x"] + box["width"] <= width, f"{width}: the switch is cut: {box}"
        toggle.click()
        wait_until(lambda: sidebar.bounding_box() is None or sidebar.bounding_box()["width"] < 1, 10,
                   message="the sidebar folded")
        page.wait_for_timeout(1000)  # the figures are laid out again at the new width
        figs = _figures(page, _titles(body))
        captions = page.locator(".key-captions").first.bounding_box()
        for title, fig in figs.items():
            b = fig["page"]
            assert b["x"] >= 0 and b["x"] + b["width"] <= width + 0.5, f"{width}: {title!r} runs past the edge: {b}"
            assert b["y"] >= 0 and b["y"] + b["height"] <= height + 0.5, f"{width}: {title!r} cut at the bottom: {b}"
            assert b["width"] >= 300, f"{title!r}: presentation mode gives the figures the room: {b}"
            assert fig["canvas"][0] <= b["width"] + 1 and fig["canvas"][1] <= b["height"] + 1, (title, fig, b)
            _check_figure(fig, f"presentation {body} at {width}x{height}")
            assert captions["y"] >= b["y"] + b["height"] - 0.5, f"the captions {captions} over {title!r} {b}"
        # the loads are one click away
        page.locator("#sidebar-toggle").click()
        slider = page.get_by_text("ft = Ft/(μ Fn)").first
        slider.wait_for(state="visible", timeout=10_000)
        wait_until(lambda: (lambda b: b is not None and 0 <= b["x"] and b["x"] + b["width"] <= width
                            and 0 <= b["y"] < height)(slider.bounding_box()), 10, message="the ft slider in view")
        page.locator("#sidebar-toggle").click()  # folded again, then presentation mode off: the sidebar is back
        wait_until(lambda: sidebar.bounding_box() is None or sidebar.bounding_box()["width"] < 1, 10,
                   message="the sidebar folded by the menu button")
        toggle.click()
        wait_until(lambda: (sidebar.bounding_box() or {}).get("width", 0) > 200, 10, message="the sidebar back")
        assert not page.evaluate("() => document.documentElement.classList.contains('presenting')")


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_the_page_stays_where_it_is_scrolled(browser, app_url, size):
    """Item 2: wheeling down the page draws the figures further down one by one; the scroll position never jumps
    back while they are drawn (it jumped to the "Compare runs" row each time)."""
    page = _open(browser, app_url, size, "?ft=0.3&w=0.5")
    try:
        _figures(page, _titles("cylinder"))
        page.evaluate("""() => { window._scrolls = []; const m = document.getElementById('main');
                                 m.addEventListener('scroll', () => window._scrolls.push(m.scrollTop)); }""")
        drawn = len(page.evaluate(_GEOMETRY))
        page.mouse.move(size[0] * 0.6, size[1] * 0.7)
        for _ in range(14):
            page.mouse.wheel(0, 250)
            page.wait_for_timeout(600)
        page.wait_for_timeout(1500)
        scrolls = page.evaluate("() => window._scrolls")
        back = [(a, b) for a, b in zip(scrolls, scrolls[1:]) if b < a - 1]
        assert len(page.evaluate(_GEOMETRY)) > drawn, "figures further down were drawn while scrolling"
        assert scrolls and max(scrolls) >= 2000, scrolls
        assert back == [], f"the page jumped back: {back}"
        assert page.problems == [], page.problems
    finally:
        page.close()


def test_units_play_and_the_paper_tab_say_what_they_do(browser, app_url):
    """Items 12, 13, 14, at 1280x720 and 1024x768 (one page, resized): the selected unit is the filled button (its
    background differs from the other's); Play says Pause while it plays and Play again when the period is over
    (played from its last :data:`_LAST_STEPS` steps);
    the Paper's figures tab shows a spinner while it is built, then its figures (once: its build is the same at
    both sizes, and it is the longest part of the test)."""
    page = _open(browser, app_url, SIZES[0], "?ft=0.3&w=0.5&periods=3")
    try:
        buttons = page.locator(".units-toggle button")
        background = "(b) => getComputedStyle(b).backgroundColor"
        play = page.locator(".play-period button").first
        for width, height in SIZES:
            page.set_viewport_size({"width": width, "height": height})
            for unit in ("physical", "normalised"):
                page.locator(".units-toggle button", has_text=unit).first.click()
                page.mouse.move(width - 5, height - 5)  # no hover
                wait_until(lambda: page.locator(".units-toggle button.bk-active").first.inner_text().strip() == unit,
                           20, message=f"{unit} selected")
                page.wait_for_timeout(400)  # the buttons' transition
                colours = {buttons.nth(i).inner_text().strip(): buttons.nth(i).evaluate(background) for i in range(2)}
                other = next(u for u in colours if u != unit)
                assert colours[unit] != colours[other], (width, colours)
                assert colours[unit] == "rgb(0, 114, 181)" and \
                    colours[other] in ("rgba(0, 0, 0, 0)", "rgb(255, 255, 255)"), (width, colours)
            # Play / Pause, from the last steps of the period (Play goes on from the step shown): what is checked,
            # Pause while it plays and Play when the period is over, is the same; the whole period took 8-11 s
            assert play.inner_text().strip() == PLAY
            page.locator(".player-speed select").first.select_option(label="fast")
            assert page.evaluate(_NEAR_THE_END, _LAST_STEPS) is not None
            play.click()
            wait_until(lambda: play.inner_text().strip() == PAUSE, 10, message=f"Pause while it plays ({width})")
            wait_until(lambda: play.inner_text().strip() == PLAY, 60,
                       message=f"Play again when the period is over ({width})")
        # the Paper's figures tab: a spinner at once, then the figures
        page.set_viewport_size({"width": SIZES[0][0], "height": SIZES[0][1]})
        page.get_by_text("Paper's figures", exact=True).first.click()
        building = page.locator(".tab-building >> visible=true")
        building.first.wait_for(state="visible", timeout=3_000)
        page.get_by_text("Building “Paper's figures”…").first.wait_for(state="visible", timeout=3_000)
        wait_until(lambda: any(f["title"].startswith("Fig") for f in page.evaluate(_GEOMETRY)) or None, 120,
                   interval=0.2, message="the paper's figures drawn")
        wait_until(lambda: building.count() == 0, 10, message="the spinner gone")
        assert page.problems == [], page.problems
    finally:
        page.close()
