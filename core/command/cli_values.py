"""The ``shakedown`` command line's value parsers: each flag's text checked and turned into its value.

Every parser raises a ValueError naming the parameter and its range (argparse
turns it into ``shakedown: error: ...`` and exit status 2, :mod:`core.command.cli`).
Only the standard library at import time (``shakedown --help`` answers at
once); numpy and the library's checks are imported when a value is parsed.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
from pathlib import Path

__all__ = ["parse_range", "MAX_AXIS_VALUES", "MAX_TEXT"]

#: Most values one ``--ft`` or ``--w`` range may expand to.
MAX_AXIS_VALUES = 10_000
#: Longest text accepted for any option value (characters).
MAX_TEXT = 200
_MAX_PATH = 4096


def _short(text: str) -> str:
    return repr(text) if len(text) <= 40 else repr(text[:37] + "...")


def _text(name: str, text: str) -> str:
    if len(text) > MAX_TEXT:
        raise ValueError(f"{name} is too long ({len(text)} characters, at most {MAX_TEXT}): {_short(text)}")
    return text.strip()


def _float(name: str, text: str) -> float:
    text = _text(name, text)
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"{name} must be a number, got {_short(text)}") from None


def parse_range(text: str, name: str = "value", lo: float | None = None, hi: float | None = None, *,
                lo_closed: bool = True, hi_closed: bool = True, max_values: int = MAX_AXIS_VALUES):
    """Parse ``START:STOP:N`` (N evenly spaced values, both ends included), ``X`` or ``X,Y,...``.

    Parameters
    ----------
    text : str
        The text to parse.
    name : str
        The option's name, for error messages.
    lo, hi : float or None
        Allowed range of every value (None: unbounded on that side).
    lo_closed, hi_closed : bool
        Whether the bounds themselves are allowed.
    max_values : int
        Most values the text may expand to.

    Returns
    -------
    ndarray
        The values, finite, within the range, distinct, in the order written.
        Inner ``START:STOP:N`` values are rounded to 12 significant digits, so that
        they are the decimals one would write (0.3, not 0.30000000000000004)
        in tables and file names.

    Raises
    ------
    ValueError
        With a message naming ``name`` for anything else.

    Examples
    --------
    >>> from core.command.cli import parse_range
    >>> parse_range("0.1:0.5:5", "ft", 0, 1, hi_closed=False).tolist()
    [0.1, 0.2, 0.3, 0.4, 0.5]
    >>> parse_range("0.3", "w").tolist(), parse_range("0.1, 0.2", "w").tolist()
    ([0.3], [0.1, 0.2])
    """
    import numpy as np

    from ..base._validate import check_scalar

    text = _text(name, text)
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise ValueError(f"{name} must be START:STOP:N, X or X,Y,..., got {_short(text)}")
        start, stop = _float(name, parts[0]), _float(name, parts[1])
        count_text = parts[2].strip()
        if not (count_text.isascii() and count_text.isdigit()):
            raise ValueError(f"{name}: N in START:STOP:N must be a whole number, got {_short(count_text)}")
        count = int(count_text)
        if not 2 <= count <= max_values:
            raise ValueError(f"{name}: N in START:STOP:N must be in [2, {max_values}], got {count}"
                             + (" (give a single value instead)" if count == 1 else ""))
        for v in (start, stop):
            check_scalar(name, v, lo, hi, lo_closed=lo_closed, hi_closed=hi_closed)
        if not math.isfinite(start) or not math.isfinite(stop):
            raise ValueError(f"{name} must be finite, got {_short(text)}")
        if start == stop:
            raise ValueError(f"{name}: START and STOP must differ in START:STOP:N, got {_short(text)}")
        values = np.linspace(start, stop, count)
        values[1:-1] = [float(f"{v:.12g}") for v in values[1:-1]]  # the ends are as written already
    else:
        items = text.split(",")
        if len(items) > max_values:
            raise ValueError(f"{name} has {len(items)} values (at most {max_values})")
        values = np.array([_float(name, item) for item in items])
    for v in values:
        check_scalar(name, float(v), lo, hi, lo_closed=lo_closed, hi_closed=hi_closed)
        if not math.isfinite(v):
            raise ValueError(f"{name} must be finite, got {v}")
    if np.unique(values).size != values.size:
        raise ValueError(f"{name} values must be distinct, got {_short(text)}")
    return values


def _arg(fn):
    """Turn a parser raising ValueError into an argparse type (message kept, exit status 2)."""
    def parse(text):
        try:
            return fn(text)
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None
    return parse


def _number(name, lo=None, hi=None, *, lo_closed=True, hi_closed=True, finite=True):
    def parse(text):
        from ..base._validate import check_scalar

        value = check_scalar(name, _float(name, text), lo, hi, lo_closed=lo_closed, hi_closed=hi_closed)
        if finite and not math.isfinite(value):
            raise ValueError(f"{name} must be finite, got {value}")
        return value
    return _arg(parse)


def _integer(name, lo, hi):
    def parse(text):
        from ..base._validate import check_int

        text = _text(name, text)
        if not (text.lstrip("+-").isascii() and text.lstrip("+-").isdigit()):
            raise ValueError(f"{name} must be a whole number in [{lo}, {hi}], got {_short(text)}")
        return check_int(name, int(text), lo, hi)
    return _arg(parse)


def _choice(name, choices):
    def parse(text):
        text = _text(name, text)
        if text not in choices:
            raise ValueError(f"{name} must be one of {', '.join(choices)}, got {_short(text)}")
        return text
    return _arg(parse)


def _range(name, lo, hi, **kw):
    return _arg(lambda text: parse_range(text, name, lo, hi, **kw))


def _address(text):
    from ..maps.tasks import check_address

    text = _text("scheduler", text)
    if not text:
        raise ValueError("scheduler must be a Dask scheduler address such as tcp://host:8786")
    check_address(text)
    return text


def _output(suffixes, stdout=False):
    def parse(text):
        if stdout and text.strip() == "-":
            return "-"
        if len(text) > _MAX_PATH or not text.strip():
            raise ValueError(f"--out must be a file path of 1 to {_MAX_PATH} characters")
        path = Path(text)
        if not any(path.name.lower().endswith(s) for s in suffixes):
            raise ValueError(f"--out must end in {', '.join(suffixes)}, got {_short(path.name)}")
        if path.is_dir():
            raise ValueError(f"--out is a directory: {_short(text)}")
        if not path.parent.is_dir():
            raise ValueError(f"--out: the directory {_short(str(path.parent))} does not exist")
        if path.name.lower().endswith(".parquet") and importlib.util.find_spec("pyarrow") is None:
            raise ValueError("--out: Parquet needs pyarrow (pip install pyarrow); or write .csv / .csv.gz")
        return path
    return _arg(parse)


class _Once(argparse.Action):
    """Store an option's value, refusing a second occurrence (``--ft 0.1 --ft 0.2``)."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = namespace.__dict__.setdefault("_seen", set())
        if self.dest in seen:
            raise argparse.ArgumentError(self, "given more than once")
        seen.add(self.dest)
        setattr(namespace, self.dest, values)
