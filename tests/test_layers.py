"""core/ in layers (issue 28): every import of a core module, those inside functions included, goes to a module of
its own layer or of a layer below, and the imports form no cycle. Read with ast; no allow-list.

The layers, bottom to top (docs/dev/architecture.md draws them): utilities -> closed forms -> loading histories ->
elasticity -> the normal solve and Melan's integral -> bodies (geometry, grids, the registry, their defaults) ->
limits by name -> results (records, verdict) -> per-step solvers -> engine -> API (simulate, static solves,
convergence, export, units) -> maps (sweeps, tables, tasks, the limit search) -> command line. ``core/__init__.py``
is the package's facade over all of them (it imports its public names on first use) and imports from every layer.
"""

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
CORE = ROOT / "core"

#: Each module of core/ and its layer (a new module must be given one: the test fails on an unknown module).
LAYERS = {
    "utilities": ["_validate", "_jit", "_hertz", "states", "progress"],
    "closed forms": ["analytical", "approximations", "punch", "point_contact", "materials"],
    "histories": ["paths", "schedule", "histories"],
    "elasticity": ["kernels", "operators", "halfspace", "coupling"],
    "normal": ["normal", "melan"],
    "bodies": ["bodies", "heightmap", "cone", "patch", "registry", "resolution"],
    "limits": ["limits"],
    "results": ["verdict", "static_result", "result"],
    "solvers": ["_pdas", "_pcg", "_pcg3d", "_coupled", "dense", "matrix_free", "solver3d", "coupled"],
    "engine": ["engine"],
    "api": ["solver", "point_runs", "contact", "convergence", "export"],
    "maps": ["grid", "tasks", "tables", "limits_search", "coupled_limits", "sweeps", "paper_figures"],
    "cli": ["cli_values", "cli"],
}
LEVEL = {module: level for level, modules in enumerate(LAYERS.values()) for module in modules}


def imports(path: pathlib.Path) -> list[tuple[int, str]]:
    """(line, module of core) of every import in ``path``, at any depth (functions, methods, branches)."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1 or (node.level == 0 and (node.module or "").split(".")[0] == "core"):
                base = (node.module or "") if node.level else (node.module or "").partition(".")[2]
                if base:
                    out.append((node.lineno, base.split(".")[0]))
                else:  # from . import a, b
                    out.extend((node.lineno, alias.name) for alias in node.names)
            elif node.level > 1:
                raise AssertionError(f"{path}:{node.lineno}: a relative import above core/")
        elif isinstance(node, ast.Import):
            out.extend((node.lineno, alias.name.split(".")[1]) for alias in node.names
                       if alias.name.startswith("core."))
    return out


def graph() -> dict[str, set[str]]:
    """Module -> the core modules it imports (the facade ``__init__`` left out)."""
    return {path.stem: {m for _, m in imports(path) if m != path.stem}
            for path in sorted(CORE.glob("*.py")) if path.stem != "__init__"}


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


def test_every_module_has_a_layer():
    unknown = sorted(set(graph()) - set(LEVEL))
    assert not unknown, f"modules of core/ without a layer in tests/test_layers.py: {unknown}"
    gone = sorted(set(LEVEL) - set(graph()))
    assert not gone, f"layers name modules that are not in core/: {gone}"


def test_no_import_goes_up_a_layer():
    upward = [f"core/{path.name}:{line} ({LAYERS_NAME[LEVEL[path.stem]]}) imports {m} ({LAYERS_NAME[LEVEL[m]]})"
              for path in sorted(CORE.glob("*.py")) if path.stem in LEVEL
              for line, m in imports(path) if m in LEVEL and LEVEL[m] > LEVEL[path.stem]]
    assert not upward, "imports up a layer:\n" + "\n".join(upward)


def test_no_import_cycle():
    assert cycles(graph()) == []


LAYERS_NAME = list(LAYERS)


def test_the_checks_can_fail(tmp_path):
    """A function-level upward import and a two-module cycle are both found."""
    probe = tmp_path / "probe.py"
    probe.write_text("from . import states\n\ndef f():\n    from .engine import run\n    import core.command.cli\n")
    assert imports(probe) == [(1, "states"), (4, "engine"), (5, "cli")]
    assert cycles({"a": {"b"}, "b": {"a"}, "c": {"a"}}) == [["a", "b"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


@pytest.mark.parametrize("module", ["core.command.cli", "core.geometry.resolution"])
def test_light_modules_stay_light(module):
    """The command line's help reads these: importing them imports no numba (a subprocess, fresh)."""
    import subprocess
    import sys

    code = f"import sys, {module}; print('numba' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"
