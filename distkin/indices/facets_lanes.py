"""The six worst-case capabilities of a redundant device (L = 8) from the null space of
Jᵀ, over 32 poses at once (Kühne et al., eqs. (5)-(7), (9)-(13); SIMD across poses).

The wrench zonotope ``Jᵀ·box`` (unit box) of L = 8 generators in R⁶ has C(8, 5) = 56
pairs of facets, one per set T of five generators (the rows g_t of J).  Its normal n
is orthogonal to every g_t, t ∈ T, so ``y = J n`` vanishes on T and lives on the three
other actuators U; and y lies in the range of J, i.e. it is orthogonal to the null
space of Jᵀ, spanned by the two columns of an 8 × 2 matrix Z.  So

.. math::  y_U = Z_{U,0} \\times Z_{U,1},\\qquad n = J^\\# y,\\qquad
           h = \\sum_i |n \\cdot g_i| = \\|y_U\\|_1,

and the twist and acceleration normals of :func:`.study._worst_cases` are
``JᵀJ n = Jᵀ y`` (J J# is the projector onto the range of J, which holds y) and
``M̂ n``.  Each capability is then ``min_T h·lim / ||n_S||`` over the slice S
(:func:`.zonotope._ratio_min`: a normal with ``||n_S|| <= 1e-15`` of the root sum of
squares over all normals is vacuous).  Z (the last two columns of the Q of a
Householder QR of J) and J# come from :mod:`.jacobi_lanes`.  The same facets as the pivoted route of
:mod:`.study_compiled` (which the numpy route :func:`.zonotope._facets` mirrors), found
without choosing a basis, so every pose of a block runs the same branch-free code and
the compiler evaluates four poses per vector instruction; results agree with the
numpy route to a few 1e-14 relative (rounding differs).  Poses whose Jᵀ is
rank-deficient (σmin/σmax <= RANK_TOL) are flagged by the caller.
"""

from __future__ import annotations

from functools import lru_cache
from itertools import combinations

import numpy as np

__all__ = ["LANES", "capabilities_lanes"]

#: poses per block (the 6 × 56 × 32 slice norms, 86 KiB, stay in L2)
LANES = 32


@lru_cache(maxsize=None)
def _subsets(L: int):
    return np.array(list(combinations(range(L), 3)), dtype=np.int64)


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True, error_model="numpy")
    def run(J, Jp, Zn, M, lims, U, caps, W):                 # pragma: no cover (compiled)
        N, L, d = J.shape
        K = U.shape[0]
        Jt = np.empty((L, d, W))
        Pt = np.empty((d, L, W))
        Z = np.empty((L, 2, W))
        vb = np.empty((6, K, W))
        hb = np.empty((K, W))
        tot = np.empty(W)
        hbest = np.empty(W)
        vbest = np.empty(W)
        for n0 in range(0, N, W):
            for l in range(L):
                for i in range(d):
                    for w in range(W):
                        Jt[l, i, w] = J[min(n0 + w, N - 1), l, i]
                        Pt[i, l, w] = Jp[min(n0 + w, N - 1), i, l]
                for c in range(2):
                    for w in range(W):
                        Z[l, c, w] = Zn[min(n0 + w, N - 1), l, c]
            # ---- the 56 facets: y on U, h, and the six slice norms (written out: no
            # inner loop, so that the pose loop is the one the compiler vectorises)
            m0, m1, m2, m3, m4, m5 = M[0], M[1], M[2], M[3], M[4], M[5]
            for t in range(K):
                u1, u2, u3 = U[t, 0], U[t, 1], U[t, 2]
                for w in range(W):
                    y1 = Z[u2, 0, w] * Z[u3, 1, w] - Z[u3, 0, w] * Z[u2, 1, w]
                    y2 = Z[u3, 0, w] * Z[u1, 1, w] - Z[u1, 0, w] * Z[u3, 1, w]
                    y3 = Z[u1, 0, w] * Z[u2, 1, w] - Z[u2, 0, w] * Z[u1, 1, w]
                    hb[t, w] = abs(y1) + abs(y2) + abs(y3)
                    w0 = y1 * Pt[0, u1, w] + y2 * Pt[0, u2, w] + y3 * Pt[0, u3, w]
                    t0 = y1 * Jt[u1, 0, w] + y2 * Jt[u2, 0, w] + y3 * Jt[u3, 0, w]
                    a0 = w0 * m0
                    w1 = y1 * Pt[1, u1, w] + y2 * Pt[1, u2, w] + y3 * Pt[1, u3, w]
                    t1 = y1 * Jt[u1, 1, w] + y2 * Jt[u2, 1, w] + y3 * Jt[u3, 1, w]
                    a1 = w1 * m1
                    w2 = y1 * Pt[2, u1, w] + y2 * Pt[2, u2, w] + y3 * Pt[2, u3, w]
                    t2 = y1 * Jt[u1, 2, w] + y2 * Jt[u2, 2, w] + y3 * Jt[u3, 2, w]
                    a2 = w2 * m2
                    w3 = y1 * Pt[3, u1, w] + y2 * Pt[3, u2, w] + y3 * Pt[3, u3, w]
                    t3 = y1 * Jt[u1, 3, w] + y2 * Jt[u2, 3, w] + y3 * Jt[u3, 3, w]
                    a3 = w3 * m3
                    w4 = y1 * Pt[4, u1, w] + y2 * Pt[4, u2, w] + y3 * Pt[4, u3, w]
                    t4 = y1 * Jt[u1, 4, w] + y2 * Jt[u2, 4, w] + y3 * Jt[u3, 4, w]
                    a4 = w4 * m4
                    w5 = y1 * Pt[5, u1, w] + y2 * Pt[5, u2, w] + y3 * Pt[5, u3, w]
                    t5 = y1 * Jt[u1, 5, w] + y2 * Jt[u2, 5, w] + y3 * Jt[u3, 5, w]
                    a5 = w5 * m5
                    vb[0, t, w] = w0 * w0 + w1 * w1 + w2 * w2
                    vb[2, t, w] = t0 * t0 + t1 * t1 + t2 * t2
                    vb[4, t, w] = a0 * a0 + a1 * a1 + a2 * a2
                    vb[1, t, w] = w3 * w3 + w4 * w4 + w5 * w5
                    vb[3, t, w] = t3 * t3 + t4 * t4 + t5 * t5
                    vb[5, t, w] = a3 * a3 + a4 * a4 + a5 * a5
            # ---- min over the facets of h·lim / ||n_S|| (zonotope._ratio_min)
            for c in range(6):
                lim = lims[0] if c < 2 else (lims[2] if c < 4 else lims[1])
                for w in range(W):
                    tot[w] = 0.0
                for t in range(K):
                    for w in range(W):
                        tot[w] += vb[c, t, w]
                for w in range(W):
                    thr = 1e-15 * (np.sqrt(tot[w]) + 1e-300)
                    tot[w] = thr * thr
                for w in range(W):
                    hbest[w] = 1.0
                    vbest[w] = 0.0
                for t in range(K):
                    for w in range(W):
                        v = vb[c, t, w]
                        h = hb[t, w]
                        # h/√v < hbest/√vbest without a square root or a division
                        better = (v > tot[w]) & (h * h * vbest[w] < hbest[w] * hbest[w] * v)
                        hbest[w] = h if better else hbest[w]
                        vbest[w] = v if better else vbest[w]
                for w in range(min(W, N - n0)):
                    v = vbest[w]
                    caps[n0 + w, c] = (hbest[w] * lim) / np.sqrt(v) if v > 0.0 else np.inf
    return run


def capabilities_lanes(J, twist, Z, M, lims, caps):
    """Fill ``caps`` (N, 6) (force, torque, velocity, angular velocity, acceleration,
    angular acceleration; the order of :data:`.study.CAPABILITIES`) for J (N, 8, 6)
    with J# ``twist`` (N, 6, 8), an orthonormal basis ``Z`` (N, 8, 2) of the null space
    of Jᵀ (both from :func:`.jacobi_lanes.jacobi_lanes`), diag(M̂) ``M`` (6,) and the
    limits ``lims`` (nominal torque, stall torque, velocity)."""
    if len(J):
        _kernel()(J, twist, Z, M, lims, _subsets(J.shape[1]), caps, LANES)
    return caps
