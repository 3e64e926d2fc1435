"""Write the API reference page from ``core.__all__``: every public name, grouped by the module that defines it."""

from __future__ import annotations

import importlib
import inspect
import types
from pathlib import Path

#: Section titles, in the page's order, of the modules that define public names (others follow, titled by
#: their docstring's first line).
SECTIONS = {
    "core.analytical": "Closed-form results (the paper's exact formulas)",
    "core.contact": "Contacts in physical units",
    "core.schedule": "Loading schedules",
    "core.histories": "Loading histories",
    "core.bodies": "Bodies: the line contact",
    "core.point_contact": "Bodies: point contacts",
    "core.solver": "Solving the cycles (line contact)",
    "core.engine": "The march over the steps",
    "core.solver3d": "Solving the cycles (point contacts)",
    "core.halfspace": "The half-space operator (3D)",
    "core.result": "Results",
    "core.states": "Element states and zones",
    "core.convergence": "Error bars",
    "core.sweeps": "Maps of the (ft, w) plane and the numerical limit",
    "core.limits_search": "The numerical limit",
    "core.tasks": "Where sweeps run",
    "core.kernels": "Influence kernels",
    "core.approximations": "The paper's regressions",
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
    # constants: the first submodule that lists the very object in its __all__
    for sub in sorted(SECTIONS, key=list(SECTIONS).index):
        mod = importlib.import_module(sub)
        if name in getattr(mod, "__all__", ()) and getattr(mod, name, None) is obj:
            return sub
    return "core"


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
    for module in order:
        if module == "modules":
            title, note = "Submodules", "Modules exposed as a whole."
        else:
            doc = inspect.getdoc(importlib.import_module(module)) or ""
            title = SECTIONS.get(module) or (doc.splitlines()[0].rstrip(".") if doc else module)
            note = f"Defined in `{module}`."
        entries = "\n".join(f"   {n}" for n in sorted(groups[module], key=str.lower))
        parts.append(f"## {title}\n\n{note}\n\n```{{eval-rst}}\n.. currentmodule:: core\n\n.. autosummary::\n"
                     f"   :toctree: generated\n   :nosignatures:\n\n{entries}\n```\n")
    text = "\n".join(parts)
    path = Path(path)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
    return names
