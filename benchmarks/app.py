"""Time the served explorer in a real browser: first load, analytical slider latency, numerical re-solve.

Usage: python benchmarks/app.py [--repeats 15] [--figures live|dynamicmap|both]

How it measures (headless Chromium via Playwright, server = ``panel serve
app/main.py --liveness`` on loopback, both on this machine):

* first load: in a 1280x720 window, from ``page.goto`` to the regime badge
  showing the solver's verdict and the first figure in view drawn (the first
  screen holds three figures since issue 22; the others are drawn as the page
  is scrolled to them). The first session after the server
  starts is reported apart (it pays for importing and compiling).
* analytical latency: in the page, set the ft slider's ``value`` (what a drag
  does, no release) on the Bokeh model, then poll every millisecond until the
  traction figure's data sources are replaced by the server's update (the
  closure curve follows ft); ``performance.now()`` before and after. This is
  the full round trip: browser -> server callback -> layer data -> Bokeh patch
  -> browser. Beside this "polled" figure (the one kept since issue 4), two
  exact ones: when the browser wrote the data into the figure's source (its
  change signal: "data set") and when the figure was next painted ("figure
  painted"). The polling loop's timer runs after any animation frame that is
  due, so "polled" is either the data set plus a few ms, or that plus the
  paint of every figure that changed: bimodal, its median over 7 moves flips
  between the two.
* numerical re-solve: set ``value`` and ``value_throttled`` (a release) to an
  ft never solved before (no cache hit), and wait the same way for the
  displacement figure's data: solve + render + round trip. The solver's own
  time for the same run (``CycleResult.runtime``) is printed beside it.
  Setting both at once is a click on the slider's track: the drag's
  analytical update and the run arrive together. Also timed: a release
  after a drag, as a hand does it (``value`` first, its update drawn, then
  ``value_throttled`` alone).
* player step: set the cycle player's step and wait the same way for the
  traction figure's data (pressure, zones, state map and displacement follow).

* server CPU per session: the ``panel serve`` process's CPU time (all its
  threads, ``/proc``) over the later first loads, divided by their number;
  the same for the yardstick page (``benchmarks/yardstick.py``: a template,
  four sliders and two HoloViews plots, served by the same server), and the
  ratio (issue 12: at most 2). Also for pages scrolled through (every figure
  drawn).
* the latencies below are taken on a 1600x1000 page scrolled through.
* every body (``--bodies``, issue 31): each body's page at its default grid, the ft slider released at
  fts never solved before, until the verdict's badge names the new run; the solver's own time beside.

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
from app.serving import chromium, scroll_through, served_app  # noqa: E402
from app.plots import FIGURES  # noqa: E402
from app.state import ExplorerState  # noqa: E402

BADGE = "[data-regime='shakedown'], [data-regime='ratcheting']"
FT_TITLE = "ft = Ft/(μ Fn)"

PLAYER = "player"  # in place of a slider title: the cycle player
# the figures the round trips wait for, by their titles in the tree measured (this script also runs in an older
# checkout, for a back-to-back pair with the same measurement)
TRACTION, DISPLACEMENT = (FIGURES[name]["opts"]["title"] for name in ("traction", "displacement"))

# set the ft slider (or the player), then wait until a figure's data sources are replaced; returns elapsed ms:
# [polled, data set, painted]. "polled" is the benchmark's historical figure: a loop that looks every millisecond
# (a timer) and sees the new data when it next runs. When the browser paints the figure before that timer runs
# (a paint is an animation frame, and the frame may come first), "polled" includes the paint: it is bimodal (the
# data set plus 1-4 ms, or plus the paint of every figure that changed). "data set" is when the browser wrote the
# server's data into the figure's source (its change signal, exact); "painted" is when the figure's canvas was
# next painted after that (what the reader sees).
_ROUND_TRIP = """
async ([title, figTitle, value, release]) => {
  const models = () => { const out = []; for (const d of Bokeh.documents) for (const m of d.all_models) out.push(m); return out; };
  const all = models();
  const slider = title === 'player' ? all.find((m) => m.title === 'Step in the period' && 'value_throttled' in m)
    : all.find((m) => m.title === title && typeof m.value === 'number' && 'value_throttled' in m);
  const fig = all.find((m) => m.title != null && m.title.text === figTitle);
  const views = [];
  const walk = (v) => { views.push(v); try { for (const c of v.children()) walk(c); } catch (e) {} };
  for (const k in Bokeh.index) walk(Bokeh.index[k]);
  const view = views.find((v) => v.model === fig);
  if (view != null && !view._timed) {
    const paint = view.paint.bind(view);
    view.paint = (...a) => { const r = paint(...a); window._painted = performance.now(); return r; };
    view._timed = true;
  }
  const sources = () => fig.renderers.map((r) => r.data_source).filter((s) => s != null);
  let set = NaN;
  const watched = sources().map((s) => { const cb = () => { if (isNaN(set)) set = performance.now(); };
                                         s.properties.data.change.connect(cb); return [s, cb]; });
  const before = sources().map((s) => s.data);
  window._painted = NaN;
  const t0 = performance.now();
  slider.value = value;
  if (release) slider.value_throttled = value;
  let polled = NaN;
  while (performance.now() - t0 < 10000) {
    const now = sources().map((s) => s.data);
    if (now.length !== before.length || now.some((d, i) => d !== before[i])) { polled = performance.now() - t0; break; }
    await new Promise((r) => setTimeout(r, 1));
  }
  const t1 = performance.now();
  while (!(window._painted > set) && performance.now() - t1 < 2000) await new Promise((r) => setTimeout(r, 5));
  for (const [s, cb] of watched) s.properties.data.change.disconnect(cb);
  return [polled, set - t0, window._painted > set ? window._painted - t0 : NaN];
}
"""


YARDSTICK = Path(__file__).resolve().parent / "yardstick.py"


def _load(browser, url, scroll: bool = False) -> float:
    """Seconds from opening ``url`` in a 1280x720 window to its first figure drawn (the explorer: and its
    verdict; ``scroll``: then every figure, scrolling through)."""
    page = browser.new_page(viewport={"width": 1280, "height": 720})
    t0 = time.perf_counter()
    page.goto(url, timeout=180_000)
    if not url.endswith("/yardstick"):
        page.locator(BADGE).first.wait_for(timeout=120_000)
    page.locator(".bk-Canvas, canvas").first.wait_for(timeout=60_000)
    if scroll:
        scroll_through(page)
    elapsed = time.perf_counter() - t0
    page.close()
    return elapsed


def _cpu_per_load(browser, url, pid, n, scroll=False) -> tuple[float, list]:
    """Server CPU [s] per page load of ``url`` over ``n`` loads one after another, and their durations [s]."""
    from benchmarks.loadtest import _cpu_s

    c0 = _cpu_s(pid)
    loads = [_load(browser, url, scroll) for _ in range(n)]
    time.sleep(1.0)  # the server finishes with the pages
    return (_cpu_s(pid) - c0) / n, loads


def _stats(values, k: int = 0) -> str:
    """Median, p90 and min of ``values`` (of the ``k``-th of each round trip's times: polled, data set, painted)."""
    v = sorted(t for t in (x[k] if isinstance(x, (list, tuple)) else x for x in values) if t == t)  # (NaN: none)
    if not v:
        return "none measured"
    p90 = v[min(len(v) - 1, int(round(0.9 * (len(v) - 1))))]
    return f"median {statistics.median(v):7.1f} ms, p90 {p90:7.1f} ms, min {v[0]:6.1f} ms  (n = {len(v)})"


def measure(n: int, figures: str = "live") -> dict:
    """Serve the explorer with ``figures`` (live or dynamicmap) and time it in Chromium; returns the figures."""
    out: dict = {"figures": figures}
    info: dict = {}
    t_start = time.perf_counter()
    with served_app(env={"SHAKEDOWN_FIGURES": figures}, info=info, extra_apps=[YARDSTICK]) as url, \
            chromium() as browser:
        yard = url.rsplit("/", 1)[0] + "/yardstick"
        out["ready"] = time.perf_counter() - t_start
        out["cold"] = _load(browser, url)
        _load(browser, yard)
        out["cpu_per_session"], out["warm"] = _cpu_per_load(browser, url, info["pid"], 5)
        out["cpu_yardstick"], _ = _cpu_per_load(browser, yard, info["pid"], 5)
        out["cpu_scrolled"], out["warm_scrolled"] = _cpu_per_load(browser, url, info["pid"], 3, scroll=True)
        page = browser.new_page(viewport={"width": 1600, "height": 1000})
        page.goto(url + "?ft=0.3&w=0.5", timeout=180_000)
        page.locator(BADGE).first.wait_for(timeout=60_000)
        scroll_through(page)
        page.locator(".bk-Canvas, canvas").nth(5).wait_for(timeout=60_000)
        out["analytical"] = [page.evaluate(_ROUND_TRIP, [FT_TITLE, TRACTION, 0.2 + 0.01 * (i % 20), False])
                             for i in range(n)]
        out["fts"] = [0.2013 + 0.0107 * i for i in range(n)]  # never solved before (a fresh server): no cache hits
        out["resolve"] = [page.evaluate(_ROUND_TRIP, [FT_TITLE, DISPLACEMENT, ft, True])
                          for ft in out["fts"]]
        out["released"] = []  # a drag to a new ft (its analytical update drawn), then the release alone
        for i in range(n):
            ft = 0.6013 + 0.0107 * i  # never solved before either
            page.evaluate(_ROUND_TRIP, [FT_TITLE, TRACTION, ft, False])
            page.wait_for_timeout(300)  # the drag's update is drawn, as a hand pauses before letting go
            out["released"].append(page.evaluate(_ROUND_TRIP, [FT_TITLE, DISPLACEMENT, ft, True]))
        out["steps"] = [page.evaluate(_ROUND_TRIP, [PLAYER, TRACTION, i % 40, False])
                        for i in range(1, n + 1)]
        out["models"] = page.evaluate("() => Bokeh.documents[0].all_models.size")
        page.close()
    return out


#: Release the ft slider at ``value`` and wait until the verdict's badge shows the run of that ft (its note names
#: it, no longer 'solving'); returns ``[elapsed ms, the server's solve ms]`` (NaN after 120 s): the second is the
#: run's own time in the server (``CycleResult.runtime``, the run card's "solve" row, sent with the badge), so that
#: the response splits into the solve and the rest (the hand-over, the figures, the browser). It is read from the
#: key-number strip's "all numbers" tooltip ("solve: 2.5 s, ...") or the cards, whichever the page holds.
_RELEASE = """
async ([title, value, printed]) => {
  const all = []; for (const d of Bokeh.documents) for (const m of d.all_models) all.push(m);
  const slider = all.find((m) => m.title === title && typeof m.value === 'number' && 'value_throttled' in m);
  const badges = () => all.filter((m) => typeof m.text === 'string' && m.text.includes('regime-badge'));
  const solved = () => {
    for (const m of all) {
      if (typeof m.text !== 'string') continue;
      const f = new RegExp("solve(?::|</span>|&lt;/span&gt;)[^0-9]{0,60}?([0-9.]+) (ms|s),").exec(m.text);
      if (f) return parseFloat(f[1]) * (f[2] === 's' ? 1000 : 1);
    }
    return NaN;
  };
  const t0 = performance.now();
  slider.value = value; slider.value_throttled = value;
  while (performance.now() - t0 < 120000) {
    if (badges().some((b) => /data-regime=(&quot;|")(shakedown|ratcheting|undetermined|cyclic slip)/.test(b.text)
                             && b.text.includes('ft = ' + printed))) return [performance.now() - t0, solved()];
    await new Promise((r) => setTimeout(r, 5));
  }
  return [NaN, NaN];
}
"""


def measure_bodies(n: int = 3, only=None):
    """Every body's response to a released ft slider (ms, ``n`` releases at fts never solved before), each body's
    page at its default grid, and the solver's own time for the first of those runs: yields
    ``(body, times, solver)`` as each body is measured."""
    from app import bodies as app_bodies

    fts = [0.32 + 0.02 * i for i in range(n)]
    with served_app(env={"SHAKEDOWN_SOLVE_BUDGET_S": "120"}) as url, chromium() as browser:
        for body in (only or app_bodies.BODIES):
            state = ExplorerState(body=body)
            try:
                if not app_bodies.runs_cycles(body, state.body_object()):
                    continue
            except ValueError:
                continue
            page = browser.new_page(viewport={"width": 1280, "height": 720})
            page.goto(f"{url}?body={body}&ft=0.3", timeout=180_000)
            page.locator("[data-regime]:not([data-regime='pending'])").first.wait_for(timeout=180_000)
            times = [page.evaluate(_RELEASE, [FT_TITLE, ft, f"{ft:.2f}"]) for ft in fts]  # [response, server solve]
            page.close()
            s = ExplorerState(body=body, ft=fts[0])
            options = s.solver_options()
            yield body, times, s.contact().simulate(**options).runtime * 1e3


def report_body(body: str, times: list, solver: float) -> str:
    """One line of :func:`measure_bodies` (``times``: [response, the server's solve] of each release, ms)."""
    return (f"  {body:10s}: {_stats(times)}; max {max(t[0] for t in times):7.1f} ms; the server's solve "
            f"(run card, 0.1 s steps for a point body) {_stats(times, 1)}; the solver alone here (first run) "
            f"{solver:7.1f} ms")


def report(r: dict) -> str:
    state = ExplorerState()
    c = state.contact()
    solver = [core.simulate_contact(c.replace(ft=ft), **state.solver_options()).runtime * 1e3 for ft in r["fts"]]
    return "\n".join([
        f"figures: {r['figures']}",
        f"server ready (/liveness answers)          : {r['ready']:6.2f} s",
        f"first load, first session after start     : {r['cold']:6.2f} s",
        f"first load, later sessions (median of 5)  : {statistics.median(r['warm']):6.2f} s   target < 3 s",
        f"  scrolled through, every figure drawn    : {statistics.median(r['warm_scrolled']):6.2f} s",
        f"server CPU per page (5 later loads)       : {r['cpu_per_session']:6.2f} s; yardstick page "
        f"{r['cpu_yardstick']:.2f} s, ratio {r['cpu_per_session'] / r['cpu_yardstick']:.1f} (goal <= 2: "
        f"{'met' if r['cpu_per_session'] <= 2 * r['cpu_yardstick'] else 'NOT met'})",
        f"  scrolled through, every figure drawn    : {r['cpu_scrolled']:6.2f} s",
        f"analytical slider -> plot data            : {_stats(r['analytical'])}   target < 100 ms",
        f"  data set in the browser (exact)         : {_stats(r['analytical'], 1)}",
        f"  figure painted after it                 : {_stats(r['analytical'], 2)}",
        f"numerical re-solve -> plot data (default) : {_stats(r['resolve'])}   target < 300 ms",
        f"  data set in the browser (exact)         : {_stats(r['resolve'], 1)}",
        f"  figure painted after it                 : {_stats(r['resolve'], 2)}",
        f"  released after a drag (release alone)   : {_stats(r['released'])}",
        f"  of which the solver alone (same runs)   : {_stats(solver)}",
        f"  default run: {state.resolution} elements per a, {state.periods} periods, kernel {state.kernel}",
        f"player step -> traction data              : {_stats(r['steps'])}   (the player steps every 150 ms)",
        f"  data set / figure painted               : {_stats(r['steps'], 1)} / {_stats(r['steps'], 2)}",
        f"Bokeh models in one session's document    : {r['models']}",
    ])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--figures", choices=["live", "dynamicmap", "both"], default="live")
    ap.add_argument("--bodies", action="store_true",
                    help="only every body's response to a released slider (issue 31), with --repeats releases each")
    ap.add_argument("--body", action="append", help="with --bodies: only this body (repeatable)")
    args = ap.parse_args(argv)
    if args.bodies:
        print("released ft slider -> the verdict of the new run, every body at its default grid (1280x720):",
              flush=True)
        for measured in measure_bodies(args.repeats, args.body):
            print(report_body(*measured), flush=True)
        return 0
    print(__doc__.split("Targets")[0].strip().split("\n\n", 1)[1])
    for figures in (["live", "dynamicmap"] if args.figures == "both" else [args.figures]):
        print()
        print(report(measure(args.repeats, figures)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
