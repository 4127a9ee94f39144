"""Batched ``auto`` when the certified tier cannot decide one problem, mismatched batch
shapes, and the messages and counts a user reads (QA round F).  References: the single
``auto``/``certified`` calls on the same problems, and the geometry of the inputs."""

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, DegenerateGeometryError, InputError
from distkin.octahedral import forward_kinematics, forward_kinematics_batched

BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
GD = [19.8, 18, 18, 17, 14.9, 17.8]


def test_a_multiple_root_goes_to_the_precise_tier():
    """Six equal legs on the equilateral pair: triple roots where three modes meet; the
    certified tier raises for it (it cannot single out the placements), and ``auto``
    raised too, although README promises "escalated to certified (or precise)" (QA R 2).
    Now the precise tier answers, saying its count is not certified, single and
    batched alike; the other problems of the batch keep their answers.  References: the
    precise tier called directly, and the exact octic's factorisation (python-flint)
    for the multiplicities."""
    import flint
    from distkin.errors import UncertifiedError
    with pytest.raises(UncertifiedError, match="multiplicity 3"):
        forward_kinematics(BASE, PLAT, [18] * 6, method="certified")
    auto = forward_kinematics(BASE, PLAT, [18] * 6, method="auto")
    direct = forward_kinematics(BASE, PLAT, [18] * 6, method="precise", dps=50)
    assert auto.tier == "precise" and not auto.certified
    assert "multiplicity 3" in auto.tier_reason and "not certified" in auto.tier_reason
    assert len(auto) == len(direct) == 16
    assert [round(p.s15, 9) for p in auto.poses] == [round(p.s15, 9) for p in direct.poses]
    assert max(p.max_leg_error_relative for p in auto.poses) < 1e-12
    # the multiplicities of the exact octic's real roots (python-flint), not the tier's
    octic = flint.fmpq_poly([flint.fmpq(c.numerator, c.denominator)
                             for c in reversed(auto.octic)])
    factors = octic.factor()[1]
    real_mult = sorted(m for f, m in factors if f.degree() == 1)
    assert [r.multiplicity for r in auto.roots if r.multiplicity > 1] == [3, 3]
    assert real_mult.count(3) == 2
    legs = np.array([GD, [18] * 6, [19.0, 18, 18, 17, 14.9, 17.8]])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)    # nothing left unresolved
        b = forward_kinematics_batched(BASE, PLAT, legs, method="auto")
    assert not b.unresolved and b.tier[1] == "precise" and not b.trusted[1]
    assert b.count[1] == 16
    for i in (0, 2):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            one = forward_kinematics(BASE, PLAT, list(legs[i]), method="auto")
        assert b.count[i] == len(one)
        assert np.allclose(b.s15[i, :len(one.assembly_roots)],
                           [r.value for r in one.assembly_roots], rtol=1e-12)


def test_mismatched_batch_axes_are_named():
    base = np.array([[[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]]] * 2)
    legs = np.array([GD] * 3)
    for method in ("fast", "auto"):
        with pytest.raises(InputError) as e:
            forward_kinematics_batched(base, PLAT, legs, method=method)
        assert e.value.field == "base" and "(2, 3, 3)" in str(e.value)
        assert "legs (3, 6)" in str(e.value)


def test_a_thin_triangle_names_the_tolerance():
    """A base 10 long and 1e-6 high is not collinear; the solver's relative test
    refuses it, and the message now gives the test's value and threshold:
    16 area² / (a + b + c)² with the squared sides (a, b, c) = (25 + 1e-12, 25 + 1e-12,
    100): 16 · (10 · 1e-6 / 2)² / 150² = 1.78e-14 (Heron's formula in float64 loses
    about eps (a + b + c)² / 16 area² = 0.6 % of it to cancellation)."""
    base = [[0, 0, 0], [5, "1/1000000", 0], [10, 0, 0]]
    with pytest.raises(DegenerateGeometryError) as e:
        forward_kinematics(base, PLAT, GD, method="fast")
    # (the exact tiers solve it: they refuse only a collinear triangle, QA N 2)
    msg = str(e.value)
    assert "within the solver's tolerance" in msg and "not above 1e-12" in msg
    import re
    value = float(re.search(r"= ([0-9.e+-]+), not above", msg).group(1))
    assert value == pytest.approx(16 * (10 * 1e-6 / 2) ** 2 / 150 ** 2, rel=0.02)


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_dps_with_a_tier_that_ignores_it_is_refused(method):
    """``dps`` was silently ignored by the fast and certified tiers (QA T 9), while the
    mechanisms' tiers refuse it; now the octahedral and 6-6 solvers refuse it too."""
    from distkin.delta import forward_kinematics66
    with pytest.raises(InputError, match="'dps' only with method 'precise' or 'auto'"):
        forward_kinematics(BASE, PLAT, GD, method=method, dps=50)
    if method == "fast":
        with pytest.raises(InputError, match="'dps' only with method"):
            forward_kinematics_batched(BASE, PLAT, np.array([GD]), dps=40)
    with pytest.raises(InputError, match="'dps' only with method"):
        forward_kinematics66((BASE, PLAT),
                             ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"],
                             ["19.8", 18, 18, 17, "14.9", "17.8"], method=method, dps=40)


def test_an_exact_tier_says_when_it_solved_bare_floats():
    """DESIGN §3: a bare float is its exact binary value "and the result says so"; the
    library's exact tiers did not (only the scene layer did, QA T 3).  Reference: the
    decimal expansion of the binary 19.8 by Python's Decimal."""
    from decimal import Decimal
    exact = forward_kinematics(BASE, PLAT, ["19.8", 18, 18, 17, "14.9", "17.8"],
                               method="certified")
    assert "bare float" not in exact.accuracy
    r = forward_kinematics(BASE, PLAT, GD, method="certified")
    assert f"legs[0] = 19.8 is {Decimal(19.8)}" in r.accuracy
    assert "also legs[4], legs[5]" in r.accuracy
    p = forward_kinematics(BASE, PLAT, GD, method="precise")
    assert "bare floats are taken as their exact binary values" in p.accuracy
    assert r.roots[0].value != exact.roots[0].value      # another problem, certified


@pytest.mark.parametrize("method", ["fast", "precise", "certified", "auto"])
def test_a_pose_cannot_be_edited_after_the_fact(method):
    """A proved pose +- its radius could be changed in place (QA T 8): every tier's pose
    arrays are read-only, single and batched, and the answer stays what was computed."""
    res = forward_kinematics(BASE, PLAT, ["19.8", 18, 18, 17, "14.9", "17.8"],
                             method=method)
    before = res[0].translation.copy()
    for p in res.poses:
        for a in (p.rotation, p.translation, p.points):
            with pytest.raises(ValueError, match="read-only"):
                a[0] = 99
    assert np.array_equal(res[0].translation, before)
    if method == "fast":
        b = forward_kinematics_batched(BASE, PLAT, np.array([GD]))
        with pytest.raises(ValueError, match="read-only"):
            b.result(0)[0].points[0, 0] = 1.0
