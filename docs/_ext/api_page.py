"""Write the API reference page from ``core.__all__``: every public name, grouped by the module that defines it."""

from __future__ import annotations

import importlib
import re
import inspect
import types
from pathlib import Path

#: Section titles, in the page's order, of the modules that define public names (others follow, titled by
#: their docstring's first line).
SECTIONS = {
    "core.theory.analytical": "Closed-form results (the paper's exact formulas)",
    "core.api.contact": "Contacts in physical units",
    "core.loading.schedule": "Loading schedules",
    "core.loading.histories": "Loading histories",
    "core.geometry.bodies": "Bodies: the line contacts",
    "core.theory.punch": "Bodies: the rounded flat punch",
    "core.theory.point_contact": "Bodies: point contacts",
    "core.geometry.cone": "Bodies: the rocking cone (its limit)",
    "core.geometry.heightmap": "Bodies: a sampled profile or height map",
    "core.geometry.registry": "The body registry",
    "core.pressure.normal": "The normal problem",
    "core.pressure.melan": "Melan's exact limit of any body",
    "core.geometry.resolution": "Default grids",
    "core.api.solver": "Solving the cycles (line contact)",
    "core.march.engine": "The march over the steps",
    "core.solvers.solver3d": "Solving the cycles (point contacts)",
    "core.elastic.halfspace": "The half-space operator (3D)",
    "core.records.result": "Results",
    "core.base.states": "Element states and zones",
    "core.api.convergence": "Error bars",
    "core.maps.sweeps": "Maps of the (ft, w) plane and the numerical limit",
    "core.maps.limits_search": "The numerical limit",
    "core.maps.tasks": "Where sweeps run",
    "core.maps.grid": "The runs of a sweep",
    "core.maps.tables": "Sweep tables",
    "core.elastic.kernels": "Influence kernels",
    "core.theory.approximations": "The paper's regressions",
}

HEADER = """\
% This page is written by docs/_ext/api_page.py at every build, from core.__all__: do not edit it.

# API reference

Every public name of the package {mod}`core`, one page each, grouped by the module that defines it.
They are all importable from `core` itself (`core.simulate_cycles`, `core.Contact`, ...), which
imports them on first use. The analytical functions take numpy arrays and broadcast like ufuncs.
Normalised units: lengths in the half-width $a$, tractions in $\\mu p_0$, $f_t = F_t/(\\mu F_n)$,
$w = W/a$; displacements in $\\mu P/E^*$.

```{eval-rst}
.. automodule:: core
   :no-members:
   :no-index:
```
"""


def defining_module(core, name: str) -> str:
    """The name of the submodule of ``core`` that defines the public name ``name``."""
    obj = getattr(core, name)
    if isinstance(obj, types.ModuleType):
        return "modules"
    module = getattr(obj, "__module__", None) if (inspect.isclass(obj) or callable(obj)) else None
    if isinstance(module, str) and module.startswith("core."):
        return module
    # constants: of the submodules that list the very object in their __all__, the one that documents it
    # with a ``#:`` comment (where it is defined), else the first
    candidates = [sub for sub in SECTIONS if name in getattr(_module(sub), "__all__", ())
                  and getattr(_module(sub), name, None) is obj]
    for sub in candidates:
        if data_doc(sub, name):
            return sub
    return candidates[0] if candidates else "core"


def _module(name: str):
    """The module ``name``, or None if this checkout's core has no such file (a title kept for later)."""
    core = importlib.import_module("core")
    if not (Path(core.__file__).parent.joinpath(*name.split(".")[1:]).with_suffix(".py")).exists():
        return None
    return importlib.import_module(name)


def is_data(obj) -> bool:
    """A constant (not a class, a function or a module): documented with ``py:data``, not autosummary."""
    return not (inspect.isclass(obj) or callable(obj) or isinstance(obj, types.ModuleType))


def data_doc(module: str, name: str) -> str:
    """The ``#:`` comment (or docstring after the assignment) of ``name`` in ``module``'s source."""
    from sphinx.pycode import ModuleAnalyzer

    try:
        docs = ModuleAnalyzer.for_module(module).find_attr_docs()
    except Exception:  # no source (a compiled module)
        return ""
    return "\n".join(docs.get(("", name), [])).strip()


def _data_entry(core, module: str, name: str) -> str:
    """A ``py:data`` entry of the constant ``core.<name>``: its value (when short) and its description."""
    value = repr(getattr(core, name))
    option = f"   :value: {value}\n" if len(value) <= 80 and "\n" not in value else ""
    doc = data_doc(module, name) if module.startswith("core.") else ""
    # ``|x|`` outside literals would be a reStructuredText substitution: escape the bars there
    doc = "".join(part if i % 2 else part.replace("|", "\\|") for i, part in enumerate(re.split(r"(``.*?``)", doc)))
    body = "\n".join(f"   {line}" if line else "" for line in doc.splitlines())
    return f".. py:data:: {name}\n   :module: core\n{option}\n{body}\n"


def write_api_page(path: Path, core) -> list[str]:
    """Write the page to ``path`` (only when its text changes) and return the names it lists."""
    names = list(core.__all__)
    groups: dict[str, list[str]] = {}
    for name in names:
        groups.setdefault(defining_module(core, name), []).append(name)
    order = [m for m in SECTIONS if m in groups] + sorted(m for m in groups if m not in SECTIONS and m != "modules")
    if "modules" in groups:
        order.append("modules")
    parts = [HEADER]
    stubs = {f"core.{n}.rst" for n in names if not is_data(getattr(core, n))}
    generated = Path(path).parent / "generated"
    if generated.is_dir():  # stubs of names no longer on the page (renamed, removed, or now a constant)
        for stale in generated.glob("core.*.rst"):
            if stale.name not in stubs:
                stale.unlink()
    for module in order:
        if module == "modules":
            title, note = "Submodules", "Modules exposed as a whole."
        else:
            doc = inspect.getdoc(importlib.import_module(module)) or ""
            title = SECTIONS.get(module) or (doc.splitlines()[0].rstrip(".") if doc else module)
            note = f"Defined in `{module}`."
        names_here = sorted(groups[module], key=str.lower)
        objects = [n for n in names_here if not is_data(getattr(core, n))]
        data = [n for n in names_here if is_data(getattr(core, n))]
        block = ".. currentmodule:: core\n"
        if objects:
            entries = "\n".join(f"   {n}" for n in objects)
            block += f"\n.. autosummary::\n   :toctree: generated\n   :nosignatures:\n\n{entries}\n"
        for n in data:
            block += "\n" + _data_entry(core, module, n)
        parts.append(f"## {title}\n\n{note}\n\n```{{eval-rst}}\n{block}```\n")
    text = "\n".join(parts)
    path = Path(path)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
    return names
