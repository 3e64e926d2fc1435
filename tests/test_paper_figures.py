"""The paper's figures (Figs 10-16): the solver's data against the paper's formulas, the shipped data, the tab.

Tolerances are explicit and say where they come from: the solver's stick
half-width is resolved to one element, the paper's stick-zone ansatz is not the
exact solution (up to 0.004 a and 0.013 mu p0 apart near the limit), and the
regressions (eqs 34, 36, 38) are fits.
"""

from __future__ import annotations

import json
import threading
import time

import holoviews as hv
import numpy as np
import pytest

import core
from core.maps import paper_figures as pf


def _a(values):
    return np.array([np.nan if v is None else v for v in values], dtype=float)


# --------------------------------------------------------------------------
# the core functions against the closed forms
# --------------------------------------------------------------------------
def test_fig10_stick_halfwidth_against_eq30():
    dx = 1 / 400
    fig = pf.stick_halfwidth_curves(w_values=(0.0, 0.52), points=3, dx=dx)
    cattaneo, rocking = fig["curves"]
    # w = 0: Cattaneo's c/a = sqrt(1 - ft) is exact, so only the grid (one element) separates them
    np.testing.assert_allclose(_a(cattaneo["solver"]), np.sqrt(1 - _a(cattaneo["ft"])), atol=dx,
                               err_msg="c_sd at w = 0 is not Cattaneo's")
    # w = 0.52: eq 30's ansatz is close but not exact near the limit (0.0036 a at dx = a/800)
    np.testing.assert_allclose(_a(rocking["solver"]), _a(rocking["eq30"]), atol=0.005,
                               err_msg="c_sd of the solver and of eq 30")
    assert fig["max_difference"] == pytest.approx(
        np.max(np.abs(_a(rocking["solver"]) - _a(rocking["eq30"]))), rel=1e-5)


def test_fig11_traction_against_the_ansatz():
    fig = pf.traction_profiles(pf.FIG11_CASES[:1], dx=1 / 100)
    (c,) = fig["curves"]
    x, q, bound = _a(c["x"]), _a(c["solver"]), _a(c["bound"])
    assert np.all(np.abs(q) <= bound + 1e-9), "traction above mu p_min"
    # load balance: sum q dx = (pi / 2) ft
    assert q.sum() / 100 == pytest.approx(0.5 * np.pi * c["ft"], rel=1e-5)
    np.testing.assert_allclose(q, _a(c["ansatz"]), atol=0.015, err_msg="traction: solver vs eqs 22-26")
    assert abs(c["c_solver"] - c["c_eq30"]) <= 0.01 + 1e-9
    assert np.all(np.abs(x) < 1.0)


def test_fig13_shakedown_displacement_direct_equals_transient_and_eq34():
    fig = pf.shakedown_displacement_curves(w_values=(0.0, 0.26), points=3, dx=1 / 100, check_ft=(0.1,),
                                           check_dx=1 / 40, periods=10)
    static, rocking = fig["curves"]
    # the direct state's centre displacement is the transient's final u, to the solver's grid
    assert fig["max_transient_difference"] <= 1e-4
    # w = 0 is the static problem: the paper's eq 13 regression within 0.01 U0
    np.testing.assert_allclose(_a(static["solver"]), _a(static["eq13"]), atol=0.01)
    np.testing.assert_allclose(_a(rocking["solver"]), _a(rocking["eq34"]), atol=0.01,
                               err_msg="u_sd: solver vs the paper's regression eq 34")
    assert static["solver"][0] == pytest.approx(0.0, abs=1e-12)  # ft = 0: no displacement


def test_fig14_limit_bracket_contains_eq35():
    fig = pf.limit_curve(ft_values=(0.5,), tol=5e-3, periods=20)
    p = fig["points"]
    assert p["w_shakedown"][0] <= p["w_eq35"][0] <= p["w_ratcheting"][0]
    assert p["w_ratcheting"][0] - p["w_shakedown"][0] <= 2 * 5e-3 + 1e-9
    assert fig["eq35_in_bracket"] == [1, 1]
    assert p["w_eq35"][0] == pytest.approx(float(core.w_limit(0.5)), abs=1e-6)
    # the regression eq 36 against the exact eq 35, over the whole line
    assert fig["max_regression_difference"] <= 0.012


def test_fig15_u_lim_is_the_limit_of_u_sd():
    lim = pf.limit_displacement_curve(w_values=(0.0, 0.5), dx=1 / 200)
    assert lim["solver"][0] == pytest.approx(1.0, abs=1e-5)  # w = 0: ft_lim = 1, u_lim = U0 by definition
    near = pf.shakedown_displacement_curves(w_values=(0.5,), points=2, dx=1 / 200, check_ft=())["curves"][0]
    assert near["ft"][-1] == pytest.approx(0.99 * lim["ft_lim"][1], rel=1e-6)
    # u_sd rises towards u_lim as ft -> ft_lim
    assert near["solver"][-1] < lim["solver"][1] < near["solver"][-1] + 0.01
    # eq 34 at the limit (eq 37 is unreadable) is within 0.01 U0
    assert lim["max_difference"] <= 0.01


def test_fig16_increment_grows_with_ft_and_eq38_is_rough():
    fig = pf.ratchet_increment_curves(w_values=(0.52,), points=3, periods=20)
    (c,) = fig["curves"]
    du = _a(c["solver"])
    assert c["regime"] == ["ratcheting"] * 3
    assert np.all(du > 0) and np.all(np.diff(du) > 0), du
    eq38 = _a(c["eq38"])
    np.testing.assert_allclose(eq38, core.theory.approximations.ratchet_increment_approx(_a(c["ft"]), 0.52), rtol=1e-5)
    # the regression is a rough fit: within 30 % of the solver at w = 0.52 (measured up to 22 %)
    np.testing.assert_allclose(eq38, du, rtol=0.3)


def test_cancel_and_bad_names():
    stop = threading.Event()
    stop.set()
    with pytest.raises(pf.FiguresCancelled):
        pf.stick_halfwidth_curves(w_values=(0.2,), points=3, cancel=stop)
    with pytest.raises(ValueError, match="figures must be among"):
        pf.compute(["fig99"])
    with pytest.raises(ValueError, match="points"):
        pf.stick_halfwidth_curves(points=1)


# --------------------------------------------------------------------------
# the shipped data
# --------------------------------------------------------------------------
def _shipped():
    from app.paper_figures import DATA_PATH

    return json.loads(DATA_PATH.read_text()), DATA_PATH


def test_shipped_data_names_its_command_and_is_small():
    data, path = _shipped()
    assert data["meta"]["command"] == pf.COMMAND
    assert path.stat().st_size < 300_000
    assert set(data["figures"]) == set(pf.FIGURES)
    readme = (path.parent / "README.md").read_text()
    assert pf.COMMAND in readme


@pytest.mark.parametrize("name", ["fig11", "fig12", "fig15", "fig16"])
def test_shipped_data_equals_a_fresh_computation(name):
    data, _ = _shipped()
    fresh = json.loads(json.dumps(pf.compute([name])["figures"][name]))

    def same(a, b, where):
        if isinstance(a, dict):
            assert a.keys() == b.keys(), where
            for k in a:
                same(a[k], b[k], f"{where}.{k}")
        elif isinstance(a, list) and a and isinstance(a[0], (dict, list, str)):
            assert len(a) == len(b), where
            for i, (x, y) in enumerate(zip(a, b)):
                same(x, y, f"{where}[{i}]")
        elif isinstance(a, (list, float, int)) and not isinstance(a, bool):
            np.testing.assert_allclose(_a(np.atleast_1d(a)), _a(np.atleast_1d(b)), rtol=1e-5, atol=1e-9,
                                       err_msg=where)
        else:
            assert a == b, where

    same(data["figures"][name], fresh, name)


def test_command_line_writes_a_subset(tmp_path, capsys):
    out = tmp_path / "figs.json"
    assert pf.main(["--out", str(out), "--only", "fig12"]) == 0
    data = json.loads(out.read_text())
    assert list(data["figures"]) == ["fig12"]
    assert data["meta"]["command"] == f"python -m core.maps.paper_figures --out {out} --only fig12"
    assert "fig12: max |solver - paper|" in capsys.readouterr().out
    with pytest.raises(SystemExit) as stop:
        pf.main(["--out", str(out), "--only", "fig99"])
    assert stop.value.code == 2 and "figures must be among" in capsys.readouterr().err


# --------------------------------------------------------------------------
# the tab, rendered without a browser
# --------------------------------------------------------------------------
def test_tab_draws_every_figure_with_labelled_axes_and_no_active_wheel_zoom():
    from app import paper_figures as apf

    tab = apf.paper_figures_tab()
    blocks = [c for c in tab.objects if getattr(c, "name", "") in apf.FIGURES]
    assert [b.name for b in blocks] == list(apf.FIGURES)
    for block in blocks:
        pane = block.objects[1]
        assert pane.object is not None, block.name
        plot = hv.render(pane.object)
        for axis in (plot.xaxis[0], plot.yaxis[0]):
            assert axis.axis_label and "[" in axis.axis_label, (block.name, axis.axis_label)
        sizes = [len(next(iter(r.data_source.data.values()))) for r in plot.renderers]
        assert sizes and min(sizes) > 0, (block.name, sizes)
        labels = [item.label.value for item in plot.legend[0].items]
        assert any(lab.startswith("solver") for lab in labels), (block.name, labels)
        assert any(lab.startswith(("paper's", "exact")) for lab in labels), (block.name, labels)
        assert plot.toolbar.active_scroll is None, block.name
        text = block.objects[0].object.lower()
        assert "largest difference" in text or "off by up to" in text, text


def test_recompute_button_redraws_with_fresh_data():
    from app import paper_figures as apf

    tab = apf.paper_figures_tab()
    block = next(c for c in tab.objects if getattr(c, "name", "") == "fig15")
    pane, controls = block.objects[1], block.objects[2]
    button, status = controls.objects[0], controls.objects[2]
    before = pane.object
    button.clicks += 1
    deadline = time.monotonic() + 60
    while "recomputed" not in status.object and "failed" not in status.object and time.monotonic() < deadline:
        time.sleep(0.05)
    assert "recomputed now" in status.object, status.object
    assert pane.object is not before and not button.disabled


# --------------------------------------------------------------------------
# the tab, served and drawn by Chromium
# --------------------------------------------------------------------------
@pytest.mark.browser
def test_served_tab_draws_in_chromium_without_console_errors(fresh_thread, paper_figures_url):
    """The tab alone, served beside the app by the suite's shared server (tests/conftest.py)."""
    fresh_thread(_draw_in_chromium, paper_figures_url)


def _draw_in_chromium(url):
    from app.serving import chromium, wait_until

    with chromium() as browser:
        page = browser.new_page(viewport={"width": 1280, "height": 720})
        errors, failed = [], []
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.on("requestfailed", lambda r: failed.append(r.url))
        page.goto(url, timeout=120_000)
        count = """() => { const d = window.Bokeh && Bokeh.documents[0]; if (!d) return -1;
            return [...d.all_models].filter(m => m.type === 'Figure' || m.type === 'Plot')
              .filter(p => p.renderers.some(r => r.data_source && r.data_source.get_length() > 0)).length; }"""
        wait_until(lambda: page.evaluate(count) == len(pf.FIGURES), 120, message="every figure drawn")
        page.get_by_role("button", name="Recompute Fig 15 with the solver").click()
        wait_until(lambda: page.get_by_text("recomputed now").count() > 0, 60, message="recompute status")
        assert not errors, errors
        assert not failed, failed
