"""Elastic operators of the tangential problem: traction field in, displacement field out.

One interface for every kernel and every way of applying it (the same
protocol is kept by the 3D half-space operators):

* ``shape``, ``size``: the traction field the operator acts on;
* ``apply(q)``: the displacements ``u = K q``;
* ``matrix()``: the dense matrix (refused above :data:`MAX_DENSE_SIZE`);
* ``precondition(r)``: an approximate inverse, the inverse of the kernel's
  continuous symbol applied by FFT.

The 1D kernels of :mod:`core.elastic.kernels` (plane strain; the strip of length
``L``, the truncated 3D model of the paper, eq 31) are symmetric Toeplitz, so
two forms exist: :class:`DenseOperator` multiplies by the matrix (O(n^2)) and
:class:`FFTOperator` embeds the Toeplitz matrix in a zero-padded circulant of
size ``N >= 2 n`` and multiplies by real FFTs (O(n log n)); the two agree to
round-off.

The preconditioner is the inverse of the CONTINUOUS symbol
(:func:`core.elastic.kernels.kernel_symbol`, ``pi |k| / 4`` for the plane-strain log
kernel) sampled at the wavenumbers ``2 pi j / (N dx)`` of the padded grid,
with the singular ``k = 0`` replaced by the first non-zero wavenumber, so that
it is symmetric positive definite. Inverting the padded DISCRETE symbol
instead can diverge for the 2D log kernel: the discrete symbol of the
truncated kernel is not positive at the lowest wavenumbers.

Units as in :mod:`core.elastic.kernels`: lengths in ``a``, tractions in ``mu p0``,
displacements in ``mu P / E*``.

References
----------
.. [1] R. M. Gray, "Toeplitz and circulant matrices: a review", Found. Trends
   Commun. Inf. Theory 2 (2006) 155 (circulant embedding).
.. [2] E. A. H. Vollebregt, "A new solver for the elastoplastic normal contact
   problem using conjugate gradients, deflation, and an FFT-based
   preconditioner", J. Comput. Phys. 257 (2014) 333.
.. [3] R. Wetter, Physical Mesomechanics 18 (2015), eq 31 (the strip model).
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft
from scipy.linalg import toeplitz

from ..base._validate import check_int, check_scalar
from .kernels import KERNELS, kernel_column, kernel_symbol

__all__ = ["DenseOperator", "FFTOperator", "elastic_operator", "FORMS", "MAX_DENSE_SIZE"]

#: Largest operator whose dense matrix :meth:`matrix` builds (8 n^2 bytes: 800 MB at the cap).
MAX_DENSE_SIZE = 10_000
#: Forms of an operator.
FORMS = ("dense", "fft")


def circulant_product(v, spectrum, N):
    """First ``v.size`` entries of the circulant product of ``v`` (zero-padded to ``N``) with a real ``spectrum``."""
    return sfft.irfft(sfft.rfft(v, N) * spectrum, N)[: v.size]


def fft_size(m: int) -> int:
    """Padded circulant size for a window of ``m`` elements: a fast real-FFT length >= 2 m."""
    return sfft.next_fast_len(2 * max(int(m), 1), real=True)


class _ToeplitzOperator:
    """Symmetric Toeplitz operator of ``n`` uniform elements (the shared part of both forms).

    Parameters
    ----------
    n : int
        Number of elements, >= 1.
    dx : float
        Element width [a], > 0.
    kernel : {"plane", "strip"}
        Which kernel of :mod:`core.elastic.kernels`.
    **options
        Passed to the kernel (``reference_length``; ``L_over_a``, ``b_coefficient``).
    """

    def __init__(self, n, dx, kernel="plane", **options):
        n = check_int("n", n, 1, 10**7)
        dx = check_scalar("dx", dx, 0.0, None, lo_closed=False)
        if kernel not in KERNELS:
            raise ValueError(f"kernel must be one of {sorted(KERNELS)}, got {kernel!r:.60}")
        self.n, self.dx, self.kernel, self.options = n, dx, kernel, dict(options)
        self.shape = (n,)
        self.size = n
        self.column = kernel_column(n, dx, kernel, **options)
        self.column.setflags(write=False)
        self._spectra = {}
        self._precond = {}

    # --- the circulant embedding, shared by the FFT products and the preconditioner
    def spectrum(self, N: int) -> np.ndarray:
        """Real FFT (length ``N // 2 + 1``) of the symmetric circulant of size ``N`` that embeds the kernel.

        Its first ``m`` rows and columns are the Toeplitz matrix of ``m`` elements
        for any ``m <= N // 2``: products of a field supported on ``m`` contiguous
        elements are exact on those elements (no wrap-around).
        """
        s = self._spectra.get(N)
        if s is None:
            half = N // 2
            col = self.column[: half + 1] if self.n > half else kernel_column(half + 1, self.dx, self.kernel,
                                                                               **self.options)
            e = np.empty(N)
            e[: half + 1] = col
            e[half + 1:] = col[1:N - half][::-1]  # e[N - j] = column[j]
            s = sfft.rfft(e).real.copy()  # real: e is symmetric (e[j] = e[N - j])
            self._spectra[N] = s
        return s

    def inverse_symbol(self, N: int) -> np.ndarray:
        """``1 / symbol(k_j)`` at ``k_j = 2 pi j / (N dx)``, ``j = 0 .. N // 2``, with ``k_0`` set to ``k_1``."""
        s = self._precond.get(N)
        if s is None:
            k = 2.0 * np.pi * np.arange(N // 2 + 1) / (N * self.dx)
            k[0] = k[1] if k.size > 1 else 2.0 * np.pi / (N * self.dx)
            s = 1.0 / kernel_symbol(k, self.kernel, **self.options)
            self._precond[N] = s
        return s

    def _check(self, q):
        q = np.asarray(q, dtype=float)
        if q.shape != self.shape:
            raise ValueError(f"q must have shape {self.shape}, got {q.shape}")
        return q

    def matrix(self) -> np.ndarray:
        """Dense ``(n, n)`` matrix [mu P/E* per mu p0]; ValueError above :data:`MAX_DENSE_SIZE` elements."""
        if self.n > MAX_DENSE_SIZE:
            raise ValueError(f"n = {self.n} elements is above MAX_DENSE_SIZE = {MAX_DENSE_SIZE} for a dense matrix")
        return np.ascontiguousarray(toeplitz(self.column))

    def precondition(self, r) -> np.ndarray:
        """Approximate inverse ``M r``: the inverse continuous symbol, applied on the zero-padded grid by FFT.

        Symmetric positive definite, so that it can precondition conjugate
        gradients on any subset of the elements.
        """
        r = self._check(r)
        N = fft_size(self.n)
        return circulant_product(r, self.inverse_symbol(N), N)


class DenseOperator(_ToeplitzOperator):
    """The operator as a dense matrix: ``apply`` is a matrix product, O(n^2)."""

    form = "dense"

    def __init__(self, n, dx, kernel="plane", **options):
        super().__init__(n, dx, kernel, **options)
        self._K = super().matrix()

    def matrix(self) -> np.ndarray:
        """The dense ``(n, n)`` matrix, built once (shared: do not modify it)."""
        return self._K

    def apply(self, q) -> np.ndarray:
        """Displacements ``u = K q`` [mu P/E*] of tractions ``q`` [mu p0]."""
        return self._K @ self._check(q)


class FFTOperator(_ToeplitzOperator):
    """The operator by FFT: the Toeplitz matrix embedded in a zero-padded circulant, O(n log n)."""

    form = "fft"

    def apply(self, q) -> np.ndarray:
        """Displacements ``u = K q`` [mu P/E*] of tractions ``q`` [mu p0]."""
        q = self._check(q)
        N = fft_size(self.n)
        return circulant_product(q, self.spectrum(N), N)


def elastic_operator(n, dx, kernel="plane", form="fft", **options):
    """The elastic operator of ``n`` uniform elements of width ``dx``.

    Parameters
    ----------
    n, dx, kernel, **options :
        As in :class:`DenseOperator` and :class:`FFTOperator`.
    form : {"dense", "fft"}
        Dense matrix products or FFT products.

    Returns
    -------
    DenseOperator or FFTOperator

    Examples
    --------
    >>> import numpy as np
    >>> from core.elastic.operators import elastic_operator
    >>> q = np.random.default_rng(0).normal(size=50)
    >>> d, f = (elastic_operator(50, 0.05, form=f) for f in ("dense", "fft"))
    >>> bool(np.allclose(d.apply(q), f.apply(q), rtol=0, atol=1e-13))
    True
    """
    if form not in FORMS:
        raise ValueError(f"form must be one of {FORMS}, got {form!r:.60}")
    return (DenseOperator if form == "dense" else FFTOperator)(n, dx, kernel, **options)
