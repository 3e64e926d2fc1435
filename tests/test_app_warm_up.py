"""app.runs' warm-up groups: a session's first solve waits for its own grid's solver only (issue 29)."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = str(Path(__file__).resolve().parent.parent)

_SCRIPT = textwrap.dedent("""
    from app import runs

    calls = []
    assert runs.warmed("line") and runs.warming_seconds() is None  # no warm-up started: nothing to wait for
    runs.on_warm("line", lambda: calls.append("now"))
    assert calls == ["now"]
    calls.clear()
    runs._STARTED.append(0.0)  # as start_warm_up does
    assert not runs.warmed("line") and runs.warming_seconds() > 0
    runs.on_warm("line", lambda: calls.append("line"))
    runs.on_warm("point", lambda: calls.append("point"))
    runs._warmed("line")
    assert calls == [], calls  # the strip kernel's run: the plane kernel's follows
    runs._warmed("line")
    assert calls == ["line"] and runs.warmed("line") and not runs.warmed("point")
    runs.on_warm("line", lambda: calls.append("at once"))
    assert calls == ["line", "at once"]
    runs._warmed("point", done=True)  # a warm-up that ended (or failed) releases every group
    assert calls == ["line", "at once", "point"] and runs.warmed("point")
    print("ok")
""")


def test_sessions_wait_for_their_own_grids_solver():
    p = subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True, text=True, timeout=300, cwd=ROOT,
                       env={**os.environ, "PYTHONPATH": ROOT})
    assert p.returncode == 0 and p.stdout.strip().endswith("ok"), p.stderr[-3000:]
