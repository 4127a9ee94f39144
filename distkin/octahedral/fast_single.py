r"""The fast tier for one problem: scalar Python per root, one numpy pass for the poses.

Rojas, Borràs and Thomas, ICRA 2012, Sec. III: the scalar flavour of the generated
kernel gives the octic and the quadratic parts of eq. (3); one LAPACK eigenvalue call on
the companion matrix of the scaled octic gives the starts (the batched tier,
:mod:`.fast`, scans instead and keeps this eigenvalue method for the problems it
doubts).  Then, per eigenvalue:

* **direct path** -- an eigenvalue that LAPACK returns exactly real (a 1x1 block of
  the real Schur form) whose neighbours, in the order of real parts, lie farther than
  :data:`_SEP` (relative) is a simple real root, accurate to the rounding of the octic's
  coefficients (~1e-9 relative): inside the triangle bounds at most two Newton steps on
  eq. (3) on its vanishing branch polish it (the accuracy the result states), outside
  (a spurious root) at most four Newton steps on the octic in Horner form; a first step
  above :data:`_CONFIRM` relative sends the eigenvalue to the careful path;
* **careful path** -- every other eigenvalue that is real or nearly so (two roots
  closer than :data:`_SEP`, a nearly real complex pair): Newton on the factored octic
  :math:`G^2-4R_1R_2` (deflated where two starts meet one root; a start that wanders is
  dropped as in :func:`.fast._newton`), then on eq. (3).

Real roots outside the triangle bounds of :math:`s_{15}`, or where a banana tetrahedron
has negative squared volume, are spurious.  The trilateration sequence of Sec. III
runs in the base-adapted frame (:func:`.assembly.assemble_components`, here in plain
floats, with everything that does not depend on the root computed once).  The two
mirror poses of every root, their rotations, translations and leg residuals are then
computed for all roots at once in one numpy pass.  Results are plain lists and array
views, turned into :class:`~.forward.Pose` objects by
:func:`.forward.forward_kinematics`.

Cost (Griffis-Duffy example, 6 real roots, 12 poses; CPU time on the shared 2-core
machine, stages timed in isolation, ~1.2-1.5x more inside the full call; see
BENCHMARKS.md for the whole call): the Python interpreter dominates.  Generated kernel
~12 µs; LAPACK ``dgeev`` on the 8x8 companion matrix ~8 µs plus ~7 µs of handling;
per real root ~6-8 µs (eq. (3), the trilateration sequence and the triangle frame,
~250 float operations at 25-35 ns each); the numpy pose pass for all 12 poses ~35 µs
(about 20 numpy calls of 1-3 µs each on tiny arrays).  The caller adds the input
checks (~5 µs) and the result objects (12 :class:`~.forward.Pose`, 6
:class:`~.forward.RootInfo`, ~20 µs).  The floor of this design is ~120 µs per call;
well separated roots take the direct path, so the careful Newton iterations (the
former cost of every root) are only paid next to close roots.
"""

from __future__ import annotations

import math
from operator import attrgetter, itemgetter

import numpy as np

from .._generated.octic_general import octic_scalar
from .fast import (_DUP, _GRACE, _NEAR_REAL, _NEWTON_DEFLATED, _NEWTON_MAX, _RATE, _RES,
                   _ROUNDS, _STEP)
from .problem import LEG_PAIRS

__all__ = ["solve_fast_single", "real_roots_scalar"]

try:  # numpy's own gufunc behind numpy.linalg.eigvals, without its per-call checks
    from numpy.linalg import _umath_linalg

    def _eigvals(a):
        return _umath_linalg.eigvals(a, signature="d->D")

    if not np.allclose(np.sort_complex(_eigvals(np.diag([2.0, 1.0]))), [1.0, 2.0]):
        raise ImportError
except Exception:  # pragma: no cover - other numpy layouts: the public function
    _eigvals = np.linalg.eigvals

#: relative distance from every other eigenvalue above which an exactly real eigenvalue
#: takes the direct path (closer ones may be a blurred pair of close roots)
_SEP = 1e-2
#: relative first Newton step on eq. (3) (or on the octic) above which a direct-path
#: eigenvalue is not trusted.  Isolated roots come out of LAPACK within the rounding
#: of the float octic's coefficients, ~1e-13..1e-9 relative; the polish then converges
#: quadratically (a start within 1e-6 of a root isolated by 1 % is deep in its basin)
_CONFIRM = 1e-6

_SUBDIAG = np.eye(8, k=-1)
_REAL = attrgetter("real")
_FIRST = itemgetter(0)
# the side -1 placement is the reflection z -> -z (adapted frame) of the side +1 one:
# points (X, Y, Z) -> (X, Y, -Z); triangle frame F -> M F D with M = D = diag(1, 1, -1)
_SIDE_SIGNS = np.array([[1.0] * 18,
                        [1.0, 1.0, -1.0] * 3
                        + [1.0, 1.0, -1.0, 1.0, 1.0, -1.0, -1.0, -1.0, 1.0]])[:, None]
_LEG_BASE = [i - 1 for i, _ in LEG_PAIRS]                   # P1 P2 P2 P3 P3 P1
_LEG_PLAT = [j - 4 for _, j in LEG_PAIRS]                   # P4 P4 P5 P5 P6 P6
# rows of the pose pass, picked from (adapted points (9), transposed frame (9)): the
# three points, the frame's rows, the platform end of each leg; and the signs of their
# mirror images (side -1)
_ROWS = np.array(list(range(18)) + [3 * p + m for p in _LEG_PLAT for m in range(3)])
_ROW_SIGNS = _SIDE_SIGNS[:, :, _ROWS]
# what is added to those rows after the product with the axes, as weights of P1 P2 P3:
# P1 for the points, 0 for the frame, P1 - (base end of the leg) for the legs
_OFFSETS = np.array([[1.0, 0.0, 0.0]] * 3 + [[0.0] * 3] * 3
                    + [[1.0 - (i == 0), -1.0 * (i == 1), -1.0 * (i == 2)] for i in _LEG_BASE])


def _quadratics(d):
    """Coefficients of the 10 quadratics of the kernel output ``d``: constant, linear,
    quadratic and twice the quadratic ones (10 each)."""
    c2 = d[2:30:3]
    return d[0:30:3], d[1:30:3], c2, [2 * v for v in c2]


def _parts(q, x):
    """The 10 quadratics of eq. (3) at x (``q`` from :func:`_quadratics`): values, then
    derivatives."""
    c0, c1, c2, c22 = q
    return ([a + x * (b + x * e) for a, b, e in zip(c0, c1, c2)],
            [b + x * e for b, e in zip(c1, c22)])


def _factored(val, der):
    (u, v, b1, b2, E1, E2, a, b, c, e), (du, dv, db1, db2, dE1, dE2, da, db, dc, de) = val, der
    G = u * E2 + v * E1 + 2 * b1 * b2
    dG = du * E2 + u * dE2 + dv * E1 + v * dE1 + 2 * (db1 * b2 + b1 * db2)
    ab, ce = a * b, c * e
    R = ab * ce
    dR = (da * b + a * db) * ce + ab * (dc * e + c * de)
    return G * G - 4 * R, 2 * G * dG - 4 * dR, G * G + 4 * abs(R)


def _newton(q, x, c, found=(), coef=None):
    """Newton on the factored octic (deflated by ``found``) from x.

    Returns the final x, the last step, convergence, and the point where the octic
    was last evaluated with the quadratics there (one negligible step before x).
    Convergence: the last step below :data:`.fast._STEP` relative and the octic small
    against the size of its terms (:data:`.fast._RES`), in the factored form or, with
    ``coef``, in the expanded form (next to a close root the factored form's
    cancellation can leave a residual above that level by rounding alone)."""
    step, prev, prev2 = 0.0, 0.0, math.inf
    H, Hs = 0.0, 1.0
    xe, pv = x, None
    for it in range(_NEWTON_DEFLATED if found else _NEWTON_MAX):
        pv = _parts(q, x)
        xe = x
        H, dH, Hs = _factored(*pv)
        defl = sum(1.0 / (x - r) for r in found if x != r) if found else 0.0
        den = dH - H * defl
        if den == 0 or not math.isfinite(den):
            step = math.inf
            break
        step = max(-0.5 * c, min(0.5 * c, H / den))
        x -= step
        size = max(abs(x), c)
        a = abs(step)
        # converged, or stalled at the rounding level of the factored octic
        if a <= 1e-14 * size or (a <= _STEP * size and a > 0.5 * prev):
            break
        if it >= _GRACE and a > _RATE * prev2:       # wanders: no real root to find here
            break
        prev2, prev = prev, a
    ok = abs(step) <= _STEP * max(abs(x), c) and math.isfinite(x) and (
        abs(H) <= _RES * Hs or (coef is not None and _small(coef, xe)))
    return x, step, ok, xe, pv


def _small(coef, x):
    """The octic in Horner form is below :data:`.fast._RES` times the size of its terms
    at x."""
    p, s, ax = 0.0, 0.0, abs(x)
    for a in coef:
        p = p * x + a
        s = s * ax + abs(a)
    return abs(p) <= _RES * s


def _polish(d, x, c):
    r"""Classify a root x of the octic inside the triangle bounds and polish it on eq. (3).

    From the kernel output ``d`` (the quadratics' coefficients at ``d[3i:3i+3]``, in the
    order u, v, b1, b2, E1, E2, T1a, T1b, T2a, T2b): if a banana tetrahedron has
    negative squared volume at x (below :math:`-10^{-9}c^3`), the root is spurious and
    ``(x, None)`` is returned; otherwise at most two Newton steps on the cleared eq. (3)
    :math:`P + \epsilon_1 v\sqrt{R_1} - \epsilon_2 u\sqrt{R_2}` on the branch where it is
    smallest (the second only when the first was not already below 1e-9 relative:
    quadratic convergence makes the next one negligible then), each clipped to 1e-3 c,
    none where a radicand is not positive.  Returns ``(x, last step, first step)``
    (steps 0.0 if none was taken)."""
    step = first = 0.0
    for k in (0, 1):
        u = d[0] + x * (d[1] + x * d[2])
        v = d[3] + x * (d[4] + x * d[5])
        b1 = d[6] + x * (d[7] + x * d[8])
        b2 = d[9] + x * (d[10] + x * d[11])
        a = d[18] + x * (d[19] + x * d[20])
        b = d[21] + x * (d[22] + x * d[23])
        cc = d[24] + x * (d[25] + x * d[26])
        e = d[27] + x * (d[28] + x * d[29])
        if k == 0 and min(a, b, cc, e) < -1e-9 * c * c * c:
            return x, None, None
        R1, R2 = a * b, cc * e
        if R1 <= 0 or R2 <= 0 or a < 0 or cc < 0:
            break
        x2 = 2 * x
        du, dv = d[1] + x2 * d[2], d[4] + x2 * d[5]
        db1, db2 = d[7] + x2 * d[8], d[10] + x2 * d[11]
        q1, q2 = math.sqrt(R1), math.sqrt(R2)
        P = u * b2 - v * b1
        vq1, uq2 = v * q1, u * q2
        N, e1, e2 = P + vq1 - uq2, 1, 1
        n_ = P + vq1 + uq2
        if abs(n_) < abs(N):
            N, e1, e2 = n_, 1, -1
        n_ = P - vq1 - uq2
        if abs(n_) < abs(N):
            N, e1, e2 = n_, -1, 1
        n_ = P - vq1 + uq2
        if abs(n_) < abs(N):
            N, e1, e2 = n_, -1, -1
        dq1 = ((d[19] + x2 * d[20]) * b + a * (d[22] + x2 * d[23])) / (2 * q1)
        dq2 = ((d[25] + x2 * d[26]) * e + cc * (d[28] + x2 * d[29])) / (2 * q2)
        dN = (du * b2 + u * db2 - dv * b1 - v * db1 + e1 * (dv * q1 + v * dq1)
              - e2 * (du * q2 + u * dq2))
        if dN == 0:
            break
        st = N / dN
        lim = 1e-3 * c
        st = lim if st > lim else (-lim if st < -lim else st)
        x -= st
        step = st
        if k == 0:
            first = st
        if abs(st) <= 1e-9 * abs(x):
            break
    return x, step, first


def _horner_newton(coef, x, c):
    """Newton on the octic in Horner form (coefficients highest first) from an accurate
    start: ``(x, last step)``, or ``(x, None)`` when the first step exceeds
    :data:`_CONFIRM` relative.  At most four steps; stops when a step is below 1e-14
    relative or stops shrinking (the rounding level of the octic)."""
    size = max(abs(x), c)
    prev = math.inf
    for k in range(4):
        p, dp = coef[0], 0.0
        for a in coef[1:]:
            dp = dp * x + p
            p = p * x + a
        st = p / dp if dp else math.inf
        a = abs(st)
        if k == 0 and not a <= _CONFIRM * size:
            return x, None
        if a >= prev:           # stalled at the rounding level: keep the last iterate
            break
        x -= st
        if a <= 1e-14 * size:
            break
        prev = a
    return x, st


class _Base:
    """Everything of the trilateration sequence that does not depend on the root."""

    def __init__(self, Bl, s2, l2):
        P1, P2, P3 = Bl
        v2 = [P2[0] - P1[0], P2[1] - P1[1], P2[2] - P1[2]]
        v3 = [P3[0] - P1[0], P3[1] - P1[1], P3[2] - P1[2]]
        self.s12 = s12 = v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]
        self.s13 = v3[0] * v3[0] + v3[1] * v3[1] + v3[2] * v3[2]
        self.d = d = math.sqrt(s12)
        e1 = [v2[0] / d, v2[1] / d, v2[2] / d]
        self.p3x = p3x = v3[0] * e1[0] + v3[1] * e1[1] + v3[2] * e1[2]
        w = [v3[0] - p3x * e1[0], v3[1] - p3x * e1[1], v3[2] - p3x * e1[2]]
        self.p3y = p3y = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
        e2 = [w[0] / p3y, w[1] / p3y, w[2] / p3y]
        e3 = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
              e1[0] * e2[1] - e1[1] * e2[0]]
        self.axes = [e1, e2, e3]                        # rows: adapted -> base frame
        self.s45, self.s46, self.s56 = s2[3], s2[4], s2[5]
        self.s14, self.s24, self.s25, self.s35, self.s36, self.s16 = l2
        self.X4 = X4 = (self.s14 - self.s24 + s12) / (2 * d)
        self.r4 = self.s14 - X4 * X4

    def assemble(self, x):
        """Side +1 placement of P4 P5 P6 in the adapted frame (9 floats, rows), its
        leg-5 residual and smallest relative squared height; None if degenerate.
        Same formulas as :func:`.assembly.assemble_components`."""
        s12, s13, d, p3x, p3y = self.s12, self.s13, self.d, self.p3x, self.p3y
        s14, s16, s36, s35 = self.s14, self.s16, self.s36, self.s35
        X5 = (x - self.s25 + s12) / (2 * d)
        Y5 = (x - s35 + s13 - 2 * p3x * X5) / (2 * p3y)
        h5 = x - X5 * X5 - Y5 * Y5
        Z5 = math.sqrt(h5) if h5 > 0 else 0.0
        rho2 = Y5 * Y5 + Z5 * Z5
        if rho2 == 0:
            return None
        X4 = self.X4
        g33 = X5 * X5 + rho2
        K4 = 0.5 * (s14 + g33 - self.s45) - X4 * X5
        h4 = self.r4 - K4 * K4 / rho2
        a4 = K4 / rho2
        b4 = math.sqrt(h4 / rho2) if h4 > 0 else 0.0
        w3 = 0.5 * (s16 + g33 - self.s56)
        s36_35 = s36 + s35
        best = None
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
            w2 = 0.5 * (s16 + g22 - self.s46)
            al = (w2 * g33 - w3 * g23) / G
            be = (w3 * g22 - w2 * g23) / G
            h6 = s16 - (al * w2 + be * w3)
            k6 = math.sqrt(h6 / G) if h6 > 0 else 0.0
            fx, fy, fz = al * X4 + be * X5, al * Y4 + be * Y5, al * Z4 + be * Z5
            ox, oy, oz = k6 * nx, k6 * ny, k6 * nz
            for X6, Y6, Z6 in ((fx + ox, fy + oy, fz + oz), (fx - ox, fy - oy, fz - oz)):
                dx, dy = X6 - p3x, Y6 - p3y
                r = abs((dx * dx + dy * dy + Z6 * Z6 - s36) / s36_35)
                if best is None or r < best[0]:
                    best = (r, (X4, Y4, Z4, X5, Y5, Z5, X6, Y6, Z6),
                            h6 / (s16 + g22 + g33))
            if best is not None and best[0] <= 1e-12 and tau > 0:
                break       # leg 5 closes to rounding: the other branch cannot do better
        if best is None:
            return None
        h2min = min(h5 / (abs(x) + s12 + s13), h4 / (s14 + s12 + g33), best[2])
        return best[1], best[0], h2min


def _frame_adapted(p):
    """Transposed frame of the triangle p = 9 floats (3 rows): the axes e1 e2 e3 as rows
    (9 floats), e1 along p1p2, e3 along the normal; None if degenerate."""
    d10, d11, d12 = p[3] - p[0], p[4] - p[1], p[5] - p[2]
    d20, d21, d22 = p[6] - p[0], p[7] - p[1], p[8] - p[2]
    n0 = d11 * d22 - d12 * d21
    n1 = d12 * d20 - d10 * d22
    n2 = d10 * d21 - d11 * d20
    l1 = math.sqrt(d10 * d10 + d11 * d11 + d12 * d12)
    ln = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if l1 == 0 or ln == 0:
        return None
    e10, e11, e12 = d10 / l1, d11 / l1, d12 / l1
    e30, e31, e32 = n0 / ln, n1 / ln, n2 / ln
    return (e10, e11, e12,
            e31 * e12 - e32 * e11, e32 * e10 - e30 * e12, e30 * e11 - e31 * e10,
            e30, e31, e32)


def _bounds(s2, l2):
    pairs = ((l2[0], s2[3]), (s2[1], l2[3]), (l2[5], s2[5]), (s2[0], l2[2]))
    lo = max((math.sqrt(a) - math.sqrt(b)) ** 2 for a, b in pairs)
    hi = min((math.sqrt(a) + math.sqrt(b)) ** 2 for a, b in pairs)
    return lo, hi


def _eigen(coef, c):
    """Eigenvalues (unscaled complex list) of the companion matrix of O(c t)."""
    big = 0.0
    sc, p = [0.0] * 9, 1.0
    for k in range(8, -1, -1):
        v = coef[k] * p
        sc[k] = v
        big = max(big, abs(v))
        p *= c
    if big == 0:
        return []
    if abs(sc[0]) <= 1e-12 * big:
        sc = [v / big for v in sc]
        eig = (np.roots(sc) if any(sc) else np.array([])).tolist()
    else:
        comp = _SUBDIAG.copy()
        lead = -sc[0]
        row = [v / lead for v in sc[1:]]
        comp[0] = row
        eig = (_eigvals(comp) if all(map(math.isfinite, row)) else
               np.linalg.eigvals(comp)).tolist()
        if any(z != z for z in eig):  # LAPACK did not converge: the public function raises
            eig = np.linalg.eigvals(comp).tolist()
    return [z * c for z in eig]


def _split(eig, c):
    """Direct-path eigenvalues and the careful path's starts from the eigenvalues ``eig``.

    Direct: exactly real, with the real parts of both neighbours (in real-part order,
    complex ones included) farther than :data:`_SEP` relative -- a conservative test of
    isolation.  Careful: one start per other real eigenvalue, two (a -+ b) per nearly
    real complex pair a +- ib (|b| below :data:`.fast._NEAR_REAL` relative)."""
    eig = sorted(eig, key=_REAL)
    res = [z.real for z in eig]
    n = len(eig)
    direct, starts = [], []
    for i, z in enumerate(eig):
        re, im = res[i], z.imag
        if im == 0:
            tol = _SEP * max(abs(re), c)
            if (i == 0 or re - res[i - 1] > tol) and (i == n - 1 or res[i + 1] - re > tol):
                direct.append(re)
            else:
                starts.append(re)
        elif im > 0 and im <= _NEAR_REAL * max(abs(z), c):
            starts.extend((re - im, re + im))
    return direct, starts


def solve_fast_single(B, Q, L, keep=None):
    """Every assembly mode of one problem, in plain floats.

    Parameters
    ----------
    B, Q : (3, 3) base points; platform points in the platform frame (float arrays or
        nested lists of floats, rows)
    L : (6,) leg lengths
    keep : dict, optional
        Receives ``sides2``, ``legs2`` (the squared lengths), ``data`` (the kernel
        output) and ``eigenvalues`` (of the octic's companion matrix, complex), for the
        conditioning estimate (:mod:`.conditioning`).

    Returns
    -------
    coef : list of 9 floats, the octic (highest degree first)
    lo, hi : floats, the triangle bounds of s15
    roots : list of [s15, |last Newton step|, status code of :data:`.fast.REASONS`]
    poses : list of (root index, side, points (3, 3), rotation (3, 3), translation (3,),
        max leg error, max relative leg error); arrays are views of one pass
    """
    Bl = B.tolist() if isinstance(B, np.ndarray) else [list(r) for r in B]
    Ql = Q.tolist() if isinstance(Q, np.ndarray) else [list(r) for r in Q]
    Ll = L.tolist() if isinstance(L, np.ndarray) else list(L)
    s2 = []
    for P in (Bl, Ql):
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = P
        s2 += [(ax - bx) ** 2 + (ay - by) ** 2 + (az - bz) ** 2,
               (ax - cx) ** 2 + (ay - cy) ** 2 + (az - cz) ** 2,
               (bx - cx) ** 2 + (by - cy) ** 2 + (bz - cz) ** 2]
    l2 = [v * v for v in Ll]
    d = octic_scalar(s2, l2)
    if keep is not None:
        keep.update(sides2=s2, legs2=l2, data=d)
    coef = d[30:]
    lo, hi = _bounds(s2, l2)
    found = real_roots_scalar(d, lo, hi, sum(s2) / 6, keep)
    roots, placed = [], []
    base = _Base(Bl, s2, l2)
    for x, st, code in found:
        if code == 0:
            out = base.assemble(min(max(x, max(lo, 0.0)), hi))
            F = _frame_adapted(out[0]) if out is not None and out[2] >= -1e-8 else None
            if F is None:
                code = 3
            else:
                placed.append((len(roots), out[0], F))
        roots.append([x, st, code])
    poses = _pose_pass(placed, roots, base, Bl, Ql, Ll) if placed else []
    return coef, lo, hi, roots, poses


def real_roots_scalar(d, lo, hi, scale, keep=None):
    """The real roots of one octic and their status, in plain floats: the direct and
    careful paths of the module docstring, without the trilateration sequence.

    Parameters
    ----------
    d : list of 39 floats, the kernel output (quadratic parts, then the octic)
    lo, hi : the triangle bounds of s15
    scale : a squared length of the problem, used when the bounds are empty

    Returns
    -------
    list of (s15, |last step|, code), increasing, at most 8; code 0 (inside the bounds,
    banana tetrahedra real, polished on eq. (3)), 1 or 2 (spurious, :data:`.fast.REASONS`)
    """
    coef = d[30:]
    c = 0.5 * (max(lo, 0.0) + hi) if hi > 0 else scale
    eig = _eigen(coef, c)
    if keep is not None:
        keep["eigenvalues"] = eig
    direct, starts = _split(eig, c)
    tol_x = 1e-9 * c
    lo_t, hi_t = lo - tol_x, hi + tol_x
    done = []                       # (x, |last step|, status code)
    for x0 in direct:
        if lo_t <= x0 <= hi_t:
            x, st, first = _polish(d, x0, c)
            if st is None:                      # a banana tetrahedron is not real
                x, st = _horner_newton(coef, x0, c)
                code = 2
            else:
                if first == 0.0:                # no step on eq. (3): a radicand vanishes
                    x, st = _horner_newton(coef, x0, c)
                elif abs(first) > _CONFIRM * max(abs(x0), c):
                    st = None                   # eq. (3) does not confirm the root
                code = 0
        else:
            x, st = _horner_newton(coef, x0, c)
            code = 1
        if st is None:
            starts.append(x0)                   # not confirmed: the careful path decides
        elif code == 1 and lo_t <= x <= hi_t:   # moved into the bounds: decide carefully
            starts.append(x0)
        else:
            done.append((x, abs(st), code))
    if starts:
        done += _careful(d, coef, starts, [r[0] for r in done], c, lo, hi)
    done.sort(key=_FIRST)
    return done[:8]


def _careful(d, coef, starts, known, c, lo, hi):
    """The careful path: Newton on the factored octic from ``starts``, deduplicated
    against each other and the ``known`` roots, deflated retries, then eq. (3).
    Returns (x, |last step|, code) records."""
    q = _quadratics(d)
    found, failed = [], []          # found: (x, step, point evaluated, its quadratics)
    for x0 in starts:
        x, st, ok, xe, pv = _newton(q, x0, c, (), coef)
        if ok and all(abs(x - r) > _DUP * max(abs(x), c) for r in known) and all(
                abs(x - r[0]) > _DUP * max(abs(x), c) for r in found):
            found.append((x, st, xe, pv))
        else:
            failed.append(x0)
    for _ in range(_ROUNDS):
        new = []
        roots = known + [r[0] for r in found]
        for x0 in failed:
            x, st, ok, xe, pv = _newton(q, x0, c, roots, coef)
            if ok and all(abs(x - r) > _DUP * max(abs(x), c) for r in roots) and all(
                    abs(x - r[0]) > _DUP * max(abs(x), c) for r in new):
                new.append((x, st, xe, pv))
        if not new:
            break
        found += new
    out = []
    tol_x = 1e-9 * c
    for x, st, xe, pv in found:
        if not lo - tol_x <= x <= hi + tol_x:
            out.append((x, abs(st), 1))
            continue
        xp, st2, _ = _polish(d, xe, c)
        if st2 is None:
            out.append((x, abs(st), 2))
        else:
            out.append((xp, abs(st2) if st2 else abs(st), 0))
    return out


def _pose_pass(placed, roots, base, Bl, Ql, Ll):
    """Both mirror poses of every placed root at once: points, rotations, translations
    and leg residuals (numpy over (side, root)); roots whose legs are off by 1e-6
    relative or more are marked rejected (code 3).

    One matrix product maps the adapted rows of every placement (points P4 P5 P6, the
    transposed triangle frame :math:`F^T`, and the platform end of each leg), side +1
    and its mirror image, to the base frame: ``M = rows @ A`` with A the base-adapted
    axes.  Then :math:`R = (F^TA)^T F_q^T` (:math:`F_q` the platform triangle's frame),
    :math:`t = \bar p - R\bar q`, and the leg residuals."""
    k = len(placed)
    A = base.axes
    rows = (np.array([p[1] + p[2] for p in placed])[:, _ROWS] * _ROW_SIGNS).reshape(
        2 * k, 12, 3)
    M = rows @ A
    M += _OFFSETS @ Bl
    P = M[:, :3]
    Fq = _frame_adapted(Ql[0] + Ql[1] + Ql[2])
    R = M[:, 3:6].transpose(0, 2, 1) @ [Fq[0:3], Fq[3:6], Fq[6:9]]
    qc = [(Ql[0][m] + Ql[1][m] + Ql[2][m]) / 3 for m in range(3)]
    t = P.sum(axis=1) * (1 / 3) - R @ qc
    dv = M[:, 6:]
    Ln = np.array(Ll)
    e = np.abs(np.sqrt(np.einsum("...k,...k->...", dv, dv)) - Ln)
    e_abs = e.max(-1).tolist()
    e_rel = (e / Ln).max(-1).tolist()
    Pl, Rl, tl = list(P), list(R), list(t)
    poses = []
    for j, (ri, _, _) in enumerate(placed):
        if e_rel[j] < 1e-6 and e_rel[k + j] < 1e-6:
            for i, side in ((j, 1), (k + j, -1)):
                poses.append((ri, side, Pl[i], Rl[i], tl[i], e_abs[i], e_rel[i]))
        else:
            roots[ri][2] = 3
    return poses


