"""Poses from three points and back (distkin.geometry.poses), in the three tiers, against
analytic rotations (Rodrigues' formula) and each other."""

from __future__ import annotations

from fractions import Fraction

import flint
import mpmath
import numpy as np
import pytest

from distkin.errors import DegenerateGeometryError
from distkin.geometry import points_from_pose, pose_from_points, triangle_frame


def _rodrigues(axis, angle):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def test_round_trip_batched_fast():
    rng = np.random.default_rng(5)
    q = rng.normal(size=(3, 3))
    R = np.stack([_rodrigues(rng.normal(size=3), rng.uniform(0, np.pi)) for _ in range(50)])
    t = rng.normal(size=(50, 3)) * 10
    p = points_from_pose(R, t, q)
    assert p.shape == (50, 3, 3)
    assert np.allclose(p, np.einsum("nij,kj->nki", R, q) + t[:, None], atol=1e-13)
    R2, t2 = pose_from_points(q, p)
    assert np.allclose(R2, R, atol=1e-12) and np.allclose(t2, t, atol=1e-11)


def test_mirror_image_of_a_planar_triangle_gives_a_proper_rotation():
    q = np.array([[0.0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
    R0 = _rodrigues([1, 2, 3], 0.7)
    p = q @ R0.T + [1, 2, 5]
    mirrored = p * [1, 1, -1]                      # reflection in z = 0
    R, t = pose_from_points(q, mirrored)
    assert np.isclose(np.linalg.det(R), 1.0) and np.allclose(R @ R.T, np.eye(3))
    assert np.allclose(q @ R.T + t, mirrored, atol=1e-12)


def test_precise_and_certified_tiers():
    q = [[0, 0, 0], [2, 0, 0], [0, 1, 0]]
    R0 = np.round(_rodrigues([0, 0, 1], np.pi / 2))   # exactly x -> y, y -> -x
    p = [[Fraction(int(round(v))) for v in row] for row in (np.array(q) @ R0.T + [1, 1, 1])]
    with mpmath.workdps(40):
        Rp, tp = pose_from_points([[mpmath.mpf(v) for v in r] for r in q],
                                  [[mpmath.mpf(v.numerator) for v in r] for r in p],
                                  method="precise")
        assert max(abs(Rp[i][j] - R0[i, j]) for i in range(3) for j in range(3)) < 1e-35
    fq = [[flint.fmpq(v) for v in r] for r in q]
    fp = [[flint.fmpq(v.numerator, v.denominator) for v in r] for r in p]
    Rc, tc = pose_from_points(fq, fp, method="certified")
    for i in range(3):
        for j in range(3):
            assert Rc[i][j].contains(flint.arb(int(round(R0[i, j]))))
        assert tc[i].contains(1)
    back = points_from_pose(Rc, tc, fq, method="certified")
    assert all(back[r][c].contains(fp[r][c]) for r in range(3) for c in range(3))


def test_frame_is_orthonormal_and_degenerate_triangles_are_refused():
    F = triangle_frame(np.array([[1.0, 2, 3], [4, 0, 1], [2, 2, 2]]))
    assert np.allclose(F.T @ F, np.eye(3)) and np.isclose(np.linalg.det(F), 1)
    with pytest.raises(DegenerateGeometryError):
        triangle_frame(np.array([[0.0, 0, 0], [1, 1, 1], [2, 2, 2]]))
    with pytest.raises(DegenerateGeometryError):
        triangle_frame([[0, 0, 0], [1, 1, 1], [2, 2, 2]], method="certified")
