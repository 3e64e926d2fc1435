"""The coupled plane-strain operator of two dissimilar bodies: pressure and traction in, both displacements out.

With Dundurs' ``beta != 0`` (:mod:`core.theory.materials`, body 1 the rocking body)
the relative surface displacements of a line contact under the pressure
``p`` and the tangential traction ``q`` (on the substrate, along x) are, from
the half-space's surface displacements (Johnson, Contact Mechanics, eq 2.25)
summed over the two bodies:

    h(x) = -(2/(pi E*)) integral p(s) ln|x - s| ds + (beta/E*) S[q](x)
    g(x) = -(2/(pi E*)) integral q(s) ln|x - s| ds - (beta/E*) S[p](x)

``h`` the normal separation the elasticity adds, ``g`` the substrate's
tangential displacement relative to the body's, and
``S[f](x) = integral f(s) sign(x - s) ds`` (the log-free kernel: its
derivative is ``2 f(x)``, the local term of the Hilbert-transform form). A
rigid body on a compressible substrate (``beta > 0``) draws the substrate's
surface inwards under pressure, and a traction along +x lowers the substrate
ahead of it. The operator is symmetric in the work-conjugate pairs
(``S^T = -S``), as Betti's theorem requires.

In the units of :mod:`core.elastic.kernels` and :mod:`core.pressure.normal` (lengths in ``a``;
pressure in ``p0`` and normal displacements in ``P/E*``; tractions in ``mu
p0`` and tangential displacements in ``mu P/E*``) the element form on a
uniform grid is

    h = K p + (2 beta mu / pi) S q,      g = K q - (2 beta / (pi mu)) S p,

``K`` the plane-strain log kernel of both problems (:func:`core.elastic.kernels.plane_strain_influence`)
and ``S_ij = dx sign(i - j)`` (the sign kernel integrated over element ``j``
at the centre of element ``i``: zero on the diagonal). ``S`` applies in
``O(n)`` by prefix sums, so both operator forms (dense and FFT,
:mod:`core.elastic.operators`) share it. The coupling enters the tangential problem
as ``beta / mu`` and the normal one as ``beta mu``.

References
----------
.. [1] K. L. Johnson, *Contact Mechanics*, CUP 1985, eqs 2.25 and 5.4.
.. [2] D. A. Hills, D. Nowell, A. Sackfield, *Mechanics of Elastic Contacts*,
   Butterworth-Heinemann 1993 (the coupled integral equations).
"""

from __future__ import annotations

import math

import numpy as np

from ..base._validate import check_int, check_scalar
from ..theory.materials import check_beta
from .operators import elastic_operator

__all__ = ["sign_influence", "cross_matrix", "cross_apply", "CoupledOperator", "coupling_factors"]


def sign_influence(offsets, dx):
    """``integral over |s - d| < dx/2 of sign(s) ds`` [a]: the sign kernel of one element of width ``dx`` at the
    offsets ``d`` (collocation point minus element centre [a]); ``dx sign(d)`` outside the element, ``2 d`` inside.

    Examples
    --------
    >>> sign_influence([-0.2, 0.0, 0.05, 0.3], 0.2).round(3)
    array([-0.2,  0. ,  0.1,  0.2])
    """
    dx = check_scalar("dx", dx, 0.0, None, lo_closed=False)
    d = np.asarray(offsets, dtype=float)
    return np.clip(2.0 * d, -dx, dx)


def cross_matrix(n, dx) -> np.ndarray:
    """The dense ``(n, n)`` matrix ``S_ij = dx sign(i - j)`` of the sign kernel on ``n`` uniform elements."""
    n = check_int("n", n, 1, 10**5)
    dx = check_scalar("dx", dx, 0.0, None, lo_closed=False)
    i = np.arange(n)
    return sign_influence(dx * (i[:, None] - i[None, :]), dx)


def cross_apply(v, dx) -> np.ndarray:
    """``S v`` in ``O(n)``: ``dx (sum_{j < i} v_j - sum_{j > i} v_j)`` along the last axis."""
    v = np.asarray(v, dtype=float)
    c = np.cumsum(v, axis=-1)
    below = c - v
    above = c[..., -1:] - c
    return dx * (below - above)


def coupling_factors(beta, mu):
    """``(2 beta mu / pi, 2 beta / (pi mu))``: the factors of ``S`` in the normal and in the tangential displacement.

    Raises
    ------
    ValueError
        ``|beta| >= 0.5`` or ``mu <= 0`` (naming it).
    """
    beta = check_beta(beta)
    mu = check_scalar("mu", mu, 0.0, 10.0, lo_closed=False)
    return 2.0 * beta * mu / math.pi, 2.0 * beta / (math.pi * mu)


class CoupledOperator:
    """The coupled operator of a line of ``n`` uniform elements: ``(p, q) -> (h, g)`` (module docstring).

    Parameters
    ----------
    n : int
        Elements, >= 1.
    dx : float
        Element width [a], > 0.
    beta : float
        Dundurs' ``beta`` (:mod:`core.theory.materials`' sign), ``|beta| < 0.5``.
    mu : float
        Friction coefficient, in (0, 10].
    form : {"dense", "fft"}
        How ``K`` is applied (:func:`core.elastic.operators.elastic_operator`); ``S`` by prefix sums in both.

    Examples
    --------
    The dense and the FFT forms agree, and the operator is symmetric in work
    (``p.h' + q.g'`` with the tangential pair weighted by ``mu^2``):

    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> p, q = rng.normal(size=(2, 30))
    >>> d, f = (CoupledOperator(30, 0.1, 0.2, 0.4, form=s) for s in ("dense", "fft"))
    >>> bool(np.allclose(np.concatenate(d.apply(p, q)), np.concatenate(f.apply(p, q)), atol=1e-12))
    True
    >>> M = d.matrix()
    >>> W = np.diag(np.r_[np.ones(30), 0.4 ** 2 * np.ones(30)])
    >>> bool(np.allclose(W @ M, (W @ M).T, atol=1e-12))
    True
    """

    def __init__(self, n, dx, beta, mu, form="dense"):
        self.K = elastic_operator(n, dx, "plane", form=form)
        self.n, self.dx = self.K.n, self.K.dx
        self.beta, self.mu = check_beta(beta), check_scalar("mu", mu, 0.0, 10.0, lo_closed=False)
        self.normal_factor, self.tangential_factor = coupling_factors(self.beta, self.mu)
        self.form = form
        self.shape = (self.n,)

    def cross(self, v) -> np.ndarray:
        """``S v`` (the sign kernel, :func:`cross_apply`)."""
        return cross_apply(v, self.dx)

    def apply(self, p, q):
        """``(h, g)``: normal displacements [P/E*] of ``p`` [p0] and ``q`` [mu p0], tangential ones [mu P/E*]."""
        p = np.asarray(p, dtype=float)
        q = np.asarray(q, dtype=float)
        return (self.K.apply(p) + self.normal_factor * self.cross(q),
                self.K.apply(q) - self.tangential_factor * self.cross(p))

    def matrix(self) -> np.ndarray:
        """The dense ``(2n, 2n)`` matrix of :meth:`apply` on ``[p, q]``."""
        K = self.K.matrix()
        S = cross_matrix(self.n, self.dx)
        return np.block([[K, self.normal_factor * S], [-self.tangential_factor * S, K]])
