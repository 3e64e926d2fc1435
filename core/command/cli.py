"""The ``shakedown`` command line: one run, a map of runs, the numerical limit curve.

::

    shakedown run --ft 0.3 --w 0.5                    # one case, normalised inputs
    shakedown run --R1 0.04 --L 0.08 --Fn 32.2 --mu 0.79 --E2 3.6e6 --nu2 0.5 --Ft 5 --W 3e-4
    shakedown sweep --ft 0.02:0.95:40 --w 0.02:0.95:40 --out map.csv
    shakedown limit --ft 0.1:0.9:9 --tol 1e-3 --out limit.csv

This module only parses arguments: the work is done by the library
(:func:`core.sweep_grid`, :func:`core.run_points`, :class:`core.maps.tables.TableFile`,
:func:`core.numerical_limit_curve`). It imports nothing heavy until a command
runs, so ``shakedown --help`` answers at once.

Every value is checked before any work starts; bad input prints one line
``shakedown: error: ...`` naming the flag (after argparse's usage line for a
malformed command line) on stderr and exits with status 2, never with a
traceback. Other exit statuses: 0 success, 1 the
work ran but some of it failed (a run that did not solve, a limit search that
did not converge, an output file that could not be written), 130 interrupted.

``sweep`` is resumable: finished rows are appended to ``OUT.partial.csv`` as
they come in, the complete table replaces ``OUT`` atomically at the end, and a
rerun of the same command skips every row already in ``OUT`` or the journal
(rows that failed are run again). A file holding rows of another grid or other
options is refused, not mixed. ``--out -`` writes the table to stdout.
"""

from __future__ import annotations

# Only the standard library at import time, so that `shakedown --help` answers at once: numpy, pandas and the
# solver are imported by the commands that need them.
import argparse
import math
import re
import sys
import time
from pathlib import Path

from .cli_values import (MAX_AXIS_VALUES, MAX_TEXT, _MAX_PATH, _address, _arg, _choice, _integer, _number, _Once,
                         _output, _range, _short, _text, parse_range)
from ..geometry import registry as _registry
from ..geometry.registry import DEFAULT as _DEFAULT_BODY, flags as _registry_flags

__all__ = ["main", "parse_range", "build_parser", "MAX_AXIS_VALUES", "MAX_TEXT", "flag_names"]

_EXIT_OK, _EXIT_FAILED, _EXIT_USAGE, _EXIT_INTERRUPTED = 0, 1, 2, 130
_PREFIX = "shakedown: error: "
# copies of library constants, so that building the parser imports nothing heavy (tests/test_cli.py checks them)
_KERNELS = ("plane", "strip")
_SHAPES = ("triangle", "sine")
_NORMALS = ("auto", "exact", "numerical")
_SOLVERS = ("auto", "dense", "fft", "pcg3d", "coupled")
# the body flags come from the registry (core/geometry/registry.py, the one list of the bodies and their parameters), read
# when the parser is built: each body parameter and run option, with the bodies that take it (these two names are
# what it held at import)
_BODY_FLAGS = _registry_flags()
_BODY_NAMES = tuple(_registry.REGISTRY)
# the run options a body may take (core.geometry.registry.BodyEntry.options): their flags, parsed here
_OPTION_FLAGS = {"angle": dict(type=_number("angle", -180.0, 180.0), metavar="DEG",
                               help="the angle of Ft to the rocking direction [degrees], in [-180, 180] (default 0)")}
_DEFAULT_DX = 1.0 / 40.0  # core.geometry.resolution.DEFAULT_DX_LINE: the cylinder's default grid
_DEFAULT_DX_POINT = 1.0 / 20.0  # core.geometry.resolution.DEFAULT_DX_POINT: the point contacts' default grid
_MAX_ELEMENTS = 16384  # core.api.solver.MAX_FFT_ELEMENTS: the grid over [-(1 + w), 1 + w] has at most this many
# elements (the solver picks the dense one up to core.api.solver.MAX_ELEMENTS and the matrix-free one above)
_DX_MIN = 1.0 / (_MAX_ELEMENTS // 2 - 1)  # the finest dx the solver accepts (at w = 0)
_MAX_RUNS, _MAX_CELLS = 20_000, 25_000_000  # core.maps.grid.MAX_RUNS, MAX_CELLS
# options that pass through to core.simulate_cycles, and the one value each has while the solver lacks it
_PASS_THROUGH = {"body": _DEFAULT_BODY, "history": "rocking"}


# --------------------------------------------------------------------------
# the parser
# --------------------------------------------------------------------------
class _Parser(argparse.ArgumentParser):
    """argparse with the error line of every other failure: ``shakedown: error: ...`` naming flags."""

    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(_EXIT_USAGE, f"{_PREFIX}{flag_names(message)}\n")


def flag_names(message: str) -> str:
    """A library message with its Python parameter names spelled as the command line's flags.

    ``"L_over_a is required with kernel='strip'"`` becomes
    ``"--L-over-a is required with --kernel strip"``; argparse's
    ``"argument --dx: dx must be ..."`` becomes ``"--dx must be ..."``.

    Examples
    --------
    >>> flag_names("L_over_a is required with kernel='strip'")
    '--L-over-a is required with --kernel strip'
    >>> flag_names("argument --dx: dx must be in [0.0005, 0.5], got 1")
    '--dx must be in [0.0005, 0.5], got 1'
    """
    m = re.match(r"argument (--[\w-]+)(?:/\S+)?: (.*)", message, re.S)
    if m and re.match(rf"{re.escape(m.group(1)[2:].replace('-', '_'))}\b", m.group(2)):
        message = m.group(2)
    for name in sorted({*_FLAGGED, *_registry_flags()}, key=len, reverse=True):
        flag = "--" + name.replace("_", "-")
        message = re.sub(rf"(?<![\w-]){name}=(['\"]?)([\w.+-]*)\1", rf"{flag} \2", message)
        if "_" in name:
            message = re.sub(rf"(?<![\w-]){name}(?![\w-])", flag, message)
        else:
            message = re.sub(rf"(?<![\w-]){name}(?= (?:must|is|are|has|values|given)\b|:)", flag, message)
    return message


def _body_flag(name, bodies) -> dict:
    """The type, metavar and help of a body flag: a run option's (:data:`_OPTION_FLAGS`) or the registry's
    parameter's (its range, default and meaning)."""
    only = f"--body {' or '.join(bodies)}: "
    if name in _OPTION_FLAGS:
        option = _OPTION_FLAGS[name]
        return dict(option, help=only + option["help"])
    p = next(p for e in _registry.REGISTRY.values() for p in e.parameters if p.name == name)
    if p.path:
        return dict(type=_arg(lambda text: _text(name, text)), metavar="PATH", help=only + p.doc)
    span = f"[{p.lo:g}, {p.hi:g}{']' if p.hi_closed else ')'}"
    default = " (required)" if p.keyword else f" (default {p.default:g})"
    return dict(type=_number(name, p.lo, p.hi, hi_closed=p.hi_closed), metavar=name.upper(),
                help=f"{only}{p.doc}, in {span}{default}")


def _add_solver_options(parser, kernel_default="plane", mu_flag=True):
    g = parser.add_argument_group("solver options (normalised: lengths in a, the Hertz half-width)")
    add = g.add_argument
    add("--beta", type=_number("beta", -0.5, 0.5, lo_closed=False, hi_closed=False), action=_Once,
        help="Dundurs' beta of the pair, the rocking body being body 1 (> 0 for a rigid body on a compressible "
             "substrate), in (-0.5, 0.5) (default 0: uncoupled); beta != 0 solves the normal and tangential "
             "problems together (a line contact on the plane kernel; needs --mu); eq 35 is then the uncoupled "
             "reference")
    add("--materials", type=_arg(lambda text: _text("materials", text)), action=_Once, metavar="BODY/SUBSTRATE",
        help="the pair instead of --beta: steel/steel, steel/aluminium, steel/titanium, steel/PMMA, steel/rubber, "
             "rigid/incompressible, or BODY/SUBSTRATE of steel, aluminium, titanium, PMMA, rubber, rigid "
             "(core/theory/materials.py)")
    if mu_flag:
        add("--mu", type=_number("mu", 0.0, 10.0, lo_closed=False), action=_Once,
            help="friction coefficient [-], in (0, 10]: needed with --beta or --materials (accepted and unused "
                 "without)")
    add("--body", type=_arg(lambda text: _text("body", text)), action=_Once, metavar="NAME",
        help=f"the rocking body: {', '.join(_registry.REGISTRY)} (core/geometry/registry.py; default {_DEFAULT_BODY}); its "
             "parameters: " + "; ".join(f"--{name.replace('_', '-')} ({' or '.join(bodies)})"
                                         for name, bodies in _registry_flags().items()))
    for name, bodies in _registry_flags().items():  # read now: a body registered after the import has its flags
        add(f"--{name.replace('_', '-')}", dest=name, action=_Once, **_body_flag(name, bodies))
    add("--normal", type=_choice("normal", _NORMALS), action=_Once,
        help="the pressure: exact (closed form), numerical (the normal problem solved by constrained conjugate "
             "gradients) or auto (the default: a line contact's closed form where there is one; a point contact's "
             "discrete normal problem on the grid)")
    add("--solver", type=_choice("solver", _SOLVERS), action=_Once,
        help="the per-step solver: auto (the default: dense or fft on a line by its size, pcg3d on a patch), "
             "dense or fft (a line of elements), pcg3d (a patch: the point contacts, height maps and cones), "
             "coupled (a line's normal and tangential problems together: what --beta picks); "
             "one that does not fit the body's grid is refused")
    add("--history", type=_arg(lambda text: _text("history", text)), action=_Once, metavar="NAME",
        help="the loading history, a name core.simulate_cycles accepts: rocking (the default: constant Ft, "
             "the centre rocked between -W and +W), normal (the same under a normal force 1 + 0.2 sin(2 pi t)) "
             "or tangential (fixed centre, Ft oscillating by (1 - |ft|)/2 about its mean: for a sphere "
             "Mindlin-Deresiewicz); every body takes every history")
    add("--periods", type=_integer("periods", 1, 10_000), action=_Once, metavar="N",
        help="rocking periods to simulate, in [1, 10000] (default 10)")
    add("--dx", type=_number("dx", _DX_MIN, 0.5), action=_Once, metavar="DX",
        help=f"element width [a], in [{_DX_MIN:.5g}, 0.5]: the grid over [-(1 + w), 1 + w] has at most "
             f"{_MAX_ELEMENTS} elements, so dx >= (1 + w)/{_MAX_ELEMENTS // 2 - 1} (default: the body's grid, "
             f"{_DEFAULT_DX:g} = 1/40 for the cylinder, {_DEFAULT_DX_POINT:g} = 1/20 for the point contacts)")
    add("--dW", type=_number("dW", 1e-4, 1.0), action=_Once, metavar="DW",
        help="largest step of the contact centre [a], in [1e-4, 1] (default: dx)")
    add("--kernel", type=_choice("kernel", _KERNELS), action=_Once,
        help=f"influence kernel: plane (plane strain) or strip (truncated 3D, length L) (default {kernel_default})")
    add("--shape", type=_choice("shape", _SHAPES), action=_Once,
        help="rocking waveform: triangle (constant speed, as in the paper) or sine (default triangle)")
    add("--load-steps", dest="load_steps", type=_integer("load_steps", 1, 10_000), action=_Once, metavar="N",
        help="steps of the initial loading at xc = 0, in [1, 10000] (default 1)")
    add("--L-over-a", dest="L_over_a", type=_number("L_over_a", 2.0, 1e9), action=_Once, metavar="L/a",
        help="strip length over a [-], in [2, 1e9] (strip kernel with normalised inputs)")
    add("--nu", type=_number("nu", 0.0, 0.5), action=_Once,
        help="Poisson ratio of the substrate [-], in [0, 0.5] (strip kernel with normalised inputs; default 0.5)")
    add("--path", type=_arg(_loading_path), action=_Once, metavar="FIELDS",
        help="the loading path before the periods (core.LoadingPath; the verdict reads the periods after it; "
             "sweep and limit give every run the same path): "
             "comma-separated KEY=VALUE, any of order=P-then-Q or order=together (P raised before Q, the default, "
             "or both in proportion), ramp=N (steps of the P ramp, in [0, 10000]; 0: P at once, or with together "
             "the --load-steps), first=+1 or first=-1 (the centre first towards +W or -W), start=X, start=+W or "
             "start=-W (the centre while the loads are raised, a fraction X of W in [-1, 1]; then back to 0), "
             "preload=FT:W:N[+FT:W:N...] (N "
             "earlier periods at each other ft and w; with --history tangential W is the force's amplitude); "
             "e.g. --path order=together,ramp=10,first=-1,start=+W,preload=0.2:0.6:5 (default: P and Q at once "
             "at xc = 0, then towards +W)")
    add("--shakedown-rtol", dest="shakedown_rtol", type=_number("shakedown_rtol", 0.0, 1.0, lo_closed=False),
        action=_Once, metavar="R",
        help="shaken down when the last increment per period is <= R times the largest, in (0, 1] (default 1e-3)")
    add("--time-budget", dest="time_budget", type=_number("time_budget", 0.0, 86400.0, lo_closed=False),
        action=_Once, metavar="S",
        help="wall-time budget of each run [s], in (0, 86400]; a run past it stops and counts as failed")


_SOLVER_DESTS = ("body", "normal", "solver", "history", "periods", "dx", "dW", "kernel", "shape", "load_steps", "L_over_a", "nu",
                 "shakedown_rtol", "time_budget", "beta", "path")
# every parameter name a library message may use, spelled as a flag by flag_names
_FLAGGED = (*_SOLVER_DESTS, "materials", "ft", "w", "tol", "max_runs", "workers", "max_workers", "scheduler", "R1", "L", "Fn",
            "mu", "E2", "nu2", "E1", "nu1", "R2", "Ft", "W")


def _loading_path(text):
    """``--path``'s text as a :class:`core.loading.paths.LoadingPath` (a ValueError naming the field otherwise)."""
    from ..loading.paths import LoadingPath

    return LoadingPath.parse(_text("path", text))


def _add_execution_options(parser):
    g = parser.add_argument_group("execution")
    g.add_argument("--scheduler", type=_arg(_address), action=_Once, metavar="ADDRESS",
                   help="Dask scheduler address (tcp://host:8786) to run on a cluster; default: local processes")
    g.add_argument("--workers", type=_integer("workers", 1, 1024), action=_Once, metavar="N",
                   help="local worker processes, in [1, 1024] (default: by the size of the job, up to all cores; "
                        "a small job runs in this process; 1 runs in this process; ignored with --scheduler)")
    g.add_argument("--no-progress", dest="progress", action="store_false",
                   help="no progress bar on stderr")


class _Version(argparse.Action):
    """``--version``: print the installed version and exit (importlib.metadata is read only then)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from importlib import metadata

        try:
            version = metadata.version("shakedown-explorer")
        except metadata.PackageNotFoundError:
            version = "unknown (not installed)"
        print(f"{parser.prog} {version}")
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    """The ``shakedown`` argument parser (subcommands ``run``, ``sweep``, ``limit``)."""
    parser = _Parser(
        prog="shakedown", allow_abbrev=False,
        description="Frictional shakedown and ratcheting of a rocking elastic cylinder (Wetter 2015): "
                    "simulate one case, map the (ft, w) plane, or find the numerical shakedown limit.",
        epilog="Normalised inputs: ft = Ft/(mu Fn) in [0, 1), w = W/a in [0, 1) with a the Hertz half-width. "
               "Displacements are in mu P/E* (P = Fn/L). Regimes: shakedown, ratcheting, or undetermined when "
               "the periods run cannot tell. Exit status: 0 ok, 1 some work failed, 2 bad input, "
               "130 interrupted. 'shakedown COMMAND --help' for each command.")
    parser.add_argument("--version", action=_Version, help="print the version and exit")
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
    _add_solver_options(run, kernel_default="plane; strip for a physical contact", mu_flag=False)
    run.add_argument("--out", type=_output((".csv", ".json")), action=_Once, metavar="FILE",
                     help="also write the result: FILE.csv (one row of scalars) or FILE.json "
                          "(scalars, increments per period, contact)")
    run.set_defaults(func=_cmd_run)

    # sweep -----------------------------------------------------------------
    sw = sub.add_parser(
        "sweep", allow_abbrev=False, help="map the (ft, w) plane: one run per grid point",
        description="Run the solver on every (ft, w) of a grid and write a table, one row per run "
                    "(regime, why, increment per period [mu P/E*], stick half-width c_sd/a, ...). "
                    "Resumable: rerunning the same command skips the rows already in --out; a file made "
                    "by another grid or other options is refused (use --overwrite or another --out).",
        epilog=f"Ranges: START:STOP:N (N values, both ends included), X, or X,Y,... . At most "
               f"--max-runs runs (default $SHAKEDOWN_MAX_RUNS or {_MAX_RUNS}) and steps x elements "
               f"<= $SHAKEDOWN_MAX_CELLS (default {_MAX_CELLS:.3g}) per run.")
    sw.add_argument("--ft", type=_range("ft", 0.0, 1.0, hi_closed=False), action=_Once, required=True,
                    metavar="RANGE", help="tangential loads Ft/(mu Fn) [-], each in [0, 1)")
    sw.add_argument("--w", type=_range("w", 0.0, 1.0, hi_closed=False), action=_Once, required=True,
                    metavar="RANGE", help="rocking amplitudes W/a [-], each in [0, 1)")
    sw.add_argument("--out", type=_output((".csv", ".csv.gz", ".parquet"), stdout=True), action=_Once,
                    required=True, metavar="FILE",
                    help="the table: FILE.csv, FILE.csv.gz or FILE.parquet (needs pyarrow); '-' writes CSV to "
                         "stdout (not resumable)")
    sw.add_argument("--max-runs", dest="max_runs", type=_integer("max_runs", 1, 10**7), action=_Once,
                    metavar="N", help=f"refuse grids of more than N runs (default $SHAKEDOWN_MAX_RUNS or {_MAX_RUNS})")
    sw.add_argument("--overwrite", action="store_true",
                    help="start afresh: ignore (and replace) rows already in --out")
    _add_solver_options(sw)
    _add_execution_options(sw)
    sw.set_defaults(func=_cmd_sweep)

    # limit -----------------------------------------------------------------
    li = sub.add_parser(
        "limit", allow_abbrev=False, help="the numerical shakedown limit w_lim(ft), then the exact one beside it",
        description="For each ft, bisect in w for the largest amplitude that still shakes down, starting from "
                    "the whole range [0, 0.999] (not from the exact limit); print the bracket found and whether the "
                    "exact limit of the body (" + "; ".join(f"{e.exact_limit} for the {n}"
                                                            for n, e in _registry.REGISTRY.items() if e.exact_limit) +
                    "; Melan's integral, core.w_limit, for any other) lies inside it. Each body runs at its own "
                    "default grid unless --dx is given.")
    li.add_argument("--ft", type=_range("ft", 0.0, 1.0, lo_closed=False, hi_closed=False, max_values=1000),
                    action=_Once, required=True, metavar="RANGE",
                    help="tangential loads Ft/(mu Fn) [-], each in (0, 1); START:STOP:N, X or X,Y,...")
    li.add_argument("--tol", type=_number("tol", 1e-6, 0.1), action=_Once, default=1e-3,
                    help="tolerance of each limit in w [-], in [1e-6, 0.1] (default 1e-3)")
    li.add_argument("--out", type=_output((".csv", ".json", ".parquet"), stdout=True), action=_Once, metavar="FILE",
                    help="also write the table: FILE.csv, FILE.json or FILE.parquet; '-' writes CSV to stdout "
                         "instead of the aligned table")
    _add_solver_options(li)
    _add_execution_options(li)
    li.set_defaults(func=_cmd_limit)
    return parser


# --------------------------------------------------------------------------
# the commands
# --------------------------------------------------------------------------
def _body_options(args, options) -> None:
    """The body flags (--flat, --ratio, --angle) into the options: a body object (core/geometry/registry.py) or the
    point contacts' ``ratio`` and ``angle`` [rad]; each flag only with its body."""
    body = options.get("body", _PASS_THROUGH["body"])
    flags = _registry_flags()
    given = {k: getattr(args, k) for k in flags if getattr(args, k, None) is not None}
    for name, value in given.items():
        if body not in flags[name]:
            raise ValueError(f"--{name.replace('_', '-')} is for --body {' or '.join(flags[name])}, not {_short(body)}")
    # the body's own parameters (core/geometry/registry.py) make the body object; one that core.simulate_cycles takes as a
    # keyword (the ellipsoid's ratio) passes as that
    from ..maps.grid import solver_defaults
    from ..geometry.registry import make_body

    entry = _registry.REGISTRY.get(body) if isinstance(body, str) else None
    if entry is not None:
        keywords = solver_defaults()
        own = {p.name: p for p in entry.parameters if p.name not in keywords}
        if any(name in given for name in own) or any(p.path for p in own.values()):
            options["body"] = make_body(body, **{k: v for k, v in given.items() if k in own})
    if "ratio" in given:
        options["ratio"] = given["ratio"]
    if "angle" in given:
        options["angle"] = math.radians(given["angle"])


def _solver_options(args) -> dict:
    """The solver options given on the command line, checked against what core.simulate_cycles accepts."""
    from ..maps.grid import solver_defaults

    options = {k: getattr(args, k) for k in _SOLVER_DESTS if getattr(args, k, None) is not None}
    _body_options(args, options)
    materials = getattr(args, "materials", None)
    if materials is not None and not _physical(args):  # a physical contact takes the pair itself (_contact)
        if "beta" in options:
            raise ValueError("give --beta or --materials, not both")
        from ..theory.materials import material_pair

        options["beta"] = material_pair(materials).beta
    if getattr(args, "mu", None) is not None and not _physical(args):
        options["mu"] = args.mu
    accepted = solver_defaults()
    for name, only in _PASS_THROUGH.items():
        if name in options and name not in accepted:
            # this solver has no such option: only its one built-in value is allowed
            if options[name] != only:
                raise ValueError(f"{name} must be one of {only}, got {_short(options[name])}")
            del options[name]
    return options


def _say(*lines, stream=None):
    print(*lines, sep="\n", file=sys.stdout if stream is None else stream)


def _jsonable(value):
    import numpy as np

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
    import json

    from ..maps.tables import atomic_write

    atomic_write(path, lambda tmp: tmp.write_text(json.dumps(_jsonable(obj), indent=2, allow_nan=False) + "\n"))


_PHYSICAL = ("R1", "L", "Fn", "mu", "E2", "nu2", "E1", "nu1", "R2", "Ft", "W")


def _physical(args) -> dict:
    """The physical inputs given (``run``); ``--mu`` alone is the normalised run's friction coefficient."""
    physical = {k: getattr(args, k) for k in _PHYSICAL if getattr(args, k, None) is not None}
    return {} if set(physical) <= {"mu"} else physical


def _contact(args):
    physical = _physical(args)
    if not physical:
        if args.ft is None or args.w is None:
            raise ValueError("give --ft and --w, or a physical contact (--R1 --L --Fn --mu --E2 ...)")
        return None
    needed = ("R1", "L", "Fn", "mu") + (() if getattr(args, "materials", None) is not None else ("E2",))
    missing = [f"--{k}" for k in needed if k not in physical]
    if missing:
        raise ValueError(f"a physical contact needs {' '.join(missing)} too")
    for big, small in (("Ft", "ft"), ("W", "w")):
        if (big in physical) == (getattr(args, small) is not None):
            raise ValueError(f"give exactly one of --{big} and --{small} with a physical contact")
    from ..api.contact import Contact

    materials = getattr(args, "materials", None)
    if materials is not None:
        clash = sorted(set(physical) & {"E1", "nu1", "E2", "nu2"})
        if clash or args.beta is not None:
            raise ValueError(f"--materials sets the moduli: give it or {', '.join('--' + k for k in clash) or '--beta'}"
                             ", not both")
        return Contact(**physical, ft=args.ft, w=args.w, materials=materials)
    if args.beta is not None:
        raise ValueError("--beta is the normalised run's: a physical contact's beta follows from --E1 --nu1 --E2 "
                         "--nu2 (or --materials)")
    physical.setdefault("nu2", 0.5)
    return Contact(**physical, ft=args.ft, w=args.w)


def _fmt(v, unit=""):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    text = f"{v:.6g}" if isinstance(v, float) else str(v)
    return f"{text} {unit}".rstrip()


def args_given(args) -> set:
    """The options given on the command line (argparse leaves the others None)."""
    return {k for k in _SOLVER_DESTS if getattr(args, k, None) is not None}


def _grid_limit_text(result) -> str:
    """Melan's limit of the run's own grid in ft (:attr:`core.CycleResult.melan_limit`), as the run prints it."""
    limit = result.melan_limit
    if limit is None:
        return "- (the tangential load varies over the last period)"
    lo, hi = limit
    text = f"{lo:.6g}" if hi - lo <= 1e-12 * hi else f"between {lo:.6g} and {hi:.6g}"
    if getattr(result, "coupled", False):
        return (f"{text} = ft_lim of the elements run, uncoupled: a reference only (beta = {result.beta:g}: "
                "Melan's theorem does not hold; shakedown limit --beta finds the coupled one)")
    return f"{text} = ft_lim of the elements run (the verdict's check)"


def _trend_rows(s: dict, unit: str) -> list[tuple[str, str]]:
    """The rows of the verdict's trend: D_inf with its error, the ratio r, the periods likely to decide."""
    D, err, r = s.get("D_inf"), s.get("D_inf_error"), s.get("decay_ratio")
    if D is None or (isinstance(D, float) and math.isnan(D)):
        return [("  D_inf (limit increment)", "- (too few periods to fit the trend)")]
    rows = [("  D_inf (limit increment)", f"{D:.4g} +- {err:.2g} {unit}"),
            ("  r (decay per period)", "- (nothing left changing)" if r is None or math.isnan(r) else f"{r:.4g}")]
    if s.get("periods_to_decide") is not None:
        rows.append(("  periods likely to decide", f"about {s['periods_to_decide']} more"))
    return rows


def _energy_rows(s: dict, contact) -> list[tuple[str, str]]:
    """The rows of the energy dissipated per period: the last period's, its limit E_inf with its error, and with
    a contact the last period's in J/m (a line) or J (a point contact)."""
    unit, E, err = s["energy_unit"], s["E_inf"], s["E_inf_error"]
    rows = [("energy, last period", _fmt(s["energy_last_period"], unit))]
    if contact is not None:
        si = "J" if unit.endswith("(E* a)") else "J/m"
        rows.append(("  in SI units", _fmt(s["energy_last_period"] * contact.energy_unit, si)))
    rows.append(("  E_inf (limit energy)", "- (too few periods to fit the trend)" if E is None or math.isnan(E)
                 else f"{E:.4g} +- {err:.2g} {unit}"))
    return rows


def _cmd_run(args) -> int:
    import pandas as pd

    from ..bounds.limits import ft_limit, w_limit
    from ..maps.grid import sweep_grid
    from ..api.contact import simulate_contact
    from ..api.solver import simulate_cycles
    from ..maps.tables import CSV_FLOAT_FORMAT, atomic_write

    options = _solver_options(args)
    contact = _contact(args)
    ft, w = (args.ft, args.w) if contact is None else (contact.ft, contact.w)
    # the same checks as a sweep: ranges, and the size of the run against the caps
    coupled = contact is not None and contact.coupled and "kernel" not in options  # as simulate_contact decides
    sweep_grid(ft, w, **options, **({"beta": contact.beta, "mu": contact.mu} if coupled else {}))
    if contact is None:
        result = simulate_cycles(ft, w, **options)
    else:
        result = simulate_contact(contact, **options)
    s = result.summary()
    inc = result.increment_per_period
    spec = result.body  # the body with its parameters
    body = spec.name
    # the paper's closure (eq 30) and eq 35: a body with a closed-form shaken-down state (the cylinder's);
    # every other body has its own exact limit
    line = getattr(spec, "shakedown_stick_halfwidth", None) is not None
    line_body = not result.is_patch  # a line contact (the cylinder, the punch, any core.geometry.bodies.Body)
    unit_u = "mu P/E*" if line_body else "mu Fn/(E* a)"
    rocking = result.params.get("history", "rocking") == "rocking"  # the closed forms are the rocking history's
    ref = " (uncoupled reference)" if getattr(result, "coupled", False) else ""
    since = f" (from period {s['shakedown_period']})" if s.get("shakedown_period") is not None else ""
    rows = [
        ("regime", f"{s['regime']}{since}"),
        ("  why", result.regime_reason),
        *_trend_rows(s, unit_u),
        ("increment, last period", _fmt(s["increment_last_period"], unit_u)),
        ("increment, first period", _fmt(float(inc[0]) if inc.size else None, unit_u)),
        *_energy_rows(s, contact),
        *([("twist, last period", _fmt(s["twist_last_period"], "mu Fn/(E* a^2) rad"))]
          if s["twist_last_period"] is not None else []),
        ("stick half-width c_sd", _fmt(s["stick_halfwidth"], "a")),
        *([("  paper's ansatz (eq 30)", _fmt(float(spec.shakedown_stick_halfwidth(ft, w)), "a"))]
          if line and rocking else []),
        # the limits of the rocking history (Melan over the rocking period): they say nothing of another history
        *([(f"{'eq 35' if line else 'exact'} limit at this w{ref}", _fmt(float(ft_limit(w, body=spec)), "= ft_lim")),
           (f"{'eq 35' if line else 'exact'} limit at this ft{ref}", _fmt(float(w_limit(ft, body=spec)), "= w_lim"))]
          if rocking else []),
        ("Melan's limit on this grid", _grid_limit_text(result)),
        ("element width dx", _fmt(s["dx"], "a") + ("" if "dx" in args_given(args) else " (the body's default)")),
        ("elements x steps", f"{s['elements']} x {s['steps']}"),
        ("max active-set iterations", str(s["max_iterations"])),
        ("max KKT residual", _fmt(s["max_kkt_residual"])),
        ("runtime", _fmt(s["runtime_s"], "s")),
    ]
    model = (f"{result.kernel} kernel" if line else f"{spec!r}, {result.kernel} kernel"
             if line_body else f"{body}, 3D half-space")
    history = result.params.get("history", "rocking")  # every body takes every history
    loading = {"normal": f"{s['shape']} rocking under an oscillating normal force",
               "tangential": f"{s['shape']} oscillating tangential force at a fixed centre"}.get(
        history, f"{s['shape']} rocking")
    head = (f"ft = {ft:.6g}, w = {w:.6g}: {model}, {loading}, "
            f"{s['periods']} periods, dx = {s['dx']:.6g} a")
    if "path" in result.params:
        head += f"\nloading path: {result.params['path']} (the verdict reads the periods after it)"
    if getattr(result, "coupled", False):
        head += f"\ncoupled: Dundurs beta = {result.beta:.4g}, mu = {result.mu:g} (normal and tangential solved together)"
    if contact is not None:
        unit = contact.displacement_unit
        rows[3:3] = [("  in metres", _fmt(s["increment_last_period"] * unit, "m"))]
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
            atomic_write(args.out, lambda tmp: pd.DataFrame([_jsonable(s)]).to_csv(tmp, index=False,
                                                                                  float_format=CSV_FLOAT_FORMAT))
        _say(f"wrote {args.out}", stream=sys.stderr)
    return _EXIT_OK


def _cmd_sweep(args) -> int:
    from ..maps.grid import sweep_grid
    from ..base.progress import ProgressBar
    from ..maps.sweeps import run_points
    from ..maps.tables import CSV_FLOAT_FORMAT, TableFile

    options = _solver_options(args)
    points = sweep_grid(args.ft, args.w, max_runs=args.max_runs, **options)
    to_stdout = args.out == "-"
    target = None if to_stdout else TableFile(args.out, points, overwrite=args.overwrite)
    todo = points if target is None else target.todo
    where = "stdout" if to_stdout else args.out.name
    _say(f"shakedown sweep: {len(points)} runs in the grid, {len(points) - len(todo)} already in "
         f"{where}, {len(todo)} to run" + (f" (loading path: {options['path']})" if "path" in options else ""),
         stream=sys.stderr)
    t0 = time.perf_counter()
    progress = ProgressBar() if args.progress else None
    try:
        new = run_points(todo, args.scheduler, workers=args.workers, progress=progress,
                         on_rows=None if target is None else target.append)
    except KeyboardInterrupt:
        where = "nothing was kept" if target is None else f"finished rows are in {target.journal}"
        _say(f"shakedown: interrupted; {where}: rerun the same command to resume", stream=sys.stderr)
        return _EXIT_INTERRUPTED
    if target is None:
        table = new
        table.to_csv(sys.stdout, index=False, float_format=CSV_FLOAT_FORMAT)
    else:
        table = target.finish(new)
    counts = new["regime"].value_counts().to_dict() if len(new) else {}
    _say(f"wrote {len(table)} rows to {where} ({len(new)} new in {time.perf_counter() - t0:.1f} s on "
         f"{new.attrs.get('backend', '-')}: " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())) + ")"
         if counts else f"wrote {len(table)} rows to {where} (nothing new to run)", stream=sys.stderr)
    failed = int(counts.get("error", 0))
    if failed:
        _say(f"shakedown: {failed} of {len(new)} runs failed (see the error column)", stream=sys.stderr)
        return _EXIT_FAILED
    return _EXIT_OK


def _cmd_limit(args) -> int:
    from ..maps.limits_search import numerical_limit_curve
    from ..base.progress import ProgressBar
    from ..maps.tables import CSV_FLOAT_FORMAT, write_table

    options = _solver_options(args)
    progress = ProgressBar(label="ft values") if args.progress else None
    try:
        table = numerical_limit_curve(args.ft, tol=args.tol, scheduler=args.scheduler, workers=args.workers,
                                      progress=progress, **options)
    except KeyboardInterrupt:
        _say("shakedown: interrupted", stream=sys.stderr)
        return _EXIT_INTERRUPTED
    if args.out == "-":
        table.to_csv(sys.stdout, index=False, float_format=CSV_FLOAT_FORMAT)
    else:
        shown = table[["ft", "start_lo", "start_hi", "w_shakedown", "w_ratcheting", "w_limit_eq35", "eq35_inside",
                       "exact_within_tol", "periods", "runs", "converged"]]
        body = options.get("body", _DEFAULT_BODY)
        name = body if isinstance(body, str) else getattr(body, "name", type(body).__name__)
        exact = getattr(_registry.REGISTRY.get(name), "exact_limit", "") or "core.w_limit of the body"
        grid = options.get("dx")
        if grid is None:
            from ..geometry.resolution import default_dx

            grid = default_dx(body)
        if "path" in options:
            _say(f"loading path: {options['path']} (every run of the search; the verdict reads the periods after it)")
        _say(f"numerical shakedown limit w_lim(ft) of the {name} (dx = {grid:.6g} a), tolerance {args.tol:g} in w: "
             "each search starts from [start_lo, start_hi] and ends with w_shakedown shaking down and w_ratcheting "
             f"ratcheting; w_limit_eq35: the exact limit ({exact}); eq35_inside: it lies in that final bracket; "
             "exact_within_tol: it lies within the tolerance of it",
             shown.to_string(index=False, float_format=lambda v: f"{v:.6f}"))
    if args.out not in (None, "-"):
        if args.out.name.lower().endswith(".json"):
            _write_json(table.to_dict("records"), args.out)
        else:
            write_table(table, args.out)
        _say(f"wrote {args.out}", stream=sys.stderr)
    bad = table[~table["converged"]]
    for row in bad.itertuples():
        _say(f"shakedown: the limit at ft = {row.ft:g} did not converge: {row.message}", stream=sys.stderr)
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
        0 success, 1 some work failed, 2 bad input, 130 interrupted. Every
        error is one line ``shakedown: error: ...`` on stderr that names the
        flag at fault.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    too_long = next((a for a in argv if len(a) > _MAX_PATH), None)
    if too_long is not None:
        _say(f"{_PREFIX}an argument is too long ({len(too_long)} characters, at most {_MAX_PATH}): "
             f"{_short(too_long)}", stream=sys.stderr)
        return _EXIT_USAGE
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # --help, --version (0) or a usage error (2, already printed)
        return e.code if isinstance(e.code, int) else _EXIT_USAGE
    if args.command is None:
        parser.print_help(sys.stderr)
        return _EXIT_USAGE
    try:
        return args.func(args)
    except ValueError as e:
        _say(f"{_PREFIX}{flag_names(str(e))}", stream=sys.stderr)
        return _EXIT_USAGE
    except KeyboardInterrupt:
        _say("shakedown: interrupted", stream=sys.stderr)
        return _EXIT_INTERRUPTED
    except (RuntimeError, OSError, ImportError) as e:
        _say(f"{_PREFIX}{type(e).__name__}: {flag_names(str(e))}", stream=sys.stderr)
        return _EXIT_FAILED


if __name__ == "__main__":
    sys.exit(main())
