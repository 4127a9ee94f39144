"""The mechanism-independent parts of the compiled control cycle (:mod:`.cycle_kernels`).

The cycle of each mechanism is compiled from :mod:`.cycle_wrappers` over that
mechanism's generated kernels, in a file of its own (numba keeps machine code per source
file).  What does not call a kernel lives here instead and is compiled once per machine
for every mechanism: the singular values of the scaled Jacobian, the normal equations
and the torque projection, the sensor wrench into the base frame, the spring and wall
wrenches of the admittance's environment, the singularity guard and the drive model
(their formulas as they were in the template; the same float operations in the same
order, so the same bits).  Compiling them once instead of per mechanism saves about
3-4 s of the first start of every further mechanism on a machine (BENCHMARKS.md,
control, "First start", and run (35)).

Imported by the generated cycle files only (it imports numba).
"""

import math

import numba
import numpy as np

from ..spatial import rotate_pose_scalar
from .admittance import rotation_log, spring_torque
from .cycle_kernels import jitted
from .kinematics import _rot, range_excess

__all__ = ["singular_values", "normal_equations", "project", "rotate_wrench",
           "spring_wrench", "near_singular", "environment", "drive", "solve", "rot_k",
           "log_k", "torque_k", "excess_k", "rotate", "readings"]

_jit = numba.njit(cache=True)

#: the 6 x 6 solve (Gaussian elimination, partial pivoting), the rotation matrix of
#: (rx, ry, rz), its logarithm and the pose update: each compiled once
solve = jitted("solve")
rot_k = _jit(_rot)
log_k = _jit(rotation_log)
torque_k = _jit(spring_torque)
excess_k = _jit(range_excess)
rotate = _jit(rotate_pose_scalar)


def singular_values(J, S):  # pragma: no cover (compiled)
    n = J.shape[0]
    for k in range(n):
        for j in range(6):
            if not math.isfinite(J[k, j]):
                return math.nan, math.nan
    G = np.empty((6, 6))
    for i in range(6):
        for j in range(6):
            s = 0.0
            for k in range(n):
                s += (J[k, i] / S[i]) * (J[k, j] / S[j])
            G[i, j] = s
    ev = np.linalg.eigvalsh(G)
    return math.sqrt(max(ev[0], 0.0)), math.sqrt(max(ev[5], 0.0))


def normal_equations(J, v, w, A, b):  # pragma: no cover (compiled)
    """``A = JᵀJ`` (6, 6) and ``b = Jᵀv + w`` (6,) for J (n, 6), v (n,), w (6,)."""
    n = J.shape[0]
    for i in range(6):
        s = 0.0
        for k in range(n):
            s += J[k, i] * v[k]
        b[i] = s + w[i]
        for j in range(6):
            s = 0.0
            for k in range(n):
                s += J[k, i] * J[k, j]
            A[i, j] = s


def project(J, tau, w, out):  # pragma: no cover (compiled)
    n = J.shape[0]
    A = np.empty((6, 6))
    b = np.empty(6)
    x = np.empty(6)
    normal_equations(J, tau, w, A, b)
    if not solve(A, b, x):
        return False
    for k in range(n):
        s = 0.0
        for j in range(6):
            s += J[k, j] * x[j]
        out[k] = s
    return True


def rotate_wrench(r, w, out):  # pragma: no cover (compiled)
    """``out = (R f, R m)`` for R = Rz Ry Rx of ``r`` (3,) rad, ``w = (f, m)``."""
    R = rot_k(r)
    for k in range(2):
        for i in range(3):
            out[3 * k + i] = (R[i, 0] * w[3 * k] + R[i, 1] * w[3 * k + 1]
                              + R[i, 2] * w[3 * k + 2])


def spring_wrench(pose, twist, p0, R0t, k, d, out):  # pragma: no cover (compiled)
    """``out = (-k e_p, spring_torque(e_r, k_r)) - d twist``, ``e = (p - p0,
    log(R(pose) R0ᵀ))`` (Spring.wrench)."""
    t = torque_k(log_k(rot_k(pose[3:]) @ R0t), k[3:])
    for i in range(3):
        out[i] = -k[i] * (pose[i] - p0[i]) - d[i] * twist[i]
        out[3 + i] = t[i] - d[3 + i] * twist[3 + i]


def _near_singular(J, prm):  # pragma: no cover (compiled)
    """Controller.near_singular: σmin(J S⁻¹) < sigma_min or cond > max_condition.

    Decided without the eigenvalues where that is possible: with G = (J S⁻¹)ᵀ(J S⁻¹),
    σmin < s ⟺ G - s² I is not positive definite (its Cholesky factorisation meets a
    pivot <= 0), and when σmin >= s, σmax² <= trace G <= (max_condition s)² rules out
    the condition test; otherwise the eigenvalues decide (:func:`singular_values`).
    The same decisions up to rounding at the thresholds themselves."""
    n = J.shape[0]
    S = prm[15:21]
    for k in range(n):
        for j in range(6):
            if not math.isfinite(J[k, j]):
                return True
    s2 = prm[4] * prm[4]
    A = np.empty((6, 6))
    tr = 0.0
    for i in range(6):
        for j in range(i + 1):
            s = 0.0
            for k in range(n):
                s += (J[k, i] / S[i]) * (J[k, j] / S[j])
            A[i, j] = s
        tr += A[i, i]
        A[i, i] -= s2
    for j in range(6):                                     # Cholesky of G - s² I
        d = A[j, j]
        for k in range(j):
            d -= A[j, k] * A[j, k]
        if not d > 0.0:
            return True
        d = math.sqrt(d)
        A[j, j] = d
        for i in range(j + 1, 6):
            s = A[i, j]
            for k in range(j):
                s -= A[i, k] * A[j, k]
            A[i, j] = s / d
    c = prm[5] * prm[4]
    if tr <= c * c:
        return False
    lo, hi = singular_values(J, S)
    return lo < prm[4] or hi > prm[5] * lo


def _environment(pose, twist, env, w):  # pragma: no cover (compiled)
    """w = Σ wrench of each Spring / Wall row of ``env``, in the scene's order."""
    for i in range(6):
        w[i] = 0.0
    M = np.empty((3, 3))
    e = np.empty(6)
    for r in range(env.shape[0]):
        row = env[r]
        if row[0] == 0.0:                                    # Spring.wrench
            R = rot_k(pose[3:])
            for a in range(3):
                for b in range(3):
                    M[a, b] = (R[a, 0] * row[4 + b] + R[a, 1] * row[7 + b]
                               + R[a, 2] * row[10 + b])
            t = torque_k(log_k(M), row[16:19])
            for i in range(3):
                e[i] = -row[13 + i] * (pose[i] - row[1 + i]) - row[19 + i] * twist[i]
                e[3 + i] = t[i] - row[22 + i] * twist[3 + i]
        else:                                                # Wall.wrench
            for i in range(6):
                e[i] = 0.0
            d = row[1] * pose[0] + row[2] * pose[1] + row[3] * pose[2] - row[4]
            if d > 0.0:
                nv = row[1] * twist[0] + row[2] * twist[1] + row[3] * twist[2]
                f = row[5] * d + row[6] * max(nv, 0.0)
                for i in range(3):
                    e[i] = -max(f, 0.0) * row[1 + i]
        for i in range(6):
            w[i] += e[i]


def drive(tau, qdot, stall, w_nl, out):  # pragma: no cover (compiled)
    """:meth:`.plant.Plant.drive`: ``out`` the torques the drives deliver (N·m); True
    if any was limited."""
    sat = False
    for i in range(tau.shape[0]):
        t = tau[i]
        motoring = np.sign(t) == np.sign(qdot[i])
        avail = stall
        if motoring:
            avail = stall * min(max(1.0 - abs(qdot[i]) / w_nl, 0.0), 1.0)
        o = min(max(t, -avail), avail)
        out[i] = o
        if o != t:
            sat = True
    return sat


def readings(q, resolution, pose, hand_wrench, noise, out):  # pragma: no cover (compiled)
    """:meth:`.plant.Plant.encoders` then :meth:`.plant.Plant.sensor` into ``out``
    (L + 6,): the quantised joint values, and the hand wrench in the platform frame
    (Rᵀ w by rows, summed in index order) plus ``noise``."""
    L = q.shape[0]
    for i in range(L):
        out[i] = np.rint(q[i] / resolution) * resolution
    R = rot_k(pose[3:])
    for i in range(3):
        f = 0.0
        m = 0.0
        for j in range(3):
            f += R[j, i] * hand_wrench[j]
            m += R[j, i] * hand_wrench[3 + j]
        out[L + i] = f + noise[i]
        out[L + 3 + i] = m + noise[3 + i]


singular_values = _jit(singular_values)
normal_equations = _jit(normal_equations)
project = _jit(project)
rotate_wrench = _jit(rotate_wrench)
spring_wrench = _jit(spring_wrench)
near_singular = _jit(_near_singular)
environment = _jit(_environment)
drive = _jit(drive)
readings = _jit(readings)
