"""Fast tests of the explorer without a browser: state, URL parsing, cache, stale runs, figures."""

import io
import math
import re

import holoviews as hv
import numpy as np
import pandas as pd
import param
import pytest
from bokeh.model import Model

import core
from app import plots, point_view, regime_map
from app.compare import MAX_PINS
from app.figures import key_figures
from app.explorer import Explorer
from app.live import LiveFigure
from app.runs import Generation, ResultCache, result_nbytes
from app.state import BODIES, PRESETS, URL_PARAMETERS, ExplorerState, parse_query


# ---- the state class -------------------------------------------------------
@pytest.mark.parametrize("name", URL_PARAMETERS)
def test_every_parameter_is_documented_with_units_and_bounds(name):
    p = ExplorerState.param[name]
    assert p.doc and p.label, name
    if isinstance(p, param.Number):
        assert p.bounds is not None and None not in p.bounds, name
        assert p.softbounds is not None and p.step, name
        assert "[" in p.doc and "]" in p.doc, f"{name}: doc should state the unit in brackets"
    if isinstance(p, param.Selector):
        assert len(p.objects) >= 2


def test_default_state_is_the_paper_simulation():
    c = ExplorerState().contact()
    ref = core.PAPER_SIMULATION
    for field in ("a", "p0", "E_star", "P", "mu"):
        assert getattr(c, field) == pytest.approx(getattr(ref, field), rel=1e-12), field


@pytest.mark.parametrize("name", PRESETS)
def test_presets_give_valid_contacts(name):
    s = ExplorerState()
    s.apply_preset(name)
    c = s.contact()
    # every preset is a contact of the paper: uncoupled (beta = 0), a long strip, loads in range
    assert c.warnings == (), c.warnings
    assert abs(c.beta) < 1e-4 and c.L > 10 * c.a
    assert 0 <= c.ft < 1 and 0 <= c.w < 1
    assert math.isinf(c.E1) == s.rigid


def test_preset_values():
    s = ExplorerState()
    s.apply_preset("Fig 7: ft = 0.58, w = 0.77")
    assert (s.ft, s.w, s.kernel) == (0.58, 0.77, "strip")
    s.apply_preset("Paper experiment (Table 1)")
    c = s.contact()
    assert not s.rigid and s.E1 == pytest.approx(206e3)
    assert 2 * c.a * 1e3 == pytest.approx(4.13, abs=0.01)  # Table 1: 2a = 4.2 mm measured, 4.13 Hertz
    with pytest.raises(ValueError, match="preset"):
        s.apply_preset("nope")


def test_invalid_geometry_raises_naming_the_field():
    s = ExplorerState(L=1.0)  # 1 mm: shorter than the contact width
    with pytest.raises(ValueError, match="L must exceed"):
        s.contact()


# ---- URL parsing -----------------------------------------------------------
def test_parse_query_accepts_what_the_url_sync_writes():
    s = ExplorerState(ft=0.42, w=0.33, periods=12, kernel="plane", rigid=False, units="physical")
    query = "&".join(f"{k}={str(v).lower() if isinstance(v, bool) else v}" for k, v in s.values().items())
    updates, errors, ignored = parse_query("?" + query)
    assert errors == [] and ignored == []
    assert updates == s.values()


@pytest.mark.parametrize("query, name", [
    ("ft=abc", "ft"), ("ft=nan", "ft"), ("ft=inf", "ft"), ("ft=1", "ft"), ("ft=-0.1", "ft"),
    ("w=1.5", "w"), ("R=0", "R"), ("R=-3", "R"), ("E2=0", "E2"), ("nu2=0.6", "nu2"),
    ("periods=10.5", "periods"), ("periods=100000", "periods"), ("resolution=1e9", "resolution"),
    ("kernel=cubic", "kernel"), ("rigid=maybe", "rigid"), ("mu=" + "9" * 500, "mu"),
    ("ft=0.2&ft=0.3", "ft"), ("units=<script>", "units"),
])
def test_parse_query_rejects_bad_values_naming_them(query, name):
    updates, errors, _ = parse_query(query)
    assert name not in updates
    assert len(errors) == 1 and errors[0].startswith(name), errors


def test_parse_query_keeps_the_good_values_and_lists_unknown_names():
    updates, errors, ignored = parse_query({"ft": "0.2", "w": ["0.4", "0.4"], "bogus": "1", "mu": "x"})
    assert updates == {"ft": 0.2, "w": 0.4}
    assert ignored == ["bogus"] and len(errors) == 1


# ---- cache and stale runs ----------------------------------------------------
@pytest.fixture(scope="module")
def small_run():
    return core.simulate_cycles(0.3, 0.5, periods=2, dx=0.1)


def test_result_cache_is_lru_and_bounded(small_run):
    cache = ResultCache(max_items=2)
    cache.put("a", small_run)
    cache.put("b", small_run)
    assert cache.get("a") is small_run  # a is now the most recent
    cache.put("c", small_run)
    assert "b" not in cache and "a" in cache and "c" in cache
    tiny = ResultCache(max_items=10, max_bytes=int(2.5 * result_nbytes(small_run)))
    for k in "abcd":
        tiny.put(k, small_run)
    assert len(tiny) == 2 and tiny.nbytes <= tiny.max_bytes
    with pytest.raises(ValueError, match="max_items"):
        ResultCache(max_items=0)


def test_a_stale_run_never_overwrites_a_newer_one():
    ex = Explorer()
    first = ex.result
    gen = ex._generation
    old = gen.next()
    new = gen.next()
    stale = core.simulate_contact(ex.contact.replace(ft=0.7), **ex.state.solver_options())
    ex._finish(old, ex.contact, ex.state.solver_options(), stale)
    assert ex.result is first
    ex._finish(new, ex.contact, ex.state.solver_options(), stale)
    assert ex.result is stale
    g = Generation()
    t = g.next()
    assert g.is_current(t) and not g.is_current(t - 1)


# ---- the headless explorer -------------------------------------------------
def test_explorer_solves_and_flips_regime_across_the_limit():
    ex = Explorer(ExplorerState(w=0.5, periods=8))
    lim = float(core.ft_limit(0.5))
    ex.state.ft = round(lim - 0.1, 2)
    assert ex.result.regime == "shakedown" and ex.result.params["ft"] == ex.state.ft
    ex.state.ft = round(lim + 0.1, 2)
    assert ex.result.regime == "ratcheting"
    assert 'data-regime="ratcheting"' in ex._badge(ex.state.ft, ex.state.w, ex.result, "")


def test_explorer_reports_invalid_input_and_recovers():
    ex = Explorer()
    ex.state.L = 1.0
    assert ex.contact is None and "L must exceed" in ex.error
    assert 'data-regime="invalid"' in ex._badge(0.3, 0.5, ex.result, ex.error)
    ex.state.L = 500.0
    assert ex.error == "" and ex.contact is not None


def test_apply_query_sets_notices_and_valid_values():
    ex = Explorer()
    ex.apply_query("?ft=0.25&w=zzz&colour=red")
    assert ex.state.ft == 0.25 and ex.state.w == 0.5
    assert any(n.startswith("w must be") for n in ex.notices)
    assert any("colour" in n for n in ex.notices)


def test_player_moves_the_frame_within_a_period():
    ex = Explorer(ExplorerState(periods=3))
    r = ex.result
    assert ex.frame == r.xc.size - 1
    assert (ex.period_slider.value, ex.period_slider.end) == (3, 3)  # periods numbered from 1, as on the plots
    ex.period_slider.value = 2
    ex.step_slider.value = 0
    first_of_period_2 = int(np.flatnonzero(r.period == 1)[0])  # core numbers periods from 0
    assert ex.frame == first_of_period_2
    ex.step(-1)  # back across the period boundary
    assert ex.frame == first_of_period_2 - 1 and ex.period_slider.value == 1
    assert ex.step_slider.value == ex.step_slider.end
    ex.period_slider.value = 0  # the loading phase is reachable
    assert r.period[ex.frame] == -1
    assert "loading" in ex._readout(r, ex.frame, ex.plot_units)


def test_csv_download_has_the_run_and_its_parameters():
    ex = Explorer(ExplorerState(periods=3))
    text = ex._csv().getvalue()
    assert "# ft = 0.3" in text
    df = pd.read_csv(io.StringIO(text), comment="#")
    assert {"step", "period", "displacement_muP_Estar", "u_U_over_U0", "displacement_m"} <= set(df.columns)
    ex.csv_table.value = "final"
    assert ex.csv_download.filename == "shakedown_final_ft0.30_w0.50_mu0.58_3p.csv"  # names carry the inputs
    assert ex.json_download.filename == "shakedown_run_ft0.30_w0.50_mu0.58_3p.json"
    final = pd.read_csv(ex._csv(), comment="#")
    assert "traction_mu_p0" in final.columns
    np.testing.assert_allclose(final["closure_traction_mu_p0"], core.shakedown_traction(final["x_a"].to_numpy(), 0.3, 0.5),
                               rtol=1e-8, atol=1e-12, err_msg="the closure column is the paper's eqs 22-30")


# ---- figures ----------------------------------------------------------------
def _layers(overlay):
    return [type(e).__name__ for e in overlay]


def _run_inputs(ex, result=None, frame=None, ft=0.3, w=0.5, table=None):
    u = plots.make_units("normalised", ex.contact, "strip", ex.result.u0)
    return plots.Inputs(ft, w, u, result, frame, table)


def test_figures_keep_their_structure_with_and_without_a_run():
    ex = Explorer(ExplorerState(periods=2))
    r = ex.result
    empty, run = _run_inputs(ex), _run_inputs(ex, r, 5, table=ex.map_table)
    for name in plots.FIGURES:
        assert _layers(plots.figure(name, empty)) == _layers(plots.figure(name, run)), name
        assert len(plots.layers(name, run)) == len(plots.specs(name, run.units)), name
    u = run.units
    assert len(plots.displacement_step(u, r, 3)[0]) == 1 and len(plots.displacement_step(u)[0]) == 0
    assert len(plots.pressure_step(u, r, 7)[0]) == 201 and len(plots.pressure_step(u)[0]) == 0
    # the numerical traction is drawn as stairs over the elements
    xs, qs = plots.traction_run(u, r, 5)[-1]
    assert xs.size == qs.size == 2 * (r.edges.size - 1) and xs[0] == r.edges[0] and xs[-1] == r.edges[-1]
    # above the limit the closure is empty (NaN), the rest still draws
    hv.render(plots.figure("traction", _run_inputs(ex, r, ft=0.9, w=0.9)), backend="bokeh")


def _glyph_props(glyph):
    """A glyph's properties, without the ids of the models they refer to."""
    return {k: re.sub(r"id='p\d+'", "", repr(v)) for k, v in glyph.properties_with_values().items()
            if not isinstance(v, Model)}


def test_live_figures_show_what_a_fresh_render_shows():
    """Updating a live figure in place (only the changed layers' data) gives the data and glyphs of a fresh
    HoloViews render of the same inputs, through runs, player steps, regimes and the map."""
    ex = Explorer(ExplorerState(periods=3))
    r1 = ex.result
    r2 = core.simulate_contact(ex.contact.replace(ft=0.6), **ex.state.solver_options())  # ratchets
    steps = [_run_inputs(ex), _run_inputs(ex, r1, None, table=ex.map_table),
             _run_inputs(ex, r2, 50, ft=0.35, w=0.6, table=ex.map_table), _run_inputs(ex, r2, 51, ft=0.35, w=0.6),
             _run_inputs(ex, r1, 3, ft=0.9, w=0.9)]
    live = {name: LiveFigure(plots.specs(name, steps[0].units), plots.layers(name, steps[0]), plots.group(name))
            for name in plots.FIGURES}
    renders = {}  # the fresh renders of steps[2], compared twice (a render: 0.3-1 s each, most of this test)
    for inputs in steps:
        _assert_live_is_fresh(live, inputs, renders if inputs is steps[2] else None)
    # a figure copied from the template rendered above, at other data: its own models, the data of a fresh render
    again = {name: LiveFigure(plots.specs(name, steps[2].units), plots.layers(name, steps[2]), plots.group(name))
             for name in plots.FIGURES}
    _assert_live_is_fresh(again, steps[2], renders)
    assert not {m.id for f in again.values() for m in f.figure.references()} & {
        m.id for f in live.values() for m in f.figure.references()}


def _assert_live_is_fresh(live, inputs, renders=None):
    """Each live figure, updated to ``inputs``, has the data and glyphs of a fresh render of them (``renders``:
    name -> fresh render of these inputs, filled and reused: a render is only read here)."""
    renders = {} if renders is None else renders
    for name, fig in live.items():
        assert not fig.update(plots.specs(name, inputs.units), plots.layers(name, inputs))
        if name not in renders:
            renders[name] = hv.renderer("bokeh").get_plot(plots.figure(name, inputs))
        fresh = renders[name]
        for i, (source, glyph, ref) in enumerate(zip(fig.sources(), fig.glyphs(), fresh.subplots.values())):
            a, b = source.data, ref.handles["source"].data
            assert a.keys() == b.keys(), (name, i)
            for col in a:
                assert repr(np.asarray(a[col], dtype=object)) == repr(np.asarray(b[col], dtype=object)), \
                    (name, i, col)
            assert _glyph_props(glyph) == _glyph_props(ref.handles["glyph"]), (name, i)
        # a legend entry is shown exactly for the layers that draw something
        for item in (item for legend in fig.figure.legend for item in legend.items):
            columns = item.renderers[0].data_source.data.values()
            assert item.visible == any(np.size(c) for c in columns), (name, item.label)


def test_live_figure_is_rebuilt_for_new_axis_labels_only():
    ex = Explorer()
    inputs = _run_inputs(ex, ex.result)
    fig = LiveFigure(plots.specs("traction", inputs.units), plots.layers("traction", inputs), "Traction")
    first = fig.figure
    assert not fig.update(plots.specs("traction", inputs.units), plots.layers("traction", inputs._replace(ft=0.2)))
    assert fig.figure is first
    physical = inputs._replace(units=plots.make_units("physical", ex.contact, "strip", ex.result.u0))
    assert fig.update(plots.specs("traction", physical.units), plots.layers("traction", physical))
    assert fig.figure is not first and fig.figure.xaxis[0].axis_label == "x [mm]"


def test_figures_are_drawn_when_the_browser_scrolls_near_them():
    """Issues 12 and 22: the served page is sent with its first screen's figures only; each other is drawn, and put
    in place of its sentinel, once the browser reports the sentinel near the view. The sphere's figures are not in
    a cylinder's page."""
    from app.live import WhenShown

    ex = Explorer()
    ex.main_area()
    key, grid = ex._key_grid, ex._grid  # the first screen's figures (drawn with the page), the others
    assert sorted(ex._live) == sorted(key_figures("cylinder")) and len(key.objects) == 3
    assert not any(isinstance(o.objects[0], WhenShown) for o in key.objects)
    assert all(isinstance(o.objects[0], WhenShown) for o in grid.objects)
    assert len(key.objects) + len(grid.objects) == len(ex._figures_of("cylinder")) < len(plots.FIGURES)
    assert sorted(Explorer._GRID) == sorted(plots.FIGURES)  # every figure has one place
    # each figure has a place in its grid (issue 31: drawing a figure replaces the sentinel in its place, not the
    # grid's children, so the page keeps its height and the browser its scroll position)
    places = dict(zip(ex._grid_names(False), grid.objects))
    cell = key.objects[0].objects[0]
    assert ex._panes["pressure"] in cell.objects and ex._panes["pressure"].object is ex._live["pressure"].figure
    ex.sentinels["states"].shown = True
    assert "states" in ex._live and "states" in [n for n in ex._grid_names(False)]
    assert list(grid.objects) == list(places.values()), "the grid keeps its places"
    assert ex._cells["states"] in places["states"].objects, "drawn in its place"
    assert isinstance(places["sketch"].objects[0], WhenShown), "the others keep waiting"
    ex.state.body = "sphere"  # the point contact's first screen is drawn at once, the other places wait
    assert len(key.objects) + len(grid.objects) == len(ex._figures_of("sphere"))
    assert set(key_figures("sphere")) <= set(ex._live) and "point_pressure" not in ex._live
    ex.sentinels["point_pressure"].shown = True
    assert "point_pressure" in ex._live
    ex.state.body = "cylinder"
    assert key.objects[0].objects[0] is cell, "a drawn figure keeps its cell"


def test_explorer_pushes_only_what_changed(scroll_through):
    """Moving ft replaces the closure and the map point, and nothing of the run."""
    ex = Explorer()
    ex.main_area()
    scroll_through(ex)
    before = {name: [s.data for s in fig.sources()] for name, fig in ex._live.items()}
    ex.ft_live = 0.25
    after = {name: [s.data for s in fig.sources()] for name, fig in ex._live.items()}
    changed = {name: [i for i, (a, b) in enumerate(zip(before[name], after[name])) if a is not b] for name in before}
    n_traction = len(before["traction"])
    assert not set(point_view.FIGURES) & set(changed)  # the sphere's figures are not drawn beside a cylinder
    assert changed == {"sketch": [], "pressure": [], "traction": [n_traction - 2 - MAX_PINS], "states": [],
                       "displacement": [], "loop": [], "increments": [], "map": [len(before["map"]) - 1]}


def test_a_new_run_pushes_only_the_layers_of_the_run(scroll_through):
    """A solver result replaces the run's layers; the analytical ones (pressure curves, closure, bounds ±μ p_min)
    and the map's static and numerical layers are not sent again (nor, by Bokeh, data equal to what is shown)."""
    ex = Explorer()
    ex.main_area()
    scroll_through(ex)
    before = {name: [s.data for s in fig.sources()] for name, fig in ex._live.items()}
    new = core.simulate_contact(ex.contact.replace(ft=0.31), **ex.state.solver_options())
    ex._finish(ex._generation.next(), ex.contact, ex.state.solver_options(), new)
    after = {name: [s.data for s in fig.sources()] for name, fig in ex._live.items()}
    kept = {name: [i for i, (a, b) in enumerate(zip(before[name], after[name])) if a is b] for name in before}
    assert {0, 1, 2, 3} <= set(kept["pressure"])  # the Hertz curves follow w, not the run
    assert {5, 6, 7} <= set(kept["traction"])  # ±μ p_min and the closure follow the sliders, not the run
    assert 8 not in kept["traction"]  # the numerical traction is new, and u(t): only the empty pinned layers stay
    assert kept["displacement"] == list(range(2, 2 + MAX_PINS))
    assert set(range(len(before["map"]) - 1)) <= set(kept["map"])  # all but the current point (its regime)


def test_a_unit_switch_shows_new_figures_with_new_labels():
    ex = Explorer()
    panes = ex.figures()
    old = {name: pane.object for name, pane in panes.items()}
    ex.state.units = "physical"
    for name in ("pressure", "traction", "states"):
        assert panes[name].object is not old[name] and panes[name].object.xaxis[0].axis_label == "x [mm]", name
    assert panes["map"].object is old["map"]  # the map has no units
    ex.ft_live = 0.2  # and the new figures update in place
    assert panes["traction"].object is ex._live["traction"].figure


def test_physical_units_scale_from_the_contact():
    c = ExplorerState().contact()
    u = plots.make_units("physical", c, "strip", 5.0)
    assert u.x == pytest.approx(c.a * 1e3) and u.x_label == "x [mm]"
    assert u.q == pytest.approx(c.mu * c.p0 / 1e6) and u.u == pytest.approx(c.displacement_unit * 1e6)
    n = plots.make_units("normalised", c, "strip", 5.0)
    assert n.u == pytest.approx(0.2) and n.u_label == "u = U / U0"
    assert plots.make_units("physical", None, "plane").system == "normalised"


def test_time_axis_puts_the_loading_before_zero():
    r = core.simulate_cycles(0.3, 0.5, periods=2, dx=0.1)
    t = plots.time_axis(r)
    assert t[r.period == -1].max() <= 0 and t[-1] == pytest.approx(2.0)
    assert math.isclose(t[np.flatnonzero(r.period == 0)[-1]], 1.0)


def test_the_template_builds():
    ex = Explorer()
    tmpl = ex.template()
    assert tmpl.title.startswith("Shakedown Explorer")
    assert len(ex.about()) >= 5


def test_the_shipped_map_shows_and_a_new_one_can_be_computed():
    ex = Explorer(ExplorerState(periods=4, kernel="plane"))
    assert len(ex.map_table) == 1600 and "shipped" in ex.map_label
    fts, ws = regime_map.grid_boundary(ex.map_table)
    assert np.abs(ws - core.w_limit(fts)).max() < 0.05  # the shipped numerical limit lies near eq 35
    ex.map_scheduler = "serial"
    ex.map_points.value = 3
    ex.compute_map()
    assert len(ex.map_table) == 9 and ex.map_label.startswith("computed 3×3, plane kernel")
    assert not ex.map_running and "9 runs" in ex.map_status
    hv.render(plots.figure("map", _run_inputs(ex, ex.result, table=ex.map_table)), backend="bokeh")


def test_map_uses_the_current_strip_options():
    ex = Explorer(ExplorerState(periods=2))
    opts = ex._map_options()
    assert opts["kernel"] == "strip" and opts["L_over_a"] == pytest.approx(ex.contact.L / ex.contact.a)
    assert opts["nu"] == core.strip_options(ex.contact)["nu"]
    ex.state.L = 1.0  # invalid geometry: the map falls back to plane strain
    assert ex.contact is None and ex._map_options()["kernel"] == "plane"



def test_two_sessions_share_no_colour_bar_ticker():
    """The state map's colour bar ticker was one Bokeh model in the cached layer options, shared by every
    session and emptied when the first expired (issue 11, defect 3): each render now makes its own."""
    a, b = Explorer(), Explorer()
    bars = []
    for ex in (a, b):
        ex.figures()
        bars.append([m for m in ex._live["states"].figure.references() if type(m).__name__ == "ColorBar"][0])
    assert bars[0].ticker is not bars[1].ticker
    for bar in bars:
        assert list(bar.ticker.ticks) == [0, 1, 2, 3]
        assert list(bar.major_label_overrides.values()) == list(core.STATE_NAMES)

# ---- issue 11: sessions share no model; one consistent state ----------------------------------------------
def test_two_sessions_share_no_bokeh_model():
    """Every model of a session's figures is its own: a model built once (e.g. a colour bar's ticker in cached
    options) is shared by all sessions and emptied when the first one is cleaned up."""
    a, b = Explorer(), Explorer()
    a.figures(), b.figures()
    ids = [{m.id for live in ex._live.values() for m in live.figure.references()} for ex in (a, b)]
    assert ids[0] and not ids[0] & ids[1]
    bar = [m for m in a._live["states"].figure.references() if type(m).__name__ == "ColorBar"][0]
    assert list(bar.ticker.ticks) == [0, 1, 2, 3]
    assert list(bar.major_label_overrides.values()) == list(core.STATE_NAMES)


def test_no_tool_takes_the_wheel():
    ex = Explorer()
    ex.figures()
    for name, live in ex._live.items():
        assert live.figure.toolbar.active_scroll is None, name
        assert any(type(t).__name__ == "WheelZoomTool" for t in live.figure.toolbar.tools), name


def test_badge_and_cards_never_mix_an_old_verdict_with_new_inputs():
    ex = Explorer(ExplorerState(periods=10))  # enough periods for a verdict (3 leave it undetermined)
    r = ex.result
    assert f'data-regime="{r.regime}"' in ex._badge(0.3, 0.5, r, "")  # the run's verdict
    # the slider moved, not yet released: no verdict, and no numerical card
    assert 'data-regime="pending"' in ex._badge(0.7, 0.5, r, "") and "RELEASE TO SOLVE" in ex._badge(0.7, 0.5, r, "")
    cards = ex._cards(0.7, 0.5, 0.58, ex.contact, r)
    assert "release the slider" in cards and "0.225" not in cards
    # a solve is on its way
    assert "SOLVING" in ex._badge(0.3, 0.5, r, "", pending=True)
    assert "solving…" in ex._cards(0.3, 0.5, 0.58, ex.contact, r, pending=True)
    # physical units: Ft in N, W in µm, c_sd in mm, creep in µm
    cards = ex._cards(0.3, 0.5, 0.58, ex.contact, r, units="physical")
    assert " N<" in cards and "µm" in cards and "creep per period" in cards and " mm" in cards


#: The properties of a Bokeh model whose change makes the browser lay out the whole page again (Bokeh's
#: LayoutDOMView.invalidate_layout: the view, then every parent up to the root, is measured and laid out anew).
_LAYOUT_PROPERTIES = ("visible", "css_classes", "width", "height", "min_width", "min_height", "max_width",
                      "max_height", "margin", "sizing_mode", "stylesheets")


def test_a_solve_changes_no_layout_property_of_the_page():
    """Issue 31 item 15: a solve's spinner and status line were shown and hidden by their models' ``visible`` (and
    the LoadingSpinner's value, which sets its CSS classes); each change made the browser recompute the layout of
    the whole page, six times a release (0.3 to 2.4 s each in a loaded headless Chromium): the 2 s beyond its solve
    that every point body paid. A solve on its way and its end now change texts only; the badge's spinner is a CSS
    animation that the browser starts after SPINNER_DELAY_MS."""
    from app.cards import SPINNER_DELAY_MS

    ex = Explorer(query="?body=sphere&periods=2")
    root = ex.main_area().get_root()

    def layout():
        return {m.id: tuple(repr(getattr(m, p)) for p in _LAYOUT_PROPERTIES if hasattr(m, p))
                for m in root.references()}

    before = layout()
    ex.param.update(pending=True)  # a release: the badge says SOLVING at once
    ex.param.update(solving=True)  # the server's delayed start, SPINNER_DELAY_MS later
    during = layout()
    badge = ex._badge(0.3, 0.5, ex.result, "", pending=True)
    ex.param.update(solving=False, pending=False)  # the run arrived
    assert during == before and layout() == before
    assert "solve-spinner" in badge and f"{SPINNER_DELAY_MS}ms" in badge and "SOLVING" in badge
    assert "solve-spinner" not in ex._badge(0.3, 0.5, ex.result, "")


def test_preset_box_follows_edits_and_notes_the_fig7_case():
    ex = Explorer()
    ex.preset.value = "Fig 7: ft = 0.58, w = 0.26"
    assert ex.state.ft == 0.58 and ex.preset.value == "Fig 7: ft = 0.58, w = 0.26"
    assert ex.preset_note.visible and "0.673" in ex.preset_note.object
    ex.state.ft = 0.3
    assert ex.preset.value == "(custom)" and not ex.preset_note.visible


def test_slider_noise_is_rounded_away():
    s = ExplorerState()
    s.ft = 0.44000000000000006
    assert s.ft == 0.44 and repr(s.ft) == "0.44"


# ---- issue 10: point contacts (sphere, ellipsoid) in the explorer --------------------------------------------
_SPHERE = "?body=sphere&ft=0.6&w=0.3&point_resolution=6&periods=3"  # a coarse, short run (about a second)


@pytest.fixture(scope="module")
def sphere_explorer():
    return Explorer(query=_SPHERE)


def test_the_body_is_a_url_parameter_checked_like_the_others():
    updates, errors, ignored = parse_query("?body=sphere&ft=0.6&w=0.3")
    assert updates == {"body": "sphere", "ft": 0.6, "w": 0.3} and errors == [] and ignored == []
    updates, errors, _ = parse_query("?body=ellipsoid&ratio=2.5&point_resolution=12")
    assert updates == {"body": "ellipsoid", "ratio": 2.5, "point_resolution": 12} and errors == []
    for query, name in (("?body=cube", "body"), ("?ratio=0.01", "ratio"), ("?ratio=25", "ratio"),
                        ("?point_resolution=3", "point_resolution"), ("?point_resolution=41", "point_resolution"),
                        ("?point_resolution=7.5", "point_resolution")):
        updates, errors, _ = parse_query(query)
        assert name not in updates and len(errors) == 1 and errors[0].startswith(name), (query, errors)
    assert ", ".join(BODIES) in parse_query("?body=cube")[1][0]  # the message lists the bodies (the registry's)


def test_a_point_body_makes_a_point_contact_with_its_own_grid():
    s = ExplorerState(body="sphere", ft=0.6, w=0.3)
    c = s.contact()
    assert isinstance(c, core.PointContact) and c.Rx == c.Ry == pytest.approx(s.R * 1e-3)
    assert c.ft == pytest.approx(0.6, abs=1e-12) and c.w == pytest.approx(0.3, abs=1e-12)
    assert c.Fn == s.Fn and c.mu == s.mu and c.E2 == pytest.approx(s.E2 * 1e6) and math.isinf(c.E1)
    assert s.solver_options() == {"periods": s.periods, "dx": 1 / s.point_resolution, "shape": s.schedule}
    s.param.update(body="ellipsoid", ratio=2.5)
    c = s.contact()
    assert c.Ry / c.Rx == pytest.approx(2.5) and c.body.ratio == pytest.approx(2.5) and c.b > c.a
    s.body = "cylinder"  # the cylinder keeps its own grid and kernel
    assert isinstance(s.contact(), core.Contact) and s.solver_options()["dx"] == 1 / s.resolution
    assert "kernel" in s.solver_options()


def test_the_paper_presets_bring_back_the_cylinder():
    s = ExplorerState(body="sphere")
    s.apply_preset("Fig 6: ft = 0.08, w = 0.26")
    assert s.body == "cylinder" and isinstance(s.contact(), core.Contact)


def test_a_sphere_link_shows_the_spheres_verdict_limit_and_cards(sphere_explorer):
    ex = sphere_explorer
    r = ex.result
    assert isinstance(r, core.PointContactResult) and r.body.name == "sphere" and r.dx == pytest.approx(1 / 6)
    assert r.params["ft"] == 0.6 and r.params["w"] == 0.3 and r.periods == 3
    badge = ex._badge(0.6, 0.3, r, "")
    assert f'data-regime="{r.regime}"' in badge
    # the sphere's exact limit, (1 - w)^2 (2 + w)/2 = 0.5635 < 0.6, predicts ratcheting (eq 35, 0.624, would not)
    assert "sphere&#x27;s exact limit" in badge and "predicts ratcheting" in badge
    cards = ex._cards(0.6, 0.3, ex.state.mu, ex.contact, r)
    assert "0.5635" in cards and "0.6238" in cards and "b (semi-axis along y)" in cards
    assert f"{r.increment_per_period[-1]:.3g}" in cards
    assert "release the slider" in ex._cards(0.5, 0.3, ex.state.mu, ex.contact, r)  # not this run's inputs


def test_point_figures_draw_point_runs_and_the_cylinders_figures_do_not(sphere_explorer):
    ex = sphere_explorer
    r = ex.result
    u = plots.make_units("normalised", None, "plane")
    run, empty = plots.Inputs(0.6, 0.3, u, r, 4), plots.Inputs(0.6, 0.3, u)
    for name in plots.FIGURES:  # the same layers with and without a run, of either kind
        assert _layers(plots.figure(name, empty)) == _layers(plots.figure(name, run)), name
    assert plots.layers("pressure", run) == plots.layers("pressure", empty)  # no sphere run on a cylinder figure
    assert [point_view.shown(n, "sphere") for n in ("pressure", "map", "point_pressure")] == [False, True, True]
    assert [point_view.shown(n, "cylinder") for n in ("pressure", "map", "point_pressure")] == [True, True, False]
    (p, bounds), edge = point_view.pressure_map(u, r, 4)
    ny, nx = r.y_edges.size - 1, r.x_edges.size - 1
    assert p.shape == (ny, nx) and bounds == (r.x_edges[0], r.y_edges[0], r.x_edges[-1], r.y_edges[-1])
    # the discrete normal solution on the grid (as CONTACT's) peaks within a per cent of Hertz's p0
    assert np.nanmax(p) <= 1.01 and np.nanmax(np.abs(np.flipud(p) - np.where(r.pressure(4) > 0, r.pressure(4), np.nan))) == 0
    assert 0.5 * (edge[0].max() + edge[0].min()) == pytest.approx(r.xc[4], abs=1e-9)  # the edge at the step's centre
    # traction and zones: the last stored full field at or before the step
    j = point_view.stored_step(r, 4)
    assert r.snapshot_steps[j] <= 4 < (r.snapshot_steps[j + 1] if j + 1 < r.snapshot_steps.size else 10**9)
    (q, _), _ = point_view.traction_map(u, r, 4)
    mag = np.hypot(*r.traction_snapshots[j])
    assert np.nanmax(np.flipud(q)) == pytest.approx(mag.max()) and np.nanmax(q) <= 1.0 + 1e-9
    (zones, _), _ = point_view.zone_map(u, r, 4)
    assert set(np.unique(zones)) <= {0, 1, 2, 3, 4} and (zones >= 2).sum() == (r.state_snapshots[j] > 0).sum()
    # the cut along y = 0: the numerical traction of the step itself, inside the Hertz bound
    *_, (xs, up), _, (_, qy), (ex_, qx) = point_view.cut_layers(u, r, 4)
    assert np.allclose(qx[::2], r.traction_cut[4, 0]) and np.allclose(qy[::2], r.traction_cut[4, 1])
    assert up.max() == pytest.approx(1.0, abs=1e-3)
    # displacement per period
    periods, inc = point_view.increment_layers(u, r)[0]
    assert list(periods) == [1, 2, 3] and np.allclose(inc, np.abs(r.increment_per_period))


def test_point_live_figures_show_what_a_fresh_render_shows(sphere_explorer):
    """In-place updates of the point-contact figures equal fresh renders, through player steps and runs."""
    ex = sphere_explorer
    r1 = ex.result
    r2 = core.simulate_cycles(0.2, 0.5, periods=2, dx=0.25, body="ellipsoid", ratio=2.0)
    u = plots.make_units("normalised", None, "plane")
    steps = [plots.Inputs(0.6, 0.3, u), plots.Inputs(0.6, 0.3, u, r1, None), plots.Inputs(0.6, 0.3, u, r1, 2),
             plots.Inputs(0.2, 0.5, u, r2, 7), plots.Inputs(0.2, 0.5, u)]
    names = list(point_view.FIGURES)
    live = {n: LiveFigure(plots.specs(n, u), plots.layers(n, steps[0]), plots.group(n)) for n in names}
    for inputs in steps:
        _assert_live_is_fresh(live, inputs)


def test_switching_bodies_solves_the_new_body_and_shows_its_figures():
    ex = Explorer(query="?ft=0.6&w=0.3&periods=2&point_resolution=5")
    ex.figures()
    assert isinstance(ex.result, core.CycleResult) and "eq 35 predicts shakedown" in ex._badge(0.6, 0.3, ex.result, "")
    ex.state.body = "sphere"
    assert isinstance(ex.result, core.PointContactResult) and ex.error == ""
    src = ex._live["point_pressure"].sources()[0]
    assert np.asarray(src.data["image"][0]).shape == (ex.result.y_edges.size - 1, ex.result.x_edges.size - 1)
    assert ex._live["traction"].sources()[-1].data["q"].size == 0  # the cylinder's traction figure is empty
    ex.state.units = "physical"  # physical units from the point contact: a in mm, displacements in µm
    assert ex.plot_units.x == pytest.approx(ex.contact.a * 1e3) and ex.plot_units.u_label == "U [µm]"
    ex.state.param.update(body="ellipsoid", ratio=2.0)
    assert ex.result.body.ratio == 2.0
    ex.state.body = "cylinder"
    assert isinstance(ex.result, core.CycleResult)


def test_point_runs_are_cached_and_downloaded(sphere_explorer):
    from app import runs

    ex = sphere_explorer
    r = ex.result
    keys = {runs.run_key(ExplorerState(body=b, ratio=2.0).contact(), {}) for b in ("sphere", "ellipsoid", "cylinder")}
    assert len(keys) == 3
    assert result_nbytes(r) >= r.traction_snapshots.nbytes
    ex.csv_table.value = "periods"
    text = ex._csv().read()
    rows = [line for line in text.splitlines() if not line.startswith("#")]
    assert rows[0].startswith("period,increment_muFn_Estar_a") and len(rows) == 1 + r.periods
    assert float(rows[-1].split(",")[1]) == pytest.approx(r.increment_per_period[-1], rel=1e-9)
    ex.csv_table.value = "steps"
    rows = [line for line in ex._csv().read().splitlines() if not line.startswith("#")]
    assert len(rows) == 1 + r.xc.size
    import json
    data = json.loads(ex._json().read())
    p = data["parameters"]
    assert p["body"] == "sphere" and p["regime"] == r.regime and len(data["periods"]["period"]) == r.periods


def test_fig14_and_the_map_show_both_bodies_exact_limits():
    from app import paper_figures as apf
    from core.maps import paper_figures as pf

    line = apf.shipped_data()["figures"]["fig14"]["line"]
    ft = np.array(line["ft"])
    np.testing.assert_allclose(line["w_sphere"], core.w_limit(ft, body="sphere"), atol=1e-6)
    np.testing.assert_allclose(pf.limit_lines(len(ft))["w_sphere"], line["w_sphere"], atol=1e-6)
    # the sphere's limit lies below the cylinder's (eq 35) at every amplitude
    inner = (ft > 0) & (ft < 1)
    assert np.all(np.array(line["w_sphere"])[inner] < np.array(line["w_eq35"])[inner])
    labels = [e.label for e in apf.figure("fig14", apf.shipped_data())]
    assert any(lab.startswith("sphere, ellipsoid") for lab in labels) and "exact limit eq 35" in labels
    curves = {e.label: e for e in regime_map.map_base() if isinstance(e, hv.Curve)}
    np.testing.assert_allclose(curves["sphere, ellipsoid (exact)"].dimension_values(1),
                               core.w_limit(curves["sphere, ellipsoid (exact)"].dimension_values(0), body="sphere"))


def test_the_map_draws_only_the_current_bodys_sweep(sphere_explorer):
    ex = sphere_explorer
    u = plots.make_units("normalised", None, "plane")
    n_runs = sum(len(layer.data[0]) for layer in regime_map.map_numerical(ex.map_table)[:3])
    assert n_runs == len(ex.map_table) > 0  # the shipped (cylinder) map
    sphere = plots.layers("map", plots.Inputs(0.6, 0.3, u, ex.result, None, ex.map_table))
    assert all(len(layer.data[0]) == 0 for layer in sphere[:3])  # not beside a sphere's run
    assert sphere[-1].data == ([0.6], [0.3])  # the current point is drawn, coloured by the sphere's regime
    assert sphere[-1].glyph["fill_color"] == plots.REGIME_COLORS[ex.result.regime]
    # a map computed for the sphere sweeps the sphere on its coarse grid
    assert ex._map_options() == {"periods": 3, "dx": 1 / 6, "shape": "triangle", "body": "sphere", "ratio": None}


def test_the_oscillating_normal_force_is_a_loading_option():
    """Issue 10, item 6: rocking under an oscillating normal force is among the loading options of the cylinder,
    kept in the URL, passed to the solver as core.loading.histories' 'normal' history, and flagged beside eq 35."""
    from app.state import URL_PARAMETERS, parse_query

    assert {"loading", "amplitude", "phase"} <= set(URL_PARAMETERS)
    values, errors, ignored = parse_query("loading=normal&amplitude=0.3&phase=90")
    assert values == {"loading": "normal", "amplitude": 0.3, "phase": 90.0} and not errors and not ignored
    assert "amplitude" in parse_query("amplitude=1.5")[1][0]  # out of [0, 1): rejected, named
    s = ExplorerState(ft=0.3, w=0.5, periods=3, resolution=20, loading="normal", amplitude=0.3, phase=90.0)
    opts = s.solver_options()
    assert opts["history"] == "normal" and opts["amplitude"] == 0.3 and opts["phase"] == pytest.approx(np.pi / 2)
    r = core.simulate_contact(s.contact(), **opts)
    assert r.params["history"] == "normal" and r.params["amplitude"] == 0.3
    rocking = core.simulate_contact(s.contact(), **ExplorerState(ft=0.3, w=0.5, periods=3, resolution=20)
                                    .solver_options())
    assert not np.allclose(r.increment_per_period, rocking.increment_per_period)  # the load history matters
    ex = Explorer(ExplorerState(ft=0.3, w=0.5, periods=3, resolution=20, loading="normal"))
    assert any("normal force oscillates" in m for m in ex._warnings(0.3, 0.5, ex.contact, r))
    assert not any("normal force oscillates" in m for m in ex._warnings(0.3, 0.5, ex.contact, rocking))
    # issue 28: every body takes every history, the point contacts too
    assert ExplorerState(body="sphere", loading="normal").solver_options()["history"] == "normal"


@pytest.mark.parametrize("body", ["cylinder", "sphere"])
def test_every_body_takes_the_tangential_history(body):
    """The explorer offers every history for every body: 'tangential' fixes the centre and oscillates Ft by the
    amplitude's share of what is left to full sliding; the run carries it."""

    s = ExplorerState(body=body, ft=0.4, w=0.3, periods=2, resolution=10, point_resolution=5, loading="tangential",
                      amplitude=0.5)
    opts = s.solver_options()
    assert opts["history"] == "tangential" and opts["amplitude"] == pytest.approx(0.3)
    r = s.contact().simulate(**opts)
    assert r.params["history"] == "tangential" and r.is_patch == (body == "sphere")
    np.testing.assert_allclose([r.Q.min(), r.Q.max()], [0.1, 0.7], atol=1e-12)
    np.testing.assert_array_equal(r.xc, 0.0)


def test_the_grid_error_of_a_shaken_down_run_is_not_relative_to_its_noise():
    """A run that shook down ends with an increment of the solver's noise (e.g. 6e-9): its grid error relative to
    it (the cone showed "±113 %") means nothing, so it is shown in the increment's unit only."""
    from types import SimpleNamespace

    from app.cards import grid_error_text

    est = SimpleNamespace(error=6.9e-9)
    assert grid_error_text(est, 6.1e-9, 1.0, "μFn/(E*a)") == "±113 % (±6.9e-09 μFn/(E*a))"
    assert grid_error_text(est, 6.1e-9, 1.0, "μFn/(E*a)", relative=False) == "±6.9e-09 μFn/(E*a)"
