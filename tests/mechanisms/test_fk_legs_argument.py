"""``legs`` of the tiered forward kinematics as a numpy integer array (QA fix-mech2:
np.array([1, 2, 3, 4, 5, 7]) was refused, 'expected 6 distinct leg numbers 1..8, got
array([...])', though its numbers are the tuple's).  Reference: the same call with a
tuple of Python ints, and the pose whose inverse kinematics gave the angles."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.mechanisms import preset


@pytest.fixture(scope="module")
def octopod_case():
    m = preset("octopod")
    X = m.home + np.array([0.01, -0.005, 0.01, 0.1, 0.0, -0.05])
    return m, X, m.inverse_kinematics(X)[0]


@pytest.mark.parametrize("dtype", [np.int64, np.int32, np.uint8])
def test_integer_array_legs_as_the_tuple(octopod_case, dtype):
    m, X, q = octopod_case
    a = m.forward_kinematics(q, X, method="certified", legs=np.array([1, 2, 3, 4, 5, 7], dtype))
    b = m.forward_kinematics(q, X, method="certified", legs=(1, 2, 3, 4, 5, 7))
    assert a.legs == b.legs == (1, 2, 3, 4, 5, 7) and a.certified
    np.testing.assert_array_equal(a.pose, b.pose)
    assert np.all(np.abs(a.pose - X) <= a.error + 1e-13)   # angles from X: rounding only


@pytest.mark.parametrize("legs", [np.array([1.0, 2, 3, 4, 5, 7]), np.array([[1, 2, 3, 4, 5, 7]]),
                                  np.array([1, 2, 3, 4, 5, 9]), np.array([True] * 6)])
def test_other_arrays_refused(octopod_case, legs):
    m, X, q = octopod_case
    with pytest.raises(InputError, match="distinct leg numbers") as exc:
        m.forward_kinematics(q, X, method="certified", legs=legs)
    assert exc.value.field == "legs"
