"""The closure a revolute leg's kernels solve, and the certified tier encloses exactly,
is the expanded form of distkin.mechanisms.legs (|cos q u + sin q v| taken as 1), not
|P - D(q)| = l3 with the table's vectors as given; the two differ when a table's
(u, v) is orthonormal only to the table check's 1e-9 (QA fix-mech2: a certified ball
of radius 3e-18 rad lay 3.9e-10 rad from the literal closure's root, undocumented).
Reference: mpmath findroot at 50 digits on each closure, written out here from the
leg's fields (Kühne et al., eqs. (1)-(2)), and the documented difference."""

from __future__ import annotations

import dataclasses

import mpmath as mp
import numpy as np
import pytest

from distkin.mechanisms import LegMechanism, preset

STRETCH = 1 + 9e-10          # |u| of leg 1: within the table check's 1e-9


def _rot(r):
    cx, cy, cz = (mp.cos(v) for v in r)
    sx, sy, sz = (mp.sin(v) for v in r)
    return mp.matrix([[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
                      [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
                      [-sy, cy * sx, cy * cx]])


def _closures(leg, X):
    """(literal, expanded) closures of a revolute leg at the pose X as functions of q,
    in mpmath from the leg's exact binary numbers."""
    V = lambda t: mp.matrix([mp.mpf(float(c)) for c in t])      # noqa: E731
    x = [mp.mpf(float(c)) for c in X]
    w = V(x[:3]) + _rot(x[3:]) * V(leg.platform) - V(leg.base) - V(leg.offset)
    u, v, l1, l3 = V(leg.crank0), V(leg.crank90), mp.mpf(leg.crank), mp.mpf(leg.distal)
    dot = lambda a, b: mp.fsum(a[i] * b[i] for i in range(3))  # noqa: E731

    def literal(q):
        d = w - l1 * (mp.cos(q) * u + mp.sin(q) * v)
        return dot(d, d) - l3 ** 2

    def expanded(q):
        return dot(w, w) - 2 * l1 * (dot(w, u) * mp.cos(q) + dot(w, v) * mp.sin(q)) \
            + l1 ** 2 - l3 ** 2
    return literal, expanded


@pytest.fixture(scope="module")
def sloppy():
    d = preset("hunt").leg_description()
    legs = list(d.leg_table)
    legs[0] = dataclasses.replace(legs[0], crank0=tuple(np.array(legs[0].crank0) * STRETCH))
    return LegMechanism(d.name + " |u1| = 1 + 9e-10", tuple(legs), d.home_pose, d.mass,
                        d.inertia, d.scale, route="generated")


def test_certified_ball_encloses_the_expanded_closure_not_the_literal_one(sloppy):
    from flint import arb

    from distkin.mechanisms.kinematics_tiers import ik_tier
    from distkin.mechanisms.reference import NumericKernels
    X = sloppy.home + np.array([0.01, -0.02, 0.01, 0.1, -0.05, 0.2])
    q0 = NumericKernels(sloppy.leg_description()).ik(X[None])[0]
    res = ik_tier(sloppy, X, "certified")
    assert res.certified.all()
    with mp.workdps(50):
        for j, leg in enumerate(sloppy.leg_table):
            literal, expanded = _closures(leg, X)
            q_exp = mp.findroot(expanded, mp.mpf(float(q0[j])))
            q_lit = mp.findroot(literal, mp.mpf(float(q0[j])))
            assert res.values[0, j].overlaps(arb(mp.nstr(q_exp, 50), "1e-45"))
            if j == 0:                   # the documented difference, about 4e-10 rad
                assert 1e-10 < abs(q_exp - q_lit) < 1e-9
                assert not res.values[0, j].overlaps(arb(mp.nstr(q_lit, 50), "1e-45"))
            else:                        # a float-orthonormal frame: rounding only
                assert abs(q_exp - q_lit) < 1e-15
