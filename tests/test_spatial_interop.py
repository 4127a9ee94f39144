"""Poses as 4x4 homogeneous matrices and scipy Rotations (distkin.spatial interop)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from distkin.errors import InputError
from distkin.mechanisms import preset
from distkin.spatial import (matrix_to_pose, pose_from, pose_to_matrix, pose_to_rotation,
                             rotation_matrix)

angles = st.floats(-3.0, 3.0)


@settings(max_examples=200, deadline=None)
@given(rx=angles, ry=st.floats(-1.5, 1.5), rz=angles)
def test_rz_ry_rx_is_scipy_extrinsic_xyz(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx) equals Rotation.from_euler('xyz', [rx, ry, rz]) and, written
    out, the product of scipy's single-axis rotations in that order."""
    R = rotation_matrix(np.array([rx, ry, rz]))
    assert np.allclose(R, Rotation.from_euler("xyz", [rx, ry, rz]).as_matrix(), atol=1e-15)
    single = [Rotation.from_euler(a, v).as_matrix() for a, v in zip("xyz", (rx, ry, rz))]
    assert np.allclose(R, single[2] @ single[1] @ single[0], atol=1e-15)


def test_round_trips_matrix_rotation_pose():
    rng = np.random.default_rng(1)
    X = np.hstack([rng.normal(size=(50, 3)), rng.uniform(-1.5, 1.5, (50, 3))])
    T = pose_to_matrix(X)
    assert T.shape == (50, 4, 4) and np.allclose(T[:, 3], [0, 0, 0, 1])
    assert np.allclose(matrix_to_pose(T), X, atol=1e-13)
    rot, t = pose_to_rotation(X)
    assert np.allclose(pose_from(rot, t), X, atol=1e-13)
    assert np.allclose(pose_from(T), X, atol=1e-13) and pose_from(X) is not None
    p = np.array([0.01, -0.02, 0.03])                       # a platform point
    assert np.allclose((T[7] @ np.append(p, 1))[:3], rot[7].apply(p) + t[7], atol=1e-15)


def test_mechanisms_take_matrices_and_return_them():
    m = preset("octo")
    X = np.array([[0.01, -0.02, 0.31, 0.1, -0.05, 0.2], [0.0, 0.01, 0.29, 0.0, 0.1, 0.0]])
    T = pose_to_matrix(X)
    for meth in ("jacobian", "reach_margin", "pose_jacobian"):
        assert np.allclose(getattr(m, meth)(T), getattr(m, meth)(X), rtol=1e-12, atol=1e-14)
        assert np.allclose(getattr(m, meth)(T[0]), getattr(m, meth)(X[0]), rtol=1e-12,
                           atol=1e-14)
    q, _ = m.inverse_kinematics(T)
    fk = m.forward_kinematics(q, m.home)
    assert np.allclose(fk.matrix, T, atol=1e-12)
    rot, t = fk.rotation
    assert np.allclose(rot.as_matrix(), T[:, :3, :3], atol=1e-12) and np.allclose(t, X[:, :3])


@pytest.mark.parametrize("bad", [np.eye(4) * 2, np.diag([1, 1, -1, 1.0]), np.ones((3, 3))])
def test_bad_matrices_refused(bad):
    with pytest.raises(InputError):
        pose_from(bad)


def test_rotation_needs_translation():
    with pytest.raises(InputError, match="translation"):
        pose_from(Rotation.identity())


@pytest.mark.parametrize("pose, where", [([0, 0, np.nan, 0, 0, 0], "nan at index 2"),
                                         ([[0] * 6, [0, 0, 1, np.inf, 0, 0]],
                                          r"inf at index \(1, 3\)")])
def test_non_finite_poses_refused(pose, where):
    """fix-v's leftover: a plain 6-value pose with a NaN passed through ``pose_from``
    (a 4x4 matrix with one was refused).  Now both are, naming the entry."""
    with pytest.raises(InputError, match=where):
        pose_from(pose)
    with pytest.raises(InputError, match="translation.*nan at index 1"):
        pose_from(Rotation.identity(), [0, np.nan, 0])
    with pytest.raises(InputError, match="rotation.*nan"):           # QA W 9
        pose_from(Rotation.from_rotvec([np.nan, 0, 0]), [0, 0, 1])
