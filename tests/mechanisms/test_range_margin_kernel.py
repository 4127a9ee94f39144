"""The arb kernel ``ranges`` (distkin.mechanisms.symbolic): the range margin
rho^2 (cos(q - m) - cos w) of a revolute leg is > 0 exactly where its crank angle is
inside its range, modulo 2π.

Independent reference: the fast tier's closed-form IK (atan2, float64) and
:func:`distkin.mechanisms.legs.in_revolute_range`, pose by pose, on random leg tables
with both IK branches and ranges written past ±π, shifted by whole turns, and wider than
a half turn; a full turn and a leg without a range have no row."""

from __future__ import annotations

import numpy as np
import pytest
from flint import arb

from distkin.mechanisms import LegMechanism
from distkin.mechanisms.kernels import range_legs
from distkin.mechanisms.legs import in_revolute_range

from legs_sampling import random_legs

#: per revolute leg, cycled: narrow; past +π (width 5 rad); shifted by -2π; a full
#: turn (no row); none (no row); a range wider than π about 0
RANGES = [(-0.3, 0.5), (2.0, 7.0), (-7.0, -5.5), (0.0, 2 * np.pi), None, (-2.0, 1.5)]


def _mechanism(seed):
    desc = random_legs(seed)
    legs, k = [], 0
    for i, leg in enumerate(desc.leg_table):
        d = leg.as_dict()
        if not leg.prismatic:
            d["range"] = RANGES[k % len(RANGES)]
            d["branch"] = -1 if k % 2 else 1              # both IK branches
            k += 1
        legs.append(d)
    return LegMechanism(desc.name, tuple(legs), desc.home_pose)


@pytest.mark.parametrize("seed", [3, 11])
def test_range_margin_sign_is_the_ik_angle_in_range(seed):
    mech = _mechanism(seed)
    rows = range_legs(mech)
    table = mech.leg_description().leg_table
    expected = [i for i, leg in enumerate(table) if not leg.prismatic
                and leg.range is not None and leg.range != (0.0, 2 * np.pi)]
    assert rows == expected and len(rows) >= 3
    ks = mech.kernels("arb")
    rng = np.random.default_rng(seed)
    home = np.asarray(mech.leg_description().home_pose)
    X = home + np.c_[rng.uniform(-0.03, 0.03, (150, 3)), rng.uniform(-0.4, 0.4, (150, 3))]
    q, _ = mech.inverse_kinematics(X)
    closes = mech.reach_margin(X) > 1e-12
    lo = np.array([table[i].range[0] for i in rows])
    hi = np.array([table[i].range[1] for i in rows])
    inside = in_revolute_range(q[:, rows], lo, hi)
    # the angle's distance to the nearer end of its range, modulo 2π
    ends = np.minimum(np.abs(np.angle(np.exp(1j * (q[:, rows] - lo)))),
                      np.abs(np.angle(np.exp(1j * (q[:, rows] - hi)))))
    seen = {True: 0, False: 0}
    for n, pose in enumerate(X):
        margins = ks.ranges([arb(float(v)) for v in pose])
        assert len(margins) == len(rows)
        for j, i in enumerate(rows):
            if not closes[n, i] or ends[n, j] < 1e-9:
                continue
            m = margins[j]
            assert m > 0 or m < 0, (n, i, m)              # decided away from the ends
            assert bool(m > 0) == bool(inside[n, j]), (n, i, q[n, i], table[i].range)
            seen[bool(inside[n, j])] += 1
    assert seen[True] > 50 and seen[False] > 50             # both outcomes tested


def test_no_ranges_kernel_without_a_revolute_range():
    """A table whose revolute legs have no range, or a full turn, has no ``ranges`` rows
    and its arb kernel set no ``ranges`` kernel (the certified workspace then reads the
    reach margins alone, as before)."""
    desc = random_legs(5)
    legs = []
    for leg in desc.leg_table:
        d = leg.as_dict()
        if not leg.prismatic:
            d["range"] = None if len(legs) % 2 else (-np.pi, np.pi)
        legs.append(d)
    mech = LegMechanism(desc.name, tuple(legs), desc.home_pose)
    assert range_legs(mech) == []
    assert not hasattr(mech.kernels("arb"), "ranges")
