"""Bananas, eq. (3) and the octic (Rojas et al., ICRA 2012, eqs. (1)-(3), (10), (11)):
symbolic identities, exact rational checks on assembled octahedra, the paper's printed
example, and the generated kernel against sympy."""

from __future__ import annotations

import math
from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp

from distkin.geometry.cayley_menger import cayley_menger
from distkin.octahedral.banana import LEG_PAIRS, SIDE_PAIRS, banana, squared_distance_symbols
from distkin.octahedral.closure import octic_data
from distkin.octahedral.octic import (PART_NAMES, closure_condition, naive_double_square,
                                      octic_parts, octic_polynomial)
from distkin.octahedral.reference import eq11_agreement, random_rational_octahedron

S = squared_distance_symbols()
X = S[(1, 5)]
GD_VALUES = {(1, 2): 144, (1, 3): 144, (2, 3): 144, (4, 5): 36, (4, 6): 36, (5, 6): 36,
             (1, 4): sp.Rational(198, 10) ** 2, (2, 4): 324, (2, 5): 324, (3, 5): 289,
             (3, 6): sp.Rational(149, 10) ** 2, (1, 6): sp.Rational(178, 10) ** 2}


def _sqd(P):
    return {(i, j): sum((P[i - 1][k] - P[j - 1][k]) ** 2 for k in range(3))
            for i in range(1, 7) for j in range(i + 1, 7)}


@pytest.mark.parametrize("index", [1, 2])
def test_banana_is_linear_in_s26_with_the_face_as_coefficient(index):
    b = banana(index)
    face = b.face
    assert sp.degree(b.bideterminant, S[(2, 6)]) == 1
    # the coefficient is the cofactor D(face), computed independently
    D = sp.zeros(6, 6)
    for (i, j), v in S.items():
        D[i - 1, j - 1] = D[j - 1, i - 1] = v
    assert sp.expand(b.coefficient - cayley_menger(D, face)) == 0
    # Jacobi identity: b^2 - D(face,2) D(face,6) = -D(face) D(face,2,6) at s26 = 0
    assert sp.expand(b.constant ** 2 - b.tetra_a * b.tetra_b + b.coefficient * b.pentad) == 0


def test_parts_are_quadratic_in_s15():
    p = octic_parts()
    assert all(sp.degree(getattr(p, n), X) == 2 for n in PART_NAMES)


def test_eq3_and_octic_vanish_exactly_on_assembled_octahedra():
    """Random octahedra with rational coordinates: volumes are rational, so eq. (3) can
    be evaluated exactly; exactly one sign branch vanishes, both bananas give the true
    s26, and the octic vanishes at the true s15 (exact kernel, fmpq)."""
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(30):
        P = random_rational_octahedron(rng)
        s = _sqd(P)
        q = lambda v: flint.fmpq(v.numerator, v.denominator)  # noqa: E731
        d = [Fraction(str(flint.fmpq(v))) for v in octic_data(
            [q(s[k]) for k in SIDE_PAIRS], [q(s[k]) for k in LEG_PAIRS], "exact")]
        part = {n: d[3 * i] + d[3 * i + 1] * s[(1, 5)] + d[3 * i + 2] * s[(1, 5)] ** 2
                for i, n in enumerate(PART_NAMES)}
        R1, R2 = part["T1a"] * part["T1b"], part["T2a"] * part["T2b"]
        r1 = Fraction(math.isqrt(R1.numerator), math.isqrt(R1.denominator))
        r2 = Fraction(math.isqrt(R2.numerator), math.isqrt(R2.denominator))
        assert r1 * r1 == R1 and r2 * r2 == R2
        u, v, b1, b2 = part["u"], part["v"], part["b1"], part["b2"]
        if u == 0 or v == 0:
            continue
        branches = [(e1, e2) for e1 in (1, -1) for e2 in (1, -1)
                    if u * b2 - v * b1 + e1 * v * r1 - e2 * u * r2 == 0]
        assert len(branches) >= 1
        e1, e2 = branches[0]
        assert (e1 * r1 - b1) / u == s[(2, 6)] == (e2 * r2 - b2) / v
        octic = sum(c * s[(1, 5)] ** (8 - k) for k, c in enumerate(d[30:]))
        assert octic == 0
        checked += 1
    assert checked >= 25


def test_closure_condition_symbolic_on_a_rational_octahedron():
    """eq. (3) as sympy builds it (with radicals), substituted exactly."""
    P = [(0, 0, 0), (4, 0, 0), (1, 3, 0), (1, 1, 3), (3, 2, 4), (0, 2, 2)]
    s = {k: sp.Integer(v) for k, v in _sqd(P).items()}
    vals = {S[k]: v for k, v in s.items() if k != (2, 6) and k != (3, 4)}
    hits = [sgn for sgn in ((1, 1), (1, -1), (-1, 1), (-1, -1))
            if sp.simplify(closure_condition(sgn).xreplace(vals)) == 0]
    assert len(hits) == 1


def test_naive_squaring_has_the_spurious_factor_of_eq10():
    """Degree 16 = (D(5,4,1) D(3,5,1))^2 x octic; the spurious roots are the
    denominators of the paper's eq. (10): 25, 841, 4761/25, 16641/25."""
    naive, spurious, octic = naive_double_square(GD_VALUES)
    assert naive.degree() == 16 and octic.degree() == 8
    assert (naive - spurious * octic).is_zero
    assert set(sp.roots(sp.Poly(spurious.as_expr(), X)).keys()) == {
        25, 841, sp.Rational(4761, 25), sp.Rational(16641, 25)}


def test_octic_matches_printed_eq11_digit_by_digit():
    """Normalised, our octic rounds to every printed digit of eq. (11) (docs/design.md §5:
    compare coefficients, never the roots of the printed polynomial)."""
    coeffs = octic_polynomial(GD_VALUES).all_coeffs()
    ok, lam, rel = eq11_agreement([Fraction(int(c.p), int(c.q)) for c in coeffs])
    assert ok
    # the paper's normalisation is 1/2.56e9, exactly inside the admissible interval
    assert lam[0] <= Fraction(1, 2560000000) <= lam[1]
    assert max(abs(r) for r in rel) < 5e-5


def test_kernel_flavours_agree_with_sympy():
    """Generated kernel (batched, scalar) vs ``sympy.lambdify`` of the parts, and its octic
    vs G^2 - 4 R1 R2 multiplied out with numpy from those parts; exact flavour vs the
    sympy octic substituted exactly."""
    from distkin._generated import octic_general as k
    rng = np.random.default_rng(3)
    syms = [S[p] for p in SIDE_PAIRS + LEG_PAIRS]
    p = octic_parts()
    parts = [[sp.Poly(getattr(p, n), X).coeff_monomial(X ** m) for m in range(3)]
             for n in PART_NAMES]
    f = sp.lambdify(syms, parts, "math")
    for _ in range(4):
        P = rng.normal(size=(6, 3))
        s2 = {(i, j): float(np.sum((P[i - 1] - P[j - 1]) ** 2)) for i, j in SIDE_PAIRS + LEG_PAIRS}
        sides = np.array([s2[q] for q in SIDE_PAIRS])
        legs = np.array([s2[q] for q in LEG_PAIRS])
        ref = {n: np.array(c[::-1]) for n, c in zip(PART_NAMES, f(*sides, *legs))}
        G = np.polyadd(np.polyadd(np.polymul(ref["u"], ref["E2"]), np.polymul(ref["v"], ref["E1"])),
                       2 * np.polymul(ref["b1"], ref["b2"]))
        R = np.polymul(np.polymul(ref["T1a"], ref["T1b"]), np.polymul(ref["T2a"], ref["T2b"]))
        octic = np.polysub(np.polymul(G, G), 4 * R)
        flat = np.concatenate([ref[n][::-1] for n in PART_NAMES])
        for out in (k.octic_batched(sides[None], legs[None])[0], np.array(k.octic_scalar(
                list(sides), list(legs)))):
            assert np.allclose(out[:30], flat, rtol=1e-12, atol=1e-12 * np.abs(flat).max())
            assert np.allclose(out[30:], octic, rtol=0, atol=1e-11 * np.abs(octic).max())
    # exact flavour against exact sympy substitution
    P = random_rational_octahedron(rng)
    s = _sqd(P)
    d = octic_data([flint.fmpq(s[p].numerator, s[p].denominator) for p in SIDE_PAIRS],
                   [flint.fmpq(s[p].numerator, s[p].denominator) for p in LEG_PAIRS], "exact")
    ref = octic_polynomial({p: sp.Rational(s[p].numerator, s[p].denominator)
                            for p in SIDE_PAIRS + LEG_PAIRS}).all_coeffs()
    ref = [0] * (9 - len(ref)) + ref
    assert [Fraction(str(flint.fmpq(v))) for v in d[30:]] == [Fraction(str(r)) for r in ref]


def test_generated_module_is_up_to_date():
    """The committed kernel equals what the generator writes now (codegen --check)."""
    from pathlib import Path
    from distkin.codegen.octic import generate_octic_module
    import distkin._generated.octic_general as mod
    assert Path(mod.__file__).read_text(encoding="utf-8") == generate_octic_module()


def test_octic_in_legs_is_cached(tmp_path, monkeypatch):
    """With what a scene fixes substituted (here the sides and legs 1-4, to keep the test
    short; the derivation script does all six legs), the coefficients are polynomials in
    the remaining squared legs; the second call reads the cache and agrees."""
    from distkin.codegen.octic import octic_in_legs
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path))
    fixed = {k: GD_VALUES[k] for k in SIDE_PAIRS + LEG_PAIRS[:4]}
    first = octic_in_legs(fixed)
    assert len(list(tmp_path.glob("octic_*.pickle"))) == 1
    second = octic_in_legs(fixed)
    assert all(sp.expand(a - b) == 0 for a, b in zip(first, second))
    assert {str(x) for c in first for x in c.free_symbols} == {"s36", "s16"}
    legs = {S[k]: GD_VALUES[k] for k in LEG_PAIRS}
    ref = octic_polynomial(GD_VALUES).all_coeffs()
    assert all(sp.expand(a.xreplace(legs) - b) == 0 for a, b in zip(first, ref))


def test_octic_cache_is_keyed_by_the_code_that_derives_it(tmp_path, monkeypatch):
    """A change of the sources that square eq. (3) into the octic must not be served
    the octic cached before it (QA: the key held the inputs only).  The sources are
    stood in for by monkeypatching what the key reads; the inputs stay the same."""
    from distkin.codegen import octic as octic_mod
    monkeypatch.setenv("DISTKIN_CACHE", str(tmp_path))
    fixed = {k: GD_VALUES[k] for k in SIDE_PAIRS + LEG_PAIRS[:5]}
    octic_mod.octic_in_legs(fixed)
    octic_mod.octic_in_legs(fixed)
    assert len(list(tmp_path.glob("octic_*.pickle"))) == 1          # the same key again
    monkeypatch.setattr(octic_mod, "_OCTIC_MODULES", ("distkin.octahedral.octic",))
    octic_mod.octic_in_legs(fixed)
    assert len(list(tmp_path.glob("octic_*.pickle"))) == 2          # another source


@pytest.mark.slow
def test_derivation_script_passes():
    """``derivations/octahedral_octic.py`` prints its steps and exits 0 (every check
    passed); about 15 s on a cold cache."""
    import subprocess
    import sys
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    r = subprocess.run([sys.executable, str(root / "derivations" / "octahedral_octic.py")],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert "all checks passed" in r.stdout


def test_parts_of_eq3_reproduce_every_integer_printed_in_eq10():
    """Rojas et al., eq. (10): eq. (3) on the Sec. VI data, multiplied out.  Every
    printed integer comes back from the parts of eq. (3) (QA: they were reproduced and
    never compared): the quartic is -1/62500 of u b2 - v b1; the four radicands are the
    tetrahedra T1a, T1b, T2a, T2b up to constant factors; the radical terms carry the
    printed 24 and 21600.  The denominator's last factor is printed "25 s_{2,3} - 16641",
    a typo for 25 s_{1,5} - 16641 (u = (25 s15 - 4761)(25 s15 - 16641)/625 here)."""
    p = octic_parts(GD_VALUES)
    x = p.x
    quartic = (375625 * x ** 4 + 2425914325 * x ** 3 - 2781440777549 * x ** 2
               + 929177720979831 * x - 94994611164672840)
    assert sp.cancel(sp.expand(p.u * p.b2 - p.v * p.b1) / quartic) == sp.Rational(-1, 62500)
    printed = {"T2a": x ** 2 - 757 * x + 27325,
               "T2b": 2220100 * x ** 2 - 1689044183 * x + 277445877004,
               "T1a": 625 * x ** 2 - 495325 * x + 85928301,
               "T1b": 625 * x ** 2 - 465550 * x + 66028321}
    factor = {}
    for name, radicand in printed.items():
        factor[name] = sp.cancel(getattr(p, name) / radicand)
        assert factor[name].is_number and factor[name] != 0, name
    assert sp.expand(p.u * 625) == sp.expand((25 * x - 4761) * (25 * x - 16641))
    assert sp.expand(p.v) == sp.expand((x - 25) * (x - 841))
    # the radical terms of eq. (3) scaled like the quartic (x -62500): 24 and 21600
    k2 = sp.sqrt(factor["T2a"] * factor["T2b"])
    k1 = sp.sqrt(factor["T1a"] * factor["T1b"])
    assert sp.nsimplify(62500 * k2 / 625) == 24
    assert sp.nsimplify(62500 * k1) == 21600
