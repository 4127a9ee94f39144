"""The rotors' J̇V term up to the reach boundary (review): within one difference step
of the boundary it was set to zero, so a free platform coasted at constant twist while
the reflected inertia grew, and its energy rose 9-fold (up) and 17-fold (down) before
the end stop; now the one-sided difference on the reachable side keeps slowing it.
Reference: the energy ½VᵀMV + ½J_r|JV|² that the unforced, undamped plant conserves
(first order in the step away from the boundary, tests/control/test_plant_energy.py)."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.control.kinematics import load_model
from distkin.control.plant import Motors, Plant
from distkin.control.protocol import MODE_ZERO_TORQUE

FREE = Motors(friction=0.0, gravity=0.0, force_noise=0.0, torque_noise=0.0)


@pytest.mark.parametrize("vz", [0.3, -0.3])
def test_no_coasting_band_before_the_end_stop(vz):
    m = load_model("octo")
    p = Plant(m, FREE)
    p.twist = np.array([0, 0, vz, 0, 0, 0.0])

    def energy():
        J = m.jacobian(p.pose)
        return 0.5 * p.twist @ p.M @ p.twist + 0.5 * FREE.joint_inertia * np.sum((J @ p.twist) ** 2)
    E0, E, v = energy(), [], []
    for _ in range(2000):
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        if p.end_stop_hits:
            break
        E.append(energy() / E0)
        v.append(abs(p.twist[2]))
    assert p.end_stop_hits == 1
    # the speed keeps falling to the end (it was constant over the last steps)
    assert all(b < a for a, b in zip(v[-10:], v[-9:])), v[-10:]
    # the explicit step still gains energy where J diverges, but not 9- or 17-fold
    assert max(E) < 5.0, max(E)
