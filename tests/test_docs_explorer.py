"""The explorer in a notebook (app/notebook.py): ``from app import Explorer; Explorer()`` builds headless, shows the
served page's inputs and figures, follows its state, and importing core or app imports no Panel."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_importing_core_and_app_imports_no_panel():
    code = ("import sys, core, app; core.ft_limit(0.3); "
            "assert 'panel' not in sys.modules and 'bokeh' not in sys.modules, sorted(sys.modules)")
    subprocess.run([sys.executable, "-c", code], cwd=ROOT, check=True, timeout=300)


def test_explorer_builds_headless_with_the_inputs_and_figures():
    import panel as pn

    from app import Explorer
    from app.notebook import Explorer as NotebookExplorer

    assert Explorer is NotebookExplorer
    ex = Explorer(ft=0.2, w=0.4)
    assert (ex.state.ft, ex.state.w) == (0.2, 0.4)
    assert ex.result is not None and ex.result.regime == "shakedown"  # eq 35: ft_lim(0.4) = 0.50
    layout = ex.__panel__()
    assert layout is ex.__panel__()  # built once
    sliders = {w.name for w in layout.select(pn.widgets.FloatSlider)}
    assert {"ft = Ft/(μ Fn)", "w = W/a"} <= sliders
    assert layout.select(pn.widgets.Select), "the preset box"
    assert layout.select(pn.widgets.FileDownload), "the downloads"
    assert layout.select(pn.Tabs), "the explorer, paper's figures and about tabs"
    drawn = [p for p in layout.select(pn.pane.Bokeh) if p.object is not None]
    assert len(drawn) >= 5, "a notebook draws every figure at once (no browser scrolls to ask for them)"
    assert all(s.shown for s in ex.explorer.sentinels.values())
    # the inputs drive the run shown
    ex.state.ft = 0.6
    ex.explorer.solve_now()
    assert ex.result.regime == "ratcheting"


def test_explorer_takes_a_query_and_rejects_unknown_inputs():
    import pytest

    from app import Explorer

    ex = Explorer(query="?ft=0.1&w=0.3")
    assert (ex.state.ft, ex.state.w) == (0.1, 0.3)
    with pytest.raises(ValueError):
        Explorer(ft=1.5)


@pytest.mark.browser
def test_explorer_renders_in_a_browser(browser):
    """The notebook layout renders in Chromium with no JavaScript error (served by Panel, as a notebook's output is
    drawn by the same Bokeh models): the verdict, the inputs and every figure's canvas."""
    import socket
    import time

    import panel as pn

    from app import Explorer

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = pn.serve(lambda: Explorer(ft=0.2, w=0.4), port=port, address="127.0.0.1", show=False, threaded=True,
                      websocket_origin=[f"127.0.0.1:{port}"])
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.2)
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.goto(f"http://127.0.0.1:{port}/", timeout=120_000)
        page.wait_for_selector("canvas", timeout=120_000)
        page.get_by_text("SHAKEDOWN", exact=True).first.wait_for(timeout=60_000)
        assert page.get_by_text("ft = Ft/(μ Fn)").count() >= 1
        assert page.locator("canvas").count() >= 5
        page.close()
        assert not errors, errors
    finally:
        server.stop()
