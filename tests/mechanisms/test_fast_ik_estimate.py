"""The fast IK's error estimate is not exceeded (QA report M, finding 7: up to 2.8x on
random mixed leg tables).  Reference: a 40-digit mpmath solve of the closed form
A cos q + B sin q = C (legs module docstring), written out here from the leg table and
the pose's exact binary value, independently of the kernels."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from distkin.mechanisms import LegMechanism
from distkin.mechanisms.kinematics_tiers import ik_tier

from legs_sampling import random_legs


def _R(r):
    rx, ry, rz = (mp.mpf(float(a)) for a in r)
    Rx = mp.matrix([[1, 0, 0], [0, mp.cos(rx), -mp.sin(rx)], [0, mp.sin(rx), mp.cos(rx)]])
    Ry = mp.matrix([[mp.cos(ry), 0, mp.sin(ry)], [0, 1, 0], [-mp.sin(ry), 0, mp.cos(ry)]])
    Rz = mp.matrix([[mp.cos(rz), -mp.sin(rz), 0], [mp.sin(rz), mp.cos(rz), 0], [0, 0, 1]])
    return Rz * Ry * Rx


def _ik_mp(desc, X):
    """Per leg the candidate solutions (both branches) at 40 digits."""
    R, out = _R(X[3:]), []
    for leg in desc.leg_table:
        P = mp.matrix([mp.mpf(float(a)) for a in X[:3]]) + R * mp.matrix(list(leg.platform))
        w = P - mp.matrix([mp.mpf(b) + mp.mpf(o) for b, o in zip(leg.base, leg.offset)])
        if leg.prismatic:
            out.append([mp.sqrt(sum(x ** 2 for x in w))])
            continue
        A = sum(w[i] * leg.crank0[i] for i in range(3))
        B = sum(w[i] * leg.crank90[i] for i in range(3))
        C = (sum(x ** 2 for x in w) + mp.mpf(leg.crank) ** 2 - mp.mpf(leg.distal) ** 2) \
            / (2 * mp.mpf(leg.crank))
        rho = mp.sqrt(A * A + B * B)
        d = mp.acos(C / rho) if abs(C) <= rho else mp.nan
        out.append([mp.atan2(B, A) + d, mp.atan2(B, A) - d])
    return out


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_fast_ik_estimate_covers_mpmath(seed):
    desc = random_legs(seed)
    m = LegMechanism.from_description(desc, route="numpy")
    rng = np.random.default_rng(100 + seed)
    worst, checked = 0.0, 0
    with mp.workdps(40):
        for _ in range(60):
            X = desc.home + np.r_[rng.uniform(-0.03, 0.03, 3), rng.uniform(-0.25, 0.25, 3)]
            r = ik_tier(m, X, "fast")
            ref = _ik_mp(desc, X)
            for j in range(m.L):
                if not r.valid[0, j]:
                    continue
                err = min(float(abs((mp.mpf(r.q[0, j]) - c + mp.pi) % (2 * mp.pi) - mp.pi))
                          for c in ref[j])
                worst = max(worst, err / r.q_error[0, j])
                checked += 1
    assert checked > 200
    assert worst <= 1.0                     # estimate >= actual on every leg
