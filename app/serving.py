"""Serve the explorer in a subprocess and drive it with headless Chromium.

Shared by the browser tests (``tests/test_app_browser.py``), the screenshot
script and ``benchmarks/app.py``: one way to start ``panel serve app/main.py
--liveness`` on a free loopback port, wait for ``/liveness`` by polling, and
launch Debian's Chromium through Playwright.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

__all__ = ["ROOT", "CHROMIUM", "CHROMIUM_ARGS", "SERVE_OPTIONS", "wait_until", "free_port", "served_app",
           "chromium"]

ROOT = Path(__file__).resolve().parent.parent
#: The ``panel serve`` options the app is served with, here, in the README and in the Dockerfile
#: (tests/test_dockerfile.py keeps them in step). ``--liveness`` gives /liveness for health checks.
#: A session whose page is built but whose websocket has not connected yet is kept for 120 s, not
#: Bokeh's default 15 s: under a class's load pages take longer than 15 s, and a discarded session
#: is built a second time, without its stylesheet paths, so the page fetched Panel's CSS from the
#: public CDN (benchmarks/loadtest.py saw it in 2 to 4 sessions of 10).
SERVE_OPTIONS = ("--liveness", "--unused-session-lifetime", "120000")
#: Debian's Chromium (Playwright drives it; no browser download needed).
CHROMIUM = os.environ.get("SHAKEDOWN_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def wait_until(predicate, timeout: float = 30.0, interval: float = 0.05, message: str = "condition"):
    """Poll ``predicate()`` until it returns a truthy value (returned), or raise TimeoutError."""
    deadline = time.monotonic() + timeout
    last_error = None
    while time.monotonic() < deadline:
        try:
            value = predicate()
            if value:
                return value
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


def _alive(url: str) -> bool:
    with urllib.request.urlopen(url, timeout=2) as r:  # noqa: S310 - loopback only
        return r.status == 200


@contextlib.contextmanager
def served_app(port: int | None = None, timeout: float = 60.0, env: dict | None = None,
               log_path: str | os.PathLike | None = None, info: dict | None = None,
               extra_args: list[str] | tuple[str, ...] = (), script: str | os.PathLike = "app/main.py"):
    """Serve ``script`` (default ``app/main.py``) on 127.0.0.1 and yield its URL; stop the server on exit.

    Parameters
    ----------
    port : int, optional
        Port to serve on (default: a free one).
    timeout : float
        Seconds to wait for ``/liveness``.
    env : dict, optional
        Extra environment variables for the server.
    log_path : path, optional
        File that receives the server's output (default: discarded, or the
        terminal when ``SHAKEDOWN_SERVER_LOG`` is set).
    extra_args : sequence of str
        Further ``panel serve`` options (e.g. ``["--num-threads", "4"]``).
    script : path, optional
        The app to serve, relative to the repository root; its URL ends in its file stem.
    info : dict, optional
        Filled with ``pid`` (the server process), ``base`` (its root URL) and,
        after the server stopped, ``returncode`` and ``stop_seconds``.
    """
    port = port or free_port()
    cmd = [sys.executable, "-m", "panel", "serve", str(ROOT / script), "--port", str(port),
           "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}", *SERVE_OPTIONS,
           *map(str, extra_args)]
    if log_path is not None:
        log = open(log_path, "w")
    else:
        log = open(os.devnull, "w") if not os.environ.get("SHAKEDOWN_SERVER_LOG") else None
    proc = subprocess.Popen(cmd, cwd=ROOT, env={**os.environ, **(env or {})}, stdout=log,
                            stderr=subprocess.STDOUT if log is not None else None)
    info = {} if info is None else info
    base = f"http://127.0.0.1:{port}"
    info.update(pid=proc.pid, base=base)
    try:
        wait_until(lambda: proc.poll() is None and _alive(f"{base}/liveness"), timeout,
                   message=f"{base}/liveness")
        yield f"{base}/{Path(script).stem}"
    finally:
        t0 = time.monotonic()
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        info.update(returncode=proc.returncode, stop_seconds=time.monotonic() - t0)
        if log is not None:
            log.close()


@contextlib.contextmanager
def chromium():
    """A headless Chromium browser (Playwright, sync API)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            yield browser
        finally:
            browser.close()
