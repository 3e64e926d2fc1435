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


def test_the_warm_up_compiles_the_coupled_solver_after_the_first_pages():
    """A coupled contact's solver (Dundurs beta != 0, kernels of its own) is warmed at start, in a group of its own
    and after the first page's line solver, whose readiness it does not delay."""
    from app import runs

    assert len(runs._WARM_RUNS) == len(runs._WARM_GROUPS)
    assert runs._WARM_GROUPS[:2] == ("line", "line")  # the first page's strip kernel, then the plane one: as before
    assert runs._WARM_GROUPS.count("coupled") == 1 and runs._WARM_GROUPS[-1] == "coupled"
    r = runs._WARM_RUNS[runs._WARM_GROUPS.index("coupled")]()
    assert r.coupled and r.beta != 0.0 and r.regime != "error"


def test_a_coupled_session_waits_for_the_coupled_solver(monkeypatch):
    from app import runs
    from app.explorer import Explorer
    from app.runs import LimitCurves
    from app.state import ExplorerState

    # the coupled limit curve the explorer starts for a coupled contact: on a tiny grid (a second's work)
    monkeypatch.setattr(runs, "LIMIT_CURVES", LimitCurves(grid=dict(w=(0.3,), dx=1 / 10, tol=0.2, periods=10)))
    s = ExplorerState()
    e = Explorer(s)
    assert e._solver_group() == "line"
    s.param.update(materials="steel/aluminium", mu=0.3)
    assert e.contact.coupled and e._solver_group() == "coupled"
    s.materials = "rigid/incompressible"  # beta = 0: the uncoupled line solver
    assert e._solver_group() == "line"
