"""QA round on distkin/geometry: cayley_menger's precise tier (NaN from an infinite
entry; an exact-looking 0 for a nearly flat triangle of exact data), the fast tier's
OverflowError on exact values beyond float64, a ``dps`` silently ignored, and
squared_distances overflowing to inf.

References: Heron's formula in exact rationals (:math:`D(1,2,3) = -16A^2 =
2(s_{12}^2+s_{13}^2+s_{23}^2) - (s_{12}+s_{13}+s_{23})^2`) and in mpmath at 80 digits,
the certified tier's exact fmpq, :math:`D(i,j) = 2 s_{ij}`.
"""

from __future__ import annotations

import warnings
from fractions import Fraction as F

import mpmath
import numpy as np
import pytest

from distkin.errors import InputError
from distkin.geometry import CancellationWarning, cayley_menger, squared_distances

INF, NAN = float("inf"), float("nan")


def _heron(s12, s13, s23):
    """D(1,2,3) of a triangle with squared sides s12, s13, s23 (exact for rationals)."""
    return 2 * (s12 * s12 + s13 * s13 + s23 * s23) - (s12 + s13 + s23) ** 2


@pytest.mark.parametrize("method", ["precise", "certified", None, "fast"])
@pytest.mark.parametrize("bad", [INF, NAN])
def test_infinite_or_nan_entry_is_refused_in_every_tier(method, bad):
    """precise returned mpf('nan') for an inf entry (a list and a numpy array alike)."""
    for sq in ([[0, bad, 1.], [bad, 0, 1.], [1., 1., 0]],
               np.array([[0, bad, 1.], [bad, 0, 1.], [1., 1., 0]])):
        with pytest.raises(InputError, match=r"finite and >= 0, got s\(1,2\)") as e:
            cayley_menger(sq, (1, 2, 3), method=method)
        assert e.value.field == "sq"


def test_precise_of_exact_data_is_the_exact_value_rounded():
    """A nearly flat triangle of exact data: precise read 0.0 (entries rounded to 30
    digits), certified -4e-40; now precise is the exact determinant correctly rounded."""
    pts = [[0, 0, 0], [1, 0, 0], [F(1, 2), F(1, 10**20), 0]]
    sq = squared_distances(pts)
    exact = _heron(sq[0, 1], sq[0, 2], sq[1, 2])
    assert exact == F(-1, 25 * 10**38)                       # -16 A^2, A = 1/(2e20)
    cert = cayley_menger(sq, (1, 2, 3), method="certified")
    assert F(int(cert.p), int(cert.q)) == exact
    for dps in (15, 30, 60):
        got = cayley_menger(sq, (1, 2, 3), method="precise", dps=dps)
        assert isinstance(got, mpmath.mpf) and got != 0
        with mpmath.workdps(dps):
            bits = mpmath.mp.prec
        with mpmath.workdps(dps + 40):               # within half an ulp at dps digits
            ref = mpmath.mpf(exact.numerator) / exact.denominator
            assert abs(got - ref) <= abs(ref) * mpmath.mpf(2) ** -bits


def test_precise_of_sampled_flat_rational_triangles_matches_exact():
    """Floats (exact binary values) and Fractions near collinear: the precise value is
    within half an ulp at its digits of the exact rational determinant, never 0."""
    rng = np.random.default_rng(7)
    for _ in range(40):
        a, b = rng.normal(size=3), rng.normal(size=3)
        c = 0.3 * a + 0.7 * b + rng.normal(size=3) * 10.0 ** rng.integers(-15, -6)
        P = np.array([a, b, c])
        S = squared_distances(P)
        # the reference is D of the float squared distances S themselves, exactly
        e = [[F(float(S[i, j])) for j in range(3)] for i in range(3)]
        exact = _heron(e[0][1], e[0][2], e[1][2])
        with warnings.catch_warnings():
            warnings.simplefilter("error")               # rational data: no warning
            got = cayley_menger(S, (1, 2, 3), method="precise")
        with mpmath.workdps(80):
            ref = mpmath.mpf(exact.numerator) / exact.denominator
            if exact == 0:
                assert got == 0
            else:
                assert abs(got - ref) <= abs(ref) * mpmath.mpf(2) ** -99    # 30 digits


def test_precise_irrational_entries_warn_when_they_cannot_vouch():
    """Irrational entries are rounded: a collinear triple of irrational squared distances
    (1, 2^(1/4) and their sum) gives a value that cannot be told from 0: warned; a proper
    irrational triangle agrees with Heron's formula at 80 digits, with no warning."""
    flat = {(1, 2): 1, (2, 3): "sqrt(2)", (1, 3): "1 + 2*2**(1/4) + sqrt(2)"}
    with pytest.warns(CancellationWarning, match=r"D\(1,2,3\)"):
        cayley_menger(flat, (1, 2, 3), method="precise")
    good = {(1, 2): "sqrt(2)", (1, 3): 1, (2, 3): "sqrt(3)"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = cayley_menger(good, (1, 2, 3), method="precise", dps=40)
    with mpmath.workdps(80):
        ref = _heron(mpmath.sqrt(2), mpmath.mpf(1), mpmath.sqrt(3))
        assert abs(got - ref) <= abs(ref) * mpmath.mpf(10) ** -39


@pytest.mark.parametrize("big", [10**400, F(10**400), mpmath.mpf("1e400"), "1e400"])
def test_fast_refuses_exact_values_beyond_float64_naming_the_entry(big):
    """fast raised a raw OverflowError; the precise tier holds the value (D = 2 s)."""
    for sq in ([[0, big], [big, 0]], {(1, 2): big}):
        with pytest.raises(InputError, match=r"float64 range \(\|x\| < 1\.8e308\).*"
                                             r"s\(1,2\) = 1\.0e\+400") as e:
            cayley_menger(sq, (1, 2), method="fast")
        assert e.value.field == "sq"
    got = cayley_menger([[0, big], [big, 0]], (1, 2), method="precise")
    assert abs(got / (2 * mpmath.mpf(10) ** 400) - 1) < 1e-15
    # just inside the range it is the float of D = 2 s
    got = cayley_menger([[0, 10**300], [10**300, 0]], (1, 2), method="fast")
    assert got == pytest.approx(2e300, rel=1e-12)


def test_floats_mixed_with_huge_exact_values_are_refused():
    """The input's own tier: floats mixed with exact values are all floats; an int
    beyond float64 among them raised OverflowError (a mapping and an array alike)."""
    mix = {(1, 2): 1.0, (1, 3): 10**400, (2, 3): 1.0}
    with pytest.raises(InputError, match=r"float64 range.*s\(1,3\)"):
        cayley_menger(mix, (1, 2, 3))
    arr = [[0, 1.0, 10**400], [1.0, 0, 1.0], [10**400, 1.0, 0]]
    with pytest.raises(InputError, match=r"float64 range.*s\(1,3\)"):
        cayley_menger(arr, (1, 2, 3))


@pytest.mark.parametrize("method", ["fast", "certified", None])
def test_dps_only_with_precise(method):
    """fast silently ignored dps=50; refused as by the other entry points."""
    with pytest.raises(InputError, match=r"'dps' only with method 'precise'") as e:
        cayley_menger([[0, 1.], [1., 0]], (1, 2), method=method, dps=50)
    assert e.value.field == "dps"
    assert cayley_menger([[0, 1], [1, 0]], (1, 2), method="precise", dps=50) == 2
    with pytest.raises(InputError, match="dps"):
        cayley_menger([[0, 1], [1, 0]], (1, 2), method="precise", dps=3)


def test_dps_without_a_method_says_so_in_the_callers_terms():
    """QA: ``cayley_menger(S, rows, cols, dps=40)`` ended in "got method None", a method
    the caller never passed.  dps stays refused without "precise" (DESIGN.md §3: it is
    the precise tier's digits; every entry point refuses it where it would be ignored,
    none escalates on it), and the message names what was given: dps and no method.
    The same for the CM conditions of distkin.singularity (the same check)."""
    from distkin.singularity import cm_pure_condition
    sq = {(i, j): 1 for i in range(1, 5) for j in range(i + 1, 5)}
    expected = ("dps: expected 'dps' only with method 'precise' (the mpmath digits), got "
                "dps=40 and no method (the default, the input's own number type, has no "
                "digits to set) (hint: method='precise' with dps)")
    with pytest.raises(InputError) as e:
        cayley_menger(sq, (1, 2, 3), (1, 2, 4), dps=40)
    assert str(e.value) == expected
    pts = [[0, 0, 0], [6, 10, 0], [12, 0, 0], [1, 2, 17], [6, 1, 15], [3, 5, 16]]
    with pytest.raises(InputError) as e:
        cm_pure_condition(pts, dps=40)
    assert str(e.value) == expected


def test_squared_distances_beyond_float64_are_refused_not_inf():
    """Finite float points 2e200 apart squared to inf silently; exact coordinates keep
    the value (4e400, exactly)."""
    for pts in (np.array([[1e200, 0.], [-1e200, 0.]]), [[1e200, 0.], [-1e200, 0.]]):
        with pytest.raises(InputError, match=r"float64 range.*s\(1,2\)"):
            squared_distances(pts)
    exact = squared_distances([[10**200, 0], [-10**200, 0]])
    assert exact[0, 1] == 4 * F(10) ** 400
    with pytest.raises(InputError, match=r"points\[1\]\[0\].*float64 range"):
        squared_distances([[1.5, 0], [10**400, 0]])


def test_non_numbers_name_the_field_in_both_entry_points():
    """A boolean or complex entry in a list: the InputError names ``sq`` / ``points``
    (it had no field) and says "boolean" as argcheck.no_booleans does."""
    with pytest.raises(InputError, match="boolean True") as e:
        cayley_menger([[0, True], [True, 0]], (1, 2))
    assert e.value.field == "sq"
    with pytest.raises(InputError, match="complex") as e:
        squared_distances([[0, 0, 1j], [1, 0, 0]])
    assert e.value.field == "points"
