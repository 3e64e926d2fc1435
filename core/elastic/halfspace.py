"""The tangential elastic operator of a half-space on a uniform 2D grid (Boussinesq-Cerruti).

A point force ``Qx`` at the origin of the surface of an elastic half-space
(shear modulus ``G``, Poisson ratio ``nu``) displaces the surface by (Cerruti,
Johnson eq 2.19 at ``z = 0``)

``u_x = Qx/(2 pi G) [(1 - nu)/rho + nu x^2/rho^3]``,  ``u_y = Qx/(2 pi G) nu x y/rho^3``,

and symmetrically for ``Qy``. With ``E* = E/(1 - nu^2)`` this is
``u = Q/(pi E*) [1/rho + nu/(1 - nu) x_i x_j/rho^3]``. Tractions are
piecewise constant on square elements of side ``h``; displacements are
collocated at element centres. The element integrals of ``1/rho``,
``x^2/rho^3``, ``y^2/rho^3`` and ``x y/rho^3`` over a rectangle have closed
forms (their primitives with ``d^2 F/dx dy`` equal to the kernel are
``x asinh(y/|x|) + y asinh(x/|y|)``, ``y asinh(x/|y|)``, ``x asinh(y/|x|)``
and ``-rho``), so the coefficients are exact for piecewise-constant tractions.

The operator is a 2D convolution (it depends on index offsets only), applied
by FFT with zero padding (circulant embedding), O(N log N); :meth:`matrix`
gives the dense form for small grids, equal to round-off. The kernels are even
(xx, yy) or odd (xy) in both offsets, so their spectra are real. The
convolution is compiled (:func:`convolve`, numpy.fft inside numba through
``rocket-fft``) so that the solvers' loops call it without Python in between.
:meth:`precondition` applies the inverse of the operator's continuous symbol,
``(1 - nu) |k| / (2 pi s) [I + nu/(1 - nu) k k^T/|k|^2]`` (the Fourier
transform of ``1/rho`` is ``2 pi/|k|`` and that of ``x_i x_j/rho^3`` is
``2 pi (delta_ij - k_i k_j/|k|^2)/|k|``).

Units: lengths in ``a`` (the contact's semi-axis along x), tractions in
``mu p0``, displacements in ``mu Fn / (E* a)``. The scale factor ``s`` of
the kernel is ``p0 a^2 / (pi Fn)`` (``3/(2 pi^2 kappa)`` for a Hertz contact
with semi-axes ``a`` and ``b = kappa a``).

References
----------
.. [1] K. L. Johnson, *Contact Mechanics*, CUP 1985, section 2.2 (eq 2.19).
.. [2] J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*,
   Kluwer 1990 (influence coefficients of rectangular elements).
"""

from __future__ import annotations

import numpy as np
import rocket_fft  # noqa: F401  (numpy.fft inside numba-compiled code)
import scipy.fft as sfft

from ..base._jit import jit
from ..base._validate import check_int, check_scalar

__all__ = ["HalfSpaceOperator", "rectangle_integrals", "convolve", "convolve_mirror", "MAX_DENSE_SIZE"]

#: Largest number of unknowns for which :meth:`HalfSpaceOperator.matrix` builds a dense matrix.
MAX_DENSE_SIZE = 6000


def _x_asinh_y_over_x(x, y):
    """``x asinh(y/|x|)`` with the limit 0 at ``x = 0``."""
    ax = np.abs(x)
    return np.where(ax > 0, x * np.arcsinh(y / np.where(ax > 0, ax, 1.0)), 0.0)


def _corner_sum(F, x, y, h, hy=None):
    """``F`` differenced over the rectangle ``[x - h/2, x + h/2] x [y - hy/2, y + hy/2]`` (``hy`` default ``h``)."""
    hy = h if hy is None else hy
    x1, x2, y1, y2 = x - 0.5 * h, x + 0.5 * h, y - 0.5 * hy, y + 0.5 * hy
    return F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1)


def rectangle_integrals(x, y, h, hy=None):
    """Integrals of the Cerruti kernels over a rectangular element ``h`` by ``hy`` centred at ``(x, y)``.

    Parameters
    ----------
    x, y : array_like
        Offset of the element's centre from the field point [length].
    h : float
        Element side along x [length], > 0.
    hy : float, optional
        Element side along y [length], > 0; default ``h`` (a square element).

    Returns
    -------
    I1, Ixx, Iyy, Ixy : ndarray
        ``integral of 1/rho``, ``x^2/rho^3``, ``y^2/rho^3`` and ``x y/rho^3``
        over the element (``rho`` the distance from the field point), exact.
    """
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    Fyy = _x_asinh_y_over_x  # primitive of y^2/rho^3: x asinh(y/|x|)

    def Fxx(u, v):  # primitive of x^2/rho^3: y asinh(x/|y|)
        return _x_asinh_y_over_x(v, u)

    def F1(u, v):
        return Fyy(u, v) + Fxx(u, v)

    def Fxy(u, v):
        return -np.hypot(u, v)

    return (_corner_sum(F1, x, y, h, hy), _corner_sum(Fxx, x, y, h, hy), _corner_sum(Fyy, x, y, h, hy),
            _corner_sum(Fxy, x, y, h, hy))


@jit
def convolve(q, hxx, hyy, hxy, py, px):
    """``u_i = K_ij * q_j`` on a zero-padded ``(py, px)`` grid from the real spectra ``hxx, hyy, hxy``.

    ``q`` has shape ``(2, ny, nx)``; the spectra shape ``(py, px // 2 + 1)``
    (:meth:`HalfSpaceOperator.spectra`); compiled, so that the solvers' inner
    loops call it without Python in between.
    """
    ny, nx = q.shape[1], q.shape[2]
    # 2D FFT in two passes, skipping the zero rows of the padding: the x-transform of the rows that hold data,
    # and on the way back the x-transform of the rows wanted only (about a quarter of the work saved)
    f = np.zeros((2, py, px // 2 + 1), np.complex128)
    f[:, :ny, :] = np.fft.rfft(q, n=px, axis=2)
    f = np.fft.fft(f, axis=1)
    g = np.empty_like(f)
    g[0] = hxx * f[0] + hxy * f[1]
    g[1] = hxy * f[0] + hyy * f[1]
    g = np.fft.ifft(g, axis=1)
    return np.ascontiguousarray(np.fft.irfft(np.ascontiguousarray(g[:, :ny, :]), n=px, axis=2)[:, :, :nx])



@jit
def convolve_mirror(q, hxx, hyy, hxy, py, px):
    """:func:`convolve` for a field mirror-symmetric in y about its centre row: half the FFT work.

    ``q`` has an odd number of rows, ``q_x`` even and ``q_y`` odd about the
    centre row ``m = ny // 2``; only the rows ``m ..`` are read (the centre
    row's ``q_y``, zero for such a field, is ignored) and the result has the
    same symmetry (``u_x`` even, ``u_y`` odd), equal to :func:`convolve` of
    the mirrored field to round-off (with the xy part of a spectrum dropped on
    the rows where the y wavenumber is its own mirror, where the spectrum of an
    odd kernel is zero anyway). The rows are laid out with the centre at
    index 0 (a translation, which a circular convolution commutes with), so
    the y-transform of ``q_x`` is even and that of ``q_y`` odd in the
    wavenumber: one complex transform of ``q_x + q_y`` carries both (split
    into even and odd parts), and the x-transforms run on the half rows only.
    The kernels' spectra are even (xx, yy) or odd (xy) in the y wavenumber,
    so ``u_x + u_y`` comes back from one inverse transform the same way.
    """
    ny, nx = q.shape[1], q.shape[2]
    m = ny // 2
    nh = m + 1
    fx = np.fft.rfft(q[:, m:, :], n=px, axis=2)
    cols = px // 2 + 1
    f = np.zeros((py, cols), np.complex128)
    f[0] = fx[0, 0]
    for k in range(1, nh):
        f[k] = fx[0, k] + fx[1, k]
        f[py - k] = fx[0, k] - fx[1, k]
    f = np.fft.fft(f, axis=0)
    v = np.empty_like(f)
    for l in range(py):
        lm = (py - l) % py
        for c in range(cols):
            a = 0.5 * (f[l, c] + f[lm, c])  # the transform of q_x (even in l)
            b = 0.5 * (f[l, c] - f[lm, c])  # the transform of q_y (odd in l)
            # an odd spectrum vanishes where l = -l (0 and the Nyquist row of an even grid); there the
            # preconditioner's symbol (sampled, not transformed) may not, so its xy part is dropped
            hc = hxy[l, c] if lm != l else 0.0
            v[l, c] = (hxx[l, c] + hc) * a + (hc + hyy[l, c]) * b
    v = np.fft.ifft(v, axis=0)
    h = np.empty((2, nh, cols), np.complex128)
    h[0, 0] = v[0]
    h[1, 0] = 0.0
    for k in range(1, nh):
        h[0, k] = 0.5 * (v[k] + v[py - k])
        h[1, k] = 0.5 * (v[k] - v[py - k])
    u = np.fft.irfft(h, n=px, axis=2)
    out = np.empty((2, ny, nx))
    for k in range(nh):
        for j in range(nx):
            out[0, m + k, j] = u[0, k, j]
            out[0, m - k, j] = u[0, k, j]
            out[1, m + k, j] = u[1, k, j]
            out[1, m - k, j] = -u[1, k, j]
    return out


class HalfSpaceOperator:
    """Tangential surface displacements of a half-space from element tractions (the 3D protocol).

    Parameters
    ----------
    ny, nx : int
        Grid rows (along y) and columns (along x), each in [1, 4096].
    h : float
        Element side [a], > 0 (along x when ``hy`` is given).
    nu : float
        Poisson ratio of the substrate, in [0, 0.5].
    scale : float
        Kernel factor ``s`` [mu Fn/(E* a) per (mu p0 a)], > 0: the displacement
        is ``s [1/rho + nu/(1 - nu) x_i x_j/rho^3]`` integrated against the
        traction.
    hy : float, optional
        Element side along y [a], > 0: rectangular elements ``h`` by ``hy``
        (a contact long along y, the cone's); default ``h`` (square elements).

    Attributes
    ----------
    shape : tuple
        ``(2, ny, nx)``: the x and y traction components on the grid.
    size : int
        ``2 ny nx`` unknowns.

    Examples
    --------
    >>> import numpy as np
    >>> from core.elastic.halfspace import HalfSpaceOperator
    >>> op = HalfSpaceOperator(5, 6, 0.2, 0.3)
    >>> q = np.random.default_rng(0).normal(size=op.shape)
    >>> bool(np.allclose(op.apply(q).ravel(), op.matrix() @ q.ravel()))
    True
    """

    def __init__(self, ny, nx, h, nu=0.5, scale=1.0 / np.pi, hy=None):
        self.ny = check_int("ny", ny, 1, 4096)
        self.nx = check_int("nx", nx, 1, 4096)
        self.h = check_scalar("h", h, 0.0, None, lo_closed=False)
        self.hy = self.h if hy is None else check_scalar("hy", hy, 0.0, None, lo_closed=False)
        self.nu = check_scalar("nu", nu, 0.0, 0.5)
        self.scale = check_scalar("scale", scale, 0.0, None, lo_closed=False)
        self.shape = (2, self.ny, self.nx)
        self.size = 2 * self.ny * self.nx
        # influence of one element on the offsets -(n-1) .. n-1 in each direction
        iy = np.arange(-(self.ny - 1), self.ny)[:, None]
        ix = np.arange(-(self.nx - 1), self.nx)[None, :]
        I1, Ixx, Iyy, Ixy = rectangle_integrals(ix * self.h, iy * self.hy, self.h, self.hy)
        c = self.nu / (1.0 - self.nu)
        self._kernels = (self.scale * (I1 + c * Ixx), self.scale * (I1 + c * Iyy), self.scale * c * Ixy)
        # zero-padded circulant embedding of the convolution
        self._pad = (sfft.next_fast_len(2 * self.ny - 1, real=True), sfft.next_fast_len(2 * self.nx - 1, real=True))
        self._hat = tuple(self._embed(k) for k in self._kernels)
        # inverse of the continuous symbol, on a periodic grid just covering the field (an approximate
        # inverse needs no padding: its kernel decays like 1/rho^3)
        self._pre_grid = (sfft.next_fast_len(self.ny, real=True), sfft.next_fast_len(self.nx, real=True))
        ky = 2 * np.pi * sfft.fftfreq(self._pre_grid[0], d=self.hy)[:, None]
        kx = 2 * np.pi * sfft.rfftfreq(self._pre_grid[1], d=self.h)[None, :]
        k2 = kx * kx + ky * ky
        k2[0, 0] = min(kx[0, 1] ** 2 if kx.size > 1 else 1.0, ky[1, 0] ** 2 if ky.size > 1 else 1.0)
        k = np.sqrt(k2)
        f = (1.0 - self.nu) * k / (2.0 * np.pi * self.scale)
        self._pre = tuple(np.ascontiguousarray(a) for a in (f * (1.0 + c * kx * kx / k2), f * (1.0 + c * ky * ky / k2),
                                                             f * c * kx * ky / k2))

    @property
    def self_influence(self) -> float:
        """Displacement of an element under its own unit traction (the diagonal of the matrix)."""
        return float(self._kernels[0][self.ny - 1, self.nx - 1])

    def _embed(self, kern):
        """FFT of the kernel placed on the padded grid with offset 0 at index 0 (wrapped)."""
        big = np.zeros(self._pad)
        ny, nx = self.ny, self.nx
        big[:ny, :nx] = kern[ny - 1:, nx - 1:]
        if ny > 1:
            big[-(ny - 1):, :nx] = kern[:ny - 1, nx - 1:]
        if nx > 1:
            big[:ny, -(nx - 1):] = kern[ny - 1:, :nx - 1]
        if ny > 1 and nx > 1:
            big[-(ny - 1):, -(nx - 1):] = kern[:ny - 1, :nx - 1]
        # the kernels are even (xx, yy) or odd (xy) in both offsets: their spectra are real
        return np.ascontiguousarray(sfft.rfft2(big).real)

    def _convolve(self, q, hats, grid):
        q = np.asarray(q, dtype=float)
        if q.shape != self.shape:
            raise ValueError(f"q must have shape {self.shape}, got {q.shape}")
        return convolve(np.require(q, np.float64, ["C", "W"]), *hats, *grid)  # one compiled specialisation

    def spectra(self):
        """``(hxx, hyy, hxy, py, px, pxx, pyy, pxy, qy, qx)``: the real spectra and padded grids of
        :meth:`apply` and :meth:`precondition`, the arguments of :func:`convolve`."""
        return (*self._hat, *self._pad, *self._pre, *self._pre_grid)

    def apply(self, q):
        """Displacements ``(u_x, u_y)`` at the element centres [mu Fn/(E* a)] from tractions ``q`` of shape :attr:`shape`."""
        return self._convolve(q, self._hat, self._pad)

    def precondition(self, r):
        """Approximate inverse of :meth:`apply`: the inverse continuous symbol, by FFT (SPD)."""
        return self._convolve(r, self._pre, self._pre_grid)

    def matrix(self):
        """Dense ``(size, size)`` matrix of :meth:`apply` (x components first, row-major grid).

        Raises
        ------
        ValueError
            Above :data:`MAX_DENSE_SIZE` unknowns.
        """
        if self.size > MAX_DENSE_SIZE:
            raise ValueError(f"the dense matrix needs size <= {MAX_DENSE_SIZE}, got {self.size}: use apply()")
        ny, nx = self.ny, self.nx
        iy, ix = np.divmod(np.arange(ny * nx), nx)
        dy = iy[:, None] - iy[None, :] + ny - 1
        dx = ix[:, None] - ix[None, :] + nx - 1
        kxx, kyy, kxy = (k[dy, dx] for k in self._kernels)
        return np.block([[kxx, kxy], [kxy, kyy]])
