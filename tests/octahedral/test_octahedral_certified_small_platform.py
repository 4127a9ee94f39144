"""The certified tier on a platform 2e-4 of the base (QA 23d, 1).

The placed platform's balls at the first working precision were too wide to prove it a
triangle (``frame_fit``), and that refusal escaped the loop that doubles the precision
for the trilateration: UncertifiedError on an ordinary problem (54 of 1812 random
octahedra with a platform 1e-5..1e-4 of the base), and ``auto`` fell back to an
uncertified precise answer.  Independent route: the precise tier at 100 digits."""

import numpy as np

from distkin.octahedral import forward_kinematics

BASE = [[0.8770800494851005, -0.4660354924993755, 0],
        [-0.6765951237220922, 0.7757893638505442, 0],
        [-0.3356656201314496, 0.9834143972113409, 0]]
PLAT = [[0.00021022708150428821, -6.749699591747583e-05, 0],
        [0.00011439206806772348, 2.5401584908207348e-05, 0],
        [0.00012800372819072852, -3.7230356987244265e-06, 0]]
LEGS = [1.4442845172521461, 0.9734536171953465, 0.9734529638575924, 0.9103190222796415,
        0.9103060745023892, 1.4441972068492026]


def test_certified_answers_a_small_platform_as_precise_at_100_digits():
    cert = forward_kinematics(BASE, PLAT, LEGS, method="certified")
    ref = forward_kinematics(BASE, PLAT, LEGS, method="precise", dps=100)
    assert cert.certified and len(cert) == len(ref) == 4
    for c, p in zip(cert.poses, ref.poses):
        assert c.side == p.side
        assert abs(float(c.s15) - float(p.s15)) <= 1e-14 * abs(float(p.s15))
        assert np.abs(np.asarray(c.points, float) - np.asarray(p.points, float)).max() < 1e-13
    auto = forward_kinematics(BASE, PLAT, LEGS, method="auto")
    assert auto.certified or auto.tier == "fast"
    assert len(auto) == 4


def test_an_unproved_empty_fast_answer_does_not_state_a_fact():
    """QA 23d 4: the fast tier finds no root here (flagged, not proved) and said 'cannot
    be assembled: the octic has no real root', against the certified tier's 4 poses."""
    import warnings

    from distkin.errors import ConditioningWarning
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        fast = forward_kinematics(BASE, PLAT, LEGS)
    assert len(fast) == 0 and not fast.conditioning.trusted
    assert "cannot be assembled" not in fast.reason and "not proved" in fast.reason
    assert len(forward_kinematics(BASE, PLAT, LEGS, method="certified")) == 4
