"""Input validation shared by every public function of :mod:`core`.

Each public entry point coerces and checks its inputs once, here, and raises a
``ValueError`` that names the parameter, the offending value and the allowed
range, so that the API, the command line and the app all speak the same way.
"""

from __future__ import annotations

from numbers import Real

import os

import numpy as np

__all__ = ["read_only", "as_float_array", "check_range", "check_scalar", "check_int", "env_int"]


def _describe(lo, hi, lo_closed, hi_closed):
    left = "[" if lo_closed and lo is not None else "("
    right = "]" if hi_closed and hi is not None else ")"
    lo_s = "-inf" if lo is None else f"{lo:g}"
    hi_s = "inf" if hi is None else f"{hi:g}"
    return f"{left}{lo_s}, {hi_s}{right}"


def as_float_array(name: str, value) -> np.ndarray:
    """Coerce ``value`` to a float64 array; raise ``ValueError`` naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise ValueError(f"{name} must be a number or an array of numbers, got {value!r:.60}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name} must be a number or an array of numbers, got {value!r:.60}") from e
    return arr


def check_range(
    name: str,
    value,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_closed: bool = True,
    hi_closed: bool = True,
    allow_nan: bool = False,
    allow_inf: bool = False,
) -> np.ndarray:
    """Return ``value`` as a float array after checking ``lo <= value <= hi``.

    Parameters
    ----------
    name : str
        The parameter's name, used in the error message.
    value : array_like
        The value(s) to check.
    lo, hi : float or None
        Bounds; ``None`` means unbounded on that side.
    lo_closed, hi_closed : bool
        Whether each bound is itself allowed.
    allow_nan : bool
        Whether NaN entries pass (they are then ignored by the range check).
    allow_inf : bool
        Whether +-inf may pass (if inside the range); by default they are refused.

    Raises
    ------
    ValueError
        If any entry is NaN (unless allowed), infinite where the range is
        finite, or outside the range. The message names ``name``.
    """
    arr = as_float_array(name, value)
    rng = _describe(lo, hi, lo_closed, hi_closed)
    nan = np.isnan(arr)
    if nan.any() and not allow_nan:
        raise ValueError(f"{name} must be a number in {rng}, got NaN")
    ok = ~nan
    vals = arr[ok]
    if not allow_inf and np.isinf(vals).any():
        raise ValueError(f"{name} must be a finite number in {rng}, got {float(vals[np.isinf(vals)].flat[0])}")
    bad = np.zeros(vals.shape, dtype=bool)
    if lo is not None:
        bad |= (vals < lo) if lo_closed else (vals <= lo)
    if hi is not None:
        bad |= (vals > hi) if hi_closed else (vals >= hi)
    if bad.any():
        first = vals[bad].flat[0]
        raise ValueError(f"{name} must be in {rng}, got {float(first)!r}")
    return arr


def check_scalar(name: str, value, lo=None, hi=None, *, lo_closed=True, hi_closed=True, allow_inf=False) -> float:
    """Check a scalar real parameter and return it as a Python float."""
    if isinstance(value, bool) or not isinstance(value, (Real, np.floating, np.integer)):
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value.item()
        else:
            raise ValueError(f"{name} must be a real number, got {value!r:.60}")
    return float(check_range(name, float(value), lo, hi, lo_closed=lo_closed, hi_closed=hi_closed,
                             allow_inf=allow_inf))


def check_int(name: str, value, lo: int, hi: int | None = None) -> int:
    """Check an integer parameter in ``[lo, hi]`` and return it as ``int``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        if isinstance(value, (float, np.floating)) and float(value).is_integer():
            value = int(value)
        else:
            raise ValueError(f"{name} must be an integer in [{lo}, {hi if hi is not None else 'inf'}], got {value!r:.60}")
    value = int(value)
    if value < lo or (hi is not None and value > hi):
        raise ValueError(f"{name} must be an integer in [{lo}, {hi if hi is not None else 'inf'}], got {value}")
    return value


def env_int(name: str, default: int, lo: int = 1, hi: int | None = None) -> int:
    """An operator's integer setting: environment variable ``name`` (``default`` if unset or empty).

    Raises
    ------
    ValueError
        If the variable is set to anything but an integer in ``[lo, hi]``; the
        message names the variable, so a typo stops start-up instead of being
        silently replaced by the default.
    """
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    try:
        return check_int(name, int(raw.strip()), lo, hi)
    except ValueError:
        positive = " (set the environment variable to a positive integer)" if lo >= 1 else ""
        raise ValueError(f"{name} must be an integer in [{lo}, {hi if hi is not None else 'inf'}], "
                         f"got {raw!r:.40}{positive}") from None


def read_only(arr):
    """``arr`` with its write flag cleared (results and grids are shared between sessions of the app)."""
    arr.setflags(write=False)
    return arr
