"""Scale invariance (issue 14, item 4): every tier divides the lengths by a power of two
and scales its answer back (:mod:`distkin.octahedral.scaling`).

Reference: the same problem at scale 1.  A scaling by 2^k is exact in binary floating
point, so the fast tier's answers must agree *bit for bit* (points x 2^k, s15 x 4^k) and
the exact tiers' exactly; other scales (1e20, 1e-100: not exact) must give the same
poses to the fast tier's own accuracy.  Lengths whose squares leave float64 are refused
with the field named.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.octahedral import forward_kinematics, forward_kinematics_batched

BASE = [[0.0, 0.0, 0.0], [6.0, math.sqrt(108.0), 0.0], [12.0, 0.0, 0.0]]
PLAT = [[0.0, 0.0, 0.0], [6.0, 0.0, 0.0], [3.0, math.sqrt(27.0), 0.0]]
LEGS = [19.8, 18.0, 18.0, 17.0, 14.9, 17.8]


def _scaled(f):
    return ([[v * f for v in r] for r in BASE], [[v * f for v in r] for r in PLAT],
            [v * f for v in LEGS])


@pytest.mark.parametrize("k", [-300, -40, 40, 300])
def test_power_of_two_scales_are_exact_in_every_tier(k):
    """Lengths x 2^k: fast (single and batched) bit for bit, certified and precise
    exactly (the same rationals), 12 poses each; 2^300 overflowed before (the octic's
    coefficients are of degree up to 24 in the lengths)."""
    f = 2.0 ** k
    for method in ("fast", "certified", "precise"):
        one = forward_kinematics(BASE, PLAT, LEGS, method=method)
        big = forward_kinematics(*_scaled(f), method=method)
        assert len(big) == len(one) == 12, method
        for p, q in zip(big, one):
            assert p.s15 == q.s15 * f * f and p.side == q.side, method
            assert np.array_equal(p.points, q.points * f), method
            assert np.array_equal(p.rotation, q.rotation), method
            assert p.max_leg_error_relative == q.max_leg_error_relative, method
    b1 = forward_kinematics_batched(BASE, PLAT, [LEGS])
    bk = forward_kinematics_batched(*_scaled(f)[:2], [_scaled(f)[2]])
    assert np.array_equal(bk.s15, b1.s15 * f * f, equal_nan=True)
    assert np.array_equal(bk.points, b1.points * f, equal_nan=True)
    assert bk.trusted.all() and b1.trusted.all()


@pytest.mark.parametrize("f", [1e-100, 1e-20, 1e20, 1e100])
def test_other_scales_solve_the_same_problem(f):
    """Lengths x 1e+-20, 1e+-100 (rounded, so a slightly different problem): the fast
    tier proves 12 poses equal to the scale-1 ones x f to 1e-12 relative; auto agrees;
    before issue 14, 1e20 raised numpy's LinAlgError (infs in the companion matrix)."""
    one = forward_kinematics(BASE, PLAT, LEGS)
    res = forward_kinematics(*_scaled(f))
    auto = forward_kinematics(*_scaled(f), method="auto")
    assert res.conditioning.trusted and len(res) == len(auto) == 12
    for p, q in zip(res, one):
        assert abs(p.s15 / (q.s15 * f * f) - 1) < 1e-12
        np.testing.assert_allclose(p.points / f, q.points, rtol=0, atol=1e-12 * 20)


def test_the_octic_in_given_units_or_a_note():
    """The fast tier reports the octic's coefficients in the given units (each of degree
    12 - j in the squared lengths) where float64 holds them, and the normalised ones,
    said in the notes, where it does not."""
    one = forward_kinematics(BASE, PLAT, LEGS)
    small = forward_kinematics(*_scaled(2.0 ** 20))
    for j, (a, b) in enumerate(zip(small.octic, one.octic)):
        assert a == b * 2.0 ** (40 * (12 - (8 - j)))
    big = forward_kinematics(*_scaled(1e100))
    assert any("overflow float64" in n for n in big.notes)
    assert all(math.isfinite(c) for c in big.octic)


@pytest.mark.parametrize("f,where", [(1e300, "larger unit"), (1e-160, "smaller unit")])
def test_out_of_range_lengths_are_input_errors(f, where):
    """Lengths whose squares (the answer's s15) leave float64 are refused by every tier,
    naming the field of the largest length."""
    for method in ("fast", "auto", "certified", "precise"):
        with pytest.raises(InputError, match=where) as info:
            forward_kinematics(*_scaled(f), method=method)
        assert info.value.field.startswith(("legs", "base", "platform")), method
    with pytest.raises(InputError, match=where):
        forward_kinematics_batched(*_scaled(f)[:2], [_scaled(f)[2]])
