r"""The fast tier for one problem: scalar Python per root, one numpy pass for the poses.

Same algorithm as :mod:`.fast` (Rojas, Borràs and Thomas, ICRA 2012, Sec. III): the
scalar flavour of the generated kernel gives the octic and the quadratic parts of
eq. (3); one LAPACK eigenvalue call on the companion matrix of the scaled octic gives
the starts; Newton on the factored octic :math:`G^2-4R_1R_2` (deflated where two starts
meet one root; a start that wanders is dropped as in :func:`.fast._newton`), then on
eq. (3) on its vanishing branch; the trilateration sequence of Sec. III in the
base-adapted frame (:func:`.assembly.assemble_components`, here in plain floats, with
everything that does not depend on the root computed once).  The two mirror poses of
every root, their rotations, translations and leg residuals are then computed for all
roots at once with a handful of numpy calls.  Results are plain lists and array views,
turned into :class:`~.forward.Pose` objects by :func:`.forward.forward_kinematics`.

Cost: the Python interpreter dominates.  Measured stage by stage on the shared 2-core
machine under a load of about 3.5: the kernel ~15 µs, the eigenvalues with their
handling ~16 µs, ~10 µs per real root (Newton, eq. (3), trilateration sequence, frame)
and ~40 µs for the numpy pose pass (see BENCHMARKS.md for the totals).
"""

from __future__ import annotations

import math

import numpy as np

from .._generated.octic_general import octic_scalar
from .fast import (_DUP, _GRACE, _NEAR_REAL, _NEWTON_DEFLATED, _NEWTON_MAX, _RATE, _RES,
                   _ROUNDS, _STEP)
from .problem import LEG_PAIRS, SIDE_PAIRS

__all__ = ["solve_fast_single"]

try:  # numpy's own gufunc behind numpy.linalg.eigvals, without its per-call checks
    from numpy.linalg import _umath_linalg

    def _eigvals(a):
        return _umath_linalg.eigvals(a, signature="d->D")

    if not np.allclose(np.sort_complex(_eigvals(np.diag([2.0, 1.0]))), [1.0, 2.0]):
        raise ImportError
except Exception:  # pragma: no cover - other numpy layouts: the public function
    _eigvals = np.linalg.eigvals

_SUBDIAG = np.eye(8, k=-1)
# the side -1 placement is the reflection z -> -z (adapted frame) of the side +1 one:
# points (X, Y, Z) -> (X, Y, -Z); triangle frame F -> M F D with M = D = diag(1, 1, -1)
_SIDE_SIGNS = np.array([[1.0] * 18,
                        [1.0, 1.0, -1.0] * 3
                        + [1.0, 1.0, -1.0, 1.0, 1.0, -1.0, -1.0, -1.0, 1.0]])[:, None]
_LEG_BASE = np.array([i - 1 for i, _ in LEG_PAIRS])          # P1 P2 P2 P3 P3 P1
_LEG_PLAT = np.array([j - 4 for _, j in LEG_PAIRS])          # P4 P4 P5 P5 P6 P6


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


def _newton(q, x, c, found=()):
    """Newton on the factored octic (deflated by ``found``) from x.

    Returns the final x, the last step, convergence, and the point where the octic
    was last evaluated with the quadratics there (one negligible step before x)."""
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
    ok = abs(step) <= _STEP * max(abs(x), c) and abs(H) <= _RES * Hs and math.isfinite(x)
    return x, step, ok, xe, pv


def _eq3_step(val, der, c):
    """One Newton step on eq. (3) on the branch where it is smallest (None if a radicand
    is negative there)."""
    (u, v, b1, b2, _, _, a, b, cc, e), (du, dv, db1, db2, _, _, da, db, dc, de) = val, der
    R1, R2 = a * b, cc * e
    if R1 <= 0 or R2 <= 0 or a < 0 or cc < 0:
        return None
    q1, q2 = math.sqrt(R1), math.sqrt(R2)
    P = u * b2 - v * b1
    vq1, uq2 = v * q1, u * q2
    N, e1, e2 = P + vq1 - uq2, 1, 1
    for n_, s1, s2 in ((P + vq1 + uq2, 1, -1), (P - vq1 - uq2, -1, 1), (P - vq1 + uq2, -1, -1)):
        if abs(n_) < abs(N):
            N, e1, e2 = n_, s1, s2
    dq1 = (da * b + a * db) / (2 * q1)
    dq2 = (dc * e + cc * de) / (2 * q2)
    dN = (du * b2 + u * db2 - dv * b1 - v * db1 + e1 * (dv * q1 + v * dq1)
          - e2 * (du * q2 + u * dq2))
    if dN == 0:
        return None
    return max(-1e-3 * c, min(1e-3 * c, N / dN))


def _eq3_polish(q, x, pv, c):
    """At most two Newton steps on eq. (3) from x (quadratics ``pv`` at x); the second
    only when the first was not already below 1e-9 relative (quadratic convergence
    makes the next one negligible then)."""
    step = 0.0
    for k in range(2):
        st = _eq3_step(*pv, c)
        if st is None:
            break
        x -= st
        step = st
        if abs(st) <= 1e-9 * abs(x) or k == 1:
            break
        pv = _parts(q, x)
    return x, step


class _Base:
    """Everything of the trilateration sequence that does not depend on the root."""

    def __init__(self, Bl, s2, l2):
        P1, P2, P3 = Bl
        v2 = [P2[k] - P1[k] for k in range(3)]
        v3 = [P3[k] - P1[k] for k in range(3)]
        self.s12 = v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]
        self.s13 = v3[0] * v3[0] + v3[1] * v3[1] + v3[2] * v3[2]
        self.d = d = math.sqrt(self.s12)
        e1 = [c / d for c in v2]
        self.p3x = p3x = v3[0] * e1[0] + v3[1] * e1[1] + v3[2] * e1[2]
        w = [v3[k] - p3x * e1[k] for k in range(3)]
        self.p3y = p3y = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
        e2 = [c / p3y for c in w]
        e3 = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
              e1[0] * e2[1] - e1[1] * e2[0]]
        self.axes = np.array([e1, e2, e3])              # rows: adapted -> base frame
        self.axes_t = self.axes.T
        self.leg_base = np.array(Bl)[_LEG_BASE]         # base end of legs 1..6
        self.s45, self.s46, self.s56 = s2[3], s2[4], s2[5]
        self.s14, self.s24, self.s25, self.s35, self.s36, self.s16 = l2
        self.X4 = (self.s14 - self.s24 + self.s12) / (2 * d)
        self.r4 = self.s14 - self.X4 * self.X4

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
                r = abs((dx * dx + dy * dy + Z6 * Z6 - s36) / (s36 + s35))
                if best is None or r < best[0]:
                    best = (r, (X4, Y4, Z4, X5, Y5, Z5, X6, Y6, Z6),
                            h6 / (s16 + g22 + g33))
        if best is None:
            return None
        h2min = min(h5 / (abs(x) + s12 + s13), h4 / (s14 + s12 + g33), best[2])
        return best[1], best[0], h2min


def _frame_adapted(p):
    """Frame (rows of 3, columns e1 e2 e3) of the triangle p = 9 floats (3 rows)."""
    d1 = (p[3] - p[0], p[4] - p[1], p[5] - p[2])
    d2 = (p[6] - p[0], p[7] - p[1], p[8] - p[2])
    n = (d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
         d1[0] * d2[1] - d1[1] * d2[0])
    l1 = math.sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2])
    ln = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    if l1 == 0 or ln == 0:
        return None
    e1 = (d1[0] / l1, d1[1] / l1, d1[2] / l1)
    e3 = (n[0] / ln, n[1] / ln, n[2] / ln)
    e2 = (e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
          e3[0] * e1[1] - e3[1] * e1[0])
    return (e1[0], e2[0], e3[0], e1[1], e2[1], e3[1], e1[2], e2[2], e3[2])


def _bounds(s2, l2):
    pairs = ((l2[0], s2[3]), (s2[1], l2[3]), (l2[5], s2[5]), (s2[0], l2[2]))
    lo = max((math.sqrt(a) - math.sqrt(b)) ** 2 for a, b in pairs)
    hi = min((math.sqrt(a) + math.sqrt(b)) ** 2 for a, b in pairs)
    return lo, hi


def _eigen_starts(coef, c):
    """Starts from the eigenvalues of the companion matrix of O(c t) (as :mod:`.fast`)."""
    sc = [coef[k] * c ** (8 - k) for k in range(9)]
    big = max(abs(v) for v in sc) or 1.0
    sc = [v / big for v in sc]
    if abs(sc[0]) <= 1e-12:
        eig = (np.roots(sc) if any(sc) else np.array([])).tolist()
    else:
        comp = _SUBDIAG.copy()
        row = [-v / sc[0] for v in sc[1:]]
        comp[0] = row
        eig = (_eigvals(comp) if all(map(math.isfinite, row)) else
               np.linalg.eigvals(comp)).tolist()
        if any(z != z for z in eig):  # LAPACK did not converge: the public function raises
            eig = np.linalg.eigvals(comp).tolist()
    starts = []
    for z in eig:
        z = z * c
        re, im = z.real, abs(z.imag)
        if im > _NEAR_REAL * max(abs(z), c):
            continue
        if z.imag == 0:
            starts.append(re)
        elif z.imag > 0:
            starts.extend((re - im, re + im))
    return starts


def solve_fast_single(B, Q, L):
    """Every assembly mode of one problem, in plain floats.

    Parameters
    ----------
    B, Q : (3, 3) float arrays (base points; platform points in the platform frame)
    L : (6,) leg lengths

    Returns
    -------
    coef : list of 9 floats, the octic (highest degree first)
    lo, hi : floats, the triangle bounds of s15
    roots : list of [s15, |last Newton step|, status code of :data:`.fast.REASONS`]
    poses : list of (root index, side, points (3, 3), rotation (3, 3), translation (3,),
        max leg error, max relative leg error); arrays are views of one pass
    """
    Bl = B.tolist()
    pts = Bl + Q.tolist()
    s2 = [sum((pts[i - 1][k] - pts[j - 1][k]) ** 2 for k in range(3)) for i, j in SIDE_PAIRS]
    Ll = L.tolist()
    l2 = [v * v for v in Ll]
    d = octic_scalar(s2, l2)
    coef = d[30:]
    q = _quadratics(d)
    lo, hi = _bounds(s2, l2)
    c = 0.5 * (max(lo, 0.0) + hi) if hi > 0 else sum(s2) / 6
    found, failed = [], []          # found: (x, step, point evaluated, its quadratics)
    for x0 in _eigen_starts(coef, c):
        x, st, ok, xe, pv = _newton(q, x0, c)
        if ok and all(abs(x - r[0]) > _DUP * max(abs(x), c) for r in found):
            found.append((x, st, xe, pv))
        else:
            failed.append(x0)
    for _ in range(_ROUNDS):
        new = []
        for x0 in failed:
            x, st, ok, xe, pv = _newton(q, x0, c, [r[0] for r in found])
            if ok and all(abs(x - r[0]) > _DUP * max(abs(x), c) for r in found + new):
                new.append((x, st, xe, pv))
        if not new:
            break
        found += new
    found.sort(key=lambda r: r[0])
    found = found[:8]
    roots = []                      # [x, |last step|, status code]
    placed = []                     # (root index, adapted side +1 points, frame)
    base = None
    tol_x = 1e-9 * c
    for x, st, xe, pv in found:
        if not lo - tol_x <= x <= hi + tol_x:
            code = 1
        elif min(pv[0][6:]) < -1e-9 * c ** 3:
            code = 2
        else:
            x, st2 = _eq3_polish(q, xe, pv, c)
            st = st2 if st2 else st
            code = 3
            base = base or _Base(Bl, s2, l2)
            out = base.assemble(min(max(x, max(lo, 0.0)), hi))
            if out is not None and out[2] >= -1e-8:
                F = _frame_adapted(out[0])
                if F is not None:
                    code = 0
                    placed.append((len(roots), out[0], F))
        roots.append([x, abs(st), code])
    poses = []
    if placed:
        poses = _pose_pass(placed, roots, base, Bl, pts[3:], Ll)
    return coef, lo, hi, roots, poses


def _pose_pass(placed, roots, base, Bl, Ql, Ll):
    """Both mirror poses of every placed root at once: points, rotations, translations
    and leg residuals (numpy over (side, root)); roots whose legs are off by 1e-6
    relative or more are marked rejected (code 3)."""
    k = len(placed)
    # adapted points (9) and frame (9) of side +1, and their mirror images: (2, k, 18)
    both = np.array([p[1] + p[2] for p in placed]) * _SIDE_SIGNS
    P = both[:, :, :9].reshape(2, k, 3, 3) @ base.axes
    P += Bl[0]                                                       # base frame
    R = base.axes_t @ both[:, :, 9:].reshape(2, k, 3, 3) @ _platform_frame_t(Ql)
    qc = [(Ql[0][m] + Ql[1][m] + Ql[2][m]) * (1 / 3) for m in range(3)]
    t = P.sum(axis=2) * (1 / 3) - R @ qc
    dv = P[:, :, _LEG_PLAT, :] - base.leg_base                       # (2, k, 6, 3)
    Ln = np.array(Ll)
    e = np.abs(np.sqrt(np.einsum("...k,...k->...", dv, dv)) - Ln)
    e_abs = e.max(-1).tolist()
    e_rel = (e / Ln).max(-1).tolist()
    Pl, Rl = list(P.reshape(2 * k, 3, 3)), list(R.reshape(2 * k, 3, 3))
    tl = list(t.reshape(2 * k, 3))
    poses = []
    for j, (ri, _, _) in enumerate(placed):
        if e_rel[0][j] < 1e-6 and e_rel[1][j] < 1e-6:
            for s, side in ((0, 1), (1, -1)):
                i = s * k + j
                poses.append((ri, side, Pl[i], Rl[i], tl[i], e_abs[s][j], e_rel[s][j]))
        else:
            roots[ri][2] = 3
    return poses


def _platform_frame_t(Ql):
    """Transposed frame (rows e1 e2 e3) of the platform triangle, as a 3x3 list."""
    F = _frame_adapted(Ql[0] + Ql[1] + Ql[2])
    return [[F[0], F[3], F[6]], [F[1], F[4], F[7]], [F[2], F[5], F[8]]]
