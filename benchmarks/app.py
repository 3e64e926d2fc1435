"""Time the served explorer in a real browser: first load, analytical slider latency, numerical re-solve.

Usage: python benchmarks/app.py [--repeats 15] [--figures live|dynamicmap|both]

How it measures (headless Chromium via Playwright, server = ``panel serve
app/main.py --liveness`` on loopback, both on this machine):

* first load: from ``page.goto`` to the regime badge showing the solver's
  verdict and all six figures drawn (canvas present). The first session after
  the server starts is reported apart (it pays for importing and compiling).
* analytical latency: in the page, set the ft slider's ``value`` (what a drag
  does, no release) on the Bokeh model, then poll every millisecond until the
  traction figure's data sources are replaced by the server's update (the
  closure curve follows ft); ``performance.now()`` before and after. This is
  the full round trip: browser -> server callback -> layer data -> Bokeh patch
  -> browser. Drawing happens on the next animation frame (<= 16 ms more).
* numerical re-solve: set ``value`` and ``value_throttled`` (a release) to an
  ft never solved before (no cache hit), and wait the same way for the
  displacement figure's data: solve + render + round trip. The solver's own
  time for the same run (``CycleResult.runtime``) is printed beside it.
* player step: set the cycle player's step and wait the same way for the
  traction figure's data (pressure, zones, state map and displacement follow).

* server CPU per session: the ``panel serve`` process's CPU time (all its
  threads, ``/proc``) over the three later first loads, divided by three.

``--figures`` picks how the figures follow the inputs: ``live`` (the
explorer's :class:`app.live.LiveFigure`: rendered once, then only the changed
layers' data written into their sources), ``dynamicmap`` (the idiomatic path:
one ``hv.DynamicMap`` per figure fed by ``pn.bind``, re-rendered by
HoloViews, ``SHAKEDOWN_FIGURES=dynamicmap``), or ``both``, one after the other.

Targets (issue 4): first load < 3 s, analytical < 100 ms, re-solve < 300 ms.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import core  # noqa: E402
from app.serving import chromium, served_app  # noqa: E402
from app.state import ExplorerState  # noqa: E402

BADGE = "[data-regime='shakedown'], [data-regime='ratcheting']"
FT_TITLE = "ft = Ft/(μ Fn)"

PLAYER = "player"  # in place of a slider title: the cycle player

# set the ft slider (or the player), then wait until a figure's data sources are replaced; returns elapsed ms
_ROUND_TRIP = """
async ([title, figTitle, value, release]) => {
  const models = () => { const out = []; for (const d of Bokeh.documents) for (const m of d.all_models) out.push(m); return out; };
  const all = models();
  const slider = title === 'player' ? all.find((m) => m.title === 'Step in the period' && 'value_throttled' in m)
    : all.find((m) => m.title === title && typeof m.value === 'number' && 'value_throttled' in m);
  const fig = all.find((m) => m.title != null && m.title.text === figTitle);
  const sources = () => fig.renderers.map((r) => r.data_source).filter((s) => s != null);
  const before = sources().map((s) => s.data);
  const t0 = performance.now();
  slider.value = value;
  if (release) slider.value_throttled = value;
  while (performance.now() - t0 < 10000) {
    const now = sources().map((s) => s.data);
    if (now.length !== before.length || now.some((d, i) => d !== before[i])) return performance.now() - t0;
    await new Promise((r) => setTimeout(r, 1));
  }
  return NaN;
}
"""


def _load(browser, url) -> float:
    page = browser.new_page(viewport={"width": 1600, "height": 1000})
    t0 = time.perf_counter()
    page.goto(url, timeout=180_000)
    page.locator(BADGE).first.wait_for(timeout=120_000)
    page.locator(".bk-Canvas, canvas").nth(5).wait_for(timeout=60_000)
    elapsed = time.perf_counter() - t0
    page.close()
    return elapsed


def _stats(values) -> str:
    v = sorted(values)
    p90 = v[min(len(v) - 1, int(round(0.9 * (len(v) - 1))))]
    return f"median {statistics.median(v):7.1f} ms, p90 {p90:7.1f} ms, min {v[0]:6.1f} ms  (n = {len(v)})"


def measure(n: int, figures: str = "live") -> dict:
    """Serve the explorer with ``figures`` (live or dynamicmap) and time it in Chromium; returns the figures."""
    from benchmarks.loadtest import _cpu_s

    out: dict = {"figures": figures}
    info: dict = {}
    t_start = time.perf_counter()
    with served_app(env={"SHAKEDOWN_FIGURES": figures}, info=info) as url, chromium() as browser:
        out["ready"] = time.perf_counter() - t_start
        out["cold"] = _load(browser, url)
        c0 = _cpu_s(info["pid"])
        out["warm"] = [_load(browser, url) for _ in range(3)]
        out["cpu_per_session"] = (_cpu_s(info["pid"]) - c0) / 3
        page = browser.new_page(viewport={"width": 1600, "height": 1000})
        page.goto(url + "?ft=0.3&w=0.5", timeout=180_000)
        page.locator(BADGE).first.wait_for(timeout=60_000)
        page.locator(".bk-Canvas, canvas").nth(5).wait_for(timeout=60_000)
        out["analytical"] = [page.evaluate(_ROUND_TRIP, [FT_TITLE, "Traction: numerical vs closure",
                                                         0.2 + 0.01 * (i % 20), False]) for i in range(n)]
        out["fts"] = [0.2013 + 0.0107 * i for i in range(n)]  # never solved before (a fresh server): no cache hits
        out["resolve"] = [page.evaluate(_ROUND_TRIP, [FT_TITLE, "Displacement of the cylinder", ft, True])
                          for ft in out["fts"]]
        out["steps"] = [page.evaluate(_ROUND_TRIP, [PLAYER, "Traction: numerical vs closure", i % 40, False])
                        for i in range(1, n + 1)]
        out["models"] = page.evaluate("() => Bokeh.documents[0].all_models.size")
        page.close()
    return out


def report(r: dict) -> str:
    state = ExplorerState()
    c = state.contact()
    solver = [core.simulate_contact(c.replace(ft=ft), **state.solver_options()).runtime * 1e3 for ft in r["fts"]]
    return "\n".join([
        f"figures: {r['figures']}",
        f"server ready (/liveness answers)          : {r['ready']:6.2f} s",
        f"first load, first session after start     : {r['cold']:6.2f} s",
        f"first load, later sessions (median of 3)  : {statistics.median(r['warm']):6.2f} s   target < 3 s",
        f"server CPU per session (3 later loads)    : {r['cpu_per_session']:6.2f} s",
        f"analytical slider -> plot data            : {_stats(r['analytical'])}   target < 100 ms",
        f"numerical re-solve -> plot data (default) : {_stats(r['resolve'])}   target < 300 ms",
        f"  of which the solver alone (same runs)   : {_stats(solver)}",
        f"  default run: {state.resolution} elements per a, {state.periods} periods, kernel {state.kernel}",
        f"player step -> traction data              : {_stats(r['steps'])}   (the player steps every 150 ms)",
        f"Bokeh models in one session's document    : {r['models']}",
    ])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--figures", choices=["live", "dynamicmap", "both"], default="live")
    args = ap.parse_args(argv)
    print(__doc__.split("Targets")[0].strip().split("\n\n", 1)[1])
    for figures in (["live", "dynamicmap"] if args.figures == "both" else [args.figures]):
        print()
        print(report(measure(args.repeats, figures)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
