"""Worst- and best-case output capabilities (Kühne et al., Sec. II-C-3, eqs. (5)-(16)).

Public entry points :func:`worst_case_output` and :func:`best_case_output` take a
generator matrix ``G`` (d × L, or batched N × d × L) and actuator limits, and return the
minimum (maximum) distance from the origin to the boundary (to a point) of the set
``{G p : pmin <= p <= pmax}``, optionally sliced to the output coordinates ``keep``.

Three algorithms (``algorithm=``, or as before ``method=``; the tier ``method`` is
"fast" only, :mod:`.tiers`) check one another:

``"zonotope"`` (production)
    The exact half-space kernel of docs/design.md §6 (:mod:`distkin.indices.zonotope`),
    batched and vectorised over poses.
``"hull"`` (reference)
    The paper's "polytope algorithm" as written: all 2^L vertices, their convex hull by
    Qhull (``scipy.spatial.ConvexHull``, eq. (13)), slicing (eq. (14)) by a half-space
    intersection, and the minimum (eq. (15)) or maximum (eq. (16)) distance.  One pose
    at a time; a few ms per pose.
``"ueberle"`` (L = d only, worst case only)
    Ueberle's least-squares problems, eqs. (10)-(12): one actuator saturated, the others
    free, optionally constrained to the slice.

:func:`output_generators` builds the generator matrices of eqs. (5)-(7) from the
Jacobian (q̇ = J ẋ, J of shape (L, 6)).
"""

from __future__ import annotations

import numpy as np

from ..argcheck import as_floats, float_array
from ..errors import InputError, SingularConfigurationError, warn as _warn
from .float_scale import pow2_exponent, scale_back
from .tiers import fast_only
from .zonotope import (RANK_TOL, check_enumeration, generator_batch, memory_guard,
                       zonotope_best, zonotope_worst)

__all__ = ["worst_case_output", "best_case_output", "output_generators",
           "hull_worst_best", "hull_multi", "ueberle_worst", "CAPABILITY_METHODS",
           "MAX_HULL_VERTICES", "NEGLIGIBLE", "UEBERLE_KAPPA"]

CAPABILITY_METHODS = ("zonotope", "hull", "ueberle")

#: the most box vertices ``method="hull"`` gives Qhull per pose (2^L; L <= 16)
MAX_HULL_VERTICES = 2 ** 16

#: ``method="hull"``: after a Qhull failure, generators with ||g_i||·(pmax−pmin)/2 at
#: most this fraction of the largest are fixed at their midpoint and Qhull retried;
#: the set then moves by at most Σ ||g_i||·(pmax−pmin)/2 of those (Hausdorff), which
#: bounds the change of the whole set's worst and best case (QA Z2 5)
NEGLIGIBLE = 1e-6


# ------------------------------------------------------------------------ arguments
def _algorithm(method, algorithm, allowed):
    """The algorithm from ``method`` (a tier, "fast", or an algorithm name as before)
    and ``algorithm`` (:mod:`.tiers`, QA Z2 7); InputError naming the field."""
    fast_only(method, "the output capability", also=allowed)
    if algorithm is None:
        return "zonotope" if method == "fast" else method
    if algorithm not in allowed:
        raise InputError(f"expected algorithm one of {', '.join(map(repr, allowed))}, "
                         f"got {algorithm!r}", field="algorithm")
    if method != "fast" and method != algorithm:
        raise InputError(f"expected method 'fast' or {algorithm!r} with algorithm="
                         f"{algorithm!r}, got method={method!r}", field="method")
    return algorithm


def _prepare(G, pmin, pmax, keep, method, allowed):
    G, single = generator_batch(G, "actuators")
    N, d, L = G.shape
    lims = []
    for name, v in (("pmin", pmin), ("pmax", pmax)):
        a = as_floats(v, name)
        try:
            a = np.broadcast_to(a, (N, L)).astype(float)
        except ValueError:
            raise InputError(f"expected a scalar, shape ({L},) or ({N}, {L}), got "
                             f"shape {a.shape}", field=name) from None
        if not np.all(np.isfinite(a)):
            raise InputError("expected finite limits, got NaN or inf", field=name)
        lims.append(a)
    lo, hi = lims
    if np.any(lo > hi):
        i = np.argwhere(lo > hi)[0]
        raise InputError(f"expected pmin <= pmax, got pmin={lo[tuple(i)]} > "
                         f"pmax={hi[tuple(i)]} at actuator {i[-1]}", field="pmin")
    S = tuple(range(d)) if keep is None else _keep_indices(keep, d)
    if method == "hull":          # Qhull on every box vertex, one pose at a time
        check_enumeration(2 ** L, L, "box vertices for Qhull (2^L)", limit=MAX_HULL_VERTICES)
    return G, lo, hi, S, single


def _keep_indices(keep, d: int, field: str = "keep") -> tuple:
    """The output coordinates of a slice: distinct integers 0..d-1 (a sequence), else
    :class:`InputError` naming ``field`` (shared with :mod:`.velocity_set`)."""
    if isinstance(keep, (str, bytes)) or any(isinstance(k, (str, bytes, bool, np.bool_))
                                             for k in np.ravel(np.asarray(keep, dtype=object))):
        raise InputError(f"expected a list of integer output indices, got {keep!r}",
                         field=field)
    try:
        S = tuple(int(k) for k in keep)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"expected a list of output indices, got {keep!r}",
                         field=field) from None
    if not S or len(set(S)) != len(S) or any(not 0 <= k < d for k in S):
        raise InputError(f"expected distinct indices in 0..{d - 1}, got {list(keep)!r}",
                         field=field)
    if any(float(k) != int(float(k)) for k in keep):
        raise InputError(f"expected integer indices, got {list(keep)!r}", field=field)
    return S


def worst_case_output(G, pmin, pmax, keep=None, method: str = "fast", *,
                      algorithm: str | None = None):
    """Worst-case output capability: the smallest distance from the origin to the
    boundary of ``{G p : pmin <= p <= pmax}`` sliced to ``keep`` (Kühne et al.,
    eqs. (9)-(15); Ueberle's eqs. (10)-(12) for L = d).

    Parameters
    ----------
    G : array_like (d, L) or (N, d, L)
        Generator matrix (eq. (8)): actuator quantity -> output, e.g. ``Jᵀ`` for the
        wrench, ``J#`` for the twist, ``M̂⁻¹Jᵀ`` for the acceleration.
    pmin, pmax : scalar, (L,) or (N, L)
        Actuator limits in the actuator unit (N·m, rad/s, ...).
    keep : sequence of int, optional
        Output coordinates of the slice (e.g. ``[0, 1, 2]``: force at zero torque).
        None: the whole set.
    method : {"fast", "zonotope", "hull", "ueberle"}
        The tier: "fast" (float64, the only one; "precise" and "certified" are refused
        with an InputError, :mod:`.tiers`).  For backward compatibility an algorithm
        name is accepted here too, as ``algorithm``.
    algorithm : {"zonotope", "hull", "ueberle"}, optional
        See the module docstring (default "zonotope").  All agree to ~1e-12 relative
        on regular poses.

    Returns
    -------
    float or ndarray (N,)
        The distance, in the output unit.  **Negative** when the origin lies outside the
        set (limits not straddling 0): a reliable flag, with ``|value|`` only a lower
        bound of the distance to the set (also when the slice misses the set).  0 at an
        exact singularity (σmin/σmax < 1e-12) unless the slice lies inside the span of
        G, where the finite in-span value is returned.

    Raises
    ------
    InputError
        Bad shapes, limits or ``keep``; ``"ueberle"`` with L != d; more than
        :data:`~.zonotope.MAX_CANDIDATES` facet normals C(L, d−1) per pose (``"hull"``:
        more than :data:`MAX_HULL_VERTICES` box vertices 2^L); limits that leave the set
        flat (``"hull"``: zero ranges, named).
    SingularConfigurationError
        ``"hull"`` only: Qhull cannot build the hull of a flat vertex set (σmin/σmax
        below about 1e-13), or of a full-dimensional one even after fixing negligible
        generators (:func:`hull_multi`; the message says which); use ``"zonotope"``.

    Notes
    -----
    Accuracy of the fast answer (``"zonotope"``): float64, relative error about
    1e-16 / κ of the pivot block of G (κ = σmin/σmax).  At :func:`~.zonotope.flat_tol`
    < κ <= :data:`~.zonotope.RANK_TOL` a slice inside the span of G is NaN with a
    ConditioningWarning (the flat set's value is not the set's, QA Z2 1); below
    ``flat_tol`` G is taken as exactly rank-deficient.  ``"ueberle"`` answers its
    singular and nearly singular poses (κ <= :data:`UEBERLE_KAPPA` = 1e-6, below which
    its least squares lose more than ~1e-12) by the zonotope kernel, with a warning.  G
    and the limits are scaled
    by powers of two into range (:mod:`.float_scale`); a result beyond float64 warns.
    Precise and certified tiers are not provided: the kernel is a min over closed-form
    ratios, and the tables it feeds are themselves sampled.
    """
    method = _algorithm(method, algorithm, CAPABILITY_METHODS)
    G, lo, hi, S, single = _prepare(G, pmin, pmax, keep, method, CAPABILITY_METHODS)
    N, d, L = G.shape
    G, lo, hi, e = _rescale(G, lo, hi)
    if method == "zonotope":
        c, r = (hi + lo) / 2, (hi - lo) / 2
        with memory_guard(L, "facet normals"):
            out = zonotope_worst(G, c, r, [S])[0]
    elif method == "hull":
        out = np.array([hull_worst_best(G[i], lo[i], hi[i], S)[0] for i in range(N)])
    else:
        if L != d:
            arg = "algorithm" if algorithm is not None else "method"
            raise InputError(f"Ueberle's method needs L = d, got L={L}, d={d}; use "
                             f"{arg}='zonotope' or 'hull'", field=arg)
        out = ueberle_worst(G, lo, hi, S)
    out = scale_back(out, e, "worst-case output")
    return float(out[0]) if single else out


def _rescale(G, lo, hi):
    """G and the limits scaled by powers of two into the float64 range of the kernels
    (:mod:`.float_scale`, exact), and the exponent of the result per pose."""
    eG = pow2_exponent(G, (1, 2))
    eP = pow2_exponent(np.concatenate([lo, hi], axis=1), 1)
    if not (eG.any() or eP.any()):
        return G, lo, hi, 0
    return (np.ldexp(G, -eG[:, None, None]), np.ldexp(lo, -eP[:, None]),
            np.ldexp(hi, -eP[:, None]), eG + eP)


def best_case_output(G, pmin, pmax, keep=None, method: str = "fast", *,
                     algorithm: str | None = None):
    """Best-case output: the largest distance from the origin to a point of the sliced
    set (the farthest point, Kühne et al. eq. (16); Cardou's maximum sensitivities with
    unit limits).

    Parameters and returns as :func:`worst_case_output`; ``algorithm`` (or, as before,
    ``method``) is ``"zonotope"`` (exact vertex enumeration: 2^L box vertices for the
    whole set, C(L,k)·2^(L−k) candidates with k × k solves for a slice removing k
    coordinates) or ``"hull"``; ``method`` is otherwise "fast", the only tier.
    ``-inf`` marks an empty slice.  Accuracy of the fast answer: float64, relative
    error about 1e-16 for the whole set (a max of vertex norms), about 1e-16 / κ of the
    removed rows' basis for a slice; inputs scaled by powers of two into range.
    """
    method = _algorithm(method, algorithm, ("zonotope", "hull"))
    G, lo, hi, S, single = _prepare(G, pmin, pmax, keep, method, ("zonotope", "hull"))
    N = G.shape[0]
    G, lo, hi, e = _rescale(G, lo, hi)
    if method == "zonotope":
        with memory_guard(G.shape[2], "vertex candidates"):
            out = zonotope_best(G, (hi + lo) / 2, (hi - lo) / 2, [S])[0]
    else:
        out = np.array([hull_worst_best(G[i], lo[i], hi[i], S)[1] for i in range(N)])
    out = scale_back(out, e, "best-case output")
    return float(out[0]) if single else out


# ---------------------------------------------------------------- the paper's method
def _box_vertices(lo, hi):
    L = len(lo)
    bits = (np.arange(2 ** L)[:, None] >> np.arange(L)[None, :]) & 1
    return np.where(bits == 1, hi[None, :], lo[None, :])      # (2^L, L)


def hull_worst_best(G, lo, hi, S):
    """The "polytope algorithm" of Kühne et al., steps (a)-(d), for one pose.

    (a) all 2^L vertices ``G p`` of the box; (b) their convex hull by Qhull, eq. (13);
    (c) the slice ``Conv(S) ∩ R^S``, eq. (14), as the intersection of the hull's
    half-spaces with the coordinate subspace (``scipy.spatial.HalfspaceIntersection``)
    followed by a second hull; (d) the minimum (eq. (15)) and maximum (eq. (16))
    distance from the origin.

    Returns ``(worst, best)`` in the output unit (worst negative if the origin lies
    outside the set).  Raises :class:`SingularConfigurationError` when Qhull fails on
    a flat set.  When Qhull fails on near-coincident vertices of a full-dimensional set,
    generators below :data:`NEGLIGIBLE` of the largest are fixed at their midpoint and
    the hull retried: the result is then that of a set within Σ ||g_i||·r_i of the
    dropped generators (Hausdorff distance), which bounds its error for the whole set.
    """
    return hull_multi(G, lo, hi, [S])[0]


def hull_multi(G, lo, hi, keeps):
    """:func:`hull_worst_best` for several slices of one pose, building the d-dimensional
    hull once; returns a list of ``(worst, best)``."""
    from scipy.spatial import QhullError
    try:
        return _hull_multi(G, lo, hi, keeps)
    except QhullError as exc:
        sv = np.linalg.svd(G, compute_uv=False)
        ratio = sv[-1] / sv[0] if sv[0] > 0 else 0.0
        # negligible generators (||g_i||·r_i <= NEGLIGIBLE of the largest) put vertices
        # within rounding of one another and Qhull fails on them (a "dupridge") on a
        # well-conditioned set (QA Z2 5): fix them at their midpoint and retry
        lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
        w = np.linalg.norm(G, axis=0) * (hi - lo) / 2
        small = w <= NEGLIGIBLE * w.max()
        if w.max() > 0 and small.any() and np.linalg.matrix_rank(G[:, ~small]) == G.shape[0]:
            shift = G[:, small] @ ((hi + lo) / 2)[small]
            try:
                return _hull_multi(G[:, ~small], lo[~small], hi[~small], keeps, shift)
            except QhullError:
                pass
        span = G[:, np.asarray(hi) > np.asarray(lo)]          # generators with a range
        rank = int(np.linalg.matrix_rank(span)) if span.size else 0
        if ratio > 1e-9 and rank < G.shape[0]:
            zero = np.flatnonzero(np.asarray(hi) <= np.asarray(lo)).tolist()
            raise InputError(
                f"expected actuator limits with pmin < pmax spanning the output space, got "
                f"pmin = pmax at actuators {zero} (values {np.asarray(lo)[zero].tolist()}): "
                f"the set is flat (rank {rank} of {G.shape[0]}), not G (σmin/σmax = "
                f"{ratio:.3g})", field="pmax",
                hint="method='zonotope' gives the flat set's values") from exc
        if ratio <= 1e-9:
            raise SingularConfigurationError(
                f"Qhull cannot build the output polytope or its slice: the set is (nearly) "
                f"flat (σmin/σmax = {ratio:.3g}); expected a full-dimensional set",
                hint="use method='zonotope', which handles singular poses") from exc
        raise SingularConfigurationError(
            f"Qhull cannot build the output polytope or its slice of a full-dimensional "
            f"set (σmin/σmax = {ratio:.3g}): expected vertices it can separate, got "
            f"{exc.__class__.__name__} (near-coincident vertices or facets)",
            hint="use method='zonotope', the exact kernel") from exc


def _hull_multi(G, lo, hi, keeps, shift=0.0):
    from scipy.spatial import ConvexHull
    d, L = G.shape
    verts = _box_vertices(lo, hi) @ G.T + shift               # (2^L, d)
    hull = ConvexHull(verts)
    return [_slice(hull, verts, list(S), d) for S in keeps]


def _slice(hull, verts, S, d):
    from scipy.spatial import ConvexHull, HalfspaceIntersection
    eq = hull.equations                                       # n·x + off <= 0, |n| = 1
    if len(S) == d:
        worst = float(np.min(-eq[:, -1]))
        best = float(np.max(np.linalg.norm(verts[hull.vertices], axis=1)))
        return worst, best
    A, off = eq[:, S], eq[:, -1]
    nA = np.linalg.norm(A, axis=1)
    use = nA > 1e-12
    h = -off[use] / nA[use]
    if np.any(-off[~use] < 0):                              # the slice misses the set
        return -np.inf, -np.inf
    hs = np.hstack([A[use], off[use, None]])
    scale = np.abs(verts).max()
    if len(S) == 1:                       # the slice is an interval [xlo, xhi]
        a, b = A[use, 0], -off[use]
        xhi, xlo = np.min(b[a > 0] / a[a > 0]), np.max(b[a < 0] / a[a < 0])
        if xlo > xhi:          # the line misses the set: the signed distance as below
            return float(h.min()), -np.inf          # and as zonotope/ueberle (QA IX 5)
        worst = float(min(-xlo, xhi)) if h.min() > 0 else float(h.min())
        return worst, float(max(abs(xlo), abs(xhi)))
    if h.min() > 1e-12 * scale:
        interior = np.zeros(len(S))
    else:
        # origin on or outside the boundary: the signed distance is the answer (a flag
        # when negative); an interior point for the farthest point comes from the
        # Chebyshev centre of the slice (an LP)
        interior = _chebyshev_centre(A[use], off[use], scale)
        if interior is None:                                   # the slice is empty
            return float(h.min()), -np.inf
    inter = HalfspaceIntersection(hs, interior).intersections
    sub = ConvexHull(inter)
    worst = float(np.min(-sub.equations[:, -1])) if h.min() > 0 else float(h.min())
    best = float(np.max(np.linalg.norm(inter[sub.vertices], axis=1)))
    return worst, best


def _chebyshev_centre(A, off, scale):
    from scipy.optimize import linprog
    nA = np.linalg.norm(A, axis=1)
    k = A.shape[1]
    res = linprog(np.r_[np.zeros(k), -1.0], A_ub=np.hstack([A, nA[:, None]]), b_ub=-off,
                  bounds=[(None, None)] * k + [(0, None)], method="highs")
    if res.status == 2:                                        # infeasible: empty slice
        return None
    if not res.success or res.x[-1] <= 1e-12 * scale:
        raise SingularConfigurationError(
            "the slice of the output polytope has no interior (flat or empty); "
            "expected a full-dimensional slice", hint="use method='zonotope'")
    return res.x[:k]


# --------------------------------------------------------------------- Ueberle's method
#: σmin/σmax of G at or below which :func:`ueberle_worst` answers by the zonotope
#: kernel, with a ConditioningWarning.  Its nested least-squares problems lose accuracy
#: faster than the zonotope kernel's 1e-16/κ: on a line of hexa poses towards a
#: singular one (QA 24) its relative error against the zonotope and Qhull routes (which
#: agree with a 50-digit enumeration) was 4e-15 at κ = 1e-4, 6e-13 at 1e-6, 1e-8 at
#: 1e-7, 1.6e-5 at 1e-8 and 1.4 at 1.7e-10, unflagged below RANK_TOL = 1e-12 only.
UEBERLE_KAPPA = 1e-6


def ueberle_worst(G, lo, hi, S):
    """Ueberle's worst case for L = d, eqs. (10)-(12), batched.

    For every actuator ``i`` saturated at ``pmin_i`` or ``pmax_i`` the others are free;
    the distance from the origin to that facet's hyperplane within the slice is the
    least-squares problem ``min ||F_S||`` with ``F = Ĵ_i p_i' + ĵ_i p_i`` (eq. (11)) and
    ``F_{S^c} = 0`` (eq. (12)), solved through the null space of the constraint.
    The sign is + when the origin is on the inner side (``pmin_i <= 0 <= pmax_i``).

    Parameters: G (N, d, d), lo/hi (N, d), S tuple.  Returns ndarray (N,).
    """
    N, d, L = G.shape
    S = list(S)
    Sc = [k for k in range(d) if k not in S]
    best = np.full(N, np.inf)
    for i in range(L):
        others = [j for j in range(L) if j != i]
        Ji = G[:, :, others]                                   # (N, d, d-1)
        gi = G[:, :, i]                                        # (N, d)
        for bound, side in ((hi[:, i], hi[:, i] >= 0), (lo[:, i], lo[:, i] <= 0)):
            b = gi * bound[:, None]                            # (N, d)
            if Sc:
                Ac, bc = Ji[:, Sc, :], b[:, Sc]
                Ac_pinv = np.linalg.pinv(Ac)                   # (N, d-1, k)
                p0 = -np.einsum("nij,nj->ni", Ac_pinv, bc)
                resid = np.einsum("nij,nj->ni", Ac, p0) + bc
                _, sv, vt = np.linalg.svd(Ac)
                rank = np.sum(sv > 1e-12 * np.maximum(sv[:, :1], 1e-300), axis=1)
                # the residual of a consistent system solved through pinv is about
                # eps·cond·(||bc|| + ||Ac||·||p0||), cond that of the kept singular
                # values: a fixed 1e-9·||bc|| rejected every facet near a singularity
                # and the worst case came out inf (QA Z2 2)
                kept = np.take_along_axis(sv, np.maximum(rank - 1, 0)[:, None], 1)[:, 0]
                cond = np.divide(sv[:, 0], kept, out=np.ones(N), where=kept > 0)
                scale_b = np.linalg.norm(bc, axis=1) + sv[:, 0] * np.linalg.norm(p0, axis=1)
                feasible = np.linalg.norm(resid, axis=1) <= np.maximum(
                    1e-9 * (np.linalg.norm(bc, axis=1) + 1e-300),
                    64 * np.finfo(float).eps * cond * scale_b)
                dist = np.empty(N)
                for rk in np.unique(rank):
                    sel = rank == rk
                    Nb = np.swapaxes(vt[sel, rk:, :], 1, 2)    # null space (n, d-1, d-1-rk)
                    As = Ji[sel][:, S, :]
                    base = np.einsum("nij,nj->ni", As, p0[sel]) + b[sel][:, S]
                    M = As @ Nb
                    z = -np.einsum("nij,nj->ni", np.linalg.pinv(M), base)
                    F = base + np.einsum("nij,nj->ni", M, z)
                    dist[sel] = np.linalg.norm(F, axis=1)
                dist = np.where(feasible, dist, np.inf)
            else:
                As = Ji
                z = -np.einsum("nij,nj->ni", np.linalg.pinv(As), b)
                F = b + np.einsum("nij,nj->ni", As, z)
                dist = np.linalg.norm(F, axis=1)
            signed = np.where(side, dist, -dist)
            best = np.minimum(best, signed)
    # Ueberle's facets are those of a regular G: at σmin/σmax <= UEBERLE_KAPPA (or a
    # pose where no facet is feasible) the pose goes to the zonotope kernel, with a
    # warning, never an inf, the ~0 of a degenerate least-squares problem (QA Z2 2) or
    # the error of its nested least squares, which grows faster than 1/κ (QA 24)
    sv = np.linalg.svd(G, compute_uv=False)
    kappa = np.divide(sv[:, -1], sv[:, 0], out=np.zeros(N), where=sv[:, 0] > 0)
    redo = np.flatnonzero((kappa <= UEBERLE_KAPPA) | ~np.isfinite(best))
    if len(redo):
        from ..errors import ConditioningWarning
        _warn(ConditioningWarning(
            f"Ueberle's method: {len(redo)} of {N} pose(s) singular or nearly so "
            f"(σmin/σmax = {kappa[redo[0]]:.3g}{', ...' if len(redo) > 1 else ''}, "
            f"expected above {UEBERLE_KAPPA:g} with a feasible facet, where its least "
            "squares keep ~1e-12 relative): answered by the zonotope kernel there"))
        c, r = (hi[redo] + lo[redo]) / 2, (hi[redo] - lo[redo]) / 2
        best[redo] = zonotope_worst(G[redo], c, r, [tuple(S)])[0]
    return best


# -------------------------------------------------------------------- eqs. (5)-(7)
def _jacobian(J, shape: str, ndim: int | None = None, field: str = "J"):
    """A Jacobian argument of the index functions (q̇ = J ẋ, last axis 6, ``ndim`` axes
    or at least 2): float, finite, else :class:`InputError` naming ``field`` with
    ``shape`` as the expectation (:func:`distkin.argcheck.float_array`)."""
    arr = as_floats(J, field, f"a Jacobian of numbers, shape {shape}")
    if (arr.ndim < 2 if ndim is None else arr.ndim != ndim) or arr.shape[-1] != 6:
        raise InputError(f"expected a Jacobian of shape {shape}, got shape {arr.shape}",
                         field=field)
    if arr.shape[-2] == 0:          # no leg: no map to take singular values of
        raise InputError(f"expected a Jacobian of shape {shape} with at least one leg "
                         f"row (L >= 1), got shape {arr.shape}", field=field)
    return float_array(arr, field, (None,) * arr.ndim)


def output_generators(J, mass=None):
    """Generator matrices of the output capabilities, eqs. (5)-(7).

    Parameters
    ----------
    J : ndarray (..., L, 6)
        Jacobian with q̇ = J·(v, ω) (the paper's J = J_q⁻¹J_x, eq. (2)).
    mass : ndarray (6,) or (6, 6), optional
        Cartesian mass matrix M̂ (docs/design.md §5: diag(m, m, m, I, I, I)).

    Returns
    -------
    dict of ndarray (..., 6, L)
        ``"twist"``: J# = (JᵀJ)⁻¹Jᵀ, eq. (5) (actuator rates in rad/s -> m/s, rad/s);
        ``"wrench"``: Jᵀ, eq. (6) (actuator torques in N·m -> N, N·m);
        ``"acceleration"`` (if ``mass``): M̂⁻¹Jᵀ, which is J#·M_q⁺ of eq. (7) with
        M_q = J#ᵀM̂J# the joint-space mass matrix (its pseudo-inverse J M̂⁻¹ Jᵀ; for
        L = d this is M_q⁻¹).  The paper's printed ``M_q = JᵀM̂J`` does not type-check
        with J of shape (L, 6); this is the consistent reading.
    """
    J = _jacobian(J, "(..., L, 6)")
    Jt = np.swapaxes(J, -1, -2)
    out = {"wrench": Jt, "twist": np.linalg.pinv(J)}
    if mass is not None:
        M = as_floats(mass, "mass", "a Cartesian mass matrix, shape (6,) or (6, 6)")
        if M.shape not in ((6,), (6, 6)):
            raise InputError(f"expected a mass matrix of shape (6,) or (6, 6), got shape "
                             f"{M.shape}", field="mass")
        M = float_array(M, "mass", M.shape)
        if M.ndim == 1 and not np.all(M > 0):
            raise InputError(f"expected 6 positive masses and inertias, got {M.tolist()}",
                             field="mass")
        if M.ndim == 2 and not (np.allclose(M, M.T) and np.all(np.linalg.eigvalsh(M) > 0)):
            raise InputError(f"expected a symmetric positive definite mass matrix, got one "
                             f"{'with smallest eigenvalue ' if np.allclose(M, M.T) else ''}"
                             f"{np.linalg.eigvalsh(M).min() if np.allclose(M, M.T) else 'not symmetric'}",
                             field="mass")
        Minv = np.diag(1.0 / M) if M.ndim == 1 else np.linalg.inv(M)
        out["acceleration"] = Minv @ Jt
    return out
