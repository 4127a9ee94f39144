r"""Real roots of many octics at once without eigenvalues: a projective sign scan.

The fast batched tier of the octahedral forward kinematics (Rojas, Borràs and Thomas,
*The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III) needs every real root of
N octics :math:`O(x)`, :math:`x = s_{15}`.  LAPACK's companion-matrix eigenvalues cost
~8 µs per octic (``dgeev``, one 8x8 matrix at a time); this scan costs about a third
of that, in a few dozen numpy operations over all octics, and says which problems it
cannot vouch for (:mod:`.batched` solves those the careful way, with eigenvalues).

**1. Projective sign scan.**  With a centre :math:`x_0` and a half-width :math:`h` per
problem (the feasible interval :math:`[lo, hi]` of :func:`~.closure.feasible_interval`,
where every assembly mode lies), :math:`x = x_0 + h\tan\theta` maps
:math:`\theta \in (-\pi/2, \pi/2)` onto the real line, :math:`\theta = \pm\pi/2` being
the point at infinity.  The homogenised octic

.. math:: f(\theta) = \cos^8\theta\; O(x_0 + h\tan\theta)
          = \sum_{j=0}^{8} q_j \sin^j\theta \cos^{8-j}\theta,

with :math:`q_j` the coefficients of :math:`O(x_0 + h u)` (a Taylor shift), is
:math:`\pi`-periodic (even degree) and has the sign of :math:`O`.  Its values on a fixed
grid of :data:`K` angles are one matrix product :math:`q V` (the sines and cosines are
the same for every problem); half of the grid covers the feasible interval
(:math:`|\theta| \le \pi/4`), the other half the rest of the real line.  Every cell
whose end values differ in sign brackets a root.  At every local minimum of
:math:`|f|` on the grid without a sign change, the minimum itself is located (the same
iteration on :math:`f'`); if :math:`f` changes sign there, each side brackets one more root (two
roots in one cell).

**2. Refinement.**  Halley's iteration (cubic convergence: two or three steps from
the start) with bisection as safeguard, all brackets at once, from an interpolated
start, in :math:`u = \tan\theta` on :math:`\sum_j q_j u^j` where
:math:`|\theta| < 3\pi/8`, or in :math:`w = \cot\theta` on the reversed polynomial
:math:`\sum_j q_j w^{8-j}` beyond, so that Horner's scheme runs on arguments of
modulus below 2.5.  With :math:`q` rebuilt around :math:`x_0` from the quadratic parts
(:func:`~.closure.shifted_octic`) the roots are good to ~1e-12 relative when isolated;
:mod:`.batched` polishes them on eq. (3) or on the factored octic.

**3. Doubt.**  A grid cannot see three roots in one cell, nor a pair next to a sign
change, and rounding can turn two close real roots into a complex pair.  A problem is doubted
when the number of roots found differs from the Sturm count of the same coefficients
(:func:`_sturm_count`, in floats: a trigger, not a proof), or when a minimum of
:math:`|f|` comes within :data:`_SHALLOW` of the size of its terms (bounded by the
caller's ``sizes``, e.g. the products of :func:`~.closure.shifted_octic` taken with
absolute values).

"""

from __future__ import annotations

import numpy as np

__all__ = ["real_roots", "grid", "K"]

#: grid angles over the period; a multiple of 8 so that theta = +-3pi/8, +-pi/4, 0 are
#: grid points
K = 96
_ITER = 12          # at most, Halley/bisection steps per bracket (interpolated start)
#: a minimum of |f| between grid points below this times the size of its terms may be
#: two real roots that the coefficients' rounding (up to ~2e3 eps) made complex
_SHALLOW = 1e-11



def grid(k):
    """The scan's grid of ``k`` cells over the period (k a multiple of 8, so that
    theta = +-3pi/8, +-pi/4, 0 are grid points): angles theta (k + 1,), V (9, k + 1)
    with V[j, i] = s_i^j c_i^(8-j) (f on the grid is q @ V), the grid points and the
    cells refined in u = tan(theta) (|theta| < 3 pi / 8; the others in w = cot(theta),
    so that |u|, |w| < 2.5 either way), and the bracket ends (k,) of each cell in its
    variable."""
    dtheta = np.pi / k
    theta = -np.pi / 2 + dtheta * np.arange(k + 1)          # theta_k = pi/2 = theta_0 + pi
    S, C = np.sin(theta), np.cos(theta)
    S[0], C[0], S[k], C[k] = -1.0, 0.0, 1.0, 0.0          # exactly the point at infinity
    S[k // 2], C[k // 2] = 0.0, 1.0
    J = np.arange(9)[:, None]
    V = np.ascontiguousarray(S[None, :] ** J * C[None, :] ** (8 - J))   # 0^0 = 1
    ku = k // 8
    u_pt = np.abs(np.arange(k + 1) - k // 2) < 3 * k // 8
    inside = (np.arange(k) >= ku) & (np.arange(k) < k - ku)
    with np.errstate(divide="ignore", invalid="ignore"):
        tan = np.where(C != 0, S / C, np.inf)
        cot = np.where(S != 0, C / S, np.inf)
    cot[0] = cot[k] = 0.0
    return (theta, V, u_pt, inside, np.where(inside, tan[:k], cot[:k]),
            np.where(inside, tan[1:], cot[1:]))


_DTHETA = np.pi / K
_THETA, _V, _U_PT, _INSIDE, _V_LO, _V_HI = grid(K)
#: rows per matrix product of the grid: larger products make OpenBLAS start threads,
#: which cost ~7x the CPU time on a loaded 2-core machine for this tiny inner dimension
_CHUNK = 256


def _horner(P, v):
    """Values and derivatives of the polynomials P (9, M), ascending, at v (M,)."""
    p = P[8] * v + P[7]
    dp = P[8].copy()
    for j in range(6, -1, -1):
        dp *= v
        dp += p
        p *= v
        p += P[j]
    return p, dp


def _horner2(P, v):
    """Values, first derivatives and half second derivatives of the polynomials P
    (9, M), ascending, at v (M,)."""
    p = P[8] * v + P[7]
    dp = P[8].copy()
    d2 = np.zeros_like(v)
    for j in range(6, -1, -1):
        d2 *= v
        d2 += dp
        dp *= v
        dp += p
        p *= v
        p += P[j]
    return p, dp, d2


def _refine(P, a, b, pa, iters, x=None, tol=1e-11):
    """Roots of the polynomials P (9, M) in the brackets [a, b] (either order) where
    P(a) has the sign ``pa`` (+1/-1) and P(b) the other: Halley's iteration from x
    (default the midpoint), bisection whenever it leaves the bracket; at most ``iters``
    steps.
    From the second step on, only the roots whose step is still above ``tol`` (the
    brackets lie in [-2.5, 2.5]) go on, and below 1e-8 only while the steps shrink (not
    yet at the rounding level).  Returns the roots and the last steps."""
    x = 0.5 * (a + b) if x is None else x.copy()
    step = np.abs(b - a)
    act = None
    xa, ppos = x, pa > 0
    for it in range(iters):
        p, dp, d2 = _horner2(P, xa)
        left = (p > 0) == ppos                     # the root lies between x and b
        a = np.where(left, xa, a)
        b = np.where(left, b, xa)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = xa - p * dp / (dp * dp - p * d2)  # Halley (cubic convergence)
        xn = np.where((xn - a) * (xn - b) <= 0, xn, 0.5 * (a + b))   # else bisect
        st = np.abs(xn - xa)
        if act is None:
            x, prev, step = xn, step, st
        else:
            prev = step[act]
            x[act], step[act] = xn, st
        xa = xn
        if it >= 1 and it < iters - 1:
            more = (st > tol) & ((st < 0.9 * prev) | (st > 1e-8))
            if not more.all():
                act = np.flatnonzero(more) if act is None else act[more]
                if not act.size:
                    break
                P, a, b, xa, ppos = P[:, more], a[more], b[more], xn[more], ppos[more]
    return x, step


def _size(A, v):
    """The sizes of the terms, sum_j A_j |v|^j, of the non-negative polynomials A (9, M)
    at v (M,)."""
    av = np.abs(v)
    size = A[8] * av + A[7]
    for j in range(6, -1, -1):
        size *= av
        size += A[j]
    return size


def _derivative_poly(P):
    r"""Coefficients of :math:`g(v) = (1+v^2)P'(v) - 8vP(v)` (9, M): with :math:`P` the
    octic in :math:`u = \tan\theta` (resp. :math:`w = \cot\theta`),
    :math:`df/d\theta = \cos^8\theta\,g(u)` (resp. :math:`-\sin^8\theta\,g(w)`)."""
    G = np.empty_like(P)
    for m in range(9):
        G[m] = ((m + 1) * P[m + 1] if m < 8 else 0.0) + ((m - 9) * P[m - 1] if m else 0.0)
    return G


def _grid_cells(F):
    """The cells of one chunk of the grid F (rows, K + 1): sign changes (row, cell, the
    values at the cell's ends and at the next point, the sign at its start) and local
    minima of |f| without sign change (row, cell before the minimum, sign of f there);
    the grid is periodic (point K is point 0)."""
    pos = F >= 0
    rc, kc = np.nonzero(pos[:, :-1] != pos[:, 1:])
    Ff = F.ravel()
    i0 = rc * (K + 1) + kc
    fa, fb = Ff.take(i0), Ff.take(i0 + 1)
    fc = Ff.take(np.where(kc < K - 1, i0 + 2, i0 + 1 - K))
    aF = np.abs(F)
    aF[:, K] = aF[:, 0]
    less = aF[:, 1:] < aF[:, :-1]                   # |f| decreases over cell k
    dipm = less & ~np.roll(less, -1, axis=1)        # ... and not over cell k + 1
    same = ~(pos[:, :-1] ^ pos[:, 1:])
    rd, kd = np.nonzero(dipm & same & np.roll(same, -1, axis=1))
    return rc, kc, fa, fb, fc, rd, kd, pos[rc, kc], pos[rd, kd + 1]


def _scan(q, sizes, x0, h):
    """Stages 1 and 2: (row, u) of every root the grid brackets (sign changes, and pairs
    at the local minima of |f|), the last step in units of x, and the problems with a
    minimum of |f| within rounding of zero."""
    n = q.shape[0]
    # the grid, by chunks of rows that stay in cache (and keep OpenBLAS single-threaded:
    # its threads cost ~7x the CPU time of this small product on a loaded machine)
    F = np.empty((_CHUNK, K + 1))
    parts = []
    for i in range(0, n, _CHUNK):
        Fi = np.matmul(q[i:i + _CHUNK], _V, out=F[:min(_CHUNK, n - i)])
        parts.append((i, _grid_cells(Fi)))
    rc = np.concatenate([i + p[0] for i, p in parts])
    kc = np.concatenate([p[1] for _, p in parts])
    fa = np.concatenate([p[2] for _, p in parts])
    fb = np.concatenate([p[3] for _, p in parts])
    fc = np.concatenate([p[4] for _, p in parts])
    rd = np.concatenate([i + p[5] for i, p in parts])
    kd = np.concatenate([p[6] for _, p in parts])
    pc = np.concatenate([p[7] for _, p in parts])      # sign of f at the change cell's start
    pd = np.concatenate([p[8] for _, p in parts])      # sign of f at the minimum
    # the start of each bracket: inverse quadratic interpolation of f in theta through
    # the cell's ends and the next grid point (linear if it leaves the cell)
    with np.errstate(divide="ignore", invalid="ignore"):
        lin = fa / (fa - fb)
        # theta(f) through (0, fa), (1, fb), (2, fc) at f = 0 (Lagrange form)
        quad = fa * fc / ((fb - fa) * (fb - fc)) + 2.0 * fa * fb / ((fc - fa) * (fc - fb))
    t = np.where((quad > 0) & (quad < 1), quad, lin)
    t0 = _THETA[kc] + _DTHETA * t
    kd = kd + 1                                     # the grid point of the minimum
    # the minimum: the root of f' between the neighbouring grid points, in the space of
    # the middle point; then the sign of f there
    qT = np.ascontiguousarray(q.T)                  # (9, N)
    flag = np.zeros(n, bool)
    m = np.zeros(0)
    if rd.size:
        kd = np.where(kd == K, 0, kd)
        usp = _U_PT[kd]
        P = qT[:, rd]
        P = np.where(usp, P, P[::-1])
        tl, tr = _THETA[kd] - _DTHETA, _THETA[kd] + _DTHETA
        with np.errstate(divide="ignore"):
            a = np.where(usp, np.tan(tl), 1.0 / np.tan(tl))
            b = np.where(usp, np.tan(tr), 1.0 / np.tan(tr))
        a = np.where(np.isfinite(a), a, 0.0)        # cot(-pi/2) = cot(pi/2) = 0
        b = np.where(np.isfinite(b), b, 0.0)
        g = _derivative_poly(P)
        ga, _ = _horner(g, a)
        gb, _ = _horner(g, b)
        ok = (ga > 0) != (gb > 0)
        m, _ = _refine(g[:, ok], a[ok], b[ok], np.where(ga[ok] > 0, 1.0, -1.0), _ITER,
                       tol=1e-7)
        pm, _ = _horner(P[:, ok], m)
        two = (pm > 0) != pd[ok]
        # a minimum within the rounding of the coefficients: the octic itself may dip
        # through zero there (two close roots that these coefficients make complex)
        A = sizes(rd[ok]).T                          # sizes of the terms at the minima
        A = np.where(usp[ok], A, A[::-1])
        flag[rd[ok][~two & (np.abs(pm) <= _SHALLOW * _size(A, m))]] = True
        sel = np.flatnonzero(ok)[two]
        rd, kd, usp, a, b, m, pd = rd[sel], kd[sel], usp[sel], a[sel], b[sel], m[two], pd[sel]
    # brackets: the sign-change cells, and both sides of every minimum that dips
    ins_c = _INSIDE[kc]
    rr = np.concatenate([rc, rd, rd])
    a_all = np.concatenate([_V_LO[kc], a if rd.size else m, m])
    b_all = np.concatenate([_V_HI[kc], m, b if rd.size else m])
    ins = np.concatenate([ins_c, usp if rd.size else ins_c[:0], usp if rd.size else ins_c[:0]])
    fd = np.where(pd, 1.0, -1.0)
    sa = np.concatenate([np.where(pc, 1.0, -1.0), fd, -fd])
    P = qT[:, rr]
    P = np.where(ins, P, P[::-1])
    with np.errstate(divide="ignore"):
        v0 = np.where(ins_c, np.tan(t0), 1.0 / np.tan(t0))
    v0 = np.concatenate([np.where(np.isfinite(v0), v0, 0.0), 0.5 * (a + m), 0.5 * (m + b)]
                        if rd.size else [np.where(np.isfinite(v0), v0, 0.0)])
    v, step = _refine(P, a_all, b_all, sa, _ITER, v0)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(ins, v, 1.0 / v)
        dxdv = np.where(ins, 1.0, 1.0 / (v * v)) * h[rr]
    ok = np.isfinite(u)
    return rr[ok], u[ok], (step * dxdv)[ok], flag


def _sturm_count(q):
    """Number of distinct real roots of each polynomial q (N, 9, ascending, degree 8) by
    the signs of the leading coefficients of its Sturm sequence (floats: a trigger for
    the careful way of :mod:`.batched`, not a proof).  -1 where a leading coefficient is
    negligible (a degree drop, of the octic or of the sequence)."""
    a = q[:, ::-1] / np.abs(q).max(axis=1, keepdims=True)       # descending, scaled
    b = a[:, :-1] * np.arange(8, 0, -1)                         # derivative
    lcs = [a[:, 0], b[:, 0]]
    for d in range(7, 0, -1):                                   # a: degree d+1, b: d
        with np.errstate(divide="ignore", invalid="ignore"):
            al = a[:, 0] / b[:, 0]
            ga = (a[:, 1] - al * b[:, 1]) / b[:, 0]
            # remainder of a / b, degree d - 1: a_i - al b_i - ga b_(i-1), i = 2 .. d+1
            r = a[:, 2:] - ga[:, None] * b[:, 1:]
            r[:, :-1] -= al[:, None] * b[:, 2:]
            a, b = b, -r / np.abs(r).max(axis=1, keepdims=True)
        lcs.append(b[:, 0])
    lc = np.array(lcs)                                          # (9, N), degrees 8..0
    deg = np.arange(8, -1, -1)[:, None]
    plus = lc > 0
    minus = np.where(deg % 2 == 0, plus, ~plus)
    count = (minus[1:] != minus[:-1]).sum(axis=0) - (plus[1:] != plus[:-1]).sum(axis=0)
    bad = ~np.isfinite(lc).all(axis=0) | (np.abs(lc) < 1e-12).any(axis=0)
    return np.where(bad, -1, count)


def real_roots(q, sizes, x0, h):
    """The real roots that the grid isolates, for N octics (see the module docstring),
    and the problems it cannot vouch for.

    Parameters
    ----------
    q : (N, 9) float, coefficients of :math:`O(x_0 + hu)`, ascending in u
        (:func:`~.closure.shifted_octic`)
    sizes : callable, rows -> (len(rows), 9) non-negative coefficients A with
        ``sum_j A_j |u|^j`` a bound on the size of the terms behind the value of the
        octic at u (for the rounding of ``q``), needed only where a minimum is tested
    x0, h : (N,) float, centre and half-width (h > 0) of the window that gets half of
        the grid (the feasible interval of :math:`s_{15}`)

    Returns
    -------
    row : (M,) int, the problem of each root
    x : (M,) float, the roots (unordered)
    step : (M,) float, the last refinement step in units of x
    doubt : (N,) bool, problems where the grid may have missed roots: its count differs
        from the Sturm count, or a minimum of |O| comes within the coefficients'
        rounding of zero (two close roots, or a nearly real complex pair)
    """
    n = q.shape[0]
    rows, u, st, doubt = _scan(q, sizes, x0, h)
    doubt |= _sturm_count(q) != np.bincount(rows, minlength=n)
    return rows, x0[rows] + h[rows] * u, st, doubt
