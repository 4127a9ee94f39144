r"""The fast tier's first stage for one problem (float64, compiled by numba): the squared
lengths, the octic kernel (``distkin/_generated/octic_general.py``), the triangle bounds
of :math:`s_{15}` and the octic's companion matrix with its eigenvalues (LAPACK).
Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, eq. (3);
the later stages are in :mod:`.single` (one problem) and :mod:`.batched`.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._generated.octic_general import octic_rows as _octic_rows, octic_scalar
from .problem import sides_into

__all__ = ["octic_array", "octic_rows", "bounds", "companion", "eigenvalues"]

_jit = numba.njit(cache=True)
_kernel = _jit(octic_scalar)
_rows = _jit(_octic_rows)

try:  # numpy's own gufunc behind numpy.linalg.eigvals, without its per-call checks
    from numpy.linalg import _umath_linalg

    def _eigvals(a):
        return _umath_linalg.eigvals(a, signature="d->D")

    if not np.allclose(np.sort_complex(_eigvals(np.diag([2.0, 1.0]))), [1.0, 2.0]):
        raise ImportError
except Exception:  # pragma: no cover - other numpy layouts: the public function
    _eigvals = np.linalg.eigvals


@_jit
def _squares(B, Q, L):
    """Squared sides s12 s13 s23 s45 s46 s56 (:func:`.problem.sides_into`: the batched
    tier's numbers) and squared legs of one problem."""
    s2 = np.empty(6)
    sides_into(B, Q, s2)
    return s2, L * L


@_jit
def octic_array(s2, l2):
    """The generated scalar kernel, compiled: (39,) outputs at the squared sides and
    legs (quadratic parts of eq. (3), then the octic, highest degree first)."""
    lst = _kernel(s2, l2)
    d = np.empty(39)
    for i in range(39):
        d[i] = lst[i]
    return d


@_jit
def octic_rows(s2, l2):
    """:func:`octic_array` for N problems (s2, l2: (N, 6)): (N, 39), the same numbers as
    the batched numpy kernel (the same generated expressions, in float64 operations;
    tests/octahedral compare them), without its (N,) temporaries: the generated loop
    ``octic_rows`` (the scalar kernel's code writing each row of the array instead of
    building a list of 39 per problem, which cost ~0.17 µs of ~0.28, issue 17)."""
    out = np.empty((s2.shape[0], 39))
    _rows(s2, l2, out)
    return out


@_jit
def bounds(s2, l2):
    """The triangle bounds (lo, hi) of s15: the triangles P1 P4 P5, P1 P2 P5, P1 P6 P5
    and P1 P3 P5 must close."""
    lo, hi = -np.inf, np.inf
    for a, b in ((l2[0], s2[3]), (s2[0], l2[2]), (l2[5], s2[5]), (s2[1], l2[3])):
        ra, rb = math.sqrt(a), math.sqrt(b)
        lo = max(lo, (ra - rb) ** 2)
        hi = min(hi, (ra + rb) ** 2)
    return lo, hi


@_jit
def _prepare(B, Q, L):
    """Squared lengths, kernel output (39), triangle bounds, scale c, and the
    companion matrix of O(c t) (``mode`` 0), or its scaled coefficients when the
    leading one is negligible (``mode`` 1: a lower degree) or all vanish (2)."""
    s2, l2 = _squares(B, Q, L)
    d = octic_array(s2, l2)
    lo, hi = bounds(s2, l2)
    c = 0.5 * (max(lo, 0.0) + hi) if hi > 0 else s2.sum() / 6
    comp, sc, mode = companion(d, c)
    return s2, l2, d, lo, hi, c, comp, sc, mode


@_jit
def companion(d, c):
    """The companion matrix (8, 8) of the octic scaled to O(c t), its scaled
    coefficients (9) and the mode of :func:`_prepare`."""
    sc = np.empty(9)
    big, p = 0.0, 1.0
    for k in range(8, -1, -1):
        v = d[30 + k] * p
        sc[k] = v
        big = max(big, abs(v))
        p *= c
    comp = np.zeros((8, 8))
    if big == 0:
        return comp, sc, 2
    if abs(sc[0]) <= 1e-12 * big:
        return comp, sc / big, 1
    for k in range(8):
        comp[0, k] = -sc[k + 1] / sc[0]
    for k in range(7):
        comp[k + 1, k] = 1.0
    return comp, sc, 0


def eigenvalues(comp, sc, mode, c):
    """Eigenvalues (complex array, unscaled) from :func:`_prepare`'s output."""
    if mode == 2:
        return np.zeros(0, complex)
    if mode == 1:
        eig = np.roots(sc) if sc.any() else np.zeros(0, complex)
    else:
        eig = _eigvals(comp) if np.isfinite(comp).all() else np.linalg.eigvals(comp)
        if np.isnan(eig).any():   # LAPACK did not converge: the public function raises
            eig = np.linalg.eigvals(comp)
    return np.asarray(eig, complex) * c
