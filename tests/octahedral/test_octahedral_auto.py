"""``method="auto"`` and the fast tier's proof of its count (issues 8 and 14).

The reference for every count is the certified tier on the same exact float data
(FLINT's root isolation on the exact ``fmpq`` octic); for the Griffis-Duffy fold it is
also sympy's Sturm count.  The hard and easy sets are those of
:mod:`distkin.octahedral.hardset`.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import pytest

from distkin.errors import ConditioningWarning, InputError
from distkin.octahedral import forward_kinematics
from distkin.octahedral.auto import escalate
from distkin.octahedral.hardset import easy_set, hard_set
from distkin.octahedral.reference import GD_BASE, GD_LEGS, GD_PLATFORM


def _counts(res):
    return len(res.assembly_roots), len(res)


@pytest.fixture(scope="module")
def hard():
    return hard_set()


def test_auto_never_miscounts_on_the_hard_set(hard):
    """Every problem of the hard set (folds, the edge of assemblability, a flat
    configuration and extreme scales, at 2^-8 .. 2^-48 from the count change): auto's
    assembly-mode and pose counts equal the certified tier's.  The fast tier alone
    miscounts some of them (else the set would not be hard), and every one it miscounts
    is one it does not prove (:mod:`distkin.octahedral.descartes`)."""
    fast_wrong = 0
    for c in hard:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            fast = forward_kinematics(c.base, c.platform, list(c.legs))
        auto = forward_kinematics(c.base, c.platform, list(c.legs), method="auto")
        assert _counts(auto) == (c.modes, c.poses), c.name
        assert auto.method == "auto" and auto.tier in ("fast", "certified") and auto.tier_reason
        if _counts(fast) != (c.modes, c.poses):
            fast_wrong += 1
            assert not fast.conditioning.trusted, c.name
            assert auto.tier == "certified"
    assert fast_wrong >= 10


def test_easy_set_stays_fast():
    """Random assembled octahedra at scales 1e-3 .. 1e3: auto keeps the fast answer for
    at least 95 % of them (it proves all 200 on this machine; BENCHMARKS.md), and the
    count always equals the certified one."""
    easy = easy_set()
    kept = 0
    for c in easy:
        auto = forward_kinematics(c.base, c.platform, list(c.legs), method="auto")
        assert _counts(auto) == (c.modes, c.poses), c.name
        kept += auto.tier == "fast"
    assert kept >= 0.95 * len(easy)


def test_griffis_duffy_auto_is_fast_and_says_why():
    """Sec. VI example: well conditioned; auto answers with the fast tier, 12 poses."""
    res = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="auto")
    assert res.tier == "fast" and len(res) == 12
    assert "proved its assembly roots" in res.tier_reason
    assert res.conditioning.trusted and res.conditioning.separation > 1e-2


def test_escalation_without_exact_data_goes_to_precise():
    """Data whose squared lengths are irrational cannot reach the certified tier: auto
    then answers with the precise tier and says the count is not certified."""
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    legs = ["19.8", "18", "18", "17", "14.9", "17.8+sqrt(2)/1000"]
    with pytest.raises(InputError, match="rational squared lengths"):
        forward_kinematics(base, plat, legs, method="certified")
    fast = forward_kinematics(base, plat, legs, method="fast")
    distrusted = replace(fast, conditioning=replace(fast.conditioning, trusted=False,
                                                    reason="forced for the test"))
    res = escalate(distrusted, base, plat, legs)
    assert res.tier == "precise" and "not certified" in res.tier_reason
    assert _counts(res) == _counts(fast) == (6, 12)


def test_fast_warning_can_be_silenced_and_method_checked():
    """``warn=False`` skips the proof (the bare fast tier); an unknown method names
    the choices, including auto."""
    res = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, warn=False)
    assert res.conditioning is None and len(res) == 12
    with pytest.raises(InputError, match="'auto'"):
        forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="automatic")


def test_factored_form():
    """The fast tier polishes on the octic as G^2 - 4 R1 R2 from the kernel's quadratic
    parts.  Second route: the kernel's own expanded octic coefficients (Horner),
    exact in rationals (fmpq kernel) -- they agree exactly there, and in float to the
    size of the terms; H' agrees with the derivative of the expanded octic."""
    import flint
    import numpy as np

    from distkin._generated.octic_general import octic_exact
    from distkin.octahedral.single import factored_grid

    sides = [flint.fmpq(v) for v in (144, 144, 144, 36, 36, 36)]
    legs = [flint.fmpq(99 ** 2, 25), flint.fmpq(324), flint.fmpq(324), flint.fmpq(289),
            flint.fmpq(149 ** 2, 100), flint.fmpq(89 ** 2, 25)]
    d = octic_exact(sides, legs)
    for x in (flint.fmpq(269), flint.fmpq(1001, 3)):
        val = [d[3 * i] + x * (d[3 * i + 1] + x * d[3 * i + 2]) for i in range(10)]
        u, v, b1, b2, E1, E2, a, b, c, e = val
        G = u * E2 + v * E1 + 2 * b1 * b2
        horner = flint.fmpq(0)
        for k in d[30:]:
            horner = horner * x + k
        assert G * G - 4 * a * b * c * e == horner
    df = np.array([[float(v) for v in d]])
    xs = np.array([269.0, 333.7, 480.0])
    H, dH, S = factored_grid(df, xs)
    assert np.all(np.abs(H[0] - np.polyval(df[0, 30:], xs)) <= 1e-10 * S[0])
    dp = np.polyval(np.polyder(df[0, 30:]), xs)
    assert np.allclose(dH[0], dp, rtol=1e-8)
