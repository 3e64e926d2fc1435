"""The runs of a sweep: every combination of ``ft``, ``w`` and the option axes, checked before any work.

Any keyword option of :func:`core.simulate_cycles` (the body, the loading
history, the resolution, ...) may be given; a list makes it a further axis.
The options are validated by the solver itself (one tiny run per option
combination), so a sweep accepts exactly what :func:`core.simulate_cycles`
accepts, now and when it grows new options.

Bounded work: a sweep may have at most :func:`default_max_runs` runs, and every run at
most :func:`default_max_cells` (steps x elements, the size of the per-step arrays).
Both default to the constants :data:`MAX_RUNS` and :data:`MAX_CELLS` and can be
set by the operator with the environment variables ``SHAKEDOWN_MAX_RUNS`` and
``SHAKEDOWN_MAX_CELLS`` or per call.
"""

from __future__ import annotations

import functools
import inspect
import itertools
import math

import numpy as np

from ..base._validate import check_int, check_range, check_scalar, env_int
from ..geometry.resolution import default_dx

__all__ = ["sweep_grid", "solver_defaults", "default_max_runs", "default_max_cells", "run_cells", "MAX_RUNS",
           "MAX_CELLS", "W_MAX"]

#: Default cap on the number of runs of one sweep (env ``SHAKEDOWN_MAX_RUNS``).
MAX_RUNS = 20_000
#: Default cap on steps x elements of one run, about 9 bytes each in memory
#: (env ``SHAKEDOWN_MAX_CELLS``); the default resolution needs about 2e5.
MAX_CELLS = 25_000_000
#: Widest rocking ``W / a`` a sweep or a limit search may ask for.
W_MAX = 0.999
# per-call hooks of simulate_cycles, not options of a run
_HOOKS = ("ft", "w", "cancel", "progress")
# the options every table has a column for (the others only when given)
_ALWAYS = ("periods", "dx", "kernel", "shape")


def default_max_runs() -> int:
    """Largest number of runs a sweep may have: ``$SHAKEDOWN_MAX_RUNS``, else :data:`MAX_RUNS`."""
    return env_int("SHAKEDOWN_MAX_RUNS", MAX_RUNS)


def default_max_cells() -> int:
    """Largest steps x elements of one run: ``$SHAKEDOWN_MAX_CELLS``, else :data:`MAX_CELLS`."""
    return env_int("SHAKEDOWN_MAX_CELLS", MAX_CELLS)


def solver_defaults() -> dict:
    """The keyword options of :func:`core.simulate_cycles` (read from its signature), with their defaults."""
    from ..api.solver import simulate_cycles

    return {name: p.default for name, p in inspect.signature(simulate_cycles).parameters.items()
            if name not in _HOOKS and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)}


def axis(name: str, value, lo, hi, *, hi_closed=False, lo_closed=True) -> list[float]:
    """A number or a 1-D sequence of numbers in a range, as a list of floats (at least one)."""
    arr = check_range(name, value, lo, hi, lo_closed=lo_closed, hi_closed=hi_closed)
    if arr.ndim > 1:
        raise ValueError(f"{name} must be a number or a 1-D sequence, got an array of shape {arr.shape}")
    arr = np.atleast_1d(arr)
    if arr.size == 0:
        raise ValueError(f"{name} must have at least one value")
    return [float(v) for v in arr]


def is_axis(value) -> bool:
    """Whether an option value is a list of values (an axis) rather than one value."""
    import pandas as pd

    return isinstance(value, (list, tuple, range, np.ndarray, pd.Series, pd.Index)) and np.ndim(value) > 0


def _plain(value):
    """NumPy scalars to Python scalars (for tables, keys and pickling)."""
    return value.item() if isinstance(value, np.generic) else value


def _option_axes(options: dict) -> dict[str, list]:
    defaults = solver_defaults()
    unknown = sorted(set(options) - set(defaults))
    if unknown:
        raise ValueError(f"unknown solver option(s) {', '.join(map(repr, unknown))}; "
                         f"expected some of {', '.join(defaults)}")
    axes = {name: [defaults[name]] for name in _ALWAYS}
    for name, value in options.items():
        values = list(value) if is_axis(value) else [value]
        if not values:
            raise ValueError(f"{name} must have at least one value")
        axes[name] = [_plain(v) for v in values]
    return axes


@functools.lru_cache(maxsize=4096)
def _cells(w: float, items: tuple) -> tuple[int, int] | None:
    """(steps, elements) of a cylinder run with rocking amplitude ``w`` and these options (None if unknown)."""
    from ..loading.schedule import rocking_schedule
    from ..api.solver import MAX_ELEMENTS, MAX_FFT_ELEMENTS, make_grid

    from ..geometry.registry import kind, resolve

    option = dict(items)
    defaults = solver_defaults()
    body = option.get("body")
    if kind(body) != "line" or resolve(body) != resolve() or option.get("history") not in (None, "rocking"):
        return None  # another body or history: the solver checks its own size
    dx = check_scalar("dx", option.get("dx") or default_dx("cylinder"), 1e-4, 0.5)
    dW = option.get("dW")
    schedule = rocking_schedule(0.0, w, periods=option.get("periods", defaults["periods"]),
                                dW=dx if dW is None else dW, shape=option.get("shape", defaults["shape"]),
                                load_steps=option.get("load_steps", defaults["load_steps"]))
    cap = MAX_ELEMENTS if option.get("solver") == "dense" else MAX_FFT_ELEMENTS  # as the solver's own
    return len(schedule), make_grid(schedule.reach, dx, cap).size - 1


def run_cells(point: dict) -> int | None:
    """Steps x elements of one run (the size of its per-step arrays; None if it cannot be told beforehand)."""
    items = tuple(sorted((k, v) for k, v in point.items() if k not in ("ft", "w")))
    size = _cells(float(point["w"]), items)
    return None if size is None else size[0] * size[1]


def _check_option(ft_values, w_values, option: dict, cells_cap: int) -> None:
    """Check one option combination before any work: its largest run against the cell cap, then
    every option as the solver sees it (a one-period run at rest, which raises the solver's own
    ``ValueError`` for a bad value)."""
    from ..api.solver import simulate_cycles

    w = max(w_values)
    items = tuple(sorted(option.items()))
    size = _cells(w, items)
    if size is not None and size[0] * size[1] > cells_cap:
        steps, elements = size
        described = ", ".join(f"{k} = {v}" for k, v in option.items())
        raise ValueError(f"a run at w = {w:g} ({described}) would have {steps} steps x {elements} "
                         f"elements = {steps * elements:.3g} cells (> {cells_cap:.3g}, see SHAKEDOWN_MAX_CELLS): "
                         "use fewer periods or a larger dx")
    try:
        simulate_cycles(0.0, 0.0, **{**option, "periods": 1})
    except ValueError:
        raise
    except Exception:  # noqa: BLE001 - not about the inputs (e.g. a tiny time budget); the runs will tell
        pass


def sweep_grid(ft, w, *, max_runs: int | None = None, max_cells: int | None = None, **solver_options) -> list[dict]:
    """The runs of a sweep: every combination of ``ft``, ``w`` and the option axes, in order.

    Parameters
    ----------
    ft : float or sequence of float
        ``Ft / (mu Fn)`` values, each in (-1, 1).
    w : float or sequence of float
        ``W / a`` values, each in [0, 1).
    max_runs : int, optional
        Cap on the number of runs (default :func:`default_max_runs`, 20000).
    max_cells : int, optional
        Cap on steps x elements of each run (default :func:`default_max_cells`).
    **solver_options
        Any keyword option of :func:`core.simulate_cycles` (``periods``,
        ``dx``, ``kernel``, the body, the loading history, ...). A list,
        tuple, range or array makes that option a further axis; a scalar (or
        a string) is fixed.

    Returns
    -------
    list of dict
        One dict of keyword arguments of :func:`core.simulate_cycles` per run,
        ``ft`` varying slowest, then ``w``, then the options in the order
        given. Each has ``ft``, ``w``, ``periods``, ``dx`` (the body's
        default grid, :func:`core.geometry.resolution.default_dx`, unless given),
        ``kernel``, ``shape`` and every option given.

    Raises
    ------
    ValueError
        For values out of range, unknown options, or a grid beyond the caps.

    Examples
    --------
    >>> from core import sweep_grid
    >>> [(p["ft"], p["w"], p["periods"]) for p in sweep_grid([0.1, 0.2], 0.5, periods=[5, 10])]
    [(0.1, 0.5, 5), (0.1, 0.5, 10), (0.2, 0.5, 5), (0.2, 0.5, 10)]
    """
    ft_values = axis("ft", ft, -1.0, 1.0, lo_closed=False)
    w_values = axis("w", w, 0.0, 1.0)
    axes = _option_axes(solver_options)
    runs_cap = default_max_runs() if max_runs is None else check_int("max_runs", max_runs, 1)
    cells_cap = default_max_cells() if max_cells is None else check_int("max_cells", max_cells, 1)
    n = len(ft_values) * len(w_values) * math.prod(len(v) for v in axes.values())
    if n > runs_cap:
        raise ValueError(f"the sweep would have {n} runs (> {runs_cap}, see SHAKEDOWN_MAX_RUNS): "
                         "use fewer values or raise the cap")
    names = list(axes)
    combos = [dict(zip(names, values)) for values in itertools.product(*axes.values())]
    for option in combos:  # the body's own default grid (core/geometry/resolution.py), recorded in the table
        if option.get("dx") is None:
            option["dx"] = default_dx(option.get("body", "cylinder"))
    for option in combos:
        _check_option(ft_values, w_values, option, cells_cap)
    return [{"ft": f, "w": x, **option} for f, x in itertools.product(ft_values, w_values) for option in combos]
