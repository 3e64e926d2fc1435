"""core/ in layers (issue 28): one package per layer, and every import of a core module, those inside functions
included, goes to a module of its own layer or of a layer below; the imports form no cycle. Read with ast; no
allow-list. A module's layer is the package it lives in: there is no list of modules here.

The layers, bottom to top (docs/dev/architecture.md draws them): utilities (``base``) -> closed forms
(``theory``) -> loading histories (``loading``) -> elasticity (``elastic``) -> the normal solve and Melan's
integral (``pressure``) -> bodies (``geometry``: geometry, grids, the registry, their defaults) -> limits by name
(``bounds``) -> results (``records``: records, verdict) -> per-step solvers (``solvers``) -> engine (``march``) ->
API (``api``: simulate, static solves, convergence, export, units) -> maps (``maps``: sweeps, tables, tasks, the
limit search) -> command line (``command``). ``core/__init__.py`` is the package's facade over all of them (it
imports its public names on first use), above every layer: no layer imports from it.
"""

import ast
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
CORE = ROOT / "core"

#: The layer packages of core/, bottom to top: a module's layer is its package's place here.
PACKAGES = ["base", "theory", "loading", "elastic", "pressure", "geometry", "bounds", "records", "solvers", "march",
            "api", "maps", "command"]
LEVEL = {package: level for level, package in enumerate(PACKAGES)}
#: The facade, ``core`` itself: above every layer.
FACADE = len(PACKAGES)


def module_files(root: pathlib.Path = CORE) -> dict[str, pathlib.Path]:
    """Every module of the layers, ``"core.<package>.<module>"`` (a package's ``__init__`` as ``"core.<package>"``)
    -> its file."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        if parts == ("__init__",):
            continue
        name = ".".join(("core", *parts[:-1])) if parts[-1] == "__init__" else ".".join(("core", *parts))
        out[name] = path
    return out


def layer_of(name: str) -> int | None:
    """The level of module ``name`` (``"core"``: the facade); None for a flat module or an unknown package."""
    parts = name.split(".")
    if parts == ["core"]:
        return FACADE
    return LEVEL.get(parts[1]) if len(parts) in (2, 3) and parts[0] == "core" else None


def imports(path: pathlib.Path, name: str, known) -> list[tuple[int, str]]:
    """(line, core module) of every import in file ``path`` of module ``name``, at any depth (functions, methods,
    branches); ``known`` holds the modules, so that ``from core.base import _jit`` is module ``core.base._jit``."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                if node.level - 1 >= len(base):
                    raise AssertionError(f"{path}:{node.lineno}: a relative import above core/")
                base = ".".join(base[:len(base) - (node.level - 1)])
                target = f"{base}.{node.module}" if node.module else base
            elif (node.module or "").split(".")[0] == "core":
                target = node.module
            else:
                continue
            subs = [f"{target}.{alias.name}" for alias in node.names if f"{target}.{alias.name}" in known]
            out.extend((node.lineno, sub) for sub in subs)
            if len(subs) < len(node.names):  # names from the module (or package) itself
                out.append((node.lineno, target))
        elif isinstance(node, ast.Import):
            out.extend((node.lineno, alias.name) for alias in node.names if alias.name.split(".")[0] == "core")
    return out


def graph(root: pathlib.Path = CORE) -> dict[str, set[str]]:
    """Module -> the core modules it imports (itself left out)."""
    files = module_files(root)
    return {name: {m for _, m in imports(path, name, files) if m != name} for name, path in files.items()}


def upward(root: pathlib.Path = CORE) -> list[str]:
    """Every import that goes up a layer, to the facade, to a flat module name or to an unknown package."""
    files = module_files(root)
    out = []
    for name, path in files.items():
        own = layer_of(name)
        for line, target in imports(path, name, files):
            level = layer_of(target)
            where = f"{path.relative_to(root.parent)}:{line}"
            if level is None:
                out.append(f"{where} imports {target}: not a module of a layer package")
            elif own is not None and level > own:
                above = "the facade" if level == FACADE else PACKAGES[level]
                out.append(f"{where} ({PACKAGES[own]}) imports {target} ({above})")
    return out


def misplaced(root: pathlib.Path = CORE) -> list[str]:
    """Flat modules left in core/, packages that are not layers, layers that are missing."""
    flat = [f"{p.relative_to(root.parent)}: a flat module (put it in its layer's package)"
            for p in sorted(root.glob("*.py")) if p.name != "__init__.py"]
    dirs = {p.parent.relative_to(root).as_posix() for p in root.rglob("__init__.py") if p.parent != root}
    unknown = [f"core/{d}: a package that is not a layer of tests/test_layers.py" for d in sorted(dirs - set(PACKAGES))]
    loose = [f"{p.relative_to(root.parent)}: a module outside a package" for p in sorted(root.rglob("*.py"))
             if not (p.parent / "__init__.py").exists()]
    missing = [f"core/{d}: a layer without its package" for d in PACKAGES if d not in dirs]
    return flat + unknown + loose + missing


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_every_module_is_in_a_layer_package():
    problems = misplaced()
    assert not problems, "core/ is not one package per layer:\n" + "\n".join(problems)


def test_no_import_goes_up_a_layer():
    found = upward()
    assert not found, "imports up a layer:\n" + "\n".join(found)


def test_no_import_cycle():
    assert cycles(graph()) == []


def _tree(root: pathlib.Path, files: dict[str, str]) -> pathlib.Path:
    for rel, text in {"__init__.py": "", **files}.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)
    return root


def test_the_checks_can_fail(tmp_path):
    """A function-level upward import, an import of the facade, a flat module, an unknown package, a missing
    layer and a two-module cycle are all found; imports below are not."""
    layers = {f"{p}/__init__.py": "" for p in PACKAGES}
    core = _tree(tmp_path / "core", {
        **layers,
        "base/states.py": "from . import progress\n",
        "base/progress.py": "def f():\n    from ..march.engine import run\n    import core.command.cli\n",
        "march/engine.py": "from ..base import states\nfrom core.base.progress import f\nfrom .. import Contact\n",
        "odd/__init__.py": "",
        "flat.py": "",
    })
    files = module_files(core)
    assert imports(files["core.base.progress"], "core.base.progress", files) == [
        (2, "core.march.engine"), (3, "core.command.cli")]
    assert imports(files["core.march.engine"], "core.march.engine", files) == [
        (1, "core.base.states"), (2, "core.base.progress"), (3, "core")]
    found = upward(core)
    assert any("progress.py:2 (base) imports core.march.engine (march)" in f for f in found), found
    assert any("progress.py:3 (base) imports core.command.cli (command)" in f for f in found), found
    assert any("engine.py:3 (march) imports core (the facade)" in f for f in found), found
    assert not any("engine.py:1" in f or "engine.py:2" in f for f in found), found
    problems = misplaced(core)
    assert any("core/flat.py: a flat module" in p for p in problems), problems
    assert any("core/odd: a package that is not a layer" in p for p in problems), problems
    assert misplaced(_tree(tmp_path / "two" / "core", {"base/__init__.py": ""}))[-1].endswith(
        "core/command: a layer without its package")
    # states -> progress -> (in a function) engine -> states
    assert cycles(graph(core)) == [["core.base.progress", "core.base.states", "core.march.engine"]]
    assert cycles({"a": {"b"}, "b": {"a"}, "c": {"a"}}) == [["a", "b"]]
    (core / "base" / "progress.py").write_text("def f():\n    return 1\n")
    assert cycles(graph(core)) == []
    (core / "march" / "engine.py").write_text("from ..base import progress\n")
    (core / "base" / "progress.py").write_text("def f():\n    from core.march import engine\n")
    assert cycles(graph(core)) == [["core.base.progress", "core.march.engine"]]


#: One interpreter that has imported the heavy third-party packages and no module of core forks a child per module
#: and imports it there: each child starts with no core module imported, as a fresh interpreter would, without
#: paying numpy's, scipy's and numba's imports 50 times (a subprocess each cost 60-75 s CPU in all).
_IMPORT_ALONE = """
import os, sys, traceback
import numpy, scipy.linalg, scipy.optimize, scipy.sparse, numba
assert not [m for m in sys.modules if m == "core" or m.startswith("core.")]
failed = []
for name in sys.argv[1:]:
    sys.stdout.flush(), sys.stderr.flush()
    pid = os.fork()
    if pid == 0:
        try:
            __import__(name)
        except BaseException:
            print(name, file=sys.stderr)
            traceback.print_exc()
            sys.stderr.flush()
            os._exit(1)
        os._exit(0)
    if os.waitpid(pid, 0)[1] != 0:
        failed.append(name)
print(" ".join(failed))
"""


@pytest.mark.slow
def test_each_module_imports_alone():
    """``import core.<package>.<module>`` with no other module of core imported first, for every module (a
    forked child of an interpreter that imported no core): no module needs another imported before it."""
    modules = sorted(m for m in module_files() if m.count(".") == 2)
    assert len(modules) > 40
    done = subprocess.run([sys.executable, "-c", _IMPORT_ALONE, *modules], capture_output=True, text=True,
                          timeout=600, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "", f"these modules do not import alone: {done.stdout}\n{done.stderr[-3000:]}"


@pytest.mark.parametrize("module", ["core.command.cli", "core.geometry.resolution"])
def test_light_modules_stay_light(module):
    """The command line's help reads these: importing them imports no numba (a subprocess, fresh)."""
    code = f"import sys, {module}; print('numba' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"
