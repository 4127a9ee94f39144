"""distkin.spatial: the scalar and batched rotations agree, and so do the two forms of
Rodrigues' formula (each an independent route to the same matrix)."""

import math

import numpy as np

from distkin.spatial import (axis_angle, exp_so3, rotation_angles, rotation_matrix,
                             rotation_matrix_scalar)


def test_scalar_rotation_is_the_batched_one():
    r = np.random.default_rng(1).uniform(-1.2, 1.2, size=(50, 3))
    R = rotation_matrix(r)
    for i in range(len(r)):
        np.testing.assert_allclose(rotation_matrix_scalar(r[i]), R[i], rtol=0, atol=1e-15)
    np.testing.assert_allclose(rotation_angles(R), r, atol=1e-13)


def test_rz_ry_rx_analytic():
    # a quarter turn about z alone sends x to y: Rz(pi/2) = [[0,-1,0],[1,0,0],[0,0,1]]
    np.testing.assert_allclose(rotation_matrix_scalar([0, 0, math.pi / 2]),
                               [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-16)


def test_axis_angle_is_exp_of_the_rotation_vector():
    rng = np.random.default_rng(2)
    for _ in range(20):
        axis, angle = rng.normal(size=3), rng.uniform(-3, 3)
        w = axis / np.linalg.norm(axis) * angle
        np.testing.assert_allclose(axis_angle(axis, angle), exp_so3(w), atol=1e-14)


def test_rotation_angles_reproduce_the_matrix_at_and_near_gimbal_lock():
    """At ry = -pi/2 the angles lost the rotation about the locked axis (QA: R =
    [[0,-1,0],[0,0,-1],[1,0,0]] came back as ry = -pi/2 alone, 1.0 off).  Reference: the
    matrix itself (any angles that rebuild it are right there), and scipy's
    ``as_euler('xyz')`` away from the lock."""
    from scipy.spatial.transform import Rotation
    R = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    assert np.abs(rotation_matrix(rotation_angles(R)) - R).max() < 1e-15
    rng = np.random.default_rng(5)
    for sign in (1, -1):
        for eps in (1e-3, 1e-8, 1e-13, 0.0):
            ang = np.column_stack([rng.uniform(-3, 3, 500),
                                   sign * (np.pi / 2 - eps * rng.random(500)),
                                   rng.uniform(-3, 3, 500)])
            Rm = rotation_matrix(ang)
            assert np.abs(rotation_matrix(rotation_angles(Rm)) - Rm).max() < 1e-15
    Rr = Rotation.random(2000, random_state=7)
    got = rotation_angles(Rr.as_matrix())
    ok = np.cos(got[:, 1]) > 1e-3
    np.testing.assert_allclose(got[ok], Rr.as_euler("xyz")[ok], rtol=0, atol=1e-12)


# QA T 10: pose_to_matrix and pose_from refuse malformed poses with the field named, and a
# reflection is called one (det R = -1), not "deviations 0 and 0".
def test_pose_to_matrix_refuses_a_short_or_nonfinite_pose():
    import pytest
    from distkin.errors import InputError
    from distkin.spatial import pose_to_matrix
    with pytest.raises(InputError, match=r"shape \(\.\.\., 6\), got shape \(5,\)"):
        pose_to_matrix([0, 0, 0, 0, 0])
    with pytest.raises(InputError, match="finite"):
        pose_to_matrix([np.nan, 0, 0, 0, 0, 0])
    with pytest.raises(InputError, match="pose"):
        pose_to_matrix([0, 0, "x", 0, 0, 0])
    T = pose_to_matrix([[1.0, 2, 3, 0, 0, math.pi / 2]] * 2)      # batched, analytic Rz(90°)
    assert T.shape == (2, 4, 4)
    assert np.allclose(T[1], [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]],
                       atol=1e-15)


def test_pose_from_names_the_determinant_of_a_reflection():
    import pytest
    from distkin.errors import InputError
    from distkin.spatial import pose_from
    with pytest.raises(InputError, match=r"det R = -1 \(a reflection\)"):
        pose_from(np.diag([1.0, 1, -1, 1]))
    with pytest.raises(InputError, match=r"max\|R\^T R - I\| = 3, det R = 8"):
        pose_from(np.diag([2.0, 2, 2, 1]))
