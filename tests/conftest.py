"""Shared test helpers (fixtures, so they work under --import-mode=importlib)."""

import os

import numpy as np
import pytest

# the servers the tests start check every page's Bokeh model graph (errors in their log fail the load test);
# a production server skips it (app/health.py)
os.environ.setdefault("BOKEH_VALIDATE_DOC", "true")


def _check_invariants(result, tol=1e-9):
    """Coulomb's law, load balance, contact and dissipation at every step of a CycleResult."""
    q = result.traction
    p = np.asarray(result.pressure)  # element-mean Hertz pressure = the traction bound in mu p0
    # |q| <= mu p
    excess = np.abs(q) - p
    assert excess.max() <= tol, f"|q| exceeds mu p by {excess.max():.3g} at step {np.unravel_index(excess.argmax(), q.shape)[0]}"
    # q = 0 out of contact
    out = p <= 0
    assert np.all(q[out] == 0.0), "traction outside the contact"
    # load balance: sum q dx = (pi/2) Q
    total = q.sum(axis=1) * result.dx
    np.testing.assert_allclose(total, 0.5 * np.pi * result.Q, atol=tol, err_msg="load balance")
    # friction dissipates
    assert result.dissipation.min() >= -tol, f"negative dissipation {result.dissipation.min():.3g}"
    # every step solved to its tolerance
    assert result.max_kkt_residual <= result.tol, f"KKT residual {result.max_kkt_residual:.3g}"
    # states are consistent: slip only at the bound, released only out of contact
    slipping = result.state >= 2
    assert np.all(np.abs(np.abs(q[slipping]) - p[slipping]) <= tol), "slip below the bound"
    assert np.all((result.state == 0) == out), "released state differs from loss of contact"


@pytest.fixture
def check_invariants():
    return _check_invariants


def _scroll_through(explorer):
    """What a browser does when the explorer's page is scrolled to its end: every figure's sentinel
    (app.live.WhenShown) in the page reports, and its figure is drawn."""
    for sentinel in list(explorer.sentinels.values()):
        sentinel.shown = True
    return explorer


@pytest.fixture(scope="session")
def scroll_through():
    return _scroll_through


def _run_in_fresh_thread(fn, *args, **kwargs):
    """Run ``fn`` in a thread of its own and return its result (or raise its exception).

    A test module that drives an asyncio loop in the main thread can leave it
    marked as running for later modules; Playwright's sync API and Bokeh's
    client then refuse to start there. A new thread has no loop of anyone else's.
    """
    import threading

    out = {}

    def target():
        try:
            out["value"] = fn(*args, **kwargs)
        except BaseException as e:  # noqa: BLE001 - re-raised in the caller's thread
            out["error"] = e

    t = threading.Thread(target=target, name=f"fresh-{getattr(fn, '__name__', 'fn')}")
    t.start()
    t.join()
    if "error" in out:
        raise out["error"]
    return out.get("value")


@pytest.fixture
def fresh_thread():
    return _run_in_fresh_thread

# ---- the served app, one for the whole run, and Chromium, one per module (Playwright's sync API allows one
# instance per process at a time, and while it lives it runs an asyncio loop in this thread: a session-wide
# browser broke later modules that run an event loop of their own, e.g. the load test's Bokeh clients) ----
@pytest.fixture(scope="session")
def app_log(tmp_path_factory):
    """The file that receives the output of the served app of :func:`app_url` (its log, tracebacks included)."""
    return tmp_path_factory.mktemp("served_app") / "server.log"


@pytest.fixture(scope="session")
def app_url(app_log):
    """``app/main.py`` served once for every browser test that needs no server of its own (each module started
    its own: 30-40 s of warm-up each, nine times). Sessions are independent, so sharing the server changes
    nothing a test sees; the solve budget (20 s by default) is raised because a point-contact run that takes 3 s
    alone takes 20 s on 2 cores shared with Chromium, and no browser test checks the budget."""
    from app.serving import served_app

    with served_app(env={"SHAKEDOWN_SOLVE_BUDGET_S": "300"}, log_path=app_log) as url:
        yield url


@pytest.fixture(scope="module")
def browser():
    from app.serving import chromium

    with chromium() as b:
        yield b
