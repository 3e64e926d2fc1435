"""The app's modules: each imports on its own, and their imports form no cycle (one job per module).

The graph is read from the source (``ast``), over every ``app/*.py``: a module-level or a function-level
import of another app module is an edge; the test finds any cycle by depth-first search.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

APP = Path(__file__).resolve().parent.parent / "app"
MODULES = sorted(p.stem for p in APP.glob("*.py") if p.stem != "__init__")
#: Modules that must not build, solve or evaluate physics of their own: they are checked to call no solver.
_SOLVERS = ("simulate_cycles", "simulate_contact", "solve_schedule", "solve_point_schedule")


def _imports(name: str) -> set[str]:
    """The app modules that ``app/<name>.py`` imports (anywhere in the file)."""
    tree = ast.parse((APP / f"{name}.py").read_text(encoding="utf-8"))
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1:  # from . import x / from .x import y
                if node.module:
                    out.add(node.module.split(".")[0])
                else:
                    out.update(a.name for a in node.names)
            elif node.module and node.module.startswith("app."):
                out.add(node.module.split(".")[1])
            elif node.module == "app":
                out.update(a.name for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name.split(".")[1] for a in node.names if a.name.startswith("app."))
    return {m for m in out if m in MODULES and m != name}


def _cycle(graph: dict) -> list | None:
    """A cycle of ``graph`` as a list of nodes, or None."""
    state, stack = {}, []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        state[node] = "done"
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def test_the_app_modules_import_each_other_without_a_cycle():
    graph = {m: _imports(m) for m in MODULES}
    assert _cycle(graph) is None, f"import cycle: {' -> '.join(_cycle(graph))}"
    # the search finds a cycle when there is one (the test can fail)
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]


def test_the_explorer_is_split_into_modules_of_one_job():
    for name in ("styles", "widgets", "scheduling", "player", "figures", "cards", "mapview", "downloads", "layout"):
        assert name in MODULES
    assert len((APP / "explorer.py").read_text(encoding="utf-8").splitlines()) < 300


@pytest.mark.parametrize("name", [m for m in MODULES if m not in ("main", "health")])
def test_each_app_module_imports_on_its_own(name):
    module = importlib.import_module(f"app.{name}")
    assert module.__doc__, f"app/{name}.py has no module docstring"
    missing = [n for n in getattr(module, "__all__", ()) if not hasattr(module, n)]
    assert not missing, f"app.{name}.__all__ names what it does not define: {missing}"


def test_no_app_module_runs_the_solver_itself():
    """Runs go through app.runs (the cache and the worker pool); the other modules call no solver of core."""
    for name in MODULES:
        if name in ("runs", "health"):
            continue
        text = (APP / f"{name}.py").read_text(encoding="utf-8")
        assert not any(f"core.{s}(" in text for s in _SOLVERS), name


def test_the_map_names_plots_exported_are_the_regime_maps():
    """The map's layers moved from app.plots to app.regime_map: the public names plots exported are the same
    objects, and the map is one entry of plots.FIGURES like every figure."""
    from app import plots, regime_map

    for name in ("map_base", "map_numerical", "map_point", "grid_boundary"):
        assert name in plots.__all__ and getattr(plots, name) is getattr(regime_map, name), name
    assert plots.FIGURES["map"]["layers"] is regime_map.layers and plots.FIGURES["map"]["specs"] is regime_map.specs
