"""Issue 12, items 4 and 5: solves and maps on a Dask cluster, a queue bound per session, read-only shared results.

The cluster is real: ``dask scheduler`` and ``dask worker`` processes on
127.0.0.1 (``app.serving.dask_cluster``), and the served app reaches it
through ``SHAKEDOWN_SCHEDULER`` as an operator would set it.
"""

import json
import threading
from concurrent.futures import ThreadPoolExecutor
import urllib.error
import urllib.request

import numpy as np
import pytest

import core
from app import limits, runs
from app.serving import SLIDER_TITLES_JS, chromium, dask_cluster, served_app, tasks_done, wait_until
from app.state import ExplorerState

pytestmark = pytest.mark.timeout(400)

BADGE = "[data-regime='shakedown'], [data-regime='ratcheting']"
# release the ft slider at a new value; resolve once the run card (text with "el., ... steps") changes
_RELEASE_FT = """
async ([value, timeoutMs]) => {
  const models = () => { const out = []; for (const d of Bokeh.documents) for (const m of d.all_models) out.push(m); return out; };
  const slider = models().find((m) => m.title === 'ft = Ft/(μ Fn)' && typeof m.value === 'number' && 'value_throttled' in m);
  const card = () => models().find((m) => typeof m.text === 'string' && m.text.includes(' steps') && m.text.includes('el.,'));
  const before = card().text;
  slider.value = value; slider.value_throttled = value;
  const t0 = performance.now();
  while (performance.now() - t0 < timeoutMs) {
    await new Promise((r) => setTimeout(r, 50));
    const now = card();  // none while the cards say 'solving…' (the run shown is not the inputs' run)
    if (now && now.text !== before) return true;
  }
  return false;
}
"""


@pytest.fixture(scope="module")
def cluster():
    with dask_cluster(workers=1) as address:
        yield address


def _default():
    state = ExplorerState()
    return state.contact(), state.solver_options()


def test_scheduler_address_is_checked_at_start_up(monkeypatch):
    monkeypatch.delenv("SHAKEDOWN_SCHEDULER", raising=False)
    assert limits.env_scheduler() is None
    monkeypatch.setenv("SHAKEDOWN_SCHEDULER", " tcp://10.0.0.5:8786 ")
    assert limits.env_scheduler() == "tcp://10.0.0.5:8786"
    for bad in ("10.0.0.5:8786", "tcp://10.0.0.5", "http://h:80", "tcp://h:99999", "tcp://:8786"):
        monkeypatch.setenv("SHAKEDOWN_SCHEDULER", bad)
        with pytest.raises(ValueError, match="SHAKEDOWN_SCHEDULER must be a Dask scheduler address"):
            limits.env_scheduler()


def test_a_shared_result_cannot_be_written():
    contact, options = _default()
    cache = runs.ResultCache()
    result = runs.solve(contact.replace(w=0.33), dict(options, periods=2), cache=cache)
    assert cache.get(runs.run_key(contact.replace(w=0.33), dict(options, periods=2))) is result
    for name in ("traction", "state", "displacement", "xc", "edges", "pressures"):
        array = getattr(result, name)
        assert not array.flags.writeable, name
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1
    with pytest.raises(ValueError, match="read-only"):  # a step's pressure: a view of the stored rows
        result.pressure[0][0] = 1


def test_a_session_may_queue_only_so_many_solves(monkeypatch):
    """A session's solves beyond SHAKEDOWN_MAX_QUEUED_PER_SESSION waiting or running are refused; another session's
    are not; a session's superseded solves make room for its newest. Session a's first solves are held in the solver
    until released (they would otherwise finish in milliseconds, and under load one did before the next was sent:
    the refusal then depended on the machine's speed), so they are provably pending when superseded. The server's
    count of solves in flight and ended (``/liveness``) follows them."""
    contact, options = _default()
    limit = runs.MAX_QUEUED_PER_SESSION
    release, superseded = threading.Event(), threading.Event()
    held_w = [round(0.31 + 0.01 * k, 6) for k in range(limit)]
    compute = runs._compute

    def held(contact, options, cancel=None, time_budget=None):
        if round(contact.w, 6) in held_w:  # session a's first solves: running or waiting until superseded
            while not release.wait(0.01):
                pass
            if cancel is not None and cancel():
                raise core.SolveCancelled("solve cancelled: a newer request replaced it")
        return compute(contact, options, cancel, time_budget)

    monkeypatch.setattr(runs, "_compute", held)
    current = [0]
    futures = []
    ended = runs.readiness()["solves_ended"]
    try:
        for w in held_w:
            futures.append(runs.submit(contact.replace(w=w), options, owner="session-a",
                                       cancel=lambda: superseded.is_set()))
        assert runs._SESSIONS.pending("session-a") == limit
        assert runs.readiness()["solves"] >= limit  # /liveness counts them (the server's and the tests' hook)
        refused = runs.submit(contact.replace(w=0.45), options, owner="session-a")
        with pytest.raises(runs.SolveQueueFull, match="SHAKEDOWN_MAX_QUEUED_PER_SESSION"):
            refused.result(timeout=5)
        # another session is not affected by session a's queue (its solve runs once a solver thread is free)
        other = runs.submit(contact.replace(w=0.46), dict(options, periods=2), owner="session-b")
        assert not (other.done() and isinstance(other.exception(), runs.SolveQueueFull))
        # session a's own superseded requests make room for its newest one while they are still pending (held)
        superseded.set()
        assert runs._SESSIONS.pending("session-a") == limit and not any(f.done() for f in futures)
        newest = runs.submit(contact.replace(w=0.47), dict(options, periods=2), owner="session-a",
                             cancel=lambda: current[0] != 0)
        assert runs._SESSIONS.pending("session-a") == 1
        release.set()
        assert newest.result(timeout=120).regime in ("shakedown", "ratcheting", "undetermined")
        assert other.result(timeout=120).regime in ("shakedown", "ratcheting", "undetermined")  # 2 periods may not tell
        for f in futures:  # each superseded one stopped
            with pytest.raises(core.SolveCancelled):
                f.result(timeout=120)
    finally:
        superseded.set()
        release.set()
        for f in futures:
            try:
                f.result(timeout=120)
            except (core.SolveCancelled, Exception):  # noqa: BLE001, S110 - cancelled on purpose
                pass
    wait_until(lambda: runs._SESSIONS.pending("session-a") == 0, 30, message="session a's queue to empty")
    # /liveness: nothing in flight, and every solve asked for (the refused one was never run) counted as ended
    wait_until(lambda: runs.readiness()["solves"] == 0, 30, message="no solve in flight")
    assert runs.readiness()["solves_ended"] >= ended + limit + 2


def test_solves_and_maps_run_on_the_cluster(cluster):
    backend = runs._Cluster(cluster)
    try:
        contact, options = _default()
        before = tasks_done(cluster, runs.SOLVE_TASK)
        cache = runs.ResultCache()
        result = backend.submit(contact.replace(w=0.39), options, None, cache).result(timeout=120)
        assert len(cache) == 1 and not result.traction.flags.writeable
        local = core.simulate_contact(contact.replace(w=0.39), **options)
        # the same run; in the full suite the worker's numbers matched this process's to 1e-15 but not to the
        # last bit once (fresh clone, cold numba cache: a summation order), so equal to rounding
        np.testing.assert_allclose(result.traction, local.traction, rtol=1e-12, atol=1e-13)
        assert tasks_done(cluster, runs.SOLVE_TASK) == before + 1
        # a map sweep on the cluster's executor: split in one chunk per worker thread, same table as here
        grid = np.linspace(0.1, 0.8, 3)
        table = core.sweep(grid, grid, backend.map_scheduler(), periods=3, dx=0.1, kernel="plane")
        serial = core.sweep(grid, grid, "serial", periods=3, dx=0.1, kernel="plane")
        assert table.attrs["backend"] == "_ClusterExecutor"
        assert list(table["regime"]) == list(serial["regime"])
    finally:
        backend.close()


def _in_a_thread(fn, *args):
    """Run ``fn`` in a thread of its own: sync Playwright refuses a thread where an earlier test left an asyncio loop."""
    with ThreadPoolExecutor(1) as pool:
        return pool.submit(fn, *args).result()


def _ready_within(request, seconds: float) -> bool:
    """Poll ``/liveness`` until it answers 200 with ``ready`` (True), or ``seconds`` pass (False)."""
    import time

    deadline = time.monotonic() + seconds
    while True:
        try:
            return bool(json.loads(urllib.request.urlopen(request, timeout=10).read())["ready"])
        except urllib.error.HTTPError as answer:
            if answer.code != 503 or time.monotonic() > deadline:
                return False
        time.sleep(2.0)


@pytest.mark.browser
@pytest.mark.timeout(900)  # the worker warms every kernel before it takes the session's run: minutes under load
def test_first_page_is_the_explorer_while_the_solver_is_prepared_then_its_runs_are_solved_on_the_cluster():
    """Until the solver is warm (here: the cluster has no worker yet) the page is the explorer already, with its
    sliders and the exact limit's prediction, and says the solver is being compiled; the verdict comes in the
    same page once a worker has joined, solved on the cluster; the served app says its backend is the cluster, and a
    slider's release is solved there too. (One served app for both: each took a server start and its warm-up.)"""
    _in_a_thread(_prepared_then_solved)


def _prepared_then_solved():
    import os
    import subprocess
    import sys

    from app.serving import ROOT, _stop

    with dask_cluster(workers=0) as address:
        info = {}
        with served_app(env={"SHAKEDOWN_SCHEDULER": address}, info=info, wait_ready=False) as url, \
                chromium() as browser:
            health = urllib.request.Request(info["base"] + "/liveness")
            with pytest.raises(urllib.error.HTTPError) as answer:
                urllib.request.urlopen(health, timeout=10)
            assert answer.value.code == 503 and not json.loads(answer.value.read())["ready"]
            page = browser.new_page()
            errors = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(url + "?ft=0.3&w=0.372", timeout=180_000)  # the first session may pay for imports
            page.get_by_text("compiling the solver (first start only)").first.wait_for(timeout=60_000)
            page.locator(".regime-note", has_text="eq 35 predicts").first.wait_for(timeout=30_000)
            assert page.evaluate(SLIDER_TITLES_JS) == ["ft = Ft/(μ Fn)", "w = W/a"]
            worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                                       "--no-nanny", "--no-dashboard", "--host", "127.0.0.1"], cwd=ROOT,
                                      env={**os.environ, "PYTHONPATH": str(ROOT)}, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL)
            try:
                # in the same page, no reload (measured under load 12 after a merge had staled the sphere's cache:
                # 290 s from the server's start, the worker warming every kernel first)
                page.locator(BADGE).first.wait_for(timeout=600_000)
                assert "w=0.372" in page.url
                # (at least one task: the joining worker may run a solve of its own before the session's)
                assert tasks_done(address, runs.SOLVE_TASK) >= 1, "the first run was solved on the cluster"
                # the run of the first page's grid needs only its own kernels: the warm-up goes on with the others
                # (and the figures' templates) after the verdict, so /liveness turns ready a little later
                assert _ready_within(health, 300), "/liveness did not turn ready after the worker joined"
                state = json.loads(urllib.request.urlopen(health, timeout=10).read())
                assert state["ready"] and state["backend"] == f"dask({address})", state
                # a slider's release: a new solve, on the cluster
                page.get_by_text("all numbers ▾").first.click()  # the cards with the solve's line, one click away
                page.locator(".cards").first.wait_for(timeout=30_000)
                before = tasks_done(address, runs.SOLVE_TASK)
                assert page.evaluate(_RELEASE_FT, [0.2917, 60_000]), "the re-solve came back"
                assert tasks_done(address, runs.SOLVE_TASK) == before + 1, "the re-solve ran on the cluster"
                assert errors == []
            finally:
                page.close()
                _stop(worker)
