"""Time a fresh install's first start: numba's cache empty, as on a new clone or a new virtual environment.

Usage: python benchmarks/cold_start.py [--skip-app] [--skip-cli]

With ``NUMBA_CACHE_DIR`` a new empty directory (so numba compiles the solver), it prints:

* the app, started as the README says (``panel serve app/main.py --plugins app.health
  --unused-session-lifetime 120000``, on a free loopback port, via :func:`app.serving.served_app`):
  from starting the command to the first page with the ft and w sliders and the exact limit's
  prediction in headless Chromium (the page is polled from the moment the server answers), to the
  first numerical verdict in that page, and to ``/liveness`` answering 200 (the whole warm-up:
  every kernel, the sphere's too);
* ``shakedown run --ft 0.3 --w 0.5`` with a cold cache, then again with the cache it filled (warm),
  wall time of each process, and whether it said once on stderr that it compiles.

Also the number of compiled signatures after the explorer's first run (``core.base._jit.KERNELS``).
The machine's load average is printed: on a shared machine the compile time grows with it.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

SLIDERS_AND_LIMIT = """
() => {
  const titles = new Set();
  let limit = false;
  for (const d of Bokeh.documents) for (const m of d.all_models) {
    if (['ft = Ft/(μ Fn)', 'w = W/a'].includes(m.title) && typeof m.value === 'number') titles.add(m.title);
    if (typeof m.text === 'string' && m.text.includes('predicts')) limit = true;
  }
  return titles.size === 2 && limit;
}
"""
VERDICT = "[data-regime='shakedown'], [data-regime='ratcheting'], [data-regime='undetermined']"


def _ready(base):
    try:
        with urllib.request.urlopen(base + "/liveness", timeout=5) as r:
            return json.loads(r.read())["ready"]
    except urllib.error.HTTPError:
        return False


def time_app() -> None:
    from app.serving import chromium, served_app, wait_until

    with tempfile.TemporaryDirectory() as cache:
        info = {}
        t0 = time.perf_counter()
        with served_app(env={"NUMBA_CACHE_DIR": cache}, wait_ready=False, info=info) as url, chromium() as browser:
            listening = time.perf_counter() - t0
            page = browser.new_page(viewport={"width": 1280, "height": 720})
            page.goto(url + "?ft=0.3&w=0.5", timeout=600_000)
            wait_until(lambda: page.evaluate(SLIDERS_AND_LIMIT), 600, interval=0.1, message="sliders and limit")
            first_page = time.perf_counter() - t0
            compiling = page.get_by_text("compiling the solver (first start only)").count() > 0
            page.locator(VERDICT).first.wait_for(timeout=1_200_000)
            verdict = time.perf_counter() - t0
            wait_until(lambda: _ready(info["base"]), 1200, interval=0.5, message="/liveness 200")
            warm = time.perf_counter() - t0
        print(f"app (cold numba cache): server listening {listening:.1f} s; first page with sliders and the exact "
              f"limit {first_page:.1f} s (compiling line shown: {compiling}); first numerical verdict "
              f"{verdict:.1f} s; /liveness ready (every kernel warm) {warm:.1f} s")


def time_cli() -> None:
    from core.base._jit import COMPILE_NOTE

    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(ROOT)}
        for label in ("cold", "warm"):
            t0 = time.perf_counter()
            p = subprocess.run([sys.executable, "-m", "core.command.cli", "run", "--ft", "0.3", "--w", "0.5"], env=env,
                               capture_output=True, text=True, cwd=ROOT)
            wall = time.perf_counter() - t0
            regime = next((line.split()[1] for line in p.stdout.splitlines() if line.strip().startswith("regime")),
                          "?")
            print(f"shakedown run --ft 0.3 --w 0.5 ({label} numba cache): {wall:.1f} s, exit {p.returncode}, "
                  f"regime {regime}, said it compiles: {p.stderr.count(COMPILE_NOTE)} time(s)")


def count_signatures() -> None:
    with tempfile.TemporaryDirectory() as cache:
        code = ("import core, core.base._jit as j; from app.state import ExplorerState; "
                "s = ExplorerState(); c, o = s.contact(), s.solver_options(); c.simulate(**o); "
                "print(sum(len(d.signatures) for d in j.KERNELS.values()), "
                "sum(1 for d in j.KERNELS.values() if d.signatures))")
        t0 = time.perf_counter()
        out = subprocess.run([sys.executable, "-c", code], env={**os.environ, "NUMBA_CACHE_DIR": cache,
                                                                "PYTHONPATH": str(ROOT)},
                             capture_output=True, text=True, cwd=ROOT)
        sigs, kernels = out.stdout.split()[-2:] if out.returncode == 0 else ("?", "?")
        print(f"the explorer's default first run (cold, in a process of its own): {time.perf_counter() - t0:.1f} s, "
              f"{sigs} compiled signatures of {kernels} kernels")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-app", action="store_true")
    parser.add_argument("--skip-cli", action="store_true")
    parser.add_argument("--skip-count", action="store_true")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    if not args.skip_app:
        time_app()
    if not args.skip_cli:
        time_cli()
    if not args.skip_count:
        count_signatures()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")


if __name__ == "__main__":
    main()
