"""Helpers of the performance-index tests (poses drawn independently of the code under
test)."""

import itertools

import mpmath as mp
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


def mp_slice_sensitivity(J, S, dps):
    """The farthest point of the slice of {J# p : |p|∞ <= 1} at zero S^c part (Kühne et
    al. eqs. (14), (16)), J# = (JᵀJ)⁻¹Jᵀ, over the C(L, 3)·2^(L−3) vertex candidates, in
    mpmath at ``dps`` digits (a vertex within 10^-(dps-20) of the box counts)."""
    L = J.shape[0]
    Sc = [i for i in range(6) if i not in S]
    with mp.workdps(dps):
        Jm = mp.matrix(J.tolist())
        P = mp.inverse(Jm.T * Jm) * Jm.T
        best = mp.mpf(0)
        for free in itertools.combinations(range(L), 3):
            fixed = [j for j in range(L) if j not in free]
            A = mp.matrix([[P[i, j] for j in free] for i in Sc])
            for sg in itertools.product((-1, 1), repeat=L - 3):
                b = mp.matrix([-sum(P[i, fixed[k]] * sg[k] for k in range(L - 3))
                               for i in Sc])
                try:
                    x = mp.lu_solve(A, b)
                except ZeroDivisionError:
                    continue
                if max(abs(v) for v in x) > 1 + mp.mpf(10) ** -(dps - 20):
                    continue
                q = [0] * L
                for k, j in enumerate(fixed):
                    q[j] = sg[k]
                for k, j in enumerate(free):
                    q[j] = x[k]
                best = max(best, mp.sqrt(sum(sum(P[i, j] * q[j] for j in range(L)) ** 2
                                             for i in S)))
        return float(best)
