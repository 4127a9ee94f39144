r"""The fast tier for one problem, in plain Python floats (no per-operation numpy cost).

Same algorithm as :mod:`.fast` (Rojas, Borràs and Thomas, ICRA 2012, Sec. III): the
scalar flavour of the generated kernel gives the octic and the quadratic parts of
eq. (3); one ``numpy.linalg.eigvals`` call on the companion matrix of the scaled octic
gives the starts; Newton on the factored octic :math:`G^2-4R_1R_2`, deflated where two
starts meet one root, then on eq. (3) on its vanishing branch; the trilateration
sequence of Sec. III in scalar arithmetic.  Results are plain lists, turned into
:class:`~.forward.Pose` objects by :func:`.forward.forward_kinematics`.
"""

from __future__ import annotations

import math

import numpy as np

from .._generated.octic_general import octic_scalar
from .fast import (_DUP, _NEAR_REAL, _NEWTON_DEFLATED, _NEWTON_EQ3, _NEWTON_MAX, _RES,
                   _ROUNDS, _STEP)

__all__ = ["solve_fast_single"]

_NP = 10  # parts


def _parts(d, x):
    val = [d[3 * k] + x * (d[3 * k + 1] + x * d[3 * k + 2]) for k in range(_NP)]
    der = [d[3 * k + 1] + 2 * x * d[3 * k + 2] for k in range(_NP)]
    return val, der


def _factored(d, x):
    (u, v, b1, b2, E1, E2, a, b, c, e), (du, dv, db1, db2, dE1, dE2, da, db, dc, de) = _parts(d, x)
    G = u * E2 + v * E1 + 2 * b1 * b2
    dG = du * E2 + u * dE2 + dv * E1 + v * dE1 + 2 * (db1 * b2 + b1 * db2)
    R = a * b * c * e
    dR = da * b * c * e + a * db * c * e + a * b * dc * e + a * b * c * de
    return G * G - 4 * R, 2 * G * dG - 4 * dR, G * G + 4 * abs(R)


def _newton(d, x, c, found=()):
    step = prev = 0.0
    H, Hs = 0.0, 1.0
    for _ in range(_NEWTON_DEFLATED if found else _NEWTON_MAX):
        H, dH, Hs = _factored(d, x)
        defl = sum(1.0 / (x - r) for r in found if x != r) if found else 0.0
        den = dH - H * defl
        if den == 0 or not math.isfinite(den):
            step = math.inf
            break
        step = max(-0.5 * c, min(0.5 * c, H / den))
        x -= step
        size = max(abs(x), c)
        # converged, or stalled at the rounding level of the factored octic
        if abs(step) <= 1e-14 * size or (abs(step) <= _STEP * size and abs(step) > 0.5 * prev):
            break
        prev = abs(step)
    # H was evaluated one (negligible) step before x
    ok = abs(step) <= _STEP * max(abs(x), c) and abs(H) <= _RES * Hs and math.isfinite(x)
    return x, step, ok


def _eq3_polish(d, x, c):
    """Newton on eq. (3) on the branch where it is smallest (radicands must be >= 0)."""
    step = 0.0
    for _ in range(_NEWTON_EQ3):
        (u, v, b1, b2, _, _, a, b, cc, e), (du, dv, db1, db2, _, _, da, db, dc, de) = \
            _parts(d, x)
        R1, R2 = a * b, cc * e
        if R1 <= 0 or R2 <= 0 or a < 0 or cc < 0:
            break
        q1, q2 = math.sqrt(R1), math.sqrt(R2)
        P = u * b2 - v * b1
        N, e1, e2 = min(((P + s1 * v * q1 - s2 * u * q2, s1, s2) for s1 in (1, -1)
                         for s2 in (1, -1)), key=lambda t: abs(t[0]))
        dq1 = (da * b + a * db) / (2 * q1)
        dq2 = (dc * e + cc * de) / (2 * q2)
        dN = (du * b2 + u * db2 - dv * b1 - v * db1 + e1 * (dv * q1 + v * dq1)
              - e2 * (du * q2 + u * dq2))
        if dN == 0:
            break
        st = max(-1e-3 * c, min(1e-3 * c, N / dN))
        x -= st
        step = st
        if abs(st) <= 1e-13 * abs(x):
            break
    return x, step


def _trilat(A, B, C, sa, sb, sc):
    """Foot, unit-scaled height vector and relative h^2 (Thomas and Ros 2005, Gram form)."""
    v2 = (B[0] - A[0], B[1] - A[1], B[2] - A[2])
    v3 = (C[0] - A[0], C[1] - A[1], C[2] - A[2])
    g22 = v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]
    g33 = v3[0] * v3[0] + v3[1] * v3[1] + v3[2] * v3[2]
    g23 = v2[0] * v3[0] + v2[1] * v3[1] + v2[2] * v3[2]
    n = (v2[1] * v3[2] - v2[2] * v3[1], v2[2] * v3[0] - v2[0] * v3[2],
         v2[0] * v3[1] - v2[1] * v3[0])
    G = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
    if G <= 0:
        return None
    w2 = (sa + g22 - sb) / 2
    w3 = (sa + g33 - sc) / 2
    al = (w2 * g33 - w3 * g23) / G
    be = (w3 * g22 - w2 * g23) / G
    foot = (A[0] + al * v2[0] + be * v3[0], A[1] + al * v2[1] + be * v3[1],
            A[2] + al * v2[2] + be * v3[2])
    h2 = sa - (al * w2 + be * w3)
    k = math.sqrt(max(h2, 0.0) / G)
    return foot, (k * n[0], k * n[1], k * n[2]), h2 / (abs(sa) + g22 + g33)


def _assemble(B, x, s2, l2):
    """Both mirror placements (rows P4 P5 P6), their min relative h^2 and leg-5 residual.

    The sequence runs for the side +1 of P5; the side -1 placement is its reflection in
    the base plane (the sequence commutes with that reflection, which fixes P1 P2 P3)."""
    P1, P2, P3 = B
    s45, s46, s56 = s2[3], s2[4], s2[5]
    s14, s24, s25, s35, s36, s16 = l2
    t5 = _trilat(P1, P2, P3, x, s25, s35)
    if t5 is None:
        return None
    f5, o5, h5 = t5
    P5 = (f5[0] + o5[0], f5[1] + o5[1], f5[2] + o5[2])
    t4 = _trilat(P1, P2, P5, s14, s24, s45)
    if t4 is None:
        return None
    f4, o4, h4 = t4
    best = None
    for tau in (1.0, -1.0):
        P4 = (f4[0] + tau * o4[0], f4[1] + tau * o4[1], f4[2] + tau * o4[2])
        t6 = _trilat(P1, P4, P5, s16, s46, s56)
        if t6 is None:
            continue
        f6, o6, h6 = t6
        for rho in (1.0, -1.0):
            P6 = (f6[0] + rho * o6[0], f6[1] + rho * o6[1], f6[2] + rho * o6[2])
            r = abs((P6[0] - P3[0]) ** 2 + (P6[1] - P3[1]) ** 2 + (P6[2] - P3[2]) ** 2
                    - s36) / (s36 + s35)
            if best is None or r < best[0]:
                best = (r, (P4, P5, P6), min(h5, h4, h6))
    if best is None:
        return None
    # reflection in the base plane: p -> p - 2 ((p - P1) . n) n, n the unit base normal
    v2 = (P2[0] - P1[0], P2[1] - P1[1], P2[2] - P1[2])
    v3 = (P3[0] - P1[0], P3[1] - P1[1], P3[2] - P1[2])
    n = (v2[1] * v3[2] - v2[2] * v3[1], v2[2] * v3[0] - v2[0] * v3[2],
         v2[0] * v3[1] - v2[1] * v3[0])
    nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
    mirror = []
    for p in best[1]:
        k = 2 * ((p[0] - P1[0]) * n[0] + (p[1] - P1[1]) * n[1] + (p[2] - P1[2]) * n[2]) / nn
        mirror.append((p[0] - k * n[0], p[1] - k * n[1], p[2] - k * n[2]))
    return [best, (best[0], tuple(mirror), best[2])]


def _frame(a1, a2, a3):
    """Right-handed orthonormal frame (columns e1 e2 e3) of a triangle, rows F[i][j]."""
    d1 = (a2[0] - a1[0], a2[1] - a1[1], a2[2] - a1[2])
    d2 = (a3[0] - a1[0], a3[1] - a1[1], a3[2] - a1[2])
    n = (d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
         d1[0] * d2[1] - d1[1] * d2[0])
    l1 = math.sqrt(d1[0] ** 2 + d1[1] ** 2 + d1[2] ** 2)
    ln = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    if ln == 0 or l1 == 0:
        return None
    e1 = (d1[0] / l1, d1[1] / l1, d1[2] / l1)
    e3 = (n[0] / ln, n[1] / ln, n[2] / ln)
    e2 = (e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2],
          e3[0] * e1[1] - e3[1] * e1[0])
    return [[e1[i], e2[i], e3[i]] for i in range(3)]


def _bounds(s2, l2):
    pairs = ((l2[0], s2[3]), (s2[1], l2[3]), (l2[5], s2[5]), (s2[0], l2[2]))
    lo = max((math.sqrt(a) - math.sqrt(b)) ** 2 for a, b in pairs)
    hi = min((math.sqrt(a) + math.sqrt(b)) ** 2 for a, b in pairs)
    return lo, hi


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
    poses : list of (root index, side, points (3 tuples), rotation (3x3 lists),
        translation (3), max leg error, max relative leg error)
    """
    from .problem import LEG_PAIRS, SIDE_PAIRS
    Bl = B.tolist()
    pts = Bl + Q.tolist()
    s2 = [sum((pts[i - 1][k] - pts[j - 1][k]) ** 2 for k in range(3)) for i, j in SIDE_PAIRS]
    Ll = L.tolist()
    l2 = [v * v for v in Ll]
    d = octic_scalar(s2, l2)
    coef = d[30:]
    lo, hi = _bounds(s2, l2)
    c = 0.5 * (max(lo, 0.0) + hi) if hi > 0 else sum(s2) / 6
    sc = [coef[k] * c ** (8 - k) for k in range(9)]
    big = max(abs(v) for v in sc) or 1.0
    sc = [v / big for v in sc]
    if abs(sc[0]) <= 1e-12:
        eig = (np.roots(sc) if any(sc) else np.array([])).tolist()
    else:
        comp = np.zeros((8, 8))
        comp[0, :] = [-v / sc[0] for v in sc[1:]]
        comp[range(1, 8), range(7)] = 1.0
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
    found, failed = [], []
    for x0 in starts:
        x, st, ok = _newton(d, x0, c)
        if ok and all(abs(x - r) > _DUP * max(abs(x), c) for r, _ in found):
            found.append((x, st))
        else:
            failed.append(x0)
    for _ in range(_ROUNDS):
        new = []
        for x0 in failed:
            x, st, ok = _newton(d, x0, c, [r for r, _ in found])
            if ok and all(abs(x - r) > _DUP * max(abs(x), c) for r, _ in found + new):
                new.append((x, st))
        if not new:
            break
        found += new
    found.sort()
    found = found[:8]
    roots = []                      # [x, |last step|, status code]
    placed = []                     # (root index, [placement side +1, side -1])
    for x, st in found:
        val, _ = _parts(d, x)
        tol_x = 1e-9 * c
        if not lo - tol_x <= x <= hi + tol_x:
            code = 1
        elif min(val[6:]) < -1e-9 * c ** 3:
            code = 2
        else:
            x, st2 = _eq3_polish(d, x, c)
            st = st2 if st2 else st
            code = 0
            pair = _assemble(Bl, min(max(x, max(lo, 0.0)), hi), s2, l2)
            if pair is None or min(p[2] for p in pair) < -1e-8:
                code = 3
            else:
                placed.append((len(roots), [p[1] for p in pair]))
        roots.append([x, abs(st), code])
    poses = []                      # (root index, side, points, R, t, err, rel)
    Fq = _frame(pts[3], pts[4], pts[5])
    qc = [(pts[3][k] + pts[4][k] + pts[5][k]) / 3 for k in range(3)]
    for k, pair in placed:
        built = []
        for side, P in zip((1, -1), pair):
            Fp = _frame(*P)
            if Fp is None or Fq is None:
                break
            R = [[Fp[i][0] * Fq[j][0] + Fp[i][1] * Fq[j][1] + Fp[i][2] * Fq[j][2]
                  for j in range(3)] for i in range(3)]
            pc = [(P[0][m] + P[1][m] + P[2][m]) / 3 for m in range(3)]
            t = [pc[i] - R[i][0] * qc[0] - R[i][1] * qc[1] - R[i][2] * qc[2] for i in range(3)]
            full = (Bl[0], Bl[1], Bl[2]) + tuple(P)
            errs = [abs(math.dist(full[i - 1], full[j - 1]) - ln)
                    for (i, j), ln in zip(LEG_PAIRS, Ll)]
            e_abs = max(errs)
            e_rel = max(e / ln for e, ln in zip(errs, Ll))
            if e_rel >= 1e-6:
                break
            built.append((k, side, P, R, t, e_abs, e_rel))
        if len(built) == 2:
            poses.extend(built)
        else:
            roots[k][2] = 3
    return coef, lo, hi, roots, poses
