"""Link interference of mechanisms given as leg tables (QA fix-mech2).  Before:
``interference(LegMechanism(...))`` raised AttributeError ('LegMechanism' object has no
attribute 'l2'); read through the RSS rules, a prismatic leg (its 'crank' a point at
its base joint) and legs sharing a joint (the octahedral manipulator, Rojas et al.
Fig. 4) would touch at 0 m at every pose; ``batch`` 0, negative or a float raised
ValueError, NameError or TypeError, a ``q`` of the wrong shape a numpy reshape error,
``clearance=True`` was taken as 1 m, and a 4x4 pose was refused.  Reference: dense
sampling of every pair of segments drawn from the joint points, with the joints a
pair shares found from the table's numbers."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.mechanisms import LegMechanism, preset
from distkin.mechanisms.interference import interference
from distkin.mechanisms.platforms import platform_mechanism


def _sampled(a0, a1, b0, b1, n=201):
    s = np.linspace(0.0, 1.0, n)[:, None]
    A, B = a0 + s * (a1 - a0), b0 + s * (b1 - b0)
    return float(np.min(np.linalg.norm(A[:, None] - B[None], axis=-1)))


@pytest.fixture(scope="module")
def octahedral():
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    return platform_mechanism((base, plat), unit=0.01, height=17)


def test_octahedral_legs_sharing_joints_are_attached_not_touching(octahedral):
    m = octahedral
    X = m.home + np.array([0.003, -0.002, 0.01, 0.05, -0.04, 0.1])
    pts = m.points(X)
    B, P = pts["B"], pts["P"]
    Bt = [tuple(leg.base) for leg in m.leg_table]
    Pt = [tuple(leg.platform) for leg in m.leg_table]
    # segments: legs B_k P_k, effector spokes x P_k, base spokes 0 B_k, each with the
    # joints at its ends named by body and frame coordinates (a spoke: the origin too)
    segs = [(B[k], P[k], {("b", Bt[k]), ("p", Pt[k])}, k) for k in range(6)]
    spokes = ([(X[:3], P[k], {("p", (0.0, 0.0, 0.0)), ("p", Pt[k])}, -1) for k in range(6)]
              + [(np.zeros(3), B[k], {("b", (0.0, 0.0, 0.0)), ("b", Bt[k])}, -1)
                 for k in range(6)])
    ref = np.inf
    for i, (a0, a1, ja, la) in enumerate(segs):
        for b0, b1, jb, lb in segs[i + 1:] + spokes:
            if not ja & jb:
                ref = min(ref, _sampled(a0, a1, b0, b1))
    r = interference(m, X)
    assert ref > 0.01                          # apart, though legs meet at their joints
    assert r.distance[0] <= ref + 1e-12 and ref - r.distance[0] < 1e-3


def test_leg_table_of_a_preset_is_its_rss_description():
    # the RSS description (offset l2 > 0 for the octo) and its leg table: one geometry
    for name in ("octo", "octopod"):
        m = preset(name)
        lm = LegMechanism.from_description(m.leg_description())
        X = np.array([m.home, m.home + [0.02, -0.01, 0.03, 0.1, 0.05, -0.1]])
        a, b = interference(m, X), interference(lm, X)
        np.testing.assert_allclose(a.distance, b.distance, rtol=1e-12)
        assert a.pair == b.pair


@pytest.mark.parametrize("kw", [dict(batch=0), dict(batch=-1), dict(batch=2.5),
                                dict(q=np.zeros(5)), dict(q=np.zeros((2, 6))),
                                dict(clearance=True)])
def test_bad_arguments_are_input_errors(kw):
    m = preset("hunt")
    with pytest.raises(InputError) as exc:
        interference(m, m.home, **kw)
    assert exc.value.field == next(iter(kw))


def test_pose_as_a_4x4_matrix():
    from distkin.spatial import pose_to_matrix
    m = preset("hunt")
    X = m.home + np.array([0.01, 0.0, -0.02, 0.1, 0.0, 0.2])
    assert interference(m, pose_to_matrix(X)).distance[0] == interference(m, X).distance[0]
