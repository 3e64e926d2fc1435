"""Headless tests of the explorer's compare, engineer and slide parts (app/compare.py, app/engineer.py,
app/sketch.py): what the browser tests do not pin down number by number."""

from __future__ import annotations

import numpy as np
import pytest

import core
import io
import json

import pandas as pd

from app import compare, pinned, plots, sketch, slides
from app.state import BODIES
from app.explorer import Explorer


@pytest.fixture(scope="module")
def explorer(scroll_through):
    ex = Explorer(query="ft=0.3&w=0.5&periods=3&kernel=plane")
    ex.template()
    return scroll_through(ex)


def test_pins_overlay_the_runs_and_keep_at_most_four(explorer):
    ex = explorer
    ex.pins.clear()
    runs = []
    for w in (0.2, 0.3, 0.4, 0.5, 0.6):
        ex.state.w = w
        ex.solve_now()
        runs.append(ex.result)
        ok = ex.pins.pin()
        assert ok == (len(runs) <= compare.MAX_PINS), ex.pins.message
    assert "unpin one first" in ex.pins.message
    assert [p.result for p in ex.pinned] == runs[:4]
    # each pin is drawn on the displacement figure as its own run's curve (plane kernel: in μP/E*)
    sources = ex._live["displacement"].sources()
    pinned = sources[2:2 + compare.MAX_PINS]
    for src, r in zip(pinned, runs):
        np.testing.assert_array_equal(src.data["u"], r.displacement)
    # the traction figure shows each pin's last step as stairs
    t = ex._live["traction"].sources()[-compare.MAX_PINS]
    np.testing.assert_array_equal(t.data["q"], np.repeat(runs[0].traction[-1], 2))
    # unpinning the second moves the third up; clearing empties every pinned layer and hides its legend entry
    ex.pins.remove(1)
    assert [p.result for p in ex.pinned] == [runs[0], runs[2], runs[3]]
    ex.pins.clear()
    assert all(len(s.data["u"]) == 0 for s in ex._live["displacement"].sources()[2:2 + compare.MAX_PINS])
    legend = {item.label.value: item.visible for item in ex._live["increments"].figure.legend[0].items}
    assert not any(v for k, v in legend.items() if k.startswith("pin "))
    assert "No run pinned" in ex.pins.table.object


def test_a_pinned_layer_is_sent_once():
    """The live figure skips a layer whose data is the same object: a pinned run's curve is memoised."""
    r = core.simulate_cycles(0.3, 0.5, periods=2)
    pin = compare.Pin(r, None, dict(ft=0.3, w=0.5, mu=0.58))
    units = plots.make_units("normalised", None, "plane")
    assert pinned.layers("displacement", (pin,), units)[0] is pinned.layers("displacement", (pin,), units)[0]


def test_the_engineers_inputs_move_the_sliders(explorer):
    ex = explorer
    s, e = ex.state, ex.engineer
    s.param.update(ft=0.3, w=0.5)
    a = ex.geometry.a
    assert e.force.value == pytest.approx(0.3 * s.mu * s.Fn, rel=1e-6)
    assert e.amplitude.value == pytest.approx(0.5 * a * 1e6, rel=1e-4)
    e.force.value = 0.2 * s.mu * s.Fn
    assert s.ft == pytest.approx(0.2, abs=1e-6)
    e.angle.value = 0.4 * a / (s.R * 1e-3) * 1e3  # θ = W / R  [mrad]
    assert s.w == pytest.approx(0.4, abs=1e-5)
    e.amplitude.value = 10 * a * 1e6  # beyond the sliders' range: clipped, and the input shows what was applied
    assert s.w == s.param.w.softbounds[1] and e.amplitude.value == pytest.approx(s.w * a * 1e6, rel=1e-4)


def test_creep_after_n_cycles_in_the_cards(explorer):
    ex = explorer
    ex.state.param.update(ft=0.3, w=0.7, units="physical")
    ex.solve_now()
    ex.engineer.cycles = 2_500_000
    html = ex._cards(0.3, 0.7, ex.state.mu, ex.contact, ex.result, units="physical", cycles=ex.engineer.cycles)
    um = float(ex.result.increment_per_period[-1]) * ex.contact.displacement_unit * 1e6
    assert "creep after 2.5×10⁶ periods" in html and f"{um * 2.5e6 / 1e3:.3g} mm" in html
    ex.state.units = "normalised"


def test_the_csv_numbers_periods_as_the_player(explorer):
    ex = explorer
    ex.csv_table.value = "periods"
    rows = [line for line in ex._csv().read().splitlines() if not line.startswith("#")]
    assert rows[1].split(",")[0] == "1" and len(rows) == ex.result.periods + 1
    ex.csv_table.value = "steps"
    rows = [line.split(",") for line in ex._csv().read().splitlines() if not line.startswith("#")]
    col = rows[0].index("period")
    assert {int(r[col]) for r in rows[1:]} == set(range(0 if (ex.result.period < 0).any() else 1,
                                                         ex.result.periods + 1))


def test_the_sketch_rolls_with_the_centre():
    r = core.simulate_cycles(0.3, 0.5, periods=1)
    k = int(np.argmax(np.diff(r.xc) > 0)) + 1  # a step moving towards +x
    inputs = plots.Inputs(0.3, 0.5, plots.make_units("normalised", None, "plane"), r, k)
    ground, centre_range, pressure, circle, spoke, patch, arrow, trailing = sketch.layers(inputs)
    xc = float(r.xc[k])
    assert sketch.motion(r, k) == 1 and centre_range == [-0.5, 0.5]
    assert np.isclose((circle[0].max() + circle[0].min()) / 2, xc) and np.isclose(circle[1].min(), 0.0, atol=1e-3)
    assert trailing[0][0] == pytest.approx(xc - 1.0)  # rolling towards +x: the trailing edge is at xc − a
    assert arrow[0][1] > xc  # the arrow points the way it rolls


@pytest.fixture(scope="module", params=BODIES)
def body_explorer(request, scroll_through):
    """An explorer of each body the app offers (a body added to app.state.BODIES is tested too), drawn."""
    ex = Explorer(query=f"body={request.param}&ft=0.3&w=0.5&periods=2&point_resolution=4&kernel=plane")
    ex.template()
    return scroll_through(ex)


def test_pin_compare_and_downloads_work_for_every_body(body_explorer):
    """Pin two runs of the body, see them on its figures and in the table, download its CSV and JSON (written by
    core.api.export: the same text as core's own, periods numbered as the player)."""
    ex = body_explorer
    body = ex.state.body
    point = ex.state.point
    ex.pins.clear()
    first = ex.result
    assert ex.pins.pin(), ex.pins.message
    ex.state.w = 0.4
    ex.solve_now()
    assert ex.pins.pin(), ex.pins.message
    assert [p.result for p in ex.pinned] == [first, ex.result]
    table = ex.pins.table.object
    assert "pin 1" in table and "pin 2" in table and (body in table)
    # the pinned runs are drawn on the figures of their body: the displacement along Ft over time
    name = "point_displacement" if point else "displacement"
    live = ex._live[name]
    curves = [s.data for s in live.sources() if "u" in s.data and len(s.data["u"]) == first.xc.size]
    along = first.displacement @ np.array([1.0, 0.0]) if point else first.displacement
    assert any(np.allclose(d["u"], along) for d in curves), name
    increments = "point_increments" if point else "increments"
    assert any(len(s.data.get("du", ())) == first.periods for s in ex._live[increments].sources()[-compare.MAX_PINS:])
    # downloads: core's export of the run shown, for each table
    for table_name in ("steps", "periods", "final"):
        ex.csv_table.value = table_name
        text = ex._csv().getvalue()
        df = pd.read_csv(io.StringIO(text), comment="#")
        assert len(df) > 0 and f"# body = {body}" in text if point else len(df) > 0
        assert ex.csv_download.filename.startswith(f"shakedown_{table_name}")
        if table_name == "periods":
            assert list(df["period"]) == list(range(1, ex.result.periods + 1))  # as on the player
        if table_name == "final" and not point:
            assert "closure_traction_mu_p0" in df.columns  # core's column, not the app's
    data = json.loads(ex._json().getvalue())
    assert set(data) == {"parameters", "steps", "periods", "final"}
    assert data["parameters"]["regime"] == ex.result.regime
    ex.pins.clear()


def test_the_svg_chooser_offers_the_bodys_own_figures(body_explorer):
    ex = body_explorer
    offered = list(ex.svg_select.options)
    own = [plots.FIGURES[n]["opts"]["title"] for n in ex._figures_of(ex.state.body)]
    assert offered == own
    assert "The body at the player's step" in offered  # every body has its sketch
    assert ("Pressure and μ p_min" in offered) == (ex.state.kind == "line")
    assert set(offered) <= set(slides.figure_titles())
