"""The ``shakedown`` command line: one run, a map of runs, the numerical limit curve.

::

    shakedown run --ft 0.3 --w 0.5                    # one case, normalised inputs
    shakedown run --R1 0.04 --L 0.08 --Fn 32.2 --mu 0.79 --E2 3.6e6 --nu2 0.5 --Ft 5 --W 3e-4
    shakedown sweep --ft 0.02:0.95:40 --w 0.02:0.95:40 --out map.csv
    shakedown limit --ft 0.1:0.9:9 --tol 1e-3 --out limit.csv

Every value is checked before any work starts; bad input prints
``shakedown: error: ...`` (or argparse's usage message) on stderr and exits
with status 2, never with a traceback. Other exit statuses: 0 success, 1 the
work ran but some of it failed (a run that did not solve, a limit search that
did not converge, an output file that could not be written), 130 interrupted.

``sweep`` is resumable: finished rows are appended to ``OUT.partial.csv`` as
they come in, the complete table replaces ``OUT`` atomically at the end, and a
rerun of the same command skips every row already in ``OUT`` or the journal
(rows that failed are run again).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from ._validate import check_int, check_scalar
from .analytical import ft_limit, shakedown_stick_halfwidth, w_limit
from .contact import Contact
from .schedule import SHAPES
from .kernels import KERNELS
from .solver import DEFAULT_DX, simulate_contact, simulate_cycles
from .sweeps import (MAX_CELLS, MAX_RUNS, ProgressBar, _input_columns, normalise_table, numerical_limit_curve,
                    run_points, sweep_grid)

__all__ = ["main", "parse_range", "build_parser", "MAX_AXIS_VALUES", "MAX_TEXT"]

#: Most values one ``--ft`` or ``--w`` range may expand to.
MAX_AXIS_VALUES = 10_000
#: Longest text accepted for any option value (characters).
MAX_TEXT = 200
_MAX_PATH = 4096
_REGIMES = ("shakedown", "ratcheting", "error")
_EXIT_OK, _EXIT_FAILED, _EXIT_USAGE, _EXIT_INTERRUPTED = 0, 1, 2, 130


# --------------------------------------------------------------------------
# parsing values
# --------------------------------------------------------------------------
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
                lo_closed: bool = True, hi_closed: bool = True, max_values: int = MAX_AXIS_VALUES) -> np.ndarray:
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

    Raises
    ------
    ValueError
        With a message naming ``name`` for anything else.

    Examples
    --------
    >>> from core.cli import parse_range
    >>> parse_range("0.1:0.5:5", "ft", 0, 1, hi_closed=False).tolist()
    [0.1, 0.2, 0.30000000000000004, 0.4, 0.5]
    >>> parse_range("0.3", "w").tolist(), parse_range("0.1, 0.2", "w").tolist()
    ([0.3], [0.1, 0.2])
    """
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
        value = check_scalar(name, _float(name, text), lo, hi, lo_closed=lo_closed, hi_closed=hi_closed)
        if finite and not math.isfinite(value):
            raise ValueError(f"{name} must be finite, got {value}")
        return value
    return _arg(parse)


def _integer(name, lo, hi):
    def parse(text):
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
    text = _text("scheduler", text)
    if not text:
        raise ValueError("scheduler must be a Dask scheduler address such as tcp://host:8786")
    return text


def _output(suffixes):
    def parse(text):
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


# --------------------------------------------------------------------------
# the parser
# --------------------------------------------------------------------------
def _add_solver_options(parser, kernel_default="plane"):
    g = parser.add_argument_group("solver options (normalised: lengths in a, the Hertz half-width)")
    add = g.add_argument
    add("--periods", type=_integer("periods", 1, 10_000), action=_Once, metavar="N",
        help="rocking periods to simulate, in [1, 10000] (default 10)")
    add("--dx", type=_number("dx", 1e-4, 0.5), action=_Once, metavar="DX",
        help=f"element width [a], in [1e-4, 0.5] (default {DEFAULT_DX:g} = 1/40)")
    add("--dW", type=_number("dW", 1e-4, 1.0), action=_Once, metavar="DW",
        help="largest step of the contact centre [a], in [1e-4, 1] (default: dx)")
    add("--kernel", type=_choice("kernel", tuple(KERNELS)), action=_Once,
        help=f"influence kernel: plane (plane strain) or strip (truncated 3D, length L) (default {kernel_default})")
    add("--shape", type=_choice("shape", SHAPES), action=_Once,
        help="rocking waveform: triangle (constant speed, as in the paper) or sine (default triangle)")
    add("--load-steps", dest="load_steps", type=_integer("load_steps", 1, 10_000), action=_Once, metavar="N",
        help="steps of the initial loading at xc = 0, in [1, 10000] (default 1)")
    add("--L-over-a", dest="L_over_a", type=_number("L_over_a", 2.0, 1e9), action=_Once, metavar="L/a",
        help="strip length over a [-], in [2, 1e9] (strip kernel with normalised inputs)")
    add("--nu", type=_number("nu", 0.0, 0.5), action=_Once,
        help="Poisson ratio of the substrate [-], in [0, 0.5] (strip kernel with normalised inputs; default 0.5)")
    add("--shakedown-rtol", dest="shakedown_rtol", type=_number("shakedown_rtol", 0.0, 1.0, lo_closed=False),
        action=_Once, metavar="R",
        help="shaken down when the last increment per period is <= R times the largest, in (0, 1] (default 1e-3)")
    add("--time-budget", dest="time_budget", type=_number("time_budget", 0.0, 86400.0, lo_closed=False),
        action=_Once, metavar="S",
        help="wall-time budget of each run [s], in (0, 86400]; a run past it stops and counts as failed")


_SOLVER_DESTS = ("periods", "dx", "dW", "kernel", "shape", "load_steps", "L_over_a", "nu", "shakedown_rtol",
                 "time_budget")


def _add_execution_options(parser):
    g = parser.add_argument_group("execution")
    g.add_argument("--scheduler", type=_arg(_address), action=_Once, metavar="ADDRESS",
                   help="Dask scheduler address (tcp://host:8786) to run on a cluster; default: local processes")
    g.add_argument("--workers", type=_integer("workers", 1, 1024), action=_Once, metavar="N",
                   help="local worker processes, in [1, 1024] (default: all cores; 1 runs in this process; "
                        "ignored with --scheduler)")
    g.add_argument("--no-progress", dest="progress", action="store_false",
                   help="no progress bar on stderr")


def build_parser() -> argparse.ArgumentParser:
    """The ``shakedown`` argument parser (subcommands ``run``, ``sweep``, ``limit``)."""
    parser = argparse.ArgumentParser(
        prog="shakedown", allow_abbrev=False,
        description="Frictional shakedown and ratcheting of a rocking elastic cylinder (Wetter 2015): "
                    "simulate one case, map the (ft, w) plane, or find the numerical shakedown limit.",
        epilog="Normalised inputs: ft = Ft/(mu Fn) in [0, 1), w = W/a in [0, 1) with a the Hertz half-width. "
               "Displacements are in mu P/E* (P = Fn/L). Exit status: 0 ok, 1 some work failed, "
               "2 bad input, 130 interrupted. 'shakedown COMMAND --help' for each command.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    # run -------------------------------------------------------------------
    run = sub.add_parser(
        "run", allow_abbrev=False, help="simulate one case and print a summary",
        description="Simulate one case: either normalised (--ft, --w) or a physical contact "
                    "(--R1 --L --Fn --mu --E2 and --Ft or --ft, --W or --w; SI units).",
        epilog="Physical inputs use the strip kernel with the contact's L/a by default.")
    g = run.add_argument_group("normalised load")
    g.add_argument("--ft", type=_number("ft", 0.0, 1.0, hi_closed=False), action=_Once,
                   help="tangential load Ft/(mu Fn) [-], in [0, 1)")
    g.add_argument("--w", type=_number("w", 0.0, 1.0, hi_closed=False), action=_Once,
                   help="rocking amplitude W/a [-], in [0, 1)")
    g = run.add_argument_group("physical contact (SI units; R1, L, Fn, mu, E2 together)")
    positive = dict(lo=0.0, lo_closed=False)
    for flag, help_ in (("R1", "cylinder radius [m], > 0"), ("L", "cylinder length [m], > 2a"),
                        ("Fn", "normal force [N], > 0"), ("E2", "substrate Young's modulus [Pa], > 0")):
        g.add_argument(f"--{flag}", type=_number(flag, **positive), action=_Once, help=help_)
    g.add_argument("--mu", type=_number("mu", 0.0, 10.0, lo_closed=False), action=_Once,
                   help="friction coefficient [-], in (0, 10]")
    g.add_argument("--nu2", type=_number("nu2", 0.0, 0.5), action=_Once,
                   help="substrate Poisson ratio [-], in [0, 0.5] (default 0.5)")
    g.add_argument("--E1", type=_number("E1", finite=False, **positive), action=_Once,
                   help="cylinder Young's modulus [Pa], > 0, 'inf' for rigid (default inf)")
    g.add_argument("--nu1", type=_number("nu1", 0.0, 0.5), action=_Once,
                   help="cylinder Poisson ratio [-], in [0, 0.5] (default 0.3)")
    g.add_argument("--R2", type=_number("R2", finite=False, **positive), action=_Once,
                   help="substrate radius [m], > 0, 'inf' for flat (default inf)")
    g.add_argument("--Ft", type=_number("Ft", 0.0, None), action=_Once,
                   help="tangential force [N], in [0, mu Fn) (or give --ft)")
    g.add_argument("--W", type=_number("W", 0.0, None), action=_Once,
                   help="rocking amplitude of the contact centre [m], in [0, a) (or give --w)")
    _add_solver_options(run, kernel_default="plane; strip for a physical contact")
    run.add_argument("--out", type=_output((".csv", ".json")), action=_Once, metavar="FILE",
                     help="also write the result: FILE.csv (one row of scalars) or FILE.json "
                          "(scalars, increments per period, contact)")
    run.set_defaults(func=_cmd_run)

    # sweep -----------------------------------------------------------------
    sw = sub.add_parser(
        "sweep", allow_abbrev=False, help="map the (ft, w) plane: one run per grid point",
        description="Run the solver on every (ft, w) of a grid and write a table, one row per run "
                    "(regime, increment per period [mu P/E*], stick half-width c_sd/a, ...). "
                    "Resumable: rerunning the same command skips the rows already in --out.",
        epilog=f"Ranges: START:STOP:N (N values, both ends included), X, or X,Y,... . At most "
               f"--max-runs runs (default $SHAKEDOWN_MAX_RUNS or {MAX_RUNS}) and steps x elements "
               f"<= $SHAKEDOWN_MAX_CELLS (default {MAX_CELLS:.3g}) per run.")
    sw.add_argument("--ft", type=_range("ft", 0.0, 1.0, hi_closed=False), action=_Once, required=True,
                    metavar="RANGE", help="tangential loads Ft/(mu Fn) [-], each in [0, 1)")
    sw.add_argument("--w", type=_range("w", 0.0, 1.0, hi_closed=False), action=_Once, required=True,
                    metavar="RANGE", help="rocking amplitudes W/a [-], each in [0, 1)")
    sw.add_argument("--out", type=_output((".csv", ".csv.gz", ".parquet")), action=_Once, required=True,
                    metavar="FILE", help="the table: FILE.csv, FILE.csv.gz or FILE.parquet (needs pyarrow)")
    sw.add_argument("--max-runs", dest="max_runs", type=_integer("max_runs", 1, 10**7), action=_Once,
                    metavar="N", help=f"refuse grids of more than N runs (default $SHAKEDOWN_MAX_RUNS or {MAX_RUNS})")
    sw.add_argument("--overwrite", action="store_true",
                    help="start afresh: ignore (and replace) rows already in --out")
    _add_solver_options(sw)
    _add_execution_options(sw)
    sw.set_defaults(func=_cmd_sweep)

    # limit -----------------------------------------------------------------
    li = sub.add_parser(
        "limit", allow_abbrev=False, help="the numerical shakedown limit w_lim(ft), against eq 35",
        description="For each ft, bisect in w for the largest amplitude that still shakes down, "
                    "and compare with the exact limit of eq 35.")
    li.add_argument("--ft", type=_range("ft", 0.0, 1.0, lo_closed=False, hi_closed=False, max_values=1000),
                    action=_Once, required=True, metavar="RANGE",
                    help="tangential loads Ft/(mu Fn) [-], each in (0, 1); START:STOP:N, X or X,Y,...")
    li.add_argument("--tol", type=_number("tol", 1e-6, 0.1), action=_Once, default=1e-3,
                    help="tolerance of each limit in w [-], in [1e-6, 0.1] (default 1e-3)")
    li.add_argument("--out", type=_output((".csv", ".json", ".parquet")), action=_Once, metavar="FILE",
                    help="also write the table: FILE.csv, FILE.json or FILE.parquet")
    _add_solver_options(li)
    _add_execution_options(li)
    li.set_defaults(func=_cmd_limit)
    return parser


# --------------------------------------------------------------------------
# the commands
# --------------------------------------------------------------------------
def _solver_options(args) -> dict:
    return {k: getattr(args, k) for k in _SOLVER_DESTS if getattr(args, k, None) is not None}


def _say(*lines, stream=None):
    print(*lines, sep="\n", file=sys.stdout if stream is None else stream)


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def _write_json(obj, path: Path) -> None:
    _atomic_write(path, lambda tmp: tmp.write_text(json.dumps(_jsonable(obj), indent=2, allow_nan=False) + "\n"))


def _atomic_write(path: Path, write) -> None:
    """Write through a temporary file beside ``path`` and rename it over ``path``."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _contact(args) -> Contact | None:
    physical = {k: getattr(args, k) for k in ("R1", "L", "Fn", "mu", "E2", "nu2", "E1", "nu1", "R2", "Ft", "W")
                if getattr(args, k) is not None}
    if not physical:
        if args.ft is None or args.w is None:
            raise ValueError("give --ft and --w, or a physical contact (--R1 --L --Fn --mu --E2 ...)")
        return None
    missing = [f"--{k}" for k in ("R1", "L", "Fn", "mu", "E2") if k not in physical]
    if missing:
        raise ValueError(f"a physical contact needs {' '.join(missing)} too")
    for big, small in (("Ft", "ft"), ("W", "w")):
        if (big in physical) == (getattr(args, small) is not None):
            raise ValueError(f"give exactly one of --{big} and --{small} with a physical contact")
    physical.setdefault("nu2", 0.5)
    return Contact(**physical, ft=args.ft, w=args.w)


def _fmt(v, unit=""):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    text = f"{v:.6g}" if isinstance(v, float) else str(v)
    return f"{text} {unit}".rstrip()


def _cmd_run(args) -> int:
    options = _solver_options(args)
    contact = _contact(args)
    ft, w = (args.ft, args.w) if contact is None else (contact.ft, contact.w)
    # the same checks as a sweep: ranges, and the size of the run against the caps
    sweep_grid(ft, w, **options)
    if contact is None:
        result = simulate_cycles(ft, w, **options)
    else:
        result = simulate_contact(contact, **options)
    s = result.summary()
    inc = result.increment_per_period
    c_paper = float(shakedown_stick_halfwidth(ft, w))
    since = f" (from period {s['shakedown_period']})" if s["shakedown_period"] is not None else ""
    rows = [
        ("regime", f"{s['regime']}{since}"),
        ("increment, last period", _fmt(s["increment_last_period"], "mu P/E*")),
        ("increment, first period", _fmt(float(inc[0]) if inc.size else None, "mu P/E*")),
        ("stick half-width c_sd", _fmt(s["stick_halfwidth"], "a")),
        ("  paper's ansatz (eq 30)", _fmt(c_paper, "a")),
        ("eq 35 limit at this w", _fmt(float(ft_limit(w)), "= ft_lim")),
        ("eq 35 limit at this ft", _fmt(float(w_limit(ft)), "= w_lim")),
        ("elements x steps", f"{s['elements']} x {s['steps']}"),
        ("max active-set iterations", str(s["max_iterations"])),
        ("max KKT residual", _fmt(s["max_kkt_residual"])),
        ("runtime", _fmt(s["runtime_s"], "s")),
    ]
    head = (f"ft = {ft:.6g}, w = {w:.6g}: {result.kernel} kernel, {s['shape']} rocking, "
            f"{s['periods']} periods, dx = {s['dx']:.6g} a")
    if contact is not None:
        unit = contact.displacement_unit
        rows[2:2] = [("  in metres", _fmt(s["increment_last_period"] * unit, "m"))]
        head += (f"\ncontact: a = {contact.a * 1e3:.6g} mm, p0 = {contact.p0 / 1e6:.6g} MPa, "
                 f"E* = {contact.E_star / 1e6:.6g} MPa, beta = {contact.beta:.3g}, L/a = {contact.L / contact.a:.6g}")
        if s.get("u0") is not None:
            rows.append(("U0 (displacement at ft = 1)", _fmt(s["u0"] * unit, "m")))
    width = max(len(k) for k, _ in rows)
    _say(head, *(f"  {k:<{width}}  {v}" for k, v in rows))
    if contact is not None:
        for warning in contact.warnings:
            _say(f"warning: {warning}", stream=sys.stderr)
    if args.out is not None:
        if args.out.name.lower().endswith(".json"):
            doc = {"summary": s, "increment_per_period": inc.tolist(),
                   "contact": None if contact is None else contact.summary()}
            _write_json(doc, args.out)
        else:
            _atomic_write(args.out, lambda tmp: pd.DataFrame([_jsonable(s)]).to_csv(tmp, index=False))
        _say(f"wrote {args.out}", stream=sys.stderr)
    return _EXIT_OK


# ---- sweep: resumable output ------------------------------------------------
def _key_value(v):
    if v is None or v is pd.NA or (isinstance(v, float) and math.isnan(v)):
        return None
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return float(f"{float(v):.12g}")
    return str(v)


def _keys(rows, columns):
    return [tuple(_key_value(row.get(c)) for c in columns) for row in rows]


def _journal(out: Path) -> Path:
    return out.with_name(out.name + ".partial.csv")


def _read_table(path: Path) -> pd.DataFrame:
    if path.name.lower().endswith(".parquet"):
        try:
            return normalise_table(pd.read_parquet(path))
        except ImportError as e:
            raise ValueError(f"Parquet needs pyarrow (pip install pyarrow): {e}") from e
    return normalise_table(pd.read_csv(path))


def _write_table(table: pd.DataFrame, path: Path) -> None:
    if path.name.lower().endswith(".parquet"):
        _atomic_write(path, lambda tmp: table.to_parquet(tmp, index=False))
    else:
        compression = "gzip" if path.name.lower().endswith(".gz") else None
        _atomic_write(path, lambda tmp: table.to_csv(tmp, index=False, compression=compression))


def _existing_rows(out: Path) -> pd.DataFrame | None:
    """Rows already computed: the output file and the journal of an interrupted run."""
    parts = []
    for path in (out, _journal(out)):
        if path.exists() and path.stat().st_size > 0:
            try:
                parts.append(_read_table(path))
            except (OSError, ValueError, pd.errors.ParserError) as e:
                raise ValueError(f"cannot resume from {path} ({e}); use --overwrite or another --out") from e
    if not parts:
        return None
    table = pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]
    if "regime" not in table.columns or "ft" not in table.columns:
        raise ValueError(f"{out} is not a sweep table (no ft/regime columns); use --overwrite or another --out")
    # a line cut short by a kill has no valid regime: drop it, its run is done again
    return table[table["regime"].isin(_REGIMES)]


def _merge(existing, new, points, key_columns) -> pd.DataFrame:
    """Existing and new rows, one per key (new wins), in grid order; rows of other grids at the end."""
    tables = [t for t in (existing, new) if t is not None and len(t)]
    if not tables:
        return new if new is not None else existing
    merged = pd.concat(tables, ignore_index=True) if len(tables) > 1 else tables[0]
    merged = normalise_table(merged)
    keys = _keys(merged.to_dict("records"), key_columns)
    merged = merged.assign(_key=keys).drop_duplicates("_key", keep="last")
    order = {k: i for i, k in enumerate(_keys(points, key_columns))}
    rank = merged["_key"].map(lambda k: order.get(k, len(order)))
    merged = merged.assign(_rank=rank).sort_values("_rank", kind="stable")
    return normalise_table(merged.drop(columns=["_key", "_rank"]))


def _cmd_sweep(args) -> int:
    options = _solver_options(args)
    points = sweep_grid(args.ft, args.w, max_runs=args.max_runs, **options)
    key_columns = _input_columns(points)
    journal = _journal(args.out)
    existing = None
    if args.overwrite:
        journal.unlink(missing_ok=True)
    else:
        existing = _existing_rows(args.out)
    if existing is not None and journal.exists():
        # fold the journal of an interrupted run into the output, so that this run's journal starts empty
        existing = _merge(existing, None, points, key_columns)
        _write_table(existing, args.out)
        journal.unlink()
    if existing is not None:
        done = set(_keys(existing[existing["regime"] != "error"].to_dict("records"), key_columns))
        todo = [p for p, k in zip(points, _keys(points, key_columns)) if k not in done]
    else:
        todo = points
    _say(f"shakedown sweep: {len(points)} runs in the grid, {len(points) - len(todo)} already in "
         f"{args.out.name}, {len(todo)} to run", stream=sys.stderr)

    def append(rows: pd.DataFrame):
        rows.to_csv(journal, mode="a", header=not journal.exists() or journal.stat().st_size == 0, index=False)

    t0 = time.perf_counter()
    progress = ProgressBar() if args.progress else None
    try:
        new = run_points(todo, args.scheduler, max_workers=args.workers, progress=progress, on_rows=append)
    except KeyboardInterrupt:
        _say(f"shakedown: interrupted; finished rows are in {journal}: rerun the same command to resume",
             stream=sys.stderr)
        return _EXIT_INTERRUPTED
    table = _merge(existing, new, points, key_columns)
    _write_table(table, args.out)
    journal.unlink(missing_ok=True)
    counts = new["regime"].value_counts().to_dict() if len(new) else {}
    _say(f"wrote {len(table)} rows to {args.out} ({len(new)} new in {time.perf_counter() - t0:.1f} s: "
         + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())) + ")" if counts else
         f"wrote {len(table)} rows to {args.out} (nothing new to run)", stream=sys.stderr)
    failed = int(counts.get("error", 0))
    if failed:
        _say(f"shakedown: {failed} of {len(new)} runs failed (see the error column)", stream=sys.stderr)
        return _EXIT_FAILED
    return _EXIT_OK


def _cmd_limit(args) -> int:
    options = _solver_options(args)
    progress = ProgressBar(label="ft values") if args.progress else None
    try:
        table = numerical_limit_curve(args.ft, tol=args.tol, scheduler=args.scheduler, max_workers=args.workers,
                                      progress=progress, **options)
    except KeyboardInterrupt:
        _say("shakedown: interrupted", stream=sys.stderr)
        return _EXIT_INTERRUPTED
    shown = table[["ft", "w_limit", "w_limit_eq35", "difference", "runs", "converged"]]
    _say(f"numerical shakedown limit w_lim(ft), tolerance {args.tol:g} in w, against eq 35:",
         shown.to_string(index=False, float_format=lambda v: f"{v:.6f}"))
    if args.out is not None:
        name = args.out.name.lower()
        if name.endswith(".json"):
            _write_json(table.to_dict("records"), args.out)
        elif name.endswith(".parquet"):
            _atomic_write(args.out, lambda tmp: table.to_parquet(tmp, index=False))
        else:
            _atomic_write(args.out, lambda tmp: table.to_csv(tmp, index=False))
        _say(f"wrote {args.out}", stream=sys.stderr)
    bad = table[~table["converged"]]
    for row in bad.itertuples():
        _say(f"shakedown: no limit found at ft = {row.ft:g}: {row.message}", stream=sys.stderr)
    return _EXIT_FAILED if len(bad) else _EXIT_OK


# --------------------------------------------------------------------------
# entry point
# --------------------------------------------------------------------------
def main(argv=None) -> int:
    """Run the ``shakedown`` command line; return the exit status (never raises on bad input).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 success, 1 some work failed, 2 bad input, 130 interrupted.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    too_long = next((a for a in argv if len(a) > _MAX_PATH), None)
    if too_long is not None:
        _say(f"shakedown: error: an argument is too long ({len(too_long)} characters, at most {_MAX_PATH}): "
             f"{_short(too_long)}", stream=sys.stderr)
        return _EXIT_USAGE
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # --help (0) or a usage error (2, already printed by argparse)
        return e.code if isinstance(e.code, int) else _EXIT_USAGE
    if args.command is None:
        parser.print_help(sys.stderr)
        return _EXIT_USAGE
    try:
        return args.func(args)
    except ValueError as e:
        _say(f"shakedown: error: {e}", stream=sys.stderr)
        return _EXIT_USAGE
    except KeyboardInterrupt:
        _say("shakedown: interrupted", stream=sys.stderr)
        return _EXIT_INTERRUPTED
    except (RuntimeError, OSError, ImportError) as e:
        _say(f"shakedown: error: {type(e).__name__}: {e}", stream=sys.stderr)
        return _EXIT_FAILED


if __name__ == "__main__":
    sys.exit(main())
