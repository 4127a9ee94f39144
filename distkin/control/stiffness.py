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
from ..errors import InfeasibleError, InputError, SingularConfigurationError

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


def servo_stiffness(mech, kp: float, poses, directions=None) -> np.ndarray:
    """The compliance reading ``1/[K⁻¹]_ii`` of ``K = kp JᵀJ`` along x, y, z (N/m),
    shape (N, 3), at poses (N, 6) (module docstring); with ``directions`` (k, 3), unit
    vectors, the reading ``1/(dᵀ [K⁻¹]_tt d)`` along each, shape (N, k) (a wall's
    normal: :func:`.scene_checks.unit_slip_warnings`).

    Raises
    ------
    InfeasibleError
        A pose that a leg cannot reach (its Jacobian rows would be finite but
        meaningless: review, the stiffness 5 m above the Octo came out as 2.5 N/m).
    SingularConfigurationError
        A pose where ``JᵀJ`` is singular (rank < 6, or not finite): no finite
        stiffness along some direction, or none defined.
    """
    kp = positive_number(kp, "kp")
    P = np.atleast_2d(np.asarray(poses, dtype=float))
    if P.ndim != 2 or P.shape[1] != 6:
        raise InputError(f"expected poses of shape (6,) or (N, 6) (x, y, z, rx, ry, rz in "
                         f"m and rad), got shape {np.shape(poses)}", field="poses")
    ok = np.atleast_1d(mech.reachable(P))    # checks the shape and finiteness of poses
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise InfeasibleError(f"expected poses every leg reaches, got {int((~ok).sum())} "
                              f"of {ok.size} that do not, the first pose[{i}] = "
                              f"{np.round(P[i], 6).tolist()} (m, rad)", field="poses")
    J = mech.jacobian(P)
    with np.errstate(all="ignore"):
        s = np.linalg.svd(J, compute_uv=False) if np.all(np.isfinite(J)) else None
    if s is None or np.any(s[:, -1] <= 1e-12 * s[:, 0]):
        bad = (np.arange(len(P)) if s is None else np.flatnonzero(s[:, -1] <= 1e-12 * s[:, 0]))
        i = int(bad[0])
        raise SingularConfigurationError(
            f"expected poses where J has rank 6 (smallest/largest singular value above "
            f"1e-12), got a singular Jacobian at pose[{i}] = {np.round(P[i], 6).tolist()} "
            "(m, rad)", field="poses")
    C = np.linalg.inv(kp * np.swapaxes(J, -1, -2) @ J)
    if directions is None:
        return 1.0 / np.diagonal(C, axis1=-2, axis2=-1)[..., :3]
    D = np.atleast_2d(np.asarray(directions, dtype=float))
    return 1.0 / np.einsum("ki,nij,kj->nk", D, C[:, :3, :3], D)


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
