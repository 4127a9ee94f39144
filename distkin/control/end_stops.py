"""The mechanical end stops of the simulated device -- joint end stops and the legs'
reach limits -- as an inelastic impact in the kinetic-energy metric, solved as a
complementarity problem.

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

**Reach limits** are contacts of the same kind.  A crank leg closes where its reach
margin :math:`m_i = A^2 + B^2 - C^2` (:meth:`.kinematics.KinematicModel.margins`) is
positive; at :math:`m_i = 0` its distal link is stretched (or folded) in the crank's
plane, the leg's row of J is infinite (a serial singularity) and the link holds any
force along it without a torque: the platform cannot move further out, but it can slide
along that surface.  A step that ends beyond it takes the impulse of the same problem
with the row :math:`-\nabla m_i` (the margin's gradient over the pose displacement, by
central differences of :data:`FD_STEP`): the margin of none of those legs decreases,
``∇m_i · V' >= 0``.  A step may not end closer to the limit than about
:data:`REACH_GAP` (m; :func:`reach_floor`): the leg's row of J grows as
1/sqrt(distance), J̇V faster, and the plant's step, which takes the rotors' -J_r J̇V
explicitly, gains energy there from nothing (a step that starts or ends within
:data:`NEAR_FLOORS` floors, or meets a contact, is bounded by :func:`passive_twist`).
The curvature of the motion is corrected by putting such a leg a quarter of
:data:`REACH_GAP` (at the gradient there) above its floor, along the gradient, where the
last projection holds its normal rate at zero.  The metric changes fast near the limit
(the rotors' share grows as 1/distance), so the twist is scaled down, direction and contact
signs kept, where its energy at the pose the step ends at would exceed that after the
impact.  Joint stops and reach limits meet at the corners of the workspace: one problem
holds both kinds of rows.

Before (4295cbd and earlier), any joint end stop froze all six DOF: a platform pressed
against one crank's stop hung in the air instead of sliding along it.  Before 7d1b1cf
a reach limit still did: the Octo, which has no joint ranges, pushed by a
30 N hand with its drives off, froze in 826 of 3000 steps at x = 311 mm, held by nothing
but the freeze; the rus8 pressed against a stop next to a reach limit froze in up to 386
of 1000 steps; and a pose exactly on the limit made the next step divide by zero
(ZeroDivisionError out of the compiled step, the Octo pushed straight up to z = 468
mm).  The plant's own equations of motion are not these (Kühne et al. give none for
the stops); this is our model of a hard stop, stated here and in README.md.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STOP_GAP", "REACH_GAP", "NEAR_FLOORS", "TURN_FLOORS", "FD_STEP", "load_solver",
           "slide", "contact_impulse", "margin_gradients", "reach_floor", "passive_twist",
           "ReachApproach"]

#: how far inside its stop (rad, or m) :func:`slide` puts a joint that the curvature of
#: the motion carried past it (not onto it: rounding would leave it past)
STOP_GAP = 1e-12
#: how far inside its reach limit (m) a crank leg's step must end, to first order at
#: the home pose's gradient (:func:`reach_floor`; nearer where the margin's gradient is
#: steeper: ~5x nearer at the top of the Octo's reach).  The leg's row of J grows as
#: 1/sqrt(distance) towards the limit, J̇V faster, and the plant's step takes the rotors'
#: -J_r J̇V explicitly: at 1e-9 m a platform left there by a contact gained up to 5e4 J
#: in the next steps (review: the Octo, the Octopod and the Hunt pushed by 10-30 N with
#: the drives off), at 1e-5 m up to 3 J, at 1e-4 m up to 5 J on the Hunt only, less
#: than the old freezing plant's own steps near the limit (up to 222 J there); at 1e-3 m
#: a slide found no step within 2 L + 1 tries and froze (628 steps of one run)
REACH_GAP = 1e-4
#: how near its reach limit, in floors (:func:`reach_floor`), a crank leg makes the
#: plant's step check the energy it ends with (:func:`passive_twist`)
NEAR_FLOORS = 100.0
#: how near its reach limit, in floors, a crank leg whose margin a step turns from
#: falling to rising makes that step a contact (:class:`ReachApproach`)
TURN_FLOORS = 4.0
#: the pose step (m, rad) of the central differences of :func:`margin_gradients`
FD_STEP = 1e-6


def load_solver():
    """scipy.optimize.nnls, imported on first use (0.25 s: a plant whose legs have
    ranges or reach limits imports it when built, before any real-time loop starts)."""
    from scipy.optimize import nnls
    return nnls


def reach_floor(model, pose):
    """The least reach margin (L,) a step of the simulated device may end at (m²):
    :data:`REACH_GAP` times the length of the margin's gradient at ``pose`` (the plant
    passes its home pose) for a crank leg, so about REACH_GAP (m) from the limit to first
    order where the gradient is home's (nearer where it is steeper: ~5x at the top of
    the Octo's reach), -inf for a prismatic leg (its stroke is its end stop,
    :meth:`.kinematics.KinematicModel.closes`).  Below it a leg is at its reach limit
    (:func:`slide` puts it back a quarter of REACH_GAP above the floor)."""
    rev = np.asarray(model.revolute, dtype=bool)
    g = margin_gradients(model, pose)
    return np.where(rev, REACH_GAP * np.linalg.norm(g, axis=1), -np.inf)


def margin_gradients(model, pose, legs=slice(None)):
    """The gradients (k, 6) of the reach margins of the ``legs`` (L,) bool (all) at ``pose``
    over the pose displacement (v, ω)·dt of the plant's step (m² per m and per rad):
    central differences of :data:`FD_STEP`
    (:meth:`.kinematics.KinematicModel.margin_gradients`; the margins are polynomials in
    the pose, defined beyond the reach too)."""
    return model.margin_gradients(pose, FD_STEP)[legs]


def contact_impulse(model, M, joint_inertia: float, pose, V, rows):
    """The twist (6,) after the impulse ``Rᵀλ``, ``λ >= 0``, that leaves ``R V' <= 0``
    for every row of ``rows`` (k, 6) and removes the least kinetic energy (module doc),
    the metric taken at ``pose``; None where it is not finite.

    ``M`` (6, 6) the platform's mass matrix (kg, kg·m²), ``joint_inertia`` J_r (kg·m²
    at a crank, kg for a prismatic leg), ``V`` (6,) the twist before (m/s, rad/s).
    """
    J = model.jacobian(pose)
    try:
        C = np.linalg.cholesky(M + joint_inertia * (J.T @ J))
    except np.linalg.LinAlgError:
        return None
    G = np.linalg.solve(C, rows.T)
    d = C.T @ V
    if not (np.all(np.isfinite(G)) and np.all(np.isfinite(d))):
        return None
    try:
        lam = load_solver()(G, d)[0]
    except (RuntimeError, ValueError):       # no convergence (scipy's maxiter)
        return None
    out = np.linalg.solve(C.T, d - G @ lam)
    return out if np.all(np.isfinite(out)) else None


def _rows(model, pose, side, reach, G=None):
    """The contact rows at ``pose``: ``s_i J_i`` of the stopped joints (``side`` ±1),
    ``-∇m_i`` of the legs at their reach limits (``reach``; ``G`` the margins' gradients
    there when known)."""
    parts = []
    if np.any(side != 0.0):
        B = side != 0.0
        parts.append(model.jacobian(pose)[B] * side[B, None])
    if np.any(reach):
        G = margin_gradients(model, pose) if G is None else G
        parts.append(-G[reach])
    return np.vstack(parts)


def _state(model, pose, ex0, floor, lengths):
    """What a pose breaks: (reach, past, q, ok).  ``reach`` (L,): crank legs at their
    reach limits (margin below ``floor``, :func:`reach_floor`); ``past`` (L,): joints
    further past their ranges than ``ex0`` (only where every leg is within its reach: q
    means nothing beyond); ``ok``: the legs close (:meth:`ik`'s flag, or on an
    all-prismatic device every length positive)."""
    q, ok = model.ik(pose)
    reach = ~(model.margins(pose) >= floor)
    if reach.any() or not np.all(np.isfinite(q)):
        past = np.zeros(model.L, dtype=bool)
    else:
        past = model.range_excess(q) > ex0
    return reach, past, q, bool(ok or (lengths and model.closes(q)))


def slide(model, M, joint_inertia: float, rot, pose0, twist, pose1, dt: float, ex0,
          floor, *, lengths: bool = False):
    """The step from ``pose0`` again after an inelastic impact on the end stops and
    reach limits that its first try ``pose1`` passes (joints further past their ranges
    than their excesses ``ex0`` at ``pose0``, or crank legs whose margins fall below
    ``floor``, :func:`reach_floor`).

    ``twist`` (6,) is the step's twist before the impact, ``dt`` (s) its length,
    ``rot`` the pose rotation of the plant (``rotate_pose``, numpy or compiled; ``pose1``
    is ``rot(pose0, twist dt)``).  The impulse of :func:`contact_impulse` at ``pose0``,
    then the pose stepped with ``V'``; joints and legs that the new step passes join
    the contacts.  A contact that the curvature of the motion still carries past (second
    order in the step: a platform pressed against it) is put back by the least-squares
    pose displacement: a stopped joint :data:`STOP_GAP` inside where it was (``Jᴮ δx =
    -s (excess)``), a leg a quarter of :data:`REACH_GAP` above its floor at the gradient
    there (``∇m_i δx = floor_i + ¼ REACH_GAP |∇m_i| - m_i``; review: twice the floor put
    some legs 0.3-0.6 mm further in a step, where the gradient is shallower than at
    home), the other contacts' rows held at zero (one at a time, two stops pushed each
    other past in turn); legs beyond their reach first, with the joints' rows of J at
    ``pose0`` (J is not defined there).  The twist is then projected once more with the
    rows at the pose the step ends at (the rates of J at the impact are not those of
    the final pose; review: up to 0.077 J gained per contact step without).
    ``lengths``: the legs are all prismatic and close at any positive length (only the
    strokes refuse them, :meth:`.kinematics.KinematicModel.closes`).

    Returns (pose, twist, q), or None when no such step stays in reach and within the
    ranges in 2 L + 1 tries (the plant then stops where it was).
    """
    L = model.L
    side = np.zeros(L)
    rset = np.zeros(L, dtype=bool)
    pose, V, V0, J0 = pose1, twist, twist, None
    for it in range(2 * L + 1):
        reach, past, q, ok = _state(model, pose, ex0, floor, lengths)
        if not (reach.any() or past.any()):
            if not ok:
                return None
            break
        if it == 2 * L:                     # (the last correction checked, review)
            return None
        new_r, new_j = reach & ~rset, past & (side == 0.0)
        if new_r.any() or new_j.any():      # an impact: these joints and legs stop too
            rset |= new_r
            if new_j.any():
                side[new_j] = model.range_sides(q)[new_j]
                if not np.all(side[new_j]):
                    return None
            V = V0 = contact_impulse(model, M, joint_inertia, pose0, twist,
                                     _rows(model, pose0, side, rset))
            if V is None:
                return None
            pose = rot(pose0, V[:3] * dt, V[3:] * dt)
            continue
        # contacts drifted past: back, the others held
        B = side != 0.0
        if reach.any():                     # the legs first, the joints' rows of pose0
            if J0 is None:
                J0 = model.jacobian(pose0)
            g = margin_gradients(model, pose, rset)
            m = model.margins(pose)[rset]
            back = np.where(reach[rset], floor[rset] + 0.25 * REACH_GAP
                            * np.linalg.norm(g, axis=1) - m, 0.0)
            A = np.vstack([g, J0[B]])
            b = np.concatenate([back, np.zeros(int(B.sum()))])
        else:
            ex = model.range_excess(q)
            A = np.vstack([model.jacobian(pose)[B], margin_gradients(model, pose, rset)])
            b = np.concatenate([np.where(past, -side * (ex - ex0 + STOP_GAP), 0.0)[B],
                                np.zeros(int(rset.sum()))])
        dx = np.linalg.lstsq(A, b, rcond=None)[0]
        if not np.all(np.isfinite(dx)):
            return None
        pose = rot(pose, dx[:3], dx[3:])
    # the last projection: a leg still at its limit (margin within 4 floors) neither
    # leaves nor passes it in this step (rows +-∇m_i: its normal rate zero): near the
    # limit its row of J is ~1/sqrt(distance), and the normal rate the impulse at pose0
    # left, a separating one included, became a crank rate whose rotor energy was
    # hundreds of joules (the Octo pushed by 30 N: 300 J out of 0.8 J)
    G = margin_gradients(model, pose) if rset.any() else None
    rows = _rows(model, pose, side, rset, G)
    held = rset & (model.margins(pose) < 4.0 * floor)
    if held.any():
        rows = np.vstack([rows, G[held]])
    V = contact_impulse(model, M, joint_inertia, pose, V, rows)
    if V is None:
        return None
    # and no energy gained: the metric of the final pose is not that of the impact
    # (near a reach limit the rotors' share grows as 1/distance: after the projections
    # above the Octo's example still read 310 J against 0.87 J at the impact); the
    # twist keeps its direction, and so every contact row's sign
    e0, e1 = _energy(model, M, joint_inertia, pose0, V0), _energy(model, M, joint_inertia,
                                                                  pose, V)
    if e1 > e0:
        V = V * np.sqrt(e0 / e1)
    return pose, V, q


def passive_twist(model, M, joint_inertia: float, weight: float, pose0, V0, pose1, V1, *,
                  force, tau, V_step, dt: float):
    """The twist ``V1`` at the end of a step from (``pose0``, ``V0``) to ``pose1``,
    scaled down (direction kept) where the step would end with more energy -- kinetic,
    the rotors' included, and potential, ``weight`` (N) times the height -- than it
    started with plus the work of the hand's ``force`` (3,) N and the drives' efforts
    ``tau`` (L,) along the step's own motion ``V_step dt`` (the dynamics' twist, before
    any contact: a contact's put-back is no motion that forces work along; review: τ·Δq
    over one credited -5.9 J and +248 J).  The friction's loss is not counted, so the
    bound is loose by it; rounding (1e-12 of the energies) is not a gain.

    Near a reach limit the leg's row of J grows as 1/sqrt(distance) and J̇V faster; the
    plant's semi-implicit step takes the rotors' -J_r J̇V explicitly, and there it gains
    energy from nothing (review: up to 5e4 J in a step of the Octo with a 1 nm floor;
    1e4 J on the Octopod before this change, when the plant froze at the limit
    instead).  The plant calls this for a step that starts or ends within
    :data:`NEAR_FLOORS` floors of a limit, or meets a contact: elsewhere its steps are
    untouched."""
    J0 = model.jacobian(pose0)
    e0 = _energy(model, M, joint_inertia, pose0, V0, J0)
    work = dt * (float(np.asarray(force) @ V_step[:3]) + float(tau @ (J0 @ V_step)))
    cap = e0 + weight * (pose0[2] - pose1[2]) + work
    e1 = _energy(model, M, joint_inertia, pose1, V1)
    if e1 <= cap + 1e-12 * (e0 + abs(weight * pose0[2]) + abs(work)):
        return V1
    return V1 * np.sqrt(max(cap, 0.0) / e1)


class ReachApproach:
    """The approach of a reach limit that never reaches its floor, counted as a contact.

    Towards a crank leg's reach limit the leg's row of J grows as 1/sqrt(distance): the
    rotors' share of the kinetic energy grows as 1/distance, so the platform's motion
    towards the limit passes into the rotors and it slows down before the floor.  The
    plant's semi-implicit step, which takes the rotors' -J_r J̇V explicitly, dissipates
    that energy within the last few floors and turns the platform back there, the loss
    an inelastic contact at the floor would take (QA 2026-11-29: the Octo dropped from
    z = 0.3 m with its drives off lost 0.28 J, its whole fall, in 16 steps of 1 ms, the
    last 0.13 J in one, and :attr:`.plant.Plant.end_stop_hits` stayed 0 until it came
    to rest on the limit a second later).  A step that turns the margin of a leg within
    :data:`TURN_FLOORS` floors from falling (the step before) to rising counts as that
    contact: :meth:`turned_back`.  The margins are evaluated only for the steps near a
    limit (within :data:`NEAR_FLOORS` floors), one compiled call each."""

    def __init__(self):
        self.pose = self.end = self.rate = None

    def turned_back(self, model, pose0, pose1, near: bool, floor) -> bool:
        """Whether the step from ``pose0`` to ``pose1`` turned a leg back within
        :data:`TURN_FLOORS` floors ``floor`` (L,) of its limit (class doc); ``near``:
        the step starts or ends near a limit (else only the state is cleared).  The
        previous step's end is known by identity (the plant keeps the array it ended
        at): a pose set from outside starts a new approach."""
        if not near:
            self.pose = None
            return False
        m1 = model.margins(pose1)
        known = pose0 is self.pose
        m0 = self.end if known else model.margins(pose0)
        prev, rate = (self.rate if known else None), m1 - m0
        self.pose, self.end, self.rate = pose1, m1, rate
        if prev is None:
            return False
        turned = (prev < 0.0) & (rate > 0.0)
        return bool(turned.any()) and bool(np.any(np.minimum(m0, m1)[turned]
                                                  < TURN_FLOORS * floor[turned]))


def _energy(model, M, joint_inertia, pose, V, J=None):
    """The kinetic energy ½ Vᵀ (M + J_r JᵀJ) V at ``pose`` (J; ``J`` there if known)."""
    qd = (model.jacobian(pose) if J is None else J) @ V
    return 0.5 * float(V @ M @ V) + 0.5 * joint_inertia * float(qd @ qd)
