"""core/base/_jit.py: a run says once per process, before it waits, that numba compiles the solver, and only when
its kernels are neither compiled in this process nor in numba's on-disk cache (issue 29)."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = str(Path(__file__).resolve().parent.parent)

_SCRIPT = textwrap.dedent("""
    import json, logging, sys
    sys.path.insert(0, sys.argv[1])
    import core.base._jit as j
    import tiny_kernel

    said = [j.announce_compile("tiny_kernel.double", "no.such.kernel")]
    said.append(j.announce_compile("tiny_kernel.double"))  # once per process
    value = tiny_kernel.double(2.0)
    print(json.dumps({"said": said, "value": value, "registered": "tiny_kernel.double" in j.KERNELS}))
""")


def _run(tmp_path, cache):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": ROOT}
    p = subprocess.run([sys.executable, "-c", _SCRIPT, str(tmp_path)], capture_output=True, text=True, env=env,
                       timeout=300, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    import json
    return json.loads(p.stdout.strip().splitlines()[-1]), p.stderr


def test_the_first_compile_is_announced_once_and_not_when_cached(tmp_path):
    from core.base._jit import COMPILE_NOTE

    (tmp_path / "tiny_kernel.py").write_text("from core.base._jit import jit\n\n\n@jit\ndef double(x):\n"
                                             "    return 2.0 * x\n")
    cache = tmp_path / "numba-cache"
    cache.mkdir()
    cold, err = _run(tmp_path, cache)
    assert cold == {"said": [True, False], "value": 4.0, "registered": True}
    assert err.count(COMPILE_NOTE) == 1, err  # on stderr: logging's last resort, nothing configured
    warm, err = _run(tmp_path, cache)  # a new process: numba's cache has it now
    assert warm["said"] == [False, False] and COMPILE_NOTE not in err, err


def test_a_kernel_compiled_in_this_process_is_not_announced():
    import core
    from core.base import _jit

    core.simulate_cycles(0.1, 0.2, periods=1, dx=0.25)  # compiled (or loaded) here
    assert _jit.KERNELS["core.solvers._pdas.march"].signatures
    before = _jit._ANNOUNCED
    try:
        _jit._ANNOUNCED = False
        assert _jit.announce_compile("core.solvers._pdas.march", "core.solvers._pdas.solve_step") is False
    finally:
        _jit._ANNOUNCED = before


def test_a_kernel_cache_index_is_read_once_per_process(monkeypatch):
    # a kernel called only from other kernels never gets a signature of its own: its on-disk index was read again
    # at every run (three of them, ~2 ms, at each coupled run)
    import core  # noqa: F401 - registers the kernels
    from core.base import _jit

    reads = []
    monkeypatch.setattr(_jit, "_cached", lambda d: reads.append(d) or True)
    monkeypatch.setattr(_jit, "_ANNOUNCED", False)
    monkeypatch.setattr(_jit, "_LOOKED_AT", set())
    names = sorted(n for n, d in _jit.KERNELS.items() if not d.signatures)[:3]
    assert len(names) == 3
    assert _jit.announce_compile(*names) is False and len(reads) == 3
    assert _jit.announce_compile(*names) is False and len(reads) == 3
    assert _jit.announce_compile(*names, "no.such.kernel") is False and len(reads) == 3
