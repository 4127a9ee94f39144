"""Random reachable poses in the paper's workspace (Table II), for the RSS tests."""

from __future__ import annotations

import numpy as np

PRESET_NAMES = ("hunt", "hexa", "ergin", "octopod", "octo")


def reachable_poses(mech, n, *, seed=0, half_side=0.075, max_angle_deg=20.0, min_margin=1e-3):
    """``n`` random poses of the Table II workspace (cube of ±75 mm about z0, rotations
    up to ±20 deg about each axis) whose legs all close with a reach margin of at least
    ``min_margin`` m^2 (about 5 deg away from a leg's inverse singularity, where the
    IK derivative, and so a finite difference of it, blows up)."""
    rng = np.random.default_rng(seed)
    out = []
    while sum(len(o) for o in out) < n:
        P = np.empty((4 * n, 6))
        P[:, :3] = rng.uniform(-half_side, half_side, (4 * n, 3))
        P[:, 2] += mech.z0
        P[:, 3:] = np.radians(rng.uniform(-max_angle_deg, max_angle_deg, (4 * n, 3)))
        ok = mech.reach_margin(P).min(axis=1) >= min_margin
        out.append(P[ok])
    return np.concatenate(out)[:n]
