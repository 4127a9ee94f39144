"""Revolute joint ranges are compared modulo 2π in every tier (QA report M, finding 1).

The IK gives crank angles in (-π, π]; a range written past ±π ([270, 450] deg, the arc
of [-90, 90] deg) or a full turn ([0, 360] deg) must accept the same angles as the
equivalent normalised range.  Independent references: the same mechanism with the
normalised range, and an mpmath search over the shifts k (50 digits).
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from distkin.mechanisms import LegMechanism
from distkin.mechanisms.kinematics_tiers import _range_check
from distkin.mechanisms.legs import full_turn, in_revolute_range

from legs_sampling import random_legs


def _with_ranges(desc, ranges):
    legs = []
    for leg, r in zip(desc.leg_table, ranges):
        d = leg.as_dict()
        if not leg.prismatic:
            d["range"] = r
        legs.append(d)
    return LegMechanism(desc.name, tuple(legs), desc.home_pose, route="numpy")


def _poses(home, n, seed):
    rng = np.random.default_rng(seed)
    return home + np.c_[rng.uniform(-0.02, 0.02, (n, 3)), rng.uniform(-0.3, 0.3, (n, 3))]


@pytest.mark.parametrize("shift", [1, -1, 2])
def test_shifted_range_same_validity_as_normalised(shift):
    desc = random_legs(3)
    rng = np.random.default_rng(5)
    # narrow ranges around 0 so that some poses fall outside
    norm = [tuple(sorted(rng.uniform(-0.5, 0.5, 2))) for _ in desc.leg_table]
    shifted = [(lo + 2 * np.pi * shift, hi + 2 * np.pi * shift) for lo, hi in norm]
    X = _poses(desc.home, 400, 1)
    v_norm = _with_ranges(desc, norm).inverse_kinematics(X)[1]
    v_shift = _with_ranges(desc, shifted).inverse_kinematics(X)[1]
    assert v_norm.any() and not v_norm.all()        # the test has both outcomes
    assert np.array_equal(v_norm, v_shift)


@pytest.mark.parametrize("turn", [(0.0, 2 * np.pi), (math.radians(0), math.radians(360)),
                                  (-10.0, 10.0)])
def test_full_turn_is_no_restriction(turn):
    desc = random_legs(4)
    X = _poses(desc.home, 200, 2)
    none = _with_ranges(desc, [None] * desc.L)
    full = _with_ranges(desc, [turn] * desc.L)
    assert np.array_equal(none.inverse_kinematics(X)[1], full.inverse_kinematics(X)[1])
    assert np.array_equal(none.reachable(X), full.reachable(X))


def _in_range_mp(q, lo, hi):
    """Independent: some q + 2πk in [lo, hi], k in -4..4, at 50 digits."""
    with mpmath.workdps(50):
        q, lo, hi = mpmath.mpf(q), mpmath.mpf(lo), mpmath.mpf(hi)
        return any(lo <= q + 2 * mpmath.pi * k <= hi for k in range(-4, 5))


class _Ranges:
    def __init__(self, lo, hi):
        self.r = (np.array([lo]), np.array([hi]))

    def _joint_ranges(self):
        return self.r


def test_certified_range_check_modulo_2pi():
    from flint import arb
    rng = np.random.default_rng(7)
    decided = 0
    for _ in range(400):
        q = float(rng.uniform(-np.pi, np.pi))
        lo = float(rng.uniform(-3 * np.pi, 3 * np.pi))
        hi = lo + float(rng.uniform(0.05, 2 * np.pi - 0.05))
        reasons = []
        got = _range_check(_Ranges(lo, hi), arb(q, 1e-25), 0, 0, reasons)
        want = _in_range_mp(q, lo, hi)
        assert got is None or got == want, (q, lo, hi, got, want)
        assert np.array_equal(in_revolute_range(q, lo, hi), want)
        decided += got is not None
    assert decided == 400                          # 1e-25 balls decide every random case
    # the QA case: a full turn [0, 2π] and q = -0.6576 rad
    assert full_turn(0.0, 2 * np.pi)
    assert _range_check(_Ranges(0.0, 2 * np.pi), arb(-0.6576), 0, 0, []) is True
    # [270, 450] deg holds q = 0.106 deg: certainly in range; and a ball on an end of the
    # range (modulo 2π) is undecided, with the reason
    lo, hi = math.radians(270), math.radians(450)
    assert _range_check(_Ranges(lo, hi), arb(math.radians(0.106), 1e-20), 0, 0, []) is True
    reasons = []
    assert _range_check(_Ranges(lo, hi), arb(hi - 2 * math.pi, 1e-10), 0, 0, reasons) is None
    assert "modulo 2π" in reasons[0][2]


def test_a_range_just_short_of_a_turn_is_not_a_full_turn():
    """QA Q 1: [0, 359.9999999997] deg was taken for the full turn (a 1e-12 relative
    tolerance, 1e4 times the conversion's rounding), and the certified tier called
    q = -1e-12 rad (359.99999999994 deg, above the range) certainly in range.  The
    reference: mpmath, the range's degree values converted at 50 digits."""
    from flint import arb
    for lo_deg, hi_deg in ((0, 359.9999999997), (-360, -1e-10), (7200, 7559.9999999)):
        lo, hi = math.radians(lo_deg), math.radians(hi_deg)
        assert not full_turn(lo, hi)
        with mpmath.workdps(50):
            want = any(mpmath.radians(lo_deg) <= mpmath.mpf(-1e-12) + 2 * mpmath.pi * k
                       <= mpmath.radians(hi_deg) for k in range(-30, 30))
        assert not want
        assert not in_revolute_range(-1e-12, lo, hi)
        assert _range_check(_Ranges(lo, hi), arb(-1e-12, 1e-28), 0, 0, []) is False
    for lo_deg, hi_deg in ((0, 360), (-180, 180), (7200, 7560), (-720, -360)):
        assert full_turn(math.radians(lo_deg), math.radians(hi_deg))


def test_a_reversed_range_hints_at_the_wrap_around_arc(tmp_path):
    """QA Q 6: [90, -90] deg is refused (min < max), and the message says how the arc
    through 180 deg is written; the hinted [90, 270] then holds 180 deg (and not 0)."""
    from pathlib import Path

    from distkin.app.scene import loads_scene
    from distkin.errors import InputError
    ex = Path(__file__).resolve().parents[2] / "examples" / "rus8_device.toml"
    text = ex.read_text(encoding="utf-8")
    with pytest.raises(InputError) as exc:
        loads_scene(text.replace("range = [-90, 90]", "range = [90, -90]"))
    assert "written [90, 270]" in str(exc.value) and exc.value.field.endswith(".range")
    lo, hi = math.radians(90), math.radians(270)
    assert in_revolute_range(math.pi, lo, hi) and not in_revolute_range(0.0, lo, hi)
