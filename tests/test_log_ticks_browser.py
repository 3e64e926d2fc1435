"""The log axes' ticks (the increments per period: the cylinder's and the point contacts'): labelled whatever the
span. Bokeh's LogTicker ticks an axis of less than two decades linearly, and with the three ticks a narrow figure
asks for it labelled only 0.05 and 0.1 of the sphere's increments from 0.002 to 0.1. The tick code runs in
Chromium here (no server: the JavaScript of app.plots alone); the figures' log axes are checked to carry it."""

from __future__ import annotations

import math

import holoviews as hv
import pytest

from app import plots, point_view  # noqa: F401 - point_view registers the point contacts' figures

_RUN = """([code, label, cases]) => {
  const ticks = new Function("cb_data", "fewest", "most", code);
  const fmt = new Function("tick", label);
  return cases.map(([lo, hi]) => ticks({start: lo, end: hi}, 3, 6)).map((t) => [t, t.map((v) => fmt(v))]);
}"""

CASES = [(0.0017, 0.11), (0.04, 0.12), (1e-12, 1.0), (0.05, 0.056), (2e-6, 3e-4), (0.5, 40.0), (0.09, 0.11)]


@pytest.mark.browser
def test_a_log_axis_has_at_least_three_labels_over_any_span(browser):
    page = browser.new_page()
    try:
        out = page.evaluate(_RUN, [plots.LOG_TICKS_JS, plots.LOG_LABEL_JS, CASES])
    finally:
        page.close()
    for (lo, hi), (ticks, labels) in zip(CASES, out):
        assert 3 <= len(ticks) <= 6 or (len(ticks) >= 2 and hi / lo < 1.25), (lo, hi, ticks)
        assert all(lo <= t <= hi for t in ticks) and ticks == sorted(set(ticks)), (lo, hi, ticks)
        assert len(set(labels)) == len(labels), (lo, hi, labels)
        # every label reads back as its tick (no "10^-1" for 0.2, no 0.30000000000000004)
        assert all(math.isclose(float(s), t, rel_tol=1e-9) and len(s) <= 8 for s, t in zip(labels, ticks)), labels
        if hi / lo > 10:  # spread over the axis: a label in its lower half (in log), not only at the top
            assert min(ticks) <= math.sqrt(lo * hi), (lo, hi, ticks)
    (sphere, _), *_ = out
    assert sphere[0] < 0.01, sphere  # the sphere's increments from 0.0017 to 0.11: 0.003 (or 0.002) is labelled


@pytest.mark.parametrize("name", ["increments", "point_increments"])
def test_the_increments_figures_log_axis_uses_the_log_ticks(name):
    from bokeh.models import CustomJSTicker, CustomJSTickFormatter

    units = plots.make_units("normalised", None, "plane")
    fig = hv.render(plots.figure(name, plots.Inputs(0.3, 0.5, units)))
    (axis,) = fig.yaxis
    assert isinstance(axis.ticker, CustomJSTicker) and axis.ticker.major_code == plots.LOG_TICKS_JS
    assert isinstance(axis.formatter, CustomJSTickFormatter) and axis.formatter.code == plots.LOG_LABEL_JS
    assert not any(isinstance(a.ticker, CustomJSTicker) for a in fig.xaxis)  # a linear axis keeps its own
