"""Joint end stops of the simulated device: an inelastic impact in the kinetic-energy
metric, solved as a complementarity problem.

A step of :class:`.plant.Plant` that takes joints further past their ranges (a crank's
arc modulo 2π, a prismatic leg's stroke: :meth:`.kinematics.KinematicModel.range_state`)
meets their end stops.  The stopped joints B, each at one end of its range (side
``s_i = ±1``, read from the range: :func:`.kinematics.range_side`, not from the sign of
a raw difference, which flips where a crank passes ±180°), take the impulse
``Jᴮᵀ S λ`` with ``λ >= 0`` (a stop pushes, it does not pull) that leaves none of them
moving outward, ``S Jᴮ V' <= 0``, and removes the least kinetic energy:

.. math:: V' = V - M_e^{-1} J_B^T S λ, \\quad M_e = \\hat M + J_r J^T J

(the metric of the plant's kinetic energy ``½ Vᵀ M̂ V + ½ J_r |J V|²``,
:mod:`.plant`).  With ``M_e = C Cᵀ`` and ``G = C⁻¹ Jᴮᵀ S`` this is the non-negative
least squares problem ``min |G λ - Cᵀ V|`` over ``λ >= 0`` (its optimality conditions
are the complementarity conditions above; the residual is ``Cᵀ V'``), solved by
scipy.optimize.nnls.  Only joints whose excess grows meet their stops: one already
past its range moving back inward is free.

Before (4295cbd and earlier), any joint end stop froze all six DOF: a platform pressed
against one crank's stop hung in the air instead of sliding along it.  The plant's own
equations of motion are not these (Kühne et al. give none for the stops); this is our
model of a hard stop, stated here and in README.md.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STOP_GAP", "load_solver", "slide", "stop_impulse"]

#: how far inside its stop (rad, or m) :func:`slide` puts a joint that the curvature of
#: the motion carried past it (not onto it: rounding would leave it past)
STOP_GAP = 1e-12


def load_solver():
    """scipy.optimize.nnls, imported on first use (0.25 s: a plant whose legs have
    ranges imports it when built, before any real-time loop starts)."""
    from scipy.optimize import nnls
    return nnls


def stop_impulse(model, M, joint_inertia: float, pose, V, side):
    """The twist (6,) after the end-stop impulse of the joints whose ``side`` is ±1 at
    ``pose`` (module doc), or None where it is not finite.

    ``M`` (6, 6) the platform's mass matrix (kg, kg·m²), ``joint_inertia`` J_r (kg·m²
    at a crank, kg for a prismatic leg), ``V`` (6,) the twist before (m/s, rad/s).
    """
    J = model.jacobian(pose)
    try:
        C = np.linalg.cholesky(M + joint_inertia * (J.T @ J))
    except np.linalg.LinAlgError:
        return None
    B = side != 0.0
    G = np.linalg.solve(C, (J[B] * side[B, None]).T)
    d = C.T @ V
    if not (np.all(np.isfinite(G)) and np.all(np.isfinite(d))):
        return None
    try:
        lam = load_solver()(G, d)[0]
    except (RuntimeError, ValueError):       # no convergence (scipy's maxiter)
        return None
    out = np.linalg.solve(C.T, d - G @ lam)
    return out if np.all(np.isfinite(out)) else None


def slide(model, M, joint_inertia: float, rot, pose0, twist, q, dt: float, ex0, *,
          lengths: bool = False):
    """The step again after an inelastic impact on the end stops that ``q`` (L,)
    passes further than the joints did at ``pose0`` (their excesses ``ex0``).

    ``twist`` (6,) is the step's twist before the impact, ``dt`` (s) its length,
    ``rot`` the pose rotation of the plant (``rotate_pose``, numpy or compiled).  The
    impulse of :func:`stop_impulse` at ``pose0``, then the pose stepped with ``V'``;
    joints that the new step passes join B.  A stopped joint that the curvature of the
    motion still carries past its stop (second order in the step: a platform pressed
    against the stop) is put back by the least-squares pose displacement
    ``Jᴮ δx = -s (excess)`` (:data:`STOP_GAP` inside where it was; the other stopped
    joints' rows held at zero: one at a time, two stops pushed each other past in
    turn), and the twist is projected once more with J at the pose the step ends at
    (the rates of J at the impact are not those of the final pose; review: up to
    0.077 J gained per contact step without).  ``lengths``: the legs are all
    prismatic and close at any positive length (only the strokes refuse them,
    :meth:`.kinematics.KinematicModel.closes`).

    Returns (pose, twist, q), or None when no such step stays in reach and within the
    ranges (all joints stopped, or a stop meeting a leg's reach limit: the plant then
    stops where it was).
    """
    L = model.L
    side = np.zeros(L)
    pose = V = None
    for it in range(2 * L + 1):
        ex = model.range_excess(q)
        past = ex > ex0
        if not past.any():
            break
        if it == 2 * L:                     # (the last correction checked, review)
            return None
        new = past & (side == 0.0)
        if new.any():                       # an impact: these joints stop too
            side[new] = model.range_sides(q)[new]
            V = stop_impulse(model, M, joint_inertia, pose0, twist, side)
            if V is None or not np.all(side[new]):
                return None
            pose = rot(pose0, V[:3] * dt, V[3:] * dt)
        else:                               # stopped joints drifted past: back
            B = side != 0.0
            back = np.where(past, -side * (ex - ex0 + STOP_GAP), 0.0)
            dx = np.linalg.lstsq(model.jacobian(pose)[B], back[B], rcond=None)[0]
            pose = rot(pose, dx[:3], dx[3:])
        q, ok = model.ik(pose)
        if not (ok or (lengths and model.closes(q))) or not np.all(np.isfinite(q)):
            return None
    V = stop_impulse(model, M, joint_inertia, pose, V, side)
    return None if V is None else (pose, V, q)
