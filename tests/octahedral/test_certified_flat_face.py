"""The certified tier at a face on the closure limit (a triangle inequality met with
equality): its answer against the exact pose it was built from.

P6 lies on the base edge P1P3 (u = 5/16 of the way), so the face P1 P3 P6 is flat and
the octic has a double root at the exact s15 = |P1P5|^2 = 859/128 (Rojas et al., ICRA
2012, Sec. III: two assembly modes meet; the tetrahedra of the bananas are flat there).
The certified tier answers from its exact path, whose points (P5 at an irrational
height) are balls: QA found them computed at the context's 53 bits, radii 2.4e-12
under an accuracy statement of "point radii <= 1.0e-15 x size".
"""

from __future__ import annotations

from fractions import Fraction as F

import flint
import numpy as np

from distkin.exact_roots import ball_ends
from distkin.octahedral import forward_kinematics

BASE = [[F(13, 8), F(-13, 16), 0], [F(13, 8), F(11, 16), 0], [F(25, 16), F(-5, 4), 0]]
TRUE = [[F(17, 16), F(29, 16), F(1, 16)], [F(-9, 16), F(9, 16), F(3, 16)], None]
TRUE[2] = [a + F(5, 16) * (c - a) for a, c in zip(BASE[0], BASE[2])]   # on P1P3
PAIRS = [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (0, 2)]


def _sq(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b))


def test_flat_face_poses_enclose_the_exact_pose_to_the_stated_radius():
    legs2 = [_sq(BASE[i], TRUE[j]) for i, j in PAIRS]
    legs = [f"sqrt({q.numerator}/{q.denominator})" for q in legs2]
    s15 = _sq(BASE[0], TRUE[1])
    assert s15 == F(859, 128)
    res = forward_kinematics([[str(c) for c in r] for r in BASE],
                             [[str(c) for c in r] for r in TRUE], legs, method="certified")
    (root,) = res.assembly_roots
    assert root.multiplicity == 2 and root.value == float(s15)
    assert len(res) == 2                              # the pose and its mirror
    sides2 = [_sq(TRUE[a], TRUE[b]) for a, b in ((0, 1), (0, 2), (1, 2))]
    size = float(max(legs2 + sides2 + [_sq(BASE[a], BASE[b])
                                       for a, b in ((0, 1), (0, 2), (1, 2))])) ** 0.5
    assert "point radii <= 1.0e-15 x size" in res.accuracy
    exact = np.array([[float(v) for v in row] for row in TRUE])
    (pose,) = [p for p in res if np.abs(p.points - exact).max() < 1e-9]
    for row, want in zip(pose.native["points"], TRUE):
        for ball, q in zip(row, want):
            lo, hi = ball_ends(flint.arb(ball))
            assert lo <= flint.fmpq(q.numerator, q.denominator) <= hi
            assert float(flint.arb(ball).rad()) <= 1e-15 * size     # the statement
    assert pose.radius <= 1e-15 * size
    assert np.abs(pose.points - exact).max() <= pose.radius
