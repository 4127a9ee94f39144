"""Thin and collinear base or platform triangles (QA N 1, 2).

float64 refuses a triangle with 16 area^2 / (sum of squared sides)^2 <= 1e-12; the
exact tiers refuse only a collinear one.  A batched fast solve flags a thin problem
(verdict 11) instead of losing every other problem's answer; ``auto`` hands it to the
certified tier.  References: the pose the legs were generated from, legs recomputed from
each pose in mpmath (50 digits), the precise tier's count (a second route), and a
second batched solve without the thin problem (bit for bit)."""

import warnings

import mpmath as mp
import numpy as np
import pytest

from distkin.errors import ConditioningWarning, DegenerateGeometryError
from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.descartes import THIN_TRIANGLE

BASE = np.array([[0.0, 0, 0], [1, 0, 0], [0.3, 1, 0]])
THIN = [[0, 0, 0], [0.7, 0, 0], [0.35, "1/10000000", 0]]        # apex 1e-7 above P4 P5
FAT = np.array([[0.0, 0, 0], [0.7, 0, 0], [0.2, 0.6, 0]])
LEGS_OF = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


def _legs(pose_points):
    allp = np.vstack([BASE, pose_points])
    return [float(np.linalg.norm(allp[i - 1] - allp[j - 1])) for i, j in LEGS_OF]


# the thin platform placed 0.8 above the base: its legs
PLACED = np.array([[0.1, 0.2, 0.8], [0.8, 0.2, 0.8], [0.45, 0.2 + 1e-7, 0.8]])
LEGS = _legs(PLACED)


def _mp_leg_error(points, legs):
    with mp.workdps(50):
        allp = [[mp.mpf(float(x)) for x in r] for r in np.vstack([BASE, points])]
        return max(abs(mp.sqrt(sum((a - b) ** 2 for a, b in zip(allp[i - 1], allp[j - 1])))
                       - mp.mpf(l)) / mp.mpf(l) for (i, j), l in zip(LEGS_OF, legs))


def test_exact_tiers_solve_a_thin_platform_that_float64_refuses():
    with pytest.raises(DegenerateGeometryError, match="hint: method='auto'"):
        forward_kinematics(BASE, THIN, LEGS)
    cert = forward_kinematics(BASE.tolist(), THIN, LEGS, method="certified")
    auto = forward_kinematics(BASE.tolist(), THIN, LEGS, method="auto")
    prec = forward_kinematics(BASE.tolist(), THIN, LEGS, method="precise", dps=40)
    assert len(cert) == len(auto) == len(prec) > 0
    assert auto.tier == "certified" and "fast tier refused" in auto.tier_reason
    for p in cert.poses:
        assert _mp_leg_error(p.points, LEGS) < 1e-12
    # the generating placement is one of the poses (up to the legs' rounding)
    gaps = [np.max(np.abs(p.points - PLACED)) for p in cert.poses]
    assert min(gaps) < 1e-6


def test_a_thin_problem_is_flagged_and_the_others_keep_their_answers():
    bases = np.array([BASE, BASE, BASE])
    plats = np.array([np.array([[0, 0, 0], [0.7, 0, 0], [0.35, 1e-7, 0]]), FAT, FAT])
    legs = np.array([LEGS, _legs(np.array([[0.1, 0.1, 0.9], [0.8, 0.1, 0.9], [0.3, 0.7, 0.9]])),
                     LEGS])
    with pytest.warns(ConditioningWarning, match="thinner than float64 resolves"):
        b = forward_kinematics_batched(bases, plats, legs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        alone = forward_kinematics_batched(bases[1:], plats[1:], legs[1:])
    assert b.verdict[0] == THIN_TRIANGLE and not b.trusted[0] and b.count[0] == 0
    assert not b.valid[0].any() and np.isnan(b.s15[0]).all()
    for name in ("count", "s15", "points", "valid", "verdict"):
        np.testing.assert_array_equal(getattr(b, name)[1:], getattr(alone, name))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        a = forward_kinematics_batched(bases, plats, legs, method="auto")
    single = forward_kinematics(BASE.tolist(), THIN, LEGS, method="certified")
    assert a.tier[0] == "certified" and a.count[0] == len(single)


def test_a_collinear_triangle_is_refused_exactly_and_per_problem():
    line = [[0, 0, 0], [0.7, 0, 0], [0.35, 0, 0]]
    with pytest.raises(DegenerateGeometryError, match="16 area\\^2 = 0 exactly"):
        forward_kinematics(BASE.tolist(), line, LEGS, method="certified")
    irr = [[0, 0, 0], ["sqrt(2)", 0, 0], ["sqrt(3)", 0, 0]]      # (sqrt3 - sqrt2)^2
    with pytest.raises(DegenerateGeometryError, match="within 1e-60"):
        forward_kinematics(BASE.tolist(), irr, LEGS, method="precise")
    fine = [[0, 0, 0], ["sqrt(2)", 0, 0], ["sqrt(3)", "1/1000", 0]]
    forward_kinematics(BASE.tolist(), fine, LEGS, method="precise")   # not refused
    with pytest.warns(ConditioningWarning, match="could not decide 1 of 2"):
        a = forward_kinematics_batched(np.array([BASE, BASE]),
                                       np.array([np.array(line, float), FAT]),
                                       np.array([LEGS, LEGS]), method="auto")
    assert 0 in a.unresolved and "collinear" in a.unresolved[0]
    assert a.count[1] == forward_kinematics(BASE, FAT, LEGS).__len__()


def test_a_ratio_below_float64_resolution_is_not_printed_as_its_rounding():
    """A base 12 long whose apex is 1e-9 off the line: 16 area^2 / (sum of squared
    sides)^2 is about 1.8e-20 (exactly, with fractions, below), which Heron's form in
    float64 computes as 0; the message printed "= 0" (QA R 6), the same as for a
    coincident pair.  Now it says "<= 1e-15" for both, never a value float64 cannot
    tell."""
    from fractions import Fraction as F
    pts = [(F(0), F(0)), (F(6), F(1, 10 ** 9)), (F(12), F(0))]
    sq = [(p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2
          for p, q in ((pts[0], pts[1]), (pts[1], pts[2]), (pts[2], pts[0]))]
    a, b, c = sq
    exact = (2 * (a * b + b * c + c * a) - (a * a + b * b + c * c)) / (a + b + c) ** 2
    assert 1e-21 < exact < 1e-19
    for base in ([[0, 0, 0], [6, "1e-9", 0], [12, 0, 0]],
                 [[0, 0, 0], [0, 0, 0], [12, 0, 0]]):
        with pytest.raises(DegenerateGeometryError) as e:
            forward_kinematics(base, FAT, [1.0] * 6)
        msg = str(e.value)
        assert "<= 1e-15, below what float64 resolves" in msg and "= 0" not in msg
