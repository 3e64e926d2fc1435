"""Real-browser tests of what a class sees: layout at projector sizes, sessions after an expiry, the player
after a preset, accessible names, a page that scrolls.

One served app and one Chromium for the module (the expiry test serves its own, with a short session
lifetime). The layout check walks the page, descending into every shadow root (Panel renders there),
collects the rectangles of visible text and of controls, and fails when two texts, or a text and a
control, overlap, or when a text is cut off by the viewport or by a clipping container.
"""

from __future__ import annotations

import pytest

import core
from app.paper_figures import TITLES
from app.serving import scroll_through, served_app, wait_until
from app.slides import FIGURE_VIEWS_JS

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]

VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting']"
SIZES = [(1024, 768), (1280, 720), (1920, 1080)]

# ---- the layout walker -------------------------------------------------------------------------------------
#: Returns [problem, ...]: overlapping texts, text over a control, text cut off.
_LAYOUT = r"""
() => {
  const texts = [], controls = [];
  const W = window.innerWidth;
  const visible = (el) => {
    for (let e = el; e; e = e.parentNode instanceof ShadowRoot ? e.parentNode.host : e.parentElement) {
      const s = getComputedStyle(e);
      if (s.display === 'none' || s.visibility === 'hidden' || Number(s.opacity) === 0) return false;
    }
    return true;
  };
  const clippers = (el) => {   // ancestors that clip their content (overflow hidden or clip)
    const out = [];
    for (let e = el.parentNode instanceof ShadowRoot ? el.parentNode.host : el.parentElement, n = 0; e && n < 12;
         e = e.parentNode instanceof ShadowRoot ? e.parentNode.host : e.parentElement, n++) {
      const s = getComputedStyle(e);
      if (['hidden', 'clip'].includes(s.overflowX) || ['hidden', 'clip'].includes(s.overflowY))
        out.push([e, s.overflowX, s.overflowY]);
      if (['auto', 'scroll'].includes(s.overflowX) || ['auto', 'scroll'].includes(s.overflowY))
        break;  // a scroll container: what lies beyond it is scrolled to, not cut off
    }
    return out;
  };
  const up = (e) => e.parentNode instanceof ShadowRoot ? e.parentNode.host : e.parentElement;
  const inside = (el, c) => { for (let e = el; e; e = up(e)) if (e === c) return true; return false; };
  const isControl = (el) => el.matches('button, input, select, textarea, .noUi-handle, [role=slider]');
  const walk = (root) => {
    const it = document.createTreeWalker(root, NodeFilter.SHOW_ELEMENT | NodeFilter.SHOW_TEXT);
    for (let n = it.currentNode; n; n = it.nextNode()) {
      if (n.nodeType === Node.ELEMENT_NODE) {
        if (n.shadowRoot) walk(n.shadowRoot);
        if (['STYLE', 'SCRIPT', 'OPTION'].includes(n.tagName)) continue;
        if (isControl(n) && visible(n)) {
          const r = n.getBoundingClientRect();
          if (r.width > 1 && r.height > 1) controls.push({el: n, r, name: n.tagName + '.' + n.className});
        }
        continue;
      }
      if (!n.textContent.trim() || !n.parentElement || !visible(n.parentElement)) continue;
      if (n.parentElement.closest('.katex, .bk-tooltip')) continue;  // math: glyphs overlap by design
      const range = document.createRange();
      range.selectNodeContents(n);
      for (const r of range.getClientRects()) {
        if (r.width > 1 && r.height > 1) texts.push({node: n, el: n.parentElement, r, t: n.textContent.trim().slice(0, 40)});
      }
    }
  };
  walk(document.body);
  const overlap = (a, b) => Math.min(a.right, b.right) - Math.max(a.left, b.left) > 2
                          && Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top) > 2;
  const problems = [];
  for (let i = 0; i < texts.length; i++) {
    const a = texts[i];
    if (a.r.right > W + 1 || a.r.left < -1)
      problems.push(`cut off by the window: "${a.t}" (${a.el.tagName}.${a.el.className} at x = ${a.r.left}..${a.r.right})`);
    for (const [c, ox, oy] of clippers(a.el)) {
      const cr = c.getBoundingClientRect();
      const outX = a.r.right > cr.right + 2 || a.r.left < cr.left - 2;
      const outY = a.r.bottom > cr.bottom + 2 || a.r.top < cr.top - 2;
      const clips = (o) => o === 'hidden' || o === 'clip';   // auto and scroll scroll, they do not cut
      if ((outX && clips(ox)) || (outY && clips(oy))) {
        problems.push(`cut off by ${c.tagName}.${c.className}: "${a.t}"`);
        break;
      }
    }
    for (let j = i + 1; j < texts.length; j++) {
      const b = texts[j];
      if (a.node !== b.node && overlap(a.r, b.r)) problems.push(`text over text: "${a.t}" / "${b.t}"`);
    }
    for (const c of controls) {
      if (!inside(a.el, c.el) && overlap(a.r, c.r))
        problems.push(`text over a control: "${a.t}" / ${c.name}`);
    }
  }
  return [...new Set(problems)];
}
"""

#: Returns [problem, ...]: a figure's legend that does not fit in its figure (Bokeh draws legends on the canvas,
#: where the walker above does not see them).
_LEGENDS = "() => {" + FIGURE_VIEWS_JS + r"""
  const problems = [];
  const is = (m, name) => m && (m.type === name || (m.constructor && m.constructor.__name__ === name));
  for (const v of figure_views()) {
    const box = v.el.getBoundingClientRect();
    if (box.width < 2 || box.height < 2) continue;   // not shown (another tab, a hidden figure)
    for (const r of (v.all_renderer_views ?? v.computed_renderer_views ?? [])) {
      if (!is(r.model, 'Legend') || !r.model.visible || !r.model.items.some((i) => i.visible)) continue;
      const b = r.bbox;
      if (b.left < -1 || b.top < -1 || b.right > box.width + 1 || b.bottom > box.height + 1)
        problems.push(`legend cut off: "${v.model.title && v.model.title.text}" (legend ${Math.round(b.left)}..` +
                      `${Math.round(b.right)} x ${Math.round(b.top)}..${Math.round(b.bottom)} in ` +
                      `${Math.round(box.width)} x ${Math.round(box.height)})`);
    }
  }
  return problems;
}"""


# app_url and browser: session fixtures in tests/conftest.py (one served app, one Chromium)


def _open(browser, url, size=(1280, 720), query=""):
    """A page at ``size``, with every failed request, HTTP error and console error recorded in ``page.problems``."""
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    page.problems = []
    page.on("requestfailed", lambda r: page.problems.append(f"request failed: {r.url}"))
    page.on("response", lambda r: page.problems.append(f"HTTP {r.status}: {r.url}") if r.status >= 400 else None)
    page.on("console", lambda m: page.problems.append(f"console: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: page.problems.append(f"page error: {e}"))
    page.goto(url + query, timeout=180_000)
    page.locator(VERDICT).first.wait_for(timeout=180_000)
    scroll_through(page)  # the figures are drawn as the page is scrolled to them
    page.locator(".bk-Canvas, canvas").nth(5).wait_for(timeout=60_000)
    return page


def _settle(page):
    """Wait until the layout stops moving (two animation frames with the same page height)."""
    page.wait_for_function("""() => new Promise((done) => {
        const h = () => document.body.scrollHeight + ':' + document.querySelectorAll('*').length;
        const a = h(); requestAnimationFrame(() => requestAnimationFrame(() => done(a === h())));
    })""", timeout=30_000)
    page.wait_for_timeout(300)


def _fits_at_every_size(page, tab):
    """Resize ``page`` to each of :data:`SIZES`: nothing overlaps or is cut off, legends included, no sideways scroll."""
    for width, height in SIZES:
        page.set_viewport_size({"width": width, "height": height})
        _settle(page)
        problems = page.evaluate(_LAYOUT) + page.evaluate(_LEGENDS)
        assert problems == [], f"{tab} at {width}x{height}:\n" + "\n".join(problems[:30])
        assert page.evaluate("() => document.documentElement.scrollWidth") <= width
        # the header clips what it cannot fit (the busy indicator, drawn without text, went unseen above)
        header = page.evaluate("() => Math.max(...[...document.querySelectorAll('#header *')].map((e) => "
                               "e.getBoundingClientRect().right))")
        assert header <= width + 1, f"{tab} at {width}x{height}: the header reaches x = {header}"


def test_nothing_overlaps_or_is_cut_off(browser, app_url):
    """At 1024x768, 1280x720 and 1920x1080 (one session, resized), in the Explorer tab and in the About tab; at
    1280x720 every control of the Explorer tab has an accessible name (see
    :func:`_every_control_has_an_accessible_name`), the wheel scrolls the page and the sketch follows the player
    (:func:`_the_wheel_scrolls_the_page_zoom_is_one_click_away_and_the_sketch_follows_the_player`); then the
    Paper's figures tab (:func:`_the_paper_figures_fit_and_save_as_png_and_svg`). The default run's page, opened
    once for all of these (each was a test of its own that opened and scrolled through the same page: a page
    costs the server a document and Chromium the drawing of every figure)."""
    page = _open(browser, app_url, SIZES[0])
    for tab in ("Explorer", "About the model"):
        if tab != "Explorer":
            page.get_by_text(tab, exact=True).first.click()
            page.locator(".katex").first.wait_for(timeout=30_000)
            # the equations are drawn with KaTeX's fonts, declared at document level
            page.wait_for_function("() => document.fonts.check('20px KaTeX_Main')", timeout=30_000)
        _fits_at_every_size(page, tab)
        if tab == "Explorer":
            page.set_viewport_size({"width": 1280, "height": 720})
            _settle(page)
            _every_control_has_an_accessible_name(page)
            _the_wheel_scrolls_the_page_zoom_is_one_click_away_and_the_sketch_follows_the_player(page)
    assert page.problems == [], page.problems
    page.set_viewport_size({"width": SIZES[0][0], "height": SIZES[0][1]})
    _the_paper_figures_fit_and_save_as_png_and_svg(page)
    assert page.problems == [], page.problems
    page.close()


def test_a_phone_gets_one_column(browser, app_url):
    page = _open(browser, app_url, (390, 844))
    _settle(page)
    assert page.evaluate("() => document.documentElement.scrollWidth") <= 390
    problems = [p for p in page.evaluate(_LAYOUT) if "cut off by the window" in p]
    assert problems == [], problems
    assert page.problems == [], page.problems
    page.close()


def _the_wheel_scrolls_the_page_zoom_is_one_click_away_and_the_sketch_follows_the_player(page):
    """At 1280x720, the default run: the wheel over a figure scrolls the page, every figure's wheel zoom is in its
    toolbar and off; then the sketch follows the player (see :func:`_the_sketch_follows_the_player`)."""
    tools = page.evaluate("""() => [...Bokeh.documents[0].all_models].filter((m) => m.type === 'Toolbar' ||
        (m.constructor && m.constructor.__name__ === 'Toolbar')).map((m) => [m.active_scroll == null,
        m.tools.some((t) => t.constructor.__name__ === 'WheelZoomTool')])""")
    assert len(tools) >= 6 and all(off and has for off, has in tools), tools
    main = "() => document.getElementById('main').scrollTop"
    canvas = page.locator(".bk-Canvas, canvas").nth(0)
    canvas.scroll_into_view_if_needed()
    before = page.evaluate(main)
    box = canvas.bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.wheel(0, 300)
    page.wait_for_function(f"(b) => ({main})() > b", arg=before, timeout=10_000)
    _the_sketch_follows_the_player(page)


def test_preset_resets_the_player_and_the_cards_agree(browser, app_url):
    page = _open(browser, app_url, (1600, 1000), "?ft=0.08&w=0.26")
    step_end = """() => { for (const m of Bokeh.documents[0].all_models)
        if (m.title === 'Step in the period' && 'value_throttled' in m) return m.end; }"""
    dom_max = """() => { const out = [];
        const walk = (root) => { for (const e of root.querySelectorAll('*')) { if (e.shadowRoot) walk(e.shadowRoot); }
          for (const h of root.querySelectorAll('.noUi-handle[aria-label="Step in the period"]'))
            out.push(Number(h.getAttribute('aria-valuemax'))); };
        walk(document); return out; }"""
    before = page.evaluate(step_end)
    page.locator("select").first.select_option("Fig 7: ft = 0.58, w = 0.77")
    page.locator("[data-regime='ratcheting']").first.wait_for(timeout=60_000)
    result = core.simulate_cycles(0.58, 0.77, periods=10, dx=1 / 40, kernel="plane")
    steps = int((result.period == 0).sum())
    page.wait_for_function(f"(n) => ({step_end})() === n", arg=steps - 1, timeout=20_000)
    assert steps - 1 != before
    # what the browser draws follows the model: the slider's handle ends at the last step of the new period
    page.wait_for_function(f"(n) => ({dom_max})().length > 0 && ({dom_max})().every((v) => v === n)",
                           arg=steps - 1, timeout=20_000)
    # consistent cards: the closure says none (ft > ft_lim) and the badge says ratcheting, never shakedown
    page.get_by_text("all numbers ▾").first.click()  # every number is one click away
    page.locator(".cards").first.wait_for(timeout=30_000)
    page.get_by_text("none (ft > ft_lim)").first.wait_for(timeout=20_000)
    assert page.locator("[data-regime='shakedown']").count() == 0
    # an edit makes the preset box say (custom)
    page.evaluate("""() => { for (const m of Bokeh.documents[0].all_models)
        if (m.title === 'ft = Ft/(μ Fn)' && 'value_throttled' in m) { m.value = 0.3; m.value_throttled = 0.3; } }""")
    page.wait_for_function("""() => { for (const m of Bokeh.documents[0].all_models)
        if (m.title === 'Preset' && 'options' in m) return m.value === '(custom)'; }""", timeout=20_000)
    # the Fig 7, w = 0.26 preset carries the note on the paper's caption
    page.locator("select").first.select_option("Fig 7: ft = 0.58, w = 0.26")
    page.get_by_text("caption lists this case among the ratcheting").first.wait_for(timeout=20_000)
    assert page.problems == [], page.problems
    page.close()


def _every_control_has_an_accessible_name(page):
    """Every visible button, slider handle, input and select has a name a screen reader reads out."""
    page.wait_for_function("""() => { let ok = 0;
        const walk = (root) => { for (const e of root.querySelectorAll('*')) if (e.shadowRoot) walk(e.shadowRoot);
          for (const h of root.querySelectorAll('.noUi-handle')) if (h.getAttribute('aria-label')) ok++; };
        walk(document); return ok >= 5; }""", timeout=20_000)
    unnamed = page.evaluate("""() => { const out = [];
        // the text a screen reader reads out: the flat tree, shadow roots included
        const text = (e) => [...(e.shadowRoot ? e.shadowRoot.childNodes : []), ...e.childNodes].map((c) =>
          c.nodeType === Node.TEXT_NODE ? c.textContent : (c.nodeType === Node.ELEMENT_NODE ? text(c) : '')).join('');
        const walk = (root) => { for (const e of root.querySelectorAll('*')) if (e.shadowRoot) walk(e.shadowRoot);
          for (const e of root.querySelectorAll('button, .noUi-handle, input, select')) {
            if (e.offsetParent === null && e.getClientRects().length === 0) continue;
            const name = e.getAttribute('aria-label') || e.getAttribute('title') || text(e).trim()
                         || (e.labels && e.labels.length) || (e.type === 'file') || e.getAttribute('aria-labelledby');
            if (!name && !(e.tagName === 'INPUT' && e.closest('label'))) out.push(e.tagName + '.' + e.className);
          } };
        walk(document); return out; }""")
    assert unnamed == [], unnamed


def test_a_session_after_an_expired_one_finds_every_label(browser, tmp_path):
    """The colour bar's state names used to live in one Bokeh model shared by all sessions, emptied when the
    first session expired: open, close, let it expire, open again."""
    labels = """() => { for (const m of Bokeh.documents[0].all_models)
        if (m.title === 'element state' && m.ticker != null) return [Array.from(m.ticker.ticks ?? []),
            Object.values(m.major_label_overrides instanceof Map ? Object.fromEntries(m.major_label_overrides)
                                                                  : m.major_label_overrides)]; }"""
    lifetime = ["--unused-session-lifetime", "1000", "--check-unused-sessions", "300", "--log-level", "debug"]
    log = tmp_path / "server.log"
    with served_app(extra_args=lifetime, log_path=log) as url:
        first = _open(browser, url)
        assert first.evaluate(labels) == [[0, 1, 2, 3], list(core.STATE_NAMES)]
        first.close()
        # the server discards the closed session (and cleans up its models) about a second later
        wait_until(lambda: "Discarding session" in log.read_text(errors="replace"), 60,
                   message="the first session to expire")
        second = _open(browser, url)
        second.wait_for_function(f"() => ({labels})() !== undefined", timeout=20_000)
        assert second.evaluate(labels) == [[0, 1, 2, 3], list(core.STATE_NAMES)]
        # (not asserted here: with a lifetime this short a page that connects late has its session rebuilt,
        # which Panel 1.9 serves without its stylesheet paths, a server-side matter of its own)
        assert not [p for p in second.problems if p.startswith("page error")], second.problems
        second.close()


def _set_slider(page, title, value):
    page.evaluate("""([title, v]) => { for (const m of Bokeh.documents[0].all_models)
        if (m.title === title && 'value_throttled' in m) { m.value = v; m.value_throttled = v; } }""", [title, value])


def test_pinned_runs_overlay_the_figures_and_the_page_still_fits(browser, app_url):
    """Pin two runs (in physical units: the engineer's inputs and the creep cards show), find them in the table
    and as curves on the displacement, increment and traction figures; unpin one, clear; the figures switch to
    SVG for export; nothing overlaps at 1024x768 with all of it shown."""
    page = _open(browser, app_url, SIZES[0], "?ft=0.3&w=0.5&units=physical&periods=6")
    pinned_points = """() => { const out = {};
        for (const m of Bokeh.documents[0].all_models) {
          if (m.type !== 'LegendItem' && !(m.constructor && m.constructor.__name__ === 'LegendItem')) continue;
          const label = m.label && (m.label.value ?? m.label);
          if (typeof label === 'string' && label.startsWith('pin ') && m.visible)
            for (const r of m.renderers) { const d = r.data_source.data;
              const n = (d instanceof Map ? [...d.values()] : Object.values(d))[0].length;
              (out[label] = out[label] || []).push(n); } }
        return out; }"""
    page.get_by_text("Pin this run", exact=True).first.click()
    page.locator("[data-pin='1']").first.wait_for(timeout=20_000)
    _set_slider(page, "w = W/a", 0.7)
    page.locator("[data-regime='ratcheting']").first.wait_for(timeout=60_000)
    page.get_by_text("Pin this run", exact=True).first.click()
    page.locator("[data-pin='2']").first.wait_for(timeout=20_000)
    rows = page.locator("table.pins tr[data-pin]").all_inner_texts()
    assert "shakedown" in rows[0] and "0.50" in rows[0] and "ratcheting" in rows[1] and "0.70" in rows[1], rows
    # each pin is drawn on the three figures, with data (legend entries of empty pins stay hidden)
    page.wait_for_function(f"""() => {{ const p = ({pinned_points})(); return Object.keys(p).length === 2
        && Object.values(p).every((n) => n.length === 3 && n.every((k) => k > 1)); }}""", timeout=20_000)
    # the engineer's inputs: Ft in N follows ft = 0.3 of μ Fn
    assert page.get_by_text("Ft, tangential force [N]").count() >= 1
    page.get_by_text("all numbers ▾").first.click()  # every number is one click away
    page.locator(".cards").first.wait_for(timeout=30_000)
    assert page.get_by_text("creep after 10⁶ periods").count() >= 1
    _settle(page)
    problems = page.evaluate(_LAYOUT)
    assert problems == [], "with pinned runs at 1024x768:\n" + "\n".join(problems[:30])
    # pinning the same run twice is refused, with a message
    page.get_by_text("Pin this run", exact=True).first.click()
    page.get_by_text("pinned already").first.wait_for(timeout=20_000)
    # unpin the first: the second becomes pin 1; clear: none left
    page.locator(".unpin select").first.select_option("pin 1")
    page.wait_for_function("""() => { let n = 0;
        const walk = (root) => { for (const e of root.querySelectorAll('*')) if (e.shadowRoot) walk(e.shadowRoot);
          n += root.querySelectorAll('table.pins tr[data-pin]').length; }; walk(document); return n === 1; }""",
                           timeout=20_000)
    assert "ratcheting" in page.locator("table.pins tr[data-pin]").first.inner_text()
    page.get_by_text("Clear pins", exact=True).first.click()
    page.get_by_text("No run pinned").first.wait_for(timeout=20_000)
    page.wait_for_function(f"() => Object.keys(({pinned_points})()).length === 0", timeout=20_000)
    # for slides: a figure saves as SVG, named after the figure and the run
    page.locator(".svg-figure select").first.select_option("Rigid-body displacement")
    with page.expect_download(timeout=20_000) as download:
        page.get_by_text("Save as SVG", exact=True).first.click()
    assert download.value.suggested_filename == "shakedown_displacement_ft0.30_w0.70.svg"
    with open(download.value.path(), encoding="utf-8") as f:
        svg = f.read()
    assert svg.startswith("<svg") and "</svg>" in svg and "<path" in svg
    assert page.problems == [], page.problems
    page.close()


def _the_sketch_follows_the_player(page):
    """The cylinder sketch of ``page`` (the default run, ft 0.3, w 0.5) shows the player's step: a step back moves
    the cylinder and keeps a trailing edge."""
    sketch = """() => { for (const m of Bokeh.documents[0].all_models)
        if (m.type === 'LegendItem' || (m.constructor && m.constructor.__name__ === 'LegendItem')) {
          const label = m.label && (m.label.value ?? m.label);
          if (label === 'trailing edge') { const d = m.renderers[0].data_source.data;
            const g = (k) => Array.from(d instanceof Map ? d.get(k) : d[k]); return [g('x'), m.visible]; } } }"""
    before = page.evaluate(sketch)
    for _ in range(5):
        page.get_by_text("◀ Step", exact=True).first.click()
    page.wait_for_function(f"(b) => JSON.stringify(({sketch})()) !== JSON.stringify(b)", arg=before, timeout=20_000)
    after = page.evaluate(sketch)
    assert len(after[0]) == 1 and after[1], after


def _the_paper_figures_fit_and_save_as_png_and_svg(page):
    """The Paper's figures tab at 1024x768, 1280x720 and 1920x1080: nothing overlaps or is cut off, legends
    included; every figure has the toolbar's save tool (PNG); a chosen figure downloads as SVG named after it."""
    page.get_by_text("Paper's figures", exact=True).first.click()
    paper_views = "figure_views().filter((v) => v.model.title && v.model.title.text.startsWith('Fig '))"
    page.wait_for_function(f"() => {{ {FIGURE_VIEWS_JS} return {paper_views}.length === {len(TITLES)}; }}",
                           timeout=60_000)
    _fits_at_every_size(page, "Paper's figures")
    # PNG: the toolbar's save tool on every figure
    saves = page.evaluate(f"""() => {{ {FIGURE_VIEWS_JS} return Object.fromEntries({paper_views}.map((v) =>
        [v.model.title.text, v.model.toolbar.tools.some((t) => t.constructor.__name__ === 'SaveTool')])); }}""")
    assert saves == {title: True for title in TITLES.values()}, saves
    # SVG: choose a figure, save, get its drawing in a file named after it
    rows = page.locator(".save-svg-row")
    rows.locator(".svg-figure select").last.select_option(TITLES["fig14"])
    with page.expect_download(timeout=20_000) as download:
        rows.get_by_text("Save as SVG", exact=True).last.click()
    assert download.value.suggested_filename == "shakedown_paper_fig_14.svg"
    with open(download.value.path(), encoding="utf-8") as f:
        svg = f.read()
    assert svg.startswith("<svg") and svg.rstrip().endswith("</svg>") and svg.count("<path") > 5, svg[:300]
    assert "Fig 14: shakedown limit" in svg and "eq 35" in svg  # the title and the legend, as SVG text
