"""Serve the explorer in a subprocess and drive it with headless Chromium.

Shared by the browser tests (``tests/test_app_browser.py``), the screenshot
script and ``benchmarks/app.py``: one way to start ``panel serve app/main.py
--plugins app.health`` on a free loopback port, wait until ``/liveness`` says
the solver is warm (so no test's page load waits for numba to compile), and
launch Debian's Chromium through Playwright.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

from core.records.verdict import REGIMES

__all__ = ["ROOT", "CHROMIUM", "CHROMIUM_ARGS", "SERVE_OPTIONS", "VERDICT_SELECTOR", "VIEWS_JS", "FIND_MODEL_JS",
           "SLIDER_TITLES_JS", "CURVE_POINTS_JS", "open_page", "wait_until", "free_port", "served_app",
           "chromium", "dask_cluster", "tasks_done", "scroll_through", "ServerExited"]

ROOT = Path(__file__).resolve().parent.parent
#: The ``panel serve`` options the app is served with, here, in the README and in the Dockerfile
#: (tests/test_dockerfile.py keeps them in step). ``--plugins app.health`` warms the solver at start and
#: serves /liveness, which answers 200 only once it is warm (app/health.py; not Panel's --liveness).
#: A session whose page is built but whose websocket has not connected yet is kept for 120 s, not
#: Bokeh's default 15 s: under a class's load pages take longer than 15 s, and a discarded session
#: is built a second time, without its stylesheet paths, so the page fetched Panel's CSS from the
#: public CDN (benchmarks/loadtest.py saw it in 2 to 4 sessions of 10).
SERVE_OPTIONS = ("--plugins", "app.health", "--unused-session-lifetime", "120000")
#: Debian's Chromium (Playwright drives it; no browser download needed).
CHROMIUM = os.environ.get("SHAKEDOWN_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


#: A verdict badge of any regime (``app.cards`` writes ``data-regime``): the page's run has its verdict.
VERDICT_SELECTOR = ", ".join(f"[data-regime='{regime}']" for regime in REGIMES)

#: JavaScript for ``page.evaluate``: the titles of the page's ft and w sliders (Bokeh models with a number value),
#: sorted.
SLIDER_TITLES_JS = """
() => {
  const out = [];
  for (const d of Bokeh.documents) for (const m of d.all_models)
    if (['ft = Ft/(μ Fn)', 'w = W/a'].includes(m.title) && typeof m.value === 'number' && 'value_throttled' in m)
      out.push(m.title);
  return [...new Set(out)].sort();
}
"""


def open_page(browser, url: str, size: tuple[int, int] = (1280, 720), *, ready: str = VERDICT_SELECTOR,
              timeout_ms: int = 180_000):
    """A new page of ``browser`` at ``size`` on ``url``, returned once ``ready`` (a selector) is shown; the console's
    errors and the page's uncaught errors are recorded in ``page.problems``."""
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    page.problems = []
    page.on("console", lambda m: page.problems.append(f"console: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: page.problems.append(f"page error: {e}"))
    page.goto(url, timeout=timeout_ms)
    page.locator(ready).first.wait_for(timeout=timeout_ms)
    return page


#: JavaScript: ``all_views()``, every Bokeh view of the page (Panel nests them in layouts, in shadow DOM).
VIEWS_JS = """
const all_views = () => {
  const seen = new Set(), found = [];
  const walk = (v) => {
    if (!v || seen.has(v)) return;
    seen.add(v);
    found.push(v);
    for (const c of (v.child_views ?? [])) walk(c);
    try { for (const c of v.children()) walk(c); } catch (e) {}
  };
  const idx = Bokeh.index;
  for (const r of (idx.roots ? [...idx.roots] : (idx.values ? [...idx.values()] : Object.values(idx)))) walk(r);
  return found;
};
"""

#: JavaScript for ``page.evaluate``: ``find(pred)``, the Bokeh model of the page for which ``pred`` holds, the one
#: drawn in the page first (Panel renders in shadow DOM, where ``document.querySelector`` does not reach; Bokeh's
#: views and ``Bokeh.documents`` do), else the first in the documents. A figure the explorer replaced (another unit
#: system: a point contact's first run) stays in ``doc.all_models``, with its old data, until BokehJS collects it,
#: some 30 s later: the first model of the documents with the title was that one, and the tests waited for it.
FIND_MODEL_JS = VIEWS_JS + """
const find = (pred) => {
  for (const v of all_views()) { if (v.model && v.el && v.el.isConnected && pred(v.model)) return v.model; }
  for (const doc of Bokeh.documents) for (const m of doc.all_models) { if (pred(m)) return m; }
  return null;
};
"""

#: JavaScript for ``page.evaluate(CURVE_POINTS_JS, title)``: how many points the curves of the figure titled
#: ``title`` hold (their ``Q`` column; null before the figure is drawn): a fretting loop's data has reached the page.
CURVE_POINTS_JS = "(title) => {" + FIND_MODEL_JS + """
  const fig = find((m) => m.title != null && m.title.text === title);
  if (fig === null) return null;
  let points = 0;
  for (const r of fig.renderers) {
    const d = r.data_source == null ? null : r.data_source.data;
    const q = d == null ? null : (d instanceof Map ? d.get('Q') : d.Q);
    if (q != null) points += q.length;
  }
  return points;
}"""

#: JavaScript for ``page.evaluate`` (after :data:`VIEWS_JS`): scrolls the first figure place that is not drawn
#: yet (an :class:`app.live.WhenShown` still in the page) into view; returns how many such places are left.
_NEXT_FIGURE_JS = """
  const waiting = all_views().filter((v) => v.model && (v.model.css_classes ?? []).includes('when-shown')
                                            && v.el.isConnected && v.el.getClientRects().length > 0);
  if (waiting.length) waiting[0].el.scrollIntoView({block: 'start'});
  return waiting.length;
"""


def scroll_through(page, timeout: float = 60.0) -> None:
    """Scroll a served explorer page, figure by figure, until every figure in it is drawn (what a reader who
    scrolls to the end does: the page draws a figure once it comes near the view), then back to the top."""
    wait_until(lambda: page.evaluate("() => {" + VIEWS_JS + _NEXT_FIGURE_JS + "}") == 0 or None, timeout,
               interval=0.1, message="every figure of the page drawn")
    page.evaluate("() => { for (const el of document.querySelectorAll('*')) if (el.scrollTop) el.scrollTop = 0;"
                  " window.scrollTo(0, 0); }")


class ServerExited(RuntimeError):
    """The served app's process ended before it answered (raised at once by :func:`served_app`)."""


def _tail(log, lines: int = 30) -> str:
    """The last ``lines`` lines of an open log file (``"(not captured)"`` for None)."""
    if log is None:
        return "(not captured: SHAKEDOWN_SERVER_LOG sends it to the terminal)"
    log.flush()
    log.seek(0)
    return "".join(log.readlines()[-lines:]) or "(nothing)"


def wait_until(predicate, timeout: float = 30.0, interval: float = 0.05, message: str = "condition",
               give_up: type[BaseException] | tuple = ()):
    """Poll ``predicate()`` until it returns a truthy value (returned), or raise TimeoutError.

    An exception of a ``give_up`` class raised by ``predicate`` ends the wait at once (re-raised); any other
    is kept and named in the TimeoutError.
    """
    deadline = time.monotonic() + timeout
    last_error = None
    while time.monotonic() < deadline:
        try:
            value = predicate()
            if value:
                return value
        except give_up:
            raise
        except Exception as e:  # noqa: BLE001 - keep polling, report the last error
            last_error = e
        time.sleep(interval)
    raise TimeoutError(f"timed out after {timeout:.0f} s waiting for {message}"
                       + (f" (last error: {last_error!r})" if last_error else ""))


def free_port() -> int:
    """A TCP port free on 127.0.0.1 right now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _alive(url: str, ready: bool = True) -> bool:
    """Whether ``url`` answers 200 (``ready``), or answers at all (503 included: the server is up, not warm)."""
    try:
        with urllib.request.urlopen(url, timeout=2) as r:  # noqa: S310 - loopback only
            return r.status == 200
    except urllib.error.HTTPError as e:
        if not ready and e.code == 503:
            return True
        raise


@contextlib.contextmanager
def served_app(port: int | None = None, timeout: float = 420.0, env: dict | None = None,
               log_path: str | os.PathLike | None = None, info: dict | None = None,
               extra_args: list[str] | tuple[str, ...] = (), extra_apps: list | tuple = (), wait_ready: bool = True,
               script: str | os.PathLike = "app/main.py"):
    """Serve ``script`` (default ``app/main.py``) on 127.0.0.1 and yield its URL; stop the server on exit.

    Parameters
    ----------
    port : int, optional
        Port to serve on (default: a free one).
    timeout : float
        Seconds to wait for ``/liveness`` to answer 200 (the solver warm; a
        fresh numba cache takes one to two minutes to fill: the cylinder and
        the point contacts are compiled).
    env : dict, optional
        Extra environment variables for the server (e.g. ``SHAKEDOWN_SCHEDULER``).
    log_path : path, optional
        File that receives the server's output (default: discarded, or the
        terminal when ``SHAKEDOWN_SERVER_LOG`` is set).
    extra_args : sequence of str
        Further ``panel serve`` options (e.g. ``["--num-threads", "4"]``).
    script : path, optional
        The app to serve, relative to the repository root; its URL ends in its file stem.
    extra_apps : sequence of paths
        Further scripts served by the same server, each at ``/<file stem>``.
    wait_ready : bool
        Wait until the solver is warm (default); False: only until the server answers.
    info : dict, optional
        Filled with ``pid`` (the server process), ``base`` (its root URL) and,
        after the server stopped, ``returncode`` and ``stop_seconds``.
    """
    port = port or free_port()
    cmd = [sys.executable, "-m", "panel", "serve", str(ROOT / script), *map(str, extra_apps), "--port", str(port),
           "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}", *SERVE_OPTIONS,
           *map(str, extra_args)]
    if log_path is not None:
        log = open(log_path, "w+")
    else:  # kept (in a temporary file) so that a server that fails to start can say why
        log = tempfile.TemporaryFile("w+") if not os.environ.get("SHAKEDOWN_SERVER_LOG") else None
    proc = subprocess.Popen(cmd, cwd=ROOT, env={**os.environ, **(env or {})}, stdout=log,
                            stderr=subprocess.STDOUT if log is not None else None)
    info = {} if info is None else info
    base = f"http://127.0.0.1:{port}"
    info.update(pid=proc.pid, base=base)

    def up():
        if proc.poll() is not None:  # it will not come up: say so now, not after the timeout
            raise ServerExited(f"the app server ({' '.join(cmd[1:5])}) exited with status {proc.returncode} before "
                               f"{base}/liveness answered; its output ends:\n{_tail(log)}")
        return _alive(f"{base}/liveness", wait_ready)

    try:
        wait_until(up, timeout, message=f"{base}/liveness", give_up=ServerExited)
        yield f"{base}/{Path(script).stem}"
    finally:
        t0 = time.monotonic()
        _stop(proc)
        info.update(returncode=proc.returncode, stop_seconds=time.monotonic() - t0)
        if log is not None:
            log.close()


def _stop(proc: subprocess.Popen, grace: float = 10.0) -> None:
    proc.terminate()
    try:
        proc.wait(grace)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


@contextlib.contextmanager
def dask_cluster(workers: int = 1, timeout: float = 60.0, log_dir: str | os.PathLike | None = None):
    """A Dask cluster on 127.0.0.1: ``dask scheduler`` and ``workers`` ``dask worker`` processes.

    Yields the scheduler's address once every worker has registered; stops
    them all on exit. Workers have one thread each (the solver holds the
    GIL) and import this checkout's ``core`` (``PYTHONPATH``). Their output
    goes to ``log_dir`` (``scheduler.log``, ``worker-<k>.log``) if given.
    """
    import distributed

    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]),
           "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    logs = Path(log_dir) if log_dir is not None else None
    procs: list[subprocess.Popen] = []
    files = []

    def start(name, args):
        out = open(logs / f"{name}.log", "w") if logs is not None else subprocess.DEVNULL  # noqa: SIM115
        if logs is not None:
            files.append(out)
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_" + args[0], *args[1:]],
                                      cwd=ROOT, env=env, stdout=out, stderr=subprocess.STDOUT))

    try:
        start("scheduler", ["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"])
        for k in range(workers):
            start(f"worker-{k}", ["worker", address, "--host", "127.0.0.1", "--nthreads", "1", "--nworkers", "1",
                                  "--no-dashboard", "--no-nanny", "--name", f"worker-{k}"])
        client = wait_until(lambda: all(p.poll() is None for p in procs)
                            and distributed.Client(address, set_as_default=False, timeout="2s"),
                            timeout, interval=0.5, message=f"the Dask scheduler at {address}")
        try:
            if workers:
                client.wait_for_workers(workers, timeout=timeout)
        finally:
            client.close()
        yield address
    finally:
        for proc in reversed(procs):  # workers first, then the scheduler
            _stop(proc)
        for f in files:
            f.close()


def tasks_done(address: str, prefix: str) -> int:
    """How many tasks whose key starts with ``prefix`` (a function's name) the scheduler at ``address`` completed."""
    import distributed

    def count(dask_scheduler, prefix=prefix):
        tp = dask_scheduler.task_prefixes.get(prefix)
        return 0 if tp is None else int(tp.state_counts.get("memory", 0))  # ever finished, released later or not

    with distributed.Client(address, set_as_default=False, timeout="10s") as client:
        return client.run_on_scheduler(count)


#: Seconds Playwright waits for Chromium to start (its own default is 180 s; a healthy start takes about 1 s).
LAUNCH_TIMEOUT_S = 60.0


@contextlib.contextmanager
def chromium():
    """A headless Chromium browser (Playwright, sync API).

    Raises
    ------
    RuntimeError
        At once if there is no browser at :data:`CHROMIUM` (saying how to install one), or if it does not start
        within :data:`LAUNCH_TIMEOUT_S`.
    """
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import sync_playwright

    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        raise RuntimeError(f"no Chromium at {CHROMIUM} for the browser tests: install Debian's chromium "
                           "(scripts/test.sh does: apt-get install chromium) or set SHAKEDOWN_CHROMIUM to a "
                           "Chromium executable")
    with sync_playwright() as pw:
        try:
            browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True,
                                         timeout=LAUNCH_TIMEOUT_S * 1e3)
        except PlaywrightError as e:
            raise RuntimeError(f"Chromium ({CHROMIUM}) did not start: {str(e).strip()[:2000]}") from e
        try:
            yield browser
        finally:
            browser.close()
