"""The served explorer: ``panel serve app/main.py --plugins app.health``.

One :class:`~app.explorer.Explorer` per browser session. URL query parameters
are validated first (rejected ones show a notice and are not applied), then
every parameter is kept in sync with the URL under its own name, so a link
reproduces the view.

The page is served as soon as the server listens, also while the server is
still warming the solver (the first minute or more after a fresh install, when
numba compiles it): the sliders, the sketch, the exact limits, the closure
curves and the paper's figures need no solver; the session's first run is
solved off the event loop (:class:`app.explorer.Explorer`) and fills the
numerical figures when it arrives, the status line saying "compiling the
solver (first start only), N s" meanwhile.
"""

import contextlib
import json
import sys
from pathlib import Path

import panel as pn

try:
    from app import runs
    from app.explorer import Explorer
    from app.state import URL_PARAMETERS
except ImportError:  # served from a checkout that is not installed
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    from app import runs
    from app.explorer import Explorer
    from app.state import URL_PARAMETERS
from app.health import watch_loop  # noqa: E402 - after the path fix above
from app.live import faster_bokeh  # noqa: E402

faster_bokeh()  # this server's Bokeh encodes a page for a fifth of the CPU (the same JSON; app.live.faster_bokeh)

pn.extension("katex", sizing_mode="stretch_width", throttled=False)


def _sync_url(explorer: Explorer) -> None:
    location = pn.state.location
    if location is None:
        return

    def rejected(values):  # values that Panel's own sync could not apply (kept out of the state)
        reported = {n.split()[0] for n in explorer.notices if n}  # named already by parse_query's notice
        names = ", ".join(sorted(v for v in map(str, values) if v not in reported))
        if names:
            explorer.notices = [*explorer.notices, f"not applied from the URL: {names}"][:20]

    location.sync(explorer.state, {p: p for p in URL_PARAMETERS}, on_error=rejected)
    # a link's noisy number (w=0.45000000000000007) is held rounded (ExplorerState.__setattr__); the address bar
    # shows the value held, so that a link copied from it is clean too. (Checked whenever the address changes:
    # the browser sends its own address, the link's, once the page has connected.)
    state = explorer.state

    def clean(*_):
        noisy = {k: json.dumps(getattr(state, k)) for k, v in location.query_params.items()
                 if k in URL_PARAMETERS and isinstance(v, float) and v != getattr(state, k) == round(v, 6)}
        if noisy:
            location.update_query(**noisy)

    clean()
    location.param.watch(clean, "search")


runs.start_warm_up()  # already running when served with --plugins app.health
watch_loop()
# URL parameters are validated and applied before the first solve, so the page is sent complete
explorer = Explorer(query=pn.state.location.search if pn.state.location else None)
explorer.map_scheduler = runs.map_scheduler()  # the Dask cluster of SHAKEDOWN_SCHEDULER, or local processes
_sync_url(explorer)
# one recomputation of the document's model graph for all the template's roots, not one per root (0.5 s)
with pn.state.curdoc.models.freeze() if pn.state.curdoc else contextlib.nullcontext():
    explorer.template().servable()
