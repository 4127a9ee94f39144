r"""The projective sign scan of :mod:`.rootscan`, compiled, one problem at a time (numba).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:
the fast batched tier needs every real root of N octics :math:`O(s_{15})`.
:mod:`.rootscan` finds them with a few dozen numpy operations over all problems (a grid
of :data:`.rootscan.K` angles as one matrix product, brackets refined by safeguarded
Halley steps, a Sturm count as a check); its docstring has the algorithm.  Here the same
algorithm runs as one compiled loop over the problems, without numpy temporaries
(issue 17: the numpy version cost ~4 µs per problem, most of it in the overhead of
gathering and scattering small arrays):

* the octic rebuilt around the middle of the feasible interval from the quadratic parts
  of eq. (3) (:func:`_shifted`, the operations of :func:`~.closure.shifted_octic` in the
  same order), and the sizes of its terms only where a minimum of :math:`|f|` is tested;
* the grid values :math:`f(\theta_k) = \sum_j q_j s_k^j c_k^{8-j}`, the sign changes,
  the local minima of :math:`|f|` that dip through zero, the Halley refinement and the
  Sturm count, operation for operation as in :mod:`.rootscan`.

One step beyond :mod:`.rootscan`: a problem the grid doubts is scanned once more on a
grid four times finer (:data:`FINE`, same checks) before it is given up to the careful
way (eigenvalues, :mod:`.batched`): on 2000 random octahedra that leaves 51 of the 172
doubted problems (BENCHMARKS.md has the cost of both).  Whatever the route, the proof of
:mod:`.descartes` then vouches for the answer or flags it.

Agreement with :mod:`.rootscan` (``fine=False``): every operation is the same except
the grid values, which numpy computes by a BLAS matrix product (another order of
summation, fused multiply-adds): they differ in the last bits.  They only choose the
brackets and the starts of the refinement: the same problems are doubted, the same
number of roots found, within 1e-9 relative (7e-10 observed; the refinement stops at
steps of 1e-11 in u), and after the polish on eq. (3) within the proved radii
(tests/octahedral/test_octahedral_signscan.py).  A grid value within rounding of zero
could in principle move a sign change by one cell; the Sturm check then doubts the
problem as before.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .rootscan import _ITER, _SHALLOW, K, grid

__all__ = ["scan_many", "scan_one", "MAX_ROOTS", "GRID", "FINE"]

#: roots kept per problem (the octic has at most 8; more means noise: the problem is
#: doubted)
MAX_ROOTS = 16

_jit = numba.njit(cache=True, error_model="numpy", _nrt=True)
#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``): it counts a reference to every array argument
#: and view (an atomic increment and decrement each, through two calls into the
#: runtime), ~9 % of the batched solve before (issue 17's last round, perf-oct-4); the
#: arithmetic, and so every bit of the answers, is the same
_leaf = numba.njit(cache=True, error_model="numpy", _nrt=False)

#: the grid of :mod:`.rootscan` (K cells), and one four times finer for the second try
#: on the problems the first one doubts (:func:`scan_many`)
GRID = grid(K)
FINE = grid(4 * K)


@_leaf
def _shifted(d, x0, h, absolute, q, ws):
    """Coefficients (ascending in u) of :math:`O(x_0 + hu)` into ``q`` (9,): the
    quadratic parts shifted, then :math:`G^2 - 4R_1R_2` multiplied out (or, with
    ``absolute``, :math:`|G|^2 + 4|R_1R_2|` term by term: the sizes of the terms), as
    :func:`~.closure.shifted_octic` computes them.  ``ws``: the work arrays of
    :func:`_workspace`."""
    P, pr, G, g2, r2 = ws[0], ws[1], ws[2], ws[3], ws[4]
    for i in range(10):
        c0, c1, c2 = d[3 * i], d[3 * i + 1], d[3 * i + 2]
        p0 = c0 + x0 * (c1 + x0 * c2)
        p1 = h * (c1 + 2 * x0 * c2)
        p2 = (h * h) * c2
        if absolute:
            p0, p1, p2 = abs(p0), abs(p1), abs(p2)
        P[i, 0], P[i, 1], P[i, 2] = p0, p1, p2
    pr[:] = 0.0
    for t, (a, b) in enumerate(((0, 5), (1, 4), (2, 3), (6, 7), (8, 9))):
        for i in range(3):
            for j in range(3):
                pr[t, i + j] += P[a, i] * P[b, j]
    for k in range(5):
        G[k] = pr[0, k] + pr[1, k] + 2 * pr[2, k]
    g2[:] = 0.0
    r2[:] = 0.0
    for i in range(5):
        for j in range(5):
            g2[i + j] += G[i] * G[j]
            r2[i + j] += pr[3, i] * pr[4, j]
    f = 4.0 if absolute else -4.0
    for k in range(9):
        q[k] = g2[k] + f * r2[k]


@_jit
def _workspace():
    """Work arrays: the shifted parts (10, 3), their products (5, 5), G (5,), G^2 and
    R1 R2 (9,) each, the sizes of the terms (9,), the dipping minima (K, 5), the
    derivative polynomial (9,), the flags of the grid cells (:func:`_flags`), the
    brackets to refine (3 K, 5) (:func:`_refine_all`), the Sturm sequence (4, 9)."""
    return (np.empty((10, 3)), np.empty((5, 5)), np.empty(5), np.empty(9), np.empty(9),
            np.empty(9), np.empty((4 * K, 5)), np.empty(9), np.empty(4 * K, np.uint8),
            np.empty((12 * K, 5)), np.empty((4, 9)))


@_leaf
def _horner(P, v):
    """Value and derivative of the octic P (9,), ascending, at v (as :mod:`.rootscan`)."""
    p = P[8] * v + P[7]
    dp = P[8]
    for j in range(6, -1, -1):
        dp = dp * v + p
        p = p * v + P[j]
    return p, dp


#: :func:`_halley`, inlined into its callers (numba ``inline='always'``: one chain of
#: operations in each, as written out before)
_step = numba.njit(cache=True, error_model="numpy", _nrt=False, inline="always")


@_step
def _halley(P, a, b, x, ppos, step, it, iters, tol):
    """One step of :func:`_refine` on P from x in [a, b]: returns (a, b, x, step, stop),
    ``stop`` when the step shows convergence (or no progress)."""
    p = P[8] * x + P[7]
    dp = P[8]
    d2 = 0.0
    for j in range(6, -1, -1):
        d2 = d2 * x + dp
        dp = dp * x + p
        p = p * x + P[j]
    if (p > 0) == ppos:
        a = x
    else:
        b = x
    xn = x - p * dp / (dp * dp - p * d2)
    if not (xn - a) * (xn - b) <= 0:
        xn = 0.5 * (a + b)
    st = abs(xn - x)
    stop = (it >= 1 and it < iters - 1
            and not (st > tol and (st < 0.9 * step or st > 1e-8)))
    return a, b, xn, st, stop


@_leaf
def _refine(P, a, b, pa, iters, x, tol):
    """One bracket of :func:`.rootscan._refine`: Halley from x in [a, b] (either order),
    P(a) of sign ``pa``; bisection when a step leaves the bracket.  Returns (root, last
    step)."""
    step = abs(b - a)
    ppos = pa > 0
    for it in range(iters):
        a, b, x, step, stop = _halley(P, a, b, x, ppos, step, it, iters, tol)
        if stop:
            break
    return x, step


@_leaf
def _refine_all(q, rev, tasks, nt, x0, h, xs, ss):
    """Refine the brackets ``tasks[:nt]`` (rows a, b, sign at a, start, in u (1) or w
    (0): on ``q`` or on ``rev``) by :func:`_refine` and emit their roots in that order
    (:func:`_emit`); returns the count (> xs.size: overflow, at the first root that
    did not fit, as when they were refined one by one).  Two brackets at a time
    (:func:`_refine2`, the same operations on each): a Halley step is one chain of
    dependent operations, so two interleaved take about the time of one
    (perf-oct-4)."""
    n = 0
    t = 0
    while t < nt:
        u1 = tasks[t, 4] > 0
        if t + 1 < nt:
            u2 = tasks[t + 1, 4] > 0
            v1, s1, v2, s2 = _refine2(q if u1 else rev, tasks[t, 0], tasks[t, 1], tasks[t, 2],
                                      tasks[t, 3], q if u2 else rev, tasks[t + 1, 0],
                                      tasks[t + 1, 1], tasks[t + 1, 2], tasks[t + 1, 3],
                                      _ITER, 1e-11)
            n = _emit(v1, s1, u1, x0, h, xs, ss, n)
            if n > xs.size:
                return n
            n = _emit(v2, s2, u2, x0, h, xs, ss, n)
            t += 2
        else:
            v1, s1 = _refine(q if u1 else rev, tasks[t, 0], tasks[t, 1], tasks[t, 2], _ITER,
                             tasks[t, 3], 1e-11)
            n = _emit(v1, s1, u1, x0, h, xs, ss, n)
            t += 1
        if n > xs.size:
            return n
    return n


@_leaf
def _refine2(P, a, b, pa, x, Q, c, d, qc, y, iters, tol):
    """:func:`_refine` of two brackets at once, [a, b] on P from x and [c, d] on Q from
    y, each step for step as alone (a bracket that has stopped is left as it is).
    Returns (root, last step) of each."""
    step, ppos, done = abs(b - a), pa > 0, False
    stq, qpos, doneq = abs(d - c), qc > 0, False
    for it in range(iters):
        if not done:
            a, b, x, step, done = _halley(P, a, b, x, ppos, step, it, iters, tol)
        if not doneq:
            c, d, y, stq, doneq = _halley(Q, c, d, y, qpos, stq, it, iters, tol)
        if done and doneq:
            break
    return x, step, y, stq


@_leaf
def _sturm_count(q, st):
    """:func:`.rootscan._sturm_count` of one octic q (9,), ascending; ``st``: a (4, 9)
    work array (its rows were four small allocations per problem)."""
    big = 0.0
    for j in range(9):
        big = max(big, abs(q[j]))
    a, b, lc, r = st[0], st[1], st[2], st[3]
    for j in range(9):
        a[j] = q[8 - j] / big
    for j in range(8):
        b[j] = a[j] * (8 - j)
    lc[0], lc[1] = a[0], b[0]
    na = 9
    for d in range(7, 0, -1):              # a: degree d+1 (na = d + 2), b: d
        al = a[0] / b[0]
        ga = (a[1] - al * b[1]) / b[0]
        nr = na - 2
        for i in range(nr):
            r[i] = a[i + 2] - ga * b[i + 1]
        for i in range(nr - 1):
            r[i] -= al * b[i + 2]
        rmax = 0.0
        for i in range(nr):
            rmax = max(rmax, abs(r[i]))
        for i in range(na - 1):
            a[i] = b[i]
        for i in range(nr):
            b[i] = -r[i] / rmax
        na -= 1
        lc[9 - d] = b[0]
    count = 0
    for k in range(9):
        if not math.isfinite(lc[k]) or abs(lc[k]) < 1e-12:
            return -1
    for k in range(8):
        p0, p1 = lc[k] > 0, lc[k + 1] > 0
        m0 = p0 if (8 - k) % 2 == 0 else not p0
        m1 = p1 if (7 - k) % 2 == 0 else not p1
        count += (m0 != m1) - (p0 != p1)
    return count


@_leaf
def _scan_one(d, x0, h, q, F, xs, ss, ws, g):
    """Stages 1 and 2 of :mod:`.rootscan` for one problem (kernel output ``d``, centre
    ``x0``, half-width ``h``; work arrays ``ws``, :func:`_workspace`, ``F`` of at least
    k + 1; the grid ``g`` of :func:`.rootscan.grid`, k cells): writes the roots (units of x) and their last steps to
    ``xs``, ``ss`` in the order of :func:`.rootscan._scan` (sign changes by cell, then
    the left and the right roots of every dipping minimum); returns their number and
    whether the problem is doubted (a shallow minimum, the Sturm count differs, or
    more than :data:`MAX_ROOTS`).  ``q`` (9,): a work array."""
    _THETA, _V, _U_PT, _INSIDE, _V_LO, _V_HI = g
    K = _V_LO.size
    _DTHETA = np.pi / K
    _shifted(d, x0, h, False, q, ws)
    for k in range(K + 1):             # (j outer: the same sums, vectorised over k)
        F[k] = 0.0
    for j in range(9):
        qj = q[j]
        for k in range(K + 1):
            F[k] += qj * _V[j, k]
    rev = q[::-1]
    qa, mins, g, fl, tasks = ws[5], ws[6], ws[7], ws[8], ws[9]
    _flags(F, K, fl)
    have_qa = False
    doubt = False
    nt = 0                  # tasks: the brackets (a, b, sign at a, start, in u), in order
    # sign changes, by cell
    for kc in range(K):
        if not fl[kc] & 1:
            continue
        fa, fb = F[kc], F[kc + 1]
        pc = fa >= 0
        fc = F[kc + 2] if kc < K - 1 else F[kc + 1 - K]
        lin = fa / (fa - fb)
        quad = fa * fc / ((fb - fa) * (fb - fc)) + 2.0 * fa * fb / ((fc - fa) * (fc - fb))
        t = quad if (quad > 0) and (quad < 1) else lin
        t0 = _THETA[kc] + _DTHETA * t
        ins = _INSIDE[kc]
        v0 = math.tan(t0) if ins else 1.0 / math.tan(t0)
        if not math.isfinite(v0):
            v0 = 0.0
        tasks[nt, 0], tasks[nt, 1], tasks[nt, 2] = _V_LO[kc], _V_HI[kc], 1.0 if pc else -1.0
        tasks[nt, 3], tasks[nt, 4] = v0, 1.0 if ins else 0.0
        nt += 1
    # local minima of |f| without a sign change that dip through zero
    nm = 0                              # mins: (a, m, b, sign, in u) of dipping minima
    for kc in range(K):
        if not fl[kc] & 2:
            continue
        k1 = kc + 1
        pd = F[k1] >= 0
        kd = k1 if k1 < K else 0
        usp = _U_PT[kd]
        P = q if usp else rev
        tl, tr = _THETA[kd] - _DTHETA, _THETA[kd] + _DTHETA
        a = math.tan(tl) if usp else 1.0 / math.tan(tl)
        b = math.tan(tr) if usp else 1.0 / math.tan(tr)
        if not math.isfinite(a):
            a = 0.0
        if not math.isfinite(b):
            b = 0.0
        for m in range(9):
            g[m] = ((m + 1) * P[m + 1] if m < 8 else 0.0) + ((m - 9) * P[m - 1] if m else 0.0)
        ga, _ = _horner(g, a)
        gb, _ = _horner(g, b)
        if (ga > 0) == (gb > 0):
            continue
        m, _ = _refine(g, a, b, 1.0 if ga > 0 else -1.0, _ITER, 0.5 * (a + b), 1e-7)
        pm, _ = _horner(P, m)
        if (pm > 0) != pd:
            mins[nm, 0], mins[nm, 1], mins[nm, 2] = a, m, b
            mins[nm, 3], mins[nm, 4] = 1.0 if pd else -1.0, 1.0 if usp else 0.0
            nm += 1
            continue
        # a minimum within the rounding of the coefficients
        if not have_qa:
            _shifted(d, x0, h, True, qa, ws)
            have_qa = True
        av = abs(m)
        A = qa if usp else qa[::-1]
        size = A[8] * av + A[7]
        for j in range(6, -1, -1):
            size = size * av + A[j]
        if abs(pm) <= _SHALLOW * size:
            doubt = True
    for side in range(2):
        for i in range(nm):
            a, m, b, fd = mins[i, 0], mins[i, 1], mins[i, 2], mins[i, 3]
            if side == 0:
                tasks[nt, 0], tasks[nt, 1], tasks[nt, 2], tasks[nt, 3] = a, m, fd, 0.5 * (a + m)
            else:
                tasks[nt, 0], tasks[nt, 1], tasks[nt, 2], tasks[nt, 3] = m, b, -fd, 0.5 * (m + b)
            tasks[nt, 4] = mins[i, 4]
            nt += 1
    n = _refine_all(q, rev, tasks, nt, x0, h, xs, ss)
    if n > xs.size:
        return xs.size, True
    if _sturm_count(q, ws[10]) != n:
        doubt = True
    return n, doubt


@_leaf
def _flags(F, K, fl):
    """The cells of the grid values ``F`` (K + 1,) that the two loops of
    :func:`_scan_one` stop at, into ``fl`` (K,): bit 1 a sign change (``F[k]``, ``F[k +
    1]``), bit 2 a local minimum of abs(F) at k + 1 without a sign change on either side
    (the tests of those loops, cell K - 1 wrapping round to ``F[0]``, ``F[1]``).  One
    pass without branches, which LLVM vectorises (perf-oct-4: the tests in the loops
    were ~0.2 µs per problem, mostly mispredicted branches); the same cells, so the
    same roots."""
    for kc in range(K - 2):
        f0, f1, f2 = F[kc], F[kc + 1], F[kc + 2]
        a0, a1, a2 = abs(f0), abs(f1), abs(f2)
        s0, s1, s2 = f0 >= 0, f1 >= 0, f2 >= 0
        dip = (a1 < a0) & (not a2 < a1) & (s0 == s1) & (s1 == s2)
        fl[kc] = (1 if s0 != s1 else 0) + (2 if dip else 0)
    for kc in range(max(K - 2, 0), K):
        k1 = kc + 1
        k2 = k1 + 1 if k1 < K else 1
        a0 = abs(F[kc])
        a1 = abs(F[k1]) if k1 < K else abs(F[0])
        a2 = abs(F[k2]) if k2 < K else abs(F[0])
        s0, s1 = F[kc] >= 0, F[k1] >= 0
        s2 = F[k1 + 1] >= 0 if k1 < K else F[1] >= 0
        dip = a1 < a0 and not a2 < a1 and s0 == s1 and s1 == s2
        fl[kc] = (1 if s0 != s1 else 0) + (2 if dip else 0)


@_leaf
def scan_one(d, x0, h, q, F, xs, ss, ws, fine):
    """:func:`_scan_one` on the grid of :mod:`.rootscan`, and once more on :data:`FINE`
    when that doubts the problem and ``fine`` is set.  ``F``: (4 K + 1,)."""
    k, dbt = _scan_one(d, x0, h, q, F, xs, ss, ws, GRID)
    if dbt and fine:
        k, dbt = _scan_one(d, x0, h, q, F, xs, ss, ws, FINE)
    return k, dbt


@_leaf
def _emit(v, st, ins, x0, h, xs, ss, n):
    """Append the root v (u = tan or w = cot space) as x = x0 + h u, with its step in
    units of x, when finite; returns the new count (> xs.size: overflow)."""
    u = v if ins else 1.0 / v
    dxdv = (1.0 if ins else 1.0 / (v * v)) * h
    if not math.isfinite(u):
        return n
    if n >= xs.size:
        return n + 1
    xs[n] = x0 + h * u
    ss[n] = st * dxdv
    return n + 1


@_jit
def scan_many(data, x0, h, fine=True):
    """:func:`.rootscan.real_roots` of the octics of N problems, compiled.

    Parameters
    ----------
    data : (N, 39) kernel output (quadratic parts of eq. (3) first)
    x0, h : (N,) centre and half-width (h > 0) of the feasible interval of s15
    fine : bool
        Scan the problems that the grid of :mod:`.rootscan` doubts once more on a grid
        four times finer (:data:`FINE`), with the same checks; those it still doubts
        are doubted.  False: :func:`.rootscan.real_roots` exactly.

    Returns
    -------
    row : (M,) int, x : (M,) roots, step : (M,) last steps (units of x), doubt : (N,)
        bool, as :func:`.rootscan.real_roots` (roots grouped by problem).
    """
    n = data.shape[0]
    row = np.empty(n * MAX_ROOTS, np.int64)
    x = np.empty(n * MAX_ROOTS)
    step = np.empty(n * MAX_ROOTS)
    doubt = np.zeros(n, np.bool_)
    m = _scan_rows(data, x0, h, fine, row, x, step, doubt, np.empty(9),
                   np.empty(4 * K + 1), _workspace())
    return row[:m], x[:m], step[:m], doubt


@_leaf
def _scan_rows(data, x0, h, fine, row, x, step, doubt, q, F, ws):
    """The loop of :func:`scan_many` over the problems, into its arrays (``q``, ``F``,
    ``ws``: work arrays); returns the number of roots."""
    m = 0
    for i in range(data.shape[0]):
        xs = x[m:m + MAX_ROOTS]
        k, dbt = scan_one(data[i], x0[i], h[i], q, F, xs, step[m:m + MAX_ROOTS], ws, fine)
        for j in range(k):
            row[m + j] = i
        doubt[i] = dbt
        m += k
    return m
