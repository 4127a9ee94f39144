"""distkin.control.admittance.rotation_log (the virtual spring's orientation error, also
compiled for the control cycle) against scipy's Rotation.as_rotvec, an independent
implementation.  Review finding: a rotation by exactly π gave the zero vector (the
spring pulled with no torque), and within 1e-12 rad of π the axis came from rounding."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from distkin.control.admittance import rotation_log


def _same_rotation_vector(got, want, theta):
    if abs(theta - np.pi) < 1e-6:        # at π both ±π a are logarithms
        return min(np.abs(got - want).max(), np.abs(got + want).max())
    return np.abs(got - want).max()


def test_a_half_turn_about_x_is_pi_x():
    got = rotation_log(np.diag([1.0, -1.0, -1.0]))
    assert np.abs(np.abs(got) - [np.pi, 0, 0]).max() < 1e-15


@pytest.mark.parametrize("theta", [0.0, 1e-13, 0.3, np.pi / 2, np.pi / 2 + 1e-9, 2.5,
                                   np.pi - 1e-7, np.pi - 1e-13, np.pi])
def test_against_scipy_on_random_axes(theta):
    rng = np.random.default_rng(int(theta * 1e6) % 1000)
    worst = 0.0
    for _ in range(200):
        a = rng.normal(size=3)
        a /= np.linalg.norm(a)
        R = Rotation.from_rotvec(theta * a).as_matrix()
        worst = max(worst, _same_rotation_vector(rotation_log(R),
                                                 Rotation.from_matrix(R).as_rotvec(), theta))
    assert worst < 5e-15


def test_the_compiled_twin_is_the_same_function():
    from distkin.control.cycle_common import log_k
    rng = np.random.default_rng(3)
    for theta in (0.2, 2.0, np.pi - 1e-10, np.pi):
        a = rng.normal(size=3)
        R = Rotation.from_rotvec(theta * a / np.linalg.norm(a)).as_matrix()
        np.testing.assert_array_equal(log_k(R), rotation_log(R))
