"""Servo stiffness of a joint-PD controlled device, against the prototype's measured one.

Kühne et al., Sec. III-D: "the stiffness of the prototype was determined [...] in 27
positions at zero rotations in the dexterous workspace [...] the center, the corners,
as well as the center of each facet and of each edge.  The minimum, maximum, and mean
stiffness were 1.6 N/mm along the x-axis, 7.9 N/mm along the z-axis, and 4.7 N/mm".

The joint PD with gain KP (N·m/rad) holds the set point like joint springs: a wrench
``w`` on the platform moves it by ``δx = K⁻¹ w`` with the Cartesian stiffness
``K = KP JᵀJ`` (J: q̇ = J (v, ω); L >= 6 legs).  Pushing along an axis with the other
directions free (a dial indicator on a free platform) reads ``1 / [K⁻¹]_ii`` (N/m): the
*compliance reading* here.  The model has only the servo: the structure, the gears and
the crank bearings of the prototype are rigid in it.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..argcheck import positive_number

__all__ = ["PAPER_STIFFNESS", "paper_positions", "servo_stiffness", "stiffness_summary"]

#: the prototype's measured stiffness, N/m: minimum (along x), maximum (along z), mean
PAPER_STIFFNESS = {"min": 1.6e3, "max": 7.9e3, "mean": 4.7e3}


def paper_positions(mech, half: float = 0.075) -> np.ndarray:
    """The 27 poses of the paper's experiment (27, 6): the centre, corners and the
    centres of the facets and edges of the dexterous-workspace cube of half-width
    ``half`` (m) about the mechanism's home, at zero rotation."""
    half = positive_number(half, "half")
    c = np.asarray(mech.home, dtype=float)
    out = [c + np.r_[np.array(d) * half, 0.0, 0.0, 0.0]
           for d in itertools.product((-1, 0, 1), repeat=3)]
    return np.array(out)


def servo_stiffness(mech, kp: float, poses) -> np.ndarray:
    """The compliance reading ``1/[K⁻¹]_ii`` of ``K = kp JᵀJ`` along x, y, z (N/m),
    shape (N, 3), at poses (N, 6) (module docstring)."""
    kp = positive_number(kp, "kp")
    J = mech.jacobian(np.atleast_2d(np.asarray(poses, dtype=float)))
    K = kp * np.swapaxes(J, -1, -2) @ J
    C = np.linalg.inv(K)
    return 1.0 / np.diagonal(C, axis1=-2, axis2=-1)[..., :3]


def stiffness_summary(mech, kp: float, half: float = 0.075) -> dict:
    """Minimum, maximum and mean of :func:`servo_stiffness` over the paper's 27
    positions and the three axes (N/m), the axes of the extremes, the value at the
    centre, and the paper's measured figures (:data:`PAPER_STIFFNESS`)."""
    P = paper_positions(mech, half)
    k = servo_stiffness(mech, kp, P)
    axes = "xyz"
    imin, imax = np.unravel_index(np.argmin(k), k.shape), np.unravel_index(np.argmax(k),
                                                                           k.shape)
    return {"min": float(k.min()), "min_axis": axes[imin[1]],
            "min_position": (P[imin[0], :3] - np.asarray(mech.home)[:3]).tolist(),
            "max": float(k.max()), "max_axis": axes[imax[1]],
            "mean": float(k.mean()), "centre": k[13].tolist(),  # (0, 0, 0): 9 + 3 + 1
            "paper": PAPER_STIFFNESS,
            "unit": "N/m"}
