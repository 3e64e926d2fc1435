"""Issue 6, item 5: no user input ever reaches eval, exec, a shell, or a file path of the server.

A static scan of the served code (``app/`` except the test harness
``app/serving.py``, and ``core/``) for the calls through which input could be
executed or name a file; plus a check that the app's downloads are built in
memory. The CLI's ``--out FILE`` is the command-line user's own path on their
own machine, and is the only file path taken from input.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SERVED = sorted(p for p in (ROOT / "app").glob("*.py") if p.name != "serving.py") + sorted((ROOT / "core").rglob("*.py"))
FORBIDDEN_CALLS = {"eval", "exec", "compile", "__import__", "system", "popen", "Popen", "run", "call",
                   "check_call", "check_output", "loads"}  # loads: pickle/marshal
ALLOWED: dict = {
    # (file, call): why it is safe. Empty: nothing needs an exception today.
}


def _calls(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None
            owner = f.value.id if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) else None
            yield name, owner, node.lineno


@pytest.mark.parametrize("path", SERVED, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_dynamic_execution_shell_or_unpickling(path):
    bad = []
    for name, owner, line in _calls(path):
        if name in FORBIDDEN_CALLS and (path.name, name) not in ALLOWED:
            if name == "loads" and owner == "json":
                continue  # json is data, not code
            if name == "compile" and owner == "re":
                continue  # a regular expression (e.g. the pattern that checks a URL's value), not code
            if name == "run" and owner not in {"subprocess", "os"}:
                continue  # e.g. asyncio/doc methods named run
            if name == "call" and owner not in {"subprocess", "os"}:
                continue
            bad.append(f"{path.name}:{line} {owner + '.' if owner else ''}{name}()")
    assert not bad, "calls that could execute input: " + ", ".join(bad)


@pytest.mark.parametrize("path", [p for p in SERVED if p.parent.name == "app"], ids=lambda p: p.name)
def test_the_served_app_opens_no_file(path):
    """The app never opens a file: nothing a browser sends can become a path."""
    opened = [line for name, owner, line in _calls(path) if name == "open" and owner in (None, "io", "os")]
    assert not opened, f"{path.name} opens files at lines {opened}"


def test_downloads_are_built_in_memory():
    text = (ROOT / "app" / "downloads.py").read_text(encoding="utf-8")  # since the app split
    assert "FileDownload" in text and ("BytesIO" in text or "StringIO" in text)


def test_an_upload_is_read_from_memory_and_writes_nothing(tmp_path):
    """An uploaded height map (a good one and one no reader understands: every reader of SurfaceTopography
    tries it) is read from memory: Python's audit events record no file opened for writing, no directory
    made and no temporary file while the explorer stores it and builds its body."""
    import os
    import sys
    import threading

    import numpy as np
    from SurfaceTopography import Topography

    from app import bodies

    n, h = 24, 0.1
    x = (np.arange(n) - n // 2) * h
    X, Y = np.meshgrid(x, x, indexing="ij")
    path = tmp_path / "bowl.nc"
    Topography(-0.375 * (X**2 + Y**2), (n * h, n * h)).to_netcdf(str(path))
    good, bad = path.read_bytes(), b"not a height map at all\n" * 40
    writes, watching, me = [], [False], threading.get_ident()
    write_flags = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC

    def hook(event, args):  # an audit hook cannot be removed: it records only while this test watches
        if not watching[0] or threading.get_ident() != me:
            return
        if event == "open":
            file, mode, flags = args
            if (isinstance(mode, str) and any(c in mode for c in "wax+")) or (flags or 0) & write_flags:
                writes.append((event, file, mode, flags))
        elif event in ("os.mkdir", "os.rename", "os.remove", "shutil.copyfile", "tempfile.mkstemp",
                       "tempfile.mkdtemp"):
            writes.append((event, args))

    # the solver's compiled kernels are loaded from numba's cache on their first use, which checks that the cache
    # directory is writable (a temporary file): not the upload's doing, and in the suite an earlier test has
    # usually loaded them; load them here so that the test does not depend on the order
    # (another file: an upload is read once per content, and the one below must be read while watched)
    warm = tmp_path / "warm.nc"
    Topography(-0.3 * (X**2 + Y**2), (n * h, n * h)).to_netcdf(str(warm))
    bodies.make("heightmap", {"file": bodies.store_upload(warm.read_bytes(), "warm.nc")})
    sys.addaudithook(hook)
    watching[0] = True
    try:
        source = bodies.store_upload(good, "bowl.nc")
        body = bodies.make("heightmap", {"file": source})
        unreadable = bodies.store_upload(bad, "notes.txt")
        with pytest.raises(ValueError, match="notes.txt is in no format that can be read"):
            bodies.make("heightmap", {"file": unreadable})
    finally:
        watching[0] = False
    assert body.heights.shape == (n, n)
    assert not writes, f"an upload touched the disk: {writes[:5]}"
