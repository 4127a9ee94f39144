"""The farthest point of a sliced zonotope, compiled (Kühne et al., eqs. (14), (16)).

The paper's maximum sensitivities (Sec. II-C-4) run its polytope algorithm with unit
actuator limits, ``|p|∞ <= 1`` (rad or N·m), and take in its last step the largest
distance from the origin to a point of the *sliced* polytope, eq. (16): e.g. the largest
translation at zero rotation.  For a generator matrix G (d × L) and the slice that keeps
the output coordinates S and sets the k others (S^c) to zero, every vertex of
``{G_S p : |p|∞ <= 1, G_{S^c} p = 0}`` has at least L − k actuators at a limit
(docs/design.md §6).  So with F the k free actuators and X the others,

.. math::  p_F = -K p_X,\\quad K = (G_{S^c,F})^{-1} G_{S^c,X},\\qquad
           u = (G_{S,X} - G_{S,F} K)\\, p_X,

over the C(L, k) sets F and the 2^(L−k) sign vectors p_X (half of them, the set being
symmetric), kept when ``|p_F|∞ <= 1``.  This is the vertex enumeration of
:func:`distkin.indices.zonotope.zonotope_best` specialised to symmetric unit limits and
k = 3, compiled by numba.  The generic kernel walks the sign vectors in Gray-code
order (about 1.6 µs per pose and slice for L = 6 and 13 µs for L = 8, against 22 and
180 µs for the numpy route).  For L = 8 (d = 6) a second kernel splits the five signs
as (+1, s1, s2) × (s3, s4), so that ``K s`` and ``E s`` are sums of 4 + 4 partial
sums, with every branch a select and 64 poses evaluated together, pose the innermost
loop, so that the compiler evaluates four poses per vector instruction
(:mod:`.slice_lanes`): about 1.1 µs per pose and slice, the same candidates, results
equal to the walk's to a few 1e-15 relative (the sums are associated differently);
for L = 6 the same kernel with three signs (+1, s1, s2): about 0.23 µs per pose and
slice against 1.9 µs for the walk.  The slab route of a square Jacobian
(:func:`slab_farthest_unit`) runs over blocks of 64 poses too, with the arithmetic of
the pose-by-pose enumeration (the same bits; 1.4 against 1.9 µs per slice).
The Table II study evaluates four sensitivities at
9 million poses per redundant device.

The three removed rows are first replaced by an orthonormal basis of their row space
(:mod:`.constraint_basis`, about 0.1 µs per pose and slice): the slice is the same, and
the test that skips a singular 3 × 3 block F (its vertices are found from other sets)
no longer depends on how the rows are scaled.  A pose whose removed rows have rank
below 3 (e.g. the zero torque row of a wrench map at a singularity) is enumerated
with fewer free actuators by :func:`.zonotope.farthest_in_slice`.  Exact up to
rounding; an empty slice gives −inf (never, with unit limits).  The test
``|p_F| <= 1`` allows the rounding error of ``K p_X`` (64 eps times the row sums of
|K| and the Hadamard ratio of the block), so that near a singularity, where J# is
huge, the vertices on the boundary are not lost to rounding.
"""

from __future__ import annotations

from functools import lru_cache
from itertools import combinations

import numpy as np

from .slice_lanes import slice_farthest_lanes
from .constraint_basis import constraint_basis
from ..errors import InputError
from .zonotope import RANK_TOL, check_enumeration, farthest_in_slice, vertex_candidates

__all__ = ["slice_farthest_unit", "slab_farthest_unit"]

#: feasibility slack of |p_F| <= 1, as zonotope._best_chunk, plus the rounding of K p
_TOL = 1e-12
_EPS = 2.220446049250313e-16


@lru_cache(maxsize=None)
def _tables(L: int, k: int):
    """Free sets F, their complements X, and a Gray-code walk over half the sign vectors
    of X (first sign +1): the start vector and, per step, the index that flips."""
    F = np.array(list(combinations(range(L), k)), dtype=np.int64)
    X = np.array([[i for i in range(L) if i not in f] for f in F], dtype=np.int64)
    m = L - k
    flips = np.array([int(np.log2(((g ^ (g >> 1)) ^ ((g - 1) ^ ((g - 1) >> 1)))))
                      for g in range(1, 2 ** (m - 1))], dtype=np.int64) + 1
    return F, X, flips


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True)
    def run(G, S, Sc, F, X, flips, out):                    # pragma: no cover (compiled)
        N = G.shape[0]
        nF, m = X.shape
        nS = S.shape[0]
        a = np.empty((3, 3))
        inv = np.empty((3, 3))
        K = np.empty((3, m))
        E = np.empty((nS, m))
        p = np.empty(3)
        slack = np.empty(3)
        u = np.empty(nS)
        sg = np.empty(m)
        for n in range(N):
            best = -1.0
            for f in range(nF):
                for i in range(3):
                    for j in range(3):
                        a[i, j] = G[n, Sc[i], F[f, j]]
                c00 = a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]
                c01 = a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]
                c02 = a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]
                det = a[0, 0] * c00 + a[0, 1] * c01 + a[0, 2] * c02
                scale = 1.0
                for j in range(3):
                    scale *= np.sqrt(a[0, j] ** 2 + a[1, j] ** 2 + a[2, j] ** 2)
                if not abs(det) > 1e-12 * scale:
                    continue
                cond = scale / abs(det)            # Hadamard ratio, >= 1
                inv[0, 0] = c00 / det
                inv[1, 0] = c01 / det
                inv[2, 0] = c02 / det
                inv[0, 1] = (a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]) / det
                inv[1, 1] = (a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]) / det
                inv[2, 1] = (a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]) / det
                inv[0, 2] = (a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]) / det
                inv[1, 2] = (a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]) / det
                inv[2, 2] = (a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]) / det
                for i in range(3):
                    ka = 0.0
                    for j in range(m):
                        s = 0.0
                        for r in range(3):
                            s += inv[i, r] * G[n, Sc[r], X[f, j]]
                        K[i, j] = s
                        ka += abs(s)
                    # |p_F| <= 1 up to the rounding of K p (and of K itself, whose
                    # relative error grows with the conditioning of the 3 x 3 block)
                    slack[i] = 1.0 + _TOL + 64.0 * _EPS * (1.0 + ka) * (1.0 + cond)
                for i in range(nS):
                    for j in range(m):
                        s = G[n, S[i], X[f, j]]
                        for r in range(3):
                            s -= G[n, S[i], F[f, r]] * K[r, j]
                        E[i, j] = s
                # start at the all-ones sign vector; p_F = -K s, u = E s
                for j in range(m):
                    sg[j] = 1.0
                for i in range(3):
                    s = 0.0
                    for j in range(m):
                        s -= K[i, j]
                    p[i] = s
                for i in range(nS):
                    s = 0.0
                    for j in range(m):
                        s += E[i, j]
                    u[i] = s
                for v in range(flips.shape[0] + 1):
                    if v > 0:                      # Gray step: flip one sign
                        j = flips[v - 1]
                        d = -2.0 * sg[j]
                        sg[j] = -sg[j]
                        for i in range(3):
                            p[i] -= d * K[i, j]
                        for i in range(nS):
                            u[i] += d * E[i, j]
                    if abs(p[0]) > slack[0] or abs(p[1]) > slack[1] or abs(p[2]) > slack[2]:
                        continue
                    nrm = 0.0
                    for i in range(nS):
                        nrm += u[i] * u[i]
                    if nrm > best:
                        best = nrm
            out[n] = np.sqrt(best) if best >= 0 else -np.inf
    return run


def slice_farthest_unit(G, keep, *, walk: bool = False, transposed: bool = False):
    """Largest ``||G_S p||`` over ``|p|∞ <= 1`` with ``G_{S^c} p = 0`` (eq. (16) after the
    slice of eq. (14)), for slices that remove exactly three coordinates.

    Parameters
    ----------
    G : ndarray (N, d, L)
        Generator matrices (e.g. J# or Jᵀ of eqs. (5)-(6)), L >= 3.
    keep : sequence of int
        The d − 3 kept output coordinates S (e.g. (0, 1, 2): translation at zero
        rotation).
    walk : bool
        Force the Gray-code walk over the sign vectors (the generic kernel, used for
        L = 7 and kept as the reference of the split-sign kernel for L = 6 and 8).
    transposed : bool
        G is given as its transpose (N, L, d) (e.g. J for Jᵀ): read in place by the
        split-sign kernel, copied for the walk.

    Returns
    -------
    ndarray (N,)
        In the output unit per unit actuator quantity.
    """
    G = np.ascontiguousarray(G, dtype=float)
    if transposed:
        N, L, d = G.shape
    else:
        N, d, L = G.shape
    S = np.array(sorted(int(k) for k in keep), dtype=np.int64)
    Sc = np.array([i for i in range(d) if i not in set(S.tolist())], dtype=np.int64)
    if len(Sc) != 3:
        raise InputError(f"expected a slice removing 3 of {d} coordinates, got "
                         f"keep={list(keep)}", field="keep")
    check_enumeration(vertex_candidates(L, 3), L,
                      "slice-vertex candidates (C(L, 3)·2^(L−3))", field="J")
    F, X, flips = _tables(L, 3)
    out = np.empty(N)
    if not N:
        return out
    # the constraint rows by an orthonormal basis of their row space (.constraint_basis):
    # the singular-block test of the kernels is then independent of how the rows are
    # scaled; a constraint of rank < 3 is enumerated in numpy afterwards
    G, rank = constraint_basis(G, Sc, tol=RANK_TOL, transposed=transposed)
    if L in (6, 8) and d == 6 and not walk:
        slice_farthest_lanes(G, S, Sc, F, X, out, transposed)
    else:
        Gk = np.ascontiguousarray(np.swapaxes(G, 1, 2)) if transposed else G
        _kernel()(Gk, S, Sc, F, X, flips, out)
    low = np.flatnonzero(rank < 3)
    if len(low):
        Gl = np.swapaxes(G[low], 1, 2) if transposed else G[low]
        out[low] = farthest_in_slice(Gl[:, S, :], Gl[:, Sc, :], rank[low],
                                     np.zeros((len(low), L)), np.ones((len(low), L)))
    return out


#: poses per block of the slab kernel
_SLAB_LANES = 64


@lru_cache(maxsize=1)
def _slab_kernel():
    import numba

    @numba.njit(cache=True, error_model="numpy")
    def run(A, T, out, W):                                  # pragma: no cover (compiled)
        """Over blocks of W poses, pose the innermost loop (SIMD across poses; a
        triple whose 3 × 3 block is singular in a pose makes its candidates infeasible
        there instead of being skipped): the same arithmetic as the pose-by-pose
        enumeration, so the same bits."""
        N, L, _ = A.shape
        a = np.empty((L, 3, W))
        V = np.empty((8, 3, W))
        Cf = np.empty((9, W))
        dt = np.empty(W)
        gd = np.empty(W, np.bool_)
        ok = np.empty((8, W), np.bool_)
        best = np.empty(W)
        for n0 in range(0, N, W):
            for i in range(L):
                for k in range(3):
                    for w in range(W):
                        a[i, k, w] = A[min(n0 + w, N - 1), i, k]
            for w in range(W):
                best[w] = -1.0
            for t in range(T.shape[0]):
                i0, i1, i2 = T[t, 0], T[t, 1], T[t, 2]
                for w in range(W):
                    a00, a01, a02 = a[i0, 0, w], a[i0, 1, w], a[i0, 2, w]
                    a10, a11, a12 = a[i1, 0, w], a[i1, 1, w], a[i1, 2, w]
                    a20, a21, a22 = a[i2, 0, w], a[i2, 1, w], a[i2, 2, w]
                    c00 = a11 * a22 - a12 * a21
                    c01 = a12 * a20 - a10 * a22
                    c02 = a10 * a21 - a11 * a20
                    det = a00 * c00 + a01 * c01 + a02 * c02
                    scale = (np.sqrt(a00 ** 2 + a01 ** 2 + a02 ** 2)
                             * np.sqrt(a10 ** 2 + a11 ** 2 + a12 ** 2)
                             * np.sqrt(a20 ** 2 + a21 ** 2 + a22 ** 2))
                    Cf[0, w], Cf[1, w], Cf[2, w] = c00, a02 * a21 - a01 * a22, \
                        a01 * a12 - a02 * a11
                    Cf[3, w], Cf[4, w], Cf[5, w] = c01, a00 * a22 - a02 * a20, \
                        a02 * a10 - a00 * a12
                    Cf[6, w], Cf[7, w], Cf[8, w] = c02, a01 * a20 - a00 * a21, \
                        a00 * a11 - a01 * a10
                    dt[w] = det
                    gd[w] = abs(det) > 1e-12 * scale
                for sg in range(8):
                    s0 = 1.0 if sg & 1 else -1.0
                    s1 = 1.0 if sg & 2 else -1.0
                    s2 = 1.0 if sg & 4 else -1.0
                    for w in range(W):
                        # v = A_T^-1 s by the adjugate (rows of the inverse: cofactors)
                        V[sg, 0, w] = (Cf[0, w] * s0 + Cf[1, w] * s1 + Cf[2, w] * s2) / dt[w]
                        V[sg, 1, w] = (Cf[3, w] * s0 + Cf[4, w] * s1 + Cf[5, w] * s2) / dt[w]
                        V[sg, 2, w] = (Cf[6, w] * s0 + Cf[7, w] * s1 + Cf[8, w] * s2) / dt[w]
                        ok[sg, w] = gd[w]
                for i in range(L):
                    for sg in range(8):
                        for w in range(W):
                            b0, b1, b2 = a[i, 0, w], a[i, 1, w], a[i, 2, w]
                            v0, v1, v2 = V[sg, 0, w], V[sg, 1, w], V[sg, 2, w]
                            r = b0 * v0 + b1 * v1 + b2 * v2
                            ra = abs(b0 * v0) + abs(b1 * v1) + abs(b2 * v2)
                            ok[sg, w] = ok[sg, w] & (abs(r) <= 1.0 + _TOL + 64.0 * _EPS
                                                     * (1.0 + ra))
                for sg in range(8):
                    for w in range(W):
                        v0, v1, v2 = V[sg, 0, w], V[sg, 1, w], V[sg, 2, w]
                        nrm = v0 * v0 + v1 * v1 + v2 * v2
                        best[w] = nrm if ok[sg, w] & (nrm > best[w]) else best[w]
            for w in range(min(W, N - n0)):
                out[n0 + w] = np.sqrt(best[w]) if best[w] >= 0 else -np.inf
    return run


def slab_farthest_unit(A):
    """Largest ``||v||`` over the polytope ``{v : |A v|∞ <= 1}`` (3 columns), batched.

    For a square Jacobian (L = d) the slice ``{J⁻¹ p : |p|∞ <= 1, (J⁻¹ p)_{S^c} = 0}``
    of eq. (5)'s zonotope is exactly ``{u : |J_S u|∞ <= 1}`` with J_S the columns S of
    J, so its farthest point (the paper's maximum translational or rotational
    sensitivity) is a vertex where three slab planes meet: C(L, 3)·8 candidates, 3 × 3
    solves on rows of J itself.  Unlike the route through J⁻¹ this keeps its accuracy
    next to a singularity, where J⁻¹ is huge and the slice of its zonotope is found by
    cancellation.

    Parameters
    ----------
    A : ndarray (N, L, 3)

    Returns
    -------
    ndarray (N,)
        +inf where no vertex exists: the polytope holds the origin, so it is then
        unbounded (A of rank < 3, or every 3 × 3 block of A singular to 1e-12: the
        singular twist of a square Jacobian, where J⁻¹ does not exist).
    """
    A = np.ascontiguousarray(A, dtype=float)
    N, L, k = A.shape
    if k != 3:
        raise ValueError(f"expected A of shape (N, L, 3), got {A.shape}")
    T = np.array(list(combinations(range(L), 3)), dtype=np.int64)
    out = np.empty(N)
    if N:
        _slab_kernel()(A, T, out, _SLAB_LANES)
    out[out == -np.inf] = np.inf                   # no vertex: unbounded (docstring)
    return out
