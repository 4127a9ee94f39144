"""The singular values of the study's four readings of the scaling, J# = pinv(J) and the
null space of Jᵀ, over 64 poses at once: a Householder QR of J, then one-sided
(Hestenes) Jacobi on the triangular factor (Kühne et al., Sec. II-C-2; SIMD across
poses).

The readings are ``ST⁻¹Jᵀ``, ``Jᵀ``, ``ST·Jᵀ`` and ``ST⁻¹Jxᵀ`` (6 × L; condition
numbers from about 5 to 1e8 on the presets' grids).  With ``J = Q R`` (Householder, Q
L × L orthogonal, R 6 × 6 upper triangular), ``σ(D Jᵀ) = σ(J D) = σ(R D)`` for every
diagonal scaling D, so the first three readings share one QR and the fourth takes one
of ``Jx = diag(Jq) J``; Householder QR is backward stable column by column (Higham,
*Accuracy and Stability of Numerical Algorithms*, Thm. 19.4), so scaling the columns of
R is as accurate as factorising ``J D`` itself.  One-sided Jacobi then rotates pairs of
rows of the 6 × 6 matrix ``R D`` (instead of the 6 × L rows of ``D Jᵀ``: a quarter
fewer operations per rotation for L = 8, and the triangular start converges in fewer
sweeps) until all rows are orthogonal to 1e-15 of their norms; the singular values
are then the row norms (relative accuracy of order 1e-15·κ, like LAPACK's SVD).  The
rotation is the classical one (Rutishauser's tangent) written with one square root
and one division for t and one of each for c; the convergence test compares squares.

From the same QR: ``J# = R⁻¹ Q₁ᵀ`` (Q₁ the first six columns of Q; back substitution)
and, for L > 6, an orthonormal basis ``Z`` of the null space of Jᵀ (the last L − 6
columns of Q), which :mod:`.facets_lanes` turns into the facets of the wrench zonotope.

The poses of a block are the innermost loop (every array indexed pose last); a pair
that needs no rotation in one pose gets (c, s) = (1, 0), which leaves its rows exactly
as they are, and a pair that needs no rotation in any pose of the block is skipped
(the same bits, without the square roots and divisions).  A block sweeps until no pose rotated (a pose that converged earlier
stays unchanged: its test sees the same rows), at most 60 sweeps; a pose still
rotating then is flagged.  The compiler evaluates four poses per vector instruction
(numpy's error model: the divisions of a pose that needs no rotation may give inf or
nan, and are selected away; a rank-deficient J gives inf or nan in J#, and the caller
flags it by its σ).  Results agree with numpy's SVD and pinv to rounding (a few 1e-13
relative on the presets' grids; tests/indices/test_study_compiled.py).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["LANES", "jacobi_lanes"]

#: poses per block (6 % faster than 32 on the benchmark machine; the block sweeps until
#: its slowest pose converged)
LANES = 64
#: rows count as orthogonal below this cosine
_JACOBI_TOL = 1e-15
_JACOBI_SWEEPS = 60


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True, error_model="numpy")
    def run(J, Jq, st, sig, twist, Z, flag, W):                  # pragma: no cover (compiled)
        N, L, d = J.shape
        tol2 = _JACOBI_TOL * _JACOBI_TOL
        Y = np.empty((L, d, W))              # QR: R above the diagonal, reflectors below
        vn = np.empty((d, W))                # ||v_k||²
        rdg = np.empty((d, W))               # R's diagonal
        Qf = np.empty((L, L, W))             # columns of Q
        X = np.empty((d, L, W))              # J#
        A = np.empty((d, d, W))              # the rows Jacobi rotates (R D)
        nrm = np.empty((d, W))
        tt = np.empty(W)
        gam = np.empty(W)
        cc = np.empty(W)
        ss = np.empty(W)
        rot = np.empty(W, np.bool_)
        conv = np.empty(W, np.bool_)
        for n0 in range(0, N, W):
            for r_ in range(4):                  # ST⁻¹Jᵀ, Jᵀ, ST·Jᵀ (one QR), ST⁻¹Jxᵀ
                if r_ == 0 or r_ == 3:
                    for l in range(L):
                        for i in range(d):
                            for w in range(W):
                                n = min(n0 + w, N - 1)
                                x = J[n, l, i]
                                Y[l, i, w] = x if r_ == 0 else x * Jq[n, l]
                    # ---- Householder QR (the reflectors overwrite Y's columns)
                    for k in range(d):
                        for w in range(W):
                            tt[w] = 0.0
                        for l in range(k, L):
                            for w in range(W):
                                tt[w] += Y[l, k, w] * Y[l, k, w]
                        for w in range(W):
                            s = tt[w]
                            nx = np.sqrt(s)
                            x0 = Y[k, k, w]
                            alpha = -nx if x0 >= 0.0 else nx
                            Y[k, k, w] = x0 - alpha
                            rdg[k, w] = alpha
                            vn[k, w] = 2.0 * nx * (nx + abs(x0))
                        for j in range(k + 1, d):
                            for w in range(W):
                                tt[w] = 0.0
                            for l in range(k, L):
                                for w in range(W):
                                    tt[w] += Y[l, k, w] * Y[l, j, w]
                            for w in range(W):
                                tt[w] = 2.0 * tt[w] / vn[k, w]
                            for l in range(k, L):
                                for w in range(W):
                                    Y[l, j, w] -= tt[w] * Y[l, k, w]
                    if r_ == 0 and L > d:
                        # ---- Q's columns: Q e_c = H_0 ... H_min(c, d-1) e_c
                        for c in range(L):
                            for l in range(L):
                                for w in range(W):
                                    Qf[l, c, w] = 1.0 if l == c else 0.0
                            for k in range(min(c, d - 1), -1, -1):
                                for w in range(W):
                                    tt[w] = 0.0
                                for l in range(k, L):
                                    for w in range(W):
                                        tt[w] += Y[l, k, w] * Qf[l, c, w]
                                for w in range(W):
                                    tt[w] = 2.0 * tt[w] / vn[k, w]
                                for l in range(k, L):
                                    for w in range(W):
                                        Qf[l, c, w] -= tt[w] * Y[l, k, w]
                        # ---- J# = R⁻¹ Q₁ᵀ by back substitution
                        for i in range(d - 1, -1, -1):
                            for l in range(L):
                                for w in range(W):
                                    X[i, l, w] = Qf[l, i, w]
                            for j in range(i + 1, d):
                                for l in range(L):
                                    for w in range(W):
                                        X[i, l, w] -= Y[i, j, w] * X[j, l, w]
                            for l in range(L):
                                for w in range(W):
                                    X[i, l, w] = X[i, l, w] / rdg[i, w]
                        for w in range(min(W, N - n0)):
                            for i in range(d):
                                for l in range(L):
                                    twist[n0 + w, i, l] = X[i, l, w]
                            for l in range(L):
                                for c in range(L - d):
                                    Z[n0 + w, l, c] = Qf[l, d + c, w]
                # ---- the rows of R D
                for i in range(d):
                    for l in range(d):
                        for w in range(W):
                            x = rdg[i, w] if l == i else (Y[i, l, w] if l > i else 0.0)
                            if r_ == 0 or r_ == 3:
                                A[i, l, w] = x / st[l]
                            elif r_ == 1:
                                A[i, l, w] = x
                            else:
                                A[i, l, w] = x * st[l]
                # ---- one-sided Jacobi
                for w in range(W):
                    conv[w] = False
                for sweep in range(_JACOBI_SWEEPS):
                    for w in range(W):
                        rot[w] = False
                    for p in range(d):
                        for w in range(W):
                            nrm[p, w] = 0.0
                        for l in range(d):
                            for w in range(W):
                                nrm[p, w] += A[p, l, w] * A[p, l, w]
                    for p in range(d - 1):
                        for q in range(p + 1, d):
                            for w in range(W):
                                gam[w] = 0.0
                            for l in range(d):
                                for w in range(W):
                                    gam[w] += A[p, l, w] * A[q, l, w]
                            anygo = False
                            for w in range(W):
                                g = gam[w]
                                anygo = anygo | (g * g > tol2 * (nrm[p, w] * nrm[q, w]))
                            if not anygo:            # no pose rotates: (c, s) = (1, 0)
                                continue
                            for w in range(W):
                                alpha = nrm[p, w]
                                beta = nrm[q, w]
                                gamma = gam[w]
                                go = gamma * gamma > tol2 * (alpha * beta)
                                dd = beta - alpha
                                t = ((2.0 * gamma if dd >= 0 else -2.0 * gamma)
                                     / (abs(dd) + np.sqrt(dd * dd + 4.0 * gamma * gamma)))
                                c = 1.0 / np.sqrt(1.0 + t * t)
                                s = c * t
                                t = t if go else 0.0
                                cc[w] = c if go else 1.0
                                ss[w] = s if go else 0.0
                                nrm[p, w] = alpha - t * gamma
                                nrm[q, w] = beta + t * gamma
                                rot[w] = rot[w] | go
                            for l in range(d):
                                for w in range(W):
                                    ap = A[p, l, w]
                                    aq = A[q, l, w]
                                    A[p, l, w] = cc[w] * ap - ss[w] * aq
                                    A[q, l, w] = ss[w] * ap + cc[w] * aq
                    anyrot = False
                    for w in range(W):
                        conv[w] = conv[w] | (not rot[w])
                        anyrot = anyrot | rot[w]
                    if not anyrot:
                        break
                for w in range(min(W, N - n0)):
                    n = n0 + w
                    if not conv[w]:
                        flag[n] = True
                    lo = np.inf
                    hi = 0.0
                    for i in range(d):
                        s = 0.0
                        for l in range(d):
                            s += A[i, l, w] * A[i, l, w]
                        s = np.sqrt(s)
                        lo = min(lo, s)
                        hi = max(hi, s)
                    sig[n, 2 * r_] = lo
                    sig[n, 2 * r_ + 1] = hi
    return run


def jacobi_lanes(J, Jq, st, sig, twist, flag, Z=None):
    """Fill ``sig`` (N, 8) ((σmin, σmax) of ST⁻¹Jᵀ, Jᵀ, ST·Jᵀ and ST⁻¹Jxᵀ), ``twist``
    (J#, only for L > 6), ``Z`` (N, L, L − 6; an orthonormal basis of the null space of
    Jᵀ, only for L > 6) and set ``flag`` where a Jacobi did not converge.  J (N, L, 6)
    and Jq (N, L) contiguous, st (6,), twist (N, 6, L), flag (N,) bool."""
    N, L, d = J.shape
    if Z is None:
        Z = np.empty((N, L, max(L - d, 0)))
    if N:
        _kernel()(J, Jq, st, sig, twist, Z, flag, LANES)
    return Z
