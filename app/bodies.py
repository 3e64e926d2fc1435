"""The explorer's bodies: every body of :data:`core.geometry.registry.REGISTRY`, its parameters as explorer inputs.

The body selector offers the registry's bodies in its order; each body's
:class:`core.geometry.registry.Parameter` becomes one input of
:class:`app.state.ExplorerState` (same name, default, range and doc; named
``<body>_<parameter>`` if another input has the name already), so a body
registered in :mod:`core.geometry.registry` appears in the explorer, with its
parameters kept in the URL, and no edit here. What this module adds:

* :func:`make`: the body object of a name and the inputs' values (built by the
  registry entry, cached: one object per body and parameters, shared by the
  sessions, so a run's cache key and a height map's normal solve are reused);
* a *source* for each parameter that is a file (:attr:`core.geometry.registry.Parameter.path`):
  a built-in demo (:data:`DEMO_FILES`, one line per body) or a file the
  visitor uploads (:func:`store_upload`), named in the URL as ``demo`` or
  ``upload-<digest>``;
* :func:`runs_cycles`: whether the app can run a body's cycles (a line body of
  :mod:`core.geometry.bodies`, an ellipsoid, or a point body with its own run grid);
  one that cannot is shown with its limit only (the "limit only" note).

No physics here: the demo height map is a documented shape (:func:`demo_heights`),
its pressure and every number come from :mod:`core`.
"""

from __future__ import annotations

import functools
import hashlib
import io
import math
import re
import threading
from collections import OrderedDict

import numpy as np
import param

__all__ = ["BODIES", "DEFAULT", "has_closure", "shown_parameters", "kind", "entry", "parameters", "state_name", "make", "runs_cycles", "own_grid", "is_ellipsoid",
           "DEMO_FILES", "demo_heights", "wide", "demo_file", "store_upload", "uploaded", "SOURCE_PATTERN", "limit_curve",
           "note"]


def _registry() -> dict:
    from core.geometry.registry import REGISTRY
    return REGISTRY


#: The body selector's options: the registry's bodies, in its order (the cylinder, the paper's, first).
BODIES: tuple[str, ...] = tuple(_registry())
#: The default body: the registry's first (the paper's). The page describes it already and a run of it
#: carries no body option.
DEFAULT: str = BODIES[0]


def has_closure(body) -> bool:
    """Whether ``body`` (a name or a body object) has the closed-form shaken-down state the cards show beside the
    solver's (stick half-width eq 30, limit eq 35): the registry's body tells (``shakedown_stick_halfwidth``)."""
    from core.geometry.registry import resolve

    try:
        spec = resolve(body)
    except ValueError:  # a body that needs inputs to be built (a height map's file): it has none
        return False
    return getattr(spec, "shakedown_stick_halfwidth", None) is not None


def shown_parameters(name: str, spec) -> dict:
    """The parameters of body object ``spec`` that its registry entry ``name`` declares (the sphere's ratio of 1
    is no parameter of the sphere's)."""
    own = {p.name for p in parameters(name)} if name in BODIES else set(getattr(spec, "parameters", {}))
    return {k: v for k, v in dict(getattr(spec, "parameters", {})).items() if k in own}


def entry(name: str):
    """The registry entry of body ``name``."""
    return _registry()[name]


def kind(name: str) -> str:
    """``"line"`` or ``"point"``: the kind of body ``name`` (a line contact on the 1D engine, or a point contact)."""
    return entry(name).kind


# --------------------------------------------------------------------------
# the demo height map and uploaded files
# --------------------------------------------------------------------------
#: Demo map: grid points per side, spacing [a], the flat top's radius [a], the roughness' rms [P/(E* a)], its seed.
DEMO_GRID, DEMO_SPACING, DEMO_FLAT, DEMO_RMS, DEMO_SEED = 32, 0.1, 0.3, 0.004, 20


def demo_heights() -> np.ndarray:
    """The demo surface's heights [P/(E* a)] on a ``DEMO_GRID`` square grid of step ``DEMO_SPACING`` a, centred.

    A rough sphere with a flattened top: the gap is Hertz's sphere's
    ``(3/8) r^2`` (in these units its contact radius is ``a``) beyond the flat
    top ``r > DEMO_FLAT``, ``(3/8) (r - DEMO_FLAT)^2``, plus independent
    Gaussian roughness of rms ``DEMO_RMS`` per sample (``numpy.random.default_rng(DEMO_SEED)``).
    The heights are the surface's (minus the gap): a bump touches first.
    Its contact reaches about ``1.1 a`` from the centre, inside the map's ``1.6 a``.
    """
    x = (np.arange(DEMO_GRID) - DEMO_GRID // 2) * DEMO_SPACING
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    gap = 0.375 * np.maximum(r - DEMO_FLAT, 0.0) ** 2
    gap += DEMO_RMS * np.random.default_rng(DEMO_SEED).standard_normal(gap.shape)
    return -gap


_LOCK = threading.Lock()


@functools.lru_cache(maxsize=1)
def _demo_heightmap():
    """The demo map (:func:`demo_heights`) as a SurfaceTopography topography (built once, in memory)."""
    from SurfaceTopography import Topography

    side = DEMO_GRID * DEMO_SPACING
    return Topography(demo_heights(), (side, side))


#: The built-in topography of each file parameter that has one, by (body, parameter): what ``demo`` stands for.
DEMO_FILES = {("heightmap", "file"): _demo_heightmap}
#: The values a file parameter takes in the URL: the demo, or an uploaded file by its digest.
SOURCE_PATTERN = re.compile(r"^(demo|upload-[0-9a-f]{16})$")
#: Largest upload accepted [bytes].
MAX_UPLOAD_BYTES = 20 * 2**20
#: Uploads kept in this process's memory (the oldest dropped first): nothing a browser sends touches the disk.
MAX_UPLOADS = 16
_UPLOADS: OrderedDict = OrderedDict()  # source name -> (the file's bytes, its name as the browser gave it)
_READ: dict = {}  # source name -> its topography, read once


def store_upload(data: bytes, filename: str = "") -> str:
    """Keep an uploaded file in this server's memory (by its digest) and return its source name
    ``upload-<digest>`` (what the URL carries; any session of this server can open it). The file is read
    (by SurfaceTopography, which tells its format from its contents) when a body is built from it.

    Raises
    ------
    ValueError
        If ``data`` is empty or larger than ``MAX_UPLOAD_BYTES``.
    """
    if not data:
        raise ValueError("the uploaded file is empty")
    if len(data) > MAX_UPLOAD_BYTES:
        raise ValueError(f"the uploaded file must be at most {MAX_UPLOAD_BYTES // 2**20} MB, got {len(data) / 2**20:.1f} MB")
    source = f"upload-{hashlib.sha1(bytes(data)).hexdigest()[:16]}"
    with _LOCK:
        _UPLOADS[source] = (bytes(data), " ".join(str(filename).split())[:80])
        _UPLOADS.move_to_end(source)
        while len(_UPLOADS) > MAX_UPLOADS:
            _READ.pop(_UPLOADS.popitem(last=False)[0], None)
    return source


def uploaded(source: str):
    """The topography of an uploaded ``source`` (``upload-<digest>``) on this server (read once from memory),
    or None if there is none.

    Raises
    ------
    ValueError
        For a file no reader understands (naming the readable formats) or one its reader cannot read, as
        :func:`core.geometry.heightmap.read_topography` says it (the same words as the command line's).
    """
    from core.geometry.heightmap import read_topography

    with _LOCK:
        data, filename = _UPLOADS.get(source, (None, ""))
        done = _READ.get(source)
    if data is None or done is not None:
        return done
    topography = read_topography(io.BytesIO(data), name=f"the uploaded file {filename}".strip())
    with _LOCK:
        return _READ.setdefault(source, topography)


def demo_file(body: str, name: str):
    """The built-in topography of file parameter ``name`` of ``body``, or None if it has none."""
    build = DEMO_FILES.get((body, name))
    return None if build is None else build()


# --------------------------------------------------------------------------
# parameters as explorer inputs
# --------------------------------------------------------------------------
def parameters(name: str) -> tuple:
    """The registry's parameters of body ``name``."""
    return tuple(entry(name).parameters)


#: Names of the explorer's own inputs (a body parameter of one of these names is prefixed with its body's name).
_RESERVED = {"ft", "w", "mu", "body", "R", "L", "Fn", "E2", "nu2", "rigid", "E1", "nu1", "periods", "resolution",
             "point_resolution", "kernel", "schedule", "loading", "amplitude", "phase", "units", "name"}


@functools.lru_cache(maxsize=None)
def _names() -> dict:
    """(body, parameter) -> the explorer input's name: the parameter's own, or ``<body>_<parameter>`` if taken."""
    out, taken = {}, set(_RESERVED)
    for body in BODIES:
        for p in parameters(body):
            name = p.name if p.name not in taken else f"{body}_{p.name}"
            out[(body, p.name)] = name
            taken.add(name)
    return out


def state_name(body: str, parameter: str) -> str:
    """The explorer input (and URL key) of parameter ``parameter`` of ``body``."""
    return _names()[(body, parameter)]


def _step(lo: float, hi: float) -> float:
    span = hi - lo
    return 10.0 ** math.floor(math.log10(span / 50.0)) if span > 0 else 0.01


def wide(p) -> bool:
    """Whether numeric parameter ``p`` spans many decades (a unit's scale) or has no finite range: a number box
    rather than a slider."""
    lo, hi = float(p.lo), float(p.hi)
    return not (math.isfinite(lo) and math.isfinite(hi)) or (lo > 0 and hi / lo > 1e3)


#: The inputs' labels in a user's words, by (body, parameter); a body registered later without one here is
#: labelled with its parameter's name in words (:func:`label`).
LABELS = {("punch", "flat"): "Flat part b/a", ("ellipsoid", "ratio"): "Radii ratio Ry/Rx",
          ("heightmap", "file"): "Height map", ("heightmap", "length_unit"): "a in the file's length unit",
          ("heightmap", "height_unit"): "P/(E* a) in the file's height unit",
          ("cone", "inner"): "Inner end r1/r2 (0: a full cone)", ("cone", "length"): "Contact length L/a",
          ("cone", "load_at"): "Where Ft acts (0 inner end, 1 outer end)"}


def label(body: str, parameter: str) -> str:
    """The label of the input of ``parameter`` of ``body`` (:data:`LABELS`, else the name in words)."""
    return LABELS.get((body, parameter)) or parameter.replace("_", " ").capitalize()


def state_parameters() -> dict:
    """The explorer inputs of every body's parameters (param objects, by input name)."""
    out = {}
    for body in BODIES:
        for p in parameters(body):
            text = label(body, p.name)
            doc = f"{p.doc[:1].upper()}{p.doc[1:]}"
            if p.path:
                out[state_name(body, p.name)] = param.String(
                    "demo", regex=SOURCE_PATTERN.pattern, label=text,
                    doc=f"{doc}: 'demo' (the built-in map) or 'upload-<digest>' (a file uploaded to this server).")
                continue
            lo, hi = float(p.lo), float(p.hi)
            default = None if p.default is None else float(p.default)
            centre = default if default else (lo if math.isfinite(lo) and lo > 0 else 1.0)
            if wide(p):  # a scale over decades (a file's units): typed in, the slider range a decade each side
                soft, step, unit = (max(lo, centre / 10), min(hi, centre * 10)), abs(centre) / 100, "[scale]"
            else:  # the registry's parameters are normalised: dimensionless
                soft, step, unit = (lo, hi if p.hi_closed else hi - _step(lo, hi)), _step(lo, hi), "[-]"
            out[state_name(body, p.name)] = param.Number(
                default, bounds=(lo, hi), inclusive_bounds=(True, bool(p.hi_closed)), softbounds=soft, step=step,
                allow_None=default is None, label=text,
                doc=f"{doc} {unit}, in [{lo:g}, {hi:g}{']' if p.hi_closed else ')'}"
                    + ("; empty: the body's own default." if default is None else "."))
    return out


# --------------------------------------------------------------------------
# the body objects
# --------------------------------------------------------------------------
@functools.lru_cache(maxsize=64)
def _make(name: str, values: tuple):
    return entry(name).make(**dict(values))


def make(name: str, values: dict):
    """The body ``name`` with parameters ``values`` (by parameter name; files as sources, see :data:`DEMO_FILES`),
    built by its registry entry; the same object for the same inputs.

    Raises
    ------
    ValueError
        For a value out of its range, a file parameter without a file, or a body the registry cannot build.
    """
    out = []
    for p in parameters(name):
        value = values.get(p.name, p.default)
        if value is None and not p.path:  # no value: the entry's own default
            continue
        if p.path:
            source = str(value)
            try:
                path = demo_file(name, p.name) if source == "demo" else uploaded(source)
            except ValueError as e:  # a file no reader understands (the formats named) or cannot read
                raise ValueError(f"body {name!r} cannot be built: {e}") from e
            except Exception as e:  # noqa: BLE001 - the reader's own errors name what it could not read
                why = " ".join(str(e).split())[:300]
                raise ValueError(f"body {name!r} cannot be built: its {p.name} {source!r} cannot be read: "
                                 f"{type(e).__name__}: {why}") from e
            if path is None:
                raise ValueError(f"{p.name} of body {name!r}: no file {source!r} on this server (upload one)"
                                 if source != "demo" else f"{p.name} of body {name!r}: no built-in file; upload one")
            value = path
        out.append((p.name, p.check(value)))
    try:
        return _make(name, tuple(out))
    except ValueError:
        raise
    except Exception as e:  # noqa: BLE001 - a reader's own errors (an uploaded file it cannot read) name the file
        if isinstance(e, (TypeError, NotImplementedError, OSError)) or any(p.path for p in parameters(name)):
            raise ValueError(f"body {name!r} cannot be built: {type(e).__name__}: {str(e).strip()[:300]}") from e
        raise


def is_ellipsoid(body) -> bool:
    """Whether ``body`` is a Hertz ellipsoid (:class:`core.Ellipsoid`: a sphere or an ellipsoid)."""
    import core
    return isinstance(body, core.Ellipsoid)


def own_grid(body) -> bool:
    """Whether ``body`` runs on a fixed grid of its own (a sampled surface, e.g. a height map: its ``spacing``),
    not at the explorer's resolution."""
    return hasattr(body, "run_grid") and hasattr(body, "spacing")


def runs_cycles(name: str, body) -> bool:
    """Whether the explorer can run ``body``'s cycles: a line body of :mod:`core.geometry.bodies`, an ellipsoid, or a point
    body with the 3D solver's interface (``run_grid`` and ``grid_pressure``: a height map, the cone). Another
    body is shown with its limit only."""
    import core
    if kind(name) == "line":
        return isinstance(body, core.Body)
    return is_ellipsoid(body) or (hasattr(body, "run_grid") and hasattr(body, "grid_pressure"))


def note(name: str) -> str:
    """One line about body ``name`` under the selector: what it is (the registry's doc) and its scales."""
    e = entry(name)
    text = f"**{name}**: {e.doc}."
    if kind(name) == "point":
        text += " R is the relative radius along the rocking direction x; physical units use Hertz's sphere of R."
    else:
        text += " Physical units use Hertz's cylinder of radius R and length L."
    return text


@functools.lru_cache(maxsize=32)
def limit_curve(body) -> tuple:
    """The exact limit of ``body`` as ``(ft_lim(w), w)`` (:func:`core.ft_limit`), for the map (cached per body).

    ``w`` from 0 to 0.98 (a body with its own grid: at the multiples of its spacing, where its limit needs no
    new normal solve). Empty if the limit cannot be evaluated.
    """
    import core
    if own_grid(body):
        h = float(body.spacing)
        w = h * np.arange(0, math.floor(0.98 / h) + 1)
    else:
        w = np.linspace(0.0, 0.98, 50)
    try:
        ft = np.asarray(core.ft_limit(w, body=body), dtype=float)
    except (ValueError, TypeError, NotImplementedError):
        return np.zeros(0), np.zeros(0)
    return ft, w
