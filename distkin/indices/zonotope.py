"""The exact zonotope half-space kernel for output capabilities (docs/design.md §6).

The set of outputs ``{G p : pmin <= p <= pmax}`` of a generator matrix ``G`` (d × L)
is a zonotope.  Its facet normals are the vectors orthogonal to (d−1)-subsets of the
generators, 2·C(L, d−1) of them, and the offset of normal ``n`` is its support value

.. math::  h(n) = \\sum_i \\max(n\\cdot g_i\\, p_{max,i},\\; n\\cdot g_i\\, p_{min,i}).

The worst case inside a coordinate slice ``S`` (e.g. force at zero torque) is therefore
``min_n h(n) / ||P_S n||``, with no convex hull (Kühne et al., eqs. (9)-(15), solved
without Qhull).  With midpoint ``c`` and half-range ``r`` of the limits both signs of a
normal are handled at once: ``min(h(n), h(-n)) = Σ|n·g_i| r_i − |n·G c|``.

Normals are built cheaply: pick a well-conditioned d × d block ``B`` of the generators
by pivoted Gram-Schmidt, write ``B⁻¹G = [I | C]``; every (d−1)-subset with ``m``
columns of ``C`` has a normal supported on ``m + 1`` coordinates, the generalised
cross product of those ``m`` columns (1-sparse, 2-sparse, 3-index cross products for
m = 0, 1, 2; small determinants beyond).  The normal in output space is ``B⁻ᵀ n'``.
For L = d this reduces to Ueberle's method [2].

The farthest point (best case, maximum sensitivities [3]) is a box vertex for the full
set; for a slice with ``k`` removed coordinates every vertex of
``{p in box : G_{S^c} p = 0}`` has at least L − k actuators at a limit, so the
C(L, k)·2^(L−k) candidates with k × k solves are enumerated exactly.

Edge cases (docs/design.md §6):

* origin outside the set (limits that do not straddle 0): the value is **negative**; it
  is then a flag, and ``|value|`` is only a lower bound of the distance to the set;
* a generator matrix with σmin/σmax below ``rank_tol`` is treated as exactly singular:
  the set is flat, the worst case is 0 for every slice that the flat set does not
  contain, and for a slice inside its span (the pure-torque null wrench seen from the
  force slice) the facets are computed within the span, so the answer stays finite and
  correct instead of the ∞ the plain formula gives;
* the best case of a slice works on an orthonormal basis of the removed rows
  (:mod:`.constraint_basis`), whose rank is decided with the same ``rank_tol``: a
  removed row that is zero (or below it) is no constraint, so the slice is the one of
  the other rows, not empty.

References
----------
.. [1] M. Kühne, J. Potzy, R. García-Rochín, P. van der Smagt, A. Peer, "Design and
   Evaluation of a Haptic Interface With Octopod Kinematics", IEEE/ASME Trans.
   Mechatronics, Sec. II-C-3, eqs. (8)-(16).
.. [2] M. Ueberle, "Design, control, and evaluation of a family of kinesthetic haptic
   interfaces", PhD thesis, TU München, 2006.
.. [3] P. Cardou, S. Bouchard, C. Gosselin, "Kinematic-sensitivity indices for
   dimensionally nonhomogeneous Jacobian matrices", IEEE Trans. Robotics 26(1), 2010.
"""

from __future__ import annotations

from contextlib import contextmanager
from functools import lru_cache
from itertools import combinations, product

import numpy as np

from ..errors import InputError, warn as _warn
from .constraint_basis import constraint_basis

__all__ = ["zonotope_worst", "zonotope_best", "facet_normals", "farthest_in_slice",
           "RANK_TOL", "MAX_CANDIDATES", "check_enumeration", "vertex_candidates",
           "memory_guard", "generator_batch", "flat_tol"]

#: σmin/σmax below which a generator matrix is treated as singular
RANK_TOL = 1e-12


def flat_tol(d: int, L: int) -> float:
    """σmin/σmax at or below which a float64 generator matrix is indistinguishable from
    an exactly rank-deficient one (its distance to rank deficiency is within the
    rounding of its entries, 4·eps·sqrt(d·L)): the flat set's values are then the
    answer.  Between this and :data:`RANK_TOL` the pose is near-flat: values that the
    flat route would return for a slice inside the span are not those of the
    (non-flat) set and are flagged (NaN + :class:`~distkin.errors.ConditioningWarning`,
    QA Z2 1)."""
    return 4.0 * np.finfo(float).eps * float(np.sqrt(d * L))

#: the most facet normals (C(L, d−1)), box vertices (2^L) or slice-vertex candidates
#: (C(L, k)·2^(L−k)) a kernel enumerates per pose: 2^18 = 262,144, about 0.05-0.5 s and
#: at most a few hundred MB per pose.  L = 8, d = 6 needs 56 normals, 256 vertices and
#: 1,792 candidates; the limit allows L <= 33 for the worst case (d = 6), L <= 18 for the
#: best case of the whole set and L <= 12 for the slices of the sensitivities
MAX_CANDIDATES = 2 ** 18

#: float64 elements of the temporaries of one batch of poses (128 MiB): a batch is cut
#: to fit, so a large L runs one pose at a time instead of exhausting the memory (the
#: default batch is unchanged up to L = 8)
_BATCH_ELEMENTS = 2 ** 24


def vertex_candidates(L: int, k: int) -> int:
    """C(L, k)·2^(L−k): the vertex candidates of a slice removing k coordinates (k = 0:
    the 2^L box vertices)."""
    from math import comb
    return comb(L, k) * 2 ** (L - k)


def check_enumeration(count: int, L: int, what: str, field: str = "G",
                      limit: int | None = None) -> int:
    """``count`` (per pose) against :data:`MAX_CANDIDATES` (or ``limit``), counted
    before anything is allocated: above it an :class:`InputError` names L and the
    cost.  Returns ``count``."""
    limit = MAX_CANDIDATES if limit is None else limit
    if count > limit:
        raise InputError(f"expected at most {limit:,} {what} per pose, got {count:,} for "
                         f"L = {L} actuators", field=field,
                         hint="fewer actuators (this exact enumeration grows "
                              "combinatorially with L), or a bound from a relaxation")
    return count


@contextmanager
def memory_guard(L: int, what: str, field: str = "G"):
    """Turn a MemoryError of an enumeration into an :class:`InputError` naming L and
    what was enumerated (the limits above keep it rare; it must never escape raw)."""
    try:
        yield
    except MemoryError:
        raise InputError(f"expected the {what} for L = {L} actuators to fit in memory, got "
                         "a MemoryError", field=field,
                         hint="fewer actuators or fewer poses per call") from None


def _batch(chunk: int, per_pose: int) -> int:
    """Poses per batch: ``chunk``, cut so the temporaries (``per_pose`` elements each)
    stay within :data:`_BATCH_ELEMENTS`."""
    return max(1, min(max(1, int(chunk)), _BATCH_ELEMENTS // max(1, per_pose)))


# --------------------------------------------------------------------------- normals
@lru_cache(maxsize=None)
def _groups(d: int, L: int):
    """Index structure of the (d−1)-subsets of ``[I | C]``: a tuple of
    ``(m, cset (m,), rows (nR, m+1))``, C(L, d−1) normals in all."""
    out = []
    for m in range(0, min(L - d, d - 1) + 1):
        rows = np.array(list(combinations(range(d), m + 1)), dtype=np.intp)
        for cset in combinations(range(L - d), m):
            out.append((m, np.array(cset, dtype=np.intp), rows))
    return tuple(out)


def _cross(M):
    """Generalised cross product of the m columns of ``M`` (..., m+1, m): the vector
    of signed m × m minors, orthogonal to every column."""
    m = M.shape[-1]
    if m == 0:
        return np.ones(M.shape[:-1])
    if m == 1:
        return np.stack([M[..., 1, 0], -M[..., 0, 0]], axis=-1)
    if m == 2:
        return np.cross(M[..., 0], M[..., 1])
    comps = []
    for j in range(m + 1):
        minor = np.delete(M, j, axis=-2)
        comps.append((-1) ** j * np.linalg.det(minor))
    return np.stack(comps, axis=-1)


def _pivot(G):
    """Column permutation (N, L) putting a well-conditioned d × d block first, and the
    rank indicator min/max of the pivots of modified Gram-Schmidt (≈ σmin/σmax)."""
    N, d, L = G.shape
    R = np.array(G, dtype=float, copy=True)
    perm = np.broadcast_to(np.arange(L), (N, L)).copy()
    ar = np.arange(N)
    piv = np.empty((N, d))
    for k in range(d):
        norms = np.einsum("ndl,ndl->nl", R[:, :, k:], R[:, :, k:])
        j = k + np.argmax(norms, axis=1)
        # swap columns k and j
        colk, colj = R[ar, :, k].copy(), R[ar, :, j].copy()
        R[ar, :, k], R[ar, :, j] = colj, colk
        pk, pj = perm[ar, k].copy(), perm[ar, j].copy()
        perm[ar, k], perm[ar, j] = pj, pk
        nk = np.sqrt(np.einsum("nd,nd->n", R[:, :, k], R[:, :, k]))
        piv[:, k] = nk
        q = np.divide(R[:, :, k], nk[:, None], out=np.zeros((N, d)), where=nk[:, None] > 0)
        if k + 1 < L:
            proj = np.einsum("nd,ndl->nl", q, R[:, :, k + 1:])
            R[:, :, k + 1:] -= q[:, :, None] * proj[:, None, :]
    top = piv[:, 0]
    ratio = np.divide(piv.min(axis=1), top, out=np.zeros(N), where=top > 0)
    return perm, ratio


def _facets(G, c, r, *, assume_regular: bool = False):
    """Facet normals and both-sign offsets of the zonotope ``G·box``.

    Returns ``n`` (N, K, d) (one normal of each ± pair, K = C(L, d−1), unnormalised),
    ``hmin`` (N, K) = min(h(n), h(−n)) = Σ|n·g_i| r_i − |n·G c|, and ``regular`` (N,)
    (False where σmin/σmax < :data:`RANK_TOL`: use the flat route).

    Everything is elementwise on gathered rows: the normal of a subset with ``m``
    columns of C on rows R is ``n = Σ_j v_j B⁻ᵀe_{R_j}`` (rows of B⁻¹), and
    ``n·g = v·[I | C]_R``.
    """
    N, d, L = G.shape
    if L == d:
        perm = np.broadcast_to(np.arange(L), (N, L))
        ratio = np.ones(N) if assume_regular else _pivot(G)[1]
        Gp, cp, rp = G, c, r
    else:
        perm, ratio = _pivot(G)
        if assume_regular:
            ratio = np.ones(N)
        Gp = np.take_along_axis(G, perm[:, None, :], axis=2)
        cp = np.take_along_axis(c, perm, axis=1)
        rp = np.take_along_axis(r, perm, axis=1)
    regular = ratio > RANK_TOL
    B = Gp[:, :, :d].copy()
    B[~regular] = np.eye(d)
    Binv = np.linalg.inv(B)
    Cm = np.einsum("nij,njl->nil", Binv, Gp[:, :, d:]) if L > d else None
    ns, hs = [], []
    for m, cset, rows in _groups(d, L):
        nR = len(rows)
        if m == 0:
            k = rows[:, 0]
            ns.append(Binv[:, k, :])
            h = rp[:, k]
            t = cp[:, k]
            if L > d:
                PC = Cm[:, k, :]                                  # (N, nR, L-d)
                h = h + np.einsum("nkl,nl->nk", np.abs(PC), rp[:, d:])
                t = t + np.einsum("nkl,nl->nk", PC, cp[:, d:])
            hs.append(h - np.abs(t))
            continue
        M = Cm[:, :, cset][:, rows, :]                            # (N, nR, m+1, m)
        v = _cross(M)                                             # (N, nR, m+1)
        n = np.zeros((N, nR, d))
        PC = np.zeros((N, nR, L - d))
        h = np.zeros((N, nR))
        t = np.zeros((N, nR))
        for j in range(m + 1):
            vj = v[..., j]
            Rj = rows[:, j]
            n += vj[..., None] * Binv[:, Rj, :]
            PC += vj[..., None] * Cm[:, Rj, :]
            h += np.abs(vj) * rp[:, Rj]
            t += vj * cp[:, Rj]
        h += np.einsum("nkl,nl->nk", np.abs(PC), rp[:, d:])
        t += np.einsum("nkl,nl->nk", PC, cp[:, d:])
        ns.append(n)
        hs.append(h - np.abs(t))
    return np.concatenate(ns, axis=1), np.concatenate(hs, axis=1), regular


def facet_normals(G, *, assume_regular: bool = False):
    """Facet normals of the zonotope ``G·box`` (docs/design.md §6, item 1).

    Parameters
    ----------
    G : ndarray (d, L) or (N, d, L)
        Generator matrices, finite, L >= d, C(L, d−1) <= :data:`MAX_CANDIDATES`.

    Returns
    -------
    n : ndarray (N, K, d) (or (K, d) for one G)
        One normal of each ± pair, K = C(L, d−1), not normalised (scale is irrelevant
        to every ratio used here).
    P : ndarray (N, K, L) (or (K, L))
        ``n · g_i`` for every generator.
    regular : ndarray (N,) bool (or a bool)
        False where σmin/σmax of G is below :data:`RANK_TOL` (use the flat route).

    Raises
    ------
    InputError
        G not numbers of shape (d, L) or (N, d, L), not finite, L < d, or too many
        facets (:func:`check_enumeration`).
    """
    from math import comb

    G, single = generator_batch(G, "generators")
    N, d, L = G.shape
    check_enumeration(comb(L, d - 1), L, f"facet normals (C(L, d−1), d = {d})")
    n, _, regular = _facets(G, np.zeros((N, L)), np.ones((N, L)),
                            assume_regular=assume_regular)
    P = n @ G
    return (n[0], P[0], bool(regular[0])) if single else (n, P, regular)


def generator_batch(G, what: str = "generators"):
    """``G`` (d, L) or (N, d, L) as a finite float array (N, d, L) with L >= d, and
    whether it was one matrix; InputError naming ``G`` otherwise (``what``: the name of
    its columns in the message)."""
    from ..argcheck import as_floats
    G = as_floats(G, "G", "a numeric generator matrix")
    single = G.ndim == 2
    if single:
        G = G[None]
    if G.ndim != 3 or G.shape[1] < 1:
        raise InputError(f"expected G of shape (d, L) or (N, d, L), got {np.shape(G)}",
                         field="G")
    _, d, L = G.shape
    if L < d:
        raise InputError(f"expected at least as many {what} as outputs (L >= d), got "
                         f"L={L}, d={d}", field="G")
    if not np.all(np.isfinite(G)):
        raise InputError("expected finite numbers in G, got NaN or inf", field="G")
    return G, single


# ------------------------------------------------------------------------ worst case
def _ratio_min(h, nS):
    """min over normals of h / ||n_S|| with the conventions for n_S = 0 (vacuous when
    h >= 0, an empty slice when h < 0)."""
    den = np.sqrt(np.einsum("nks,nks->nk", nS, nS))
    scale = np.sqrt(np.einsum("nks,nks->n", nS, nS))[:, None] + 1e-300
    zero = den <= 1e-15 * scale
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(zero, np.where(h >= 0, np.inf, -np.inf), h / np.where(zero, 1.0, den))
    return q.min(axis=1)


def zonotope_worst(G, c, r, keeps, *, chunk: int = 4096):
    """Signed distance from the origin to the boundary of each slice of ``G·box``.

    Parameters
    ----------
    G : ndarray (N, d, L)
    c, r : ndarray (N, L)
        Midpoint and half-range of the limits (r >= 0).
    keeps : sequence of index tuples
        Output coordinates kept in each slice (``tuple(range(d))`` = whole set).

    chunk : int
        Poses per facet computation: the temporaries (about 10 KiB per pose for
        L = 8, d = 6) are bounded by the chunk, not by N.

    Returns
    -------
    ndarray (len(keeps), N)
        Distance (origin inside) or a negative flag (origin outside).  NaN (with one
        :class:`~distkin.errors.ConditioningWarning` naming the count) for a slice
        inside the span of a near-flat G (:func:`flat_tol` < σmin/σmax <=
        :data:`RANK_TOL`): there the flat set's finite value is not the limit of the
        set's (QA Z2 1) and float64 cannot compute the latter.
    """
    from math import comb
    G = np.asarray(G, dtype=float)
    N, d, L = G.shape
    K = check_enumeration(comb(L, d - 1), L, f"facet normals (C(L, d−1), d = {d})")
    out = np.empty((len(keeps), N))
    step = _batch(chunk, K * (d + 2 * L))
    near = 0
    tol = flat_tol(d, L)
    for lo in range(0, N, step):
        sl = slice(lo, min(N, lo + step))
        n, h, regular = _facets(G[sl], c[sl], r[sl])
        for a, S in enumerate(keeps):
            out[a, sl] = _ratio_min(h, n[:, :, list(S)])
        for j in np.flatnonzero(~regular):
            i = lo + j
            exact = _pivot(G[i:i + 1])[1][0] <= tol       # the ratio _facets tested
            out[:, i] = _flat_worst(G[i], c[i], r[i], keeps, exact=exact)
            near += bool(np.isnan(out[:, i]).any())
    if near:
        from ..errors import ConditioningWarning
        _warn(ConditioningWarning(
            f"worst-case output: {near} of {N} pose(s) with a near-flat generator matrix "
            f"({tol:.2g} < σmin/σmax <= RANK_TOL = {RANK_TOL:g}) and a slice inside its "
            "span: NaN returned there (the flat set's value is not the set's, and float64 "
            "cannot compute the latter)"))
    return out


def _flat_worst(G, c, r, keeps, exact: bool = True):
    """The rank-deficient pose: facets inside the span of G, and the equality
    constraints of its orthogonal complement (docs/design.md §6, edge cases).

    ``exact`` False (a near-flat G, :func:`flat_tol` < σmin/σmax <= RANK_TOL): a slice
    inside the span gives NaN, not the flat value (the set is thin, not flat, and its
    slice's distance differs from the flat one's, QA Z2 1); a slice leaving the span
    keeps 0, within κ·||G||·max r of the set's value."""
    d, L = G.shape
    U, s, _ = np.linalg.svd(G)
    rank = int(np.sum(s > RANK_TOL * s[0])) if s[0] > 0 else 0
    res = np.empty(len(keeps))
    W = U[:, rank:]                                            # null directions (d, d-rank)
    if rank == 0:                                              # the set is {0}
        return np.zeros(len(keeps))
    if rank == d:
        nn, h, _ = _facets(G[None], c[None], r[None], assume_regular=True)
    else:
        Ur = U[:, :rank]
        nr, h, _ = _facets((Ur.T @ G)[None], c[None], r[None], assume_regular=True)
        nn = nr @ Ur.T                                         # back to output space
    whole = _ratio_min(h, nn)[0]          # < 0: the origin lies outside the flat set
    for a, S in enumerate(keeps):
        S = list(S)
        if rank < d and np.linalg.norm(W[S, :]) > 1e-9:
            # the slice leaves the span of G (which holds the origin): the sliced set
            # is lower-dimensional in R^|S|, its boundary passes through the origin
            res[a] = 0.0 if whole >= 0 else whole
            continue
        res[a] = _ratio_min(h, nn[:, :, S])[0] if exact or rank == d else np.nan
    return res


# ------------------------------------------------------------------------- best case
@lru_cache(maxsize=None)
def _signs(n: int):
    return np.array(list(product((-1.0, 1.0), repeat=n))).T if n else np.zeros((0, 1))


def zonotope_best(G, c, r, keeps, *, chunk: int = 4096):
    """Largest distance from the origin to a point of each slice of ``G·box`` (the
    farthest point; Kühne et al. eq. (16), Cardou et al. [3]).

    Full set: the 2^L box vertices.  Slice with k removed coordinates: the
    C(L, k)·2^(L−k) vertex candidates with L − k actuators at a limit, solved by k × k
    systems and kept when the free actuators lie within their limits, on an orthonormal
    basis of the row space of ``G_{S^c}`` (:mod:`.constraint_basis`: the result does
    not depend on how those rows are scaled or mixed; a basis of rank k' < k, e.g. the
    zero torque row of a wrench map at a singularity, enumerates C(L, k')·2^(L−k')
    candidates).  Exact up to rounding; an empty slice gives −inf.

    Returns ndarray (len(keeps), N).
    """
    G = np.asarray(G, dtype=float)
    N, d, L = G.shape
    out = np.empty((len(keeps), N))
    for a, S in enumerate(keeps):
        k = d - len(set(S))
        check_enumeration(vertex_candidates(L, k), L,
                          "box vertices (2^L)" if k == 0 else
                          f"slice-vertex candidates (C(L, {k})·2^(L−{k}))")
        step = _batch(chunk, 2 ** (L - k) * (d + L))
        for lo in range(0, N, step):
            sl = slice(lo, min(N, lo + step))
            out[a, sl] = _best_chunk(G[sl], c[sl], r[sl], tuple(S))
    return out


def farthest_in_slice(GS, Q, rank, c, r):
    """The farthest point of ``{G_S p : p in box, Q p = 0}`` at each pose, with ``Q``
    (N, k, L) and ``rank`` from :func:`.constraint_basis.constraint_basis` (a rank below
    k enumerates fewer free actuators; rank 0 is the box vertices)."""
    best = np.empty(GS.shape[0])
    for kk in np.unique(rank):
        idx = np.flatnonzero(rank == kk)
        best[idx] = (_box_farthest(GS[idx], c[idx], r[idx]) if kk == 0 else
                     _vertex_farthest(GS[idx], Q[idx, :kk], c[idx], r[idx]))
    return best


def _box_farthest(GS, c, r):
    """max over the 2^L box vertices of ||G_S p||."""
    N, _, L = GS.shape
    # u = G c + (G r) S over the sign matrix S: one large GEMM, not N small ones
    Gr = (GS * r[:, None, :]).reshape(-1, L)
    u = (Gr @ _signs(L)).reshape(N, GS.shape[1], -1)
    u += np.einsum("nsl,nl->ns", GS, c)[:, :, None]
    return np.sqrt(np.einsum("nsv,nsv->nv", u, u)).max(axis=1)


def _vertex_farthest(GS, GC, c, r):
    """The C(L, k)·2^(L−k) vertex candidates with k × k solves (module docstring);
    ``GC`` (N, k, L) of full row rank, orthonormal rows preferred."""
    N, k, L = GC.shape
    best = np.full(N, -np.inf)
    sg = _signs(L - k)
    tol = 1e-12
    for F in combinations(range(L), k):
        F = list(F)
        X = [i for i in range(L) if i not in F]
        A = GC[:, :, F]                                         # (N, k, k)
        det = np.linalg.det(A)
        scaleA = np.prod(np.linalg.norm(A, axis=1), axis=1)
        ok = np.abs(det) > 1e-12 * scaleA
        A = np.where(ok[:, None, None], A, np.eye(k))
        pX = c[:, X, None] + r[:, X, None] * sg[None]            # (N, L-k, 2^(L-k))
        rhs = -GC[:, :, X] @ pX                                 # (N, k, V)
        pF = np.linalg.solve(A, rhs)                            # (N, k, V)
        lo = (c[:, F] - r[:, F])[:, :, None]
        hi = (c[:, F] + r[:, F])[:, :, None]
        slack = tol * (np.abs(c[:, F]) + r[:, F] + 1e-300)[:, :, None]
        feas = np.all((pF >= lo - slack) & (pF <= hi + slack), axis=1) & ok[:, None]
        u = GS[:, :, F] @ pF + GS[:, :, X] @ pX
        nrm = np.sqrt(np.einsum("nsv,nsv->nv", u, u))
        nrm = np.where(feas, nrm, -np.inf)
        best = np.maximum(best, nrm.max(axis=1))
    return best


def _best_chunk(G, c, r, S):
    d = G.shape[1]
    Sc = [i for i in range(d) if i not in S]
    S = list(S)
    if not Sc:
        return _box_farthest(G[:, S, :], c, r)
    Gq, rank = constraint_basis(G, Sc, tol=RANK_TOL)
    return farthest_in_slice(G[:, S, :], Gq[:, Sc, :], rank, c, r)
