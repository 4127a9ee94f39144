"""Extremes of the octahedral forward kinematics, each stating what happens.

Independent check of every certified count: sympy's exact Sturm-sequence count of the
distinct real roots of the same exact octic.  In every case the certified tier's count
is right (or it raises UncertifiedError); the fast tier's behaviour is stated.
"""

from __future__ import annotations

import warnings
from fractions import Fraction as F

import numpy as np
import pytest
import sympy as sp

from distkin.errors import ConditioningWarning, DegenerateGeometryError, InputError
from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.reference import GD_BASE, GD_PLATFORM, GD_ROOTS

LEGS = [F(198, 10), 18, 18, 17, F(149, 10), F(178, 10)]


def _sturm_count(octic):
    """Distinct real roots of the exact octic by sympy's Sturm sequences."""
    x = sp.Symbol("x")
    p = sp.Poly([sp.Rational(c.numerator, c.denominator) for c in octic], x)
    return p.sqf_part().count_roots()


def _modes(legs, tol=1e-6):
    return len(forward_kinematics(GD_BASE, GD_PLATFORM, legs, method="certified",
                                  tol=tol).assembly_roots)


def _bisect(family, a, b, inside, width):
    """Rational bisection between a (``inside(a)``) and b (not), certified decisions."""
    while b - a > width:
        m = (a + b) / 2
        if inside(family(m)):
            a = m
        else:
            b = m
    return a, b


def test_two_assembly_modes_about_to_merge():
    """Leg 5 varied between 15 (6 modes) and 15.5 (4 modes): two modes merge at a fold.
    2^-43 before the fold their roots differ by ~1e-7 relative.  Certified: 6 roots and
    12 poses, the count confirmed by Sturm.  Precise (30 digits): the same 12 poses.
    Fast: drops the pair (the companion eigenvalues make it a complex pair and Newton
    on eq. (3) finds no real root there) -- 8 poses, each of them valid -- and its
    proof fails, so it warns (ConditioningWarning)."""
    family = lambda t: LEGS[:4] + [t] + LEGS[5:]  # noqa: E731
    a, b = _bisect(family, F(15), F(31, 2), lambda legs: _modes(legs) == 6, F(1, 2 ** 43))
    near = forward_kinematics(GD_BASE, GD_PLATFORM, family(a), method="certified", tol=1e-12)
    assert near.real_root_count == _sturm_count(near.octic) == 6
    assert len(near) == 12 and all(p.max_leg_error_relative <= 1e-12 for p in near)
    vals = np.array([r.value for r in near.roots])
    assert np.min(np.diff(vals) / vals[1:]) < 1e-6          # a near-double root indeed
    import flint
    octic = flint.fmpq_poly([flint.fmpq(c.numerator, c.denominator) for c in near.octic[::-1]])
    (factor, mult), = octic.factor()[1]                      # irreducible over Q
    assert factor.degree() == 8 and mult == 1
    past = forward_kinematics(GD_BASE, GD_PLATFORM, family(b), method="certified", tol=1e-12)
    assert past.real_root_count == _sturm_count(past.octic) == 4 and len(past) == 8
    prec = forward_kinematics(GD_BASE, GD_PLATFORM, family(a), method="precise", dps=30)
    assert len(prec) == 12
    with pytest.warns(ConditioningWarning, match="not proved"):
        fast = forward_kinematics(GD_BASE, GD_PLATFORM, [float(v) for v in family(a)])
    assert len(fast) == 8                      # the pair is dropped, and the tier says so
    for p in fast:
        assert p.max_leg_error_relative <= 1e-9
        assert np.min(np.abs(vals - p.s15)) <= 1e-9 * p.s15


def test_leg_lengths_at_the_edge_of_assemblability():
    """All legs scaled by lambda: no assembly for lambda <= 0.36, four poses from 0.38.
    At the edge two roots are born from a complex pair (a fold): 2^-60 inside it the
    certified tier finds the 2 new roots (4 poses, mirror pairs), 2^-60 outside none;
    Sturm agrees on both sides.  Fast: no false pose on either side."""
    family = lambda k: [k * v for v in LEGS]  # noqa: E731
    a, b = F(36, 100), F(38, 100)       # a: outside, b: inside
    while b - a > F(1, 2 ** 60):
        m = (a + b) / 2
        if _modes(family(m)) > 0:
            b = m
        else:
            a = m
    inside = forward_kinematics(GD_BASE, GD_PLATFORM, family(b), method="certified", tol=1e-12)
    outside = forward_kinematics(GD_BASE, GD_PLATFORM, family(a), method="certified",
                                 tol=1e-12)
    assert inside.real_root_count == _sturm_count(inside.octic)
    assert outside.real_root_count == _sturm_count(outside.octic)
    assert inside.real_root_count == outside.real_root_count + 2
    assert len(inside) == 4 and len(outside) == 0 and "cannot be assembled" in outside.reason
    assert all(p.max_leg_error_relative <= 1e-12 for p in inside)
    for legs in (family(a), family(b)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConditioningWarning)
            fast = forward_kinematics(GD_BASE, GD_PLATFORM, [float(v) for v in legs])
        assert len(fast) in (0, 4)
        if len(fast) != len(forward_kinematics(GD_BASE, GD_PLATFORM, legs, method="certified")):
            assert caught                      # a wrong count never goes unannounced
        assert all(p.max_leg_error_relative <= 1e-8 for p in fast)


def test_exactly_flat_configuration():
    """All six points in one plane (rational): the root s15 = 37 has multiplicity 4 and
    the two mirror images coincide.  Certified: one exact flat pose.  Fast sees no real
    root there (a quadruple root splits into complex ones under rounding), reports that
    the manipulator cannot be assembled, and distrusts its count.  Precise used to say
    the same without a warning (QA F 01: G and R1 R2 vanish together at the root, so
    its relative residual test failed); it now accepts the root by its backward error,
    gives the one flat pose (not twice: it is its own mirror image) and warns that the
    four-fold cluster was merged."""
    base = [[0, 0, 0], [4, 8, 0], [9, 0, 0]]
    plat = [[0, 0, 0], [3, -1, 0], [1, 2, 0]]          # P4 P5 P6 = (3,2) (6,1) (4,4)
    legs = ["sqrt(13)", "sqrt(37)", "sqrt(53)", "sqrt(10)", "sqrt(41)", "sqrt(32)"]
    res = forward_kinematics(base, plat, legs, method="certified")
    assert res.real_root_count == _sturm_count(res.octic)
    (flat,) = [r for r in res.roots if r.status == "assembly"]
    assert flat.value == 37 and flat.multiplicity == 4
    assert len(res) == 1
    assert np.array_equal(res[0].points, [[3, 2, 0], [6, 1, 0], [4, 4, 0]])
    with pytest.warns(ConditioningWarning, match="not proved"):
        fast = forward_kinematics(base, plat, legs, method="fast")
    assert len(fast) == 0 and "no pose found" in fast.reason and "not proved" in fast.reason
    for dps in (30, 60):
        with pytest.warns(ConditioningWarning, match="merged"):
            pre = forward_kinematics(base, plat, legs, method="precise", dps=dps)
        assert len(pre) == 1 and pre.roots[[r.status for r in pre.roots].index(
            "assembly")].multiplicity == 4
        assert np.allclose(pre[0].points, [[3, 2, 0], [6, 1, 0], [4, 4, 0]], atol=1e-8)


@pytest.mark.parametrize("scale", ["0.001", "1000"])
def test_scales(scale):
    """The paper's example scaled exactly by 1e-3 and 1e3: roots scale by 1e-6 and 1e6."""
    k = F(scale)
    base = [[0, 0, 0], [6 * k, f"sqrt(108)*{scale}", 0], [12 * k, 0, 0]]
    plat = [[0, 0, 0], [6 * k, 0, 0], [3 * k, f"sqrt(27)*{scale}", 0]]
    legs = [k * v for v in LEGS]
    res = forward_kinematics(base, plat, legs, method="certified")
    assert res.real_root_count == 6 and len(res) == 12
    for r, g in zip(res.roots, GD_ROOTS):
        assert abs(r.value / float(k * k) - float(g)) <= 0.05
    assert all(p.max_leg_error_relative <= 1e-12 for p in res)
    fast = forward_kinematics(np.array([[float(v) if not isinstance(v, str) else float(
        sp.sympify(v)) for v in row] for row in base]), np.array(
        [[float(v) if not isinstance(v, str) else float(sp.sympify(v)) for v in row]
         for row in plat]), [float(v) for v in legs])
    assert len(fast) == 12 and all(p.max_leg_error_relative <= 1e-9 for p in fast)
    assert np.allclose([p.points for p in fast], [p.points for p in res], rtol=0,
                       atol=1e-9 * float(k) * 20)


def test_cannot_be_assembled_triangle_bounds():
    """Legs of length 1 on a base of side 12: the triangles through P1 P5 cannot close.
    (The fast tier also warns that its count of the spurious real roots is not
    reliable: a multiple root of the octic splits into a cluster,
    tests/octahedral/test_octahedral_clusters.py.)"""
    legs = [1, 1, 1, 1, 1, 1]
    for method in ("fast", "certified"):
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "fast tier: the real-root count",
                                    ConditioningWarning)
            res = forward_kinematics(GD_BASE, GD_PLATFORM, legs, method=method)
        assert len(res) == 0 and "cannot be assembled" in res.reason
    with pytest.warns(ConditioningWarning, match="1e-4 relative"):
        fast = forward_kinematics(GD_BASE, GD_PLATFORM, legs)
    assert "triangle" in fast.reason


def test_cannot_be_assembled_only_spurious_roots():
    """Legs x 0.3: the octic has real roots, every one spurious (a banana tetrahedron with
    negative squared volume, or a face that is no triangle): no pose, the reason says so."""
    legs = [F(3, 10) * v for v in LEGS]
    res = forward_kinematics(GD_BASE, GD_PLATFORM, legs, method="certified")
    assert res.real_root_count == _sturm_count(res.octic) > 0
    assert len(res) == 0 and all(r.status == "spurious" for r in res.roots)
    assert "spurious" in res.reason
    fast = forward_kinematics(GD_BASE, GD_PLATFORM, [float(v) for v in legs])
    assert len(fast) == 0 and fast.real_root_count == res.real_root_count


def test_bad_input_is_reported():
    with pytest.raises(InputError, match="positive"):
        forward_kinematics(GD_BASE, GD_PLATFORM, [1, 2, 3, 4, 5, -6])
    with pytest.raises(InputError, match="6 leg"):
        forward_kinematics(GD_BASE, GD_PLATFORM, [1, 2, 3], method="certified")
    with pytest.raises(DegenerateGeometryError, match="base"):
        forward_kinematics([[0, 0, 0], [1, 1, 1], [2, 2, 2]], GD_PLATFORM, LEGS,
                           method="certified")
    with pytest.raises(DegenerateGeometryError, match="platform"):
        forward_kinematics(GD_BASE, [[0, 0, 0], [1, 0, 0], [2, 0, 0]], [float(v) for v in LEGS])
    with pytest.raises(InputError, match="rational"):
        forward_kinematics(GD_BASE, GD_PLATFORM, ["sqrt(sqrt(2))"] + LEGS[1:],
                           method="certified")


def test_bad_values_are_named_plainly():
    """The element is named, and the value printed as the user wrote it (no numpy
    reprs such as ``np.float64(-17.8)``); a value beyond float64 is an InputError naming
    its element (it was an OverflowError, then an InputError without a field)."""
    legs = [19.8, 18, 18, 17, 14.9, -17.8]
    with pytest.raises(InputError) as err:
        forward_kinematics(GD_BASE, GD_PLATFORM, legs)          # (a string: general path)
    assert err.value.field == "legs[5]" and str(err.value).endswith("got -17.8")
    assert "np." not in str(err.value)
    with pytest.raises(InputError) as err:
        forward_kinematics_batched(GD_BASE, GD_PLATFORM, [[19.8, 18, 18, 17, 14.9, 17.8], legs])
    assert err.value.field == "legs[1][5]" and "np." not in str(err.value)
    for where, kw in (("legs[0]", {"legs": ["1e400"] + LEGS[1:]}),
                      ("base[2][2]", {"base": GD_BASE[:2] + [[12, 0, "1e999"]]})):
        args = {"base": GD_BASE, "platform": GD_PLATFORM, "legs": LEGS, **kw}
        with pytest.raises(InputError, match="float64 range") as err:
            forward_kinematics(args["base"], args["platform"], args["legs"])
        assert err.value.field == where


def test_degree_drop_when_a_root_goes_to_infinity():
    """Leg 5 = 12 (= the base side): the octic's leading coefficient vanishes exactly and
    its degree drops to 7.  Certified: the count (Sturm-confirmed) and the two assembly
    modes; fast (companion of the degree-7 polynomial after the drop is detected): the
    same modes, and it proves them (the root that went to infinity lies outside the
    feasible interval, where the proof of :mod:`distkin.octahedral.descartes` looks), so
    it does not warn."""
    legs = LEGS[:4] + [12] + LEGS[5:]
    res = forward_kinematics(GD_BASE, GD_PLATFORM, legs, method="certified")
    assert res.octic[0] == 0 and res.degree == 7
    assert res.real_root_count == _sturm_count(res.octic[1:])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        fast = forward_kinematics(GD_BASE, GD_PLATFORM, [float(v) for v in legs])
    assert fast.conditioning.trusted
    assert len(fast) == len(res) == 4
    assert np.allclose([p.points for p in fast], [p.points for p in res], atol=1e-9)


def test_inputs_are_refused_alike_by_every_tier():
    """QA (2026-11-27): a boolean leg and legs of shape (1, 6) were taken by the fast
    tier (single) but refused by the exact tiers; a negative or NaN ``tol`` came out as
    an ``UncertifiedError``; the batched errors did not say which problem; legs of
    1e100 on a base of side 12 were called a collinear base (its 16 area^2 underflowed).
    Now every tier refuses the same inputs, naming the field (and the problem)."""
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    legs = [19.8, 18, 18, 17, 14.9, 17.8]
    for method in ("fast", "auto", "precise", "certified"):
        with pytest.raises(InputError, match="boolean True") as err:
            forward_kinematics(base, plat, [True] + legs[1:], method=method)
        assert err.value.field == "legs[0]"
        with pytest.raises(InputError) as err:
            forward_kinematics(base, plat, [legs], method=method)
        assert err.value.field == "legs"
    for method, tol in (("certified", -1), ("precise", float("nan")), ("auto", "x")):
        with pytest.raises(InputError) as err:
            forward_kinematics(base, plat, legs, method=method, tol=tol)
        assert err.value.field == "tol"
    B = np.array([[[0, 0, 0], [6, 108 ** 0.5, 0], [12, 0, 0]]] * 3)
    P = np.array([[[0, 0, 0], [6, 0, 0], [3, 27 ** 0.5, 0]]] * 3)
    L = np.array([legs] * 3)
    L[2, 1] = np.nan
    with pytest.raises(InputError) as err:
        forward_kinematics_batched(B, P, L)
    assert err.value.field == "legs[2][1]"
    B[1, 2] = 2 * B[1, 1]                       # P3 = 2 P2: collinear with P1
    # batched: that problem alone is flagged, not solved (QA N 1; the others keep
    # their answers: tests/octahedral/test_thin_triangles.py)
    with pytest.warns(ConditioningWarning, match="thinner than float64 resolves"):
        b = forward_kinematics_batched(B, P, np.array([legs] * 3))
    assert b.verdict[1] == 11 and b.count[1] == 0 and b.count[0] == b.count[2] > 0
    # a base tiny against the legs is no collinear base: every tier takes it (the
    # fast tier's proof then refuses the span, and says so)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        forward_kinematics(base, plat, [1e100] * 6)
        forward_kinematics(base, plat, [10 ** 30] * 6, method="precise")


def test_exact_squared_sides_keep_every_digit():
    """A base vertex 1e-18 off the Griffis-Duffy one, given exactly: its squared sides
    keep the small irrational part (sympy's nsimplify used to snap 144 + 1e-36 -
    3 sqrt(3)/2.5e17 to 144, and the certified tier then certified the neighbouring
    problem); with irrational squared sides the certified tier refuses, as it must."""
    import sympy as sp
    from distkin.octahedral.problem import exact_problem
    base = [[0, 0, 0], [6, "sqrt(108) - 1/10**18", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    legs = ["19.8", 18, 18, 17, "14.9", "17.8"]
    s12 = exact_problem(base, plat, legs).sides2[0]
    y = sp.sqrt(108) - sp.Rational(1, 10 ** 18)
    assert sp.simplify(s12 - (36 + y ** 2)) == 0 and s12 != 144
    with pytest.raises(InputError, match="rational squared lengths"):
        forward_kinematics(base, plat, legs, method="certified")


def test_huge_leg_names_the_same_field_in_every_tier():
    """QA M 8: a leg of 1e200 was ``legs`` in the fast tier, ``legs[0]`` in the exact
    ones.  Every tier names the leg: the first, whose square overflows float64."""
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    legs = ["1e200", 18, 18, 17, "14.9", "17.8"]
    assert float(legs[0]) * float(legs[0]) == float("inf")   # the reason, independently
    for method in ("fast", "auto", "precise", "certified"):
        with pytest.raises(InputError, match="overflow") as err:
            forward_kinematics(base, plat, legs, method=method)
        assert err.value.field == "legs[0]", method
