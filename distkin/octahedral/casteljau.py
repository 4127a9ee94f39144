r"""Bernstein subdivision with rigorous bounds by de Casteljau's algorithm: the fast
tier's proof (:mod:`.descartes`) without a rebuild of the octic on every piece.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, eq. (3):
the octic is :math:`H = G^2 - 4R_1R_2`, :math:`G = uE_2 + vE_1 + 2b_1b_2`,
:math:`R_1 = T_{1a}T_{1b}`, :math:`R_2 = T_{2a}T_{2b}`, from ten quadratic parts
:math:`q_i(x) = c_{i0} + x(c_{i1} + x c_{i2})` (the generated kernel's first 30 outputs,
each within a proved :math:`e_{ik}` of the exact coefficient: :func:`.error_bounds.part_errors`).

A cheaper way to the same decisions as :mod:`.descartes` (which falls back to its own
steps when this one does not decide; issue 17):

**Subdivision** (:func:`split`, :func:`count`).  The Bernstein coefficients
   :math:`b_i` of :math:`H` on :math:`[\alpha, \beta]` with bounds :math:`e_i` (from
   :func:`.bounded_octic._bernstein`, unscaled) give those of :math:`[\alpha, x^*]` and
   :math:`[x^*, \beta]`, :math:`x^* = \alpha + \tau(\beta - \alpha)`, by de Casteljau's
   rows :math:`b_i \leftarrow \sigma b_i + \tau b_{i+1}` with floats
   :math:`\sigma + \tau = 1` *exactly* (:math:`\sigma = fl(1 - \hat\tau)`,
   :math:`\tau = 1 - \sigma`, exact by Sterbenz's lemma for :math:`\sigma \ge 1/2`;
   :func:`weights`).  Each row is a convex combination, so the bounds do not grow:
   :math:`e' = \sigma e_i + \tau e_{i+1} + u(|\widehat{\sigma b_i}| +
   |\widehat{\tau b_{i+1}}| + |\hat b'|) + 2\cdot2^{-1074}` (Higham, *Accuracy and
   Stability of Numerical Algorithms*, Sec. 3.1: :math:`|fl(y) - y| \le u|fl(y)|`).  The
   last coefficient of the left part is :math:`H(x^*)` itself: the sign at a cut comes
   with the split.  A split costs ~45 float operations against ~600 for the rebuild of
   the octic from its parts on a sub-interval that :func:`.bounded_octic._count` does; its
   bounds are those of the whole interval, so where the octic is small against its
   size there (a complex pair next to the real axis) it may not decide, and the rebuild
   answers.  The cut point :math:`x^*` is a real number, not a float: it is carried as a
   float and a bound on the difference (:func:`cut_point`).
"""

from __future__ import annotations

import numba
import numpy as np

from .error_bounds import _SAFE, U

__all__ = ["split", "weights", "cut_point", "count", "unscale", "STACK"]

#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_jit = numba.njit(cache=True, _nrt=True)
_leaf = numba.njit(cache=True, _nrt=False)

_TINY = 2.0 ** -1074
#: depth of the subdivision stack of :func:`count`
STACK = 40
_BINOM = np.array([1.0, 8.0, 28.0, 56.0, 70.0, 56.0, 28.0, 8.0, 1.0])


@_leaf
def unscale(Bs, EBs, P, EP):
    r"""Unscaled Bernstein coefficients :math:`b_i = \tilde b_i / \binom8i` (into ``P``,
    bounds into ``EP``) of the scaled ones of :func:`.bounded_octic._bernstein`: one
    division each, :math:`|fl(\tilde b/C) - \tilde b^*/C| \le \tilde e/C + u|\hat b|`
    (the bound's own division rounded up by :math:`1 + 2u`)."""
    for i in range(9):
        v = Bs[i] / _BINOM[i]
        P[i] = v
        EP[i] = _SAFE * ((EBs[i] / _BINOM[i]) * (1.0 + 2.0 * U) + U * abs(v) + _TINY)


@_leaf
def weights(t):
    """Floats (sigma, tau) with sigma + tau = 1 exactly and tau within an ulp or two of
    ``t`` in (0, 1): sigma = fl(1 - t) (in [1/2, 1) for t <= 1/2; exact for t >= 1/2),
    tau = 1 - sigma (exact by Sterbenz's lemma when sigma >= 1/2, and when sigma < 1/2
    it is t itself)."""
    s = 1.0 - t
    return s, 1.0 - s


@_leaf
def cut_point(xa, ea, xb, eb, sigma, tau):
    r"""Float :math:`\hat x` and bound :math:`e` of :math:`x^* = \sigma x_a^* + \tau
    x_b^*` from floats ``xa``, ``xb`` within ``ea``, ``eb`` of the exact ends:
    :math:`e = \sigma e_a + \tau e_b + u(|\widehat{\sigma x_a}| + |\widehat{\tau x_b}|
    + |\hat x|) + 2\cdot 2^{-1074}`, rounded up."""
    p, q = sigma * xa, tau * xb
    x = p + q
    return x, _SAFE * (sigma * ea + tau * eb + U * (abs(p) + abs(q) + abs(x)) + 2 * _TINY)


@_leaf
def split(P, EP, sigma, tau, L, EL, R, ER, w, ew):
    r"""de Casteljau's subdivision (module docstring, 1.): the Bernstein coefficients
    ``P`` (9,) of H on :math:`[\alpha, \beta]` with bounds ``EP`` give those of
    :math:`[\alpha, x^*]` (``L``, ``EL``) and :math:`[x^*, \beta]` (``R``, ``ER``),
    :math:`x^* = \alpha + \tau(\beta - \alpha)`, ``sigma + tau == 1`` exactly
    (:func:`weights`).  ``w``, ``ew`` (9,): work arrays.  ``L`` and ``R`` may not be
    ``P``."""
    for i in range(9):
        w[i] = P[i]
        ew[i] = EP[i]
    L[0], EL[0] = w[0], ew[0]
    R[8], ER[8] = w[8], ew[8]
    for r in range(1, 9):
        for i in range(9 - r):
            a = sigma * w[i]
            b = tau * w[i + 1]
            v = a + b
            ew[i] = (sigma * ew[i] + tau * ew[i + 1] + U * (abs(a) + abs(b) + abs(v))
                     + 2.0 * _TINY)
            w[i] = v
        L[r], EL[r] = w[0], _SAFE * ew[0]
        R[8 - r], ER[8 - r] = w[8 - r], _SAFE * ew[8 - r]


@numba.njit(cache=True, inline="always")
def _changes(B, EB):
    """The largest number of sign changes of B over the signs its bounds allow (a
    coefficient whose bound decides nothing may take either sign; an exact 0 none)."""
    none = -1                        # most changes so far ending on +, on - (-1: none)
    best_p, best_m = none, none
    for i in range(9):
        can_p = B[i] > -EB[i]
        can_m = B[i] < EB[i]
        np_ = nm = none
        if can_p:
            np_ = max(0, best_p, best_m + 1 if best_m != none else none)
        if can_m:
            nm = max(0, best_m, best_p + 1 if best_p != none else none)
        if can_p or can_m:
            best_p, best_m = (np_ if can_p else best_p), (nm if can_m else best_m)
    return max(best_p, best_m, 0)


@numba.njit(cache=True, inline="always")
def _sign_of(v, e):
    return 1 if v > e else (-1 if v < -e else 0)


@_leaf
def count(P, EP, xa, ea, xb, eb, budget, S, X, L, EL, w, ew, found):
    r"""Roots of the exact H in :math:`(x_a^*, x_b^*)` by Descartes' rule on the
    Bernstein coefficients ``P`` (bounds ``EP``) and bisection by :func:`split` at
    :math:`\tau = 1/2` (exact weights).  The end signs are those of ``P[0]``, ``P[8]``
    (the values of H at the ends).

    Returns (count, splits used), and writes the pieces with exactly one root, from
    left to right, into the rows of ``found`` (k, 4) (ends as floats and bounds:
    ia, ea, ib, eb; the first k of them); count -1 when a sign at a cut or an end is
    not decided by its bound, the budget of splits or the stack runs out, or a piece
    gets narrower than 2^-44 of its ends (the rebuild of :mod:`.descartes` decides
    those).  ``S`` (STACK, 18), ``X`` (STACK, 4): the stack (coefficients and bounds;
    ends and their bounds); ``L``, ``EL``, ``w``, ``ew`` (9,): work."""
    if _sign_of(P[0], EP[0]) == 0 or _sign_of(P[8], EP[8]) == 0:
        return -1, 0
    for i in range(9):
        S[0, i], S[0, 9 + i] = P[i], EP[i]
    X[0, 0], X[0, 1], X[0, 2], X[0, 3] = xa, ea, xb, eb
    top, n, used = 1, 0, 0
    scale = max(abs(xa), abs(xb))
    while top > 0:
        top -= 1
        for i in range(9):
            L[i], EL[i] = S[top, i], S[top, 9 + i]
        a, ae, b, be = X[top, 0], X[top, 1], X[top, 2], X[top, 3]
        v = _changes(L, EL)
        sa, sb = _sign_of(L[0], EL[0]), _sign_of(L[8], EL[8])
        if v == 0 or (v == 1 and sa == sb):
            continue
        if v == 1:
            if n < found.shape[0]:
                found[n, 0], found[n, 1], found[n, 2], found[n, 3] = a, ae, b, be
            n += 1
            continue
        if used >= budget or top + 2 > S.shape[0] or b - a <= 2.0 ** -44 * scale:
            return -1, used
        # the left half into row top + 1 (popped first), the right half into row top
        # (free: the node was copied out of it)
        split(L, EL, 0.5, 0.5, S[top + 1, :9], S[top + 1, 9:], S[top, :9], S[top, 9:],
              w, ew)
        used += 1
        if _sign_of(S[top, 0], S[top, 9]) == 0:        # H at the midpoint, undecided
            return -1, used
        m, me = cut_point(a, ae, b, be, 0.5, 0.5)
        X[top, 0], X[top, 1], X[top, 2], X[top, 3] = m, me, b, be
        X[top + 1, 0], X[top + 1, 1], X[top + 1, 2], X[top + 1, 3] = a, ae, m, me
        top += 2
    return n, used
