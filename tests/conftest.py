"""Shared test helpers (fixtures, so they work under --import-mode=importlib)."""

import os

import numpy as np
import pytest

# the servers the tests start check every page's Bokeh model graph (errors in their log fail the load test);
# a production server skips it (app/health.py)
os.environ.setdefault("BOKEH_VALIDATE_DOC", "true")

# ---- numba's cache, filled once before the first test (the workers start and collect meanwhile) ----
#: Small runs through the public API that compile (or load) the solver's numba kernels, in two groups run side by
#: side: the line solvers (dense and FFT, both kernels, the punch, the coupled march, a sampled profile's run) and the
#: patch solver (the sphere, as the served app warms it, the ellipsoid, the cone's twist, a height map). The point
#: group starts with the sampled profile's normal solve (its exact limit: core.pressure.normal's three kernels, 10 s
#: of CPU cold, which no other line run uses) and the verdict's fit (core.records._fit, which no run of one period
#: needs): the line group, the longer, reaches that profile's run last, some
#: 90 s later, and loads them from the cache instead of compiling them (line 108 s and point 85 s of CPU in CI's
#: precompile before: about even after).
_PRECOMPILE = {
    "line": """
import core
for kernel, L in (("strip", 10.0), ("plane", None)):
    for solver in ("dense", "fft"):
        core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, kernel=kernel, L_over_a=L, solver=solver)
core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, body=core.Punch(flat=0.5))
core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, beta=0.25, mu=0.3)  # the coupled march
import numpy as np
from core.geometry.heightmap import HeightProfile
x = np.linspace(-2, 2, 401)
core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, body=HeightProfile((2 / np.pi) * x**2, x[1] - x[0]))
""",
    "point": """
import numpy as np
import core
from core.geometry.heightmap import HeightMap, HeightProfile
x = np.linspace(-2, 2, 401)
core.ft_limit(0.2, body=HeightProfile((2 / np.pi) * x**2, x[1] - x[0]))  # the line group's profile's normal kernels
from core.records.verdict import fit_trend
fit_trend([1.0, 0.5, 0.25, 0.125, 0.0625])  # the verdict's fit (4 periods or more; 5 s of CPU cold)
core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25, body="sphere")
core.simulate_cycles(0.1, 0.2, periods=1, body="ellipsoid", ratio=2.0)
core.simulate_cycles(0.1, 0.2, periods=1, body="cone")
X, Y = np.meshgrid(np.arange(-40, 41) * 0.05, np.arange(-40, 41) * 0.05)
core.simulate_cycles(0.1, 0.2, periods=1, body=HeightMap(0.375 * (X**2 + Y**2), 0.05))
""",
}


def _numba_cache_is_cold() -> bool:
    """Whether some kernel of core has no code in numba's on-disk cache (a fresh clone, an edited module)."""
    import importlib
    import pkgutil

    import core
    from core.base import _jit

    for info in pkgutil.walk_packages(core.__path__, "core."):  # the layer packages and their modules
        if not info.ispkg and not info.name.endswith(("__main__", ".cli")):
            importlib.import_module(info.name)
    return any(not _jit._cached(kernel) for kernel in _jit.KERNELS.values())


@pytest.hookimpl(trylast=True)  # after the terminal's and xdist's own set-up, before xdist starts its workers
def pytest_configure(config):
    """Under pytest-xdist, before the workers start: on a cold numba cache (CI's fresh clone), start compiling the
    solver once, here, in two processes side by side, instead of in every worker and every served app at once
    (each compiled the same kernels: 300-430 s for a worker's first solve, 2 cores shared by four compiling
    processes). The tests that are about compiling use a cache directory of their own (test_jit,
    test_app_cold_start). The run waits for them in :func:`pytest_runtestloop`: the workers start and collect
    meanwhile (collecting compiles nothing: 20 s of CPU a worker, on the core the shorter group leaves idle)."""
    import subprocess
    import sys
    import time

    if hasattr(config, "workerinput") or not config.getoption("numprocesses", None) or not _numba_cache_is_cold():
        return
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [root, os.environ.get("PYTHONPATH")]))}
    config._shakedown_precompile = (time.monotonic(), {
        group: subprocess.Popen([sys.executable, "-c", code], cwd=root, env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True) for group, code in _PRECOMPILE.items()})


@pytest.hookimpl(hookwrapper=True, tryfirst=True)
def pytest_runtestloop(session):
    """Before xdist hands out the first test (its workers have started and collected meanwhile): wait for the
    compile that :func:`pytest_configure` started, if it did."""
    precompile = getattr(session.config, "_shakedown_precompile", None)
    if precompile is not None:
        import time

        t0, procs = precompile
        say = session.config.get_terminal_writer().line
        for group, proc in procs.items():
            out, _ = proc.communicate()
            if proc.returncode:  # the tests compile what is missing, and the failing run fails its own tests
                say(f"conftest: compiling the {group} solver failed ({proc.returncode}):\n{out[-2000:]}")
        say(f"conftest: numba's cache was cold; the solver compiled once, before the first test, in "
            f"{time.monotonic() - t0:.0f} s (the workers started and collected meanwhile)")
    yield


def pytest_unconfigure(config):
    """A run that ends before its first test (a collection error, Ctrl-C) stops the compile it started."""
    for proc in getattr(config, "_shakedown_precompile", (None, {}))[1].values():
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


# ---- the order of the run: the longest first, the tests of the shared served app together ----
#: Test modules run before the others, in this order (the rest keep pytest's order). pytest-xdist's worksteal hands
#: the first half of the collection to one worker and the second half to the other, and an idle worker takes the
#: later half of the other's queue: with the longest tests at the front they start at once and the run ends on short
#: ones, and the modules of the served app of :func:`app_url` (a session fixture: one server per worker that uses it,
#: 15 s of CPU to warm) run together. They are half the suite's wall time (2243 of 4290 s, -n 2 at load 6.6), so the
#: other worker takes some of them in the end and warms a server too; the two workers ended 24 s apart
#: (benchmarks/results/suite_time_s5.txt). The wall times of each module's longest test: the last fresh-clone CI run
#: (main c5094f7, -n 2), then the run of suite_time_s5 (-n 2, load 6.6); update them from CI's --durations list.
RUN_FIRST = (
    "test_docs.py",  # the Sphinx build with the executed gallery and notebook: 102 s; 198 s
    "test_app_cold_start.py",  # the served app compiling the line solver's main kernels: 92 s in CI when it compiled
    # all of them (343 s at load 6 here, 107 s with the two main ones only, suite_time_s7)
    "test_loadtest.py",  # a server of its own: 43 s; 67 s
    "test_verdict_limits.py",  # the sphere's limit search at a/20: 56 s
    "test_verdict_rule.py",  # the slow cone's verdicts: 39 s; 64 s
    # the served app of app_url: the first of these on a worker pays its warm-up
    "test_app_teacher_numbers_browser.py",  # closing tabs mid-update: 54 s; 127 s
    "test_paper_figures.py",  # the Paper-tab in Chromium: 45 s; 46 s
    "test_app_layout.py",  # a session after an expired one: 85 s
    "test_app_bodies_browser.py", "test_app_browser.py", "test_app_coupling.py", "test_app_first_screen.py",
    "test_app_point_browser.py", "test_app_review_browser.py", "test_app_teacher_layout_browser.py",
    "test_fretting_layout_browser.py", "test_regimes_browser.py",
)


def pytest_collection_modifyitems(config, items):
    """Run :data:`RUN_FIRST`'s modules first, in its order; every other test keeps its place after them (a stable
    sort: a module's tests stay together and in order, so its module fixtures are made once)."""
    here = os.path.dirname(os.path.abspath(__file__))
    rank = {name: i for i, name in enumerate(RUN_FIRST)}

    def place(item):
        path = str(item.path)
        return rank.get(os.path.basename(path), len(rank)) if os.path.dirname(path) == here else len(rank)

    items.sort(key=place)


# ---- where the suite's time goes: SHAKEDOWN_TEST_TIMES=FILE appends a JSON line per test ----
@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """With ``SHAKEDOWN_TEST_TIMES=FILE``: each test's wall and CPU seconds (set-up, call and tear-down; CPU is this
    process's and its waited-for children's, user + sys: a server a fixture stops counts at its tear-down), its
    xdist worker, its start and end (epoch s) and the 1-minute load, one JSON line a test, appended to FILE (both
    workers write to it). On a shared machine CPU is the figure to compare; the ends tell whether the workers
    ended together."""
    path = os.environ.get("SHAKEDOWN_TEST_TIMES")
    if not path:
        yield
        return
    import json
    import resource
    import time

    def cpu():
        own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime

    start, t0, c0 = time.time(), time.monotonic(), cpu()
    yield
    record = {"test": item.nodeid, "wall": round(time.monotonic() - t0, 2), "cpu": round(cpu() - c0, 2),
              "worker": os.environ.get("PYTEST_XDIST_WORKER", "main"), "start": round(start, 1),
              "end": round(time.time(), 1), "load": round(os.getloadavg()[0], 2)}
    with open(path, "a") as f:  # one short write: the workers' lines do not interleave
        f.write(json.dumps(record) + "\n")


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

    with served_app(env={"SHAKEDOWN_SOLVE_BUDGET_S": "300"}, log_path=app_log, extra_apps=[PAPER_FIGURES_APP]) as url:
        yield url


#: The "Paper's figures" tab alone (``tests/test_paper_figures.py``), served beside ``app/main.py`` by the server of
#: :func:`app_url` (it started a server of its own: a second warm-up, 30-40 s).
PAPER_FIGURES_APP = "tests/paper_figures_app.py"


@pytest.fixture(scope="session")
def paper_figures_url(app_url):
    """The URL of :data:`PAPER_FIGURES_APP` on the server of :func:`app_url`."""
    return app_url.rsplit("/", 1)[0] + "/" + os.path.splitext(os.path.basename(PAPER_FIGURES_APP))[0]


@pytest.fixture(scope="module")
def browser():
    from app.serving import chromium

    with chromium() as b:
        yield b
