"""Derive and check the octic of the octahedral manipulator, step by step.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sections II,
III and VI, eqs. (1)-(3), (10), (11).  Run from the repository root::

    python derivations/octahedral_octic.py [--full]

Every step prints what was derived and asserts a check: symbolic identities, exact
rational checks on random assembled octahedra, and the paper's printed example.
``--full`` also expands the octic with every length symbolic (about a minute; the
result is cached).  Exit status 0 means every check passed.
"""

from __future__ import annotations

import math
import sys
import time
from fractions import Fraction
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

from distkin.exact_roots import real_roots  # noqa: E402
from distkin.octahedral.banana import (LEG_PAIRS, SIDE_PAIRS, banana,  # noqa: E402
                                       squared_distance_symbols)
from distkin.codegen.octic import octic_in_legs  # noqa: E402
from distkin.octahedral.octic import (PART_NAMES, closure_condition,  # noqa: E402
                                      naive_double_square, octic_parts,
                                      octic_polynomial)
from distkin.octahedral.reference import (EQ11_PRINTED, GD_ROOTS, eq11_agreement,  # noqa: E402
                                          random_rational_octahedron)

S = squared_distance_symbols()
X = S[(1, 5)]
GD_SIDES = {(1, 2): 144, (1, 3): 144, (2, 3): 144, (4, 5): 36, (4, 6): 36, (5, 6): 36}
GD_LEGS2 = {(1, 4): sp.Rational(198, 10) ** 2, (2, 4): 324, (2, 5): 324, (3, 5): 289,
            (3, 6): sp.Rational(149, 10) ** 2, (1, 6): sp.Rational(178, 10) ** 2}


def step(title):
    print(f"\n== {title}")


def check(cond, what):
    if not cond:
        raise SystemExit(f"CHECK FAILED: {what}")
    print(f"   ok: {what}")


def _sqd(P):
    return {(i, j): sum((P[i - 1][k] - P[j - 1][k]) ** 2 for k in range(3))
            for i in range(1, 7) for j in range(i + 1, 7)}


def _frac(e) -> Fraction:
    e = sp.Rational(sp.expand(e))
    return Fraction(int(e.p), int(e.q))


def _exact_sqrt(q: Fraction) -> Fraction:
    a, b = math.isqrt(q.numerator), math.isqrt(q.denominator)
    if a * a != q.numerator or b * b != q.denominator:
        raise SystemExit(f"CHECK FAILED: {q} is not a rational square")
    return Fraction(a, b)


def main(full: bool = False) -> None:
    t0 = time.perf_counter()
    step("1. Bananas, eqs. (1) and (2): D(face,2; face,6) is linear in s26")
    for k in (1, 2):
        b = banana(k)
        face = ",".join(map(str, b.face))
        print(f"   banana {k}: D({face},2;{face},6) = {sp.count_ops(b.bideterminant)} ops; "
              f"coefficient of s26 = {sp.factor(b.coefficient)}")
        check(sp.degree(b.bideterminant, S[(2, 6)]) == 1, f"banana {k} is linear in s26")
        check(sp.expand(b.coefficient - banana(k).coefficient) == 0
              and sp.expand(b.bideterminant - b.coefficient * S[(2, 6)] - b.constant) == 0,
              f"D({face},2;{face},6) = D({face}) s26 + b{k}")
        jac = sp.expand(b.constant ** 2 - b.tetra_a * b.tetra_b + b.coefficient * b.pentad)
        check(jac == 0, f"Jacobi identity b{k}^2 - D({face},2) D({face},6) = "
                        f"-D({face}) D({face},2,6)|s26=0")
        plus, minus = b.s26_branches()
        print(f"   s26 = (+/- sqrt(D({face},2) D({face},6)) - b{k}) / D({face})")
        check(sp.simplify(plus + minus + 2 * b.constant / b.coefficient) == 0,
              f"the two branches of banana {k} are symmetric about -b{k}/D({face})")

    step("2. Closure condition eq. (3) and the octic O = G^2 - 4 R1 R2")
    p = octic_parts()
    for name in PART_NAMES:
        d = sp.degree(getattr(p, name), X)
        check(d <= 2, f"part {name} has degree {d} <= 2 in s15")
    print("   eq. (3): [P + e1 v sqrt(R1) - e2 u sqrt(R2)] / (u v) = 0, P = u b2 - v b1")
    print("   F = P^2 - v^2 R1 - u^2 R2 = -u v G, G = u E2 + v E1 + 2 b1 b2 (by the Jacobi "
          "identities)")
    print("   => F^2 - 4 u^2 v^2 R1 R2 = (u v)^2 (G^2 - 4 R1 R2): degree 16 = spurious (uv)^2 "
          "x octic")

    step("3. Random assembled octahedra, exactly in rationals")
    rng = np.random.default_rng(2012)
    n_ok = 0
    for trial in range(25):
        P = random_rational_octahedron(rng)
        s = _sqd(P)
        vals = {S[k]: sp.Rational(v.numerator, v.denominator) for k, v in s.items()}
        parts = {n: _frac(getattr(p, n).xreplace(vals)) for n in PART_NAMES}
        R1 = parts["T1a"] * parts["T1b"]
        R2 = parts["T2a"] * parts["T2b"]
        r1, r2 = _exact_sqrt(R1), _exact_sqrt(R2)
        u, v, b1, b2 = parts["u"], parts["v"], parts["b1"], parts["b2"]
        if u == 0 or v == 0:
            continue
        Pp = u * b2 - v * b1
        branches = [(e1, e2) for e1 in (1, -1) for e2 in (1, -1)
                    if Pp + e1 * v * r1 - e2 * u * r2 == 0]
        if not branches:
            raise SystemExit(f"CHECK FAILED: eq. (3) does not vanish at trial {trial}")
        e1, e2 = branches[0]
        s26 = (e1 * r1 - b1) / u
        if s26 != s[(2, 6)] or (e2 * r2 - b2) / v != s[(2, 6)]:
            raise SystemExit(f"CHECK FAILED: the banana branch does not give the true s26 "
                             f"at trial {trial}")
        G = u * parts["E2"] + v * parts["E1"] + 2 * b1 * b2
        if G * G - 4 * R1 * R2 != 0:
            raise SystemExit(f"CHECK FAILED: the octic does not vanish at trial {trial}")
        n_ok += 1
    check(n_ok >= 20, f"eq. (3) on one sign branch, both banana s26 values and the octic "
                      f"vanish exactly at the true s15 ({n_ok} octahedra)")
    e = closure_condition((1, 1), cleared=True)
    check(e.has(sp.sqrt(p.R1)) or e.has(sp.Pow), "eq. (3) built symbolically (with radicals)")

    step("4. Squaring twice on the paper's example (Sec. VI): spurious factors")
    values = {**GD_SIDES, **GD_LEGS2}
    naive, spurious, oct8 = naive_double_square(values)
    print(f"   naive degree {naive.degree()}, octic degree {oct8.degree()}")
    check(naive.degree() == 16 and oct8.degree() == 8, "degree 16 after squaring, true degree 8")
    check((naive - spurious * oct8).is_zero, "naive = (D(5,4,1) D(3,5,1))^2 x octic exactly")
    fac = sp.factor_list(spurious.as_expr())
    print(f"   spurious factor: {sp.factor(spurious.as_expr())}")
    roots = sorted(sp.roots(sp.Poly(spurious.as_expr(), X)).keys())
    check(set(roots) == {25, 841, sp.Rational(4761, 25), sp.Rational(16641, 25)},
          "its roots 25, 841, 4761/25, 16641/25 are the denominators of the paper's eq. (10)")
    del fac
    import flint
    coeffs = [sp.Rational(c) for c in oct8.all_coeffs()]
    fq = flint.fmpq_poly([flint.fmpq(int(c.p), int(c.q)) for c in reversed(coeffs)])
    factors = fq.factor()[1]
    check(len(factors) == 1 and factors[0][1] == 1, "the example's octic is irreducible over Q")

    step("5. Comparison with the printed eq. (11), digit by digit (docs/design.md §5)")
    ok, lam, rel = eq11_agreement([Fraction(int(c.p), int(c.q)) for c in coeffs])
    for t, r in zip(EQ11_PRINTED, rel):
        print(f"   printed {t:>12}: ours x lambda differs by {r:+.2e} (relative)")
    print(f"   lambda in [{float(lam[0]):.10e}, {float(lam[1]):.10e}] (1/2.56e9 = "
          f"{1 / 2.56e9:.10e})")
    check(ok, "one normalisation makes every coefficient round to the printed digits")

    step("6. Certified real roots of the example's octic")
    rr = real_roots(coeffs)
    vals = [r.mid for r in rr]
    print("   " + ", ".join(f"{v:.6f}" for v in vals))
    check(len(rr) == 6 and all(abs(v - float(g)) <= 0.05 for v, g in zip(vals, GD_ROOTS)),
          "six real roots, agreeing with 269.2, 328.7, 359.5, 463.6, 497.9, 513.0")

    step("7. Coefficients as polynomials in the six squared legs (sides of the example "
         "fixed), cached")
    t1 = time.perf_counter()
    cl = octic_in_legs(GD_SIDES)
    t2 = time.perf_counter()
    cl2 = octic_in_legs(GD_SIDES)
    t3 = time.perf_counter()
    print(f"   terms per coefficient o8..o0: {[len(sp.Add.make_args(c)) for c in cl]}")
    print(f"   first call {t2 - t1:.2f} s, second call {t3 - t2:.2f} s (cache)")
    check(all(sp.expand(a - b) == 0 for a, b in zip(cl, cl2)), "the cached octic is the same")
    legsub = {S[k]: v for k, v in GD_LEGS2.items()}
    check(all(sp.expand(a.xreplace(legsub) - b) == 0 for a, b in zip(cl, coeffs)),
          "substituting the example's legs gives the example's octic")

    step("8. The generated kernel reproduces the symbolic octic (random rational lengths)")
    from distkin.octahedral.closure import octic_data
    same = 0
    for _ in range(5):
        P = random_rational_octahedron(rng)
        s = _sqd(P)
        sides = [flint.fmpq(s[k].numerator, s[k].denominator) for k in SIDE_PAIRS]
        legs = [flint.fmpq(s[k].numerator, s[k].denominator) for k in LEG_PAIRS]
        d = octic_data(sides, legs, "exact")
        sub = {S[k]: sp.Rational(v.numerator, v.denominator) for k, v in s.items()}
        ref = octic_polynomial({k: sub[S[k]] for k in SIDE_PAIRS + LEG_PAIRS}).all_coeffs()
        ref = [sp.Rational(0)] * (9 - len(ref)) + ref
        same += [Fraction(str(v)) for v in d[30:]] == [Fraction(str(r)) for r in ref]
    check(same == 5, "kernel octic_exact == sympy octic on 5 random rational octahedra")

    if full:
        step("9. Fully symbolic octic (every length a symbol), cached")
        t1 = time.perf_counter()
        cf = octic_in_legs()
        print(f"   terms per coefficient o8..o0: {[len(sp.Add.make_args(c)) for c in cf]} "
              f"({time.perf_counter() - t1:.1f} s)")
    print(f"\nall checks passed ({time.perf_counter() - t0:.1f} s)")


if __name__ == "__main__":
    main(full="--full" in sys.argv[1:])
