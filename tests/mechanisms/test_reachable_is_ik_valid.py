"""``reachable`` is ``inverse_kinematics(...)[1].all(-1)`` (QA fix-mech2: at a pose where a
prismatic leg has zero length, its IK is not valid, its line undefined, but
``reachable`` said True: it read only the reach margin, which is q^2 >= 0 there).
Reference: the pose built so that platform joint and base joint of leg 1 coincide
exactly (0.03 - 0.03 and -0.0173... + 0.0173... are 0 in float64)."""

from __future__ import annotations

import numpy as np

from distkin.mechanisms.platforms import platform_mechanism


def test_zero_length_prismatic_leg_is_not_reachable():
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    m = platform_mechanism((base, plat), unit=0.01, height=17)
    p = m.leg_table[0].platform
    X = np.array([[-p[0], -p[1], -p[2], 0.0, 0.0, 0.0], m.home])
    assert tuple(m.leg_table[0].base) == (0.0, 0.0, 0.0)
    P = m.points(X)["P"]
    assert np.all(P[0, 0] == 0.0)                      # leg 1 of zero length
    q, valid = m.inverse_kinematics(X)
    assert not valid[0, 0] and valid[1].all()
    np.testing.assert_array_equal(m.reachable(X), valid.all(axis=-1))
    assert not m.reachable(X[0]) and m.reachable(X[1])
