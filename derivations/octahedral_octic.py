"""Derive and check the octic of the octahedral manipulator, step by step.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sections II,
III and VI, eqs. (1)-(3), (10), (11).  Run from the repository root::

    python derivations/octahedral_octic.py [--full]

Every step prints what was derived and asserts a check: symbolic identities, exact
rational checks on random assembled octahedra, and the paper's printed example.
``--full`` also expands F + u v G and the octic with every length symbolic (one to two
minutes; the octic is cached) and compares the latter, specialised to the paper's example,
with the generated kernel.  ``--help`` lists the options; an unknown option is refused
(exit status 2).  Exit status 0 means every check passed.
"""

from __future__ import annotations

import argparse
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


def _cm_det(points, cols=None):
    """D(points; cols) from the paper's definition (Sec. II, after eq. (1)): the bordered
    determinant of the squared distances, built here from the symbols (a route
    independent of :mod:`distkin.geometry.cayley_menger`)."""
    cols = points if cols is None else cols
    n = len(points)
    M = sp.zeros(n + 1, n + 1)
    for a in range(1, n + 1):
        M[0, a] = M[a, 0] = 1
        for c in range(1, n + 1):
            i, j = points[a - 1], cols[c - 1]
            M[a, c] = 0 if i == j else S[(min(i, j), max(i, j))]
    return sp.expand(M.det(method="berkowitz"))


def _heron(i, j, k):
    """-16 A^2 of triangle P_i P_j P_k from its squared sides (Heron's formula)."""
    a, b, c = S[tuple(sorted((i, j)))], S[tuple(sorted((j, k)))], S[tuple(sorted((i, k)))]
    return sp.expand(-(2 * (a * b + b * c + c * a) - a ** 2 - b ** 2 - c ** 2))


def _frac(e) -> Fraction:
    e = sp.Rational(sp.expand(e))
    return Fraction(int(e.p), int(e.q))


def _exact_sqrt(q: Fraction) -> Fraction:
    a, b = math.isqrt(q.numerator), math.isqrt(q.denominator)
    if a * a != q.numerator or b * b != q.denominator:
        raise SystemExit(f"CHECK FAILED: {q} is not a rational square")
    return Fraction(a, b)


def step_bananas(banana=banana) -> None:
    """Step 1: eqs. (1)-(2).  ``banana`` is injectable (tests pass a wrong one)."""
    step("1. Bananas, eqs. (1) and (2): D(face,2; face,6) is linear in s26")
    for k in (1, 2):
        b = banana(k)
        face = ",".join(map(str, b.face))
        print(f"   banana {k}: D({face},2;{face},6) = {sp.count_ops(b.bideterminant)} ops; "
              f"coefficient of s26 = {sp.factor(b.coefficient)}")
        check(sp.degree(b.bideterminant, S[(2, 6)]) == 1, f"banana {k} is linear in s26")
        check(sp.expand(b.bideterminant - b.coefficient * S[(2, 6)] - b.constant) == 0,
              f"D({face},2;{face},6) = c{k} s26 + b{k}, b{k} its value at s26 = 0")
        d_face = _cm_det(b.face)
        check(sp.expand(b.coefficient - d_face) == 0
              and sp.expand(d_face - _heron(*b.face)) == 0,
              f"c{k} = D({face}), the bordered determinant of the paper's definition "
              f"(= -16 A^2 by Heron's formula)")
        check(sp.expand(b.tetra_a - _cm_det(b.face + (2,))) == 0
              and sp.expand(b.tetra_b - _cm_det(b.face + (6,))) == 0,
              f"the radicands are D({face},2) and D({face},6) of the definition")
        check(sp.expand(b.bideterminant - _cm_det(b.face + (2,), b.face + (6,))) == 0,
              f"the bideterminant is D({face},2;{face},6) of the definition")
        jac = sp.expand(b.constant ** 2 - b.tetra_a * b.tetra_b + b.coefficient * b.pentad)
        check(jac == 0, f"Jacobi identity b{k}^2 - D({face},2) D({face},6) = "
                        f"-D({face}) D({face},2,6)|s26=0")
        plus, minus = b.s26_branches()
        print(f"   s26 = (+/- sqrt(D({face},2) D({face},6)) - b{k}) / D({face})")
        check(sp.simplify(plus + minus + 2 * b.constant / b.coefficient) == 0,
              f"the two branches of banana {k} are symmetric about -b{k}/D({face})")


def _f_plus_uvg(q):
    """F + u v G from a dict of the parts' values (numbers or expressions)."""
    R1, R2 = q["T1a"] * q["T1b"], q["T2a"] * q["T2b"]
    F = (q["u"] * q["b2"] - q["v"] * q["b1"]) ** 2 - q["v"] ** 2 * R1 - q["u"] ** 2 * R2
    return F + q["u"] * q["v"] * (q["u"] * q["E2"] + q["v"] * q["E1"] + 2 * q["b1"] * q["b2"])


def step_closure(p) -> None:
    """Step 2: F = P^2 - v^2 R1 - u^2 R2 = -u v G, abstractly and on the parts ``p``."""
    step("2. Closure condition eq. (3) and the octic O = G^2 - 4 R1 R2")
    for name in PART_NAMES:
        d = sp.degree(getattr(p, name), X)
        check(d <= 2, f"part {name} has degree {d} <= 2 in s15")
    print("   eq. (3): [P + e1 v sqrt(R1) - e2 u sqrt(R2)] / (u v) = 0, P = u b2 - v b1")
    print("   F = P^2 - v^2 R1 - u^2 R2 = -u v G, G = u E2 + v E1 + 2 b1 b2 (by the Jacobi "
          "identities)")
    u, v, b1, b2, R1, R2, E1, E2 = sp.symbols("u v b1 b2 R1 R2 E1 E2")
    sym = {"u": u, "v": v, "b1": b1, "b2": b2, "E1": E1, "E2": E2,
           "T1a": R1, "T1b": 1, "T2a": R2, "T2b": 1}
    jacobi1, jacobi2 = b1 ** 2 - R1 + u * E1, b2 ** 2 - R2 + v * E2
    check(sp.expand(_f_plus_uvg(sym) - u ** 2 * jacobi2 - v ** 2 * jacobi1) == 0,
          "F + u v G = u^2 J2 + v^2 J1 for free symbols, J_i = b_i^2 - R_i + D(face_i) E_i "
          "(zero by step 1)")
    rng = np.random.default_rng(15)
    zero = 0
    for _ in range(6):
        pt = {S[k]: sp.Rational(int(rng.integers(-500, 500)), int(rng.integers(1, 30)))
              for k in S}
        zero += _f_plus_uvg({n: getattr(p, n).xreplace(pt) for n in PART_NAMES}) == 0
    check(zero == 6, "F + u v G = 0 on the parts of eq. (3) at 6 random rational points of "
                     "all 15 squared distances (Schwartz-Zippel; --full expands it)")
    print("   => F^2 - 4 u^2 v^2 R1 R2 = (u v)^2 (G^2 - 4 R1 R2): degree 16 = spurious (uv)^2 "
          "x octic")


#: Rojas et al., eq. (10) (Sec. VI example): numerator's quartic, the radical terms as
#: (coefficient, radicand under the two square roots), and the denominator (its last
#: factor is printed "25 s_{2,3} - 16641", a typo for 25 s_{1,5} - 16641)
EQ10_QUARTIC = (375625 * X ** 4 + 2425914325 * X ** 3 - 2781440777549 * X ** 2
                + 929177720979831 * X - 94994611164672840)
EQ10_RADICALS = (
    (24 * (25 * X - 4761) * (25 * X - 16641),
     (X ** 2 - 757 * X + 27325) * (2220100 * X ** 2 - 1689044183 * X + 277445877004)),
    (21600 * (X - 25) * (X - 841),
     (625 * X ** 2 - 495325 * X + 85928301) * (625 * X ** 2 - 465550 * X + 66028321)))
EQ10_DENOMINATOR = 100 * (X - 25) * (X - 841) * (25 * X - 4761) * (25 * X - 16641)


def check_eq3_against_eq10(closure_condition=closure_condition) -> None:
    """eq. (3) as built by ``closure_condition`` on the Sec. VI data against the printed
    eq. (10), term by term, and squared twice against (u v)^2 x the octic."""
    values = {**GD_SIDES, **GD_LEGS2}
    pg = octic_parts(values)
    e = sp.expand(closure_condition((1, 1), values, cleared=True))
    groups = {}
    for term in sp.Add.make_args(e):
        rad = frozenset(a for a in term.atoms(sp.Pow) if a.exp == sp.S.Half)
        groups[rad] = groups.get(rad, 0) + term
    shape = sorted(len(r) for r in groups)
    check(shape == [0, 1, 1], f"eq. (3) built: a polynomial plus two terms, each with one "
                              f"square root (found radical groups of sizes {shape})")
    k = sp.cancel(EQ10_DENOMINATOR / (pg.u * pg.v))
    check(k.is_number and k != 0, f"eq. (10)'s denominator = {k} u v")
    poly = groups.pop(frozenset())
    check(sp.expand(k * poly + EQ10_QUARTIC) == 0,
          "eq. (3) x eq. (10)'s denominator / (u v): its rational part is -1 x eq. (10)'s "
          "quartic (an overall sign: the paper subtracts the s26 of banana 1 from that of "
          "banana 2)")
    pieces, unmatched = [], list(EQ10_RADICALS)
    for rad, terms in groups.items():
        (r,) = rad
        c = sp.cancel(terms / r)
        pieces.append((c, r.base))
        hit = [t for t in unmatched if sp.expand((k * c) ** 2 * r.base - t[0] ** 2 * t[1]) == 0]
        unmatched = [t for t in unmatched if t not in hit[:1]]
    check(not unmatched, "its two radical terms are eq. (10)'s +/- 24 (25 x - 4761)(25 x - 16641)"
                         " sqrt(.) sqrt(.) and +/- 21600 (x - 25)(x - 841) sqrt(.) sqrt(.)")
    (c1, q1), (c2, q2) = pieces
    Px = sp.Poly(poly, X)
    c1, c2, q1, q2 = (sp.Poly(t, X) for t in (c1, c2, q1, q2))
    naive = (Px ** 2 - c1 ** 2 * q1 - c2 ** 2 * q2) ** 2 - 4 * c1 ** 2 * q1 * c2 ** 2 * q2
    uv = sp.Poly(pg.u, X) * sp.Poly(pg.v, X)
    check((naive - uv ** 2 * octic_polynomial(values)).is_zero,
          "eq. (3) built, squared twice = (u v)^2 x octic G^2 - 4 R1 R2 (example)")


def step_random_octahedra(p, rng, closure_condition=closure_condition) -> None:
    """Step 3: eq. (3) on random assembled octahedra (exact) and on the paper's example."""
    step("3. Random assembled octahedra, exactly in rationals; eq. (3) against eq. (10)")
    n_ok = n_built = 0
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
        if n_built < 3:
            n_built += sp.expand(closure_condition((e1, e2), cleared=True).xreplace(vals)) == 0
        n_ok += 1
    check(n_ok >= 20, f"eq. (3) on one sign branch, both banana s26 values and the octic "
                      f"vanish exactly at the true s15 ({n_ok} octahedra)")
    check(n_built == 3, "closure_condition(branch, cleared=True), the symbolic eq. (3), "
                        "vanishes exactly at the true lengths (3 octahedra)")
    check_eq3_against_eq10(closure_condition)


def step_double_square():
    """Step 4; returns the example's octic coefficients (highest first)."""
    step("4. Squaring twice on the paper's example (Sec. VI): spurious factors")
    values = {**GD_SIDES, **GD_LEGS2}
    naive, spurious, oct8 = naive_double_square(values)
    print(f"   naive degree {naive.degree()}, octic degree {oct8.degree()}")
    check(naive.degree() == 16 and oct8.degree() == 8, "degree 16 after squaring, true degree 8")
    check((naive - spurious * oct8).is_zero, "naive = (D(5,4,1) D(3,5,1))^2 x octic exactly")
    print(f"   spurious factor: {sp.factor(spurious.as_expr())}")
    roots = sorted(sp.roots(sp.Poly(spurious.as_expr(), X)).keys())
    check(set(roots) == {25, 841, sp.Rational(4761, 25), sp.Rational(16641, 25)},
          "its roots 25, 841, 4761/25, 16641/25 are the denominators of the paper's eq. (10)")
    import flint
    coeffs = [sp.Rational(c) for c in oct8.all_coeffs()]
    fq = flint.fmpq_poly([flint.fmpq(int(c.p), int(c.q)) for c in reversed(coeffs)])
    factors = fq.factor()[1]
    check(len(factors) == 1 and factors[0][1] == 1, "the example's octic is irreducible over Q")
    return coeffs


def step_printed(coeffs) -> None:
    """Steps 5 and 6: the printed eq. (11) and the printed roots (Sec. VI)."""
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


def _kernel_octic(values):
    """The generated kernel's exact octic (distkin._generated.octic_general) as Fractions."""
    import flint
    from distkin.octahedral.closure import octic_data

    def q(k):
        r = sp.Rational(values[k])
        return flint.fmpq(int(r.p), int(r.q))
    d = octic_data([q(k) for k in SIDE_PAIRS], [q(k) for k in LEG_PAIRS], "exact")
    return [Fraction(str(c)) for c in d[30:]]


def step_kernels(coeffs, rng) -> None:
    """Steps 7 and 8: the cached octic in the legs and the generated kernel."""
    step("7. Coefficients as polynomials in the six squared legs (sides of the example "
         "fixed), cached")
    t1 = time.perf_counter()
    cl = octic_in_legs(GD_SIDES, use_cache=False)     # derived, whatever the cache holds
    t2 = time.perf_counter()
    octic_in_legs(GD_SIDES)                             # fills the disk cache if empty
    t3 = time.perf_counter()
    cl2 = octic_in_legs(GD_SIDES)                       # read from the disk cache
    t4 = time.perf_counter()
    print(f"   terms per coefficient o8..o0: {[len(sp.Add.make_args(c)) for c in cl]}")
    print(f"   derived {t2 - t1:.2f} s; read from the disk cache {t4 - t3:.2f} s")
    check(all(sp.expand(a - b) == 0 for a, b in zip(cl, cl2)),
          "the cached octic is the derived one")
    legsub = {S[k]: v for k, v in GD_LEGS2.items()}
    check(all(sp.expand(a.xreplace(legsub) - b) == 0 for a, b in zip(cl, coeffs)),
          "substituting the example's legs gives the example's octic")

    step("8. The generated kernel reproduces the symbolic octic (random rational lengths)")
    same = 0
    for _ in range(5):
        s = _sqd(random_rational_octahedron(rng))
        sub = {S[k]: sp.Rational(v.numerator, v.denominator) for k, v in s.items()}
        ref = octic_polynomial({k: sub[S[k]] for k in SIDE_PAIRS + LEG_PAIRS}).all_coeffs()
        ref = [sp.Rational(0)] * (9 - len(ref)) + ref
        same += _kernel_octic(s) == [Fraction(str(r)) for r in ref]
    check(same == 5, "kernel octic_exact == sympy octic on 5 random rational octahedra")


def step_full(coeffs, full_octic=None) -> None:
    """Step 9 (``--full``): F + u v G expanded with every length a symbol, and the fully
    symbolic octic specialised to the example against the kernel and step 4.

    ``full_octic`` (nine coefficients) replaces :func:`octic_in_legs` ``()`` (tests); with
    it given, the expansion of F + u v G is skipped.
    """
    step("9. Fully symbolic: F + u v G expanded, and the octic (every length a symbol, "
         "cached)")
    t1 = time.perf_counter()
    if full_octic is None:
        p = octic_parts()
        check(sp.expand(_f_plus_uvg(p.as_dict())) == 0,
              f"F + u v G expands to 0 with every length a symbol "
              f"({time.perf_counter() - t1:.1f} s)")
        t1 = time.perf_counter()
        full_octic = octic_in_legs()
    print(f"   terms per coefficient o8..o0: {[len(sp.Add.make_args(c)) for c in full_octic]} "
          f"({time.perf_counter() - t1:.1f} s)")
    values = {**GD_SIDES, **GD_LEGS2}
    sub = {S[k]: sp.Rational(v) for k, v in values.items()}
    spec = [c.xreplace(sub) for c in full_octic]
    check(len(spec) == 9 and all(c.is_Rational for c in spec),
          "specialised to the example's 12 lengths, nine rational coefficients")
    spec = [Fraction(int(c.p), int(c.q)) for c in spec]
    check(spec == _kernel_octic(values),
          "the full octic at the example's lengths == the generated kernel's octic_exact "
          "(products of the numeric parts), coefficient by coefficient")
    lam = Fraction(int(coeffs[0].p), int(coeffs[0].q)) / spec[0] if spec[0] else None
    check(lam is not None and all(Fraction(int(c.p), int(c.q)) == lam * f
                                  for c, f in zip(coeffs, spec)),
          f"== lambda x the example's octic of step 4 (eq. (11), step 5), lambda = {lam}")


def parse_args(argv=None):
    ap = argparse.ArgumentParser(
        prog="octahedral_octic.py",
        description="Derive and check the octic of the octahedral manipulator step by "
                    "step: Rojas, Borràs, Thomas, The Octahedral Manipulator Revisited "
                    "(ICRA 2012), Secs. II, III and VI, eqs. (1)-(3), (10), (11).  Exit "
                    "status 0 means every check passed.")
    ap.add_argument("--full", action="store_true",
                    help="also expand F + u v G and the octic with every length symbolic "
                         "(one to two minutes) and compare the octic, specialised to the "
                         "example, with the generated kernel")
    return ap.parse_args(argv)


def main(argv=None) -> None:
    args = parse_args(argv)
    t0 = time.perf_counter()
    step_bananas()
    p = octic_parts()
    step_closure(p)
    rng = np.random.default_rng(2012)
    step_random_octahedra(p, rng)
    coeffs = step_double_square()
    step_printed(coeffs)
    step_kernels(coeffs, rng)
    if args.full:
        step_full(coeffs)
    print(f"\nall checks passed ({time.perf_counter() - t0:.1f} s)")


if __name__ == "__main__":
    main()
