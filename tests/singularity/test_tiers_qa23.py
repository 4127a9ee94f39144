"""QA 23: the singularity tests' precise tier at its own precision, their answers
under scaling of the coordinates, malformed input, and the fast det J's warning.

Every reference is independent of the code under test: determinants written out in
mpmath at 400 digits, exact rational arithmetic (Fractions), or the homogeneity of the
values (exact power-of-two and decimal scalings)."""

from __future__ import annotations

import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from distkin.errors import ConditioningWarning, FloatRangeWarning, InputError
from distkin.singularity import (certified_sign, cm_pure_condition, four_planes, jacobian_det,
                                 octahedral_joints, plucker_jacobian, rotation_from_vector,
                                 signed_cm_condition, volume_factors)

PTS = np.array([[0, 0, 0], [6, 10.392304845413264, 0], [12, 0, 0], [3, 3, 15], [8, 2, 14],
                [6, 7, 16.]])
#: the legs (base label, platform label) of the octahedral manipulator
LEGS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


def _mp_det_j(base, plat, digits=400):
    """det J (normalised Plücker rows (u, b x u)) of float joints (6, 3), written out in
    mpmath."""
    with mpmath.workdps(digits):
        rows = []
        for bk, pk in zip(base, plat):
            b = [mpmath.mpf(float(x)) for x in bk]
            d = [mpmath.mpf(float(x)) - y for x, y in zip(pk, b)]
            n = mpmath.sqrt(sum(x * x for x in d))
            u = [x / n for x in d]
            rows.append(u + [b[1] * u[2] - b[2] * u[1], b[2] * u[0] - b[0] * u[2],
                             b[0] * u[1] - b[1] * u[0]])
        return +mpmath.det(mpmath.matrix(rows))


def _at_global(dps, f):
    old = mpmath.mp.dps
    try:
        mpmath.mp.dps = dps
        return f()
    finally:
        mpmath.mp.dps = old


# ------------------------------------------------------------- 1: the precise tier's dps

def test_precise_jacobian_det_does_not_use_the_global_precision():
    """QA example: base joints x 1e20; 15 global digits gave -1.563 (true -26.7887)."""
    b, p = octahedral_joints(PTS)
    f = lambda: jacobian_det(b * 1e20, p, method="precise")  # noqa: E731
    v15, v50 = _at_global(15, f), _at_global(50, f)
    assert v15 == v50
    exact = _mp_det_j(b * 1e20, p)
    with mpmath.workdps(60):
        assert abs(v15 - exact) < mpmath.mpf(10) ** -5 * abs(exact)   # 30 digits, 20 lost
        v60 = jacobian_det(b * 1e20, p, method="precise", dps=60)
        assert abs(v60 - exact) < mpmath.mpf(10) ** -35 * abs(exact)


@pytest.mark.parametrize("name", ["plucker", "volume", "planes", "rotation", "cm_none"])
def test_precise_tiers_do_not_depend_on_the_global_precision(name):
    b, p = octahedral_joints(PTS * np.pi)
    mp_pts = np.vectorize(mpmath.mpf, otypes=[object])(PTS * np.pi)
    calls = {
        "plucker": lambda: plucker_jacobian(b, p, method="precise")[2, 4],
        "volume": lambda: volume_factors(PTS * np.pi, method="precise")[0],
        "planes": lambda: four_planes(PTS * np.pi, method="precise").det,
        "rotation": lambda: rotation_from_vector([0.1, 0.2, 0.3], method="precise")[0, 1],
        "cm_none": lambda: cm_pure_condition(mp_pts),      # mpf input, method None
    }
    v15, v50 = (_at_global(d, calls[name]) for d in (15, 50))
    assert v15 == v50
    with mpmath.workdps(80):                  # 30 digits (not 15): against 80 (QA: 1e-16)
        ref = _at_global(80, calls[name])
        assert abs(v15 - ref) <= mpmath.mpf(10) ** -27 * abs(ref)


def test_rotation_precise_agrees_with_a_40_digit_rodrigues():
    w = [mpmath.mpf("0.1"), mpmath.mpf("0.2"), mpmath.mpf("0.3")]
    R = _at_global(15, lambda: rotation_from_vector(w, method="precise", dps=40))
    with mpmath.workdps(60):
        th = mpmath.sqrt(sum(x * x for x in w))
        k = [x / th for x in w]
        r01 = -mpmath.sin(th) * k[2] + (1 - mpmath.cos(th)) * k[0] * k[1]
        assert abs(R[0, 1] - r01) < mpmath.mpf(10) ** -38


def test_dps_only_with_precise():
    with pytest.raises(InputError, match="dps"):
        four_planes(PTS, dps=40)
    with pytest.raises(InputError, match="dps"):
        jacobian_det(*octahedral_joints(PTS), method="fast", dps=40)


# ------------------------------------------------------------ 2, 3: scale invariance

def _exact_relative_four_planes(pts):
    """The relative four-planes value in exact arithmetic but for the unit normals:
    det of rows (n, -n.P / L) / |n| with Fractions, |n| in mpmath at 50 digits."""
    P = [[Fraction(float(x)) for x in p] for p in pts]
    L = max(sum((a - b) ** 2 for a, b in zip(p, P[0])) for p in P)
    with mpmath.workdps(50):
        Lm = mpmath.sqrt(mpmath.mpf(L.numerator) / L.denominator)
        rows = []
        for i, j, k in ((1, 2, 4), (2, 3, 5), (3, 1, 6), (4, 5, 6)):
            a, bb, c = P[i - 1], P[j - 1], P[k - 1]
            u = [bb[m] - a[m] for m in range(3)]
            v = [c[m] - a[m] for m in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            off = -sum(x * y for x, y in zip(n, a))
            nm = [mpmath.mpf(x.numerator) / x.denominator for x in n]
            norm = mpmath.sqrt(sum(x * x for x in nm))
            rows.append([x / norm for x in nm] + [mpmath.mpf(off.numerator) / off.denominator
                                                  / norm / Lm])
        return float(mpmath.det(mpmath.matrix(rows)))


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
@pytest.mark.parametrize("scale", [1e-100, 1e-20, 1e80, 1e100, 1e150])
def test_four_planes_relative_is_scale_invariant(method, scale):
    """QA 23: relative 0.0 at 1e80 / 1e100 (every tier), a false "collinear" at 1e-100
    (every tier, certified too), OverflowError at 1e150 (certified)."""
    pts = np.array([[0, 0, 0], [6, 10, 0], [12, 0, 0], [3, 3, 15], [8, 2, 14], [6, 7, 16]],
                   float)
    want = _exact_relative_four_planes(pts)
    assert want == pytest.approx(-0.02825, abs=1e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FloatRangeWarning)    # det F itself is beyond
        r = four_planes(pts * scale, method=method)
    assert r.relative == pytest.approx(want, rel=1e-12)
    one = four_planes(pts, method=method)
    assert float(r.spread) == pytest.approx(float(one.spread) * scale, rel=1e-9)


def test_four_planes_certified_det_scales_by_s9_and_fast_warns_beyond_float():
    pts = [[Fraction(int(x)) for x in p] for p in
           [[0, 0, 0], [6, 10, 0], [12, 0, 0], [3, 3, 15], [8, 2, 14], [6, 7, 16]]]
    import flint
    s = Fraction(10) ** 150
    F1 = four_planes(np.array(pts, dtype=object), method="certified").det
    Fs = four_planes(np.array([[x * s for x in p] for p in pts], dtype=object),
                     method="certified").det
    assert Fs == F1 * flint.fmpq(s.numerator) ** 9
    with pytest.warns(FloatRangeWarning, match="four-planes det F"):
        f = four_planes(np.array(pts, float) * 1e100).det
    assert f == -np.inf or f == np.inf


def test_four_planes_fast_det_scales_exactly_by_powers_of_two():
    """F is of degree 9: F(2^k P) = 2^(9k) F(P), to rounding (the scaled points may be
    computed at another power of two than the unscaled ones)."""
    F = four_planes(PTS).det
    for k in (-100, -40, 40, 100):
        assert four_planes(np.ldexp(PTS, k)).det == pytest.approx(np.ldexp(F, 9 * k), rel=1e-13)


@pytest.mark.parametrize("k", [-330, -110, 60, 170])
def test_volume_factors_fast_rescale_or_warn(k):
    """QA 23: (-0.0, 0.0) at 1e-100 without a word, (-inf, inf) at 1e50, NaN at 1e150.
    a and b are of degree 9: exact by 2^(9k) where that is a float, else a warning."""
    a1, b1 = volume_factors(PTS)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        a, b = volume_factors(np.ldexp(PTS, k))
    in_range = abs(9 * k) < 1000
    if in_range:
        assert (a, b) == (np.ldexp(a1, 9 * k), np.ldexp(b1, 9 * k))
        assert not w
    else:
        assert [x.category for x in w] == [FloatRangeWarning]
        assert "volume factors" in str(w[0].message)
        assert not np.isnan(a) and not np.isnan(b)
    with mpmath.workdps(40):                  # the precise tier: exact scaling too
        ap, _ = volume_factors(np.ldexp(PTS, k), method="precise")
        assert ap == mpmath.ldexp(volume_factors(PTS, method="precise")[0], 9 * k)


# ----------------------------------------------------------- 4, 5: input of any kind

def test_integer_points_default_method():
    """QA 23: AttributeError: 'bool' object has no attribute 'all'."""
    pts = np.array([[0, 0, 0], [6, 10, 0], [12, 0, 0], [3, 3, 15], [8, 2, 14], [6, 7, 16]])
    exact = cm_pure_condition(np.array(pts.tolist(), dtype=object))    # Python ints: fmpq
    assert cm_pure_condition(pts) == pytest.approx(float(exact.p) / float(exact.q), rel=1e-9)
    ks = signed_cm_condition(np.array(pts.tolist(), dtype=object))
    assert signed_cm_condition(pts) == pytest.approx(float(ks.p) / float(ks.q), rel=1e-9)


def test_numeric_strings_are_exact():
    strs = [[str(x) for x in p] for p in
            [[0, 0, 0], [6, 10, 0], [12, 0, 0], [3, 3, 15], [8, 2, 14], [6, 7, 16]]]
    strs[1][1] = "10.1"                                    # 101/10 exactly
    frac = np.array([[Fraction(x) for x in p] for p in strs], dtype=object)
    assert cm_pure_condition(strs) == cm_pure_condition(frac)
    assert four_planes(strs).det == four_planes(frac, method="certified").det
    assert cm_pure_condition(strs, method="fast") == pytest.approx(
        float(cm_pure_condition(frac, method="fast")), rel=1e-15)


@pytest.mark.parametrize("bad, what", [
    (None, "NoneType"), ("abc", "abc"), ([[0, 0, 0]] * 5 + [[1, 2]], "regular shape"),
    ([["1", "2", "x"]] * 6, "x"), ([[0, 0, 0]] * 5 + [[1, 2, None]], "NoneType")])
@pytest.mark.parametrize("entry", ["cm", "signed", "volume", "planes", "jdet"])
def test_malformed_input_is_an_input_error_naming_the_field(bad, what, entry):
    b, p = octahedral_joints(PTS)
    f = {"cm": lambda: cm_pure_condition(bad), "signed": lambda: signed_cm_condition(bad),
         "volume": lambda: volume_factors(bad), "planes": lambda: four_planes(bad),
         "jdet": lambda: jacobian_det(bad, p)}[entry]
    field = "base_joints" if entry == "jdet" else "points"
    with pytest.raises(InputError, match=rf"^{field}\S*: .*{what}") as exc:
        f()
    assert type(exc.value) is InputError


# ------------------------------------------------------------ 6: the fast det's warning

def test_fast_det_warns_where_its_estimate_exceeds_it():
    b, p = octahedral_joints(PTS)
    exact = float(_mp_det_j(b * 1e20, p))
    with pytest.warns(ConditioningWarning, match=r"det J = -1\.5\d* is within its "
                                                 r"rounding-error estimate 4\.\de\+49"):
        v = jacobian_det(b * 1e20, p)
    assert abs(v - exact) > 10                  # indeed wrong: -1.56 for -26.79
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        v1 = jacobian_det(b, p)                 # a regular pose: no warning
        vb = jacobian_det(np.stack([b, b]), np.stack([p, p]))
    assert v1 == pytest.approx(float(_mp_det_j(b, p)), rel=1e-12)
    assert vb[1] == v1
    with pytest.warns(ConditioningWarning, match=r"at 1 of 2 pose\(s\) \(first: batch index "
                                                 r"\(1,\)\)"):
        jacobian_det(np.stack([b, b * 1e20]), np.stack([p, p]))
    with warnings.catch_warnings():             # warn=False: the same value, no warning
        warnings.simplefilter("error", ConditioningWarning)
        assert jacobian_det(b * 1e20, p, warn=False) == v


# ------------------------------------------- QA 23d 5: the certified tier's own precision

def test_certified_det_decides_at_its_own_precision_not_flints_global_53_bits():
    """Leg sets bisected onto det J = 0 (to the last float of the path): at python-flint's
    global 53 bits every certified ball held 0 (undecided); at the tier's own 128 bits
    (``tiers.CERTIFIED_BITS``) each is decided, with the sign of the exact rational det
    Jhat of the same float coordinates (Fractions), under a global precision of 53."""
    from fractions import Fraction

    from distkin.exact_roots import working_precision
    from near_singular import bisected_sign_change, moved
    rng = np.random.default_rng(3)
    decided = 0
    for _ in range(12):
        pts, d = rng.standard_normal((6, 3)), rng.standard_normal(3)
        lo = bisected_sign_change(pts, d)
        if lo is None:
            continue
        X = moved(pts, d, lo)
        exact = jacobian_det(*octahedral_joints(np.vectorize(Fraction, otypes=[object])(X)),
                             normalised=False)
        with working_precision(53):
            ball = jacobian_det(*octahedral_joints(X), method="certified")
        assert certified_sign(ball) == (exact > 0) - (exact < 0)
        decided += 1
    assert decided >= 6
