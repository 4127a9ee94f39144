"""Helpers of the performance-index tests (poses drawn independently of the code under
test)."""

import numpy as np


def random_reachable_poses(mech, n, rot_deg, seed):
    """``n`` random poses of ``mech`` inside the Table II box (±75 mm about z0,
    ±rot_deg about every axis) at which every leg closes."""
    rng = np.random.default_rng(seed)
    out = []
    while sum(len(o) for o in out) < n:
        P = np.c_[rng.uniform(-0.075, 0.075, (4 * n, 3)) + [0, 0, mech.z0],
                  np.deg2rad(rng.uniform(-rot_deg, rot_deg, (4 * n, 3)))]
        _, valid = mech.inverse_kinematics(P)
        out.append(P[valid.all(axis=1)])
    return np.concatenate(out)[:n]


def rel_err(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300))
