"""Real-browser tests of the served explorer (Chromium driven by Playwright).

A session fixture serves ``app/main.py`` with ``panel serve --liveness`` on a
free loopback port and waits on ``/liveness``; every wait below polls (no fixed
sleeps). Panel renders into shadow DOM: Playwright's CSS locators pierce it,
and the Bokeh models (``Bokeh.documents[0].all_models``) give widget values and
plot data.
"""

import io

import pandas as pd
import pytest

import core
from app.figures import key_figures
from app.plots import FIGURES
from app import point_view
from app.serving import FIND_MODEL_JS, scroll_through

pytestmark = [pytest.mark.browser, pytest.mark.timeout(300)]

BADGE = "[data-regime='shakedown'], [data-regime='cyclic slip'], [data-regime='ratcheting'], [data-regime='undetermined']"  # a verdict is shown
FT_TITLE = "ft = Ft/(μ Fn)"
W_TITLE = "w = W/a"

# ---- Bokeh model access (page.evaluate) ------------------------------------
_FIND = FIND_MODEL_JS
_GET_SLIDER = "(title) => {" + _FIND + """
  const m = find((m) => m.title === title && typeof m.value === 'number' && 'value_throttled' in m);
  return m === null ? null : m.value;
}"""
_SET_SLIDER = "([title, value, release]) => {" + _FIND + """
  const m = find((m) => m.title === title && typeof m.value === 'number' && 'value_throttled' in m);
  m.value = value;
  if (release) m.value_throttled = value;   // what a mouse-up does
}"""
_TRACTION = "(title) => {" + _FIND + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  const out = [];
  for (const r of fig.renderers) {
    const d = r.data_source == null ? null : r.data_source.data;
    if (d == null) continue;
    for (const k of Object.keys(d).sort()) out.push(k + ':' + Array.from(d[k]).map(Number).join(','));
  }
  return out.join('|');
}"""
_SET_PLAYER = "(value) => {" + _FIND + """
  const m = find((m) => m.title === 'Step in the period' && 'value_throttled' in m);
  m.value = value;
}"""
_AXIS_LABEL = "(label) => {" + _FIND + """
  return find((m) => m.axis_label === label) !== null;
}"""
_MAP_POINT = "() => {" + _FIND + "\n  const fig = find((m) => m.title != null && m.title.text === " + repr(FIGURES["map"]["opts"]["title"]) + """);
  // the current point is the map's last layer (a run layer of the shipped map may hold one point too)
  for (const r of [...fig.renderers].reverse()) {
    const d = r.data_source == null ? null : r.data_source.data;
    if (d != null && d.ft != null && d.ft.length === 1) return Number(d.ft[0]);
  }
  return null;
}"""


# app_url and browser: session fixtures in tests/conftest.py (one served app, one Chromium)


@pytest.fixture
def open_app(browser, app_url):
    """Open the app (with an optional query); yields a function returning (page, console errors)."""
    contexts = []

    def _open(query=""):
        ctx = browser.new_context(viewport={"width": 1600, "height": 1000}, accept_downloads=True)
        contexts.append(ctx)
        page = ctx.new_page()
        errors = []
        page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(app_url + query, timeout=180_000)  # the first session pays for imports and compiling
        page.locator(BADGE).first.wait_for(timeout=60_000)
        scroll_through(page)  # every figure drawn, as for a reader who scrolled to the end
        return page, errors

    yield _open
    for ctx in contexts:
        ctx.close()


def regime(page) -> str:
    return page.locator("[data-regime]").first.get_attribute("data-regime")


# ---- the tests ---------------------------------------------------------------
def test_page_loads_without_errors_and_the_about_tab_renders_the_equations(open_app):
    """The default page (one load for both checks): its figures drawn, no traceback, the default verdict; then the
    About tab's equations, drawn by KaTeX served by Panel itself (no CDN)."""
    page, errors = open_app()
    page.wait_for_function("() => window.Bokeh !== undefined && Bokeh.documents.length > 0")
    page.locator(".bk-Canvas, canvas").nth(5).wait_for(timeout=30_000)  # the six figures
    assert page.get_by_text("Traceback").count() == 0
    assert regime(page) == "shakedown"  # the default, ft = 0.3, w = 0.5
    assert errors == [], errors
    page.get_by_text("About the model").first.click()
    page.get_by_text("What is exact and what is approximate").first.wait_for(timeout=20_000)
    page.locator(".katex").first.wait_for(timeout=20_000)  # KaTeX, served by Panel itself (no CDN)
    assert errors == [], errors


_FIGURE_TITLES = "() => [...Bokeh.documents[0].all_models].filter((m) => m.type === 'Figure').map((m) => m.title.text)"


def test_figures_are_drawn_as_the_page_is_scrolled_to_them(browser, app_url):
    """Issue 12: the page comes with the figures at its top only (a visitor who never scrolls costs the server
    only those); each of the others is drawn when the reader scrolls near it, and then updates like the first."""
    page = browser.new_page(viewport={"width": 1280, "height": 720})
    try:
        page.goto(app_url, timeout=180_000)
        page.locator(BADGE).first.wait_for(timeout=60_000)
        page.wait_for_function(f"() => ({_FIGURE_TITLES})().length >= 1", timeout=30_000)
        page.wait_for_timeout(1000)  # nothing more comes by itself
        page.wait_for_function(f"() => ({_FIGURE_TITLES})().length >= 3", timeout=30_000)
        page.wait_for_timeout(1000)  # nothing more comes by itself
        first = page.evaluate(_FIGURE_TITLES)  # the first screen's three figures
        assert sorted(first) == sorted(FIGURES[n]["opts"]["title"] for n in key_figures("cylinder")), first
        scroll_through(page)
        titles = page.evaluate(_FIGURE_TITLES)
        # every figure of the cylinder's page, the fretting loop (issue 30) included: eight
        shown = [f["opts"]["title"] for n, f in FIGURES.items() if point_view.shown(n, "cylinder")]
        assert sorted(titles) == sorted(shown), titles
        assert len(titles) == 8 and "Fretting loop" in titles, titles
        before = page.evaluate(_TRACTION, FIGURES["traction"]["opts"]["title"])
        page.evaluate(_SET_SLIDER, [FT_TITLE, 0.2, False])  # a drag: the closure follows
        page.wait_for_function(f"() => ({_TRACTION})({FIGURES['traction']['opts']['title']!r}) !== {before!r}",
                               timeout=30_000)
    finally:
        page.close()


def test_moving_ft_across_the_limit_flips_the_badge(open_app):
    page, errors = open_app("?w=0.5&periods=8")
    lim = float(core.ft_limit(0.5))
    # while dragging, the analytical layers follow but the solver does not run
    page.evaluate(_SET_SLIDER, [FT_TITLE, round(lim + 0.15, 2), False])
    page.wait_for_function(f"(v) => Math.abs(({_MAP_POINT})() - v) < 1e-9", arg=round(lim + 0.15, 2))
    # the old verdict is not shown beside the new inputs: the badge waits for the release
    page.locator("[data-regime='pending']").first.wait_for(timeout=10_000)
    page.get_by_text("RELEASE TO SOLVE").first.wait_for(timeout=10_000)
    # on release the solver runs and the verdict flips
    page.evaluate(_SET_SLIDER, [FT_TITLE, round(lim + 0.15, 2), True])
    page.wait_for_function("() => window.location.search.includes('ft=0.54')", timeout=60_000)
    page.locator("[data-regime='ratcheting']").first.wait_for(timeout=90_000)
    page.evaluate(_SET_SLIDER, [FT_TITLE, round(lim - 0.15, 2), True])
    page.locator("[data-regime='shakedown']").first.wait_for(timeout=90_000)
    assert "ft=" + str(round(lim - 0.15, 2)) in page.evaluate("() => window.location.search")
    assert errors == [], errors


def test_url_parameters_are_restored(open_app):
    page, errors = open_app("?ft=0.61&w=0.2&kernel=plane&periods=5&units=physical")
    page.wait_for_function(f"() => ({_GET_SLIDER})({FT_TITLE!r}) === 0.61")
    assert page.evaluate(_GET_SLIDER, W_TITLE) == 0.2
    assert regime(page) == "shakedown"  # ft_lim(0.2) = 0.75
    page.wait_for_function(f"() => ({_AXIS_LABEL})('x [mm]')")  # physical units on the axes
    search = page.evaluate("() => window.location.search")
    for part in ("ft=0.61", "w=0.2", "kernel=plane", "periods=5", "units=physical"):
        assert part in search, search
    assert errors == [], errors


def test_csv_download_has_the_right_columns(open_app):
    page, errors = open_app("?ft=0.3&w=0.5&periods=4")
    with page.expect_download(timeout=30_000) as info:
        page.locator(".csv-download button, .csv-download a").first.click()
    text = open(info.value.path(), encoding="utf-8").read()
    assert "# ft = 0.3" in text and "# contact_mu = 0.58" in text
    df = pd.read_csv(io.StringIO(text), comment="#")
    assert list(df.columns) == ["step", "period", "xc_a", "displacement_muP_Estar", "u_U_over_U0",
                                "dissipation", "xc_m", "displacement_m"]
    assert df["period"].min() == 0 and df["period"].max() == 4  # numbered as on the player: 0 the loading
    assert errors == [], errors


def test_player_changes_the_traction_plot(open_app):
    page, errors = open_app("?ft=0.58&w=0.52&periods=3")
    title = FIGURES["traction"]["opts"]["title"]
    page.wait_for_function(f"() => ({_TRACTION})({title!r}) !== null")
    before = page.evaluate(_TRACTION, title)
    page.evaluate(_SET_PLAYER, 3)
    page.wait_for_function(f"(b) => ({_TRACTION})({title!r}) !== b", arg=before, timeout=20_000)
    assert errors == [], errors


def test_bad_url_parameter_shows_a_notice(open_app):
    page, errors = open_app("?ft=abc&w=0.3&periods=-4")
    notice = page.locator(".url-notice").first
    notice.wait_for(timeout=20_000)
    page.get_by_text("ft must be a number").first.wait_for(timeout=10_000)
    page.get_by_text("periods must be in [1, 200]").first.wait_for(timeout=10_000)
    assert page.evaluate(_GET_SLIDER, W_TITLE) == 0.3  # the good parameter is applied
    assert page.evaluate(_GET_SLIDER, FT_TITLE) == 0.3  # the bad one is not (default kept)
    assert page.get_by_text("Traceback").count() == 0
    assert regime(page) == "shakedown"
    assert errors == [], errors
