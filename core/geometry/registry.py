"""Every body a run can use, with its parameters: the one list the API and the CLI read.

Each entry names a body, how to build it from its parameters, its
parameters (default, range, meaning) and its kind: ``"line"`` (a line
contact on the 1D engine, :class:`core.geometry.bodies.Body`) or ``"point"`` (a point
contact on the 3D solver, :class:`core.theory.point_contact.Ellipsoid`,
:class:`core.geometry.heightmap.HeightMap` or :class:`core.geometry.cone.Cone`).
:func:`make_body` builds a body from a name and parameters;
:func:`describe` lists them (``shakedown`` prints it in its help).

A new line body needs no entry here to run (``core.simulate_cycles(...,
body=MyBody())`` takes any :class:`core.geometry.bodies.Body`); an entry makes it
reachable by name from the CLI (see ``docs/dev/adding-a-body.md``).

Examples
--------
>>> from core.geometry.registry import make_body, REGISTRY
>>> make_body("punch", flat=0.8), make_body("ellipsoid", ratio=2.0)
(Punch(flat=0.8), Ellipsoid(ratio=2.0))
>>> sorted(REGISTRY)
['cone', 'cylinder', 'ellipsoid', 'heightmap', 'punch', 'sphere']
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

__all__ = ["Parameter", "BodyEntry", "REGISTRY", "DEFAULT", "make_body", "register", "describe", "body_name",
           "resolve", "kind", "point_body", "flags"]

#: The default body's name: the paper's cylinder (a run without ``body``).
DEFAULT = "cylinder"


@dataclass(frozen=True)
class Parameter:
    """One parameter of a body: its name, default, range ``[lo, hi)`` (or closed) and meaning."""

    name: str
    default: float
    lo: float
    hi: float
    doc: str
    hi_closed: bool = True
    #: A path to a file (``--file``) or what was read from one, not a number: ``default`` None, no range.
    path: bool = False
    #: Also a keyword of :func:`core.simulate_cycles` (the ellipsoid's ``ratio``): a run by name needs it given
    #: (:func:`point_body`: no default taken silently); ``default`` serves :func:`make_body` alone.
    keyword: bool = False

    def check(self, value):
        """The value as a float (a path: a str), or ValueError naming the parameter and its range."""
        from ..base._validate import check_scalar  # here: the registry imports nothing heavy (the CLI's help reads it)

        if self.path:  # a file's path, or what was read from one (a SurfaceTopography topography: has heights())
            if not isinstance(value, (str, bytes)) and not hasattr(value, "__fspath__") and not (
                    hasattr(value, "heights") and hasattr(value, "dim")):
                raise ValueError(f"{self.name} must be a path or a topography, got {type(value).__name__}")
            return value
        return check_scalar(self.name, value, self.lo, self.hi, hi_closed=self.hi_closed)


@dataclass(frozen=True)
class BodyEntry:
    """A registered body: ``make(**parameters)`` builds it."""

    name: str
    make: Callable
    kind: str
    doc: str
    parameters: tuple = field(default_factory=tuple)
    #: Run options of :func:`core.simulate_cycles` the body takes besides its parameters (e.g. ``"angle"``: the
    #: direction of Ft on a patch); the CLI offers their flags with this body only.
    options: tuple = ()
    #: Its exact limit in words, where it has a closed form (the CLI's ``limit`` table names it).
    exact_limit: str = ""


def _punch(flat=0.5):
    from .bodies import Punch
    return Punch(flat=flat)


def _cylinder():
    from .bodies import Cylinder
    return Cylinder()


def _ellipsoid(ratio=2.0):
    from ..theory.point_contact import Ellipsoid
    return Ellipsoid(ratio)


def _heightmap(file=None, length_unit=1.0, height_unit=1.0):
    if file is None:
        raise ValueError("body 'heightmap' needs a file: a profilometer map SurfaceTopography reads (--file PATH)")
    from .heightmap import HeightMap
    return HeightMap.from_topography(file, length_unit=length_unit, height_unit=height_unit)


def _cone(inner=0.5, length=None, load_at=0.5):
    from .cone import DEFAULT_LENGTH, Cone
    load_point = "centre" if load_at == 0.5 else inner + load_at * (1.0 - inner)
    return Cone(inner=inner, load_point=load_point, length=DEFAULT_LENGTH if length is None else length)


def _sphere():
    from ..theory.point_contact import Ellipsoid
    return Ellipsoid(1.0)


#: The bodies by name.
REGISTRY: dict[str, BodyEntry] = {}


def register(entry: BodyEntry) -> BodyEntry:
    """Add (or replace) a body in :data:`REGISTRY`; line bodies also become names of :data:`core.geometry.bodies.BODIES`."""
    _add(entry)
    if entry.kind == "line":
        from .bodies import BODIES
        BODIES.setdefault(entry.name, type(entry.make()))
    return entry


def _add(entry: BodyEntry) -> BodyEntry:
    """Add a body to :data:`REGISTRY` only (the built-in line bodies are in :data:`core.geometry.bodies.BODIES` already:
    importing the registry imports no body module)."""
    if entry.kind not in ("line", "point"):
        raise ValueError(f"kind must be 'line' or 'point', got {entry.kind!r:.40}")
    REGISTRY[entry.name] = entry
    return entry


_POINT_LIMIT = "the point contacts' ft = 1 - 3w/2 + w^3/2"
_add(BodyEntry("cylinder", _cylinder, "line", "the rocking cylinder (Hertz line contact, the paper's)",
               exact_limit="eq 35"))
_add(BodyEntry("punch", _punch, "line", "the rounded flat punch (plane strain, Ciavarella, Hills and Monno 1998)",
                   (Parameter("flat", 0.5, 0.0, 1.0, "flat half-width over the contact half-width, b/a",
                              hi_closed=False),)))
_add(BodyEntry("sphere", _sphere, "point", "the rocking sphere (Hertz point contact)", options=("angle",),
               exact_limit=_POINT_LIMIT))
_add(BodyEntry("ellipsoid", _ellipsoid, "point", "the rocking ellipsoid, rocked along its x axis",
               (Parameter("ratio", 2.0, 0.05, 20.0, "Ry/Rx, its principal relative radii's ratio", keyword=True),), options=("angle",),
               exact_limit=_POINT_LIMIT))
_add(BodyEntry("heightmap", _heightmap, "point", "a measured or designed surface (a height map read by "
                   "SurfaceTopography), rocked along x like the sphere on its own grid",
                   (Parameter("file", None, 0.0, 0.0, "the map's file (any format SurfaceTopography reads)", path=True),
                    Parameter("length_unit", 1.0, 1e-12, 1e12, "a in the file's length unit"),
                    Parameter("height_unit", 1.0, 1e-12, 1e12, "P/(E* a) in the file's height unit")),
               options=("angle",)))
_add(BodyEntry("cone", _cone, "point", "the rocking cone or frustum (a tapered roller) on its side, turning about "
                   "the vertical axis through its apex, free to translate and turn about the normal; "
                   "a and w at the mid-length",
                   (Parameter("inner", 0.5, 0.0, 1.0, "r1/r2, the inner end's distance from the apex over the outer "
                              "end's (0: a full cone)", hi_closed=False),
                    Parameter("length", 10.0, 4.0, 200.0, "L/a_m, the contact length over the half-width at the "
                              "mid-length (the slice model needs it large; the run's grid grows with it)"),
                    Parameter("load_at", 0.5, 0.0, 1.0, "where Ft acts along the contact, (r_F - r1)/(r2 - r1) "
                              "(0.5: the mid-length)"))))


def make_body(name, **parameters):
    """The body ``name`` of :data:`REGISTRY` with ``parameters`` (missing ones at their defaults).

    Raises
    ------
    ValueError
        For an unknown name or parameter, or a value out of its range.
    """
    if name not in REGISTRY:
        raise ValueError(f"body must be one of {', '.join(sorted(REGISTRY))}, got {name!r:.60}")
    entry = REGISTRY[name]
    known = {p.name: p for p in entry.parameters}
    unknown = sorted(set(parameters) - set(known))
    if unknown:
        allowed = ", ".join(known) or "none"
        raise ValueError(f"body {name!r} has no parameter(s) {', '.join(unknown)} (its parameters: {allowed})")
    return entry.make(**{k: known[k].check(v) for k, v in parameters.items()})


def resolve(body=None):
    """The body object of ``body``: a registered name (its default parameters), a body class or a body object.

    ``None`` is the default body, the cylinder. This is the one place where a body's name becomes a body.

    Raises
    ------
    ValueError
        For a name that is not registered (the message lists the names).
    """
    if body is None:
        body = DEFAULT
    if isinstance(body, str):
        return make_body(body)
    if isinstance(body, type):
        return body()
    return body


def kind(body) -> str:
    """``"line"`` (a line contact on the 1D engine) or ``"point"`` (a patch of elements) for a name or body object.

    Raises
    ------
    ValueError
        For a name that is not registered.
    """
    if body is None or isinstance(body, str):
        name = DEFAULT if body is None else body
        if name not in REGISTRY:  # the registry's order: the paper's cylinder first
            raise ValueError(f"body must be one of {', '.join(REGISTRY)}, got {name!r:.60}")
        return REGISTRY[name].kind
    return "line" if getattr(body, "dim", None) == 1 else "point"


def point_body(body, ratio=None):
    """A point body object from a registered name or an object, with ``ratio = Ry/Rx`` for a body that takes it.

    A name whose entry has a ``ratio`` parameter needs ``ratio``; ``ratio`` for another body is refused unless it
    is the body's own (the sphere's 1).

    Raises
    ------
    ValueError
        For a line body, an unknown name, or a ``ratio`` the body does not take.
    """
    if kind(body) != "point":
        raise ValueError(f"body must be a point body ({', '.join(n for n, e in REGISTRY.items() if e.kind == 'point')}"
                         f" or an object), got {body!r:.60}")
    if not isinstance(body, str):
        own = getattr(body, "ratio", None)
        if ratio is not None and (own is None or float(ratio) != own):
            raise ValueError(f"ratio = {ratio!r} contradicts body = {body!r}" if own is not None else
                             f"ratio is the ellipsoid's, not a {type(body).__name__}'s: got ratio={ratio!r}")
        return body
    takes_ratio = {p.name: p for p in REGISTRY[body].parameters}.get("ratio")
    if takes_ratio is not None and ratio is None:  # its shape: no default taken silently
        raise ValueError(f"body={body!r} needs ratio = Ry/Rx in [{takes_ratio.lo:g}, {takes_ratio.hi:g}]")
    if ratio is None or takes_ratio is not None:
        return make_body(body, **({} if ratio is None else {"ratio": ratio}))
    made = make_body(body)
    if float(ratio) != getattr(made, "ratio", None):
        raise ValueError(f"body {body!r} takes no ratio (got ratio = {ratio!r}): use a body with one, "
                         f"{', '.join(n for n, e in REGISTRY.items() if any(p.name == 'ratio' for p in e.parameters))}")
    return made


def body_name(body) -> str:
    """The registry name of a body given by name or object."""
    return body if isinstance(body, str) else body.name


def describe() -> str:
    """One line per body: its name, kind, parameters with defaults and ranges, and what it is."""
    lines = []
    for e in REGISTRY.values():
        params = ", ".join(f"--{p.name.replace('_', '-')} PATH" if p.path else
                           f"--{p.name.replace('_', '-')} {p.default:g} in [{p.lo:g}, {p.hi:g}{']' if p.hi_closed else ')'}"
                           for p in e.parameters)
        lines.append(f"{e.name} ({e.kind}{'; ' + params if params else ''}): {e.doc}")
    return "\n".join(lines)


def flags() -> dict:
    """Each body parameter and run option a body takes (:attr:`BodyEntry.options`), with the bodies that take it,
    in the registry's order: what the CLI makes its body flags of.

    Examples
    --------
    >>> flags()["flat"], flags()["angle"]
    (('punch',), ('sphere', 'ellipsoid', 'heightmap'))
    """
    out = {}
    for entry in REGISTRY.values():
        for name in (*(p.name for p in entry.parameters), *entry.options):
            out.setdefault(name, [])
            out[name].append(entry.name)
    return {name: tuple(bodies) for name, bodies in out.items()}
