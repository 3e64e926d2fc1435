"""Shakedown Explorer core: the physics of a rocking cylindrical contact.

The public names are imported on first use (PEP 562 ``__getattr__``), so that
a light submodule such as :mod:`core.command.cli` (``shakedown --help``) starts
without importing numba, scipy and pandas. ``core.__all__`` lists them all
(asking for it imports them).

The modules live in one package per layer (``core.march.engine``, ``core.geometry.registry``, ...;
docs/dev/architecture.md). Their former flat names (``core.engine``, ``import core.solver3d``,
``from core import melan``, a pickle or a mock target naming ``core.result``) still import the same
module object, with a :class:`DeprecationWarning` naming the new one: an import hook, :class:`FormerNames`.
"""

import importlib
import importlib.util
import os
import sys
import threading
import warnings

# the thread running _load (its own look-ups inside it must fail fast); other threads wait on the lock,
# e.g. the app's warm-up thread loading core while the main thread reads core.PAPER_SIMULATION
_loading = None
_lock = threading.RLock()


def _load():
    with _lock:
        _load_locked()


def _load_locked():
    global _loading
    _loading = threading.get_ident()
    try:
        from .theory import analytical
        globals().update({name: getattr(analytical, name) for name in analytical.__all__})
        from .api.contact import Contact, PAPER_SIMULATION, PAPER_EXPERIMENT, BETA_WARNING_LEVEL  # noqa: F401
        from .theory import approximations  # noqa: F401
        from .loading import histories  # noqa: F401
        from .elastic.kernels import influence_matrix, strip_u0  # noqa: F401
        from .loading.schedule import Schedule, rocking_schedule  # noqa: F401
        from .loading.paths import LoadingPath  # noqa: F401
        from .base.states import State, Zone, STATE_NAMES, ZONE_NAMES, RESIDUAL_NAMES  # noqa: F401
        from .geometry.bodies import BODIES, Body, Cylinder, LineGrid, Punch, get_body, NORMAL_CHOICES  # noqa: F401
        from .pressure.normal import NormalSolution, solve_normal, solve_line, solve_patch  # noqa: F401
        from .pressure.melan import ft_limit_numerical  # noqa: F401
        from .bounds.limits import ft_limit, w_limit, fretting_energy  # noqa: F401 (any body's, by name or object: over analytical's eq 35)
        from .geometry.cone import Cone  # noqa: F401
        from .geometry.heightmap import HeightMap, HeightProfile  # noqa: F401
        from .records.result import CycleResult, LineResult, PerStep, StaticResult, SolverError, SolveCancelled  # noqa: F401
        from .march.engine import run, STEP_SOLVERS  # noqa: F401
        from .api.solver import (simulate_cycles, solve_schedule, solve_static, shakedown_state,  # noqa: F401
                             simulate_point_contact)
        from .api.contact import PointContact, simulate_contact, strip_options  # noqa: F401
        from .api.convergence import ConvergedIncrement, converged_increment, grid_error, increment_error  # noqa: F401
        from .geometry.resolution import default_dx  # noqa: F401
        from .theory.point_contact import Ellipsoid, Sphere, POINT_BODIES  # noqa: F401
        from .elastic.halfspace import HalfSpaceOperator  # noqa: F401
        from .api.point_runs import solve_point_schedule, mindlin_state, shakedown_state_3d  # noqa: F401
        from .records.result import PointContactResult  # noqa: F401
        from .maps.sweeps import (sweep, sweep_grid, run_points, numerical_w_limit, numerical_limit,  # noqa: F401
                             numerical_limit_curve, LimitResult, SweepCancelled, load_default_map)
        from .maps.coupled_limits import (coupled_limit, coupled_limit_curve, CoupledLimit,  # noqa: F401
                                     CoupledLimitCurve)
        public = {k: v for k, v in locals().items() if k != "analytical"}
        globals().update(public)
        # every public name, for ``from core import *`` and the documentation's API reference
        globals()["__all__"] = sorted({*analytical.__all__, *public})
    finally:
        _loading = None


def __getattr__(name):
    if name == "__all__" and _loading != threading.get_ident():
        _load()
        return globals()["__all__"]
    if name.startswith("__") or _loading == threading.get_ident():
        raise AttributeError(name)
    if importlib.util.find_spec(f"{__name__}.{name}") is not None:
        # a submodule (``from . import analytical`` inside a submodule): import just it,
        # not every public name, or a half-imported submodule would be imported again
        return importlib.import_module(f"{__name__}.{name}")
    _load()
    try:
        return globals()[name]
    except KeyError:
        raise AttributeError(f"module 'core' has no attribute {name!r}") from None


def __dir__():
    _load()
    return sorted(globals())


def former_names() -> dict[str, str]:
    """Each module's former flat name (before the layer packages) -> its name now.

    Returns
    -------
    dict
        ``{"core.engine": "core.march.engine", ...}``: every module of every layer package.
    """
    here = os.path.dirname(__file__)
    out = {}
    for layer in sorted(os.listdir(here)):
        if os.path.isfile(os.path.join(here, layer, "__init__.py")):
            for file in sorted(os.listdir(os.path.join(here, layer))):
                if file.endswith(".py") and file != "__init__.py":
                    out.setdefault(f"{__name__}.{file[:-3]}", f"{__name__}.{layer}.{file[:-3]}")
    return out


def _caller_level() -> int:
    """The ``stacklevel`` of the first frame outside importlib and this file (the import statement), counted as
    :func:`warnings.warn` counts: it skips importlib's bootstrap frames by itself."""
    frame, level = sys._getframe(2), 2  # the caller of the function that warns
    while frame is not None:
        name = frame.f_code.co_filename
        if not ("importlib" in name and "_bootstrap" in name):
            if name not in (__file__, importlib.__file__):
                return level
            level += 1
        frame = frame.f_back
    return level


# move_core: former names (the script that made the layer packages leaves the former names here as they are)
class FormerNames:
    """The import hook of the former module names: ``core.X`` imports ``core.<layer>.X``, with a warning.

    A finder of :data:`sys.meta_path` and its own loader (the protocols of :class:`importlib.abc.MetaPathFinder`
    and :class:`importlib.abc.Loader`, not subclassed: importing ``importlib.abc`` would cost every start). The
    same module object under both names (so a mock target or ``monkeypatch.setattr`` on the former name
    patches the module the code uses), a :class:`DeprecationWarning` naming the new one on the first import.
    """

    _names: dict[str, str] | None = None

    def _new_name(self, fullname: str) -> str | None:
        if not fullname.startswith(f"{__name__}.") or fullname.count(".") != 1:
            return None
        if os.path.isdir(os.path.join(os.path.dirname(__file__), fullname.partition(".")[2])):
            return None  # a layer package (``import core.march``): the usual finders have it, no table needed
        if FormerNames._names is None:
            FormerNames._names = former_names()
        return FormerNames._names.get(fullname)

    def find_spec(self, fullname, path=None, target=None):
        """A spec for a former name, None for any other."""
        return importlib.util.spec_from_loader(fullname, self) if self._new_name(fullname) else None

    def create_module(self, spec):
        """The module under its new name (imported if need be): the former name is an alias of it."""
        new = self._new_name(spec.name)
        warnings.warn(f"{spec.name} is now {new} (core's layer packages, issue 28): import it from there",
                      DeprecationWarning, stacklevel=_caller_level())
        return importlib.import_module(new)

    def exec_module(self, module):
        """Nothing to run: the module ran under its new name."""

    def get_code(self, fullname):
        """For ``python -m core.X``: :func:`_run_former_main`'s code, which :mod:`runpy` runs as ``__main__`` and
        which runs the new module there (the new module's own code would need its package for its relative
        imports), with the warning."""
        new = self._new_name(fullname)
        warnings.warn(f"{fullname} is now {new} (core's layer packages, issue 28): run python -m {new}",
                      DeprecationWarning, stacklevel=2)
        return _run_former_main.__code__


def _run_former_main():
    """Run as the code of ``python -m core.X`` (a former name): ``python -m core.<layer>.X`` in its place."""
    import runpy

    import core

    runpy.run_module(core.FormerNames()._new_name(__spec__.name), run_name="__main__", alter_sys=True)


if not any(type(finder).__name__ == "FormerNames" and type(finder).__module__ == __name__
           for finder in sys.meta_path):
    # first: a former name is this package's module even where another finder (an editable install of another
    # checkout, a stale copy) could find a file of that name
    sys.meta_path.insert(0, FormerNames())
