"""Template of the per-mechanism compiled cycle kinematics (:mod:`.cycle_kernels`).

Not imported as such: :func:`.cycle_kernels.build` writes this text, under a header
that binds ``ik_k``, ``reach_k``, ``jac_k``, ``clo_k`` (one mechanism's generated scalar
kernels under numba), ``solve`` and ``rotate``, into a module file of the derivation
cache (:mod:`distkin.sourcecache`), and compiles its functions there with
``numba.njit(cache=True)``: a file per mechanism is what lets numba keep the machine
code on disk.  The functions write into preallocated arrays.
"""

import math

import numpy as np

__all__ = ["ik", "jacobian", "closure", "forward", "singular_values", "project",
           "rotate_wrench", "spring_wrench"]

#: bound by the footer of each copy
ik_k = reach_k = jac_k = clo_k = solve = rotate = rot_k = log_k = None


def ik(pose, q):  # pragma: no cover (compiled)
    r = ik_k(pose)
    s = reach_k(pose)
    m = s[0]
    for i in range(len(r)):
        q[i] = r[i]
        if s[i] < m:                                     # Python's min(): first, then <
            m = s[i]
    return m >= 0.0


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


def project(J, tau, w, out):  # pragma: no cover (compiled)
    n = J.shape[0]
    A = np.empty((6, 6))
    b = np.empty(6)
    x = np.empty(6)
    for i in range(6):
        s = 0.0
        for k in range(n):
            s += J[k, i] * tau[k]
        b[i] = s + w[i]
        for j in range(6):
            s = 0.0
            for k in range(n):
                s += J[k, i] * J[k, j]
            A[i, j] = s
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
    """``out = -k e - d twist``, ``e = (p - p0, log(R(pose) R0ᵀ))`` (Spring.wrench)."""
    v = log_k(rot_k(pose[3:]) @ R0t)
    for i in range(3):
        out[i] = -k[i] * (pose[i] - p0[i]) - d[i] * twist[i]
        out[3 + i] = -k[3 + i] * v[i] - d[3 + i] * twist[3 + i]
