"""Bodies from a designed or measured surface: a sampled line profile (1D engine) and a height map (its limit).

:class:`HeightProfile` is a line-contact :class:`core.geometry.bodies.Body` whose gap
is a sampled profile (an array, or a line scan read with SurfaceTopography,
the field's reader of profilometer files): it runs on the 1D engine with the
numerical normal solve (:mod:`core.pressure.normal`), translating like the cylinder,
and its limit is Melan's (:mod:`core.pressure.melan`).

:class:`HeightMap` is a rigid surface sampled on a square grid, pressed onto
the half-space (the patch normal solve, :func:`core.pressure.normal.solve_patch`) and
rocked along x like the sphere: its exact shakedown limit is Melan's,
``ft_lim = integral p_min / integral p`` with ``p_min`` the sliding minimum of
the translating pressure along x; ``core.simulate_cycles(..., body=HeightMap(...))``
runs its cycles on the 3D solver (:mod:`core.solvers.solver3d`) with its numerically
solved pressure.

Units: as the bodies they stand beside. A profile's heights are in ``P/E*``
and its positions in ``a`` (Hertz's cylinder is ``(2/pi) x^2``); a map's
heights in ``P/(E* a)``, positions in ``a`` and the nominal load ``2 pi / 3``
(``p0 a^2``; Hertz's sphere is ``(3/8) r^2``). :meth:`HeightProfile.from_topography`
converts a measured scan with the length and height units the caller gives.
"""

from __future__ import annotations

import hashlib
import math
import os

import numpy as np
from scipy.ndimage import minimum_filter1d

from ..base._validate import check_scalar
from .bodies import Body

__all__ = ["HeightProfile", "HeightMap", "read_topography", "readable_formats"]


def _digest(a):
    return hashlib.sha1(np.ascontiguousarray(a).tobytes()).hexdigest()[:12]


def readable_formats() -> list[str]:
    """The file formats a height map can be read from: SurfaceTopography's readers, as ``"name (.ext, ...)"``.

    Returns
    -------
    list of str
        One entry per reader of the installed SurfaceTopography (its own list, ``SurfaceTopography.IO.readers``).

    Examples
    --------
    >>> from core.geometry.heightmap import readable_formats
    >>> any(f.startswith("Network Common Data Format (NetCDF) (.nc") for f in readable_formats())
    True
    """
    from SurfaceTopography.IO import readers

    return [f"{r.name()} ({', '.join('.' + e for e in r.file_extensions())})" for r in readers]


def read_topography(source, name=None):
    """Read a height map's file with SurfaceTopography, or raise a ValueError a user can act on.

    Parameters
    ----------
    source : str, path-like or binary file object
        A file's path, or its bytes (``io.BytesIO``: an upload, never written to disk). The format is told
        from the contents.
    name : str, optional
        How the file is named in a message (default: the path; ``"the file"`` for a file object).

    Returns
    -------
    SurfaceTopography topography
        What the file holds (a line scan or a 2D map).

    Raises
    ------
    ValueError
        ``file not found: PATH`` for a path that does not exist (or is not a file); for a file that no reader
        understands, a message naming every readable format (:func:`readable_formats`); for a file a reader
        recognises but cannot read, the reader's reason.
    """
    from SurfaceTopography import read_topography as _read
    from SurfaceTopography.Exceptions import CannotDetectFileFormat, ReadFileError, UnknownFileFormat

    is_path = isinstance(source, (str, bytes)) or hasattr(source, "__fspath__")
    if is_path:
        path = os.fsdecode(source)
        name = path if name is None else name
        if not os.path.isfile(path):
            raise ValueError(f"file not found: {path}" if not os.path.exists(path) else f"{path} is not a file")
    name = "the file" if name is None else name
    try:
        return _read(source)
    except (CannotDetectFileFormat, UnknownFileFormat) as e:
        raise ValueError(f"{name} is in no format that can be read; the readable formats: "
                         f"{'; '.join(readable_formats())}") from e
    except (ReadFileError, OSError) as e:
        why = " ".join(str(e).split())[:300]
        raise ValueError(f"{name} cannot be read: {why or type(e).__name__}") from e


def _read_topography(topography, length_unit, height_unit, dim):
    """A SurfaceTopography topography of dimension ``dim`` (an object, or a file read with it) and the checked units."""
    length_unit = check_scalar("length_unit", length_unit, 0.0, None, lo_closed=False)
    height_unit = check_scalar("height_unit", height_unit, 0.0, None, lo_closed=False)
    if isinstance(topography, (str, bytes)) or hasattr(topography, "__fspath__"):
        topography = read_topography(topography)
    if getattr(topography, "dim", None) != dim:
        raise ValueError("topography must be a 1D line scan" if dim == 1 else "topography must be a 2D topography")
    return topography, length_unit, height_unit


class HeightProfile(Body):
    """A line body given by its sampled gap: heights ``h_k`` [P/E*] every ``spacing`` [a].

    Parameters
    ----------
    heights : array_like, shape (n,)
        The profile, n >= 5, finite. Its lowest sample is placed at ``x = 0``
        (or ``centre``) and subtracted.
    spacing : float
        Distance between samples [a], > 0.
    centre : int, optional
        Index of the sample placed at ``x = 0`` (default: the lowest).

    The contact must stay inside the samples: the numerical normal solve
    covers ``|x| < support``, the distance from the centre to the nearer end.

    Examples
    --------
    >>> import numpy as np, core
    >>> from core.geometry.heightmap import HeightProfile
    >>> x = np.linspace(-2, 2, 801)
    >>> body = HeightProfile((2 / np.pi) * x**2, 0.005)
    >>> abs(float(core.ft_limit(0.3, body=body)) - float(core.ft_limit(0.3))) < 1e-4
    True
    """

    #: Its name on a result (``body_name``); not a registry name (a profile is given as an object).
    name = "profile"

    def __init__(self, heights, spacing, centre=None):
        h = np.array(heights, dtype=float)
        if h.ndim != 1 or h.size < 5 or not np.all(np.isfinite(h)):
            raise ValueError(f"heights must be a finite 1-D array of at least 5 samples, got shape {h.shape}")
        self.spacing = check_scalar("spacing", spacing, 0.0, None, lo_closed=False)
        k = int(np.argmin(h)) if centre is None else int(centre)
        if not 0 <= k < h.size:
            raise ValueError(f"centre must be an index in [0, {h.size - 1}], got {centre!r}")
        self.heights = h - h[k]
        self.heights.setflags(write=False)
        self.centre = k
        self.xs = (np.arange(h.size) - k) * self.spacing
        self.support = float(min(-self.xs[0], self.xs[-1]))
        if self.support <= 0:
            raise ValueError("the centre must not be an end of the profile")

    @classmethod
    def from_topography(cls, topography, length_unit, height_unit, centre=None):
        """A profile from a SurfaceTopography line scan (an object, or a file it reads).

        Parameters
        ----------
        topography : SurfaceTopography line scan or path
            A uniform 1D topography (``read_topography(path)`` for a file).
        length_unit : float
            The length ``a`` in the scan's length unit (its positions are divided by it), > 0.
        height_unit : float
            ``P/E*`` in the scan's height unit; the body is the rigid surface, so
            the gap is ``-height / height_unit`` (a bump of the scan touches first), > 0.
        """
        topography, length_unit, height_unit = _read_topography(topography, length_unit, height_unit, 1)
        pixel = float(topography.pixel_size[0])
        return cls(-np.asarray(topography.heights(), dtype=float) / height_unit, pixel / length_unit, centre)

    @property
    def parameters(self) -> dict:
        return {"samples": int(self.heights.size), "spacing": self.spacing, "data": _digest(self.heights)}

    def profile(self, x):
        """The sampled gap, linear between samples (the end values beyond them) [P/E*]."""
        return np.interp(np.asarray(x, dtype=float), self.xs, self.heights)


class HeightMap:
    """A rigid surface sampled on a square grid, rocked along x like the sphere: its normal solution, its
    shakedown limit, and its cycles on the 3D solver.

    ``core.simulate_cycles(ft, w, periods, body=HeightMap(...))`` runs it on
    :func:`core.api.point_runs.solve_point_schedule` on the map's own grid (``dx`` =
    ``spacing``): the element ``(i, j)`` sits at ``x = (j - nx // 2) spacing``,
    ``y = (i - ny // 2) spacing`` when the body is centred, and the body
    translates by ``xc`` along x. Its pressure is solved once
    (:meth:`solve`) and shifted by whole elements when ``xc`` is a multiple
    of ``spacing`` (the discrete problem is translation-invariant); otherwise
    the heights are interpolated linearly along x to the fractional offset and
    the normal problem is solved again (once per offset, cached).

    Parameters
    ----------
    heights : array_like, shape (ny, nx)
        The gap [P/(E* a)] (rows along y), finite, at least 5 x 5.
    spacing : float
        Grid step [a], > 0.

    Examples
    --------
    >>> import numpy as np
    >>> from core.geometry.heightmap import HeightMap
    >>> x = (np.arange(64) + 0.5) * 0.05 - 1.6
    >>> X, Y = np.meshgrid(x, x)
    >>> m = HeightMap(0.375 * (X**2 + Y**2), 0.05)
    >>> abs(m.ft_limit(0.3) - (1 - 1.5 * 0.3 + 0.5 * 0.3**3)) < 0.02  # the sphere's closed form
    True
    """

    #: Its registry and CLI name (``core.geometry.registry``, ``--body heightmap``), and its name on a result.
    name = "heightmap"
    dim = 2
    #: Nominal load [p0 a^2] and kernel factor of the sphere's units (:mod:`core.theory.point_contact`).
    load = 2.0 * math.pi / 3.0
    total_load = load
    kernel_scale = 1.5 / math.pi**2
    #: No semi-axis ratio (a point body's summary field).
    ratio = None

    def __init__(self, heights, spacing):
        h = np.array(heights, dtype=float)
        if h.ndim != 2 or min(h.shape) < 5 or not np.all(np.isfinite(h)):
            raise ValueError(f"heights must be a finite 2-D array of at least 5 x 5, got shape {h.shape}")
        self.heights = h - h.min()
        self.heights.setflags(write=False)
        self.spacing = check_scalar("spacing", spacing, 0.0, None, lo_closed=False)
        self._solution = None
        self._shifted = {}

    @classmethod
    def from_topography(cls, topography, length_unit, height_unit):
        """A map from a SurfaceTopography 2D topography (object or file); units as in
        :meth:`HeightProfile.from_topography` (the gap is ``-height / height_unit``)."""
        topography, length_unit, height_unit = _read_topography(topography, length_unit, height_unit, 2)
        px, py = (float(v) for v in topography.pixel_size)
        if not math.isclose(px, py, rel_tol=1e-9):
            raise ValueError(f"the topography's pixels must be square, got {px:g} x {py:g}")
        # SurfaceTopography's arrays are indexed (x, y): rows along y here
        return cls(-np.asarray(topography.heights(), dtype=float).T / height_unit, px / length_unit)

    def __repr__(self):
        ny, nx = self.heights.shape
        return f"HeightMap({ny}x{nx}, spacing={self.spacing:g}, data={_digest(self.heights)})"

    @property
    def default_dx(self) -> float:
        """A run's element side [a]: the map's spacing (it runs on its own grid, :func:`core.geometry.resolution.default_dx`)."""
        return self.spacing

    @property
    def parameters(self) -> dict:
        return {"shape": self.heights.shape, "spacing": self.spacing, "data": _digest(self.heights)}

    def solve(self):
        """The normal solution at the nominal load (:func:`core.pressure.normal.solve_patch`, solved once).

        Raises
        ------
        ValueError
            If the contact reaches the edge of the map.
        """
        if self._solution is None:
            from ..pressure.normal import solve_patch
            sol = solve_patch(self.heights, self.spacing, load=self.load, scale=self.kernel_scale)
            c = sol.contact
            if c[0].any() or c[-1].any() or c[:, 0].any() or c[:, -1].any():
                raise ValueError("the contact reaches the edge of the height map: sample a larger area")
            self._solution = sol
        return self._solution

    def _pressure_at(self, frac, scale):
        """Element pressures [p0] on the map's grid of the body displaced by ``frac`` elements along x (|frac| <= 1/2)
        under the load ``load * scale^3``: :meth:`solve` shifted, or solved again for a fractional offset."""
        if frac == 0.0 and scale == 1.0:
            return self.solve().pressure
        key = (round(frac, 9), round(scale, 12))
        p = self._shifted.get(key)
        if p is None:
            from ..pressure.normal import solve_patch
            H = np.asarray(self.heights)
            if frac > 0:  # the height at x - frac h: between the element and its left neighbour
                H = (1.0 - frac) * H + frac * np.concatenate([H[:, :1], H[:, :-1]], axis=1)
            elif frac < 0:
                H = (1.0 + frac) * H - frac * np.concatenate([H[:, 1:], H[:, -1:]], axis=1)
            sol = solve_patch(H, self.spacing, load=self.load * scale**3, scale=self.kernel_scale,
                              initial=self.solve().pressure)
            c = sol.contact
            if c[0].any() or c[-1].any() or c[:, 0].any() or c[:, -1].any():
                raise ValueError("the contact reaches the edge of the height map: sample a larger area")
            if len(self._shifted) >= 64:
                self._shifted.clear()
            p = self._shifted[key] = sol.pressure
        return p

    def run_grid(self, reach_x, scale, h):
        """The edges ``(x_edges, y_edges)`` [a] of a point-contact run whose centre reaches ``|xc| <= reach_x``
        and whose largest load has the length scale ``scale`` (``(P / P_nominal)^(1/3)``): the map's elements that
        carry pressure under that load, one more around them, and ``reach_x`` more along x.

        Raises
        ------
        ValueError
            If ``h`` is not the map's spacing, or the contact under the largest load reaches the map's edge.
        """
        if not math.isclose(h, self.spacing, rel_tol=1e-9):
            raise ValueError(f"dx must be the height map's spacing {self.spacing:g} for a run on it, got {h:g}")
        # the contact at the largest load of the run (a normal load above the nominal one widens it)
        contact = self.solve().contact if scale <= 1.0 + 1e-12 else self._pressure_at(0.0, scale) > 0
        rows, cols = np.nonzero(contact)
        ny, nx = self.heights.shape
        half_y = int(max(ny // 2 - rows.min(), rows.max() - ny // 2)) + 1
        half_x = int(max(nx // 2 - cols.min(), cols.max() - nx // 2)) + 1 + math.ceil(reach_x / h - 1e-9)
        return h * (np.arange(2 * half_x + 2) - half_x - 0.5), h * (np.arange(2 * half_y + 2) - half_y - 0.5)

    def grid_pressure(self, x_edges, y_edges, xc, scale=1.0):
        """Element pressures [p0] on a run grid (:meth:`run_grid`) with the body's centre at ``xc`` [a]."""
        h = self.spacing
        k = math.floor(xc / h + 0.5)
        frac = xc / h - k
        if abs(frac) < 1e-9:
            frac = 0.0
        p = self._pressure_at(frac, scale)
        ny, nx = self.heights.shape
        out = np.zeros((y_edges.size - 1, x_edges.size - 1))
        half_y, half_x = out.shape[0] // 2, out.shape[1] // 2
        rows, cols = np.nonzero(p > 0)
        r = rows - ny // 2 + half_y
        c = cols - nx // 2 + k + half_x
        if r.min() < 0 or c.min() < 0 or r.max() >= out.shape[0] or c.max() >= out.shape[1]:
            raise ValueError(f"the contact at xc = {xc:g} leaves the run's grid")
        out[r, c] = p[rows, cols]
        return out

    def ft_limit(self, w):
        """Melan's limit when the map translates along x over ``[-w, w]`` [a]: ``integral p_min / integral p``.

        ``p_min`` is the lowest pressure over the positions ``j spacing``
        (``|j spacing| <= w``, the pressure shifted by whole elements) and the
        turning points ``+-w`` (for a ``w`` between whole elements, the map's
        heights interpolated to the fractional offset and solved again, as in a
        run). It is continuous in ``w``; a run at ``dW = spacing`` and ``w`` a
        multiple of it sees exactly these positions.
        """
        w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
        p = self.solve().pressure
        h = self.spacing
        k = math.floor(w / h + 1e-9)
        frac = w / h - k
        pad = np.pad(p, ((0, 0), (k + 1, k + 1)))
        p_min = minimum_filter1d(pad, 2 * k + 1, axis=1, mode="constant", cval=0.0) if k else pad.copy()
        if frac > 1e-9:
            nx = p.shape[1]
            for sign in (1, -1):  # the turning points: the body displaced by +-(k + frac) elements
                q = np.zeros_like(pad)
                q[:, k + 1 + sign * k:k + 1 + sign * k + nx] = self._pressure_at(sign * frac, 1.0)
                p_min = np.minimum(p_min, q)
        return float(p_min.sum() / p.sum())
