r"""The fast tier of the octahedral forward kinematics, batched over problems (float64).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:

1. the generated kernel gives the octic :math:`O(s_{15})` and the quadratic parts of
   eq. (3) for every problem (:mod:`distkin._generated.octic_general`, its scalar form
   compiled over the rows: :func:`.companion.octic_rows`, the same bits as the batched
   numpy form without its temporaries);
2. the real roots come from a projective sign scan of the octic over a fixed grid
   (the algorithm of :mod:`.rootscan`, compiled problem by problem in
   :mod:`.signscan`: brackets refined by safeguarded Halley steps, a Sturm count as a
   check), not from companion eigenvalues -- LAPACK's ``dgeev`` costs
   ~8 µs per 8x8 matrix, most of the target of the whole batched solve.  The scan
   works on the octic rebuilt around the middle of the feasible interval from the
   quadratic parts (:func:`~.closure.shifted_octic`), which keeps the digits the
   expanded coefficients lose to cancellation there;
3. the roots inside the triangle bounds, where the banana tetrahedra are real, are
   polished on eq. (3) itself, on the branch :math:`(\epsilon_1,\epsilon_2)` where it
   vanishes; those where eq. (3) converges slowly (a nearly flat tetrahedron makes its
   branch nearly singular) and the spurious roots by Newton on the factored octic
   :math:`G^2 - 4R_1R_2` (:func:`polish_scan`, compiled, root by root);
4. the careful way, for every problem the scan doubts (:func:`.signscan.scan_many`:
   its count differs from the Sturm count, or a minimum of :math:`|O|` comes within
   rounding of zero) or whose factored Newton moves a root by more than 1e-6 relative
   or does not converge: the single-problem solver's root stage
   (:func:`roots_many`: companion eigenvalues in one numpy call, then the
   direct and careful paths of :mod:`.single`).  The scan tries a doubted problem
   once more on a grid four times finer first (:func:`.signscan.scan_one`); about
   0.5 % of the problems near the Griffis-Duffy example (Sec. VI, legs x (1 + 1 %
   noise)) and 2.6 % of random octahedra (pairs of roots next to a third) are left
   to the careful way;
5. real roots outside the feasible interval, or where a tetrahedron of the bananas has
   negative squared volume, are spurious (complex assemblies) and are rejected;
6. the trilateration sequence of Sec. III, both mirror poses, rotations, translations
   and leg residuals, problem by problem (:func:`.placement.place_many`, compiled),
   written straight into the (N, 16, ...) arrays of :class:`~.forward.BatchResult`.

Every stage is compiled by numba (here, :mod:`.signscan`, :mod:`.single`,
:mod:`.placement`, :mod:`.descartes`; the input checks of float64 arrays in
:func:`.problem.float_problem`): in numpy the scan needed dozens of calls on gathered
arrays (issue 17).  Cost per problem: see BENCHMARKS.md
(``python -m benchmarks octahedral``).

Accuracy: legs reproduced to about 1e-12 relative on well-conditioned problems; the
result states the achieved leg residual of every pose.  Known limitation: two real roots
closer than about 1e-8 relative (two assembly modes about to merge) may be merged into
one, or a nearly real complex pair reported as a double root; the certified tier decides
those cases.  Single problems (:mod:`.single`) use the eigenvalue method directly;
both agree on the roots and their statuses (tests/octahedral).
"""

from __future__ import annotations

import numba
import numpy as np

from .closure import OCTIC
from .companion import _squares, bounds, octic_array, octic_rows
from .single import (CONFIRM, EQ3_STEPS, NEWTON_MAX, SingleSolve, companion, eigen_rows,
                     newton_factored, polish_eq3, roots_from_eigenvalues, solve_fast_single,
                     tet_min)
from .placement import _place_many, place_many
from .problem import REASONS
from .signscan import MAX_ROOTS, K, _workspace, scan_many, scan_one

__all__ = ["solve_fast", "recover_flagged", "solve_scan_single", "scan_single", "scan_window", "polish_scan", "roots_many", "companions", "REASONS"]

_jit = numba.njit(cache=True, _nrt=True)
#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_leaf = numba.njit(cache=True, _nrt=False)


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
    B, Q, L, sides2, legs2 = (np.ascontiguousarray(a, dtype=float)
                              for a in (B, Q, L, sides2, legs2))
    data = octic_rows(sides2, legs2)
    lo, hi, x0, h, c = scan_window(sides2, legs2)
    row, x, step, doubt = scan_many(data, x0, h)
    # polish on eq. (3) or the factored octic (steps 3 and 4 of the module docstring);
    # the problems in doubt go the careful way
    status, x, step = polish_scan(data, row, x, step, lo, hi, c, doubt)
    care = np.flatnonzero(doubt)
    if care.size:
        keep = ~doubt[row]
        dc, cc = data[care], c[care]
        er, ei, nr = eigen_rows(*companions(dc, cc), cc)
        r2, x2, s2, st2 = roots_many(dc, lo[care], hi[care], cc, er, ei, nr)
        row = np.concatenate([row[keep], care[r2]])
        x = np.concatenate([x[keep], x2])
        step = np.concatenate([step[keep], s2])
        status = np.concatenate([status[keep], st2])
    roots, steps, stat, slot, count, s15, P, R, T, E, Er = place_many(
        B, Q, L, sides2, legs2, lo, hi, c, row, x, step, status)
    return {"coef": data[:, OCTIC], "lo": lo, "hi": hi, "roots": roots, "status": stat,
            "step": steps, "slot": slot, "count": count, "s15": s15, "points": P,
            "rotation": R, "translation": T, "leg_error": E, "leg_error_rel": Er,
            "valid": np.arange(16) < count[:, None], "data": data}


#: the proof's verdicts (:data:`.descartes.VERDICTS`) after which :func:`recover_flagged`
#: solves a problem again: two roots too close for a cut, a piece with more roots than
#: found, a piece with none
_RECOVERABLE = (3, 4, 5)
#: the row-wise arrays of :func:`solve_fast` that :func:`recover_flagged` writes back, in
#: the order :func:`.placement.place_many` returns them
_ROWS = ("roots", "step", "status", "slot", "count", "s15", "points", "rotation",
         "translation", "leg_error", "leg_error_rel")


def recover_flagged(B, Q, L, sides2, legs2, raw, eta, verdict, radii):
    """The problems whose answer the proof refused, solved again from the proof's own
    isolation of the roots (issue 17).

    The proof's subdivision (:func:`.descartes.recover`) isolates every real root of the
    exact octic in the feasible interval [a, b] where float64 can (a pair of roots the
    sign scan took for none, in one grid cell: 1 of 2000 random octahedra); those roots,
    with the fast tier's roots outside [a, b] (spurious: no pose), go through the same
    polish and placement as a scanned problem (:func:`polish_scan`,
    :func:`.placement.place_many`) and the same proof
    (:func:`.descartes.vouch_many`).  Only an answer the proof then vouches for
    (verdict 0) replaces the refused one, row by row in ``raw`` (the arrays of
    :func:`solve_fast`), ``verdict`` and ``radii``; the others stay as they were,
    flagged.  Tried for the verdicts of :data:`_RECOVERABLE` only (a miscount); a flat
    face or tetrahedron at a root (verdict 6) or an undecided end (2) stays as it is.
    Returns the indices of the problems replaced."""
    from .descartes import recover, vouch_many
    bad = np.flatnonzero(np.isin(verdict, _RECOVERABLE))
    rows, xs, steps, idx = [], [], [], []
    out = np.empty(8)
    for i in bad:
        cnt, a, b = recover(raw["data"][i], sides2[i], legs2[i], eta[i], raw["lo"][i],
                            raw["hi"][i], out)
        if cnt < 0:
            continue
        old = raw["roots"][i][raw["status"][i] >= 0]
        outside = old[(old < a) | (old > b)]
        x = np.concatenate([out[:cnt], outside])
        rows.append(np.full(x.size, len(idx)))
        xs.append(x)
        steps.append(np.zeros(x.size))
        idx.append(i)
    if not idx:
        return np.empty(0, np.int64)
    idx = np.array(idx)
    Bs, Qs, Ls, s2, l2 = (np.ascontiguousarray(v[idx]) for v in (B, Q, L, sides2, legs2))
    data = np.ascontiguousarray(raw["data"][idx])
    lo, hi, _, _, c = scan_window(s2, l2)
    doubt = np.zeros(idx.size, np.bool_)
    row = np.concatenate(rows)
    status, x, step = polish_scan(data, row, np.concatenate(xs), np.concatenate(steps), lo,
                                  hi, c, doubt)
    new = dict(zip(_ROWS, place_many(Bs, Qs, Ls, s2, l2, lo, hi, c, row, x, step, status)))
    v, r = np.empty(idx.size, np.int64), np.empty((idx.size, 8))
    vouch_many(data, s2, l2, np.ascontiguousarray(eta[idx]), lo, hi, new["roots"],
               new["status"], v, r)
    ok = (v == 0) & ~doubt
    for name in _ROWS:
        raw[name][idx[ok]] = new[name][ok]
    raw["valid"][idx[ok]] = np.arange(16) < new["count"][ok, None]
    verdict[idx[ok]], radii[idx[ok]] = 0, r[ok]
    return idx[ok]


@_jit
def scan_window(sides2, legs2):
    """The triangle bounds lo, hi (N,) of s15 (:func:`.companion.bounds`, the same
    numbers as :func:`~.closure.feasible_interval`), the centre x0 and half-width h (N,)
    of the window that gets half of the scan's grid (the feasible interval, or around c
    when it is empty or tiny), and the scale c (N,) of the relative tolerances (its
    middle, or the mean squared side), problem by problem (:func:`_window`; compiled:
    numpy's ~20 calls on (N,) arrays cost ~0.15 µs per problem, issue 17)."""
    n = sides2.shape[0]
    lo, hi, x0, h, c = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        lo[i], hi[i], x0[i], h[i], c[i] = _window(sides2[i], legs2[i])
    return lo, hi, x0, h, c


@_jit
def _window(s2, l2):
    """:func:`scan_window` of one problem: (lo, hi, x0, h, c)."""
    lo, hi = bounds(s2, l2)
    lo0 = max(lo, 0.0)
    c = 0.5 * (lo0 + hi) if hi > 0 else s2.sum() / 6
    x0, h = (0.5 * (lo0 + hi), 0.5 * (hi - lo0)) if hi > lo0 else (c, 0.5 * c)
    return lo, hi, x0, max(h, 1e-3 * c), c


def solve_scan_single(B, Q, L):
    """One problem the batched tier's way (issue 17): the compiled sign scan, polish and
    placement of :func:`solve_fast` without numpy temporaries, instead of the companion
    eigenvalues of :func:`.single.solve_fast_single` (LAPACK's ``dgeev``, ~14 µs, most
    of a single solve).  A problem the scan doubts goes the careful way, to
    :func:`.single.solve_fast_single` itself, as in the batched tier.  The answer is the
    batched tier's, bit for bit: both entry points compute the squared lengths with the
    same formula (:func:`.problem.sides_into`; until issue 17's last round the batched
    checks summed with numpy's ``einsum`` in another order, and 22 of the 240 family
    problems of :func:`.hardset.hard_families` differed in their last bits, one in its
    count), and every later stage is the same compiled code
    (tests/octahedral/test_octahedral_signscan.py compares the routes).

    The compiled part returns everything in one float64 buffer (:func:`_scan_single`;
    numba boxes each returned array at ~0.3 µs, and this path returned eleven), and the
    fields of the :class:`.single.SingleSolve` are views of it.

    Parameters
    ----------
    B, Q : (3, 3) float64 arrays, L : (6,) (normalised: :func:`.problem.float_single`)

    Returns
    -------
    :class:`.single.SingleSolve` (its ``eigenvalues`` None unless the careful way ran)
    """
    B = np.asarray(B, dtype=float)
    Q = np.asarray(Q, dtype=float)
    L = np.asarray(L, dtype=float)
    doubt, lo, hi, nr, m, buf = _scan_single(B, Q, L)
    if doubt:
        return solve_fast_single(B, Q, L)
    o = 51 + 3 * nr
    o1, o2, o3, o4, o5 = o + m, o + 10 * m, o + 19 * m, o + 22 * m, o + 23 * m
    poses = (buf[o:o1], _SIDES[:m], buf[o1:o2].reshape(m, 3, 3),
             buf[o2:o3].reshape(m, 3, 3), buf[o3:o4].reshape(m, 3), buf[o4:o5],
             buf[o5:o5 + m])
    d = buf[12:51]
    return SingleSolve(d[OCTIC], lo, hi, buf[51:o].reshape(nr, 3), poses, buf[:6],
                       buf[6:12], d, None)


def scan_single(B, Q, L):
    """:func:`solve_scan_single` without the :class:`.single.SingleSolve`: the output of
    the compiled part, ``(lo, hi, nr, m, buffer)`` (:func:`_scan_single`), which the lean
    result of the fast tier reads lazily (:func:`.result._buffer_result`); None when
    the scan doubts the problem (then :func:`.single.solve_fast_single` answers).
    ``B``, ``Q``, ``L``: (3, 3), (3, 3), (6,) float64 arrays or lists (normalised)."""
    doubt, lo, hi, nr, m, buf = _scan_single(np.asarray(B, dtype=float),
                                             np.asarray(Q, dtype=float),
                                             np.asarray(L, dtype=float))
    return None if doubt else (lo, hi, nr, m, buf)


#: the sides of the poses of a single solve: two mirror poses per assembly root, +1 first
_SIDES = np.tile(np.array([1, -1], dtype=np.int64), 8)


@_jit
def _scan_single(B, Q, L):
    """The compiled part of :func:`solve_scan_single`: (doubt, lo, hi, number of roots
    nr, number of poses m, buffer).  The buffer (float64) holds the squared sides (6),
    legs (6), the kernel output (39), the root rows (nr, 3), then over the m poses the
    roots S15, points (m, 3, 3), rotations (m, 3, 3), translations (m, 3), absolute and
    relative leg errors (m each); empty when the scan doubts the problem."""
    s2, l2 = _squares(B, Q, L)
    d = octic_array(s2, l2)
    lo, hi, x0, h, c = _window(s2, l2)
    xs = np.empty(MAX_ROOTS)
    ss = np.empty(MAX_ROOTS)
    n, dbt = scan_one(d, x0, h, np.empty(9), np.empty(4 * K + 1), xs, ss, _workspace(), True)
    one = np.empty((1, 39))
    one[0] = d
    los, his, cs = np.full(1, lo), np.full(1, hi), np.full(1, c)
    doubt = np.full(1, dbt)
    status, x, step = polish_scan(one, np.zeros(n, np.int64), xs[:n], ss[:n], los, his, cs,
                                  doubt)
    if doubt[0]:
        return True, lo, hi, 0, 0, np.empty(0)
    roots = np.empty((1, 8))            # (every element written by _place_many)
    steps = np.empty((1, 8))
    stat = np.empty((1, 8), np.int64)
    slot = np.empty((1, 8), np.int64)
    count = np.empty(1, np.int64)
    s15 = np.empty((1, 8))
    P = np.empty((1, 16, 3, 3))
    R = np.empty((1, 16, 3, 3))
    T = np.empty((1, 16, 3))
    E = np.empty((1, 16))
    Er = np.empty((1, 16))
    _place_many(B.reshape(1, 3, 3), Q.reshape(1, 3, 3), L.reshape(1, 6), s2.reshape(1, 6),
                l2.reshape(1, 6), los, his, cs, np.zeros(n, np.int64), x, step, status,
                roots, steps, stat, slot, count, s15, P, R, T, E, Er)
    nr = 0
    while nr < 8 and stat[0, nr] >= 0:
        nr += 1
    m = count[0]
    o = 51 + 3 * nr
    buf = np.empty(o + 24 * m)
    buf[:6] = s2
    buf[6:12] = l2
    buf[12:51] = d
    for t in range(nr):
        buf[51 + 3 * t], buf[52 + 3 * t], buf[53 + 3 * t] = roots[0, t], steps[0, t], stat[0, t]
        if slot[0, t] >= 0:
            k = slot[0, t]
            buf[o + k] = roots[0, t]
            buf[o + k + 1] = roots[0, t]
    for k in range(m):
        for a in range(3):
            for b in range(3):
                buf[o + m + 9 * k + 3 * a + b] = P[0, k, a, b]
                buf[o + 10 * m + 9 * k + 3 * a + b] = R[0, k, a, b]
            buf[o + 19 * m + 3 * k + a] = T[0, k, a]
        buf[o + 22 * m + k] = E[0, k]
        buf[o + 23 * m + k] = Er[0, k]
    return False, lo, hi, nr, m, buf


@_jit
def polish_scan(data, row, x, step, lo, hi, c, doubt):
    """Classify and polish the roots a sign scan found, one by one (compiled).

    A root outside the triangle bounds (1e-9 c tolerance) is spurious (code 1), one
    where a banana tetrahedron has negative squared volume (below :math:`-10^{-9}c^3`)
    too (code 2); the others are polished on eq. (3) (at most :data:`EQ3_STEPS`
    steps).  A large first step (above 1e-6 relative), or a last one still above 1e-9
    relative (a nearly singular branch: a banana tetrahedron nearly flat), and the
    spurious roots go to Newton on the factored octic; where that does not converge,
    or moves the root by more than 1e-6 relative, the problem is doubted (``doubt``
    set).  Returns status, x, |step| (new arrays)."""
    status = np.zeros(x.size, np.int64)
    xo = x.copy()
    so = np.abs(step)
    _polish_rows(data, row, x, lo, hi, c, doubt, status, xo, so)
    return status, xo, so


@_leaf
def _polish_rows(data, row, x, lo, hi, c, doubt, status, xo, so):
    """The loop of :func:`polish_scan` over the roots, into ``status``, ``xo``, ``so``
    (zeros, a copy of x, |step|)."""
    for k in range(x.size):
        r = row[k]
        d = data[r]
        cr, xi = c[r], x[k]
        tol_x = 1e-9 * cr
        if not (lo[r] - tol_x <= xi <= hi[r] + tol_x):
            status[k] = 1
        else:
            tet = tet_min(d, xi)
            if tet < -1e-9 * cr * cr * cr:
                status[k] = 2
            elif tet < 0:
                continue            # within rounding of flat: the scan's root stands
            else:
                xp, sp, first, taken, how = polish_eq3(d, xi, cr, EQ3_STEPS)
                sz = max(abs(xi), cr)
                if abs(first) <= CONFIRM * sz and how < 2:
                    xo[k], so[k] = xp, abs(sp)
                    continue
        xn, sn, conv, _ = newton_factored(d, xi, cr, xo, 0, NEWTON_MAX)
        if not conv or abs(xn - xi) > 1e-6 * max(abs(xi), cr):
            doubt[r] = True
        if conv:
            xo[k], so[k] = xn, abs(sn)


@_jit
def roots_many(data, lo, hi, c, er, ei, nr):
    """:func:`.single.roots_from_eigenvalues` for several problems (eigenvalues
    (m, 8): real and imaginary parts, ``nr`` of them valid per problem).  Returns
    (row, x, step, status) flat."""
    m = data.shape[0]
    out = np.empty((8, 3))
    rr = np.empty(8 * m, np.int64)
    xx = np.empty(8 * m)
    ss = np.empty(8 * m)
    cc = np.empty(8 * m, np.int64)
    n = 0
    for i in range(m):
        k = roots_from_eigenvalues(data[i], lo[i], hi[i], c[i], er[i, :nr[i]],
                                   ei[i, :nr[i]], out)
        for j in range(k):
            rr[n], xx[n], ss[n], cc[n] = i, out[j, 0], out[j, 1], int(out[j, 2])
            n += 1
    return rr[:n], xx[:n], ss[:n], cc[:n]


@_jit
def companions(data, c):
    """:func:`companion` for several problems: (m, 8, 8), scaled coefficients (m, 9),
    modes (m,)."""
    m = data.shape[0]
    comp = np.empty((m, 8, 8))
    sc = np.empty((m, 9))
    mode = np.empty(m, np.int64)
    for i in range(m):
        comp[i], sc[i], mode[i] = companion(data[i], c[i])
    return comp, sc, mode
