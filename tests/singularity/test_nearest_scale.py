"""The nearest singular pose is scale-invariant (QA V 4): the same octahedral
manipulator and pose written at length scales 1e-11 .. 1e4 give the same distance / L
(the search runs in units of L).  Reference: the same query at scale 1, and det J of
the normalised Plücker lines (eq. (5)) recomputed here with numpy at the pose found."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.singularity import nearest_singularity, rotation_from_vector

S3 = np.sqrt(3)
BASE = np.array([[0, 0, 0], [6, 6 * S3, 0], [12, 0, 0]], dtype=float)
PLAT = np.array([[0, 0, 0], [6, 0, 0], [3, 3 * S3, 0]], dtype=float)
LEGS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


def _det_j(base, plat, R, t, L):
    """det J of eq. (5) with numpy: rows (u, b x u / L), batched over poses."""
    P = np.einsum("...ij,nj->...ni", R, plat) + t[..., None, :]
    rows = []
    for b, p in LEGS:
        bb = np.broadcast_to(base[b - 1], P[..., p - 4, :].shape)
        u = P[..., p - 4, :] - bb
        u = u / np.linalg.norm(u, axis=-1)[..., None]
        rows.append(np.concatenate([u, np.cross(bb, u) / L], axis=-1))
    return np.linalg.det(np.stack(rows, axis=-2))


def _search(f_scale):
    base, plat = BASE * f_scale, PLAT * f_scale
    L = 2 * S3 * f_scale                                  # the platform's circumradius
    R0 = rotation_from_vector(np.radians([170, 20, 5]))
    t0 = np.array([1, 2, 10]) * f_scale
    ns = nearest_singularity(lambda R, t: _det_j(base, plat, R, t, L), R0, t0, L)
    return ns, base, plat, L


@pytest.mark.parametrize("f_scale", [1e-11, 1e-6, 1e4])
def test_distance_over_L_does_not_depend_on_the_length_unit(f_scale):
    ref, *_ = _search(1.0)
    ns, base, plat, L = _search(f_scale)
    assert ref.converged and ns.converged                 # QA V 4: not converged at 1e-11
    assert ns.distance / L == pytest.approx(ref.distance / (2 * S3), rel=1e-9)
    assert ns.first_order / L == pytest.approx(ref.first_order / (2 * S3), rel=1e-9)
    assert abs(_det_j(base, plat, ns.rotation, ns.translation, L)) < 1e-9
