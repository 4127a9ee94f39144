"""Derive and check the Δ-transform algebra and the singularity identities, step by step.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sections
IV-VI.  Run from the repository root::

    python derivations/delta_transform.py

Every step prints what was derived and asserts a check against the paper's printed
formula or an independent route.  ``--help`` describes the script; any argument other
than ``-h``/``--help`` is refused (exit status 2).  Exit status 0 means every check
passed.
"""

from __future__ import annotations

import argparse
import random
import sys
from fractions import Fraction
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

from distkin.delta import (ROWS, delta_matrices, delta_transform, derive_eq7,  # noqa: E402
                           equivalent_platform)
from distkin.errors import DegenerateGeometryError  # noqa: E402
from distkin.singularity import (RATIO_CONSTANT, cm_pure_condition, four_planes,  # noqa: E402
                                 jacobian_det, octahedral_joints, signed_cm_condition,
                                 volume_factors)

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
M_LEGS = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)",
          "1/25*sqrt(136210)", "1/5*sqrt(8153)"]
L_LEGS = [sp.Rational(198, 10), 18, 18, 17, sp.Rational(149, 10), sp.Rational(178, 10)]


def step(title):
    print(f"\n== {title}")


def check(cond, what):
    if not cond:
        raise SystemExit(f"CHECK FAILED: {what}")
    print(f"   ok: {what}")


def parse_args(argv=None):
    ap = argparse.ArgumentParser(
        prog="delta_transform.py",
        description="Derive and check the Delta-transform algebra and the singularity "
                    "identities step by step: Rojas, Borràs, Thomas, The Octahedral "
                    "Manipulator Revisited (ICRA 2012), Secs. IV-VI, eqs. (4)-(9) and "
                    "the Sec. VI example.  Exit status 0 means every check passed.")
    return ap.parse_args(argv)


def main(argv=None) -> None:
    parse_args(argv)
    # ---------------------------------------------------------------- eq. (7)
    step("1. eq. (7) from the vanishing Cayley-Menger determinant D(1,2,3,4)")
    eq = derive_eq7()
    s = eq.symbols
    d, delta, s13, s23, s34 = s["d"], s["delta"], s["s13"], s["s23"], s["s34"]
    print("   D(1,2,3,4) with s14 = delta^2, s24 = (d - delta)^2, s12 = d^2 factors as -2 L^2,")
    print(f"   L = {eq.relation}")
    printed7 = delta * s23 + (d - delta) * s13 - d * s34 - d * delta * (d - delta)
    check(sp.expand(eq.relation - printed7) == 0, "L equals the paper's eq. (7) exactly")
    # D(1,2,3,4) from the paper's definition (Sec. II): the bordered determinant of the
    # squared distances, built here, not by derive_eq7 (whose cm produced L)
    sq = {(1, 2): d ** 2, (1, 3): s13, (2, 3): s23, (1, 4): delta ** 2,
          (2, 4): (d - delta) ** 2, (3, 4): s34}
    M = sp.Matrix(5, 5, lambda i, j: 0 if i == j else 1 if 0 in (i, j)
                  else sq[(min(i, j), max(i, j))])
    d1234 = sp.expand(M.det(method="berkowitz"))
    check(sp.expand(eq.cm - d1234) == 0,
          "derive_eq7's determinant is D(1,2,3,4) of the definition (bordered, built here)")
    check(sp.expand(d1234 + 2 * printed7 ** 2) == 0,
          "D(1,2,3,4) + 2 L^2 == 0 with the printed eq. (7) as L")
    print(f"   s34 = {eq.s34}   (affine in s13, s23)")

    # ---------------------------------------------------------------- A and b
    step("2. A and b of eqs. (8)-(9) for arbitrary offsets and side lengths")
    sides = sp.symbols("d12 d45 d23 d56 d13 d46", positive=True)
    offs = sp.symbols("delta1:7", real=True)
    A, b = delta_matrices(sides, offs)
    sp.pprint(A)
    print(f"   b^T = {list(b)}")
    P = sp.zeros(6, 6)
    for i, (dd, de) in enumerate(zip(sides, offs)):
        P[i, i] = (dd - de) / dd
        P[i, (i + 1) % 6] = de / dd
    Pb = sp.Matrix([de * (dd - de) for dd, de in zip(sides, offs)])
    check(sp.simplify(A - P) == sp.zeros(6, 6), "A equals the printed eq. (9)")
    check(sp.simplify(b - Pb) == sp.zeros(6, 1), "b equals the printed b (with m^2 = A l^2 - b)")

    # second route: coordinates (random rational octahedra)
    rng = random.Random(4)
    for _ in range(5):
        pts = [sp.Matrix([sp.Rational(rng.randint(-40, 40), 7) for _ in range(3)]) for _ in range(6)]
        sd = [sp.sqrt(sum(x ** 2 for x in (pts[r.edge[1] - 1] - pts[r.edge[0] - 1]))) for r in ROWS]
        od = [dd * sp.Rational(rng.randint(1, 9), 10) for dd in sd]
        A_, b_ = delta_matrices(sd, od)
        l2 = sp.Matrix([sum(x ** 2 for x in (pts[p - 1] - pts[q - 1])) for q, p in
                        ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))])
        m2 = []
        for r, dd, de in zip(ROWS, sd, od):
            s_, e_ = r.edge
            new = pts[s_ - 1] + de / dd * (pts[e_ - 1] - pts[s_ - 1])
            m2.append(sp.expand(sum(x ** 2 for x in (new - pts[r.shared - 1]))))
        check(sp.simplify(A_ * l2 - b_ - sp.Matrix(m2)) == sp.zeros(6, 1),
              "m^2 from coordinates of the moved joints == A l^2 - b (random octahedron)")

    # ---------------------------------------------------------------- sign of b
    step("3. Sign of b: eq. (8) (m^2 = A l^2 - b) against the printed example")
    tr = delta_transform(GD, ["12/5", "6/5"] * 3)
    m2 = sp.Matrix([sp.expand(sp.sympify(m) ** 2) for m in M_LEGS])
    l2 = sp.Matrix([sp.Rational(x) ** 2 for x in L_LEGS])
    check(tr.A * l2 - tr.b == m2, "m^2 = A l^2 - b holds exactly for the printed m- and l-legs")
    check(tr.A * l2 + tr.b != m2, "m^2 = A l^2 + b (eq. (4) with this b) does not")

    # ---------------------------------------------------------------- inverse map
    step("4. Inverse map l^2 = A^-1 (m^2 + b)")
    Ainv, c = tr.inverse()
    check(Ainv * tr.A == sp.eye(6), "A^-1 A = I")
    l_sq, l = tr.map_legs(M_LEGS)
    print(f"   l = {[str(x) for x in l]}")
    check(list(l) == [sp.Rational(x) for x in L_LEGS],
          "the printed m-legs map exactly onto l = 19.8, 18, 18, 17, 14.9, 17.8")

    # ---------------------------------------------------------------- det A
    step("5. det(A) for arbitrary offsets")
    detA = sp.factor(A.det(method="berkowitz"))
    closed = (sp.prod([dd - de for dd, de in zip(sides, offs)]) - sp.prod(offs)) / sp.prod(sides)
    print("   det(A) = (prod(d_i - delta_i) - prod(delta_i)) / prod(d_i)")
    check(sp.simplify(detA - closed) == 0,
          "det(A) = (prod(d_i - delta_i) - prod(delta_i)) / prod(d_i)  (cyclic bidiagonal)")

    step("6. The example family: Delta1 = delta1 = delta3 = delta5, Delta2 = delta2 = delta4 = delta6")
    fam = delta_transform(GD, ["Delta1", "Delta2"] * 3)
    D1, D2 = fam.free_symbols
    R = sp.Rational
    printed = (-R(1, 20736) * D1**3 * D2**2 - R(1, 10368) * D1**2 * D2**3 + R(1, 3456) * D1**3 * D2
               + R(1, 576) * D1**2 * D2**2 + R(1, 864) * D1 * D2**3 - R(1, 1728) * D1**3
               - R(1, 96) * D1**2 * D2 - R(1, 48) * D1 * D2**2 - R(1, 216) * D2**3 + R(1, 48) * D1**2
               + R(1, 8) * D1 * D2 + R(1, 12) * D2**2 - R(1, 4) * D1 - R(1, 2) * D2 + 1)
    print(f"   det(A) = {fam.det}")
    check(sp.expand(fam.det - printed) == 0, "det(A) equals the printed polynomial (Sec. VI)")
    const, factors = fam.det_factors()
    print(f"   det(A) = {const} * " + " * ".join(f"({f})" for f, _ in factors))
    lin = [f for f, _ in factors if sp.Poly(f, D1, D2).total_degree() == 1]
    check(len(lin) == 1 and sp.expand(lin[0] - (D1 + 2 * D2 - 12)) == 0,
          "linear factor Delta1 + 2 Delta2 - 12, i.e. Delta1/d12 + Delta2/d45 = 1")
    quad = [f for f, _ in factors if sp.Poly(f, D1, D2).total_degree() > 1][0]
    x = (1 - D1 / 12) * (1 - D2 / 6)
    y = D1 * D2 / 72
    ratio = sp.simplify(quad / (x**2 + x * y + y**2))
    check(ratio.is_number and ratio != 0,
          "quadratic factor is a multiple of x^2 + xy + y^2, x = (1-D1/12)(1-D2/6), y = D1 D2/72")
    print("   x^2 + xy + y^2 = (x + y/2)^2 + 3y^2/4 >= 0, zero only at x = y = 0:")
    pts = sp.solve([x, y], [D1, D2], dict=True)
    print(f"   real zeros of the quadratic factor: {pts}")
    check(len(pts) == 2 and all(sp.simplify(lin[0].subs(p)) == 0 for p in pts), "both lie on the line")
    print("   => real architecturally singular locus: the line Delta1 + 2 Delta2 = 12")
    for t in [R(1, 2), R(3), R(6), R(12, 5), R(9), R(23, 2)]:
        sub = {D1: t, D2: (12 - t) / 2}
        A_ = fam.A.subs(sub)
        check(A_.det() == 0 and A_.rank() == 5,
              f"on the line at (Delta1, Delta2) = ({sub[D1]}, {sub[D2]}): det A = 0, rank A = 5")
    for sub in ({D1: 0, D2: 6}, {D1: 12, D2: 0}):
        A_ = fam.A.subs(sub)
        check(A_.rank() == 3, f"at the end point ({sub[D1]}, {sub[D2]}) rank A = 3: "
              "the legs coincide in pairs")
    check(fam.det.subs({D1: 6, D2: 6}) == R(-1, 8),
          "paper's line Delta1 + Delta2 = 12 is NOT singular: det A(6, 6) = -1/8")
    for t in (R(7), R(9), R(21, 2)):        # inside the offsets' ranges 0 < Delta2 < d45 = 6
        v = fam.det.subs({D1: t, D2: 12 - t})
        check(v != 0, f"nor inside the ranges: det A({t}, {12 - t}) = {v}")
    check(fam.det.subs({D1: 6, D2: 3}) == 0,
          "midpoints (6, 3), the architecturally singular Griffis-Duffy platform, lie on our line")
    try:
        delta_transform(GD, [6, 3] * 3).check_regular()
        check(False, "midpoint offsets rejected")
    except DegenerateGeometryError as exc:
        print(f"   {exc}")
        check("delta1 + 2*delta2 - 12" in str(exc), "the error names the vanishing factor")

    # ---------------------------------------------------------------- singularities
    step("7. Singularity identities (exact rational configurations, Schwartz-Zippel)")
    rng = np.random.default_rng(7)
    holds = []
    for _ in range(8):
        X = np.vectorize(lambda v: Fraction(int(v), 97), otypes=[object])(
            rng.integers(-500, 500, size=(6, 3)))
        bj, pj = octahedral_joints(X)
        dj = jacobian_det(bj, pj, normalised=False)
        a, bb = volume_factors(X)
        F = four_planes(X).det
        C = cm_pure_condition(X)
        K = signed_cm_condition(X)
        holds.append(dj != 0 and dj == -216 * (a + bb) and F == dj
                     and C == -RATIO_CONSTANT * (a - bb) * dj and K == -RATIO_CONSTANT * a * dj)
    check(all(holds),
          "det Jhat = -216 (a + b) = four-planes det F;  C = -110592 (a - b) det Jhat;  "
          "K = -110592 a det Jhat  (8 exact random configurations)")
    print("   a = V1245 V3456 V1236, b = V1234 V2456 V1356 (signed volumes)")

    step("8. The paper's CM form vanishes at the regular symmetric home pose")
    s3 = sp.sqrt(3)
    Xh = [sp.Matrix(p) for p in ([0, 0, 0], [6, 6 * s3, 0], [12, 0, 0],
                                 [3, 3 * s3, 10], [9, 3 * s3, 10], [6, 0, 10])]
    Xs = np.array([[x for x in p] for p in Xh], dtype=object)
    from distkin.geometry.cayley_menger import cayley_menger, squared_distances
    sq = squared_distances(Xs)
    Dv = lambda *r: cayley_menger(sq, r)  # noqa: E731
    Cs = sp.simplify(Dv(1, 2, 4, 5) * Dv(3, 4, 5, 6) * Dv(1, 2, 3, 6)
                     - Dv(1, 2, 3, 4) * Dv(2, 4, 5, 6) * Dv(1, 3, 5, 6))
    J = sp.Matrix(6, 6, lambda i, j: 0)
    for k, (q, p) in enumerate(((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))):
        u = Xh[p - 1] - Xh[q - 1]
        J[k, :3] = u.T
        J[k, 3:] = Xh[q - 1].cross(u).T
    dJ = sp.simplify(J.det())
    print(f"   C = {Cs},  det Jhat = {dJ}")
    check(Cs == 0 and dJ != 0, "C = 0 exactly while det Jhat != 0 (a = b there, not a + b = 0)")

    step("9. det(AJ) = det(A) det(J): Jhat66 = A Jhat on the built 6-6 platform")
    plat = equivalent_platform(GD, ["12/5", "6/5"] * 3)
    q = sp.Matrix([R(1, 3), R(-2, 7), R(1, 5)])            # rational rotation (Cayley)
    Q = sp.Matrix([[0, -q[2], q[1]], [q[2], 0, -q[0]], [-q[1], q[0], 0]])
    Rm = ((sp.eye(3) + Q) * (sp.eye(3) - Q).inv()).applyfunc(sp.nsimplify)
    t = sp.Matrix([5, 3, 11])
    base = [sp.Matrix([sp.sympify(x) for x in r]) for r in GD[0]]
    platl = [sp.Matrix([sp.sympify(x) for x in r]) for r in GD[1]]
    Xw = base + [Rm * p + t for p in platl]
    Jo = sp.zeros(6, 6)
    for k, (qq, pp) in enumerate(((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))):
        u = Xw[pp - 1] - Xw[qq - 1]
        Jo[k, :3] = u.T
        Jo[k, 3:] = Xw[qq - 1].cross(u).T
    J6 = sp.zeros(6, 6)
    for k in range(6):
        bj = sp.Matrix(plat.base_joints[k])
        pj = Rm * sp.Matrix(plat.platform_joints[k]) + t
        u = pj - bj
        J6[k, :3] = u.T
        J6[k, 3:] = bj.cross(u).T
    check((J6 - plat.transform.A * Jo).applyfunc(sp.simplify) == sp.zeros(6, 6),
          "Jhat66 == A Jhat exactly (rational pose), hence det(Jhat66) = det(A) det(Jhat)")
    print("\nall checks passed")


if __name__ == "__main__":
    main()
