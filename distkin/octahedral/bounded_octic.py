r"""The octic of the octahedral manipulator with running rounding bounds: the bounded
evaluations, Bernstein expansions and counts the fast tier's proof is made of
(:mod:`.descartes`, steps 3, 4, 6 and 8 of its docstring).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, eq. (3):
:math:`H = G^2 - 4R_1R_2`, :math:`G = uE_2 + vE_1 + 2b_1b_2`,
:math:`R_1 = T_{1a}T_{1b}`, :math:`R_2 = T_{2a}T_{2b}`, from ten quadratic parts
:math:`q_i(x) = c_{i0} + x(c_{i1} + x c_{i2})` (``d[3i:3i+3]``, each coefficient within
``e[3i:3i+3]`` of the exact one: :func:`.error_bounds.part_errors`).  Every value comes
with a bound by the rules of :func:`.error_bounds._add` and :func:`.error_bounds._mul`
(Higham, *Accuracy and Stability of Numerical Algorithms*, Sec. 3.3), except a part at a
point, whose bound is a priori (``e[30:60]``: :func:`.error_bounds.part_bounds_into`;
perf-oct-5: a bounded evaluation of H ~60 -> ~32 ns, no wider than the running bound
by more than ~10 %, the same values); the plain-float
helpers at the end (:func:`_slope`, :func:`_h_slope`, :func:`_bracketed`) give guesses
and approximations only, never a decision.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .casteljau import _changes
from .error_bounds import _SAFE, UNDERFLOW, U, _add, _mul

#: the compiled helpers are the proof's own (called by :mod:`.descartes`, with their
#: leading underscores); the module exports its one constant
__all__ = ["MIN_WIDTH"]

#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_jit = numba.njit(cache=True, _nrt=True)
_leaf = numba.njit(cache=True, _nrt=False)

#: relative width under which a piece is not split further
MIN_WIDTH = 2.0 ** -44
_MIN_WIDTH = MIN_WIDTH
#: binomials C(8 - j, i - j) of the scaled Bernstein transform
_BINOM = np.array([[math.comb(8 - j, i - j) if j <= i else 0 for j in range(9)]
                   for i in range(9)], dtype=np.float64)

# (the smallest helpers called per evaluation -- _part, _value, _pmul, _range, _changes,
# _slope -- are inlined into their callers, ``inline="always"``: the same operations in
# the same order, the same bits, ~0.25 µs less per batched problem; inlining the larger
# ones too (_sign, _status, _first_radius) saved ~0.05 µs more but cost ~16 s more of
# numba compilation on each first call of a machine, issue 17)

@numba.njit(cache=True, inline="always")
def _part(d, e, i, x):
    """Quadratic part i at x (float): value (Horner's rule) and its a priori bound
    (:func:`.error_bounds.part_bounds_into`: the coefficients ``e[30:]``)."""
    ax = abs(x)
    t = x * d[3 * i + 2]
    t = d[3 * i + 1] + t
    t = x * t
    f0, f1, f2 = e[30 + 3 * i], e[31 + 3 * i], e[32 + 3 * i]
    w = 1.0 + ax
    return (d[3 * i] + t,
            (f0 + ax * (f1 + ax * f2)) * (1.0 + 8.0 * U) + (w * w) * UNDERFLOW)


@numba.njit(cache=True, inline="always")
def _value(d, e, x):
    """H(x) = G^2 - 4 T1a T1b T2a T2b, G = u E2 + v E1 + 2 b1 b2, and its bound."""
    u, eu = _part(d, e, 0, x)
    v, ev = _part(d, e, 1, x)
    b1, eb1 = _part(d, e, 2, x)
    b2, eb2 = _part(d, e, 3, x)
    E1, eE1 = _part(d, e, 4, x)
    E2, eE2 = _part(d, e, 5, x)
    g, eg = _mul(u, eu, E2, eE2)
    p, ep = _mul(v, ev, E1, eE1)
    g, eg = _add(g, eg, p, ep)
    p, ep = _mul(b1, eb1, b2, eb2)
    g, eg = _add(g, eg, 2.0 * p, 2.0 * ep)
    t1, et1 = _part(d, e, 6, x)
    t2, et2 = _part(d, e, 7, x)
    r1, er1 = _mul(t1, et1, t2, et2)
    t1, et1 = _part(d, e, 8, x)
    t2, et2 = _part(d, e, 9, x)
    r2, er2 = _mul(t1, et1, t2, et2)
    r, er = _mul(r1, er1, r2, er2)
    g, eg = _mul(g, eg, g, eg)
    h, eh = _add(g, eg, -4.0 * r, 4.0 * er)
    return h, _SAFE * eh


@_leaf
def _sign(d, e, x):
    """The proved sign of H(x): +1, -1, or 0 when the bound does not decide it."""
    h, eh = _value(d, e, x)
    return 1 if h > eh else (-1 if h < -eh else 0)


@numba.njit(cache=True, inline="always")
def _pmul(W, a, b, out):
    """Rows out (values) and out + 1 (bounds) of W: the product (degree 4) of the
    quadratics in rows a and b (values; bounds in the next rows)."""
    for k in range(5):
        W[out, k] = 0.0
        W[out + 1, k] = 0.0
    for i in range(3):
        for j in range(3):
            p, ep = _mul(W[a, i], W[a + 1, i], W[b, j], W[b + 1, j])
            W[out, i + j], W[out + 1, i + j] = _add(W[out, i + j], W[out + 1, i + j], p, ep)


@_leaf
def _bernstein(d, e, alpha, beta, W, B, EB):
    r"""Scaled Bernstein coefficients :math:`\tilde b_i = \binom8i b_i` (9,) of H on
    :math:`[\alpha, \beta]`, with bounds: the parts shifted to
    :math:`x = \alpha + w t`, multiplied out, then
    :math:`\tilde b_i = \sum_{j \le i}\binom{8-j}{i-j} h_j`.  ``W``: a (30, 9)
    work array (rows 2i, 2i + 1: part i's values and bounds; then G, R1, R2, H)."""
    w = beta - alpha
    ew = U * abs(w) * (1.0 + 4.0 * U)      # |fl(beta - alpha) - (beta - alpha)|
    ww, eww = _mul(w, ew, w, ew)
    for i in range(10):
        c0, c1, c2 = d[3 * i], d[3 * i + 1], d[3 * i + 2]
        e0, e1, e2 = e[3 * i], e[3 * i + 1], e[3 * i + 2]
        t1, et1 = _mul(alpha, 0.0, c2, e2)
        t2, et2 = _add(c1, e1, t1, et1)
        t3, et3 = _mul(alpha, 0.0, t2, et2)
        W[2 * i, 0], W[2 * i + 1, 0] = _add(c0, e0, t3, et3)
        t5, et5 = _add(c1, e1, 2.0 * t1, 2.0 * et1)
        W[2 * i, 1], W[2 * i + 1, 1] = _mul(w, ew, t5, et5)
        W[2 * i, 2], W[2 * i + 1, 2] = _mul(ww, eww, c2, e2)
    # G = u E2 + v E1 + 2 b1 b2 (rows 20, 21), R1 = T1a T1b (24, 25), R2 = T2a T2b (26, 27)
    _pmul(W, 0, 10, 20)
    _pmul(W, 2, 8, 22)
    for k in range(5):
        W[20, k], W[21, k] = _add(W[20, k], W[21, k], W[22, k], W[23, k])
    _pmul(W, 4, 6, 22)
    for k in range(5):
        W[20, k], W[21, k] = _add(W[20, k], W[21, k], 2.0 * W[22, k], 2.0 * W[23, k])
    _pmul(W, 12, 14, 24)
    _pmul(W, 16, 18, 26)
    # H = G^2 - 4 R1 R2 (rows 28, 29); G^2 with each cross product once, doubled
    for k in range(9):
        W[28, k] = 0.0
        W[29, k] = 0.0
    for i in range(5):
        for j in range(5):
            r, er = _mul(W[24, i], W[25, i], W[26, j], W[27, j])
            if j >= i:
                p, ep = _mul(W[20, i], W[21, i], W[20, j], W[21, j])
                f = 1.0 if j == i else 2.0
                r, er = _add(f * p, f * ep, -4.0 * r, 4.0 * er)
            else:
                r, er = -4.0 * r, 4.0 * er
            W[28, i + j], W[29, i + j] = _add(W[28, i + j], W[29, i + j], r, er)
    # scaled Bernstein coefficients: the coefficients of sum_j h_j y^j (1 + y)^(8 - j),
    # by Q <- Q (1 + y) + h_j y^j for j = 1 .. 8 from Q = h_0 (additions only)
    for i in range(9):
        B[i], EB[i] = 0.0, 0.0
    B[0], EB[0] = W[28, 0], W[29, 0]
    for j in range(1, 9):
        B[j], EB[j] = _add(W[28, j], W[29, j], B[j - 1], EB[j - 1])
        for i in range(j - 1, 0, -1):
            B[i], EB[i] = _add(B[i], EB[i], B[i - 1], EB[i - 1])
    for i in range(9):
        EB[i] *= _SAFE


@_leaf
def _count(d, e, alpha, beta, sa, sb, budget, W, B, EB, stack, signs, found):
    """Roots of the exact H in (alpha, beta), whose ends have proved signs sa, sb
    (+-1), by Descartes' rule and bisection: (count, the last isolating piece lo, hi,
    Bernstein evaluations used); count -1 when the budget or the width runs out.
    ``W`` (30, 9), ``B``, ``EB`` (9,), ``stack`` (64, 2) and ``signs`` (64, 2): work
    arrays; the isolating pieces, from left to right, into the rows (lo, hi) of
    ``found`` (k, >= 2) (the first k of them)."""
    stack[0, 0], stack[0, 1], signs[0, 0], signs[0, 1] = alpha, beta, sa, sb
    top = 1
    count, used = 0, 0
    ia, ib = alpha, beta
    scale = max(abs(alpha), abs(beta))
    while top > 0:
        top -= 1
        a, b, s_a, s_b = stack[top, 0], stack[top, 1], signs[top, 0], signs[top, 1]
        if used >= budget:
            return -1, ia, ib, used
        _bernstein(d, e, a, b, W, B, EB)
        used += 1
        v = _changes(B, EB)
        if v == 0 or (v == 1 and s_a == s_b):
            continue
        if v == 1:
            if count < found.shape[0]:
                found[count, 0], found[count, 1] = a, b
            count += 1
            ia, ib = a, b
            continue
        if b - a <= _MIN_WIDTH * scale or top + 2 > stack.shape[0]:
            return -1, ia, ib, used
        # split where H has a proved sign, near the middle
        m, sm = a, 0
        for f in (0.5, 0.4375, 0.5625, 0.375, 0.625):
            m = a + f * (b - a)
            sm = _sign(d, e, m)
            if sm != 0:
                break
        if sm == 0:
            return -1, ia, ib, used
        stack[top, 0], stack[top, 1], signs[top, 0], signs[top, 1] = m, b, sm, s_b
        stack[top + 1, 0], stack[top + 1, 1] = a, m
        signs[top + 1, 0], signs[top + 1, 1] = s_a, sm
        top += 2
    return count, ia, ib, used


@numba.njit(cache=True, inline="always")
def _slope(d, x):
    """H'(x) in plain float (a guess for :func:`_first_radius`, no bound)."""
    q = np.empty(10)
    dq = np.empty(10)
    for i in range(10):
        q[i] = d[3 * i] + x * (d[3 * i + 1] + x * d[3 * i + 2])
        dq[i] = d[3 * i + 1] + 2.0 * x * d[3 * i + 2]
    G = q[0] * q[5] + q[1] * q[4] + 2.0 * q[2] * q[3]
    dG = (dq[0] * q[5] + q[0] * dq[5] + dq[1] * q[4] + q[1] * dq[4]
          + 2.0 * (dq[2] * q[3] + q[2] * dq[3]))
    R1, R2 = q[6] * q[7], q[8] * q[9]
    dR = (dq[6] * q[7] + q[6] * dq[7]) * R2 + R1 * (dq[8] * q[9] + q[8] * dq[9])
    return 2.0 * G * dG - 4.0 * dR


@_jit
def _first_radius(d, e, r, lim):
    """A first guess of the radius around r within which H changes sign: twice
    (|H(r)| + its bound) / |H'(r)| (a guess only: the signs at r -+ rho are then
    proved, and rho grown while they are not)."""
    h, eh = _value(d, e, r)
    slope = abs(_slope(d, r))
    rho = 2.0 * (abs(h) + eh) / slope if slope > 0 else lim
    return min(max(rho, max(abs(r), 1e-300) * 2.0 ** -52), lim)


@numba.njit(cache=True, inline="always")
def _range(d, e, i, x, rho):
    r"""Proved sign of quadratic part i over [x - rho, x + rho]: +1, -1 or 0.  The value
    and the slope at x with their a priori bounds (:func:`_part`; the slope
    :math:`c_1 + 2xc_2` is within :math:`f_1 + 2|x|f_2` of the exact one, its rounding
    :math:`\gamma_2(|c_1| + 2|x||c_2|)` included), then
    :math:`|q'(x)|\rho + |c_2|\rho^2` (the exact coefficients' sizes)."""
    c1, c2 = d[3 * i + 1], d[3 * i + 2]
    f1, f2 = e[31 + 3 * i], e[32 + 3 * i]
    q, eq = _part(d, e, i, x)
    ax = abs(x)
    w = 1.0 + ax
    dq = c1 + 2.0 * (x * c2)
    edq = (f1 + 2.0 * ax * f2) * (1.0 + 8.0 * U) + (w * w) * UNDERFLOW
    spread = ((abs(dq) + edq) * rho + (abs(c2) + e[3 * i + 2]) * rho * rho) * (1.0 + 8.0 * U)
    bound = _SAFE * (eq + spread)
    return 1 if q > bound else (-1 if q < -bound else 0)


@_leaf
def _status(d, e, x, rho):
    """Proved status over [x - rho, x + rho]: 0 assembly, 1 spurious (a face not a real
    triangle), 2 spurious (a negative tetrahedron), -1 undecided."""
    su, sv = _range(d, e, 0, x, rho), _range(d, e, 1, x, rho)
    if su > 0 or sv > 0:
        return 1
    neg, und = False, False
    for i in range(6, 10):
        s = _range(d, e, i, x, rho)
        if s < 0:
            neg = True
        elif s == 0:
            und = True
    if neg:
        return 2
    if su < 0 and sv < 0 and not und:
        return 0
    return -1


@_leaf
def _grow(d, e, r, rho, lim, lo_in, hi_in):
    """Step 6's radius: from ``rho``, times 16 while below ``lim``, until H has proved
    opposite signs at the floats r -+ rho, both strictly inside (lo_in, hi_in).
    Returns (found, rho)."""
    while rho < lim:
        xl, xr = r - rho, r + rho          # (floats: the signs are proved there)
        if not (lo_in < xl and xr < hi_in):
            break
        sl, sr = _sign(d, e, xl), _sign(d, e, xr)
        if sl != 0 and sr != 0 and sl != sr:
            return True, rho
        rho *= 16.0
    return False, rho


@_jit
def _h_slope(d, x):
    """H(x) and H'(x) in plain float (no bound), from the quadratic parts."""
    q0, q1, q2, q3, q4 = (d[0] + x * (d[1] + x * d[2]), d[3] + x * (d[4] + x * d[5]),
                          d[6] + x * (d[7] + x * d[8]), d[9] + x * (d[10] + x * d[11]),
                          d[12] + x * (d[13] + x * d[14]))
    q5, q6, q7, q8, q9 = (d[15] + x * (d[16] + x * d[17]), d[18] + x * (d[19] + x * d[20]),
                          d[21] + x * (d[22] + x * d[23]), d[24] + x * (d[25] + x * d[26]),
                          d[27] + x * (d[28] + x * d[29]))
    G = q0 * q5 + q1 * q4 + 2.0 * q2 * q3
    R1, R2 = q6 * q7, q8 * q9
    return G * G - 4.0 * R1 * R2, _slope(d, x)


@_jit
def _bracketed(d, xl, xr):
    """A root of H in the float bracket [xl, xr] (signs of H opposite at its ends, or
    nearly): Newton from the middle, bisection whenever a step leaves the bracket."""
    hl, _ = _h_slope(d, xl)
    if hl == 0:
        hr, _ = _h_slope(d, xr)
        hl = -hr
    x = 0.5 * (xl + xr)
    for _ in range(200):
        h, dh = _h_slope(d, x)
        if h == 0:
            return x
        if (h > 0) == (hl > 0):
            xl = x
        else:
            xr = x
        xn = x - h / dh if dh != 0 else 0.5 * (xl + xr)
        if not xl < xn < xr:
            xn = 0.5 * (xl + xr)
        if abs(xn - x) <= 2.0 ** -51 * abs(x) or xr - xl <= 2.0 ** -51 * abs(x):
            return xn
        x = xn
    return x


@_leaf
def _outside(d, e, a, b, lo, hi, roots, radii):
    """Step 8 of :mod:`.descartes`: a proved radius for each root outside [a, b]
    (increasing ``roots``; ``radii`` written where H has proved opposite signs at
    r -+ rho), within half the gaps to its neighbours and off [a, b], so that the
    exact roots so found are distinct from each other and from those in [a, b]."""
    n = roots.size
    scale = max(abs(lo), abs(hi))
    for k in range(n):
        r = roots[k]
        if a <= r <= b:
            continue
        lo_in = 0.5 * (roots[k - 1] + r) if k > 0 else -np.inf
        hi_in = 0.5 * (r + roots[k + 1]) if k + 1 < n else np.inf
        if a <= b:
            if r < a:
                hi_in = min(hi_in, a)
            else:
                lo_in = max(lo_in, b)
        lim = min(r - lo_in, hi_in - r, max(abs(r), scale))
        found, rho = _grow(d, e, r, _first_radius(d, e, r, lim), lim, lo_in, hi_in)
        if found:
            radii[k] = rho * (1.0 + 4.0 * U) + 4.0 * U * abs(r)
