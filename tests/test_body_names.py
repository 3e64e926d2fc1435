"""The registry is the only code that knows body names (issue 28): no body name is compared as a string in core/
or app/ outside core/geometry/registry.py. Read with ast: every comparison (==, !=, in, not in) with a string constant that
is a registered body's name, or a tuple/list/set of such constants, is a switch on body names."""

import ast
import pathlib

import pytest

from core.geometry.registry import REGISTRY

ROOT = pathlib.Path(__file__).resolve().parents[1]
ALLOWED = {ROOT / "core" / "geometry" / "registry.py"}


def _names_in(node) -> list[str]:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value] if node.value in REGISTRY else []
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [n for elt in node.elts for n in _names_in(elt)]
    return []


def _switches(source: str) -> list[tuple[int, list[str]]]:
    """(line, names) of every comparison with body names in ``source``."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            names = [n for side in (node.left, *node.comparators) for n in _names_in(side)]
            if names:
                out.append((node.lineno, names))
    return out


def test_the_scan_finds_a_switch():
    """The check can fail: a comparison with a body's name is found, on either side and in a tuple."""
    source = "def f(body):\n    return body == 'cylinder' or body in ('punch', 'x') or 'sphere' != body or body == 'x'\n"
    assert [names for _, names in _switches(source)] == [["cylinder"], ["punch"], ["sphere"]]


@pytest.mark.parametrize("package", ["core", "app"])
def test_no_body_name_is_compared_outside_the_registry(package):
    found = [f"{path.relative_to(ROOT)}:{line} compares with {names}"
             for path in sorted((ROOT / package).rglob("*.py")) if path not in ALLOWED
             for line, names in _switches(path.read_text())]
    assert not found, "body names compared outside core/geometry/registry.py:\n" + "\n".join(found)
