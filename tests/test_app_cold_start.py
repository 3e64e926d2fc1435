"""Issue 29, item 4: on a fresh install (numba's cache empty) the first page is the explorer at once.

The server is started as the README says (``panel serve app/main.py --plugins app.health``) with
``NUMBA_CACHE_DIR`` a new directory that lacks the line solver's main kernels (``DenseSolver.kernels``, the ones a
first run announces as compiling: the march and the per-step solve the first page's run needs), so the warm-up
compiles the solver the first page runs. While it compiles (``/liveness`` 503) the page already has the ft and w
sliders, the exact limit's prediction and the line "compiling the solver (first start only), N s"; the verdict comes
into the same page when the run is done.

The rest of numba's cache is copied into that directory from the run's own (warm once the suite's precompile has
filled it, :mod:`tests.conftest`): an empty directory made the server compile every kernel of the line solver, a
minute and a half of one core in CI (92 s), for what compiling its two main kernels proves as well. (With the run's
cache cold nothing is copied, and the server compiles everything, as before.)
"""

import importlib
import inspect
import json
import os
import pkgutil
import shutil
import urllib.error
import urllib.request

import pytest

from app.serving import SLIDER_TITLES_JS, chromium, served_app

pytestmark = [pytest.mark.browser, pytest.mark.slow, pytest.mark.timeout(1800)]  # a cold compile: minutes

VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting'], [data-regime='undetermined']"
INVALID = "[data-regime='invalid']"


def _seed_all_but(cache, cold):
    """Copy numba's cached code of every kernel of core but ``cold`` from this run's cache into ``cache``, where a
    process with ``NUMBA_CACHE_DIR=cache`` looks for it; return the kernels copied."""
    import numba

    import core
    from core.base import _jit

    for info in pkgutil.walk_packages(core.__path__, "core."):  # every module's kernels into _jit.KERNELS
        if not info.ispkg and not info.name.endswith(("__main__", ".cli")):
            importlib.import_module(info.name)
    copied = []
    for name, dispatcher in _jit.KERNELS.items():
        if name in cold or not _jit._cached(dispatcher):
            continue
        index = dispatcher._cache._cache_file
        # numba's layout under NUMBA_CACHE_DIR: a folder per source folder (its name and a hash of its path)
        into = os.path.join(cache, numba.core.caching._CacheLocator.get_suitable_cache_subpath(
            inspect.getfile(dispatcher.py_func)))
        os.makedirs(into, exist_ok=True)
        for data in (*index._load_index().values(), os.path.basename(index._index_path)):
            shutil.copyfile(os.path.join(os.path.dirname(index._index_path), data), os.path.join(into, data))
        copied.append(name)
    return copied


def _liveness(base):
    try:
        with urllib.request.urlopen(base + "/liveness", timeout=10) as r:
            return json.loads(r.read())
    except urllib.error.HTTPError as e:
        return json.loads(e.read())


def test_first_page_has_sliders_and_the_exact_limit_while_the_solver_compiles(tmp_path, fresh_thread):
    fresh_thread(_cold_start, tmp_path)


def _cold_start(tmp_path):
    cache = tmp_path / "numba-cache"
    cache.mkdir()
    from core.solvers.dense import DenseSolver

    _seed_all_but(str(cache), DenseSolver.kernels)
    info = {}
    with served_app(env={"NUMBA_CACHE_DIR": str(cache)}, wait_ready=False, info=info) as url, chromium() as browser:
        page = browser.new_page()
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(url + "?ft=0.3&w=0.5", timeout=120_000)
        page.get_by_text("compiling the solver (first start only)").first.wait_for(timeout=120_000)
        page.locator(".regime-note", has_text="eq 35 predicts shakedown for ft = 0.30, w = 0.50").first.wait_for(
            timeout=60_000)
        assert page.evaluate(SLIDER_TITLES_JS) == ["ft = Ft/(μ Fn)", "w = W/a"]
        health = _liveness(info["base"])
        assert not health["ready"], f"the solver was ready already: the cache was not cold ({health})"
        shown = page.get_by_text("compiling the solver (first start only)").first.inner_text()
        assert shown.startswith("compiling the solver (first start only), ") and shown.endswith(" s"), shown
        # the verdict arrives in the same page (no reload), and the compiling line goes (a solve that failed, e.g.
        # one cut by its time budget while it compiled, shows the invalid badge: reported at once)
        page.locator(f"{VERDICT}, {INVALID}").first.wait_for(timeout=1_500_000)
        assert page.locator(INVALID).count() == 0, page.locator(".regime-note").first.inner_text()
        assert "w=0.5" in page.url
        assert page.get_by_text("compiling the solver (first start only)").count() == 0
        assert errors == []
        page.close()
