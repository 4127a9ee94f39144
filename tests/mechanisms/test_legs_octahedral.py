"""A leg table with the octahedral topology: FK by the exact octic (Rojas et al., Sec.
VI, the Griffis-Duffy example of docs/design.md §5), chosen automatically."""

from __future__ import annotations

import math

import numpy as np
import pytest

from distkin.errors import GeometryWarning
from distkin.mechanisms.kinematics import LegMechanism
from distkin.octahedral import forward_kinematics as octic_fk
from distkin.spatial import pose_error, rotation_angles

S108, S27 = math.sqrt(108), math.sqrt(27)
BASE = [(0, 0, 0), (6, S108, 0), (12, 0, 0)]                # P1 P2 P3
PLAT = [(0, 0, 0), (6, 0, 0), (3, S27, 0)]                  # P4 P5 P6
LEGS = [19.8, 18, 18, 17, 14.9, 17.8]                       # P1P4 P2P4 P2P5 P3P5 P3P6 P1P6
PAIRS = [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (0, 2)]
SHUFFLE = [3, 0, 5, 1, 4, 2]                                # our table's leg order


def _mech():
    legs = [dict(type="SPS", base=BASE[PAIRS[k][0]], platform=PLAT[PAIRS[k][1]])
            for k in SHUFFLE]
    with pytest.warns(GeometryWarning, match="home is a singular pose|architecturally"):
        return LegMechanism("griffis-duffy", legs, (6, 6, 15, 0, 0, 0), 1.0, 1.0)


def test_topology_is_found_whatever_the_leg_order():
    topo = _mech().octahedral()
    assert topo is not None
    assert [SHUFFLE[i] for i in topo["order"]] == [0, 1, 2, 3, 4, 5]
    assert np.array_equal(topo["base"], np.array(BASE, float))
    assert np.array_equal(topo["platform"], np.array(PLAT, float))
    with pytest.warns(GeometryWarning, match="architecturally singular"):  # lines meet 2 lines
        six_six = LegMechanism("x", [dict(type="SPS", base=(i, 0, 0), platform=(0, i, 0))
                                     for i in range(6)], (0, 0, 1, 0, 0, 0))
    assert six_six.octahedral() is None


def test_fk_is_the_octic_mode_nearest_the_guess():
    """Every one of the 12 certified poses (6 real roots, docs/design.md §5) comes back
    when guessed near it, reproducing the legs to 1e-12."""
    m = _mech()
    q = np.array(LEGS)[SHUFFLE]
    ref = octic_fk(BASE, PLAT, LEGS, method="certified")
    assert len(ref) == 12
    X = np.array([np.concatenate([p.translation, rotation_angles(p.rotation)]) for p in ref])
    for x in X:
        fk = m.forward_kinematics(q, x + [0.05, -0.05, 0.05, 0.01, 0.0, -0.01])
        assert fk.converged and len(fk.modes) == 12 and "exact octic" in fk.message
        dp, da = pose_error(fk.pose, x)
        assert dp < 1e-9 and da < 1e-9
        assert np.allclose(m.inverse_kinematics(fk.pose)[0], q, rtol=1e-12)
    off = m.forward_kinematics(q, X[0] + [0.05, -0.05, 0.05, 0.01, 0.0, -0.01], octic=False)
    assert off.modes is None and pose_error(off.pose, X[0])[0] < 1e-9   # Gauss-Newton agrees


@pytest.mark.slow   # 10 s; batched = single solves: tests/octahedral/test_octahedral_signscan.py
def test_many_leg_sets_in_one_batched_call_equal_single_solves():
    """N > 1 leg sets go through forward_kinematics_batched: the same assembly modes
    (as sets, to 1e-12) and the same nearest pose as one octic solve per problem."""
    from distkin.mechanisms.octahedral_fk import octahedral_forward
    m = _mech()
    ref = octic_fk(BASE, PLAT, LEGS, method="certified")
    X = np.array([np.concatenate([p.translation, rotation_angles(p.rotation)]) for p in ref])
    rng = np.random.default_rng(3)
    poses = X[[0, 3, 7]] + rng.uniform(-0.02, 0.02, (3, 6))
    q = m.inverse_kinematics(poses)[0]
    guesses = poses + 0.01
    for method in ("fast", "auto"):
        near, modes, tiers = octahedral_forward(m, q, guesses, method=method)
        for n in range(3):
            one, one_modes, one_tier = octahedral_forward(m, q[n], guesses[n], method=method)
            assert tiers[n] == one_tier[0]
            assert modes[n].shape == one_modes[0].shape
            for x in one_modes[0]:                       # every mode of the single solve
                assert np.abs(modes[n] - x).max(axis=1).min() < 1e-12
            assert np.abs(near[n] - one).max() < 1e-12
            assert pose_error(near[n], poses[n])[0] < 1e-9
