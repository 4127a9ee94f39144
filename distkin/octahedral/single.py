r"""The fast tier, one problem at a time: compiled scalar stages (numba).

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III.
The generated scalar kernel (:mod:`distkin._generated.octic_general`, compiled as it is
by numba) gives the octic :math:`O(s_{15})` and the quadratic parts of eq. (3); one
LAPACK eigenvalue call (numpy's ``dgeev``, with balancing) on the companion matrix of
the scaled octic gives the starts.  Then, per eigenvalue (:func:`roots_from_eigenvalues`):

* **direct path** -- an eigenvalue that LAPACK returns exactly real (a 1x1 block of
  the real Schur form) whose neighbours, in the order of real parts, lie farther than
  :data:`SEP` (relative) is a simple real root, accurate to the rounding of the octic's
  coefficients (~1e-9 relative): inside the triangle bounds at most four Newton steps on
  eq. (3) on its vanishing branch polish it (the accuracy the result states; Newton on
  the factored octic where eq. (3) stops short, next to a nearly flat banana
  tetrahedron, as in the batched tier), outside
  (a spurious root) at most four Newton steps on the octic in Horner form; a first step
  above :data:`CONFIRM` relative sends the eigenvalue to the careful path;
* **careful path** -- every other eigenvalue that is real or nearly so (two roots
  closer than :data:`SEP`, a nearly real complex pair :math:`a \pm ib` starts two, at
  :math:`a \mp b`): Newton on the factored octic :math:`G^2-4R_1R_2` (deflated by the
  roots found where two starts meet one root; a start whose steps stop shrinking like
  Newton's linear rate at a root of multiplicity up to six has no real root to find
  and is dropped), then eq. (3).

Two roots closer than :data:`.placement.DUP` relative after the polish are one; so are two within
1e-7 relative when the factored octic has opposite signs just outside both (one
crossing: two starts from a nearly real pair stalled on the two sides of one simple
root, which the certified tier confirms; tests/octahedral).

Real roots outside the triangle bounds of :math:`s_{15}`, or where a banana tetrahedron
has negative squared volume, are spurious.  The trilateration sequence of Sec. III and
the two mirror poses of every assembly root are :func:`.placement.place`.

The public single solve (:func:`~.forward.forward_kinematics`) now goes the batched
tier's way first (:func:`.batched.solve_scan_single`, issue 17: the eigenvalue call was
most of its cost) and comes here for the problems the sign scan doubts; the tests
compare both routes.  The batched tier (:mod:`.batched`) finds its roots by a sign scan and uses the same
compiled stages (the polish on eq. (3), the factored Newton, :func:`roots_from_eigenvalues` for the
problems the scan doubts, the placement).

Why compiled: in CPython the same scalar code took ~180 µs per Griffis-Duffy solve
(~250 float operations per root at 25-35 ns each, ~20 numpy calls on tiny arrays for
the poses); issue 3 asks for 100 µs.  Every function here is plain Python that numba
compiles once per machine (``cache=True``: the machine code is kept in
``__pycache__``); ``NUMBA_DISABLE_JIT=1`` runs the same source in the interpreter.
Cost after compilation: see BENCHMARKS.md (``python -m benchmarks octahedral``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from .._generated.octic_general import OCTIC
from .companion import (_eigvals, _prepare, bounds, companion,  # noqa: F401
                        eigenvalues, octic_array)
from .placement import DUP, place
from .problem import REASONS

__all__ = ["solve_fast_single", "SingleSolve", "roots_from_eigenvalues",
           "eigenvalues", "eigen_rows", "companion", "polish_eq3", "newton_factored",
           "tet_min", "octic_array", "factored_grid", "bounds", "REASONS", "CONFIRM",
           "EQ3_STEPS", "NEWTON_MAX", "compile_notice", "cached"]

#: relative distance from every other eigenvalue above which an exactly real eigenvalue
#: takes the direct path (closer ones may be a blurred pair of close roots)
SEP = 1e-2
#: relative first Newton step on eq. (3) (or on the octic) above which a direct-path
#: root is not trusted.  Isolated roots come out of LAPACK within the rounding of the
#: float octic's coefficients, ~1e-13..1e-9 relative; the polish then converges
#: quadratically (a start within 1e-6 of a root isolated by 1 % is deep in its basin)
CONFIRM = 1e-6
_CLOSE = 1e-7        # ... and up to which they are one if the octic says so,
_SIGN_OK = 1e-12     # ... with values above this times the size of their terms
NEWTON_MAX = 60     # Newton on the factored octic: linear near a double root
_NEWTON_DEFLATED = 25  # deflated retries: a start that has not settled by then has none
EQ3_STEPS = 4       # Newton steps on eq. (3) at most (stops at 1e-9 relative)
_RES = 1e-4          # relative residual of the factored octic accepted as a root
_ROUNDS = 3          # rounds of deflated Newton from the starts that found nothing new
_STEP = 1e-9         # relative size of the last Newton step of a converged polish
_NEAR_REAL = 0.05    # |Im| / scale under which an eigenvalue starts a polish
_GRACE = 6           # Newton steps before a start must show convergence ...
_RATE = 0.7          # ... |step_k| <= _RATE |step_(k-2)|: Newton's linear rate (m-1)/m
#                      at a root of multiplicity m <= 6 gives ((m-1)/m)^2 <= 0.7

_jit = numba.njit(cache=True, _nrt=True)
#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_leaf = numba.njit(cache=True, _nrt=False)



# ------------------------------------------------------------ eq. (3) and the octic

@_leaf
def _q(d, i, x):
    """Quadratic part i of eq. (3) (u, v, b1, b2, E1, E2, T1a, T1b, T2a, T2b) at x."""
    return d[3 * i] + x * (d[3 * i + 1] + x * d[3 * i + 2])


@_leaf
def _dq(d, i, x):
    """Its derivative."""
    return d[3 * i + 1] + (2 * x) * d[3 * i + 2]


@_leaf
def _factored(d, x):
    r"""The octic in its factored form :math:`H = G^2-4R_1R_2` at x, its derivative, and
    the size :math:`G^2+4|R_1R_2|` of its terms (quadratic parts from ``d``)."""
    u, v, b1, b2 = _q(d, 0, x), _q(d, 1, x), _q(d, 2, x), _q(d, 3, x)
    E1, E2 = _q(d, 4, x), _q(d, 5, x)
    a, b, cc, e = _q(d, 6, x), _q(d, 7, x), _q(d, 8, x), _q(d, 9, x)
    G = u * E2 + v * E1 + 2 * b1 * b2
    dG = (_dq(d, 0, x) * E2 + u * _dq(d, 5, x) + _dq(d, 1, x) * E1 + v * _dq(d, 4, x)
          + 2 * (_dq(d, 2, x) * b2 + b1 * _dq(d, 3, x)))
    ab, ce = a * b, cc * e
    R = ab * ce
    dR = (_dq(d, 6, x) * b + a * _dq(d, 7, x)) * ce + ab * (_dq(d, 8, x) * e + cc * _dq(d, 9, x))
    return G * G - 4 * R, 2 * G * dG - 4 * dR, G * G + 4 * abs(R)


@_leaf
def tet_min(d, x):
    """The smallest of the four banana tetrahedra's squared-volume factors at x."""
    return min(_q(d, 6, x), _q(d, 7, x), _q(d, 8, x), _q(d, 9, x))


@_leaf
def polish_eq3(d, x, c, steps):
    r"""Newton on the cleared eq. (3) :math:`P + \epsilon_1 v\sqrt{R_1} -
    \epsilon_2 u\sqrt{R_2}` on the branch where it is smallest, at most ``steps`` steps
    (stopping at a step at rounding level, or below 1e-9 relative and 1e-4 times the
    one before: quadratic convergence makes the next one negligible then; next to a
    nearly flat banana tetrahedron the branch is nearly singular and a first small step
    proves nothing), each clipped to 1e-3 c, none where a radicand is not positive.
    The caller has checked the tetrahedra.  Returns
    ``(x, radius, first step, steps taken, how)``: ``radius`` the largest step taken
    (about the error of the start; the last step alone, tiny once converged, says
    nothing of the rounding error: on 884 assembly roots of random octahedra the
    certified root lay farther than the last step in 24 %, farther than this radius in
    1.5 %, all below 1e-12 relative); ``how`` 0 converged, 1 the steps ran out with
    the last one below 1e-9 relative (the rounding noise of a badly conditioned
    problem), 2 not settled: stopped by a radicand that is not positive (or a vanishing
    derivative; next to a nearly flat banana tetrahedron the pose goes as the square
    root of the root's error, and the caller polishes on the factored octic instead),
    or out of steps above 1e-9.
    """
    step = first = prev = 0.0
    taken = 0
    how = 2
    for k in range(steps):
        u, v, b1, b2 = _q(d, 0, x), _q(d, 1, x), _q(d, 2, x), _q(d, 3, x)
        a, b, cc, e = _q(d, 6, x), _q(d, 7, x), _q(d, 8, x), _q(d, 9, x)
        R1, R2 = a * b, cc * e
        if R1 <= 0 or R2 <= 0 or a < 0 or cc < 0:
            break
        du, dv, db1, db2 = _dq(d, 0, x), _dq(d, 1, x), _dq(d, 2, x), _dq(d, 3, x)
        q1, q2 = math.sqrt(R1), math.sqrt(R2)
        P = u * b2 - v * b1
        vq1, uq2 = v * q1, u * q2
        N, e1, e2 = P + vq1 - uq2, 1.0, 1.0
        n_ = P + vq1 + uq2
        if abs(n_) < abs(N):
            N, e1, e2 = n_, 1.0, -1.0
        n_ = P - vq1 - uq2
        if abs(n_) < abs(N):
            N, e1, e2 = n_, -1.0, 1.0
        n_ = P - vq1 + uq2
        if abs(n_) < abs(N):
            N, e1, e2 = n_, -1.0, -1.0
        dq1 = (_dq(d, 6, x) * b + a * _dq(d, 7, x)) / (2 * q1)
        dq2 = (_dq(d, 8, x) * e + cc * _dq(d, 9, x)) / (2 * q2)
        dN = (du * b2 + u * db2 - dv * b1 - v * db1 + e1 * (dv * q1 + v * dq1)
              - e2 * (du * q2 + u * dq2))
        if dN == 0 or not math.isfinite(dN):
            break
        st = N / dN
        lim = 1e-3 * c
        st = lim if st > lim else (-lim if st < -lim else st)
        x -= st
        prev, step = step, st
        taken += 1
        if k == 0:
            first = st
        a = abs(st)
        if a <= 4e-16 * abs(x) or (a <= 1e-9 * abs(x) and k > 0 and a <= 1e-4 * abs(prev)):
            how = 0             # at rounding level, or small and shrinking quadratically
            break
        if k == steps - 1:      # out of steps: noise level, or not converging
            how = 1 if a <= 1e-9 * abs(x) else 2
    return x, max(abs(step), abs(prev), abs(first)), first, taken, how


@_leaf
def _horner_newton(d, x, c):
    """Newton on the octic in Horner form from an accurate start: ``(x, |last step|,
    ok)``, not ok when the first step exceeds :data:`CONFIRM` relative.  At most four
    steps; stops when a step is below 1e-14 relative or stops shrinking."""
    size = max(abs(x), c)
    prev = np.inf
    st = 0.0
    for k in range(4):
        p, dp = d[30], 0.0
        for i in range(31, 39):
            dp = dp * x + p
            p = p * x + d[i]
        st = p / dp if dp != 0 else np.inf
        a = abs(st)
        if k == 0 and not a <= CONFIRM * size:
            return x, np.inf, False
        if a >= prev:
            break
        x -= st
        if a <= 1e-14 * size:
            break
        prev = a
    return x, abs(st), True


@_leaf
def _small(d, x):
    """The octic in Horner form is below :data:`_RES` times the size of its terms."""
    p, s, ax = 0.0, 0.0, abs(x)
    for i in range(30, 39):
        p = p * x + d[i]
        s = s * ax + abs(d[i])
    return abs(p) <= _RES * s


@_leaf
def newton_factored(d, x, c, found, nfound, iters):
    """Newton on the factored octic from x, deflated by ``found[:nfound]``.

    Returns the final x, the last step, convergence, and the point where the octic
    was last evaluated (one negligible step before x).  Convergence: the last step below
    :data:`_STEP` relative and the octic small against the size of its terms in the
    factored form or in the expanded form (next to a close root the factored form's
    cancellation can leave a residual above that level by rounding alone)."""
    step, prev, prev2 = 0.0, 0.0, np.inf
    H, Hs = 0.0, 1.0
    xe = x
    for it in range(iters):
        xe = x
        H, dH, Hs = _factored(d, x)
        defl = 0.0
        for j in range(nfound):
            if x != found[j]:
                defl += 1.0 / (x - found[j])
        den = dH - H * defl
        if den == 0 or not math.isfinite(den):
            step = np.inf
            break
        step = max(-0.5 * c, min(0.5 * c, H / den))
        x -= step
        size = max(abs(x), c)
        a = abs(step)
        if a <= 1e-14 * size or (a <= _STEP * size and a > 0.5 * prev):
            break
        if it >= _GRACE and a > _RATE * prev2:       # wanders: no real root to find here
            break
        prev2, prev = prev, a
    ok = abs(step) <= _STEP * max(abs(x), c) and math.isfinite(x) and (
        abs(H) <= _RES * Hs or _small(d, xe))
    return x, step, ok, xe


@_leaf
def _one_crossing(d, x1, x2):
    """The factored octic has opposite signs at x1 - g and x2 + g (g = x2 - x1), each
    above :data:`_SIGN_OK` times the size of its terms (not rounding noise): an odd
    number of roots around the two, i.e. one where two were found."""
    g = x2 - x1
    a, _, sa = _factored(d, x1 - g)
    b, _, sb = _factored(d, x2 + g)
    return (a > 0) != (b > 0) and abs(a) > _SIGN_OK * sa and abs(b) > _SIGN_OK * sb


@_leaf
def _distinct(x, c, xs, n):
    """x is farther than :data:`DUP` relative from every one of ``xs[:n]``."""
    tol = DUP * max(abs(x), c)
    for j in range(n):
        if abs(x - xs[j]) <= tol:
            return False
    return True


# --------------------------------------------------------------------- the roots

@_jit
def roots_from_eigenvalues(d, lo, hi, c, er, ei, out):
    """The real roots of one octic and their status from its eigenvalues (real parts
    ``er``, imaginary ``ei``): the direct and careful paths of the module docstring.
    Writes ``out[k] = (s15, error estimate, code)`` increasing, at most 8, none closer
    than :data:`.placement.DUP` relative to another; returns their number.  Codes: 0
    inside the bounds with the banana tetrahedra real, polished on eq. (3); 1, 2
    spurious (:data:`REASONS`)."""
    n = er.size
    order = np.argsort(er, kind="mergesort")
    tol_x = 1e-9 * c
    lo_t, hi_t = lo - tol_x, hi + tol_x
    starts = np.empty(2 * n + 8)
    ns = 0
    xs = np.empty(16)
    ss = np.empty(16)
    cs = np.empty(16, np.int64)
    nd = 0
    for k in range(n):
        i = order[k]
        re, im = er[i], ei[i]
        if im == 0:
            tol = SEP * max(abs(re), c)
            if ((k > 0 and re - er[order[k - 1]] <= tol)
                    or (k < n - 1 and er[order[k + 1]] - re <= tol)):
                starts[ns] = re
                ns += 1
                continue
            # the direct path
            x0 = re
            if lo_t <= x0 <= hi_t:
                if tet_min(d, x0) < -1e-9 * c * c * c:     # a banana tetrahedron
                    x, st, ok = _horner_newton(d, x0, c)
                    code = 2
                    if ok and tet_min(d, x) >= -1e-9 * c * c * c:
                        ok = False      # real at the polished root: decide carefully
                else:
                    x, st, first, taken, how = polish_eq3(d, x0, c, EQ3_STEPS)
                    st = abs(st)
                    ok = True
                    size = max(abs(x0), c)
                    if abs(first) > CONFIRM * size:
                        ok = False          # eq. (3) does not confirm the root
                    elif how == 2:
                        # a radicand vanishes at or near the root (a banana tetrahedron
                        # nearly flat: eq. (3) stops or crawls): the factored octic
                        x, st, ok, _ = newton_factored(d, x0, c, xs, 0, NEWTON_MAX)
                        ok = ok and abs(x - x0) <= CONFIRM * size
                        st = abs(st)
                    code = 0
            else:
                x, st, ok = _horner_newton(d, x0, c)
                code = 1
                if ok and lo_t <= x <= hi_t:  # moved into the bounds: decide carefully
                    ok = False
            if ok:
                xs[nd], ss[nd], cs[nd] = x, st, code
                nd += 1
            else:
                starts[ns] = x0
                ns += 1
        elif im > 0 and im <= _NEAR_REAL * max(math.hypot(re, im), c):
            starts[ns] = re - im
            starts[ns + 1] = re + im
            ns += 2
    if ns:
        nd = _careful(d, starts[:ns], xs, ss, cs, nd, c, lo, hi)
    # increasing, at most 8; roots that met after their polish on eq. (3) are one (the
    # careful path deduplicates before it), as in .placement.place_many; so are two
    # within _CLOSE where the octic changes sign once across both (two starts from a
    # nearly real pair that stalled on the two sides of one simple root)
    order = np.argsort(xs[:nd], kind="mergesort")
    m = 0
    for k in range(nd):
        i = order[k]
        if m:
            gap = xs[i] - out[m - 1, 0]
            size = max(abs(xs[i]), c)
            if gap <= DUP * size or (gap <= _CLOSE * size
                                     and _one_crossing(d, out[m - 1, 0], xs[i])):
                continue
        if m == 8:
            break
        out[m, 0], out[m, 1], out[m, 2] = xs[i], ss[i], cs[i]
        m += 1
    return m


@_jit
def _careful(d, starts, xs, ss, cs, nd, c, lo, hi):
    """The careful path: Newton on the factored octic from ``starts``, deduplicated
    against each other and the roots ``xs[:nd]`` known, deflated retries, then eq. (3).
    Appends to ``xs, ss, cs``; returns their new count."""
    ns = starts.size
    fx = np.empty(ns + 8)           # roots found here, where their octic was evaluated
    fe = np.empty(ns + 8)
    fs = np.empty(ns + 8)
    nf = 0
    failed = np.empty(ns)
    nfail = 0
    for k in range(ns):
        x, st, ok, xe = newton_factored(d, starts[k], c, xs, 0, NEWTON_MAX)
        if ok and _distinct(x, c, xs, nd) and _distinct(x, c, fx, nf):
            fx[nf], fs[nf], fe[nf] = x, st, xe
            nf += 1
        else:
            failed[nfail] = starts[k]
            nfail += 1
    roots = np.empty(nd + ns + 8)
    for _ in range(_ROUNDS):
        if nfail == 0:
            break
        nr = 0
        for j in range(nd):
            roots[nr] = xs[j]
            nr += 1
        for j in range(nf):
            roots[nr] = fx[j]
            nr += 1
        new = 0
        for k in range(nfail):
            x, st, ok, xe = newton_factored(d, failed[k], c, roots, nr,
                                    _NEWTON_DEFLATED if nr else NEWTON_MAX)
            if ok and _distinct(x, c, roots, nr) and _distinct(x, c, fx[nf:], new):
                if nf + new < fx.size:
                    fx[nf + new], fs[nf + new], fe[nf + new] = x, st, xe
                    new += 1
        if new == 0:
            break
        nf += new
    tol_x = 1e-9 * c
    for k in range(nf):
        if nd >= xs.size:
            break
        x, st, xe = fx[k], abs(fs[k]), fe[k]
        if not lo - tol_x <= x <= hi + tol_x:
            xs[nd], ss[nd], cs[nd] = x, st, 1
        elif tet_min(d, xe) < -1e-9 * c * c * c:
            xs[nd], ss[nd], cs[nd] = x, st, 2
        else:
            xp, st2, _, taken, _ = polish_eq3(d, xe, c, EQ3_STEPS)
            xs[nd], ss[nd], cs[nd] = xp, (abs(st2) if st2 != 0 else st), 0
        nd += 1
    return nd


@_jit
def _solve(B, Q, L, d, lo, hi, c, er, ei, s2, l2):
    roots = np.empty((8, 3))
    n = roots_from_eigenvalues(d, lo, hi, c, er, ei, roots)
    P = np.empty((16, 3, 3))
    R = np.empty((16, 3, 3))
    T = np.empty((16, 3))
    E = np.empty(16)
    Er = np.empty(16)
    S15 = np.empty(16)
    side = np.empty(16, np.int64)
    slot = np.empty(8, np.int64)
    m = place(B, Q, L, s2, l2, lo, hi, roots, n, P, R, T, E, Er, S15, side, slot)
    return roots[:n], P[:m], R[:m], T[:m], E[:m], Er[:m], S15[:m], side[:m]


class SingleSolve(NamedTuple):
    """What :func:`solve_fast_single` returns (float64 arrays; squared lengths in the
    problem's units squared).

    coef : (9,) the octic (highest degree first)
    lo, hi : floats, the triangle bounds of s15
    roots : (n, 3) rows (s15, |last Newton step|, status code of :data:`REASONS`)
    poses : tuple (s15, side, points, rotation, translation, max leg error, max
        relative leg error) of arrays over the poses, two per assembly root (side +1
        first), by increasing root
    sides2, legs2 : (6,) the squared sides and legs (kernel inputs)
    data : (39,) the kernel output, for the proof of :mod:`.descartes`
        (:mod:`.conditioning`)
    eigenvalues : complex array, of the octic's companion matrix
    """

    coef: np.ndarray
    lo: float
    hi: float
    roots: np.ndarray
    poses: tuple
    sides2: np.ndarray
    legs2: np.ndarray
    data: np.ndarray
    eigenvalues: np.ndarray


def solve_fast_single(B, Q, L) -> SingleSolve:
    """Every assembly mode of one problem (float64, compiled stages).

    Parameters
    ----------
    B, Q : (3, 3) base points; platform points in the platform frame (rows; arrays or
        nested lists of floats)
    L : (6,) leg lengths

    Returns
    -------
    SingleSolve
        The octic, the triangle bounds, the roots and the poses, with the squared
        lengths, the kernel output and the eigenvalues that the proof and the hard sets
        reuse.
    """
    B = np.asarray(B, dtype=float)
    Q = np.asarray(Q, dtype=float)
    L = np.asarray(L, dtype=float)
    s2, l2, d, lo, hi, c, comp, sc, mode = _prepare(B, Q, L)
    eig = eigenvalues(comp, sc, mode, c)
    roots, P, R, T, E, Er, S15, side = _solve(B, Q, L, d, lo, hi, c, eig.real.copy(),
                                              eig.imag.copy(), s2, l2)
    return SingleSolve(d[OCTIC], lo, hi, roots, (S15, side, P, R, T, E, Er), s2, l2, d, eig)


def eigen_rows(comp, sc, mode, c):
    """:func:`eigenvalues` for several problems (the output of :func:`companions`): real
    and imaginary parts (m, 8) of the unscaled eigenvalues and their number per row
    (one LAPACK call for the rows of full degree)."""
    m = comp.shape[0]
    er = np.zeros((m, 8))
    ei = np.zeros((m, 8))
    nr = np.zeros(m, np.int64)
    full = np.flatnonzero(mode == 0)
    if full.size:
        eig = _eigvals(comp[full]) if np.isfinite(comp[full]).all() else None
        # (the rows LAPACK solved written at once: a loop over them cost ~4 µs a row)
        ok = (np.zeros(full.size, bool) if eig is None
              else ~np.isnan(eig.real).any(axis=1) & ~np.isnan(eig.imag).any(axis=1))
        if ok.any():
            rows, cs = full[ok], c[full[ok], None]
            er[rows], ei[rows], nr[rows] = eig[ok].real * cs, eig[ok].imag * cs, 8
        for i in full[~ok]:                 # LAPACK did not converge: the public path
            z = eigenvalues(comp[i], sc[i], 0, 1.0)
            er[i], ei[i], nr[i] = z.real * c[i], z.imag * c[i], 8
    for i in np.flatnonzero(mode != 0):
        z = eigenvalues(comp[i], sc[i], mode[i], c[i])
        er[i, :z.size], ei[i, :z.size], nr[i] = z.real, z.imag, z.size
    return er, ei, nr


@_jit
def factored_grid(data, x):
    r"""The factored octic :math:`H = G^2-4R_1R_2`, its derivative and the size of its
    terms (:func:`_factored`) for every row of ``data`` (k, 39) at every point of ``x``
    (M,): three (k, M) arrays."""
    k, m = data.shape[0], x.size
    H = np.empty((k, m))
    dH = np.empty((k, m))
    S = np.empty((k, m))
    for i in range(k):
        for j in range(m):
            H[i, j], dH[i, j], S[i, j] = _factored(data[i], x[j])
    return H, dH, S


def cached(dispatcher) -> bool:
    """Whether numba's cache index of ``dispatcher`` exists (an internal of numba:
    True, "nothing to do", when it cannot be told): :func:`compile_notice` and
    :func:`.warmup.pending_chains`."""
    import os
    try:
        return os.path.exists(dispatcher._cache._cache_file._index_path)
    except Exception:  # pragma: no cover - other numba layouts
        return True


def compile_notice() -> str:
    """What to tell the user before the first fast solve on a machine, when numba's
    cache holds no machine code for it yet (the call then compiles: the default call,
    with its proof, took 39 s on the 2-core machine of BENCHMARKS.md on 2026-11-26,
    46 s with ``method="auto"``; the CLI's queries compile it in two processes,
    :mod:`.warmup`: 19.5 s); ""
    when it does, or when that cannot be told (the check reads numba's cache index, an
    internal of numba).  Every fast solve runs the compiled sign scan
    (:func:`.signscan.scan_one`, issue 17); the eigenvalue route here compiles later, on
    the first problem the scan doubts."""
    from .signscan import scan_one
    pending = not cached(scan_one)
    return ("compiling the fast octahedral tier for this machine (numba, 20-60 s, "
            "once: later runs load it from numba's cache)") if pending else ""
