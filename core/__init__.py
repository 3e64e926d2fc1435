"""Shakedown Explorer core: the physics of a rocking cylindrical contact.

The public names are imported on first use (PEP 562 ``__getattr__``), so that
a light submodule such as :mod:`core.command.cli` (``shakedown --help``) starts
without importing numba, scipy and pandas. ``core.__all__`` lists them all
(asking for it imports them).
"""

import importlib
import importlib.util
import threading

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
