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
SERVED = sorted(p for p in (ROOT / "app").glob("*.py") if p.name != "serving.py") + sorted((ROOT / "core").glob("*.py"))
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
