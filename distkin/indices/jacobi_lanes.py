"""One-sided (Hestenes) Jacobi SVD of the study's four readings of the scaling over 32
poses at once (Kühne et al., Sec. II-C-2; SIMD across poses).

The singular values of ``ST⁻¹Jᵀ``, ``Jᵀ``, ``ST·Jᵀ`` and ``ST⁻¹Jxᵀ`` (6 × L; condition
numbers from about 5 to 1e8 on the presets' grids) and ``J# = pinv(J)`` from the
Jacobi of ``Jᵀ``: rotations of row pairs until all rows are orthogonal to 1e-15 of
their norms; the singular values are then the row norms (relative accuracy of order
1e-15·κ, like LAPACK's SVD), and with ``Q Jᵀ = B`` (orthogonal Q accumulated from the
rotations, orthogonal rows b_i of norm σ_i), ``J# = Qᵀ diag(σ⁻²) B``.

The arithmetic is that of the pose-by-pose Jacobi the study used before (issue 17),
operation for operation, so the results are bit for bit the same; the poses of a block
are the innermost loop (every array indexed pose last) and a pair that needs no rotation in
one pose gets the rotation (c, s) = (1, 0), which leaves its rows exactly as they are.
A block sweeps until no pose rotated (a pose that converged earlier stays unchanged:
its test sees the same rows), at most 60 sweeps; a pose still rotating then is flagged.
The compiler evaluates four poses per vector instruction (numpy's error model: the
divisions of a pose that needs no rotation may give inf or nan, and are selected away).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["LANES", "jacobi_lanes"]

#: poses per block
LANES = 32
#: rows count as orthogonal below this cosine (as study_compiled._JACOBI_TOL)
_JACOBI_TOL = 1e-15
_JACOBI_SWEEPS = 60


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True, error_model="numpy")
    def run(J, Jq, st, sig, twist, flag, W):                     # pragma: no cover (compiled)
        N, L, d = J.shape
        A = np.empty((d, L, W))
        Q = np.empty((d, d, W))
        nrm = np.empty((d, W))
        gam = np.empty(W)
        cc = np.empty(W)
        ss = np.empty(W)
        rot = np.empty(W, np.bool_)
        conv = np.empty(W, np.bool_)
        for n0 in range(0, N, W):
            for r_ in range(4):                  # ST⁻¹Jᵀ, Jᵀ (with Q, for J#), ST·Jᵀ, ST⁻¹Jxᵀ
                for i in range(d):
                    for l in range(L):
                        for w in range(W):
                            n = min(n0 + w, N - 1)
                            x = J[n, l, i]
                            if r_ == 0:
                                A[i, l, w] = x / st[i]
                            elif r_ == 1:
                                A[i, l, w] = x
                            elif r_ == 2:
                                A[i, l, w] = x * st[i]
                            else:
                                A[i, l, w] = (x * Jq[n, l]) / st[i]
                if r_ == 1:
                    for i in range(d):
                        for j in range(d):
                            for w in range(W):
                                Q[i, j, w] = 1.0 if i == j else 0.0
                for w in range(W):
                    conv[w] = False
                for sweep in range(_JACOBI_SWEEPS):
                    for w in range(W):
                        rot[w] = False
                    for p in range(d):
                        for w in range(W):
                            nrm[p, w] = 0.0
                        for l in range(L):
                            for w in range(W):
                                nrm[p, w] += A[p, l, w] * A[p, l, w]
                    for p in range(d - 1):
                        for q in range(p + 1, d):
                            for w in range(W):
                                gam[w] = 0.0
                            for l in range(L):
                                for w in range(W):
                                    gam[w] += A[p, l, w] * A[q, l, w]
                            for w in range(W):
                                alpha = nrm[p, w]
                                beta = nrm[q, w]
                                gamma = gam[w]
                                go = abs(gamma) > _JACOBI_TOL * np.sqrt(alpha * beta)
                                zeta = (beta - alpha) / (2.0 * gamma)
                                t = ((1.0 if zeta >= 0 else -1.0)
                                     / (abs(zeta) + np.sqrt(1.0 + zeta * zeta)))
                                c = 1.0 / np.sqrt(1.0 + t * t)
                                s = c * t
                                t = t if go else 0.0
                                cc[w] = c if go else 1.0
                                ss[w] = s if go else 0.0
                                nrm[p, w] = alpha - t * gamma
                                nrm[q, w] = beta + t * gamma
                                rot[w] = rot[w] | go
                            for l in range(L):
                                for w in range(W):
                                    ap = A[p, l, w]
                                    aq = A[q, l, w]
                                    A[p, l, w] = cc[w] * ap - ss[w] * aq
                                    A[q, l, w] = ss[w] * ap + cc[w] * aq
                            if r_ == 1:
                                for l in range(d):
                                    for w in range(W):
                                        ap = Q[p, l, w]
                                        aq = Q[q, l, w]
                                        Q[p, l, w] = cc[w] * ap - ss[w] * aq
                                        Q[q, l, w] = ss[w] * ap + cc[w] * aq
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
                        for l in range(L):
                            s += A[i, l, w] * A[i, l, w]
                        s = np.sqrt(s)
                        lo = min(lo, s)
                        hi = max(hi, s)
                    sig[n, 2 * r_] = lo
                    sig[n, 2 * r_ + 1] = hi
                    if r_ == 1 and L > d:
                        # J# = Qᵀ diag(1/σ²) B  (twist (d, L))
                        for i in range(d):
                            s = 0.0
                            for l in range(L):
                                s += A[i, l, w] * A[i, l, w]
                            nrm[i, w] = 1.0 / s if s > 0 else 0.0
                        for i in range(d):
                            for l in range(L):
                                s = 0.0
                                for j in range(d):
                                    s += Q[j, i, w] * nrm[j, w] * A[j, l, w]
                                twist[n, i, l] = s
    return run


def jacobi_lanes(J, Jq, st, sig, twist, flag):
    """Fill ``sig`` (N, 8) ((σmin, σmax) of ST⁻¹Jᵀ, Jᵀ, ST·Jᵀ and ST⁻¹Jxᵀ), ``twist``
    (J#, only for L > 6) and set ``flag`` where a Jacobi did not converge.  J (N, L, 6)
    and Jq (N, L) contiguous, st (6,), twist (N, 6, L), flag (N,) bool."""
    if len(J):
        _kernel()(J, Jq, st, sig, twist, flag, LANES)
