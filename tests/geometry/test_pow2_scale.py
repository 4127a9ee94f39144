"""One power-of-two rescaling for the fast tiers (distkin.geometry.pow2_scale): exact
against rational arithmetic, the float64 normal range as the boundary, and the one
warning of its three callers (Cayley-Menger determinants, singularity conditions,
capability indices) pointing at the caller's line."""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from distkin.errors import FloatRangeWarning
from distkin.geometry.pow2_scale import SMALLEST_NORMAL, exponent, scale_back


def test_exponent_matches_frexp_and_zero():
    rng = np.random.default_rng(1)
    m = np.abs(rng.standard_normal(200)) * 2.0 ** rng.integers(-1070, 1020, 200)
    m[:3] = [0.0, 5e-324, np.finfo(float).max]
    e = exponent(m)
    for x, ex in zip(m, e):
        assert ex == (math.frexp(x)[1] if x > 0 else 0)
        if x > 0:
            assert 0.5 <= Fraction(x) / Fraction(2) ** int(ex) < 1       # exact


def test_scale_back_is_exact_and_flags_only_values_leaving_the_normal_range():
    v = np.array([0.75, -3.0, 0.0, np.nan, 1.5, 1.5, 1.0])
    k = np.array([10, -1000, 5000, 7, 1024, -1023, -1022])
    with pytest.warns(FloatRangeWarning) as rec:
        out, lost = scale_back(v, k, "test value", "something else")
    # exact where representable: compare with rationals
    assert Fraction(out[0]) == Fraction(3, 4) * 2 ** 10
    assert Fraction(out[1]) == -3 * Fraction(1, 2 ** 1000)
    assert out[6] == SMALLEST_NORMAL                 # 2^-1022 itself is normal
    # 0 and NaN are no range loss; 1.5·2^1024 overflows; 1.5·2^-1023 is subnormal
    assert lost.tolist() == [False, False, False, False, True, True, False]
    assert len(rec) == 1
    msg = str(rec[0].message)
    assert "test value = " in msg and "beyond the largest" in msg and "(2 of 7)" in msg
    assert "batch index (4,)" in msg and msg.endswith("use something else")
    ref = mpmath.mpf(3) * mpmath.mpf(2) ** 1023                  # 1.5·2^1024
    assert float(mpmath.mpf(rec[0].message.value) / ref) == pytest.approx(1.0, rel=1e-5)
    assert rec[0].filename == __file__


def test_in_range_values_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out, lost = scale_back(3.0, 4, "x", "y")
    assert out == 48.0 and not lost


def _warned_here(call):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        call()
    ours = [w for w in rec if issubclass(w.category, FloatRangeWarning)]
    assert len(ours) == 1, [str(w.message) for w in rec]
    return ours[0]


def test_each_caller_warns_once_at_the_users_line():
    """The three callers (different degrees, same helper): the warning's value agrees with
    an independent mpmath evaluation and its location is this file (stacklevel)."""
    from distkin.geometry import cayley_menger, squared_distances
    from distkin.indices import worst_case_output
    from distkin.singularity import jacobian_det, octahedral_joints, signed_cm_condition

    tet = np.array([[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4]], float)   # D = 288 V^2, V = 20
    w = _warned_here(lambda: cayley_menger(squared_distances(tet * 1e-60), (1, 2, 3, 4)))
    assert w.filename == __file__
    assert float(mpmath.mpf(w.message.value) / mpmath.mpf("1.152e-355")) == pytest.approx(1, rel=1e-5)
    assert "Cayley-Menger determinant" in str(w.message)

    P0 = np.random.default_rng(0).standard_normal((6, 3))
    w = _warned_here(lambda: signed_cm_condition(P0 * 1e-30))   # degree 18: 1e-540
    assert w.filename == __file__
    with mpmath.workdps(30):
        ref = signed_cm_condition(P0 * 1e-30, method="precise")
        assert float(mpmath.mpf(w.message.value) / ref) == pytest.approx(1, rel=1e-4)
    w = _warned_here(lambda: jacobian_det(*octahedral_joints(P0 * 1e-300), normalised=False))
    assert w.filename == __file__                   # another depth below the public call

    G = np.random.default_rng(3).normal(size=(6, 8))
    w = _warned_here(lambda: worst_case_output(G * 1e300, -1e300, 1e300))
    assert w.filename == __file__ and "worst-case output" in str(w.message)


def test_a_batch_warning_names_the_batch_index_of_the_value():
    """Only the out-of-range entries of a batch are recomputed; the warning still gives
    the index in the caller's batch (review: it gave the index within the subset), and
    a subnormal result warns through the Cayley-Menger route too."""
    from distkin.geometry import cayley_menger, squared_distances
    tet = np.array([[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4]], float)   # D = 288 V^2 = 115200
    for batch, where, side in (([tet, tet, tet * 1e-60, tet], "(2,)", "below the smallest"),
                               ([tet, tet * 1e-54], "(1,)", "below the smallest normal")):
        w = _warned_here(lambda: cayley_menger(squared_distances(np.stack(batch)),
                                               (1, 2, 3, 4)))
        assert f"at batch index {where}" in str(w.message) and side in str(w.message)
        assert "(1 of " + str(len(batch)) + ")" in str(w.message)
        scale = 1e-60 if where == "(2,)" else 1e-54
        ref = mpmath.mpf(115200) * mpmath.mpf(scale) ** 6                # degree 3 in s
        assert float(mpmath.mpf(w.message.value) / ref) == pytest.approx(1, rel=1e-5)
