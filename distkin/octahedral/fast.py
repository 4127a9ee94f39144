r"""The fast tier of the octahedral forward kinematics, batched over problems (float64).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:

1. the generated kernel gives the octic :math:`O(s_{15})` and the quadratic parts of
   eq. (3) for every problem (:mod:`distkin._generated.octic_general`);
2. the real roots come from a projective sign scan of the octic over a fixed grid
   (:mod:`.rootscan`: one matrix product for all problems, brackets refined by
   safeguarded Halley steps), not from companion eigenvalues -- LAPACK's ``dgeev`` costs
   ~8 µs per 8x8 matrix, most of the target of the whole batched solve.  The scan
   works on the octic rebuilt around the middle of the feasible interval from the
   quadratic parts (:func:`~.closure.shifted_octic`), which keeps the digits the
   expanded coefficients lose to cancellation there;
3. the roots inside the triangle bounds, where the banana tetrahedra are real, are
   polished on eq. (3) itself, on the branch :math:`(\epsilon_1,\epsilon_2)` where it
   vanishes (at most :data:`_EQ3_SCAN` steps); those where eq. (3) converges slowly (a
   nearly flat tetrahedron makes its branch nearly singular) and the spurious roots
   (reported with their values) by Newton on the factored octic
   :math:`G^2 - 4R_1R_2`, evaluated from the quadratics;
4. the careful way, for every problem the scan doubts (:func:`.rootscan.real_roots`:
   its count differs from the Sturm count, or a minimum of :math:`|O|` comes within
   rounding of zero) or whose factored Newton moves a root by more than 1e-6 relative
   or does not converge: the eigenvalue method, by the single-problem solver's root
   stage in plain floats (:func:`.fast_single.real_roots_scalar`) when there are at
   most :data:`_SCALAR_CAREFUL` such problems, else by :func:`_careful_roots` -- every
   companion eigenvalue that is real or nearly so starts Newton on the factored octic
   (iterated until the step stalls, since convergence is only linear near two close
   roots), then eq. (3); a nearly real complex pair :math:`a \pm ib` starts two, at
   :math:`a \pm b`, so that two close real roots that the eigenvalues blurred into a
   pair are both found; a start whose steps stop shrinking has no real root to find and
   is dropped early; starts that found nothing new are retried, deflated by the roots
   found.  About 0.5 % of the problems near the Griffis-Duffy example (Sec. VI, legs
   x (1 + 1 % noise)), ~9 % of random octahedra (pairs of roots next to a third);
5. real roots outside the feasible interval, or where a tetrahedron of the bananas has
   negative squared volume, are spurious (complex assemblies) and are rejected;
6. the trilateration sequence of Sec. III (:func:`~.assembly.assemble_components`, in
   the base-adapted frame) places P4 P5 P6 on both sides of the base plane; rotations,
   translations and leg residuals follow for all roots and sides at once, written
   straight into the (N, 16, ...) arrays of :class:`~.forward.BatchResult`.

Every stage works on all problems, roots and sides at once, with the long axis last so
that numpy's inner loops are long (arrays shaped (..., 3) or (..., 2) with the batch
first make numpy loop over 2 or 3 elements at a time and cost several times more).

Cost (2000 problems near the Griffis-Duffy example, CPU time on the shared 2-core
machine; see BENCHMARKS.md): ~10-11 µs per problem on a quiet machine, 13-15 µs under
a load of 2-3 (22-28 µs with eigenvalues for every problem, measured side by side),
of which, timed stage by stage: the generated kernel 0.7 µs, the rebuilt octic
0.25 µs, the scan 2.2 µs and its Sturm check 0.3-0.6 µs, classification and polish
1.2 µs, the careful way for the ~0.5 % doubted problems ~0.3 µs, the trilateration
sequence 1.0 µs, rotations and translations 0.8 µs, leg residuals 0.55 µs, the
(N, 16, 3, 3) result arrays 1.4 µs, sorting and glue the rest.  No stage dominates:
each is a few dozen numpy operations at ~0.5-1 ns per element.

Accuracy: legs reproduced to about 1e-12 relative on well-conditioned problems; the
result states the achieved leg residual of every pose.  Known limitation: two real roots
closer than about 1e-8 relative (two assembly modes about to merge) may be merged into
one, or a nearly real complex pair reported as a double root; the certified tier decides
those cases.  Single problems (:mod:`.fast_single`) use the eigenvalue method directly;
both tiers agree on the roots and their statuses (tests/octahedral).
"""

from __future__ import annotations

import numpy as np

from .assembly import assemble_components, base_frame
from .closure import feasible_interval, octic_data, shifted_octic
from .problem import LEG_PAIRS
from .rootscan import real_roots

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
_EQ3_SCAN = 4       # Newton steps on eq. (3) from the scan's roots (batched tier)
_NEWTON_CAREFUL = 20  # the same in the batched tier's careful path (linear rate 1/2 near
#                       a double root: 20 steps gain 6 digits, eq. (3) the rest)
_NEWTON_DEFLATED = 25  # deflated retries: a start that has not settled by then has no root
_SCALAR_CAREFUL = 64  # up to this many doubted problems take the scalar careful way
_DEFLATED_CAREFUL = 15  # the same in the batched tier's careful path
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


def _careful_roots(coef, Call, lo, hi, c):
    """The real roots of the problems the scan doubts, the careful way: every companion
    eigenvalue that is real or nearly so starts Newton on the factored octic (a nearly
    real pair a +- ib starts two, at a -+ b), then eq. (3) where feasible; starts that
    found nothing new are retried, deflated by the roots found.  Returns (row, x, step)
    flat."""
    n = coef.shape[0]
    eig = _eigen_roots(coef, c)
    re, im = eig.real, np.abs(eig.imag)
    ok = np.isfinite(re) & (im <= _NEAR_REAL * np.maximum(np.abs(eig), c[:, None]))
    starts = np.concatenate([re - im, re + im], axis=1)                   # (n, 16)
    okk = np.concatenate([ok & (eig.imag >= 0), ok & (eig.imag > 0)], axis=1)
    row, col = np.nonzero(okk)
    x = starts[row, col]
    x0 = x.copy()
    C = Call[:, :, row]
    cc = c[row]
    x, step, conv, val, der = _newton(C, x, cc, _NEWTON_CAREFUL)
    pol = np.flatnonzero(conv & (val[6:] >= 0).all(axis=0))
    if pol.size:
        x[pol], step[pol], _ = _eq3_polish(C[:, :, pol], x[pol], step[pol], cc[pol],
                                           val[:, pol], der[:, pol])
    roots, steps, kept = _cluster(row, x, conv, step, n, c)
    near = (x0 >= lo[row] - 0.05 * cc) & (x0 <= hi[row] + 0.05 * cc)
    for _ in range(_ROUNDS):
        retry = np.flatnonzero(~kept & near)
        if not retry.size:
            break
        before = np.isfinite(roots).sum()
        xr, sr, cr, _, _ = _newton(C[:, :, retry], x0[retry], cc[retry], _DEFLATED_CAREFUL,
                                   roots[row[retry]])
        x[retry], step[retry], conv[retry] = xr, sr, cr
        roots, steps, kept = _cluster(row, x, conv, step, n, c)
        if np.isfinite(roots).sum() == before:
            break
    r, k = np.nonzero(np.isfinite(roots))
    return r, roots[r, k], steps[r, k]


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
        s15; ``roots`` (N, 8) real roots found (NaN padded, increasing); ``status``
        (N, 8) codes of :data:`REASONS` (-1 padding); ``step`` (N, 8) size of the last
        Newton step (an error estimate of the root); ``slot`` (N, 8) index of the
        first of the two poses of each assembly root (-1 otherwise); ``count`` (N,)
        poses per problem; ``s15`` (N, 8) the assembly roots, increasing, NaN padded;
        ``points`` (N, 16, 3, 3) rows P4 P5 P6, ``rotation`` (N, 16, 3, 3),
        ``translation`` (N, 16, 3), ``leg_error`` (N, 16) absolute, length units,
        ``leg_error_rel`` (N, 16), ``valid`` (N, 16): the poses of each problem first,
        two mirror poses (side +1, -1) per assembly root by increasing root, NaN
        padded; ``data`` (N, 39) the kernel output.
    """
    n = B.shape[0]
    data = octic_data(sides2, legs2, "fast")
    coef = data[:, 30:]
    Call = _quadratics(data)
    lo, hi, _ = feasible_interval(sides2, legs2)
    lo0 = np.maximum(lo, 0.0)
    c = np.where(hi > 0, 0.5 * (lo0 + hi), np.mean(sides2, axis=1))
    wide = hi > lo0
    x0 = np.where(wide, 0.5 * (lo0 + hi), c)
    h = np.maximum(np.where(wide, 0.5 * (hi - lo0), 0.5 * c), 1e-3 * c)
    row, x, step, doubt = real_roots(
        shifted_octic(data, x0, h),
        lambda r: shifted_octic(data[r], x0[r], h[r], absolute=True), x0, h)
    # polish on eq. (3) or the factored octic (steps 3 and 4 of the module docstring);
    # the problems in doubt go the careful way
    status, x, step = _classify_polish(Call, row, x, step, lo, hi, c, doubt)
    care = np.flatnonzero(doubt)
    if care.size:
        keep = ~doubt[row]
        if care.size <= _SCALAR_CAREFUL:
            # a few problems: the single-problem solver's root stage, in plain floats
            # (numpy calls on small arrays cost more than the arithmetic they do)
            from .fast_single import real_roots_scalar     # (it imports this module)
            recs = [real_roots_scalar(d, a, b, m) for d, a, b, m in
                    zip(data[care].tolist(), lo[care].tolist(), hi[care].tolist(),
                        c[care].tolist())]
            r2 = np.repeat(care, [len(r) for r in recs])
            x2, s2, st2 = (np.array([v[k] for r in recs for v in r]) for k in range(3))
            st2 = st2.astype(int)
        else:
            r2, x2, s2 = _careful_roots(coef[care], Call[:, :, care], lo[care], hi[care],
                                        c[care])
            r2 = care[r2]
            st2 = _classify(Call, r2, x2, lo, hi, c)
        row = np.concatenate([row[keep], r2])
        x = np.concatenate([x[keep], x2])
        step = np.concatenate([step[keep], s2])
        status = np.concatenate([status[keep], st2])
    # one root per cluster, increasing, at most 8 per problem
    row, x, step, status, pos = _sorted_unique(row, x, step, status, n, c, x0, h)
    # the trilateration sequence at every feasible root; then poses and leg residuals
    sel = np.flatnonzero(status == 0)
    pr = row[sel]
    pts = R = t = err = errr = None
    if sel.size:
        xs = np.clip(x[sel], lo0[pr], hi[pr])
        frame = tuple(a[pr] for a in base_frame(B))
        Bp = B[pr]
        pts, h2min, _ = assemble_components(Bp, xs, sides2[pr], legs2[pr], frame)
        R, t = _poses(_platform(Q), pr, pts)
        err, errr = _leg_errors(Bp, pts, L[pr])
        good = (h2min > -1e-8) & (errr.max(-1) < 1e-6)
        pts = pts.transpose(3, 2, 0, 1)
        if not good.all():
            status[sel[~good]] = 3
            keep = np.flatnonzero(good)
            sel, pr = sel[keep], pr[keep]
            pts, R, t, err, errr = pts[keep], R[keep], t[keep], err[keep], errr[keep]
    return _outputs(n, coef, lo, hi, row, x, step, pos, status, sel, pr, pts, R, t, err,
                    errr, data)


def _sorted_unique(row, x, step, status, n, c, x0, h):
    """The roots of each problem in increasing order, at most 8; two roots closer than
    :data:`_DUP` relative (a polish that met another root) are one.  Returns row, x,
    |step|, status and the position of each root in its problem's list."""
    # one sort on row + (a monotone map of x into (0, 1))
    order = np.argsort(row + (0.5 + np.arctan((x - x0[row]) / h[row]) / np.pi), kind="stable")
    r, xv, sv, tv = row[order], x[order], np.abs(step[order]), status[order]
    if r.size:
        newrow = np.r_[True, r[1:] != r[:-1]]
        gap = np.r_[True, np.abs(np.diff(xv)) > _DUP * np.maximum(np.abs(xv[1:]), c[r[1:]])]
        keep = newrow | gap
        r, xv, sv, tv = r[keep], xv[keep], sv[keep], tv[keep]
    pos = np.arange(r.size) - np.searchsorted(r, r)
    sel = pos < 8
    return r[sel], xv[sel], sv[sel], tv[sel], pos[sel]


def _classify(Call, row, x, lo, hi, c):
    """Status codes of roots: 1 outside the triangle bounds (1e-9 c tolerance), 2 where
    a banana tetrahedron has negative squared volume (below -1e-9 c^3), else 0."""
    cr = c[row]
    tol_x = 1e-9 * cr
    status = np.where((x >= lo[row] - tol_x) & (x <= hi[row] + tol_x), 0, 1)
    ins = np.flatnonzero(status == 0)
    if ins.size:
        tv, _ = _parts(Call[:, 6:, row[ins]], x[ins])
        status[ins[tv.min(axis=0) < -1e-9 * cr[ins] ** 3]] = 2
    return status


def _classify_polish(Call, row, x, step, lo, hi, c, doubt):
    """:func:`_classify` the scan's roots and polish them (see :func:`solve_fast`);
    marks the problems to doubt.  Returns status, x, step."""
    cr = c[row]
    tol_x = 1e-9 * cr
    status = np.where((x >= lo[row] - tol_x) & (x <= hi[row] + tol_x), 0, 1)
    x, step = x.copy(), step.copy()
    ins = np.flatnonzero(status == 0)
    if ins.size:
        C, xi, ci = Call[:, :, row[ins]], x[ins], cr[ins]
        val, der = _parts(C, xi)
        tet = val[6:].min(axis=0)
        status[ins[tet < -1e-9 * ci ** 3]] = 2
        pol = np.flatnonzero(tet >= 0)
        if pol.size < ins.size:
            C, xi, ci, val, der = C[:, :, pol], xi[pol], ci[pol], val[:, pol], der[:, pol]
        pi = ins[pol]
        xp, sp, first = _eq3_polish(C, xi, step[pi], ci, val, der, _EQ3_SCAN)
        x[pi], step[pi] = xp, sp
        # a large first step, or a last one still above 1e-9 relative (a nearly
        # singular branch: a banana tetrahedron nearly flat), goes to the factored octic
        sz = np.maximum(np.abs(xi), ci)
        slow = (np.abs(first) > 1e-6 * sz) | (sp > 1e-9 * sz)
        x[pi[slow]] = xi[slow]
        other = np.flatnonzero(status != 0)
        other = np.concatenate([other, pi[slow]]) if slow.any() else other
    else:
        other = np.flatnonzero(status != 0)
    if other.size:
        xo, co = x[other], cr[other]
        xn, sn, conv, _, _ = _newton(Call[:, :, row[other]], xo, co, _NEWTON_MAX)
        doubt[row[other[~conv | (np.abs(xn - xo) > 1e-6 * np.maximum(np.abs(xo), co))]]] = True
        x[other] = np.where(conv, xn, xo)
        step[other] = np.where(conv, sn, step[other])
    return status, x, step


def _eq3_polish(C, x, step, c, val, der, steps=_NEWTON_EQ3):
    """At most ``steps`` Newton steps on eq. (3), on the branch where it is smallest
    (:func:`_eq3`), each clipped to 1e-3 c; a further one only where the last was not
    already below 1e-9 relative (quadratic convergence makes the next one negligible
    there).  ``val``, ``der``: the quadratics at x.  Returns x, |last step|
    (the previous step where none was taken), first step."""
    x, step = x.copy(), step.copy()
    idx = np.arange(x.size)
    first = np.zeros(x.size)
    for k in range(steps):
        N3, dN3 = _eq3(val, der)
        with np.errstate(divide="ignore", invalid="ignore"):
            st = N3 / dN3
        st = np.clip(np.where(np.isfinite(st), st, 0.0), -1e-3 * c, 1e-3 * c)
        if k == 0:
            first = st
        xn = x[idx] - st
        x[idx] = xn
        step[idx] = np.where(st != 0, st, step[idx])
        more = np.abs(st) > 1e-9 * np.abs(xn)
        if k == steps - 1 or not more.any():
            break
        idx, C, c = idx[more], C[:, :, more], c[more]
        val, der = _parts(C, xn[more])
    return x, np.abs(step), first


def _outputs(n, coef, lo, hi, row, x, step, pos, status, sel, pr, pts, R, t, err, errr,
             data):
    """The arrays of :func:`solve_fast`: roots (n, 8) and poses (n, 16, ...), the poses
    of each problem first (two mirror poses per assembly root, by increasing root).
    Filled through flat indices (one-dimensional scatters are the cheapest)."""
    f8 = row * 8 + pos
    roots = np.full(n * 8, np.nan)
    steps = np.full(n * 8, np.nan)
    stat = np.full(n * 8, -1)
    roots[f8], steps[f8], stat[f8] = x, step, status
    points = np.full((n * 16, 9), np.nan)
    rot = np.full((n * 16, 9), np.nan)
    trans = np.full((n * 16, 3), np.nan)
    lerr = np.full(n * 16, np.nan)
    lrel = np.full(n * 16, np.nan)
    slot = np.full(n * 8, -1)
    s15 = np.full(n * 8, np.nan)
    count = np.zeros(n, int)
    if sel.size:
        rank = np.arange(pr.size) - np.searchsorted(pr, pr)     # pr is sorted
        slot[pr * 8 + pos[sel]] = 2 * rank
        s15[pr * 8 + rank] = x[sel]
        idx = np.empty(2 * pr.size, int)
        idx[0::2] = pr * 16 + 2 * rank
        idx[1::2] = idx[0::2] + 1
        points[idx] = pts.reshape(-1, 9)
        rot[idx] = R.reshape(-1, 9)
        trans[idx] = t.reshape(-1, 3)
        lerr[idx], lrel[idx] = err.ravel(), errr.ravel()
        count = 2 * np.bincount(pr, minlength=n)
    valid = np.arange(16) < count[:, None]
    return {"coef": coef, "lo": lo, "hi": hi, "roots": roots.reshape(n, 8),
            "status": stat.reshape(n, 8), "step": steps.reshape(n, 8),
            "slot": slot.reshape(n, 8), "count": count, "s15": s15.reshape(n, 8),
            "points": points.reshape(n, 16, 3, 3), "rotation": rot.reshape(n, 16, 3, 3),
            "translation": trans.reshape(n, 16, 3), "leg_error": lerr.reshape(n, 16),
            "leg_error_rel": lrel.reshape(n, 16), "valid": valid, "data": data}


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


def _platform(Q):
    """Frame (3 rows, 3 columns e1 e2 e3, each (N,)) and centroid (3 of (N,)) of the
    platform triangles ``Q`` (N, 3, 3), for :func:`_poses`."""
    Qc = Q.transpose(1, 2, 0)                           # (3 points, 3 coords, N)
    return np.array(_frame(Qc)), Qc.mean(axis=0)


def _poses(platform, pr, pts):
    r"""Rotations and translations carrying the platform triangles onto the placements.

    :math:`R = F_p F_q^T`, :math:`t = \bar p - R \bar q` (as
    :func:`distkin.geometry.poses.pose_from_points`).  ``platform`` from
    :func:`_platform`, ``pr`` (M,) the problem of each placement, ``pts`` (3, 3, 2, M)
    from :func:`~.assembly.assemble_components`.  Returns R (M, 2, 3, 3) and t (M, 2, 3).
    """
    Fq, qc = platform
    Fq = Fq[:, :, pr][:, :, None, :]                    # (3, 3, 1, M)
    qc = qc[:, pr][:, None, :]                          # (3, 1, M)
    P = pts                                             # (3 points, 3 coords, 2, M)
    Fp = _frame(P)
    pc = P.mean(axis=0)
    R = np.empty((3, 3) + P.shape[2:])
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
