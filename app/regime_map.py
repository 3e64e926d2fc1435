"""The regime map of the explorer: the (ft, w) plane of the rocking (the (mean ft, amplitude) plane of the
tangential loading) with the lines of the run's loading, a sweep's runs and its boundary, the run's body's own
limit, a coupled contact's limit curve and the current point.

One figure of :data:`app.plots.FIGURES` (its ``"map"`` entry: :func:`specs`, :func:`layers`), in a module of its own
because its layers are many: the exact limits (eq 35, the sphere's and ellipsoid's, the paper's Fig 14), the
paper's regression (eq 36), the closure's c_sd contours, Melan's limit under an oscillating normal force, the
gross-sliding boundary, and a coupled contact's limit beside eq 35 as the uncoupled reference. Like every figure
module: plain layer data from memoised functions of the inputs, no physics (every curve from :mod:`core`), no
Bokeh model at import.
"""

from __future__ import annotations

import math
from functools import lru_cache

import holoviews as hv
import holoviews.plotting.bokeh  # noqa: F401 - registers the Bokeh backend and its options
import numpy as np

import core
from core.theory import approximations as approx

from .live import Layer, Styled
from .looks import EMPTY as _EMPTY, LINE, OKABE_ITO as _C, REGIME_COLORS, REGIME_MARKERS, memo as _memo

__all__ = ["specs", "layers", "map_base", "map_numerical", "map_point", "grid_boundary", "map_lines", "map_history",
           "map_coupled", "body_limit", "is_tangential", "GROSS_SLIDING", "EQ35_REFERENCE", "COUPLED_LIMIT"]

_CSD_LEVELS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
#: Axis labels that read for both planes: (ft, w) of the rocking loadings, (mean ft, A) of the tangential one
_MAP_X, _MAP_Y = "ft = Ft / (μ Fn) (tangential: its mean)", "w = W / a (tangential: amplitude A)"
_MAP_DIMS = (hv.Dimension("ft", label=_MAP_X), hv.Dimension("w", label=_MAP_Y))


@lru_cache(maxsize=1)
def map_base() -> hv.Overlay:
    """The (ft, w) plane of the rocking under constant loads: exact limits (the cylinder's eq 35, the sphere's and
    ellipsoid's ``(1 - w)^2 (2 + w)/2``, the paper's Fig 14), the paper's regression (eq 36) and c_sd/a contours of
    the closure (the map draws them under the rocking loading: :func:`map_lines`)."""
    kd = [hv.Dimension("ft", label=_MAP_X, range=(0, 1)), hv.Dimension("w", label=_MAP_Y, range=(0, 1))]
    ft = np.linspace(0.0, 1.0, 401)
    n = 161
    g = (np.arange(n) + 0.5) / n
    FT, W = np.meshgrid(g, g)
    csd = core.shakedown_stick_halfwidth(FT * 0.999, W * 0.999)
    img = hv.Image((g, g, csd), kdims=kd, vdims=[hv.Dimension("c_sd", label="c_sd / a (closure)")])
    contours = hv.operation.contours(img, levels=_CSD_LEVELS, filled=False).opts(
        cmap="viridis", line_width=2, colorbar=True, show_legend=False,
        colorbar_opts={"title": "c_sd / a (closure)"})
    return hv.Overlay([
        contours,
        hv.Curve((ft, core.w_limit(ft)), kdims=kd[:1], vdims=kd[1:], label="eq 35 (exact)").opts(
            color="black", line_width=LINE + 1),
        hv.Curve((ft, core.w_limit(ft, body="sphere")), kdims=kd[:1], vdims=kd[1:],
                 label="sphere, ellipsoid (exact)").opts(color=_C["purple"], line_dash="dotdash", line_width=LINE),
        hv.Curve((ft, approx.w_limit_regression(ft)), kdims=kd[:1], vdims=kd[1:],
                 label="eq 36 regression").opts(color=_C["orange"], line_dash="dashed",
                                                                       line_width=LINE),
    ])


def grid_boundary(table) -> tuple[np.ndarray, np.ndarray]:
    """The numerical boundary of a sweep table: per ``ft``, midway between the largest ``w`` that shook
    down and the next ``w`` of the grid (the grid's resolution of the numerical limit)."""
    fts, ws = [], []
    if table is None or len(table) == 0:
        return np.array(fts), np.array(ws)
    for ft, group in table.sort_values(["ft", "w"]).groupby("ft", sort=True):
        w = group["w"].to_numpy(float)
        ok = group["regime"].isin(("shakedown", "cyclic slip")).to_numpy()  # not ratcheting, as the limit search
        if ok.all() or not ok.any():
            continue
        k = int(np.argmin(ok))  # first grid w that did not shake down
        fts.append(float(ft))
        ws.append(0.5 * (w[k - 1] + w[k]) if k > 0 else 0.5 * w[0])
    return np.array(fts), np.array(ws)


_MAP_REGIMES = ("shakedown", "cyclic slip", "ratcheting", "undetermined")
#: The fretting map's gross-sliding boundary |ft| + A = 1 (|Q| reaches μ P) in the (mean ft, amplitude) plane.
GROSS_SLIDING = (np.array([0.0, 1.0]), np.array([1.0, 0.0]))


def is_tangential(table) -> bool:
    """Whether a sweep table is of the tangential loading: its plane is (mean ft, amplitude), not (ft, w)."""
    return table is not None and "history" in table.columns and bool((table["history"] == "tangential").any())


#: The region names of each history's map: (x, y, name) in its plane (the normal loading's x scaled by 1 - A).
_REGION_NAMES = {"rocking": ((0.2, 0.25, "shakedown"), (0.8, 0.5, "ratcheting")),
                 "normal": ((0.2, 0.25, "shakedown"), (0.8, 0.5, "ratcheting")),
                 "tangential": ((0.15, 0.12, "cyclic slip"), (0.72, 0.62, "gross sliding"))}
_REGION_DIMS = (*_MAP_DIMS, hv.Dimension("name"))


def specs(units=None, label: str = "solver") -> list:
    """How the map's layers are drawn (the same in every unit system: the map's axes are normalised)."""
    kd = _MAP_DIMS
    base = {e.label: e for e in map_base() if isinstance(e, hv.Curve)}

    def curve(name, **style):
        return Layer(hv.Curve, kd[:1], kd[1:], name, style)

    return [
        *[Layer(hv.Points, kd, (), f"{regime}, {label}",
                dict(color=REGIME_COLORS[regime], marker=REGIME_MARKERS[regime], size=8, alpha=0.7, line_alpha=0))
          for regime in _MAP_REGIMES],
        # the grid resolves the limit to half a grid step: markers, not a line that would look like a staircase
        Layer(hv.Points, kd, (), "numerical limit ±½ step",
              dict(color="black", fill_color="white", marker="diamond", size=11, line_width=2)),
        # each history's lines (:func:`map_lines`): the rocking's limits, the normal loading's Melan limit at its
        # amplitude and phase, the gross-sliding boundary of the oscillating loads
        curve("gross sliding: |Q| reaches μ Fn", color="black", line_width=LINE + 1, line_dash="dashed"),
        Layer(hv.Contours, kd, (hv.Dimension("c_sd", label="c_sd / a (closure)"),), "",
              dict(cmap="viridis", line_width=2, color="c_sd", clim=(0.0, 1.0), show_legend=False)),
        *[curve(name, **dict(base[name].opts.get().kwargs)) for name in _ROCKING_LINES],
        curve("Melan's limit, oscillating Fn (this body)", color=_C["green"], line_width=LINE + 1,
              line_dash="dotdash"),
        Layer(hv.Labels, kd, _REGION_DIMS[2:], "", dict(text_font_size="11px", text_color="#444444")),
        Layer(hv.Labels, kd, _REGION_DIMS[2:], "", dict(text_font_size="16px", text_color="black")),
        curve("this body's exact limit (Melan)", color=_C["green"], line_width=LINE + 1, line_dash="solid"),
        # a coupled contact (Dundurs β ≠ 0): eq 35 is only the uncoupled reference; the coupled limit is the
        # solver's, found by bisection at a few w (:func:`map_coupled`): each w's bracket, and a line through them
        curve(EQ35_REFERENCE, color="black", line_width=LINE, line_dash="dashed"),
        curve(COUPLED_LIMIT, color=_C["vermillion"], line_width=LINE + 1, line_dash="solid"),
        Layer(hv.Curve, kd[:1], kd[1:], "", dict(color=_C["vermillion"], line_width=LINE + 6, alpha=0.6)),
        Layer(hv.Points, kd, (), "current point", dict(size=18, marker="circle", line_color="black", line_width=2)),
    ]


#: Legend labels of a coupled contact's limits on the map: eq 35 as the reference, the solver's coupled limit.
EQ35_REFERENCE = "eq 35 (uncoupled reference)"
COUPLED_LIMIT = "coupled limit (numerical, β ≠ 0)"


@_memo
def map_coupled(curve) -> tuple:
    """The map's layers of a coupled contact's limit curve (a :class:`core.CoupledLimitCurve`, maybe still partial:
    the amplitudes found so far): eq 35 as the uncoupled reference, a line through the brackets' midpoints, and the
    brackets themselves (one segment per w, NaN between them); empty layers for an uncoupled contact (None)."""
    if curve is None:
        return _EMPTY, _EMPTY, _EMPTY
    reference = tuple(e.dimension_values(i) for e in map_base() if isinstance(e, hv.Curve)
                      and e.label == "eq 35 (exact)" for i in (0, 1))
    ok = [p for p in curve.points if p.converged]
    line = (np.array([p.ft_limit for p in ok]), np.array([p.w for p in ok]))
    nan = [math.nan] * len(ok)
    brackets = (np.ravel(np.column_stack([[p.ft_shakedown for p in ok], [p.ft_ratcheting for p in ok], nan])),
                np.ravel(np.column_stack([[p.w for p in ok], [p.w for p in ok], nan])))
    return reference, line, brackets


#: The rocking plane's lines (of :func:`map_base`), drawn under the rocking loading only.
_ROCKING_LINES = ("eq 35 (exact)", "sphere, ellipsoid (exact)", "eq 36 regression")


def map_history(result) -> tuple:
    """The loading history of a run as its map reads it: ``(name, amplitude, phase, shape)`` (rocking without a
    run)."""
    if result is None:
        return ("rocking", 0.0, 0.0, "triangle")
    p = result.params
    history = str(p.get("history", "rocking"))
    if history == "normal" and float(p.get("amplitude", 0.0)) == 0.0:
        history = "rocking"  # no oscillation: the rocking's plane and limits
    return (history, float(p.get("amplitude", 0.0)), float(p.get("phase", 0.0)), str(p.get("shape", "triangle")))


@lru_cache(maxsize=8)
def _normal_limit(body, amplitude: float, phase: float, shape: str) -> tuple:
    """Melan's limit ``(ft_lim(w), w)`` of ``body`` rocked under the oscillating normal force
    (:func:`core.pressure.melan.ft_limit_oscillating`), or empty for a body it has no pressure of (a point contact: its
    integral over the plane takes seconds a point; the run's own limit is in its cards)."""
    from core.pressure.melan import ft_limit_oscillating

    if not isinstance(body, core.Body):
        return _EMPTY
    w = np.linspace(0.0, 0.98, 50)
    return ft_limit_oscillating(w, body, amplitude, phase, shape=shape, dx=1 / 500, samples=200), w


@_memo
def map_lines(history: tuple, body=None) -> tuple:
    """The data of the map's lines for a history (:func:`map_history`), in the order of their layers: the
    gross-sliding boundary, the c_sd contours, the rocking limits (eq 35, the sphere's, eq 36), Melan's limit
    under the oscillating normal force, the contours' values and the region names.

    * rocking: the (ft, w) plane of the constant loads: eq 35, the sphere's and ellipsoid's exact limit, the
      regression and the closure's c_sd contours;
    * normal (amplitude ``A > 0``): the (ft, w) plane at the run's amplitude and phase: Melan's limit of
      ``body`` (a line body; None: not drawn) under the oscillating force and gross sliding at the lowest
      force, ``ft = 1 - A``;
    * tangential: the (mean ft, amplitude A) plane: the gross-sliding boundary ``|ft| + A = 1``, below which
      every run slips cyclically; no limit of the rocking applies.
    """
    name, A, phase, shape = history
    base = {e.label: e for e in map_base() if isinstance(e, hv.Curve)}
    contours = next(e for e in map_base() if isinstance(e, hv.Contours))
    rocking = name == "rocking"
    if name == "tangential":
        gross = GROSS_SLIDING
    elif name == "normal":
        gross = (np.array([1.0 - A, 1.0 - A]), np.array([0.0, 1.0]))
    else:
        gross = _EMPTY
    curves = [tuple(base[n].dimension_values(i) for i in (0, 1)) if rocking else _EMPTY for n in _ROCKING_LINES]
    melan = _normal_limit(body, A, phase, shape) if name == "normal" and body is not None else _EMPTY
    scale = 1.0 - A if name == "normal" else 1.0
    names = tuple(np.array(c) for c in zip(*[(x * scale, y, t) for x, y, t in _REGION_NAMES[name]]))
    return (gross, contours.data if rocking else [], *curves, melan, _csd_levels() if rocking else (_EMPTY + ([],)),
            names)


@lru_cache(maxsize=1)
def _csd_levels() -> tuple:
    """The c_sd / a value of each contour of :func:`map_base`, written at its point nearest w = 0.15 (where the
    contours are furthest apart)."""
    contours = next(e for e in map_base() if isinstance(e, hv.Contours))
    xs, ys, texts = [], [], []
    for path in contours.split():
        ft, w = path.dimension_values(0), path.dimension_values(1)
        k = int(np.argmin(np.abs(w - 0.15)))
        xs.append(float(ft[k]))
        ys.append(float(w[k]))
        texts.append(f"{float(path.dimension_values(2)[0]):.1f}")
    return np.array(xs), np.array(ys), np.array(texts)


_NUMERICAL_MEMO: list = [None, None]  # (table, its layers): the map's numerical layers for the last table


def map_numerical(table) -> tuple:
    """Sweep results in the (ft, w) plane: each regime's runs and the grid's boundary between shakedown and
    ratcheting (:func:`grid_boundary`); a tangential loading's table in the (mean ft, amplitude) plane, without a
    boundary (its gross-sliding line is the history's: :func:`map_lines`)."""
    table_seen, layers = _NUMERICAL_MEMO
    if table_seen is table and layers is not None:
        return layers
    n = 1 if table is None else max(1.0, np.sqrt(len(table)))
    size = float(np.clip(260.0 / n, 6.0, 24.0))  # a small map's markers fill their grid cells
    tangential = is_tangential(table)
    y = "amplitude" if tangential else "w"
    runs = [Styled(_EMPTY if table is None else tuple(table.loc[table["regime"] == regime, c].to_numpy(float)
                                                     for c in ("ft", y)), {"size": size})
            for regime in _MAP_REGIMES]
    layers = (*runs, _EMPTY if tangential else grid_boundary(table))
    _NUMERICAL_MEMO[:] = [table, layers]
    return layers


@_memo
def map_point(ft: float, w: float, regime: str | None = None) -> Styled:
    """The current (ft, w), coloured and shaped by the numerical regime when known."""
    return Styled(([ft], [w]), {"fill_color": REGIME_COLORS.get(regime, REGIME_COLORS[None]),
                                "marker": REGIME_MARKERS.get(regime, REGIME_MARKERS[None])})


def _body_of(run) -> str:
    """The body of a run or a sweep table (a table without a 'body' column is the cylinder's)."""
    if isinstance(run, (core.PointContactResult, core.CycleResult)):
        spec = run.body if isinstance(run, core.PointContactResult) else (getattr(run, "body_spec", None) or run.body)
        if isinstance(spec, str) or isinstance(spec, (core.Cylinder, core.Ellipsoid)):
            return spec if isinstance(spec, str) else str(spec.name)
        return repr(spec)  # a body with parameters, as core.sweep names it: Punch(flat=0.8)
    columns = getattr(run, "columns", ())
    return str(run["body"].iloc[0]) if "body" in columns and len(run) else "cylinder"


def layers(i) -> tuple:
    """The data of each layer of the map (:func:`specs`) for the inputs ``i`` (an :class:`app.plots.Inputs`): the
    sweep's runs and boundary, the lines of the run's loading, the body's own limit, the coupled limit curve and the
    current point."""
    regime = None if i.result is None else i.result.regime
    # a sweep of another body than the run's is not drawn (the cylinder's shipped map beside a sphere's run)
    table = i.table if i.result is None or _body_of(i.result) == _body_of(i.table) else None
    tangential = i.result is not None and i.result.params.get("history") == "tangential"
    if tangential != is_tangential(table):  # a (ft, w) map beside a tangential run, or the other way round
        table = None
    if i.result is not None and not _same_loading(table, map_history(i.result)):
        table = None  # a sweep under another loading (the shipped constant-load map beside a 'normal' run)
    if not _same_coupling(table, 0.0 if i.coupled is None else i.coupled.beta):
        table = None  # an uncoupled sweep (the shipped map) beside a coupled contact, or the other way round
    # the current point: (mean ft, amplitude) under the tangential loading
    y = float(i.result.params.get("amplitude", 0.0)) if tangential else i.w
    history = map_history(i.result)
    body = None if i.result is None else getattr(i.result, "body_spec", None) or getattr(i.result, "body", None)
    lines = map_lines(history, body if isinstance(body, core.Body) else None)
    coupled = i.coupled if history[0] == "rocking" else None
    if coupled is not None:
        lines = _coupled_lines(lines)
    return (*map_numerical(table), *lines, body_limit(i.result) if history[0] == "rocking" else _EMPTY,
            *map_coupled(coupled), map_point(i.ft, y, regime))


def _coupled_lines(lines: tuple) -> tuple:
    """The rocking lines (:func:`map_lines`) of a coupled contact: none of the uncoupled closed forms. eq 35 is drawn
    as the one uncoupled reference by :func:`map_coupled`; the closure's c_sd contours (and their labels), the
    sphere's limit and the eq 36 regression are not drawn: the closure's stick zone is the uncoupled one (the
    traction figure draws no closure for a coupled run either), the point contacts take no β ≠ 0, and eq 36 fits
    eq 35."""
    gross, _, *curves, melan, _, names = lines
    return (gross, [], *[_EMPTY] * len(curves), melan, _EMPTY + ([],), names)


def _same_coupling(table, beta: float) -> bool:
    """Whether a sweep table was run with Dundurs' ``beta`` (to 1e-4, the coupled curve's rounding; a table without
    a 'beta' column is uncoupled, as the shipped map)."""
    if table is None or len(table) == 0:
        return True
    own = float(table["beta"].iloc[0]) if "beta" in getattr(table, "columns", ()) else 0.0
    return math.isclose(0.0 if math.isnan(own) else own, beta, abs_tol=1e-4)


def _same_loading(table, history: tuple) -> bool:
    """Whether a sweep table was run under the loading ``history`` (:func:`map_history`; a table without a
    'history' column is the rocking's, the shipped map's), the normal force's amplitude and phase included."""
    if table is None or len(table) == 0:
        return True
    name, A, phase, _ = history
    columns = getattr(table, "columns", ())
    own = str(table["history"].iloc[0]) if "history" in columns else "rocking"
    if own == "normal" and "amplitude" in columns and float(table["amplitude"].iloc[0]) == 0.0:
        own = "rocking"
    if own != name:
        return False
    if name != "normal":
        return True
    return (math.isclose(float(table["amplitude"].iloc[0]), A, abs_tol=1e-9)
            and math.isclose(float(table["phase"].iloc[0]), phase, abs_tol=1e-9))


def body_limit(result) -> tuple:
    """The exact limit of the run's body when it is neither the cylinder nor an ellipsoid (their closed forms are
    drawn already), as ``(ft_lim(w), w)`` (:func:`app.bodies.limit_curve`)."""
    from . import bodies

    body = None if result is None else getattr(result, "body_spec", None) or getattr(result, "body", None)
    if body is None or isinstance(body, (str, core.Cylinder)) or bodies.is_ellipsoid(body):
        return _EMPTY
    return bodies.limit_curve(body)
