r"""A proof, in float64, that the fast tier counted and classified the assembly roots right.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:
the assembly modes are the real roots :math:`x = s_{15}` of the octic
:math:`H = G^2 - 4R_1R_2` (eq. (3) squared twice, :mod:`.octic`) at which the faces
:math:`D(5,4,1)`, :math:`D(3,5,1)` are real triangles (:math:`u, v < 0`) and the four
banana tetrahedra have non-negative squared volume (:math:`T \ge 0`).  Every one lies
in the feasible interval :math:`[lo, hi]` of the triangle inequalities through
:math:`P_1P_5` (:func:`~.closure.feasible_interval`; a real face and a non-negative
tetrahedron embed in space, so every face of it is a real triangle).

:func:`vouch` checks a fast answer -- its real roots in and near that interval and
their status -- against the *exact* octic of the exact input data, with nothing but
float64 arithmetic whose rounding is bounded rigorously.  It answers "proved" or "cannot
vouch"; it never guesses.

Why this test, and not the others
---------------------------------
Three were weighed (issue 14), on the easy set and the near-coplanar, near-line and
clustered families of :mod:`.hardset` (:func:`~.hardset.hard_families`):

* the calibrated estimate it replaces (:math:`K = 400` times a measured noise) was not a
  bound: its few sample points missed clusters of four roots within 1.6e-7 that float64
  had turned into two complex pairs, and ``auto`` kept answers with too few poses;
* inclusion discs (Gerschgorin / Braess-Hadeler: discs of radius
  :math:`8|H(z_i)/(a_8\prod_{j\ne i}(z_i-z_j))|` around the eight eigenvalues, real
  ones replaced by the polished roots) need every complex eigenvalue to a fraction of
  its distance to the real axis, but the eigenvalues come from the monomial
  coefficients, which lose up to 1e7 eps to cancellation.  Even with the residuals
  :math:`H(z_i)` computed exactly (60 digits: more than a rigorous float version can
  have), they decided 198 of the 200 easy problems and 91 of the 240 family problems,
  where this test proves 200 and 117; and the batched tier has no eigenvalues (its sign
  scan is what makes it fast);
* a Sturm or Descartes count on the monomial coefficients inherits the same 1e7 eps;
  **Descartes' rule of signs in the Bernstein basis on the octic rebuilt over each
  sub-interval from the quadratic parts of eq. (3)** (the form the fast tier polishes
  with, which keeps those digits) needs neither eigenvalues nor the monomial
  coefficients, serves the single and the batched tier alike, and costs a few
  microseconds.  This is the test.

The argument
------------
1. **Exact data.**  The fast tier works on the squared lengths :math:`\hat s_i`,
   computed in float from the (power-of-two normalised, :mod:`.scaling`) inputs with
   relative error at most :math:`\eta` (``eta``: :math:`\gamma_5` for float inputs,
   more when the inputs were themselves rounded).  The exact problem is the one with
   the exact squared lengths :math:`s_i`.
2. **The quadratic parts.**  The generated kernel's rounding is bounded from its own
   source (:mod:`distkin.codegen.rounding`: depth, degree and the magnitude kernel
   ``parts_magnitude``): each coefficient :math:`\hat c_k` is within :math:`e_k` of the
   exact :math:`c_k(s)` (:func:`part_errors`).
3. **Running error bounds.**  Everything after that -- the parts shifted to a
   sub-interval :math:`[\alpha, \beta]`, their products, :math:`H`, its Bernstein
   coefficients, point values -- is computed as pairs (value, bound) with the rules
   :math:`|\widehat{a+b} - (a+b)| \le e_a + e_b + u|\widehat{a+b}|` and
   :math:`|\widehat{ab} - ab| \le |\hat a|e_b + |\hat b|e_a + e_ae_b + u|\widehat{ab}| +
   2^{-1074}` (Higham, *Accuracy and Stability of Numerical Algorithms*, Sec. 3.3).  The
   bounds are sums of products of non-negative floats over fewer than 10^4 operations,
   so their own rounding is below a relative :math:`10^4u < 2^{-30}`; every bound is
   multiplied by :math:`1 + 2^{-30}` when used (:data:`_SAFE`).  A part at a point is
   bounded a priori instead (:func:`.error_bounds.part_bounds_into`, perf-oct-5).
4. **Counting** (Descartes' rule of signs in the Bernstein basis).  With
   :math:`t = (x-\alpha)/(\beta-\alpha)` and :math:`t = y/(1+y)`,
   :math:`H = \sum_i \tilde b_i\, t^i(1-t)^{8-i} = (1+y)^{-8}\sum_i \tilde b_i y^i`:
   the roots of :math:`H` in :math:`(\alpha, \beta)` are the positive roots of
   :math:`\sum_i \tilde b_i y^i`, so by Descartes' rule their number, with
   multiplicity, is at most the number of sign changes of the
   :math:`\tilde b_i = \binom8i b_i` (:func:`_bernstein`).  Where a coefficient's sign is
   not decided by its bound, the largest number of changes over both signs is taken
   (a zero coefficient adds none).  At most 0 changes: no root.  At most 1, and
   :math:`H(\alpha)`, :math:`H(\beta)` proved of opposite signs: exactly one root, and
   simple.  At most 1 and the same signs: none (an even number below two).  More: the
   interval is split at a point where :math:`H` has a proved sign.
5. **The interval.**  :math:`[a, b] = [lo - \delta, hi + \delta]` with :math:`\delta`
   the rounding bound of the float triangle bounds (:func:`margin`): every exact
   assembly root lies in it.  It is cut at :math:`a`, at points between consecutive
   fast roots and at :math:`b`, each cut point with :math:`H` of proved sign; each piece
   must hold exactly one exact root and the fast tier's root in it.
6. **Classification.**  Around each fast root :math:`r` a radius :math:`\rho` is grown
   until :math:`H(r\pm\rho)` have proved opposite signs: the piece's one root lies in
   :math:`[r-\rho, r+\rho]`, and there :math:`u, v` and the tetrahedra are bounded
   (value at :math:`r`, plus :math:`|q'(r)|\rho + |c_2|\rho^2`).  Proved
   :math:`u, v < 0` and all :math:`T > 0`: an assembly mode; some proved
   :math:`u > 0`, :math:`v > 0` or :math:`T < 0`: spurious; anything else: cannot vouch
   (a flat tetrahedron or a face at the edge of assemblability).
7. **The verdict** is "proved" when every piece holds one root, every status agrees
   with the fast tier's, and no fast assembly root lies outside :math:`[a, b]`.  Then
   the fast tier's assembly roots are, one to one, the exact problem's, each within its
   :math:`\rho` (a rigorous radius), and so are its poses (two per root; the residual
   of each pose is stated separately).
8. **The roots outside** :math:`[a, b]` (spurious: no pose), with ``tight`` (the
   single solve, a batched ``result(i)``) and a proved answer: around each, a radius
   grown as in step 6 until :math:`H(r\pm\rho)` have proved opposite signs, inside
   half the gaps to the neighbouring roots found and off :math:`[a, b]`
   (:func:`.bounded_octic._outside`): an exact real root lies within :math:`\rho`
   of each, a different one for each, none in :math:`[a, b]` (where no :math:`\rho`
   is found the root keeps its estimate; on the 240 family problems of :mod:`.hardset`
   all 307 such roots of proved answers got one, none exceeded).

What it does not claim: the count of *spurious* real roots outside :math:`[a, b]`
(they give no pose: step 8 proves that each root found there is near a real root of
the exact octic, not that there are no others); the digits of a pose beyond its stated
leg residual.  That count is float64's, and it goes wrong where the octic has a multiple root out there: a root
of multiplicity m moves by about :math:`(\epsilon\,\mathrm{cond})^{1/m}` under
rounding and splits into a cluster (the Griffis-Duffy geometry with six legs of 1: a
root of the exact octic at -71 comes out as six roots within 1.6e-3, 8 real roots
reported where the certified tier proves 4).  Such an answer is not let through: when
two consecutive real roots outside :math:`[a, b]` lie within :data:`CLUSTER` relative
of each other, the verdict is 10 (not proved) however the assembly roots fared, so
that the fast tier flags the problem and ``auto`` escalates it (a screen, not a proof:
it finds split multiple roots, nothing else: on 20000 random octahedra at scales
1e-3..1e3, half with perturbed legs, it refused 6 answers whose counts were right
(and none of 2000 random octahedra, of the 200 easy and the 240 family problems of
:mod:`.hardset`); on 400 Griffis-Duffy problems with six equal legs of 0.5..30 it
refused 33 more, 29 of them miscounted, and let one miscount through: two exact double
roots reported once each, in an empty feasible interval, which float64 cannot tell
from a simple root).

Two routes to steps 4-6 (issue 17).  :func:`_vouch_split` first: the Bernstein
coefficients on the whole of :math:`[a, b]` once (their first and last are
:math:`H(a)`, :math:`H(b)`, so the end signs come with them); when the whole count and
the signs at the cuts decide, one root per piece as in step 5; otherwise the pieces,
and their bisection, by de Casteljau's subdivision of those coefficients with running
bounds (:mod:`.casteljau`: ~45 operations a split instead of ~600 for a rebuild).  Where
that does not decide (the whole interval's bounds are too wide near a cluster or a
complex pair next to the axis: 15 of 2000 random octahedra), :func:`_vouch_bisect`
rebuilds the octic on every piece (the route above, word for word) and its verdict
stands.  Both are rigorous; the first only decides fewer problems.  In the batched
form (``tight=False``) the radius around a root whose piece does not decide its status
starts at :math:`2^{-32}|r|` instead of the first-order guess (one bounded evaluation
less; the batched radii are the pieces' half-widths wherever those decide anyway).

The bounded evaluations, expansions and counts are in :mod:`.bounded_octic`, the
subdivision in :mod:`.casteljau`.  :func:`recover` isolates the roots in
:math:`[a, b]` with the same machinery when an answer is refused, so that the batched
tier can solve such a problem again (:func:`.batched.recover_flagged`).

Cost: one more kernel evaluation (the magnitudes, written into a work array by the
generated ``parts_magnitude``), then ~1.0-1.2 µs per problem on random octahedra in the
batched form (perf-oct-5), compiled; see ``python -m benchmarks octahedral`` and
``accuracy``.
"""

from __future__ import annotations

import numba
import numpy as np

from .bounded_octic import (_bernstein, _bracketed, _count, _first_radius, _grow, _outside,
                            _sign, _status)
from .casteljau import STACK, _changes, _sign_of, count, cut_point, split, unscale, weights
from .error_bounds import (ETA_FLOAT, LEAF_BOUND, U, error_cache, eta_rounded, margin,
                           part_bounds_into, part_errors)
from .verdicts import NOT_CHECKED, SPLIT_STEPS, THIN_TRIANGLE, VERDICTS

__all__ = ["vouch", "vouch_many", "recover", "vouch_rows", "vouch_buffer", "part_errors",
           "margin", "eta_rounded", "VERDICTS", "NOT_CHECKED", "THIN_TRIANGLE", "SPLIT_STEPS",
           "CLUSTER", "U", "ETA_FLOAT", "LEAF_BOUND"]

#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_jit = numba.njit(cache=True, _nrt=True)
_leaf = numba.njit(cache=True, _nrt=False)

_BUDGET = 48                  # Bernstein evaluations per problem, beyond one per piece
#: consecutive real roots outside [a, b] closer than this, relative, make verdict 10
CLUSTER = 1e-4


@_jit
def vouch(d, s2, l2, eta, lo, hi, roots, codes, radii, tight=True):
    r"""Prove the fast tier's assembly roots (module docstring).

    Parameters
    ----------
    d : (>= 30,) kernel output (quadratic parts of eq. (3) first) at the float squared
        lengths ``s2`` (s12 s13 s23 s45 s46 s56), ``l2`` (s14 .. s16), all in
        [LEAF_MIN, LEAF_BOUND] (else the verdict is 1)
    eta : relative error bound of those squared lengths against the exact ones
    lo, hi : the float triangle bounds of s15 (:func:`.single.bounds`)
    roots : (n,) the fast tier's real roots, increasing (any status; two that are not
        strictly increasing make verdict 3)
    codes : (n,) their status codes (0 assembly, 1 and 2 spurious, 3 rejected)
    radii : (n,) output: the proved radius of each root (inf where none: outside
        [a, b] unless ``tight``, and wherever the verdict is not 0)
    tight : bool
        Grow the radius around each root from its first-order error (step 6 of the
        module docstring; about 1 µs per root).  False (the batched tier) classifies
        over the isolating piece first, and tightens only where that does not decide;
        the radii are then the pieces' half-widths.  True also gives the roots
        outside [a, b] their radii (step 8); False leaves them inf.

    Returns
    -------
    int, a key of :data:`VERDICTS` (0: proved)
    """
    return _vouch(d, s2, l2, eta, lo, hi, roots, codes, radii, tight, _workspace())


@_jit
def _workspace():
    """Work arrays of :func:`_vouch`: (W (30, 9), B (9,), EB (9,), stack (64, 2),
    stack signs (64, 2), cuts (9,), cut signs (9,)), then those of
    :func:`_vouch_split`: coefficients and bounds (6, 9) (P, EP, the piece, its bounds,
    two rows of work), the subdivision stack (STACK, 18) and its ends (STACK, 4), the
    cuts' bounds (9,), the isolating pieces (9, 4); the parts' error bounds and a
    priori coefficients (60,), the factors of :func:`.error_bounds.part_bounds_into` (61,)."""
    return (np.empty((30, 9)), np.empty(9), np.empty(9), np.empty((64, 2)),
            np.empty((64, 2), np.int64), np.empty(9), np.empty(9, np.int64),
            np.empty((6, 9)), np.empty((STACK, 18)), np.empty((STACK, 4)), np.empty(9),
            np.empty((9, 4)), np.empty(60), error_cache())


@_leaf
def _vouch(d, s2, l2, eta, lo, hi, roots, codes, radii, tight, ws):
    """:func:`vouch` with its work arrays ``ws`` (:func:`_workspace`): the bounds of the
    parts, the interval [a, b] and the fast roots in it (steps 2 and 5), then the
    subdivision route (:func:`_vouch_split`), and where it does not prove the answer
    the rebuild route (:func:`_vouch_bisect`), whose verdict then stands."""
    e = ws[12]
    part_bounds_into(d, s2, l2, eta, e, ws[13])
    for k in range(roots.size):
        radii[k] = np.inf
    verdict, a, b, first, m = _interval(e, s2, l2, eta, lo, hi, roots, codes)
    if verdict > 0:
        return verdict
    if verdict < 0 and _vouch_split(d, e, a, b, first, m, roots, codes, radii, tight,
                                    ws) != 0:
        for k in range(roots.size):
            radii[k] = np.inf
        verdict = _vouch_bisect(d, e, a, b, first, m, roots, codes, radii, tight, ws)
        if verdict != 0:
            return verdict
    if _clustered(roots, a, b):
        return 10
    if tight:
        _outside(d, e, a, b, lo, hi, roots, radii)
    return 0


@_leaf
def _clustered(roots, a, b):
    """Two consecutive roots (increasing), not both in [a, b] (a > b: none is), within
    :data:`CLUSTER` relative of each other: float64's count of the spurious real roots
    is not reliable (verdict 10, module docstring)."""
    for k in range(roots.size - 1):
        x, y = roots[k], roots[k + 1]
        if a <= x <= b and a <= y <= b:
            continue
        if y - x <= CLUSTER * max(abs(x), abs(y)):
            return True
    return False


@_leaf
def _interval(e, s2, l2, eta, lo, hi, roots, codes):
    """Steps 2 and 5 of the module docstring: (verdict, a, b, first, m), the verdict
    -1 unless it is decided here (1: the bounds' range; 8: an assembly root outside
    [a, b]; 5: more than eight roots in it; 0: no assembly possible and none claimed);
    the fast roots in [a, b] are ``roots[first:first + m]``."""
    n = roots.size
    for k in range(30):
        if not e[k] < np.inf:
            return 1, 0.0, 0.0, 0, 0
    delta = margin(s2, l2, eta)
    a, b = lo - delta, hi + delta
    if a > b:
        # the triangle inequalities exclude every assembly, rounding included
        for k in range(n):
            if codes[k] == 0:
                return 8, a, b, 0, 0
        return 0, a, b, 0, 0
    if lo > hi:
        a, b = hi - delta, lo + delta
    # the fast roots inside [a, b]; an assembly root outside it is wrong
    first, last = n, -1
    for k in range(n):
        if a <= roots[k] <= b:
            first = min(first, k)
            last = max(last, k)
        elif codes[k] == 0:
            return 8, a, b, 0, 0
    m = last - first + 1 if last >= first else 0
    if m > 8:
        return 5, a, b, first, m    # more than the octic's eight roots: some twice
    return -1, a, b, first, m


@_leaf
def _vouch_split(d, e, a, b, first, m, roots, codes, radii, tight, ws):
    """Steps 4-7 of the module docstring on [a, b] and the m fast roots from index
    ``first`` in it, the cheap way (issue 17): the Bernstein coefficients of H on the
    whole of [a, b] once (:func:`_bernstein`; their first and last are H(a), H(b));
    when their sign changes leave room for no root more than the fast tier found and
    the signs at the cuts (:func:`_sign`) alternate, one root per piece; otherwise the
    pieces and their bisection by de Casteljau's algorithm from those coefficients
    (:mod:`.casteljau`), not by rebuilding the octic on each.  Classification as in
    :func:`_vouch_bisect`.  Returns 0 when the answer is proved (``radii`` written),
    else the step that did not prove it (:data:`SPLIT_STEPS`; then
    :func:`_vouch_bisect` decides and gives the verdict)."""
    W, B, EB, cuts, signs = ws[0], ws[1], ws[2], ws[5], ws[6]
    C, S, X, ecut, iso = ws[7], ws[8], ws[9], ws[10], ws[11]
    _bernstein(d, e, a, b, W, B, EB)
    v = _changes(B, EB)
    cuts[0], cuts[m], ecut[0], ecut[m] = a, b, 0.0, 0.0
    signs[0], signs[m] = _sign_of(B[0], EB[0]), _sign_of(B[8], EB[8])
    if signs[0] == 0 or signs[m] == 0:
        signs[0], signs[m] = _sign(d, e, a), _sign(d, e, b)
        if signs[0] == 0 or signs[m] == 0:
            return 14
    if m == 0 and (v == 0 or (v == 1 and signs[0] == signs[1])):
        return 0
    # the whole interval: signs at float cuts between the roots, alternating, and no
    # more sign changes than roots found
    whole = m > 0 and v <= m
    for j in range(1, m if whole else 0):
        x = 0.5 * (roots[first + j - 1] + roots[first + j])
        cuts[j], signs[j], ecut[j] = x, _sign(d, e, x), 0.0
        if not roots[first + j - 1] < x < roots[first + j]:
            whole = False
            break
    for j in range(m):
        if signs[j] == 0 or signs[j] == signs[j + 1]:
            whole = False
    if whole:
        for j in range(m):
            iso[j, 0], iso[j, 1], iso[j, 2], iso[j, 3] = cuts[j], 0.0, cuts[j + 1], 0.0
    else:
        # the pieces from the whole interval's coefficients by de Casteljau's
        # algorithm, each cut at the middle between two roots found
        P, EP, Lp, ELp, w, ew = C[0], C[1], C[2], C[3], C[4], C[5]
        unscale(B, EB, P, EP)
        xa, ea = a, 0.0
        budget = 32
        for j in range(max(m, 1)):
            if j < m - 1:
                c = 0.5 * (roots[first + j] + roots[first + j + 1])
                t = (c - xa) / (b - xa)
                if not (0.0 < t < 1.0):
                    return 15
                sg, tu = weights(t)
                split(P, EP, sg, tu, Lp, ELp, P, EP, w, ew)
                xb, eb = cut_point(xa, ea, b, 0.0, sg, tu)
                cnt, used = count(Lp, ELp, xa, ea, xb, eb, budget, S, X, Lp, ELp, w, ew,
                                  iso[j:j + 1])
            else:
                xb, eb = b, 0.0
                cnt, used = count(P, EP, xa, ea, xb, eb, budget, S, X, Lp, ELp, w, ew,
                                  iso[j:j + 1])
            budget -= used
            if m == 0:
                return 0 if cnt == 0 else 16
            if cnt < 0:
                return 16
            if cnt != 1:
                return 17
            cuts[j + 1], ecut[j + 1] = xb, eb
            xa, ea = xb, eb
    # classification (step 6), piece by piece
    for j in range(m):
        k = first + j
        ia, iea, ib, ieb = iso[j, 0], iso[j, 1], iso[j, 2], iso[j, 3]
        if not tight:
            r = 0.5 * (ia + ib)
            rho = (0.5 * (ib - ia) * (1.0 + 4.0 * U) + 4.0 * U * abs(r)
                   + max(iea, ieb) * (1.0 + 4.0 * U))
            status = _status(d, e, r, rho)
            if status >= 0:
                if (status == 0) != (codes[k] == 0):
                    return 18
                radii[k] = abs(roots[k] - r) + rho
                continue
        r = roots[k]
        # (twice the bounds: the float sums may round towards the cuts by up to u|x|,
        # which each bound already exceeds)
        lo_in, hi_in = cuts[j] + 2.0 * ecut[j], cuts[j + 1] - 2.0 * ecut[j + 1]
        lim = min(r - lo_in, hi_in - r)
        if tight:
            rho = _first_radius(d, e, r, lim)
        else:                       # (the batched tier's radii are the pieces' anyway)
            rho = min(max(abs(r), 1e-300) * 2.0 ** -32, 0.5 * lim)
        found, rho = _grow(d, e, r, rho, lim, lo_in, hi_in)
        if found:
            rho = rho * (1.0 + 4.0 * U) + 4.0 * U * abs(r)
        else:                       # the isolating piece itself
            r = 0.5 * (ia + ib)
            rho = (0.5 * (ib - ia) * (1.0 + 4.0 * U) + 4.0 * U * abs(r)
                   + max(iea, ieb) * (1.0 + 4.0 * U))
        status = _status(d, e, r, rho)
        if status < 0:
            return 19
        if (status == 0) != (codes[k] == 0):
            return 18
        radii[k] = abs(roots[k] - r) + rho
    return 0


@_leaf
def _vouch_bisect(d, e, a, b, first, m, roots, codes, radii, tight, ws):
    """Steps 4-7 of the module docstring on [a, b] and the m fast roots from index
    ``first`` in it, with a rebuild of the octic on every piece (:func:`_count`) and
    running bounds at every point (:func:`_sign`)."""
    W, B, EB, stack, ssigns, cuts, signs = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6]
    # cut points: a, points between consecutive roots, b (each with a proved sign)
    cuts[0], cuts[m] = a, b
    signs[0] = _sign(d, e, a)
    signs[m] = _sign(d, e, b)
    if signs[0] == 0 or signs[m] == 0:
        return 2
    for j in range(1, m):
        r0, r1 = roots[first + j - 1], roots[first + j]
        ok = False
        for f in (0.5, 0.25, 0.75, 0.125, 0.875):
            x = r0 + f * (r1 - r0)
            s = _sign(d, e, x)
            if s != 0 and r0 < x < r1:
                cuts[j], signs[j] = x, s
                ok = True
                break
        if not ok:
            return 3
    budget = m + 1 + _BUDGET
    if m == 0:
        c, _, _, _ = _count(d, e, a, b, signs[0], signs[1], budget, W, B, EB, stack, ssigns,
                            ws[11][:0])
        return 0 if c == 0 else 4
    # one count over all of [a, b] first (step 4 on the union of the pieces): at most
    # m sign changes and signs alternating at the m + 1 cuts prove one simple root per
    # piece (each piece holds an odd number of roots, the m pieces at most m in all);
    # otherwise piece by piece, by bisection (:func:`_count`)
    whole = True
    for j in range(m):
        if signs[j] == signs[j + 1]:
            whole = False
    if whole and m > 1:
        _bernstein(d, e, a, b, W, B, EB)
        budget -= 1
        whole = _changes(B, EB) <= m
    for j in range(m):
        if whole and m > 1:
            c, ia, ib = 1, cuts[j], cuts[j + 1]
        else:
            c, ia, ib, used = _count(d, e, cuts[j], cuts[j + 1], signs[j], signs[j + 1],
                                     budget, W, B, EB, stack, ssigns, ws[11][:0])
            budget -= used
        if c < 0 or c > 1:
            return 4
        if c == 0:
            return 5
        # the one root of the piece: tighten around the fast root, then classify
        k = first + j
        if not tight:
            r = 0.5 * (ia + ib)
            rho = 0.5 * (ib - ia) * (1.0 + 4.0 * U) + 4.0 * U * abs(r)
            status = _status(d, e, r, rho)
            if status >= 0:
                if (status == 0) != (codes[k] == 0):
                    return 7
                radii[k] = abs(roots[k] - r) + rho
                continue
        r = roots[k]
        lim = min(r - cuts[j], cuts[j + 1] - r)
        rho = _first_radius(d, e, r, lim)
        found, rho = _grow(d, e, r, rho, lim, cuts[j], cuts[j + 1])
        if not found:               # the isolating piece itself
            r = 0.5 * (ia + ib)
            rho = 0.5 * (ib - ia)
        # [r - rho, r + rho] with rho so widened covers the float ends and the midpoint
        rho = rho * (1.0 + 4.0 * U) + 4.0 * U * abs(r)
        status = _status(d, e, r, rho)
        if status < 0:
            return 6
        if (status == 0) != (codes[k] == 0):
            return 7
        radii[k] = abs(roots[k] - r) + rho
    return 0


@_jit
def recover(d, s2, l2, eta, lo, hi, out):
    """Every real root of the exact octic in the feasible interval [a, b] (step 5), found
    by the proof's own subdivision (:func:`.casteljau.count` from the whole interval's
    Bernstein coefficients; where that does not decide, :func:`_count`'s rebuild on
    every piece) and refined by bracketed Newton steps in plain float
    (:func:`_bracketed`): approximations, increasing, into ``out`` (8,); returns
    (their number, a, b), the number -1 when the subdivision does not decide (a cluster
    within the bounds).
    For a problem whose fast answer the proof refused (a pair of roots the scan did not
    see): its roots inside [a, b] again, to be placed and proved once more (issue 17)."""
    ws = _workspace()
    e = ws[12]
    part_bounds_into(d, s2, l2, eta, e, ws[13])
    for k in range(30):
        if not e[k] < np.inf:
            return -1, 0.0, 0.0
    delta = margin(s2, l2, eta)
    a, b = lo - delta, hi + delta
    if a > b:
        return 0, a, b
    if lo > hi:
        a, b = hi - delta, lo + delta
    W, B, EB, C, S, X = ws[0], ws[1], ws[2], ws[7], ws[8], ws[9]
    _bernstein(d, e, a, b, W, B, EB)
    P, EP, Lp, ELp, w, ew = C[0], C[1], C[2], C[3], C[4], C[5]
    unscale(B, EB, P, EP)
    found = ws[11]
    cnt, _ = count(P, EP, a, 0.0, b, 0.0, 4 * _BUDGET, S, X, Lp, ELp, w, ew, found)
    if cnt < 0:                 # the rebuild on every piece (:func:`_count`)
        sa, sb = _sign(d, e, a), _sign(d, e, b)
        if sa == 0 or sb == 0:
            return -1, a, b
        cnt, _, _, _ = _count(d, e, a, b, sa, sb, 4 * _BUDGET, W, B, EB, ws[3], ws[4], X)
        for t in range(min(cnt, 8)):
            found[t, 0], found[t, 2] = X[t, 0], X[t, 1]
    if cnt < 0 or cnt > 8:
        return -1, a, b
    for t in range(cnt):
        out[t] = _bracketed(d, found[t, 0], found[t, 2])
    return cnt, a, b


@_jit
def vouch_many(data, s2, l2, eta, lo, hi, roots, status, verdict, radii):
    """:func:`vouch` for the N problems of the batched tier: ``data`` (N, 39), ``s2``,
    ``l2`` (N, 6), ``eta``, ``lo``, ``hi`` (N,), ``roots`` (N, 8) increasing and NaN
    padded, ``status`` (N, 8) codes (-1 padding); writes ``verdict`` (N,) and ``radii``
    (N, 8) (the radii of ``tight=False``)."""
    _vouch_rows(data, s2, l2, eta, lo, hi, roots, status, verdict, radii, _workspace())


@_leaf
def _vouch_rows(data, s2, l2, eta, lo, hi, roots, status, verdict, radii, ws):
    """The loop of :func:`vouch_many` over the problems, with the work arrays ``ws``."""
    for i in range(data.shape[0]):
        n = 0
        while n < 8 and status[i, n] >= 0:
            n += 1
        for j in range(n, 8):
            radii[i, j] = np.inf
        verdict[i] = _vouch(data[i], s2[i], l2[i], eta[i], lo[i], hi[i], roots[i, :n],
                            status[i, :n], radii[i, :n], False, ws)


@_jit
def vouch_rows(d, s2, l2, eta, lo, hi, rows):
    """:func:`vouch` on the root rows (n, 3) = (s15, step, code) of the single solve
    (:func:`.single.solve_fast_single`).  Returns (verdict, smallest relative gap
    between consecutive roots, largest proved radius, largest relative proved radius,
    the (n,) proved radius of each root: inf where none, meaningful only when the
    verdict is 0)."""
    n = rows.shape[0]
    x = np.empty(n)
    codes = np.empty(n, np.int64)
    for k in range(n):
        x[k] = rows[k, 0]
        codes[k] = int(rows[k, 2])
    radii = np.empty(n)
    v = vouch(d, s2, l2, eta, lo, hi, x, codes, radii)
    sep, rad, rel = np.inf, 0.0, 0.0
    for k in range(n):
        if k:
            sep = min(sep, (x[k] - x[k - 1]) / max(abs(x[k]), 1e-300))
        if radii[k] < np.inf:
            rad = max(rad, radii[k])
            rel = max(rel, radii[k] / max(abs(x[k]), 1e-300))
    return v, sep, rad, rel, radii


@_jit
def vouch_buffer(buf, nr, eta, lo, hi):
    """:func:`vouch_rows` on the buffer of the single solve (``.batched._scan_single``:
    squared sides, legs, kernel output, then ``nr`` root rows), without unpacking it in
    Python."""
    return vouch_rows(buf[12:51], buf[:6], buf[6:12], eta, lo, hi,
                      buf[51:51 + 3 * nr].reshape(nr, 3))
