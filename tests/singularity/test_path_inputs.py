"""Inputs of the pose and path helpers of :mod:`distkin.singularity.paths` (QA defects
5, 6, 9, 10): bad input is an InputError naming the field, never a numpy/Python
traceback or a silent NaN; certify_crossing names an exact zero of det J as a proved
singular pose instead of "got +0 on both sides", and proves a crossing only by a sign
change (an exact zero is a crossing or a touch).

References: analytic rotations (a rotation by a multiple of 2 pi about an axis is the
identity; by pi/2 a quarter turn), exact rational functions of s for the crossings.
"""

from __future__ import annotations

import math
from fractions import Fraction

import flint
import numpy as np
import pytest

from distkin.errors import InputError, UncertifiedError
from distkin.singularity import (certify_crossing, path_crossings, pose_points,
                                 rotation_from_vector)


# ------------------------------------------------------------------ rotation_from_vector

@pytest.mark.parametrize("w", [[1e300, 0, 0], [0, 1e300, 1e300], [1e6, 0, 0]])
def test_huge_angles_are_refused_naming_the_range(w):
    with pytest.raises(InputError, match=r"^w: expected a rotation angle \|w\| <= 9.01e\+05 "
                                         r"rad at 53 bits"):
        rotation_from_vector(w)
    with pytest.raises(InputError, match=r"^w: expected a rotation angle"):
        rotation_from_vector(np.array([w, [0, 0, 0]]))        # in a batch too


def test_large_angles_in_range_are_finite_and_right():
    # 2 pi k about z: the identity, to the rounding of 2 pi k (about 2^-53 |w| rad)
    k = 100_000
    w = [0.0, 0.0, 2 * math.pi * k]
    R = rotation_from_vector(w)
    assert np.all(np.isfinite(R))
    assert np.allclose(R, np.eye(3), atol=1e-9)
    # a quarter turn about x, plus many full turns (exact binary angle, analytic cos/sin)
    a = math.pi / 2 + 2 * math.pi * 1000
    Rx = rotation_from_vector([a, 0, 0])
    assert np.allclose(Rx, [[1, 0, 0], [0, math.cos(a), -math.sin(a)],
                            [0, math.sin(a), math.cos(a)]], atol=1e-15)
    assert np.allclose(Rx, [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-9)


def test_precise_tier_refuses_by_its_own_precision():
    """The precise tier's limit is that of its own ``dps`` (default 30 digits, 103 bits),
    never mpmath's global precision (QA 23)."""
    import mpmath
    w = [mpmath.mpf(10) ** 20, 0, 0]
    with pytest.raises(InputError, match=r"at 53 bits"):
        rotation_from_vector(w, method="precise", dps=15)
    R = rotation_from_vector(w, method="precise", dps=60)   # 1e-10 2^200 >> 1e20
    with mpmath.workdps(80):
        assert abs(R[1, 1] - mpmath.cos(mpmath.mpf(10) ** 20)) < mpmath.mpf(10) ** -40
    with mpmath.workprec(200):               # the ambient precision is not the tier's
        ambient = rotation_from_vector(w)
    assert ambient[1, 1] == rotation_from_vector(w, method="precise", dps=30)[1, 1]
    with pytest.raises(InputError, match=r"^w: .*?at 20 bits"):
        rotation_from_vector([mpmath.mpf(10) ** 7, 0, 0], method="precise", dps=5)


@pytest.mark.parametrize("w, shape", [([1, 0], r"\(2,\)"), ([[1, 0], [0, 1]], r"\(2, 2\)"),
                                      (1.0, r"\(\)")])
def test_wrong_shapes_name_w(w, shape):
    with pytest.raises(InputError, match=rf"^w: expected rotation vectors of shape "
                                         rf"\(\.\.\., 3\), got {shape}"):
        rotation_from_vector(w)


def test_certified_tier_names_w():
    with pytest.raises(InputError, match=r"^w: expected one rotation vector \(3,\)"):
        rotation_from_vector([flint.fmpq(1), flint.fmpq(0)], method="certified")


# --------------------------------------------------------------------------- pose_points

@pytest.mark.parametrize("args, field, what", [
    (([[0, 0, np.nan]], np.eye(3), [0, 0, 0]), r"points\[0\]\[2\]", "finite"),
    (([[0, 0, 0]], np.eye(3), [0, np.inf, 0]), r"translation\[1\]", "finite"),
    (([[0, 0, 0]], np.full((3, 3), np.nan), [0, 0, 0]), r"rotation\[0\]\[0\]", "finite"),
    (([[0, 0, 0]], np.eye(3), [0, 0]), "translation", r"shape \(\.\.\., 3\), got \(2,\)"),
    (([[0, 0, 0]], np.eye(2), [0, 0, 0]), "rotation", r"shape \(\.\.\., 3, 3\), got \(2, 2\)"),
    (([0, 0, 0], np.eye(3), [0, 0, 0]), "points", r"shape \(n, 3\), got \(3,\)"),
    (([[0, 0, 0]], np.stack([np.eye(3)] * 3), np.zeros((2, 3))), "translation",
     "matching batch shapes"),
    (([[True, 0, 0]], np.eye(3), [0, 0, 0]), r"points\[0\]\[0\]", "boolean"),
])
def test_pose_points_refuses_bad_input(args, field, what):
    with pytest.raises(InputError, match=rf"^{field}: expected .*{what}"):
        pose_points(*args)


def test_pose_points_values():
    R = rotation_from_vector([0, 0, math.pi / 2])
    q = [[1.0, 0, 0], [0, 2.0, 0]]
    assert np.allclose(pose_points(q, R, [1, 1, 1]), [[1, 2, 1], [-1, 1, 1]], atol=1e-15)
    Rs = np.stack([np.eye(3), R])
    out = pose_points(q, Rs, np.zeros((2, 3)))
    assert out.shape == (2, 2, 3) and np.allclose(out[1], [[0, 1, 0], [-2, 0, 0]], atol=1e-15)


# ------------------------------------------------------------------------ path_crossings

@pytest.mark.parametrize("samples", [-5, 0, 1, 10.5, "10", True, None])
def test_path_crossings_samples_must_be_an_integer_of_at_least_two(samples):
    with pytest.raises(InputError, match=rf"^samples: expected an integer >= 2, got "
                                         rf"{re_escape(repr(samples))}"):
        path_crossings(lambda s: s - 0.5, samples)


@pytest.mark.parametrize("xtol", [0.0, -1e-12, float("nan")])
def test_path_crossings_xtol_must_be_positive(xtol):
    with pytest.raises(InputError, match=r"^xtol: "):
        path_crossings(lambda s: s - 0.5, 10, xtol=xtol)


def test_path_crossings_root():
    roots, grid, vals = path_crossings(lambda s: s - 0.3, 2)   # the analytic root 0.3
    assert roots == [pytest.approx(0.3, abs=1e-14)] and grid.size == 2


def re_escape(text):
    import re
    return re.escape(text)


# ---------------------------------------------------------------------- certify_crossing

def test_an_exact_zero_at_the_upper_end_is_said_not_called_a_crossing():
    # f(1) = 0 exactly at hi: no bracket can show a sign change (nothing beyond hi); the
    # error names the exact zero (it said "-1 on both sides"; then, review, it returned a
    # Crossing with signs (0, 0), counted as a certified sign change)
    with pytest.raises(UncertifiedError, match=r"exactly 0 at s = 1 \(a proved singular"):
        certify_crossing(lambda s: flint.arb(s) - 1, 1.0)


def test_an_exact_zero_at_zero_is_said_not_called_a_crossing():
    with pytest.raises(UncertifiedError, match=r"exactly 0 at s = 0 \(a proved singular"):
        certify_crossing(lambda s: flint.arb(s), 0.0)


def test_an_exact_zero_at_s_is_bracketed_like_any_crossing():
    # f = s - 1/2 exactly; asked around s = 0.5 + 1e-9 or at the exact zero s = 0.5 the
    # sign change is proved by a bracket around it (reference: f's signs at the ends)
    f = lambda s: flint.arb(s) - flint.arb(1) / 2  # noqa: E731
    for s in (0.5 + 1e-9, 0.5):
        c = certify_crossing(f, s)
        assert c.signs == (-1, 1) and c.bracket[0] < Fraction(1, 2) < c.bracket[1]


def test_an_exact_touch_is_not_a_crossing():
    # (s - 1/2)^2: exactly 0 at 1/2, positive on both sides: a touch (review: it was
    # returned as a Crossing)
    f = lambda s: (flint.arb(s) - flint.arb(1) / 2) ** 2  # noqa: E731
    with pytest.raises(UncertifiedError, match=r"\+1 at s = .* and \+1 at s = .*exactly 0 "
                                               r"at s = 0.5 \(a proved singular pose"):
        certify_crossing(f, 0.5)


def test_a_touch_prints_its_signs_right():
    # (s - 1/2)^2 + 1e-30 > 0: no crossing; both signs +1, printed as such
    f = lambda s: (flint.arb(s) - flint.arb(1) / 2) ** 2 + flint.arb(10) ** -30  # noqa: E731
    with pytest.raises(UncertifiedError, match=r"got \+1 at s = .* and \+1 at s = "):
        certify_crossing(f, 0.5)


@pytest.mark.parametrize("kw, field", [({"s": float("nan")}, "s"), ({"s": float("inf")}, "s"),
                                       ({"s": 1.5}, "s"), ({"s": "x"}, "s"),
                                       ({"s": 0.5, "start": 0}, "start"),
                                       ({"s": 0.5, "limit": -1}, "limit"),
                                       ({"s": 0.5, "lo": 1.0, "hi": 0.0}, "hi")])
def test_certify_crossing_refuses_bad_parameters(kw, field):
    with pytest.raises(InputError, match=rf"^{field}: (expected|cannot parse)"):
        certify_crossing(lambda s: flint.arb(s) - 1, **kw)
