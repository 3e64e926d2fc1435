"""Bodies from a designed or measured surface: a sampled line profile (1D engine) and a height map (its limit).

:class:`HeightProfile` is a line-contact :class:`core.bodies.Body` whose gap
is a sampled profile (an array, or a line scan read with SurfaceTopography,
the field's reader of profilometer files): it runs on the 1D engine with the
numerical normal solve (:mod:`core.normal`), translating like the cylinder,
and its limit is Melan's (:mod:`core.melan`).

:class:`HeightMap` is a rigid surface sampled on a square grid, pressed onto
the half-space (the patch normal solve, :func:`core.normal.solve_patch`) and
rocked along x like the sphere: its exact shakedown limit is Melan's,
``ft_lim = integral p_min / integral p`` with ``p_min`` the sliding minimum of
the translating pressure along x. (The 3D transient solver, :mod:`core.solver3d`,
takes Hertz's pressure only: a height map does not run there yet.)

Units: as the bodies they stand beside. A profile's heights are in ``P/E*``
and its positions in ``a`` (Hertz's cylinder is ``(2/pi) x^2``); a map's
heights in ``P/(E* a)``, positions in ``a`` and the nominal load ``2 pi / 3``
(``p0 a^2``; Hertz's sphere is ``(3/8) r^2``). :meth:`HeightProfile.from_topography`
converts a measured scan with the length and height units the caller gives.
"""

from __future__ import annotations

import hashlib
import math

import numpy as np
from scipy.ndimage import minimum_filter1d

from ._validate import check_scalar
from .bodies import Body

__all__ = ["HeightProfile", "HeightMap"]


def _digest(a):
    return hashlib.sha1(np.ascontiguousarray(a).tobytes()).hexdigest()[:12]


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
    >>> from core.heightmap import HeightProfile
    >>> x = np.linspace(-2, 2, 801)
    >>> body = HeightProfile((2 / np.pi) * x**2, 0.005)
    >>> abs(float(core.ft_limit(0.3, body=body)) - float(core.ft_limit(0.3))) < 1e-4
    True
    """

    name = "heightmap"

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
        length_unit = check_scalar("length_unit", length_unit, 0.0, None, lo_closed=False)
        height_unit = check_scalar("height_unit", height_unit, 0.0, None, lo_closed=False)
        if isinstance(topography, (str, bytes)) or hasattr(topography, "__fspath__"):
            from SurfaceTopography import read_topography
            topography = read_topography(topography)
        if getattr(topography, "dim", None) != 1:
            raise ValueError("topography must be a 1D line scan")
        pixel = float(topography.pixel_size[0])
        return cls(-np.asarray(topography.heights(), dtype=float) / height_unit, pixel / length_unit, centre)

    @property
    def parameters(self) -> dict:
        return {"samples": int(self.heights.size), "spacing": self.spacing, "data": _digest(self.heights)}

    def profile(self, x):
        """The sampled gap, linear between samples (the end values beyond them) [P/E*]."""
        return np.interp(np.asarray(x, dtype=float), self.xs, self.heights)


class HeightMap:
    """A rigid surface sampled on a square grid, rocked along x: its normal solution and its shakedown limit.

    Parameters
    ----------
    heights : array_like, shape (ny, nx)
        The gap [P/(E* a)] (rows along y), finite, at least 5 x 5.
    spacing : float
        Grid step [a], > 0.

    Examples
    --------
    >>> import numpy as np
    >>> from core.heightmap import HeightMap
    >>> x = (np.arange(64) + 0.5) * 0.05 - 1.6
    >>> X, Y = np.meshgrid(x, x)
    >>> m = HeightMap(0.375 * (X**2 + Y**2), 0.05)
    >>> abs(m.ft_limit(0.3) - (1 - 1.5 * 0.3 + 0.5 * 0.3**3)) < 0.02  # the sphere's closed form
    True
    """

    name = "heightmap2d"
    dim = 2
    #: Nominal load [p0 a^2] and kernel factor of the sphere's units (:mod:`core.point_contact`).
    load = 2.0 * math.pi / 3.0
    kernel_scale = 1.5 / math.pi**2

    def __init__(self, heights, spacing):
        h = np.array(heights, dtype=float)
        if h.ndim != 2 or min(h.shape) < 5 or not np.all(np.isfinite(h)):
            raise ValueError(f"heights must be a finite 2-D array of at least 5 x 5, got shape {h.shape}")
        self.heights = h - h.min()
        self.heights.setflags(write=False)
        self.spacing = check_scalar("spacing", spacing, 0.0, None, lo_closed=False)
        self._solution = None

    @classmethod
    def from_topography(cls, topography, length_unit, height_unit):
        """A map from a SurfaceTopography 2D topography (object or file); units as in
        :meth:`HeightProfile.from_topography` (the gap is ``-height / height_unit``)."""
        length_unit = check_scalar("length_unit", length_unit, 0.0, None, lo_closed=False)
        height_unit = check_scalar("height_unit", height_unit, 0.0, None, lo_closed=False)
        if isinstance(topography, (str, bytes)) or hasattr(topography, "__fspath__"):
            from SurfaceTopography import read_topography
            topography = read_topography(topography)
        if getattr(topography, "dim", None) != 2:
            raise ValueError("topography must be a 2D topography")
        px, py = (float(v) for v in topography.pixel_size)
        if not math.isclose(px, py, rel_tol=1e-9):
            raise ValueError(f"the topography's pixels must be square, got {px:g} x {py:g}")
        # SurfaceTopography's arrays are indexed (x, y): rows along y here
        return cls(-np.asarray(topography.heights(), dtype=float).T / height_unit, px / length_unit)

    @property
    def parameters(self) -> dict:
        return {"shape": self.heights.shape, "spacing": self.spacing, "data": _digest(self.heights)}

    def solve(self):
        """The normal solution at the nominal load (:func:`core.normal.solve_patch`, solved once).

        Raises
        ------
        ValueError
            If the contact reaches the edge of the map.
        """
        if self._solution is None:
            from .normal import solve_patch
            sol = solve_patch(self.heights, self.spacing, load=self.load, scale=self.kernel_scale)
            c = sol.contact
            if c[0].any() or c[-1].any() or c[:, 0].any() or c[:, -1].any():
                raise ValueError("the contact reaches the edge of the height map: sample a larger area")
            self._solution = sol
        return self._solution

    def ft_limit(self, w):
        """Melan's limit when the map translates along x over ``[-w, w]`` [a]: ``integral p_min / integral p``.

        ``w`` is rounded to whole grid steps (at least one step in [0, 1)).
        """
        w = check_scalar("w", w, 0.0, 1.0, hi_closed=False)
        p = self.solve().pressure
        k = int(round(w / self.spacing))
        pad = np.pad(p, ((0, 0), (k, k)))
        p_min = minimum_filter1d(pad, 2 * k + 1, axis=1, mode="constant", cval=0.0) if k else pad
        return float(p_min.sum() / p.sum())
