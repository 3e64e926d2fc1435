"""The first screen follows the loading (issue 30, item 3) and the regime map draws each history's lines (item 5):
the Python objects of the explorer, without a browser (tests/test_fretting_layout_browser.py checks the page)."""

import math

import numpy as np
import pytest

import core
from app import plots, regime_map
from app.bodies import BODIES
from app.explorer import Explorer
from app.figures import KEY_FIGURES, ORDER, key_figures

LOADINGS = ("rocking", "normal", "tangential")


@pytest.mark.parametrize("body", BODIES)
def test_the_loop_is_beside_the_displacement_under_an_oscillating_load(body):
    for loading in LOADINGS:
        names = key_figures(body, loading)
        assert len(names) == 3 and set(names) <= set(plots.FIGURES), (body, loading)
        displacement = next(i for i, n in enumerate(names) if "displacement" in n)
        if loading == "rocking":
            assert "loop" not in names
        else:
            assert names.index("loop") == displacement + 1, (body, loading, names)  # right of it
    assert key_figures(body) == key_figures(body, "rocking")


def test_every_figure_has_one_place_in_the_order_and_the_table_names_figures():
    assert sorted(ORDER) == sorted(plots.FIGURES) and len(set(ORDER)) == len(ORDER)
    for by_loading in KEY_FIGURES.values():
        assert set(by_loading) == set(LOADINGS)
    with pytest.raises(ValueError, match="loading"):
        key_figures("cylinder", "sliding")


def test_the_loading_moves_the_loop_between_the_grids_keeping_its_place_and_cell(scroll_through):
    ex = Explorer()
    ex.main_area()
    key, below = ex._key_grid, ex._grid
    names = lambda grid: [p.css_classes[0].removeprefix("place-") for p in grid.objects]  # noqa: E731
    assert names(key) == list(key_figures("cylinder")) and names(below)[0] == "loop"
    ex.state.param.update(loading="tangential", periods=3)
    assert ex.result.regime == "cyclic slip"
    assert names(key) == ["traction", "displacement", "loop"] and names(below)[0] == "pressure"
    loop_place = ex._places["loop"]
    assert loop_place in key.objects and ex._cells["loop"] in loop_place.objects  # drawn with the first screen
    assert not ex._captions["loop"].visible  # its caption is in the list under the first screen
    assert "Fretting loop" in ex._key_captions_html("cylinder", "tangential")
    assert loop_place.styles["min-height"] == f"{plots.KEY_HEIGHT}px"
    scroll_through(ex)
    assert ex._captions["pressure"].visible
    first, last = plots.layers("loop", ex._inputs())
    assert len(first[0]) > 2 and len(last[0]) > 2
    ex.state.loading = "rocking"
    assert names(key) == list(key_figures("cylinder")) and ex._places["loop"] is loop_place
    assert loop_place in below.objects and ex._captions["loop"].visible and not ex._captions["pressure"].visible


def test_the_loop_draws_a_point_contacts_run_in_its_units():
    r = core.simulate_cycles(0.0, 0.0, periods=2, body="sphere", history="tangential", amplitude=0.4, dx=1 / 5)
    units = plots.make_units("normalised", None, "strip", None, point=True)
    first, last = plots.loop_curves(r, units)
    loop = r.fretting_loop(-1)
    np.testing.assert_allclose(last[1], loop.Q)
    assert plots.specs("loop", units)[0].kdims[0].label == "u − k·Q [μ Fn/(E* a)]"
    # the shear keeps the area: the drawn last loop's work is the loop's
    work = float(np.sum(0.5 * (last[1][1:] + last[1][:-1]) * np.diff(last[0])))
    assert work == pytest.approx(loop.work, rel=1e-9, abs=1e-12)


def _drawn(lines) -> dict:
    """Which of the map's history lines have data, by name."""
    gross, contours, eq35, sphere, eq36, melan, levels, regions = lines
    return {"gross": len(gross[0]) > 0, "contours": len(contours) > 0, "eq35": len(eq35[0]) > 0,
            "sphere": len(sphere[0]) > 0, "eq36": len(eq36[0]) > 0, "melan": len(melan[0]) > 0,
            "levels": len(levels[0]) > 0, "regions": sorted(regions[2])}


def test_the_map_draws_the_lines_of_each_history():
    rocking = _drawn(regime_map.map_lines(("rocking", 0.0, 0.0, "triangle")))
    assert rocking == {"gross": False, "contours": True, "eq35": True, "sphere": True, "eq36": True,
                       "melan": False, "levels": True, "regions": ["ratcheting", "shakedown"]}
    tangential = regime_map.map_lines(("tangential", 0.4, 0.0, "triangle"))
    assert _drawn(tangential) == {"gross": True, "contours": False, "eq35": False, "sphere": False,
                                  "eq36": False, "melan": False, "levels": False,
                                  "regions": ["cyclic slip", "gross sliding"]}
    ft, A = tangential[0]
    np.testing.assert_allclose(ft + A, 1.0)  # |Q| = mu P
    normal = regime_map.map_lines(("normal", 0.3, math.pi / 2, "triangle"), core.Cylinder())
    assert _drawn(normal) == {"gross": True, "contours": False, "eq35": False, "sphere": False, "eq36": False,
                              "melan": True, "levels": False, "regions": ["ratcheting", "shakedown"]}
    np.testing.assert_allclose(normal[0][0], 0.7)  # gross sliding at the lowest force: ft = 1 - A
    ft_lim, w = normal[5]
    np.testing.assert_allclose(ft_lim, core.pressure.melan.ft_limit_oscillating(w, core.Cylinder(), 0.3, math.pi / 2,
                                                                       dx=1 / 500, samples=200))
    assert np.all(ft_lim <= 0.7 + 1e-4)
    # without a line body (a point contact's run) no Melan curve: not another body's under "this body"
    assert _drawn(regime_map.map_lines(("normal", 0.3, math.pi / 2, "triangle")))["melan"] is False


def test_the_map_reads_the_history_of_the_run():
    u = plots.make_units("normalised", None, "plane")
    for kwargs, name in ((dict(), "rocking"), (dict(history="tangential", amplitude=0.4), "tangential"),
                         (dict(history="normal", amplitude=0.2, phase=0.5), "normal"),
                         (dict(history="normal", amplitude=0.0), "rocking")):
        r = core.simulate_cycles(0.3, 0.3, periods=1, dx=0.05, **kwargs)
        assert regime_map.map_history(r)[0] == name, kwargs
        data = plots.layers("map", plots.Inputs(0.3, 0.3, u, r))
        assert len(data) == len(plots.specs("map", u))
        eq35 = data[[getattr(s, "label", None) for s in plots.specs("map", u)].index("eq 35 (exact)")]
        assert (len(eq35[0]) > 0) == (name == "rocking"), kwargs
    assert regime_map.map_history(None)[0] == "rocking"


def test_the_map_draws_a_sweep_only_beside_a_run_of_its_loading():
    """The shipped map (constant loads) is not drawn beside a run under the oscillating normal force: its regimes
    are not that loading's (they read shakedown beyond gross sliding, ft > 1 - A)."""
    u = plots.make_units("normalised", None, "plane")
    shipped = core.load_default_map()
    rocking = core.simulate_cycles(0.3, 0.3, periods=1, dx=0.05)
    normal = core.simulate_cycles(0.3, 0.3, periods=1, dx=0.05, history="normal", amplitude=0.2, phase=0.5)

    def runs(result, table):
        return sum(len(layer.data[0]) for layer in plots.layers("map", plots.Inputs(0.3, 0.3, u, result, None,
                                                                                      table))[:4])

    assert runs(rocking, shipped) == len(shipped) > 0
    assert runs(normal, shipped) == 0
    swept = core.sweep([0.2, 0.4], [0.3], history="normal", amplitude=0.2, phase=0.5, periods=1, dx=0.05)
    assert runs(normal, swept) == 2
    other = core.simulate_cycles(0.3, 0.3, periods=1, dx=0.05, history="normal", amplitude=0.3, phase=0.5)
    assert runs(other, swept) == 0  # another amplitude
