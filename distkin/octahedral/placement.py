r"""From the roots :math:`s_{15}` to the poses: the trilateration sequence of Sec. III,
compiled (numba), for the fast tier.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:
:math:`P_5` from :math:`P_1, P_2, P_3`, then :math:`P_4` from :math:`P_1, P_2, P_5`,
then :math:`P_6` from :math:`P_1, P_4, P_5`; of the four :math:`(P_4, P_6)` choices the
one that best closes leg 5 (:math:`P_3P_6`) is the assembly.  In the base-adapted frame
(:math:`P_1` at the origin, :math:`P_2` on the x axis, :math:`P_3` in the xy plane) the
first two trilaterations have closed forms and :math:`P_6` is in Gram form (Thomas and
Ros, IEEE T-RO 21(1), 2005), as :func:`.assembly.assemble_exact` does in the precise and
certified tiers (:func:`_assemble`).  The mirror pose of each placement is its
reflection in the base plane.  :func:`place` gives both poses of every assembly root of
one problem: points, rotation :math:`R = \sum_k b_k q_k^T` (:math:`b_k`, :math:`q_k` the
axes of the placed and of the platform triangle, :func:`_frame`), translation
:math:`t = \bar p - R\bar q` and leg residuals; :func:`place_many` does so for the
batched tier, after sorting and merging each problem's roots.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["place", "place_many", "assemble_many", "DUP"]

DUP = 1e-9           # relative distance under which two polished roots are one
_LEG_OK = 1e-6       # relative leg residual under which a placement is accepted
# legs l1..l6 = P1P4, P2P4, P2P5, P3P5, P3P6, P1P6: base and platform point indices
_LEG_BASE = (0, 1, 1, 2, 2, 0)
_LEG_PLAT = (0, 0, 1, 1, 2, 2)

_jit = numba.njit(cache=True, error_model="numpy", _nrt=True)
#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_leaf = numba.njit(cache=True, error_model="numpy", _nrt=False)


@_leaf
def _adapted_base(B, A):
    """The base-adapted frame: axes e1 (along P1P2), e2, e3 written to the rows of
    ``A`` (3, 3); returns |P1P2| and P3's in-plane coordinates (p3x, p3y)."""
    v20, v21, v22 = B[1, 0] - B[0, 0], B[1, 1] - B[0, 1], B[1, 2] - B[0, 2]
    v30, v31, v32 = B[2, 0] - B[0, 0], B[2, 1] - B[0, 1], B[2, 2] - B[0, 2]
    dd = math.sqrt(v20 * v20 + v21 * v21 + v22 * v22)
    A[0, 0], A[0, 1], A[0, 2] = v20 / dd, v21 / dd, v22 / dd
    p3x = v30 * A[0, 0] + v31 * A[0, 1] + v32 * A[0, 2]
    w0, w1, w2 = v30 - p3x * A[0, 0], v31 - p3x * A[0, 1], v32 - p3x * A[0, 2]
    p3y = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    A[1, 0], A[1, 1], A[1, 2] = w0 / p3y, w1 / p3y, w2 / p3y
    A[2, 0] = A[0, 1] * A[1, 2] - A[0, 2] * A[1, 1]
    A[2, 1] = A[0, 2] * A[1, 0] - A[0, 0] * A[1, 2]
    A[2, 2] = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    return dd, p3x, p3y


@_leaf
def _assemble(x, s2, l2, dd, p3x, p3y, out):
    """The trilateration sequence of Sec. III at s15 = x, side +1, in the base-adapted
    frame (P1 at the origin, P2 on the x axis, P3 in the xy plane): writes P4 P5 P6 to
    ``out`` (3, 3); returns the smallest relative squared height met (negative:
    infeasible; -inf when degenerate) and the relative leg-5 residual
    :math:`(|P_3P_6|^2 - s_{36})/(s_{36}+s_{35})` of the chosen (P4, P6), which is
    the candidate of the four with the smallest one.

    Closed forms: P5 from P1 P2 P3 (:math:`X_5, Y_5` linear, Z5 >= 0 from
    its height), P4 from P1 P2 P5 as a rotation about the x axis (P1 P2), P6 from P1 P4
    P5 in Gram form (Thomas and Ros 2005)."""
    s12, s13 = s2[0], s2[1]
    s45, s46, s56 = s2[3], s2[4], s2[5]
    s14, s24, s25, s35, s36, s16 = l2[0], l2[1], l2[2], l2[3], l2[4], l2[5]
    X4 = (s14 - s24 + s12) / (2 * dd)
    r4 = s14 - X4 * X4
    X5 = (x - s25 + s12) / (2 * dd)
    Y5 = (x - s35 + s13 - 2 * p3x * X5) / (2 * p3y)
    h5 = x - X5 * X5 - Y5 * Y5
    Z5 = math.sqrt(h5) if h5 > 0 else 0.0
    rho2 = Y5 * Y5 + Z5 * Z5
    if rho2 == 0:
        return -np.inf, np.inf
    g33 = X5 * X5 + rho2
    K4 = 0.5 * (s14 + g33 - s45) - X4 * X5
    h4 = r4 - K4 * K4 / rho2
    a4 = K4 / rho2
    b4 = math.sqrt(h4 / rho2) if h4 > 0 else 0.0
    w3 = 0.5 * (s16 + g33 - s56)
    s36_35 = s36 + s35
    best, h6best = np.inf, 0.0
    for tau in (1.0, -1.0):
        Y4 = a4 * Y5 - tau * b4 * Z5
        Z4 = a4 * Z5 + tau * b4 * Y5
        g22 = X4 * X4 + Y4 * Y4 + Z4 * Z4
        g23 = X4 * X5 + Y4 * Y5 + Z4 * Z5
        nx = Y4 * Z5 - Z4 * Y5
        ny = Z4 * X5 - X4 * Z5
        nz = X4 * Y5 - Y4 * X5
        G = nx * nx + ny * ny + nz * nz
        if G == 0:
            continue
        w2 = 0.5 * (s16 + g22 - s46)
        al = (w2 * g33 - w3 * g23) / G
        be = (w3 * g22 - w2 * g23) / G
        h6 = s16 - (al * w2 + be * w3)
        k6 = math.sqrt(h6 / G) if h6 > 0 else 0.0
        fx, fy, fz = al * X4 + be * X5, al * Y4 + be * Y5, al * Z4 + be * Z5
        for rho in (1.0, -1.0):
            X6, Y6, Z6 = fx + rho * k6 * nx, fy + rho * k6 * ny, fz + rho * k6 * nz
            dx, dy = X6 - p3x, Y6 - p3y
            r = abs((dx * dx + dy * dy + Z6 * Z6 - s36) / s36_35)
            if r < best:
                best = r
                h6best = h6 / (s16 + g22 + g33)
                out[0, 0], out[0, 1], out[0, 2] = X4, Y4, Z4
                out[2, 0], out[2, 1], out[2, 2] = X6, Y6, Z6
        if best <= 1e-12 and tau > 0:
            break       # leg 5 closes to rounding: the other branch cannot do better
    if best == np.inf:
        return -np.inf, np.inf
    out[1, 0], out[1, 1], out[1, 2] = X5, Y5, Z5
    return min(h5 / (abs(x) + s12 + s13), h4 / (s14 + s12 + g33), h6best), best


@_leaf
def _to_base(B, A, ad, sg, P):
    """P = P1 + X e1 + Y e2 + side Z e3: the adapted rows ``ad`` in the base frame."""
    for r in range(3):
        for m in range(3):
            P[r, m] = (B[0, m] + ad[r, 0] * A[0, m] + ad[r, 1] * A[1, m]
                       + sg * ad[r, 2] * A[2, m])


@_jit
def assemble_many(B, x, s2, l2):
    """The trilateration sequence of Sec. III for M roots, both sides, in the base frame.

    Parameters
    ----------
    B : (M, 3, 3) rows P1 P2 P3 of each root's problem; x : (M,) roots s15;
    s2, l2 : (M, 6) squared sides and legs

    Returns
    -------
    points : (M, 2, 3, 3) rows P4 P5 P6 for side +1 and side -1 of P5
    h2min : (M,) the smallest relative squared height met (negative: infeasible)
    r36 : (M,) relative leg-5 residual of the chosen (P4, P6)
    """
    m = x.size
    pts = np.full((m, 2, 3, 3), np.nan)
    h2 = np.empty(m)
    r36 = np.empty(m)
    ad = np.empty((3, 3))
    A = np.empty((3, 3))
    for i in range(m):
        dd, p3x, p3y = _adapted_base(B[i], A)
        h2[i], r36[i] = _assemble(x[i], s2[i], l2[i], dd, p3x, p3y, ad)
        if h2[i] > -np.inf:
            _to_base(B[i], A, ad, 1.0, pts[i, 0])
            _to_base(B[i], A, ad, -1.0, pts[i, 1])
    return pts, h2, r36


@_leaf
def _frame(P, F):
    """Axes (rows of F) of the triangle P (rows): e1 along p1p2, e3 along the normal;
    False if degenerate."""
    d10, d11, d12 = P[1, 0] - P[0, 0], P[1, 1] - P[0, 1], P[1, 2] - P[0, 2]
    d20, d21, d22 = P[2, 0] - P[0, 0], P[2, 1] - P[0, 1], P[2, 2] - P[0, 2]
    n0 = d11 * d22 - d12 * d21
    n1 = d12 * d20 - d10 * d22
    n2 = d10 * d21 - d11 * d20
    l1 = math.sqrt(d10 * d10 + d11 * d11 + d12 * d12)
    ln = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if l1 == 0 or ln == 0:
        return False
    e10, e11, e12 = d10 / l1, d11 / l1, d12 / l1
    e30, e31, e32 = n0 / ln, n1 / ln, n2 / ln
    F[0, 0], F[0, 1], F[0, 2] = e10, e11, e12
    F[1, 0] = e31 * e12 - e32 * e11
    F[1, 1] = e32 * e10 - e30 * e12
    F[1, 2] = e30 * e11 - e31 * e10
    F[2, 0], F[2, 1], F[2, 2] = e30, e31, e32
    return True


@_jit
def place(B, Q, L, s2, l2, lo, hi, roots, nroots, P, R, T, E, Er, S15, side, slot):
    """Both mirror poses of every assembly root ``roots[:nroots]`` (rows s15, step,
    code) of one problem, written to the pose arrays (16, ...): points P (rows P4 P5
    P6), rotation R, translation T, absolute and relative largest leg errors E, Er, the
    root S15 and the side (+1, -1); ``slot[k]`` is the index of root k's first pose
    (-1 if none).  Roots whose sequence degenerates or whose legs are off by
    :data:`_LEG_OK` relative or more get code 3.  Returns the number of poses."""
    c = np.ascontiguousarray
    return _place(c(B).reshape(1, 3, 3), c(Q).reshape(1, 3, 3), c(L).reshape(1, 6),
                  c(s2).reshape(1, 6), c(l2).reshape(1, 6), np.full(1, lo), np.full(1, hi),
                  roots, nroots, P.reshape(1, 16, 3, 3), R.reshape(1, 16, 3, 3),
                  T.reshape(1, 16, 3), E.reshape(1, 16), Er.reshape(1, 16), S15, side,
                  slot.reshape(1, 8), np.empty((4, 3, 3)), 0)


@_leaf
def _place(B, Q, L, s2, l2, lo, hi, roots, nroots, P, R, T, E, Er, S15, side, slot, ws, i):
    """:func:`place` for problem ``i`` of the batched arrays (B, Q (n, 3, 3), L, s2, l2
    (n, 6), lo, hi (n,), P, R (n, 16, 3, 3), T (n, 16, 3), E, Er (n, 16), slot (n, 8)),
    with a work array ``ws`` (4, 3, 3).  Indexed, not sliced: numba counts a reference
    to every view it makes (two calls to the runtime each), and this ran per pose."""
    A, Fq, ad, Fb = ws[0], ws[1], ws[2], ws[3]
    dd, p3x, p3y = _adapted_base(B[i], A)
    _frame(Q[i], Fq)
    qc0 = (Q[i, 0, 0] + Q[i, 1, 0] + Q[i, 2, 0]) / 3.0
    qc1 = (Q[i, 0, 1] + Q[i, 1, 1] + Q[i, 2, 1]) / 3.0
    qc2 = (Q[i, 0, 2] + Q[i, 1, 2] + Q[i, 2, 2]) / 3.0
    np_ = 0
    lo0 = max(lo[i], 0.0)
    for k in range(nroots):
        slot[i, k] = -1
        if roots[k, 2] != 0:
            continue
        x = min(max(roots[k, 0], lo0), hi[i])
        h2, _ = _assemble(x, s2[i], l2[i], dd, p3x, p3y, ad)
        ok = h2 >= -1e-8
        for sd in range(2):
            j = np_ + sd
            sg = 1.0 - 2.0 * sd
            if not ok:
                break
            for r in range(3):          # (:func:`_to_base`, written out)
                for m in range(3):
                    P[i, j, r, m] = (B[i, 0, m] + ad[r, 0] * A[0, m] + ad[r, 1] * A[1, m]
                                     + sg * ad[r, 2] * A[2, m])
            if not _frame(P[i, j], Fb):
                ok = False
                break
            for r in range(3):
                for m in range(3):
                    R[i, j, r, m] = (Fb[0, r] * Fq[0, m] + Fb[1, r] * Fq[1, m]
                                     + Fb[2, r] * Fq[2, m])
            for r in range(3):
                T[i, j, r] = ((P[i, j, 0, r] + P[i, j, 1, r] + P[i, j, 2, r]) / 3.0
                              - (R[i, j, r, 0] * qc0 + R[i, j, r, 1] * qc1
                                 + R[i, j, r, 2] * qc2))
            e, er = 0.0, 0.0
            for t in range(6):
                b, p = _LEG_BASE[t], _LEG_PLAT[t]
                dx = P[i, j, p, 0] - B[i, b, 0]
                dy = P[i, j, p, 1] - B[i, b, 1]
                dz = P[i, j, p, 2] - B[i, b, 2]
                et = abs(math.sqrt(dx * dx + dy * dy + dz * dz) - L[i, t])
                e = max(e, et)
                er = max(er, et / L[i, t])
            E[i, j], Er[i, j] = e, er
            if not er < _LEG_OK:
                ok = False
            S15[j], side[j] = roots[k, 0], 1 - 2 * sd
        if ok:
            slot[i, k] = np_
            np_ += 2
        else:
            roots[k, 2] = 3
    return np_



def place_many(B, Q, L, s2, l2, lo, hi, c, row, x, step, status):
    """Sort the roots (row, x, step, status) of every problem, merge those closer than
    :data:`DUP` relative, keep at most 8, and place both poses of each assembly root
    (:func:`place`).  Returns the arrays of :func:`.batched.solve_fast`: roots, steps,
    status (n, 8), slot (n, 8), count (n,), s15 (n, 8), points, rotation (n, 16, 3, 3),
    translation (n, 16, 3), leg errors absolute and relative (n, 16).  (The arrays are
    allocated empty; :func:`_place_many`, compiled, writes every element, the padding
    too (NaN, -1), problem by problem while the row is in cache: numpy's fill first
    cost ~0.8 µs per problem, issue 17.)

    The float arrays are views of one block (~3 KiB per problem), the integer ones of
    another: glibc serves an allocation above its mmap threshold with fresh pages and
    gives them back on free, and raises the threshold to the size of a freed block.
    Eight arrays of up to 2.3 MiB each (N = 2000) left the threshold below what one
    call frees at once, so every call faulted ~6 MiB of fresh zeroed pages in again
    (~0.6 µs per problem, a third of the placement); after one call with the block the
    next calls reuse heap memory.  A process that has freed a larger block before was
    already fast; N beyond ~10^4 (blocks above glibc's 32 MiB cap) gets fresh pages
    either way.  (BENCHMARKS.md, octahedral section.)"""
    n = B.shape[0]
    roots, steps, s15, P, R, T, E, Er = _views(np.empty(n * _FLOATS), n, _FLOAT_SHAPES)
    stat, slot, count = _views(np.empty(n * 17, np.int64), n, ((8,), (8,), ()))
    out = (roots, steps, stat, slot, count, s15, P, R, T, E, Er)
    _place_many(B, Q, L, s2, l2, lo, hi, c, row, x, step, status, *out)
    return out


#: the float arrays of :func:`place_many` per problem: roots, steps, s15 (8 each), points,
#: rotations (16, 3, 3), translations (16, 3), leg errors absolute and relative (16)
_FLOAT_SHAPES = ((8,), (8,), (8,), (16, 3, 3), (16, 3, 3), (16, 3), (16,), (16,))
_FLOATS = sum(math.prod(shape) for shape in _FLOAT_SHAPES)


def _views(block, n, shapes):
    """Consecutive C-contiguous views (n, *shape) of the 1-D ``block``, one per shape."""
    views, o = [], 0
    for shape in shapes:
        size = n * math.prod(shape)
        views.append(block[o:o + size].reshape((n,) + shape))
        o += size
    return views


@_jit
def _place_many(B, Q, L, s2, l2, lo, hi, c, row, x, step, status, roots, steps, stat, slot,
                count, s15, P, R, T, E, Er):
    """:func:`place_many` into its output arrays (every element written: the padding is
    NaN, and -1 in ``stat`` and ``slot``)."""
    n = B.shape[0]
    S = np.empty(16)
    side = np.empty(16, np.int64)
    # the roots grouped by problem, in their given order within each (a counting
    # sort: stable, as a merge sort would be, in O(m + n))
    m = row.size
    start = np.zeros(n + 1, np.int64)
    for t in range(m):
        start[row[t] + 1] += 1
    for t in range(n):
        start[t + 1] += start[t]
    fill = start[:n].copy()
    order = np.empty(m, np.int64)
    for t in range(m):
        order[fill[row[t]]] = t
        fill[row[t]] += 1
    _place_rows(B, Q, L, s2, l2, lo, hi, c, x, step, status, roots, steps, stat, slot, count,
                s15, P, R, T, E, Er, start, order, np.empty((16, 3)), np.empty((8, 3)),
                np.empty(16, np.int64), np.empty((4, 3, 3)), S, side)


@_leaf
def _place_rows(B, Q, L, s2, l2, lo, hi, c, x, step, status, roots, steps, stat, slot, count,
                s15, P, R, T, E, Er, start, order, buf, rt, srt, ws, S, side):
    """The loop of :func:`_place_many` over the problems (the roots of problem i are
    ``order[start[i]:start[i + 1]]``; the rest: work arrays)."""
    nan = np.nan
    for i in range(B.shape[0]):
        k, j = start[i], start[i + 1]
        nb = min(j - k, 16)
        for t in range(nb):
            q = order[k + t]
            buf[t, 0], buf[t, 1], buf[t, 2] = x[q], abs(step[q]), status[q]
        # by increasing root, stable (insertion sort of at most 16)
        for t in range(nb):
            u = t
            while u > 0 and (buf[srt[u - 1], 0] > buf[t, 0] or (
                    math.isnan(buf[srt[u - 1], 0]) and not math.isnan(buf[t, 0]))):
                srt[u] = srt[u - 1]
                u -= 1
            srt[u] = t
        nr = 0
        for t in range(nb):
            u = srt[t]
            v0 = buf[u, 0]
            if nr and abs(v0 - rt[nr - 1, 0]) <= DUP * max(abs(v0), c[i]):
                continue
            if nr == 8:
                break
            rt[nr, 0], rt[nr, 1], rt[nr, 2] = v0, buf[u, 1], buf[u, 2]
            nr += 1
        np_ = 0
        if nr:
            np_ = _place(B, Q, L, s2, l2, lo, hi, rt, nr, P, R, T, E, Er, S, side, slot, ws,
                         i)
        count[i] = np_
        # the padding (a rejected placement also leaves partial writes in the two slots
        # after the poses)
        for t in range(np_, 16):
            for a in range(3):
                T[i, t, a] = nan
                for b in range(3):
                    P[i, t, a, b] = nan
                    R[i, t, a, b] = nan
            E[i, t], Er[i, t] = nan, nan
        a = 0
        for t in range(nr):
            roots[i, t], steps[i, t], stat[i, t] = rt[t, 0], rt[t, 1], int(rt[t, 2])
            if slot[i, t] >= 0:
                s15[i, a] = rt[t, 0]
                a += 1
        for t in range(nr, 8):
            roots[i, t], steps[i, t], stat[i, t], slot[i, t] = nan, nan, -1, -1
        for t in range(a, 8):
            s15[i, t] = nan
