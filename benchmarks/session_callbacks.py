"""Do a served session's updates from threads all arrive? Coupled pages, several at once, beside a busy core.

Each page is steel on aluminium at its own friction coefficient (a coupled limit curve of its own, computed in the
server's curve thread and sent to the page amplitude by amplitude, :class:`app.runs.LimitCurves`). A page whose
status does not read "coupled limit: 5 amplitudes" within ``--wait`` seconds after its batch was opened lost an
update: its curve was computed (the curves of the pages after it came), the page never heard.

Before ``app.runs.call_in_session`` the threads added the document's next-tick callbacks themselves, racing the event
loop's holds of the document: 6 of 18 pages, 6 at once with one core busy, never heard the end of their curve (a
CI run's browser test waited 300 s for one). The figures: pages opened, pages stuck, the curves' CPU seconds,
the load. Prints a line per batch; ``--out FILE`` appends the summary.

Run: python benchmarks/session_callbacks.py [--pages 36] [--at-once 6] [--burn 1] [--mu0 0.70] [--wait 90]
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
DONE = "coupled limit: 5 amplitudes"


def _burn(seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass


def main(argv=None) -> int:
    from app.serving import chromium, open_page, served_app

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pages", type=int, default=36)
    ap.add_argument("--at-once", type=int, default=6)
    ap.add_argument("--burn", type=int, default=1, help="cores kept busy meanwhile (default 1)")
    ap.add_argument("--mu0", type=float, default=0.70, help="the first page's mu (each next one + 0.005)")
    ap.add_argument("--wait", type=float, default=90.0)
    ap.add_argument("--out", type=Path)
    args = ap.parse_args(argv)
    mus = [round(args.mu0 + 0.005 * i, 3) for i in range(args.pages)]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    burners = [mp.Process(target=_burn, args=(3600.0,), daemon=True) for _ in range(args.burn)]
    stuck, cpu, t0 = [], [], time.monotonic()
    with served_app(env={"SHAKEDOWN_SOLVE_BUDGET_S": "300"}) as url, chromium() as browser:
        for b in burners:
            b.start()
        try:
            while mus:
                batch, mus = mus[:args.at_once], mus[args.at_once:]
                pages = {}
                for mu in batch:
                    page = open_page(browser, f"{url}?materials=steel/aluminium&ft=0.5&w=0.3&mu={mu}&periods=6",
                                     ready="[data-regime]:not([data-regime='pending'])", timeout_ms=300_000)
                    page.locator(".place-map").first.scroll_into_view_if_needed(timeout=60_000)
                    pages[mu] = page
                deadline, waiting = time.monotonic() + args.wait, dict(pages)
                while waiting and time.monotonic() < deadline:
                    for mu, page in list(waiting.items()):
                        text = page.locator(".coupled-status-text").first.inner_text()
                        if DONE in text:
                            cpu.append(float(re.search(r"coupled runs, (\d+) s CPU", text).group(1)))
                            del waiting[mu]
                    time.sleep(0.5)
                for mu, page in waiting.items():
                    text = page.locator(".coupled-status-text").first.inner_text()
                    stuck.append((mu, text))
                    print(f"  stuck: mu {mu}: {text}", flush=True)
                print(f"{time.monotonic() - t0:5.0f} s: mu {batch[0]}-{batch[-1]}, {len(stuck)} stuck so far "
                      f"(load average {os.getloadavg()[0]:.1f})", flush=True)
                for page in pages.values():
                    page.close()
        finally:
            for b in burners:
                b.terminate()
    summary = (f"{time.strftime('%Y-%m-%d %H:%M')} {commit}: {args.pages} pages, {args.at_once} at once, "
               f"{args.burn} core(s) busy: {len(stuck)} stuck, {args.pages - len(stuck)} heard their whole curve "
               f"(curves {min(cpu, default=0):.0f}-{max(cpu, default=0):.0f} s CPU each), "
               f"{time.monotonic() - t0:.0f} s")
    print(summary)
    if args.out:
        with open(args.out, "a") as f:
            f.write(summary + "\n" + "".join(f"  stuck: mu {mu}: {text}\n" for mu, text in stuck))
    return 1 if stuck else 0


if __name__ == "__main__":
    sys.exit(main())
