"""Template of the per-mechanism compiled cycle kinematics (:mod:`.cycle_kernels`).

Not imported as such: :func:`.cycle_kernels.build` writes this text, under a header
and a footer that bind ``ik_k``, ``reach_k``, ``jac_k``, ``clo_k`` (one mechanism's
generated scalar kernels under numba) and the mechanism-independent compiled functions
of :mod:`.cycle_common` (the 6 x 6 solve, the pose update, the guard, the projection,
the wrenches, the drive model), into a module file of the derivation cache
(:mod:`distkin.sourcecache`), and compiles its functions there with
``numba.njit(cache=True)``: a file per mechanism is what lets numba keep the machine
code on disk.  Only what calls a kernel is here (IK, J, closure, the forward
kinematics, the fused cycle, the plant's step).  The functions write into preallocated
arrays.
"""

import math

import numpy as np

__all__ = ["ik", "reach", "reach_gradient", "jacobian", "closure", "forward", "cycle",
           "plant_dynamics", "jdot_v"]

#: bound by the header and footer of each copy
ik_k = reach_k = jac_k = clo_k = solve = rotate = rotate_wrench = project = None
normal_equations = _near_singular = _environment = _excess = None


def ik(pose, q):  # pragma: no cover (compiled)
    r = ik_k(pose)
    s = reach_k(pose)
    m = s[0]
    for i in range(len(r)):
        q[i] = r[i]
        if s[i] < m:                                     # Python's min(): first, then <
            m = s[i]
    return m >= 0.0


def reach(pose, m):  # pragma: no cover (compiled)
    s = reach_k(pose)
    for i in range(len(s)):
        m[i] = s[i]


def reach_gradient(pose, step, G):  # pragma: no cover (compiled)
    """The reach margins' gradients (L, 6) into ``G`` over the pose displacement (v, ω)
    that ``rotate`` applies: central differences of ``step`` (m, rad), as
    :meth:`.kinematics.KinematicModel.margin_gradients` computes them in Python."""
    L = G.shape[0]
    for k in range(6):
        d, w = np.zeros(3), np.zeros(3)
        if k < 3:
            d[k] = step
        else:
            w[k - 3] = step
        sp = reach_k(rotate(pose, d, w))
        sm = reach_k(rotate(pose, -d, -w))
        for i in range(L):
            G[i, k] = (sp[i] - sm[i]) / (2.0 * step)


def jacobian(pose, J):  # pragma: no cover (compiled)
    r = jac_k(pose)
    for i in range(len(r)):
        row = r[i]
        for j in range(6):
            J[i, j] = row[j]


def closure(q, pose, C):  # pragma: no cover (compiled)
    r = clo_k(q, pose)
    for i in range(len(r)):
        row = r[i]
        for j in range(7):
            C[i, j] = row[j]


def forward(q, guess, tol, max_iter, out):  # pragma: no cover (compiled)
    n = q.shape[0]
    C = np.empty((n, 7))
    A = np.empty((6, 6))
    b = np.empty(6)
    step = np.zeros(6)
    pose = guess.copy()
    for it in range(1, max_iter + 1):
        closure(q, pose, C)
        tot = 0.0
        for i in range(n):
            for j in range(7):
                tot += C[i, j]
        if not math.isfinite(tot):
            out[:] = pose
            return math.inf, it, False
        # normal equations (DᵀD) step = -Dᵀc, D = C[:, 1:]
        for i in range(6):
            s = 0.0
            for k in range(n):
                s += C[k, 1 + i] * C[k, 0]
            b[i] = -s
            for j in range(6):
                s = 0.0
                for k in range(n):
                    s += C[k, 1 + i] * C[k, 1 + j]
                A[i, j] = s
        if not solve(A, b, step):
            out[:] = pose
            return math.inf, it, False
        out[:] = rotate(pose, step[:3], step[3:])
        pose[:] = out
        ss = 0.0
        for i in range(6):
            ss += step[i] * step[i]
        if ss < tol * tol or it == max_iter:
            rr = 0.0
            for k in range(n):
                r = C[k, 0]
                for j in range(6):
                    r += C[k, 1 + j] * step[j]
                rr += r * r
            return math.sqrt(rr / n), it, ss < tol * tol
    return math.inf, max_iter, False


def cycle(q, ws, dt, started, run, guess, adm_pose, adm_twist, pd, prm, env, rng,
          out):  # pragma: no cover (compiled)
    """Steps 2-8 of :meth:`.controller.Controller.compute` in one call (the layouts of
    ``prm``, ``env``, ``pd`` and ``out`` are those of :func:`.cycle_kernels.cycle_params`).

    Returns 0 (set point accepted), 1 (FK failed), 2 (singular stop: at the measured
    pose, or at the last estimate when FK fails there), 3 (not in RUN:
    zero torque), 4 / 5 (candidate refused: unreachable / singular), 6 (the torque
    distribution's 6 × 6 system is singular).  ``pd`` (rows e_prev, d_prev, d_f, ∫e;
    ``pd[4, 0]`` 1 once e_prev holds an error) is updated in place.  ``rng`` (2, L): the
    joints' ranges (rad, modulo 2π; ±inf where a leg has none or a full turn): a
    candidate that takes a joint further outside them than the set point is is
    unreachable (:meth:`.controller.Controller.check_pose`).
    """
    L = q.shape[0]
    pose = out[0:6]
    w = out[6:12]
    apose = out[12:18]
    atwist = out[18:24]
    tau = out[24:24 + L]
    # 2. forward kinematics, warm-started
    mi = prm[1] if started else prm[2]
    res, it, conv = forward(q, guess, prm[0], int(mi), pose)
    out[24 + L] = res
    out[25 + L] = it
    out[26 + L] = 0.0
    if not conv or res > prm[3]:
        if started:           # near a singularity FK cannot converge: stop, as below
            J = np.empty((L, 6))
            jacobian(guess, J)
            if _near_singular(J, prm):
                for i in range(6):
                    pose[i] = guess[i]
                    apose[i] = adm_pose[i]
                    atwist[i] = adm_twist[i]
                rotate_wrench(pose[3:], ws, w)
                for i in range(L):
                    tau[i] = 0.0
                return 2
        return 1
    if not started:                                          # Controller.start_at
        for i in range(6):
            apose[i] = pose[i]
            atwist[i] = 0.0
        for k in range(4):
            for i in range(L):
                pd[k, i] = 0.0
        pd[4, 0] = 0.0
    else:
        for i in range(6):
            apose[i] = adm_pose[i]
            atwist[i] = adm_twist[i]
    # 3. the sensor wrench in the base frame; the guard at the measured pose
    rotate_wrench(pose[3:], ws, w)
    J = np.empty((L, 6))
    jacobian(pose, J)
    for i in range(L):
        tau[i] = 0.0
    if _near_singular(J, prm):
        return 2
    if not run:
        return 3
    # 3. admittance: semi-implicit Euler, a late frame's gap in steps of at most the
    # nominal period prm[35] (Admittance.propose, admittance.substeps)
    n = 1
    if prm[35] > 0.0 and dt > prm[35] * (1.0 + 1e-9):
        n = int(math.ceil(dt / prm[35] * (1.0 - 1e-9)))
    h = dt / n
    we = np.empty(6)
    tw = atwist.copy()
    cand = apose.copy()
    for _ in range(n):
        _environment(cand, tw, env, we)
        for i in range(6):
            wi = w[i] + we[i]
            tw[i] = tw[i] + h * (wi - prm[27 + i] * tw[i]) / prm[21 + i]
        cand = rotate(cand, tw[:3] * h, tw[3:] * h)
    # 4-5. refuse an unreachable or near-singular candidate (Controller.check_pose)
    qd = np.empty(L)
    code = 0
    ok = ik(cand, qd)
    out_of_range = False
    for i in range(L):
        if not math.isfinite(qd[i]):
            ok = False
        elif _excess(qd[i], rng[0, i], rng[1, i]) > 0.0:
            out_of_range = True
    if ok and out_of_range:          # refused where a joint's excess grows (check_pose)
        qc = np.empty(L)
        ik(apose, qc)
        for i in range(L):
            ec = _excess(qc[i], rng[0, i], rng[1, i])
            if not math.isfinite(ec):
                ec = 0.0
            if _excess(qd[i], rng[0, i], rng[1, i]) > ec:
                ok = False
    if not ok:
        code = 4
    else:
        Jc = np.empty((L, 6))
        jacobian(cand, Jc)
        if _near_singular(Jc, prm):
            code = 5
    if code:
        for i in range(6):                                   # Admittance.refuse
            atwist[i] = 0.0
        ik(apose, qd)
    else:
        for i in range(6):                                   # Admittance.commit
            apose[i] = cand[i]
            atwist[i] = tw[i]
    # 6. PD(I) with the forward-Euler filtered derivative (Controller.filter_derivative)
    T = prm[9]
    a = min(dt, prm[33]) / T if T > 0 else 0.0    # capped step (filter_derivative)
    for i in range(L):
        e = qd[i] - q[i]
        if prm[34] > 0.0:               # crank angles: the short way round (joint_step)
            e = (e + math.pi) % (2.0 * math.pi) - math.pi
        d_raw = 0.0 if pd[4, 0] == 0.0 else (e - pd[0, i]) / dt
        if T > 0:
            pd[2, i] = pd[2, i] + a * (pd[1, i] - pd[2, i])
        else:
            pd[2, i] = d_raw
        pd[1, i] = d_raw
        pd[0, i] = e
        tau[i] = prm[6] * e + prm[7] * pd[2, i]
        if prm[8] != 0.0:
            lim = prm[10] / prm[8]
            pd[3, i] = min(max(pd[3, i] + e * dt, -lim), lim)
            tau[i] = tau[i] + prm[8] * pd[3, i]
    pd[4, 0] = 1.0
    # 7. distribution and feed-forward
    wff = np.zeros(6)
    if prm[13] != 0.0:
        for i in range(6):
            wff[i] = -w[i]
    if prm[12] != 0.0:
        wff[2] += prm[14]
    if prm[11] != 0.0:
        t2 = np.empty(L)
        if not project(J, tau, wff, t2):
            return 6
        tau[:] = t2
    elif prm[12] != 0.0 or prm[13] != 0.0:
        t2 = np.empty(L)
        if not project(J, np.zeros(L), wff, t2):
            return 6
        for i in range(L):
            tau[i] = tau[i] + t2[i]
    # 8. saturation by one common factor
    peak = 0.0
    for i in range(L):
        peak = max(peak, abs(tau[i]))
    if peak > prm[10]:
        f = prm[10] / peak
        for i in range(L):
            tau[i] = tau[i] * f
        out[26 + L] = 1.0
    return code


def plant_dynamics(pose, twist, q, qdot, tau, hand, M, prm, floor,
                   out):  # pragma: no cover (compiled)
    """One semi-implicit Euler step of :meth:`.plant.Plant.step` after the drives:
    ``(M + j_r JᵀJ) V̇ = Jᵀ(tau - j_r J̇V - b q̇) + w_h + w_g``, the rotors' ``J̇V`` by
    :func:`jdot_v` with the pose step h.  ``prm`` = (b, m g, j_r, dt, h, lengths:
    1.0 where the strokes do not bound J̇V, :func:`_reaches`; wrap: 1.0 where the
    joints are crank angles; near: how many floors from its reach limit a crank leg
    counts as near it); ``floor`` (L,): the least reach margin a crank leg may end the
    step at (-inf for a prismatic leg: :meth:`.plant.Plant.reach_floor`); ``out``
    (13 + 2L,) = new pose, twist, q, the joint rates ``(q_new - q)/dt`` (cranks the
    short way round with wrap 1.0: :meth:`.kinematics.KinematicModel.joint_step`), and
    1.0 where a crank leg starts or ends the step near its reach limit.  False: a mechanical end stop
    (singular or unreachable); NaN where the step stopped before the IK."""
    L = q.shape[0]
    v = np.empty(L)
    jdot_v(pose, twist, prm[4], prm[5], v)
    for k in range(L):
        v[k] = (tau[k] + -prm[2] * v[k]) - prm[0] * qdot[k]
    J = np.empty((L, 6))
    jacobian(pose, J)
    w = np.empty(6)
    A = np.empty((6, 6))
    normal_equations(J, v, hand, A, w)
    for i in range(6):
        for j in range(6):
            A[i, j] = M[i, j] + prm[2] * A[i, j]
    w[2] -= prm[1]
    for i in range(6):
        ok = math.isfinite(w[i])
        for j in range(6):
            ok = ok and math.isfinite(A[i, j])
        if not ok:
            out[:] = np.nan
            return False
    a = np.linalg.solve(A, w)
    dt = prm[3]
    for i in range(6):
        out[6 + i] = twist[i] + dt * a[i]
    out[0:6] = rotate(pose, out[6:9] * dt, out[9:12] * dt)
    x = out[0:6]
    r = ik_k(x)
    s = reach_k(x)
    m = s[0]
    ok = True
    near = 0.0
    for k in range(L):
        out[12 + k] = r[k]
        if s[k] < m:
            m = s[k]
        if not s[k] >= floor[k]:    # at its reach limit, where J is infinite (and
            ok = False              # near it, where it outgrows the platform's mass)
        if s[k] < prm[7] * floor[k]:
            near = 1.0
    s0 = reach_k(pose)              # (or starts near: its J̇V is the start's)
    for k in range(L):
        if s0[k] < prm[7] * floor[k]:
            near = 1.0
    out[12 + 2 * L] = near
    ok = ok and m >= 0.0
    for k in range(L):
        if not math.isfinite(out[12 + k]):
            ok = False
        d = out[12 + k] - q[k]
        if prm[6] > 0.0:
            d = (d + math.pi) % (2.0 * math.pi) - math.pi
        out[12 + L + k] = d / dt
    return ok


def _reaches(x, q, lengths):  # pragma: no cover (compiled)
    """The legs at pose ``x`` close (joint values into ``q``): :func:`ik`'s flag, or
    with ``lengths`` (1.0: an all-prismatic device) every length finite and positive,
    whatever the strokes say (:meth:`.kinematics.KinematicModel.closes`)."""
    ok = ik(x, q)
    if ok or lengths == 0.0:
        return ok
    for k in range(q.shape[0]):
        if not (q[k] > 0.0 and q[k] < math.inf):
            return False
    return True


def _finite(J):  # pragma: no cover (compiled)
    """Every entry of J finite."""
    for i in range(J.shape[0]):
        for j in range(J.shape[1]):
            if not math.isfinite(J[i, j]):
                return False
    return True


def jdot_v(pose, twist, h, lengths, out):  # pragma: no cover (compiled)
    """``J̇ V`` (L,) into ``out``: :meth:`.plant.Plant.jdot_v` in one call (the same
    central difference of J over pose steps ``h`` either side along the twist, one-sided
    on the reachable side within a step of the reach boundary, zero where neither
    displaced pose is in reach -- ``lengths`` 1.0: where the legs close, strokes
    aside (:func:`_reaches`); the rotation and the kernels are the ones the Python
    route calls, the products summed in a fixed order)."""
    L = out.shape[0]
    nn = 0.0
    for i in range(6):
        nn += twist[i] * twist[i]
    if nn == 0.0:
        out[:] = 0.0
        return
    s = h / math.sqrt(nn)
    dv, dw = np.empty(3), np.empty(3)
    for i in range(3):
        dv[i], dw[i] = twist[i] * s, twist[3 + i] * s
    plus = rotate(pose, dv, dw)
    minus = rotate(pose, -dv, -dw)
    q = np.empty(L)
    Jp, Jm = np.empty((L, 6)), np.empty((L, 6))
    # (a displaced pose whose J is not finite, at a leg's reach limit, counts as out of
    # reach: its J would make J̇V infinite)
    ok_p = _reaches(plus, q, lengths)
    if ok_p:
        jacobian(plus, Jp)
        ok_p = _finite(Jp)
    ok_m = _reaches(minus, q, lengths)
    if ok_m:
        jacobian(minus, Jm)
        ok_m = _finite(Jm)
    if ok_p and ok_m:
        den = 2.0 * s
    elif ok_p:
        jacobian(pose, Jm)
        den = s
    elif ok_m:
        jacobian(pose, Jp)
        den = s
    else:
        out[:] = 0.0
        return
    for k in range(L):
        acc = 0.0
        for j in range(6):
            acc += (Jp[k, j] - Jm[k, j]) * twist[j]
        out[k] = acc / den
