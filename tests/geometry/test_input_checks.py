"""Input checks of the geometry helpers, the same in every tier (QA), and scale-free
degeneracy tests.

Independent routes: analytic cases (the right-angled corner P = (0, 0, 1) over the
triangle (0,0,0), (1,0,0), (0,1,0); the regular tetrahedron of edge sqrt(2), D = 288 V^2
= 32), exact rational data, and the other tiers.
"""

from __future__ import annotations

import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
from flint import arb, fmpq

from distkin.errors import DegenerateGeometryError, InfeasibleError, InputError
from distkin.geometry import (cayley_menger, parse_label, pose_from_points, squared_distances,
                              trilaterate, trilaterate_both, trilateration_parts)

TIERS = ("fast", "precise", "certified")
TRI = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]          # right triangle; (0, 0, 1) is at 1, 2, 2


def _floats(p):
    """A point of any tier as floats (arb: the midpoint, checked to contain the value)."""
    return np.array([float(x.mid()) if type(x).__name__ == "arb" else float(x) for x in p])


@pytest.mark.parametrize("method", TIERS)
def test_numeric_strings_parse_exactly_in_every_tier(method):
    """Strings are exact numbers in every tier (the fast tier took "1", the certified
    one raised AttributeError): the right-angled corner comes back, and the mixed
    strings "12/5", "sqrt(2)" agree with exact rational/irrational data in that tier."""
    got = trilaterate(TRI, ["1", "2", "2"], method=method)
    np.testing.assert_allclose(_floats(got), [0, 0, 1], atol=1e-15)
    pts = [["0", "0", "0"], ["1", "0", "0"], ["0", "1", "0"]]
    got = trilaterate(pts, ["12/5", "2", "sqrt(2)"], method=method)
    # independent: x = (s_a - s_b + 1) / 2, y = (s_a - s_c + 1) / 2, z = sqrt(s_a - x^2 - y^2)
    with mpmath.workdps(50):
        sa, sb, sc = mpmath.mpf(12) / 5, mpmath.mpf(2), mpmath.sqrt(2)
        x = (sa - sb + 1) / 2
        y = (sa - sc + 1) / 2
        z = mpmath.sqrt(sa - x * x - y * y)
        ref = [mpmath.nstr(v, 45) for v in (x, y, z)]
    np.testing.assert_allclose(_floats(got), [float(v) for v in ref], rtol=1e-15)
    if method == "certified":                # balls around the exact values (x = 7/10)
        assert arb(got[0]).contains(fmpq(7, 10))
        assert got[1].contains(arb(ref[1])) and got[2].contains(arb(ref[2]))


@pytest.mark.parametrize("method", TIERS)
def test_bad_strings_and_types_name_the_element(method):
    with pytest.raises(InputError, match=r"sq\[1\]") as e:
        trilaterate(TRI, ["1", "two", "2"], method=method)
    assert "'two'" in str(e.value)
    with pytest.raises(InputError, match=r"points\[2\]\[1\]"):
        trilaterate([[0, 0, 0], [1, 0, 0], [0, "1/0", 0]], [1, 2, 2], method=method)
    with pytest.raises(InputError, match=r"sq\[0\].*boolean"):
        trilaterate(TRI, [True, 2, 2], method=method)


@pytest.mark.parametrize("method", TIERS)
def test_side_is_checked_in_every_tier(method):
    for bad in ("+", 0, 2, np.nan, True, None):
        with pytest.raises(InputError, match="side") as e:
            trilaterate(TRI, [1, 2, 2], side=bad, method=method)
        assert "+1 or -1" in str(e.value)
    np.testing.assert_allclose(_floats(trilaterate(TRI, [1, 2, 2], side=-1, method=method)),
                               [0, 0, -1], atol=1e-15)
    if method != "fast":                    # one side: batches run in the fast tier
        with pytest.raises(InputError, match="side"):
            trilaterate(TRI, [1, 2, 2], side=[1, -1], method=method)


def test_batch_shapes_that_do_not_broadcast():
    P = np.array([TRI, TRI], float)
    with pytest.raises(InputError, match=r"sq.*\(3,\).*\(2,\)"):
        trilaterate(P, np.array([[1, 2, 2]] * 3, float))
    with pytest.raises(InputError, match=r"side.*\(3,\).*\(2,\)"):
        trilaterate(P, np.array([[1, 2, 2]] * 2, float), side=np.array([1, -1, 1]))
    # shapes that broadcast still do: one triangle, two distance sets, two sides
    got = trilaterate(np.array(TRI, float), np.array([[1, 2, 2]] * 2, float),
                      side=np.array([1, -1]))
    np.testing.assert_array_equal(got, [[0, 0, 1], [0, 0, -1]])


@pytest.mark.parametrize("method", TIERS)
def test_negative_squared_distance_is_an_input_error(method):
    with pytest.raises(InputError, match=r"sq\[1\].*>= 0"):
        trilaterate(TRI, [1, -2, 2], method=method)
    with pytest.raises(InputError, match=r">= 0"):
        trilaterate_both(TRI, [1, 2, "-1/2"], method=method)
    # the parts keep answering "cannot close" (the octahedral solver rejects a spurious
    # negative root s15 so): h^2 <= s < 0
    with pytest.raises(InfeasibleError):
        trilateration_parts(TRI, [-1, 2, 2], method=method)


def test_negative_squared_distance_batched_names_the_element():
    S = np.array([[1, 2, 2], [1, 2, -2.0]])
    with pytest.raises(InputError, match=r"sq\[1\]\[2\]: expected squared distances >= 0, "
                                         r"got -2"):
        trilaterate(np.array([TRI, TRI], float), S)


@pytest.mark.parametrize("k", [-150, -100, -40, 40, 100, 150])
def test_scaled_right_triangle_answers_in_every_tier(k):
    """A proper triangle of size 1e-150..1e150 was called collinear (|n|^2 under- or
    overflowed) with numpy warnings; the corner comes back, scaled, with no warning."""
    f = 10.0 ** k
    P = np.array(TRI, float) * f
    S = np.array([1.0, 2, 2]) * f * f
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = trilaterate(P, S)
        np.testing.assert_allclose(got / f, [0, 0, 1], atol=1e-15)
        R, t = pose_from_points(P, P + f * np.array([1.0, 2, 3]))
        np.testing.assert_allclose(R, np.eye(3), atol=1e-15)
        np.testing.assert_allclose(t / f, [1, 2, 3], rtol=1e-15)
        lo, hi = trilaterate_both(np.array([P, P]), np.array([S, S]))
        np.testing.assert_allclose(lo / f, [[0, 0, 1]] * 2, atol=1e-15)
        np.testing.assert_allclose(hi / f, [[0, 0, -1]] * 2, atol=1e-15)
    # the precise tier on the same (exact binary) data: the same point
    pts = [[mpmath.mpf(x) for x in row] for row in P]
    got = trilaterate(pts, [mpmath.mpf(x) for x in S], method="precise")
    np.testing.assert_allclose([float(x / f) for x in got], [0, 0, 1], atol=1e-15)
    # and a flat triangle at that scale is still flat
    flat = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], float) * f
    with pytest.raises(DegenerateGeometryError):
        trilaterate(flat, S)
    with pytest.raises(DegenerateGeometryError):
        pose_from_points(flat, flat)


def test_distances_beyond_the_range_of_the_triangle_are_refused():
    with pytest.raises(InputError, match="sq: expected squared distances within the float64"):
        trilaterate(np.array(TRI, float) * 1e-200, [1.0, 1.0, 1.0])


# ------------------------------------------------------------------ Cayley-Menger

def _tetra_sq(value):
    """The squared distances of a regular tetrahedron, all equal to ``value``."""
    M = np.full((4, 4), value, dtype=object)
    np.fill_diagonal(M, 0)
    return M


def test_strings_are_exact_in_cayley_menger():
    """Regular tetrahedron of edge sqrt(2): V = 1/3, so D(1,2,3,4) = 288/9 = 32 exactly,
    from strings as from integers; squared_distances of string coordinates too."""
    assert cayley_menger(_tetra_sq("2"), (1, 2, 3, 4)) == 32
    assert cayley_menger(_tetra_sq(2), (1, 2, 3, 4)) == 32
    corners = [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"], ["0", "0", "0"]]
    # the corner tetrahedron: V = 1/6, D = 288 / 36 = 8
    assert cayley_menger(squared_distances(corners), (1, 2, 3, 4)) == 8
    s = squared_distances([["0", "0", "0"], ["19.8", "0", "0"]])
    assert s[0, 1] == Fraction(99, 5) ** 2
    s = squared_distances([[0, 0, 0], ["sqrt(2)", 0, 0]])          # irrational: sympy
    assert s[0, 1] == 2
    assert cayley_menger({(1, 2): "12/5"}, (1, 2)) == Fraction(24, 5)   # D(i,j) = 2 s_ij


BAD = [np.nan, np.inf, -1.0]


@pytest.mark.parametrize("bad", BAD)
def test_cayley_menger_refuses_bad_squared_distances_in_every_kind(bad):
    for make in (float, mpmath.mpf, lambda v: arb(v)):
        M = _tetra_sq(make(2))
        M[0, 1] = M[1, 0] = make(bad)
        with pytest.raises(InputError, match=r"sq: expected squared distances that are "
                                             r"finite and >= 0, got s\(1,2\)"):
            cayley_menger(M if make is not float else M.astype(float), (1, 2, 3))
    if np.isfinite(bad):
        for make in (Fraction, int, fmpq, sp.Integer):
            M = _tetra_sq(make(2))
            M[0, 2] = M[2, 0] = make(int(bad))
            with pytest.raises(InputError, match=r"s\(1,3\)"):
                cayley_menger(sp.Matrix(M) if make is sp.Integer else M, (1, 2, 3))
    # batched floats: one bad set in a batch is named by its value
    B = np.stack([_tetra_sq(2.0).astype(float)] * 3)
    B[1, 2, 3] = B[1, 3, 2] = bad
    with pytest.raises(InputError, match=r"s\(3,4\)"):
        cayley_menger(B, (1, 2, 3, 4))
    # an unused entry does not matter
    M = _tetra_sq(2.0).astype(float)
    M[0, 3] = M[3, 0] = bad
    # equilateral, side^2 = 2: area^2 = 3/4, D(1,2,3) = -16 area^2 = -12
    assert cayley_menger(M, (1, 2, 3)) == pytest.approx(-12, rel=1e-15)


def test_symbols_still_pass():
    """Symbolic squared distances (the banana derivation) are not refused; a certainly
    negative one is."""
    s12, s13, s23 = sp.symbols("s12 s13 s23", positive=True)
    S = sp.Matrix([[0, s12, s13], [s12, 0, s23], [s13, s23, 0]])
    D = cayley_menger(S, (1, 2, 3))
    # Heron: 16 A^2 = 2(ab + bc + ca) - (a^2 + b^2 + c^2) = -D(1,2,3)
    heron16 = 2 * (s12 * s13 + s12 * s23 + s13 * s23) - (s12**2 + s13**2 + s23**2)
    assert sp.expand(D + heron16) == 0
    with pytest.raises(InputError, match=r"s\(1,2\)"):
        cayley_menger(S.subs(s12, -s13), (1, 2, 3))


@pytest.mark.parametrize("text", ["D(5,4;1)", "D(5,4,1,2;5,4,1)", "D(1,2;3,4;5,6)", "D()",
                                  "D(1,,2)", "D(0,1,2)", "D(1,2,3", "1_0,2", "D(-1,2)",
                                  "hello", "D(1,2;)"])
def test_malformed_labels_are_refused(text):
    with pytest.raises(InputError, match="expected a determinant label like") as e:
        parse_label(text)
    assert repr(text) in str(e.value)


def test_labels_parse_and_name_the_determinant():
    assert parse_label("D(5,4,1,2;5,4,1,6)") == ((5, 4, 1, 2), (5, 4, 1, 6))
    assert parse_label(" D( 1, 2 ,3 ) ") == ((1, 2, 3), None)
    assert parse_label("10,11,12") == ((10, 11, 12), None)
    # the triangle (0,0,0), (3,0,0), (0,4,0): area 6, D(1,2,3) = -16 * 36
    S = squared_distances([[0, 0, 0], [3, 0, 0], [0, 4, 0]])
    rows, cols = parse_label("D(1,2,3)")
    assert cayley_menger(S, rows, cols) == -16 * 36


def _regular_tetrahedron_sq():
    """Squared distances of the regular tetrahedron of edge sqrt(2): D(1,2,3,4) = 32."""
    return [[0, 2, 2, 2], [2, 0, 2, 2], [2, 2, 0, 2], [2, 2, 2, 0]]


@pytest.mark.parametrize("kind", ["float", "exact", "fmpq", "arb", "mpf", "sympy"])
def test_cayley_menger_refuses_an_asymmetric_matrix_in_every_kind(kind):
    """A matrix of squared distances is symmetric with a zero diagonal; the determinant
    reads one triangle only, so an asymmetric one gave the determinant of another
    configuration with no complaint (QA).  The symmetric one gives the analytic 32."""
    conv = {"float": float, "exact": int, "fmpq": fmpq, "arb": arb, "mpf": mpmath.mpf,
            "sympy": sp.Integer}[kind]

    def build(m):
        m = [[conv(x) for x in row] for row in m]
        return sp.Matrix(m) if kind == "sympy" else (
            np.array(m, float) if kind == "float" else np.array(m, dtype=object))

    d = cayley_menger(build(_regular_tetrahedron_sq()), (1, 2, 3, 4))
    assert abs(float(d.mid() if kind == "arb" else d) - 32) < 1e-12
    bad = _regular_tetrahedron_sq()
    bad[0][2] = 3                                   # s(1,3) = 3, s(3,1) = 2
    with pytest.raises(InputError, match=r"symmetric.*s\(1,3\) = .*3.* s\(3,1\) = .*2"):
        cayley_menger(build(bad), (1, 2, 3, 4))
    diag = _regular_tetrahedron_sq()
    diag[1][1] = 1
    with pytest.raises(InputError, match=r"s\(2,2\) = 0"):
        cayley_menger(build(diag), (1, 2, 3))
    # labels the determinant does not use are not judged
    d3 = cayley_menger(build(diag), (1, 3, 4))
    assert abs(float(d3.mid() if kind == "arb" else d3) + 16 * 3 / 4) < 1e-12  # A^2 = 3/4


def test_cayley_menger_refuses_asymmetry_in_a_batch_and_a_mapping():
    """Batched floats name the batch index; a mapping may not give two values for one
    pair or a non-zero diagonal; float rounding (a transposed product) still passes."""
    rng = np.random.default_rng(3)
    sq = squared_distances(rng.normal(size=(2, 4, 3)))
    sq[1, 0, 3] += 1.0
    with pytest.raises(InputError, match=r"batch index \(1,\)"):
        cayley_menger(sq, (1, 2, 3, 4))
    with pytest.raises(InputError, match="one squared distance per pair"):
        cayley_menger({(1, 2): 1, (2, 1): 2, (1, 3): 1, (2, 3): 1}, (1, 2, 3))
    with pytest.raises(InputError, match=r"s\(1,1\) = 0"):
        cayley_menger({(1, 1): 1, (1, 2): 1, (1, 3): 1, (2, 3): 1}, (1, 2, 3))
    assert cayley_menger({(1, 2): 1, (2, 1): 1, (1, 3): 1, (2, 3): 1, (1, 1): 0},
                         (1, 2, 3)) == -3        # equilateral side 1: -16 * 3/16
    P = rng.normal(size=(5, 3))
    G = P @ P.T
    s = np.diag(G)[:, None] + np.diag(G)[None, :] - 2 * G   # symmetric to rounding only
    np.fill_diagonal(s, 0.0)
    ref = cayley_menger(squared_distances(P), (1, 2, 3, 4))
    assert abs(cayley_menger(s, (1, 2, 3, 4)) - ref) <= 1e-9 * max(1.0, abs(ref))


def test_mixed_mapping_bool_labels_and_coordinate_messages():
    """A mapping of fmpq and floats is computed in floats (it raised TypeError); a
    boolean label is refused; coordinates are called coordinates; mpmath and arb
    infinities are refused in squared_distances, as NaN floats are (QA)."""
    # equilateral side 1 except s(2,3) = 2: Heron, 16 A^2 = 2(ab+bc+ca) - (a^2+b^2+c^2)
    a, b, c = 1.0, 1.0, 2.0
    heron16 = 2 * (a * b + b * c + c * a) - (a * a + b * b + c * c)
    got = cayley_menger({(1, 2): fmpq(1), (1, 3): 1.0, (2, 3): 2.0}, (1, 2, 3))
    assert isinstance(got, float) and abs(got + heron16) < 1e-15
    with pytest.raises(InputError, match=r"1-based integer labels, got \(True, 2\)"):
        cayley_menger({(True, 2): 1, (1, 3): 1, (2, 3): 1}, (1, 2, 3))
    with pytest.raises(InputError, match="expected coordinates as numbers, got the boolean True"):
        squared_distances([[True, 0, 0], [1, 0, 0]])
    for inf in (mpmath.inf, arb("inf")):
        with pytest.raises(InputError, match="finite coordinates"):
            squared_distances([[inf, 0, 0], [1, 0, 0]])


@pytest.mark.parametrize("method", TIERS)
def test_trilateration_tol_is_checked(method):
    """tol <= 0 raised a nonsensical 'infeasible, h^2 = 1' and NaN was taken (QA)."""
    for bad, what in ((-1, "positive"), (0, "positive"), (float("nan"), "finite"),
                      (True, "boolean")):
        with pytest.raises(InputError, match=what):
            trilaterate(TRI, [1, 2, 2], method=method, tol=bad)
    np.testing.assert_allclose(_floats(trilaterate(TRI, [1, 2, 2], method=method, tol=1e-9)),
                               [0, 0, 1], atol=1e-15)


@pytest.mark.parametrize("ball", [arb, mpmath.mpf])
def test_balls_mixed_with_exact_coordinates(ball):
    """arb or mpf coordinates beside exact ones (fmpq, int: what the certified tier makes
    of '1/2' beside 'sqrt(3)/2') are fine: the finiteness check of the balls raised
    TypeError on the exact entries (the demo's certified Cayley-Menger query).
    Reference: the unit equilateral triangle, D(1,2,3) = -16 * 3/16 = -3."""
    if ball is arb:
        pts = [[fmpq(0), 0, 0], [1, fmpq(0), 0], [fmpq(1, 2), arb(3).sqrt() / 2, 0]]
    else:                                          # the precise tier: ints beside mpf
        pts = [[0, 0, 0], [1, 0, 0], [mpmath.mpf(1) / 2, mpmath.sqrt(3) / 2, 0]]
    pts = np.array(pts, dtype=object)
    d = cayley_menger(squared_distances(pts), (1, 2, 3))
    assert abs(float(d.mid() if ball is arb else d) + 3) < 1e-12


@pytest.mark.parametrize("points, got", [([[0, 0, 0], [1, 0]], "got 2 coordinates"),
                                         ([[0, 0, 0], [1, 0, 0], 7], "got a scalar")])
def test_ragged_points_name_the_row(points, got):
    """QA J 8: a ragged list raised numpy's ValueError (inhomogeneous shape)."""
    from distkin.geometry import squared_distances
    bad = len(points) - 1
    with pytest.raises(InputError, match=got) as exc:
        squared_distances(points)
    assert exc.value.field == f"points[{bad}]"


@pytest.mark.parametrize("rows, cols, name", [(None, None, "rows"), (5, None, "rows"),
                                              ((1, 2, 3, 4), 3, "cols")])
def test_labels_that_are_not_a_sequence_are_named(rows, cols, name):
    """A bare label or None for ``rows``/``cols`` (QA 23b, 11): an InputError naming the
    argument, not ``TypeError: ... not iterable``; the same tetrahedron with its labels
    as a sequence gives 288 V^2 = 8 (V = 1/6: the unit corner tetrahedron)."""
    P = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 0]], float)
    S = squared_distances(P)
    with pytest.raises(InputError, match=f"sequence of 1-based point labels for {name}"):
        cayley_menger(S, rows, cols)
    assert float(cayley_menger(S, [1, 2, 3, 4])) == pytest.approx(288 / 36)
