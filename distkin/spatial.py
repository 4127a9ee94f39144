"""Spatial maths, the one place for it: rotations Rz·Ry·Rx (batched and scalar),
Rodrigues' formula, pose errors.  Poses of the RSS mechanisms, the certified workspace
and the controller are position plus fixed-axis x-y-z angles.

A pose is ``(x, y, z, rx, ry, rz)``: the end-effector centre in metres (base frame)
and the rotation

.. math:: R = R_z(r_z)\\, R_y(r_y)\\, R_x(r_x),

i.e. a rotation about the fixed base axis x by ``rx``, then about y by ``ry``, then
about z by ``rz`` (the "rotations around all axes" of Kühne et al., Table II).  The
parametrisation is singular at ``ry = ±pi/2``, far outside any RSS workspace.

The angular velocity is ``omega = E(r) @ rdot`` with
``E = [Rz Ry e_x | Rz e_y | e_z]`` (:func:`omega_map`); the Jacobian J maps
``(v, omega)``, the derivative of IK with respect to the pose parameters is
``J @ blockdiag(I, E)``.  Plain numpy, batched over leading axes; no sympy.  The
``*_scalar`` twins take one pose in plain floats (the controller's 1 ms cycle, where
numpy's per-call overhead on 3-vectors dominates); the symbolic twin is
:func:`distkin.mechanisms.symbolic.rotation_matrix` (sympy, for the derivations).

Interop: R = Rz(rz) Ry(ry) Rx(rx) equals scipy's
``Rotation.from_euler('xyz', [rx, ry, rz]).as_matrix()`` (lower-case 'xyz': extrinsic,
fixed axes; tests/test_spatial_interop.py).  :func:`pose_to_matrix` and
:func:`matrix_to_pose` convert to and from 4x4 homogeneous transforms,
:func:`pose_to_rotation` gives a scipy ``Rotation`` and the translation, and
:func:`pose_from` reads any of the three; every mechanism method that takes poses also
takes 4x4 matrices (:func:`distkin.mechanisms.description._poses`).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["rotation_matrix", "rotation_matrix_scalar", "rotation_angles", "rotation_defect",
           "omega_map", "omega_entries", "exp_so3", "rotate_pose_scalar", "axis_angle",
           "pose_error", "pose_to_matrix", "matrix_to_pose", "pose_to_rotation", "pose_from"]


def rotation_matrix(r):
    """R = Rz(rz) Ry(ry) Rx(rx).

    Parameters
    ----------
    r : array (..., 3), rad

    Returns
    -------
    array (..., 3, 3)
    """
    r = np.asarray(r, dtype=float)
    cx, cy, cz = np.cos(r[..., 0]), np.cos(r[..., 1]), np.cos(r[..., 2])
    sx, sy, sz = np.sin(r[..., 0]), np.sin(r[..., 1]), np.sin(r[..., 2])
    R = np.empty(r.shape[:-1] + (3, 3))
    R[..., 0, 0] = cz * cy
    R[..., 0, 1] = cz * sy * sx - sz * cx
    R[..., 0, 2] = cz * sy * cx + sz * sx
    R[..., 1, 0] = sz * cy
    R[..., 1, 1] = sz * sy * sx + cz * cx
    R[..., 1, 2] = sz * sy * cx - cz * sx
    R[..., 2, 0] = -sy
    R[..., 2, 1] = cy * sx
    R[..., 2, 2] = cy * cx
    return R


def rotation_matrix_scalar(r):
    """:func:`rotation_matrix` of one angle triple ``r`` (3,) rad in plain floats:
    R = Rz(rz) Ry(ry) Rx(rx), a (3, 3) array."""
    cx, cy, cz = math.cos(r[0]), math.cos(r[1]), math.cos(r[2])
    sx, sy, sz = math.sin(r[0]), math.sin(r[1]), math.sin(r[2])
    return np.array([[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
                     [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
                     [-sy, cy * sx, cy * cx]])


def rotation_angles(R):
    """Inverse of :func:`rotation_matrix`: (rx, ry, rz) with ry in [-pi/2, pi/2].

    Parameters
    ----------
    R : array (..., 3, 3)

    Returns
    -------
    array (..., 3), rad
    """
    R = np.asarray(R, dtype=float)
    ry = np.arctan2(-R[..., 2, 0], np.hypot(R[..., 2, 1], R[..., 2, 2]))
    rz = np.arctan2(R[..., 1, 0], R[..., 0, 0])
    # rx from the second row of Rz(rz)^T R = Ry Rx, which is (0, cos rx, -sin rx) for
    # every ry: consistent with the rz just found, also at and near ry = +-pi/2 (gimbal
    # lock: there R[1,0] = R[0,0] = 0 gives rz = 0, and rx takes the whole rotation
    # about the locked axis; atan2(R[2,1], R[2,2]) read atan2(0, 0) = 0 and lost it)
    cz, sz = np.cos(rz), np.sin(rz)
    rx = np.arctan2(sz * R[..., 0, 2] - cz * R[..., 1, 2], cz * R[..., 1, 1] - sz * R[..., 0, 1])
    return np.stack([rx, ry, rz], axis=-1)


def omega_map(r):
    """E(r) with omega = E @ rdot for R = Rz Ry Rx.

    Parameters
    ----------
    r : array (..., 3), rad

    Returns
    -------
    array (..., 3, 3)
    """
    r = np.asarray(r, dtype=float)
    E = np.zeros(r.shape[:-1] + (3, 3))
    rows = omega_entries(np.cos(r[..., 1]), np.sin(r[..., 1]), np.cos(r[..., 2]),
                         np.sin(r[..., 2]))
    for i in range(3):
        for j in range(3):
            E[..., i, j] = rows[i][j]
    return E


def omega_entries(cy, sy, cz, sz):
    """The rows of :func:`omega_map` from cos and sin of ry and rz, for any number type
    (floats, arrays, mpmath numbers, python-flint ``arb`` balls: the certified forward
    kinematics, :mod:`distkin.mechanisms.forward_tiers`): the columns are
    :math:`R_zR_y e_x`, :math:`R_z e_y`, :math:`e_z`."""
    return ((cz * cy, -sz, 0 * cz), (sz * cy, cz, 0 * cz), (-sy, 0 * cz, 0 * cz + 1))


def exp_so3(w):
    """Rotation matrix of the rotation vector ``w`` (..., 3) (Rodrigues' formula)."""
    w = np.asarray(w, dtype=float)
    th = np.linalg.norm(w, axis=-1)[..., None, None]
    K = np.zeros(w.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    small = th < 1e-8
    ths = np.where(small, 1.0, th)
    a = np.where(small, 1.0 - th ** 2 / 6.0, np.sin(ths) / ths)
    b = np.where(small, 0.5 - th ** 2 / 24.0, (1.0 - np.cos(ths)) / ths ** 2)
    return np.eye(3) + a * K + b * (K @ K)


def rotate_pose_scalar(pose, dpos, dw):
    """Pose (6,) moved by ``dpos`` (m, base frame) and rotated by the rotation vector
    ``dw`` (rad, base frame): ``R' = exp(dw) R`` (Rodrigues' formula).

    Plain-float arithmetic: for one 3x3 product this is several times faster than
    numpy's per-call dispatch.  It is the pose update of the single-pose Gauss-Newton
    (:func:`distkin.mechanisms.forward.gauss_newton`) and of the control loop's
    admittance and plant, and numba compiles this very function for the compiled
    control cycle (:mod:`distkin.control.cycle_kernels`).
    """
    wx, wy, wz = float(dw[0]), float(dw[1]), float(dw[2])
    th2 = wx * wx + wy * wy + wz * wz
    if th2 < 1e-16:
        a, b = 1.0 - th2 / 6.0, 0.5 - th2 / 24.0
    else:
        th = math.sqrt(th2)
        a, b = math.sin(th) / th, (1.0 - math.cos(th)) / th2
    # E = I + a K + b K^2, K = [w]x
    e00, e11, e22 = 1.0 - b * (wy * wy + wz * wz), 1.0 - b * (wx * wx + wz * wz), \
        1.0 - b * (wx * wx + wy * wy)
    e01, e10 = -a * wz + b * wx * wy, a * wz + b * wx * wy
    e02, e20 = a * wy + b * wx * wz, -a * wy + b * wx * wz
    e12, e21 = -a * wx + b * wy * wz, a * wx + b * wy * wz
    rx, ry, rz = float(pose[3]), float(pose[4]), float(pose[5])
    cx, cy, cz = math.cos(rx), math.cos(ry), math.cos(rz)
    sx, sy, sz = math.sin(rx), math.sin(ry), math.sin(rz)
    r00, r01, r02 = cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx
    r10, r11, r12 = sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx
    r20, r21, r22 = -sy, cy * sx, cy * cx
    # the entries of E R needed by the angle extraction (Rz Ry Rx convention)
    n00 = e00 * r00 + e01 * r10 + e02 * r20
    n10 = e10 * r00 + e11 * r10 + e12 * r20
    n20 = e20 * r00 + e21 * r10 + e22 * r20
    n21 = e20 * r01 + e21 * r11 + e22 * r21
    n22 = e20 * r02 + e21 * r12 + e22 * r22
    return np.array([pose[0] + dpos[0], pose[1] + dpos[1], pose[2] + dpos[2],
                     math.atan2(n21, n22), math.atan2(-n20, math.hypot(n21, n22)),
                     math.atan2(n10, n00)])


def axis_angle(axis, angle):
    """Rotation (3, 3) about ``axis`` (3,), any length, by ``angle`` rad (Rodrigues'
    formula; :func:`exp_so3` takes the rotation vector instead)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def pose_error(p1, p2):
    """Position error (m) and rotation angle between two poses (rad), each (...,).

    Parameters
    ----------
    p1, p2 : array (..., 6)
    """
    p1, p2 = np.asarray(p1, dtype=float), np.asarray(p2, dtype=float)
    dpos = np.linalg.norm(p1[..., :3] - p2[..., :3], axis=-1)
    Rrel = np.swapaxes(rotation_matrix(p1[..., 3:]), -1, -2) @ rotation_matrix(p2[..., 3:])
    tr = np.trace(Rrel, axis1=-2, axis2=-1)
    # angle from the skew part (accurate near 0) and the trace (accurate near pi)
    sk = np.stack([Rrel[..., 2, 1] - Rrel[..., 1, 2], Rrel[..., 0, 2] - Rrel[..., 2, 0],
                   Rrel[..., 1, 0] - Rrel[..., 0, 1]], axis=-1)
    ang = np.arctan2(0.5 * np.linalg.norm(sk, axis=-1), 0.5 * (tr - 1.0))
    return dpos, ang


# ---------------------------------------------------------------------- interop
def pose_to_matrix(pose):
    """The 4x4 homogeneous transform of poses (x, y, z, rx, ry, rz) (m, rad).

    ``T = [[R, t], [0, 1]]`` with R = Rz(rz) Ry(ry) Rx(rx) (:func:`rotation_matrix`) and
    t = (x, y, z): a point p of the end-effector frame is at ``T @ (p, 1)`` in the base
    frame.

    Parameters
    ----------
    pose : array (..., 6)

    Returns
    -------
    array (..., 4, 4)

    Examples
    --------
    >>> T = pose_to_matrix([0.1, 0.0, 0.3, 0.0, 0.0, np.pi / 2])
    >>> np.round(T @ [1.0, 0.0, 0.0, 1.0], 12).tolist()
    [0.1, 1.0, 0.3, 1.0]
    """
    X = _poses(pose)
    T = np.zeros(X.shape[:-1] + (4, 4))
    T[..., :3, :3] = rotation_matrix(X[..., 3:])
    T[..., :3, 3] = X[..., :3]
    T[..., 3, 3] = 1.0
    return T


def _poses(pose, field="pose"):
    """Poses (..., 6) as a finite float array, or InputError naming ``field`` (QA T 10)."""
    from .argcheck import as_floats
    from .errors import InputError
    X = as_floats(pose, field, "poses (x, y, z, rx, ry, rz) of shape (..., 6)")
    if X.shape[-1:] != (6,):
        raise InputError(f"expected poses (x, y, z, rx, ry, rz) of shape (..., 6), got shape "
                         f"{X.shape}", field=field)
    if not np.all(np.isfinite(X)):
        raise InputError("expected finite poses, got NaN or inf", field=field)
    return X


def rotation_defect(R):
    """How far matrices (..., 3, 3) are from rotations: ``(max|R^T R - I|, det R)``, the
    first over every matrix, the second per matrix (a rotation: 0 and +1; a reflection
    has det -1, a scaled rotation det != 1).  The one test of :func:`matrix_to_pose` and
    of the poses checked elsewhere (:mod:`distkin.delta.pose_input`)."""
    R = np.asarray(R, dtype=float)
    ortho = float(np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(initial=0.0))
    return ortho, np.linalg.det(R)


def matrix_to_pose(T, *, atol: float = 1e-9):
    """Poses (x, y, z, rx, ry, rz) of 4x4 homogeneous transforms (..., 4, 4); the inverse
    of :func:`pose_to_matrix` (ry in [-pi/2, pi/2]).

    Raises :class:`~distkin.errors.InputError` unless the last row is (0, 0, 0, 1) and
    the rotation block is orthonormal with determinant +1 (to ``atol``)."""
    from .errors import InputError
    T = np.asarray(T, dtype=float)
    if T.shape[-2:] != (4, 4):
        raise InputError(f"expected 4x4 homogeneous matrices, got shape {T.shape}",
                         field="pose")
    R = T[..., :3, :3]
    last = np.abs(T[..., 3, :] - [0.0, 0.0, 0.0, 1.0]).max(initial=0.0)
    ortho, det = rotation_defect(R)
    if not np.all(np.isfinite(T)):
        raise InputError("expected finite 4x4 matrices, got NaN or inf", field="pose")
    if not (last <= atol and ortho <= atol and np.all(det > 0)):
        dmin = float(np.min(det)) if np.size(det) else 1.0
        what = " (a reflection)" if dmin < 0 else ""
        raise InputError(f"expected a rigid transform (orthonormal R with max|R^T R - I| <= "
                         f"{atol:g}, det R = +1, last row 0 0 0 1), got max|R^T R - I| = "
                         f"{ortho:.3g}, det R = {dmin:.6g}{what} and last-row deviation "
                         f"{last:.3g}", field="pose")
    return np.concatenate([T[..., :3, 3], rotation_angles(R)], axis=-1)


def pose_to_rotation(pose):
    """(scipy ``Rotation``, translation (..., 3) m) of poses (..., 6).

    R = Rz(rz) Ry(ry) Rx(rx) is scipy's extrinsic ``Rotation.from_euler('xyz', [rx, ry,
    rz])`` (lower-case: rotations about the fixed axes x, then y, then z), which is what
    this function returns.

    Examples
    --------
    >>> rot, t = pose_to_rotation([0.0, 0.0, 0.3, 0.1, -0.2, 0.3])
    >>> bool(np.allclose(rot.as_matrix(), rotation_matrix([0.1, -0.2, 0.3]), atol=1e-15))
    True
    """
    from scipy.spatial.transform import Rotation
    X = np.asarray(pose, dtype=float)
    return Rotation.from_euler("xyz", X[..., 3:]), X[..., :3].copy()


def pose_from(value, translation=None):
    """Poses (..., 6) from any of: poses (..., 6); 4x4 homogeneous matrices (..., 4, 4);
    a scipy ``Rotation`` (one or many) with ``translation`` (..., 3) m.

    The angles are those of :func:`rotation_angles` (ry in [-pi/2, pi/2]), so a pose
    written with |ry| > pi/2 comes back as its equivalent."""
    from .errors import InputError
    if hasattr(value, "as_matrix") and hasattr(value, "as_euler"):
        if translation is None:
            raise InputError("expected a translation (x, y, z) with a scipy Rotation, got "
                             "none", field="pose")
        R = value.as_matrix()
        t = np.asarray(translation, dtype=float)
        if t.shape[-1:] != (3,):
            raise InputError(f"expected a translation of shape (..., 3), got {t.shape}",
                             field="translation")
        _finite(t, "translation")
        _finite(R, "rotation")                # a NaN quaternion (QA W 9)
        return np.concatenate(np.broadcast_arrays(t, rotation_angles(R)), axis=-1)
    if translation is not None:
        raise InputError("expected a translation only with a scipy Rotation, got one with "
                         f"{type(value).__name__}", field="translation")
    arr = np.asarray(value, dtype=float)
    if arr.shape[-2:] == (4, 4):
        return matrix_to_pose(arr)
    if arr.shape[-1:] != (6,):
        raise InputError(f"expected poses (..., 6), 4x4 matrices or a scipy Rotation, got "
                         f"shape {arr.shape}", field="pose")
    return _finite(arr, "pose")


def _finite(arr, field):
    """``arr`` when every entry is finite; else an InputError naming the first that is not."""
    from .errors import InputError
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        at = tuple(int(i) for i in bad[0])
        raise InputError(f"expected finite numbers, got {arr[at]} at index "
                         f"{at if len(at) != 1 else at[0]}", field=field)
    return arr
