r"""The fast tier of the octahedral forward kinematics, batched over problems (float64).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:

1. the generated kernel gives the octic :math:`O(s_{15})` and the quadratic parts of
   eq. (3) for every problem (:mod:`distkin._generated.octic_general`);
2. the roots of :math:`O(c\,t)` (scaled by :math:`c`, the middle of the feasible interval
   of :func:`~.closure.feasible_interval`) are the eigenvalues of its companion matrix
   (numpy, batched);
3. every eigenvalue that is real or nearly so starts a Newton polish: first on the octic
   in its factored form :math:`G^2 - 4R_1R_2` (smooth, no radicals; iterated until the
   step stalls, since convergence is only linear near two close roots), then on eq. (3)
   itself on the branch :math:`(\epsilon_1,\epsilon_2)` where it vanishes; a nearly real
   complex pair :math:`a \pm ib` starts two polishes, at :math:`a \pm b`, so that two
   close real roots that the eigenvalues blurred into a pair are both found; a start
   whose steps stop shrinking (slower than Newton's linear rate at a root of
   multiplicity six) has no real root to find and is dropped early; starts that found
   nothing new are retried, deflated by the roots found;
4. real roots outside the feasible interval, or where a tetrahedron of the bananas has
   negative squared volume, are spurious (complex assemblies) and are rejected;
5. the trilateration sequence of Sec. III (:func:`~.assembly.assemble_components`, in
   the base-adapted frame) places P4 P5 P6 on both sides of the base plane; rotations,
   translations and leg residuals follow for all roots and sides at once.

Every stage works on all problems, roots and sides at once, with the long axis last so
that numpy's inner loops are long (arrays shaped (..., 3) or (..., 2) with the batch
first make numpy loop over 2 or 3 elements at a time and cost several times more).
The companion eigenvalues (LAPACK ``dgeev``, one 8x8 matrix at a time) are the largest
single cost.

Accuracy: legs reproduced to about 1e-12 relative on well-conditioned problems; the
result states the achieved leg residual of every pose.  Known limitation: two real roots
closer than about 1e-8 relative (two assembly modes about to merge) may be merged into
one, or a nearly real complex pair reported as a double root; the certified tier decides
those cases.
"""

from __future__ import annotations

import numpy as np

from .assembly import assemble_components, base_frame
from .closure import feasible_interval, octic_data
from .problem import LEG_PAIRS

__all__ = ["solve_fast", "REASONS"]

#: status codes of the real roots found
REASONS = {
    0: "assembly mode",
    1: "spurious: outside the triangle bounds of s15 (a triangle through P1 P5 cannot close)",
    2: "spurious: a tetrahedron of the bananas has negative squared volume (complex assembly)",
    3: "rejected: the trilateration sequence or the leg check failed at this root",
}

_NEWTON_MAX = 60  # Newton on the factored octic: linear near a double root, so allow many
_NEWTON_EQ3 = 2
_NEWTON_DEFLATED = 25  # deflated retries: a start that has not settled by then has no root
_DUP = 1e-9       # relative distance under which two polished roots are one
_RES = 1e-4       # relative residual of the factored octic accepted as a root
_ROUNDS = 3       # rounds of deflated Newton from the starts that found nothing new
_STEP = 1e-9      # relative size of the last Newton step of a converged polish
_NEAR_REAL = 0.05  # |Im| / scale under which an eigenvalue starts a polish
_GRACE = 6        # Newton steps before a start must show convergence ...
_RATE = 0.7       # ... |step_k| <= _RATE |step_(k-2)|: Newton's linear rate (m-1)/m at a
#                   root of multiplicity m <= 6 gives ((m-1)/m)^2 <= 0.7


def _quadratics(data):
    """(3, 10, N) contiguous coefficients (constant, x, x^2) of the 10 quadratics."""
    return np.ascontiguousarray(data[:, :30].reshape(-1, 10, 3).transpose(2, 1, 0))


def _parts(C, x):
    """Values and x-derivatives (10, M) of the quadratics ``C`` (3, 10, M) at ``x`` (M,)."""
    c0, c1, c2 = C
    return c0 + x * (c1 + x * c2), c1 + (2 * x) * c2


def _factored(C, x):
    r"""The octic in its factored form :math:`H = G^2 - 4R_1R_2`, its derivative, the
    size :math:`G^2 + 4|R_1R_2|` of its terms, and the quadratics' values/derivatives."""
    val, der = _parts(C, x)
    u, v, b1, b2, E1, E2, a, b, c, d = val
    du, dv, db1, db2, dE1, dE2, da, db, dc, dd = der
    G = u * E2 + v * E1 + 2 * b1 * b2
    dG = du * E2 + u * dE2 + dv * E1 + v * dE1 + 2 * (db1 * b2 + b1 * db2)
    ab, cd = a * b, c * d
    R = ab * cd
    dR = (da * b + a * db) * cd + ab * (dc * d + c * dd)
    return G * G - 4 * R, 2 * G * dG - 4 * dR, G * G + 4 * np.abs(R), val, der


_SIGNS = np.array([[1.0, 1.0], [1.0, -1.0], [-1.0, 1.0], [-1.0, -1.0]])


def _eq3(val, der):
    """Cleared eq. (3) on the branch where it is smallest, with its derivative."""
    u, v, b1, b2, _, _, a, b, c, d = val
    du, dv, db1, db2, _, _, da, db, dc, dd = der
    R1, R2 = a * b, c * d
    q1, q2 = np.sqrt(np.maximum(R1, 0.0)), np.sqrt(np.maximum(R2, 0.0))
    P = u * b2 - v * b1
    vq1, uq2 = v * q1, u * q2
    N = P + _SIGNS[:, :1] * vq1 - _SIGNS[:, 1:] * uq2           # (4, M) branches
    k = np.abs(N).argmin(axis=0)
    best = np.choose(k, N)
    e1b, e2b = _SIGNS[:, 0].take(k), _SIGNS[:, 1].take(k)
    dR1 = da * b + a * db
    dR2 = dc * d + c * dd
    dP = du * b2 + u * db2 - dv * b1 - v * db1
    with np.errstate(divide="ignore", invalid="ignore"):
        dq1 = np.where(q1 > 0, dR1 / (2 * q1), 0.0)
        dq2 = np.where(q2 > 0, dR2 / (2 * q2), 0.0)
    dN = dP + e1b * (dv * q1 + v * dq1) - e2b * (du * q2 + u * dq2)
    return best, dN


def _eigen_roots(coef, c):
    """Roots of sum coef[k] x^(8-k) via the companion matrix of the scaled polynomial."""
    n = coef.shape[0]
    powers = c[:, None] ** np.arange(8, -1, -1)
    sc = coef * powers
    sc = sc / np.max(np.abs(sc), axis=1, keepdims=True)
    lead = sc[:, 0]
    roots = np.full((n, 8), np.nan + 0j)
    good = np.abs(lead) > 1e-12
    if np.any(good):
        comp = np.zeros((int(good.sum()), 8, 8))
        comp[:, 0, :] = -sc[good, 1:] / lead[good, None]
        idx = np.arange(7)
        comp[:, idx + 1, idx] = 1.0
        roots[good] = np.linalg.eigvals(comp)
    for i in np.flatnonzero(~good):  # the leading coefficient vanishes: lower degree
        r = np.roots(sc[i]) if np.any(sc[i]) else np.array([])
        roots[i, :len(r)] = r
    return roots * c[:, None]


def _cluster(row, x, conv, step, n, c):
    """One root per cluster of converged polishes (per problem, increasing)."""
    roots = np.full((n, 8), np.nan)
    steps = np.full((n, 8), np.nan)
    kept = np.zeros(x.size, dtype=bool)
    order = np.lexsort((x, row))
    k = order[conv[order]]
    r, xv = row[k], x[k]
    if k.size:
        newrow = np.r_[True, r[1:] != r[:-1]]
        gap = np.r_[True, np.abs(np.diff(xv)) > _DUP * np.maximum(np.abs(xv[1:]), c[r[1:]])]
        keep = newrow | gap
        k, r, xv = k[keep], r[keep], xv[keep]
        first = np.r_[0, np.flatnonzero(r[1:] != r[:-1]) + 1]
        pos = np.arange(r.size) - np.repeat(first, np.diff(np.r_[first, r.size]))
        sel = pos < 8
        roots[r[sel], pos[sel]] = xv[sel]
        steps[r[sel], pos[sel]] = np.abs(step[k[sel]])
        kept[k[sel]] = True
    return roots, steps, kept


def _newton(C, x, cc, iters, found=None):
    r"""Newton on the factored octic from the starts ``x`` (M,), all at once.

    With ``found`` (M, k) (NaN padded), Newton on :math:`H(x)/\prod_j (x - r_j)`
    (implicit deflation by the roots found).  A start stops when its step is negligible
    or stalls at rounding level, or when, after :data:`_GRACE` steps, its step no
    longer shrinks at least like Newton's linear rate at a root of multiplicity up to
    six (:math:`|s_k| > 0.7\,|s_{k-2}|`: it wanders, there is no real root to find).

    Returns
    -------
    x : (M,) the final iterates
    step : (M,) the last steps
    conv : (M,) bool, :func:`_converged` with the octic at x
    val, der : (10, M) the quadratics' values and derivatives at x
    """
    x = x.copy()
    step = np.zeros_like(x)
    prev2 = np.full_like(x, np.inf)
    active = np.arange(x.size)
    Ca, fa = C, found
    for it in range(iters):
        if not active.size:
            break
        xa = x[active]
        H, dH, _, _, _ = _factored(Ca, xa)
        with np.errstate(divide="ignore", invalid="ignore"):
            if fa is None:
                st = H / dH
            else:
                st = H / (dH - H * np.nansum(1.0 / (xa[:, None] - fa), axis=1))
        ca = cc[active]
        st = np.clip(np.where(np.isfinite(st), st, 0.0), -0.5 * ca, 0.5 * ca)
        xn = xa - st
        prev = np.abs(step[active])
        keep = _moving(st, prev, xn, ca)
        if it >= _GRACE:
            keep &= np.abs(st) <= _RATE * prev2[active]
        x[active] = xn
        prev2[active] = prev
        step[active] = st
        if not keep.all():
            active = active[keep]
            Ca = Ca[:, :, keep]
            fa = None if fa is None else fa[keep]
    H, _, Hs, val, der = _factored(C, x)
    return x, step, _converged(H, Hs, step, x, cc), val, der


def _moving(st, prev, x, cc):
    """Still iterating: the step is not yet negligible, nor stalled at rounding level."""
    size = np.maximum(np.abs(x), cc)
    a = np.abs(st)
    return (a > 1e-14 * size) & ~((a <= _STEP * size) & (a > 0.5 * prev))


def _converged(H, Hs, step, x, cc):
    """A polish converged when its last step is negligible and the factored octic is
    small against its terms (near two close roots that ratio is only ~1e-7: the
    cancellation is severe; a nearly real complex pair never settles the step)."""
    return (np.abs(step) <= _STEP * np.maximum(np.abs(x), cc)) & (np.abs(H) <= _RES * Hs)


def solve_fast(B, Q, L, sides2, legs2):
    """Every assembly mode of N problems (float64).

    Parameters
    ----------
    B : (N, 3, 3) base points P1 P2 P3; Q : (N, 3, 3) platform points P4 P5 P6 in the
    platform frame; L : (N, 6) leg lengths; sides2, legs2 : (N, 6) squared sides and legs.

    Returns
    -------
    dict of arrays:
        ``coef`` (N, 9) octic, highest degree first; ``lo``, ``hi`` (N,) bounds of
        s15; ``roots`` (N, 8) real roots found (NaN padded, increasing);
        ``status`` (N, 8) codes of :data:`REASONS` (-1 padding); ``points``
        (N, 8, 2, 3, 3) rows P4 P5 P6 per root and mirror side; ``rotation``
        (N, 8, 2, 3, 3); ``translation`` (N, 8, 2, 3); ``leg_error`` (N, 8, 2)
        absolute, length units; ``leg_error_rel`` (N, 8, 2); ``step`` (N, 8) size of
        the last Newton step (an error estimate of the root).
    """
    n = B.shape[0]
    data = octic_data(sides2, legs2, "fast")
    coef = data[:, 30:]
    Call = _quadratics(data)
    lo, hi, _ = feasible_interval(sides2, legs2)
    c = np.where(hi > 0, 0.5 * (np.maximum(lo, 0) + hi), np.mean(sides2, axis=1))
    eig = _eigen_roots(coef, c)
    re, im = eig.real, np.abs(eig.imag)
    ok = np.isfinite(re) & (im <= _NEAR_REAL * np.maximum(np.abs(eig), c[:, None]))
    starts = np.concatenate([re - im, re + im], axis=1)                   # (N, 16)
    # one start per real eigenvalue, two (a -+ b) per conjugate pair a +- ib
    okk = np.concatenate([ok & (eig.imag >= 0), ok & (eig.imag > 0)], axis=1)
    row, col = np.nonzero(okk)
    x = starts[row, col]
    x0 = x.copy()
    C = Call[:, :, row]
    cc = c[row]
    x, step, conv, val, der = _newton(C, x, cc, _NEWTON_MAX)
    # eq. (3) polish where the root is feasible (all radicands >= 0)
    feas_t = (val[6:] >= 0).all(axis=0)
    pol = np.flatnonzero(conv & feas_t)
    if pol.size:
        xp, sp, Cp, cp = x[pol], step[pol], C[:, :, pol], cc[pol]
        vp, dp = val[:, pol], der[:, pol]
        for k in range(_NEWTON_EQ3):
            N3, dN3 = _eq3(vp, dp)
            with np.errstate(divide="ignore", invalid="ignore"):
                st = N3 / dN3
            st = np.clip(np.where(np.isfinite(st), st, 0.0), -1e-3 * cp, 1e-3 * cp)
            xp = xp - st
            sp = np.where(st != 0, st, sp)
            x[pol], step[pol] = xp, sp
            # a further step only where this one was not already below 1e-9 relative
            # (Newton's quadratic convergence makes the next one negligible there)
            more = np.abs(st) > 1e-9 * np.abs(xp)
            if k == _NEWTON_EQ3 - 1 or not more.any():
                break
            pol, xp, sp, Cp, cp = pol[more], xp[more], sp[more], Cp[:, :, more], cp[more]
            vp, dp = _parts(Cp, xp)
    roots, steps, kept = _cluster(row, x, conv, step, n, c)
    # starts that failed or fell onto a root already found: Newton again from the start,
    # deflated by the roots found (close roots blurred by the eigenvalues); repeated
    # while it finds new roots (clusters of three)
    # (only starts near the feasible interval: elsewhere no assembly mode can hide)
    near = (x0 >= lo[row] - 0.05 * cc) & (x0 <= hi[row] + 0.05 * cc)
    for _ in range(_ROUNDS):
        retry = np.flatnonzero(~kept & near)
        if not retry.size:
            break
        before = np.isfinite(roots).sum()
        xr, sr, cr, _, _ = _newton(C[:, :, retry], x0[retry], cc[retry], _NEWTON_DEFLATED,
                                   roots[row[retry]])
        x[retry], step[retry], conv[retry] = xr, sr, cr
        roots, steps, kept = _cluster(row, x, conv, step, n, c)
        if np.isfinite(roots).sum() == before:
            break
    status = np.full((n, 8), -1)
    has = np.isfinite(roots)
    hr, hc = np.nonzero(has)
    xs = roots[hr, hc]
    tol_x = 1e-9 * c[hr]
    inside = (xs >= lo[hr] - tol_x) & (xs <= hi[hr] + tol_x)
    tv, _ = _parts(Call[:, 6:, hr], xs)
    tet_ok = tv.min(axis=0) >= -1e-9 * c[hr] ** 3
    st_h = np.where(inside, np.where(tet_ok, 0, 2), 1)
    status[hr, hc] = st_h
    # assemble every feasible root
    points = np.full((n, 8, 2, 3, 3), np.nan)
    rot = np.full((n, 8, 2, 3, 3), np.nan)
    trans = np.full((n, 8, 2, 3), np.nan)
    lerr = np.full((n, 8, 2), np.nan)
    lrel = np.full((n, 8, 2), np.nan)
    sel = st_h == 0
    pr, pc = hr[sel], hc[sel]
    if pr.size:
        xs = np.clip(xs[sel], np.maximum(lo[pr], 0.0), hi[pr])
        Bp = B[pr]
        frame = tuple(a[pr] for a in base_frame(B))
        pts, h2min, _ = assemble_components(Bp, xs, sides2[pr], legs2[pr], frame)
        R, t = _poses(Q[pr], pts)
        err, errr = _leg_errors(Bp, pts, L[pr])
        good = (h2min > -1e-8) & (errr.max(-1) < 1e-6)
        points[pr, pc] = pts.transpose(3, 2, 0, 1)
        rot[pr, pc], trans[pr, pc] = R, t
        lerr[pr, pc], lrel[pr, pc] = err, errr
        status[pr[~good], pc[~good]] = 3
    return {"coef": coef, "lo": lo, "hi": hi, "roots": roots, "status": status,
            "points": points, "rotation": rot, "translation": trans, "leg_error": lerr,
            "leg_error_rel": lrel, "step": steps, "data": data}


def _frame(P):
    """Right-handed orthonormal frame of triangles, as
    :func:`distkin.geometry.poses.triangle_frame` but in component layout: ``P``
    (3 points, 3 coords, ...) -> F (3 rows, 3 columns e1 e2 e3, ...); a degenerate
    triangle gives NaN (which the leg check then rejects)."""
    d1 = [P[1][k] - P[0][k] for k in range(3)]
    d2 = [P[2][k] - P[0][k] for k in range(3)]
    n = [d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
         d1[0] * d2[1] - d1[1] * d2[0]]
    with np.errstate(divide="ignore", invalid="ignore"):
        l1 = 1.0 / np.sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2])
        ln = 1.0 / np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    e1 = [c * l1 for c in d1]
    e3 = [c * ln for c in n]
    e2 = [e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
          e3[0] * e1[1] - e3[1] * e1[0]]
    return [[e1[i], e2[i], e3[i]] for i in range(3)]


def _poses(Q, pts):
    r"""Rotations and translations carrying the platform triangles onto the placements.

    :math:`R = F_p F_q^T`, :math:`t = \bar p - R \bar q` (as
    :func:`distkin.geometry.poses.pose_from_points`).  ``Q`` (M, 3, 3) rows P4 P5 P6 in
    the platform frame, ``pts`` (3, 3, 2, M) from :func:`~.assembly.assemble_components`.
    Returns R (M, 2, 3, 3) and t (M, 2, 3).
    """
    Qc = Q.transpose(1, 2, 0)                           # (3 points, 3 coords, M)
    Fq = _frame(Qc)
    Fp = _frame(pts)
    qc = Qc.mean(axis=0)
    pc = pts.mean(axis=0)
    R = np.empty((3, 3) + pts.shape[2:])
    for i in range(3):
        for j in range(3):
            R[i, j] = Fp[i][0] * Fq[j][0] + Fp[i][1] * Fq[j][1] + Fp[i][2] * Fq[j][2]
    t = pc - (R[:, 0] * qc[0] + R[:, 1] * qc[1] + R[:, 2] * qc[2])
    return R.transpose(3, 2, 0, 1), t.transpose(2, 1, 0)


def _leg_errors(Bp, pts, L):
    """Absolute and relative leg errors (M, 2) of the placements ``pts`` (3, 3, 2, M)
    (base points ``Bp`` (M, 3, 3), leg lengths ``L`` (M, 6))."""
    Bc = Bp.transpose(1, 2, 0)
    full = (Bc[0], Bc[1], Bc[2], pts[0], pts[1], pts[2])
    err = rel = None
    for k, (i, j) in enumerate(LEG_PAIRS):
        a, b = full[i - 1], full[j - 1]
        dx, dy, dz = a[0] - b[0], a[1] - b[1], a[2] - b[2]
        e = np.abs(np.sqrt(dx * dx + dy * dy + dz * dz) - L[:, k])
        er = e / L[:, k]
        err = e if err is None else np.maximum(err, e)
        rel = er if rel is None else np.maximum(rel, er)
    return err.T, rel.T
