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
   close real roots that the eigenvalues blurred into a pair are both found;
4. real roots outside the feasible interval, or where a tetrahedron of the bananas has
   negative squared volume, are spurious (complex assemblies) and are rejected;
5. the trilateration sequence of Sec. III (:func:`~.assembly.assemble_fast`) places
   P4 P5 P6 on both sides of the base plane.

Accuracy: legs reproduced to about 1e-12 relative on well-conditioned problems; the
result states the achieved leg residual of every pose.  Known limitation: two real roots
closer than about 1e-8 relative (two assembly modes about to merge) may be merged into
one, or a nearly real complex pair reported as a double root; the certified tier decides
those cases.
"""

from __future__ import annotations

import numpy as np

from ..geometry.poses import pose_from_points
from .assembly import assemble_fast
from .closure import feasible_interval, octic_data, part_values
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


def _factored(data, x):
    val, der = part_values(data, x)
    u, v, b1, b2, E1, E2 = (val[k] for k in ("u", "v", "b1", "b2", "E1", "E2"))
    du, dv, db1, db2, dE1, dE2 = (der[k] for k in ("u", "v", "b1", "b2", "E1", "E2"))
    G = u * E2 + v * E1 + 2 * b1 * b2
    dG = du * E2 + u * dE2 + dv * E1 + v * dE1 + 2 * (db1 * b2 + b1 * db2)
    a, b, c, d = val["T1a"], val["T1b"], val["T2a"], val["T2b"]
    da, db, dc, dd = der["T1a"], der["T1b"], der["T2a"], der["T2b"]
    R = a * b * c * d
    dR = da * b * c * d + a * db * c * d + a * b * dc * d + a * b * c * dd
    return G * G - 4 * R, 2 * G * dG - 4 * dR, G * G + 4 * np.abs(R), val, der


def _eq3(val, der):
    """Cleared eq. (3) on the branch where it is smallest, with its derivative."""
    u, v, b1, b2 = val["u"], val["v"], val["b1"], val["b2"]
    R1 = val["T1a"] * val["T1b"]
    R2 = val["T2a"] * val["T2b"]
    q1, q2 = np.sqrt(np.maximum(R1, 0.0)), np.sqrt(np.maximum(R2, 0.0))
    P = u * b2 - v * b1
    best, e1b, e2b = None, None, None
    for e1 in (1.0, -1.0):
        for e2 in (1.0, -1.0):
            N = P + e1 * v * q1 - e2 * u * q2
            if best is None:
                best, e1b, e2b = N, np.full_like(N, e1), np.full_like(N, e2)
            else:
                take = np.abs(N) < np.abs(best)
                best = np.where(take, N, best)
                e1b = np.where(take, e1, e1b)
                e2b = np.where(take, e2, e2b)
    dR1 = der["T1a"] * val["T1b"] + val["T1a"] * der["T1b"]
    dR2 = der["T2a"] * val["T2b"] + val["T2a"] * der["T2b"]
    dP = der["u"] * b2 + u * der["b2"] - der["v"] * b1 - v * der["b1"]
    with np.errstate(divide="ignore", invalid="ignore"):
        dq1 = np.where(q1 > 0, dR1 / (2 * q1), 0.0)
        dq2 = np.where(q2 > 0, dR2 / (2 * q2), 0.0)
    dN = dP + e1b * (der["v"] * q1 + v * dq1) - e2b * (der["u"] * q2 + u * dq2)
    scale = np.abs(u * b2) + np.abs(v * b1) + np.abs(v) * q1 + np.abs(u) * q2
    return best, dN, scale, e1b, e2b


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


def _deflated_newton(d, x, found, cc):
    r"""Newton on :math:`H(x)/\prod_j (x - r_j)` (implicit deflation by the roots found)."""
    x = x.copy()
    step = np.zeros_like(x)
    active = np.arange(x.size)
    for _ in range(_NEWTON_DEFLATED):
        if not active.size:
            break
        xa = x[active]
        H, dH, _, _, _ = _factored(d[active], xa)
        with np.errstate(divide="ignore", invalid="ignore"):
            defl = np.nansum(1.0 / (xa[:, None] - found[active]), axis=1)
            st = H / (dH - H * defl)
        st = np.clip(np.nan_to_num(st), -0.5 * cc[active], 0.5 * cc[active])
        x[active] = xa - st
        prev = np.abs(step[active])
        step[active] = st
        active = active[_moving(st, prev, x[active], cc[active])]
    H, _, Hs, _, _ = _factored(d, x)
    return x, step, _converged(H, Hs, step, x, cc)


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
    d = data[row]
    cc = c[row]
    step = np.zeros_like(x)
    active = np.arange(x.size)
    for _ in range(_NEWTON_MAX):
        if not active.size:
            break
        H, dH, _, _, _ = _factored(d[active], x[active])
        with np.errstate(divide="ignore", invalid="ignore"):
            st = np.where(dH != 0, H / dH, 0.0)
        st = np.clip(np.nan_to_num(st), -0.5 * cc[active], 0.5 * cc[active])
        x[active] -= st
        prev = np.abs(step[active])
        step[active] = st
        active = active[_moving(st, prev, x[active], cc[active])]
    H, dH, Hs, val, der = _factored(d, x)
    conv = _converged(H, Hs, step, x, cc)
    # eq. (3) polish where the root is feasible (all radicands >= 0)
    feas_t = ((val["T1a"] >= 0) & (val["T1b"] >= 0) & (val["T2a"] >= 0) & (val["T2b"] >= 0))
    for _ in range(_NEWTON_EQ3):
        N3, dN3, _, _, _ = _eq3(val, der)
        with np.errstate(divide="ignore", invalid="ignore"):
            st = np.where(conv & feas_t & (dN3 != 0), N3 / dN3, 0.0)
        st = np.clip(np.nan_to_num(st), -1e-3 * cc, 1e-3 * cc)
        x = x - st
        step = np.where(st != 0, st, step)
        val, der = part_values(d, x)
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
        xr, sr, cr = _deflated_newton(d[retry], x0[retry], roots[row[retry]], cc[retry])
        x[retry], step[retry], conv[retry] = xr, sr, cr
        roots, steps, kept = _cluster(row, x, conv, step, n, c)
        if np.isfinite(roots).sum() == before:
            break
    status = np.full((n, 8), -1)
    has = np.isfinite(roots)
    rr = np.where(has, roots, 0.0)
    val, _ = part_values(data[:, None, :], rr)
    tol_x = 1e-9 * c[:, None]
    inside = (rr >= lo[:, None] - tol_x) & (rr <= hi[:, None] + tol_x)
    tscale = c[:, None] ** 3
    tet = np.minimum(np.minimum(val["T1a"], val["T1b"]), np.minimum(val["T2a"], val["T2b"]))
    tet_ok = tet >= -1e-9 * tscale
    status[has] = 0
    status[has & inside & ~tet_ok] = 2
    status[has & ~inside] = 1
    # assemble every feasible root
    points = np.full((n, 8, 2, 3, 3), np.nan)
    rot = np.full((n, 8, 2, 3, 3), np.nan)
    trans = np.full((n, 8, 2, 3), np.nan)
    lerr = np.full((n, 8, 2), np.nan)
    lrel = np.full((n, 8, 2), np.nan)
    pr, pc = np.nonzero(status == 0)
    if pr.size:
        xs = np.clip(roots[pr, pc], np.maximum(lo[pr], 0.0), hi[pr])
        pts, h2min, r36 = assemble_fast(B[pr], xs, sides2[pr], legs2[pr])
        full = np.concatenate([np.broadcast_to(B[pr][:, None], pts.shape), pts], axis=-2)
        err = np.zeros(pts.shape[:2])
        errr = np.zeros(pts.shape[:2])
        for k, (i, j) in enumerate(LEG_PAIRS):
            dv = full[..., i - 1, :] - full[..., j - 1, :]
            dist = np.sqrt(np.einsum("...k,...k->...", dv, dv))
            e = np.abs(dist - L[pr][:, k, None])
            err = np.maximum(err, e)
            errr = np.maximum(errr, e / L[pr][:, k, None])
        good = (h2min > -1e-8).all(-1) & (errr.max(-1) < 1e-6)
        R, t = pose_from_points(Q[pr][:, None], pts)
        points[pr, pc], rot[pr, pc], trans[pr, pc] = pts, R, t
        lerr[pr, pc], lrel[pr, pc] = err, errr
        status[pr[~good], pc[~good]] = 3
    return {"coef": coef, "lo": lo, "hi": hi, "roots": roots, "status": status,
            "points": points, "rotation": rot, "translation": trans, "leg_error": lerr,
            "leg_error_rel": lrel, "step": steps, "data": data}
