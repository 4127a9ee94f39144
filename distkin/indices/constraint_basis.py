"""Orthonormal bases of the constraint rows of a sliced zonotope (Kühne et al., eq. (14)).

The slice that keeps the output coordinates S of ``{G p : p in box}`` is
``{G_S p : p in box, G_{S^c} p = 0}``: it depends on the k removed rows ``G_{S^c}``
only through their row space.  The vertex enumerations of the farthest point
(:func:`.zonotope.zonotope_best`, :mod:`.slice_farthest`) solve k × k blocks of those
rows and skip a block whose determinant is below 1e-12 times the product of its column
norms.  On the rows as given that test depends on their scale: a torque row 1e-13 the
size of the force rows failed it for every block, so the slice came out empty (−inf),
or a vertex on a nearly singular block was lost.  On an orthonormal basis ``Q`` of
the row space the test sees only the geometry: ``|det Q_F|`` and the column norms are
the same for every orthonormal basis.

The basis is modified Gram-Schmidt with pivoting (the largest remaining row first, each
projection applied twice so that the rows are orthogonal to rounding).  A remaining
norm at or below :data:`.zonotope.RANK_TOL` times the largest row norm of the whole
generator matrix ends it: that is the rank of the constraint, and the rows past it are
treated as zero, as the worst case treats a generator matrix with σmin/σmax below the
same tolerance as exactly singular (a wrench map with no torque about z at a pose
drops that constraint instead of reporting an empty slice).  For k = 3 (the slices of
the sensitivities, 4 per pose of the study) the rows are first tried by the Cholesky
factor C of their Gram matrix, Q = C⁻¹ R: independent dot products instead of a chain
of projections, taken only when the rows are far from dependent and from zero (every
pivot² above 1e-8 of its row's norm², and above (1e-6)² of the largest squared row
norm), so that the rank is 3 without doubt and Q is orthonormal to ~1e-8.

Compiled by numba (about 0.08 µs per pose for k = 3, L = 8; numpy's batched QR takes
0.9 µs and does not pivot).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["constraint_basis"]


#: the Cholesky route (k = 3) is taken when every pivot² is above this fraction of its
#: row's norm² (rows not nearly dependent: the basis is orthonormal to ~1e-8 or better)
#: and every pivot above ``_CHOL_ABS`` times the largest row norm (far above RANK_TOL)
_CHOL_REL = 1e-8
_CHOL_ABS = 1e-6


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True)
    def run(G, Sc, tol, out, rank):                         # pragma: no cover (compiled)
        """``out`` (a copy of G; both (N, d, L), any strides) gets the basis in its rows
        Sc."""
        N, d, L = G.shape
        k = Sc.shape[0]
        R = np.empty((k, L))
        for n in range(N):
            sc = 0.0                           # the largest squared row norm of G
            for i in range(d):
                s = 0.0
                for j in range(L):
                    s += G[n, i, j] * G[n, i, j]
                sc = max(sc, s)
            for i in range(k):
                for j in range(L):
                    R[i, j] = G[n, Sc[i], j]
            chol = False
            if k == 3:
                # Q = C⁻¹ R by the Cholesky factor C of the Gram matrix (module docstring)
                lim = _CHOL_ABS * _CHOL_ABS * sc
                m00 = m10 = m11 = m20 = m21 = m22 = 0.0
                for j in range(L):
                    a0, a1, a2 = R[0, j], R[1, j], R[2, j]
                    m00 += a0 * a0
                    m10 += a1 * a0
                    m11 += a1 * a1
                    m20 += a2 * a0
                    m21 += a2 * a1
                    m22 += a2 * a2
                chol = m00 > lim
                c00 = np.sqrt(m00) if chol else 1.0
                c10 = m10 / c00
                t = m11 - c10 * c10
                chol = chol and t > _CHOL_REL * m11 and t > lim
                c11 = np.sqrt(t) if chol else 1.0
                c20 = m20 / c00
                c21 = (m21 - c20 * c10) / c11
                t = m22 - c20 * c20 - c21 * c21
                chol = chol and t > _CHOL_REL * m22 and t > lim
                c22 = np.sqrt(t) if chol else 1.0
                if chol:
                    r00, r11, r22 = 1.0 / c00, 1.0 / c11, 1.0 / c22
                    for j in range(L):
                        a0 = R[0, j] * r00
                        a1 = (R[1, j] - c10 * a0) * r11
                        R[0, j] = a0
                        R[1, j] = a1
                        R[2, j] = (R[2, j] - c20 * a0 - c21 * a1) * r22
            if chol:
                r = k
            else:
                # Gram-Schmidt with pivoting, each projection twice, ended by the rank
                # tolerance (every k other than 3; for k = 3 rows near dependence or 0)
                thr = tol * np.sqrt(sc)
                r = 0
                for i in range(k):
                    jb = i
                    best = -1.0
                    for a in range(i, k):
                        s = 0.0
                        for j in range(L):
                            s += R[a, j] * R[a, j]
                        if a == i or not s <= best:          # a NaN row: the pose stays NaN
                            jb = a
                            best = s
                    for j in range(L):
                        t = R[i, j]
                        R[i, j] = R[jb, j]
                        R[jb, j] = t
                    nv = np.sqrt(best)
                    if r == i and not nv <= thr:
                        r += 1
                        for j in range(L):
                            R[i, j] /= nv
                        for a in range(i + 1, k):
                            for _ in range(2):
                                s = 0.0
                                for j in range(L):
                                    s += R[a, j] * R[i, j]
                                for j in range(L):
                                    R[a, j] -= s * R[i, j]
                    else:
                        for j in range(L):
                            R[i, j] = 0.0
            for i in range(k):
                for j in range(L):
                    out[n, Sc[i], j] = R[i, j]
            rank[n] = r
    return run


def constraint_basis(G, Sc, *, tol: float, transposed: bool = False):
    """Orthonormal bases of the row spaces of ``G[:, Sc, :]`` (module docstring).

    Parameters
    ----------
    G : ndarray (N, d, L), or (N, L, d) with ``transposed``
        Generator matrices.
    Sc : sequence of int
        The k removed output coordinates (the constraint rows).
    tol : float
        Relative rank tolerance (against the largest row norm of each G).

    Returns
    -------
    Gq : ndarray, the shape of G
        A copy of G whose rows Sc (columns with ``transposed``) are the basis:
        orthonormal rows first, in the order the pivoting took them (``rank[n]`` of
        them), zero rows after.
    rank : ndarray (N,) int
        A pose with NaN in its constraint rows counts as full rank (its answer is NaN
        or −inf either way).
    """
    G = np.ascontiguousarray(G, dtype=float)
    Sc = np.asarray(Sc, dtype=np.int64)
    out = G.copy()
    rank = np.empty(G.shape[0], dtype=np.int64)
    if len(G):
        # the transposed layout as a view (N, d, L): one code path, strided reads
        view = (lambda a: np.swapaxes(a, 1, 2)) if transposed else (lambda a: a)
        _kernel()(view(G), Sc, float(tol), view(out), rank)
    return out, rank
