"""The split-sign vertex enumeration of :mod:`.slice_farthest` for L = 8, d = 6, over 64
poses at once (Kühne et al., eqs. (14), (16); SIMD across poses).

For each free set F of three actuators: the 3 × 3 block ``G_{S^c,F}`` inverted by
its adjugate and one division, ``K = (G_{S^c,F})^{-1} G_{S^c,X}``,
``E = G_{S,X} - G_{S,F} K``, the five signs of X split as (+1, s1, s2) × (s3, s4) so
that ``K s`` and ``E s`` are sums of 4 + 4 partial sums, and the feasibility test
``|p_F| <= 1`` with the rounding allowance of :mod:`.slice_farthest` (the same
candidates as its Gray-code walk, which the tests compare it with, as with the numpy
enumeration).  The poses of a block are the innermost loop, the Jacobians transposed
so that pose is the fastest index, and every branch of the body is a select (a
singular block makes all its sign vectors infeasible instead of being skipped).  The
compiler then evaluates four poses per vector instruction; for that the kernel is
compiled with numpy's error model (a float division by zero gives inf instead of
raising, so the division carries no branch; the one division here never sees zero).
The body is written out (16 sign vectors, no inner loops) so that nothing stops the
vectoriser.  About 1.1 µs per pose and slice, against 3.8 µs for the same
enumeration pose by pose (which skipped E where no sign vector was feasible; a block
of poses cannot skip).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["LANES", "slice_farthest_lanes"]

#: poses per block (the transposed block, 6 × 8 × 64 float64 = 24 KiB, stays in L1; 5 %
#: faster than 32 on the benchmark machine)
LANES = 64
#: as slice_farthest._TOL / _EPS (kept equal by tests/indices/test_study_compiled.py)
_TOL = 1e-12
_EPS = 2.220446049250313e-16


@lru_cache(maxsize=1)
def _kernel():
    import numba

    # the steps both kernels share, inlined into their pose loops (numba IR level), so
    # that the vectoriser sees one straight body as before; module globals, not closure
    # variables: numba keys its cache of a closure on the cells, so the kernels would be
    # compiled again in every process
    global _inverse, _k_column, _e_entry
    inline = numba.njit(inline="always", error_model="numpy")

    @inline
    def _inverse(g, s0, s1, s2, f0, f1, f2, w):            # pragma: no cover (compiled)
        """The block G_{S^c,F} of pose w (rows s, columns f) inverted by its adjugate:
        (good, cond, its inverse by rows); not good (and the inverse meaningless) where
        |det| <= 1e-12 times the product of its column norms; cond = that product /
        |det|."""
        a00 = g[s0, f0, w]
        a01 = g[s0, f1, w]
        a02 = g[s0, f2, w]
        a10 = g[s1, f0, w]
        a11 = g[s1, f1, w]
        a12 = g[s1, f2, w]
        a20 = g[s2, f0, w]
        a21 = g[s2, f1, w]
        a22 = g[s2, f2, w]
        c00 = a11 * a22 - a12 * a21
        c01 = a12 * a20 - a10 * a22
        c02 = a10 * a21 - a11 * a20
        det = a00 * c00 + a01 * c01 + a02 * c02
        scale = np.sqrt((a00 ** 2 + a10 ** 2 + a20 ** 2) * (a01 ** 2 + a11 ** 2 + a21 ** 2)
                        * (a02 ** 2 + a12 ** 2 + a22 ** 2))
        good = abs(det) > 1e-12 * scale
        rd = 1.0 / (det if good else 1.0)
        cond = scale * abs(rd)
        i00, i10, i20 = c00 * rd, c01 * rd, c02 * rd
        i01 = (a02 * a21 - a01 * a22) * rd
        i11 = (a00 * a22 - a02 * a20) * rd
        i21 = (a01 * a20 - a00 * a21) * rd
        i02 = (a01 * a12 - a02 * a11) * rd
        i12 = (a02 * a10 - a00 * a12) * rd
        i22 = (a00 * a11 - a01 * a10) * rd
        return good, cond, (i00, i01, i02, i10, i11, i12, i20, i21, i22)

    @inline
    def _k_column(g, s0, s1, s2, x, w, inv):               # pragma: no cover (compiled)
        """Column x of K = (G_{S^c,F})^{-1} G_{S^c,X} (3 rows) from the inverse by rows."""
        i00, i01, i02, i10, i11, i12, i20, i21, i22 = inv
        b0, b1, b2 = g[s0, x, w], g[s1, x, w], g[s2, x, w]
        return (i00 * b0 + i01 * b1 + i02 * b2, i10 * b0 + i11 * b1 + i12 * b2,
                i20 * b0 + i21 * b1 + i22 * b2)

    @inline
    def _e_entry(g, t, f0, f1, f2, x, w, k):               # pragma: no cover (compiled)
        """Entry (t, x) of E = G_{S,X} - G_{S,F} K, k the column x of K."""
        return g[t, x, w] - (g[t, f0, w] * k[0] + g[t, f1, w] * k[1] + g[t, f2, w] * k[2])

    @numba.njit(cache=True, error_model="numpy")
    def run(G, S, Sc, F, X, out, W, tr):                    # pragma: no cover (compiled)
        N = G.shape[0]
        g = np.empty((6, 8, W))
        best = np.empty(W)
        s0, s1, s2 = Sc[0], Sc[1], Sc[2]
        t0, t1, t2 = S[0], S[1], S[2]
        for n0 in range(0, N, W):
            for w in range(W):                 # the block, pose fastest (last pose padded)
                n = min(n0 + w, N - 1)
                for i in range(6):
                    for l in range(8):
                        g[i, l, w] = G[n, l, i] if tr else G[n, i, l]
                best[w] = -1.0
            for f in range(F.shape[0]):
                f0, f1, f2 = F[f, 0], F[f, 1], F[f, 2]
                x0, x1, x2, x3, x4 = X[f, 0], X[f, 1], X[f, 2], X[f, 3], X[f, 4]
                for w in range(W):
                    good, cond, inv = _inverse(g, s0, s1, s2, f0, f1, f2, w)
                    c0 = _k_column(g, s0, s1, s2, x0, w, inv)
                    c1 = _k_column(g, s0, s1, s2, x1, w, inv)
                    c2 = _k_column(g, s0, s1, s2, x2, w, inv)
                    c3 = _k_column(g, s0, s1, s2, x3, w, inv)
                    c4 = _k_column(g, s0, s1, s2, x4, w, inv)
                    k00, k10, k20 = c0
                    k01, k11, k21 = c1
                    k02, k12, k22 = c2
                    k03, k13, k23 = c3
                    k04, k14, k24 = c4
                    e00 = _e_entry(g, t0, f0, f1, f2, x0, w, c0)
                    e01 = _e_entry(g, t0, f0, f1, f2, x1, w, c1)
                    e02 = _e_entry(g, t0, f0, f1, f2, x2, w, c2)
                    e03 = _e_entry(g, t0, f0, f1, f2, x3, w, c3)
                    e04 = _e_entry(g, t0, f0, f1, f2, x4, w, c4)
                    e10 = _e_entry(g, t1, f0, f1, f2, x0, w, c0)
                    e11 = _e_entry(g, t1, f0, f1, f2, x1, w, c1)
                    e12 = _e_entry(g, t1, f0, f1, f2, x2, w, c2)
                    e13 = _e_entry(g, t1, f0, f1, f2, x3, w, c3)
                    e14 = _e_entry(g, t1, f0, f1, f2, x4, w, c4)
                    e20 = _e_entry(g, t2, f0, f1, f2, x0, w, c0)
                    e21 = _e_entry(g, t2, f0, f1, f2, x1, w, c1)
                    e22 = _e_entry(g, t2, f0, f1, f2, x2, w, c2)
                    e23 = _e_entry(g, t2, f0, f1, f2, x3, w, c3)
                    e24 = _e_entry(g, t2, f0, f1, f2, x4, w, c4)
                    ka = abs(k00) + abs(k01) + abs(k02) + abs(k03) + abs(k04)
                    sl0 = 1.0 + _TOL + 64.0 * _EPS * (1.0 + ka) * (1.0 + cond) if good else -1.0
                    k1p, k1m = k01 + k02, k01 - k02
                    pa00 = -(k00 + k1p)
                    pa10 = -(k00 + k1m)
                    pa20 = -(k00 - k1m)
                    pa30 = -(k00 - k1p)
                    k3p, k3m = k03 + k04, k03 - k04
                    pb00 = -k3p
                    pb10 = -k3m
                    pb20 = k3m
                    pb30 = k3p
                    e1p, e1m = e01 + e02, e01 - e02
                    ua00 = e00 + e1p
                    ua10 = e00 + e1m
                    ua20 = e00 - e1m
                    ua30 = e00 - e1p
                    e3p, e3m = e03 + e04, e03 - e04
                    ub00 = e3p
                    ub10 = e3m
                    ub20 = -e3m
                    ub30 = -e3p
                    ka = abs(k10) + abs(k11) + abs(k12) + abs(k13) + abs(k14)
                    sl1 = 1.0 + _TOL + 64.0 * _EPS * (1.0 + ka) * (1.0 + cond) if good else -1.0
                    k1p, k1m = k11 + k12, k11 - k12
                    pa01 = -(k10 + k1p)
                    pa11 = -(k10 + k1m)
                    pa21 = -(k10 - k1m)
                    pa31 = -(k10 - k1p)
                    k3p, k3m = k13 + k14, k13 - k14
                    pb01 = -k3p
                    pb11 = -k3m
                    pb21 = k3m
                    pb31 = k3p
                    e1p, e1m = e11 + e12, e11 - e12
                    ua01 = e10 + e1p
                    ua11 = e10 + e1m
                    ua21 = e10 - e1m
                    ua31 = e10 - e1p
                    e3p, e3m = e13 + e14, e13 - e14
                    ub01 = e3p
                    ub11 = e3m
                    ub21 = -e3m
                    ub31 = -e3p
                    ka = abs(k20) + abs(k21) + abs(k22) + abs(k23) + abs(k24)
                    sl2 = 1.0 + _TOL + 64.0 * _EPS * (1.0 + ka) * (1.0 + cond) if good else -1.0
                    k1p, k1m = k21 + k22, k21 - k22
                    pa02 = -(k20 + k1p)
                    pa12 = -(k20 + k1m)
                    pa22 = -(k20 - k1m)
                    pa32 = -(k20 - k1p)
                    k3p, k3m = k23 + k24, k23 - k24
                    pb02 = -k3p
                    pb12 = -k3m
                    pb22 = k3m
                    pb32 = k3p
                    e1p, e1m = e21 + e22, e21 - e22
                    ua02 = e20 + e1p
                    ua12 = e20 + e1m
                    ua22 = e20 - e1m
                    ua32 = e20 - e1p
                    e3p, e3m = e23 + e24, e23 - e24
                    ub02 = e3p
                    ub12 = e3m
                    ub22 = -e3m
                    ub32 = -e3p
                    bw = best[w]
                    ok = ((abs(pa00 + pb00) <= sl0) & (abs(pa01 + pb01) <= sl1)
                          & (abs(pa02 + pb02) <= sl2))
                    u0, u1, u2 = ua00 + ub00, ua01 + ub01, ua02 + ub02
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa00 + pb10) <= sl0) & (abs(pa01 + pb11) <= sl1)
                          & (abs(pa02 + pb12) <= sl2))
                    u0, u1, u2 = ua00 + ub10, ua01 + ub11, ua02 + ub12
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa00 + pb20) <= sl0) & (abs(pa01 + pb21) <= sl1)
                          & (abs(pa02 + pb22) <= sl2))
                    u0, u1, u2 = ua00 + ub20, ua01 + ub21, ua02 + ub22
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa00 + pb30) <= sl0) & (abs(pa01 + pb31) <= sl1)
                          & (abs(pa02 + pb32) <= sl2))
                    u0, u1, u2 = ua00 + ub30, ua01 + ub31, ua02 + ub32
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa10 + pb00) <= sl0) & (abs(pa11 + pb01) <= sl1)
                          & (abs(pa12 + pb02) <= sl2))
                    u0, u1, u2 = ua10 + ub00, ua11 + ub01, ua12 + ub02
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa10 + pb10) <= sl0) & (abs(pa11 + pb11) <= sl1)
                          & (abs(pa12 + pb12) <= sl2))
                    u0, u1, u2 = ua10 + ub10, ua11 + ub11, ua12 + ub12
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa10 + pb20) <= sl0) & (abs(pa11 + pb21) <= sl1)
                          & (abs(pa12 + pb22) <= sl2))
                    u0, u1, u2 = ua10 + ub20, ua11 + ub21, ua12 + ub22
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa10 + pb30) <= sl0) & (abs(pa11 + pb31) <= sl1)
                          & (abs(pa12 + pb32) <= sl2))
                    u0, u1, u2 = ua10 + ub30, ua11 + ub31, ua12 + ub32
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa20 + pb00) <= sl0) & (abs(pa21 + pb01) <= sl1)
                          & (abs(pa22 + pb02) <= sl2))
                    u0, u1, u2 = ua20 + ub00, ua21 + ub01, ua22 + ub02
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa20 + pb10) <= sl0) & (abs(pa21 + pb11) <= sl1)
                          & (abs(pa22 + pb12) <= sl2))
                    u0, u1, u2 = ua20 + ub10, ua21 + ub11, ua22 + ub12
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa20 + pb20) <= sl0) & (abs(pa21 + pb21) <= sl1)
                          & (abs(pa22 + pb22) <= sl2))
                    u0, u1, u2 = ua20 + ub20, ua21 + ub21, ua22 + ub22
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa20 + pb30) <= sl0) & (abs(pa21 + pb31) <= sl1)
                          & (abs(pa22 + pb32) <= sl2))
                    u0, u1, u2 = ua20 + ub30, ua21 + ub31, ua22 + ub32
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa30 + pb00) <= sl0) & (abs(pa31 + pb01) <= sl1)
                          & (abs(pa32 + pb02) <= sl2))
                    u0, u1, u2 = ua30 + ub00, ua31 + ub01, ua32 + ub02
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa30 + pb10) <= sl0) & (abs(pa31 + pb11) <= sl1)
                          & (abs(pa32 + pb12) <= sl2))
                    u0, u1, u2 = ua30 + ub10, ua31 + ub11, ua32 + ub12
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa30 + pb20) <= sl0) & (abs(pa31 + pb21) <= sl1)
                          & (abs(pa32 + pb22) <= sl2))
                    u0, u1, u2 = ua30 + ub20, ua31 + ub21, ua32 + ub22
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(pa30 + pb30) <= sl0) & (abs(pa31 + pb31) <= sl1)
                          & (abs(pa32 + pb32) <= sl2))
                    u0, u1, u2 = ua30 + ub30, ua31 + ub31, ua32 + ub32
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    best[w] = bw
            for w in range(min(W, N - n0)):
                out[n0 + w] = np.sqrt(best[w]) if best[w] >= 0 else -np.inf
    @numba.njit(cache=True, error_model="numpy")
    def run6(G, S, Sc, F, X, out, W, tr):                   # pragma: no cover (compiled)
        """L = 6: three free actuators, three at a limit, signs (+1, s1, s2)."""
        N = G.shape[0]
        g = np.empty((6, 6, W))
        best = np.empty(W)
        s0, s1, s2 = Sc[0], Sc[1], Sc[2]
        t0, t1, t2 = S[0], S[1], S[2]
        for n0 in range(0, N, W):
            for w in range(W):
                n = min(n0 + w, N - 1)
                for i in range(6):
                    for l in range(6):
                        g[i, l, w] = G[n, l, i] if tr else G[n, i, l]
                best[w] = -1.0
            for f in range(F.shape[0]):
                f0, f1, f2 = F[f, 0], F[f, 1], F[f, 2]
                x0, x1, x2 = X[f, 0], X[f, 1], X[f, 2]
                for w in range(W):
                    good, cond, inv = _inverse(g, s0, s1, s2, f0, f1, f2, w)
                    c0 = _k_column(g, s0, s1, s2, x0, w, inv)
                    c1 = _k_column(g, s0, s1, s2, x1, w, inv)
                    c2 = _k_column(g, s0, s1, s2, x2, w, inv)
                    k00, k10, k20 = c0
                    k01, k11, k21 = c1
                    k02, k12, k22 = c2
                    e00 = _e_entry(g, t0, f0, f1, f2, x0, w, c0)
                    e01 = _e_entry(g, t0, f0, f1, f2, x1, w, c1)
                    e02 = _e_entry(g, t0, f0, f1, f2, x2, w, c2)
                    e10 = _e_entry(g, t1, f0, f1, f2, x0, w, c0)
                    e11 = _e_entry(g, t1, f0, f1, f2, x1, w, c1)
                    e12 = _e_entry(g, t1, f0, f1, f2, x2, w, c2)
                    e20 = _e_entry(g, t2, f0, f1, f2, x0, w, c0)
                    e21 = _e_entry(g, t2, f0, f1, f2, x1, w, c1)
                    e22 = _e_entry(g, t2, f0, f1, f2, x2, w, c2)
                    sl0 = (1.0 + _TOL + 64.0 * _EPS * (1.0 + abs(k00) + abs(k01) + abs(k02))
                           * (1.0 + cond)) if good else -1.0
                    sl1 = (1.0 + _TOL + 64.0 * _EPS * (1.0 + abs(k10) + abs(k11) + abs(k12))
                           * (1.0 + cond)) if good else -1.0
                    sl2 = (1.0 + _TOL + 64.0 * _EPS * (1.0 + abs(k20) + abs(k21) + abs(k22))
                           * (1.0 + cond)) if good else -1.0
                    bw = best[w]
                    # (s1, s2) = (+, +), (+, -), (-, +), (-, -); p_F = -K s, u = E s
                    kp0, km0 = k01 + k02, k01 - k02
                    kp1, km1 = k11 + k12, k11 - k12
                    kp2, km2 = k21 + k22, k21 - k22
                    ep0, em0 = e01 + e02, e01 - e02
                    ep1, em1 = e11 + e12, e11 - e12
                    ep2, em2 = e21 + e22, e21 - e22
                    ok = ((abs(k00 + kp0) <= sl0) & (abs(k10 + kp1) <= sl1)
                          & (abs(k20 + kp2) <= sl2))
                    u0, u1, u2 = e00 + ep0, e10 + ep1, e20 + ep2
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(k00 + km0) <= sl0) & (abs(k10 + km1) <= sl1)
                          & (abs(k20 + km2) <= sl2))
                    u0, u1, u2 = e00 + em0, e10 + em1, e20 + em2
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(k00 - km0) <= sl0) & (abs(k10 - km1) <= sl1)
                          & (abs(k20 - km2) <= sl2))
                    u0, u1, u2 = e00 - em0, e10 - em1, e20 - em2
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    ok = ((abs(k00 - kp0) <= sl0) & (abs(k10 - kp1) <= sl1)
                          & (abs(k20 - kp2) <= sl2))
                    u0, u1, u2 = e00 - ep0, e10 - ep1, e20 - ep2
                    nrm = u0 * u0 + u1 * u1 + u2 * u2
                    bw = nrm if ok & (nrm > bw) else bw
                    best[w] = bw
            for w in range(min(W, N - n0)):
                out[n0 + w] = np.sqrt(best[w]) if best[w] >= 0 else -np.inf
    return run, run6


def slice_farthest_lanes(G, S, Sc, F, X, out, transposed: bool = False):
    """Fill ``out`` (N,) with the farthest point of each slice: G (N, 6, L) contiguous
    with L = 8 or 6 (``transposed``: G given as its transpose (N, L, 6), e.g. J for Jᵀ,
    read without a copy), S and Sc the kept and removed coordinates (3 each), F (C(L, 3), 3) and X
    (C(L, 3), L - 3) the free sets and their complements
    (:func:`.slice_farthest._tables`)."""
    if len(G):
        run, run6 = _kernel()
        L = G.shape[1] if transposed else G.shape[2]
        (run if L == 8 else run6)(G, S, Sc, F, X, out, LANES, bool(transposed))
    return out
