"""The control cycle's kinematics compiled: the generated scalar kernels under numba, and
the warm-started Gauss-Newton forward kinematics, the scaled-Jacobian guard and the
torque projection around them, without a Python call per operation.

:class:`~.kinematics.KinematicModel` calls the generated scalar kernels (plain Python,
:mod:`distkin.codegen`) and numpy on 6-vectors and 8 × 6 matrices; each numpy call costs
1-5 µs of dispatch and a cycle makes a few dozen.  Here the same generated functions are
compiled by numba (``numba.njit`` of the functions of ``distkin/_generated``, so the
formulas keep their one source), and the loops around them are plain compiled code
writing into preallocated arrays:

* :func:`build` -> :class:`CycleKernels`: ``ik(pose, q) -> ok``, ``jacobian(pose, J)``,
  ``closure(q, pose, C)``, ``forward(q, guess, tol, max_iter, pose_out) -> (residual,
  iterations, converged)``, ``singular_values(J, S) -> (σmin, σmax)`` of ``J S⁻¹``,
  ``project(J, tau, w, out)``: ``J (JᵀJ)⁻¹ (Jᵀ tau + w)`` (the torque distribution of
  :mod:`.controller`);
* :func:`reading_extremes`, :func:`rotate_wrench`, :func:`spring_wrench` and
  :func:`rotate_pose` (any mechanism, in numba's disk cache): the checks of a state
  frame in one call, the sensor wrench rotated into the base frame, the admittance's
  spring and its SO(3) step -- the functions of :mod:`.kinematics` and
  :mod:`.admittance` themselves compiled, so the formulas have one source.

The kernels give the same bits as the generated Python functions (the same float
operations in the same order); the Gauss-Newton step and the 6 × 6 solves use a
Gaussian elimination with partial pivoting instead of LAPACK and agree with the Python
route to rounding (tests/control/test_cycle_kernels.py).  The wrappers close over one
mechanism's kernels, so numba cannot keep them in its disk cache: :func:`build` compiles
them once per mechanism and process (about 2-4 s; the kernels themselves are cached).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CycleKernels", "build", "reading_extremes", "rotate_wrench", "rotate_pose",
           "spring_wrench"]

_BUILT: dict = {}


@dataclass(frozen=True)
class CycleKernels:
    """Compiled per-cycle kinematics of one mechanism (see the module docstring)."""

    L: int
    ik: object
    jacobian: object
    closure: object
    forward: object
    singular_values: object
    project: object


def _solve_into(A, b, x):                                    # pragma: no cover (compiled)
    """x = A⁻¹ b for a small square A by Gaussian elimination with partial pivoting;
    False if a pivot is 0 (A and b are overwritten)."""
    n = A.shape[0]
    for c in range(n):
        p = c
        for i in range(c + 1, n):
            if abs(A[i, c]) > abs(A[p, c]):
                p = i
        if A[p, c] == 0.0 or not math.isfinite(A[p, c]):
            return False
        if p != c:
            for j in range(n):
                t = A[c, j]
                A[c, j] = A[p, j]
                A[p, j] = t
            t = b[c]
            b[c] = b[p]
            b[p] = t
        for i in range(c + 1, n):
            f = A[i, c] / A[c, c]
            for j in range(c, n):
                A[i, j] -= f * A[c, j]
            b[i] -= f * b[c]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * x[j]
        x[i] = s / A[i, i]
    return True


def _reading_extremes(a, w):                                 # pragma: no cover (compiled)
    finite = True
    ma = 0.0
    for i in range(a.shape[0]):
        if not math.isfinite(a[i]):
            finite = False
        ma = max(ma, abs(a[i]))
    mf = 0.0
    mm = 0.0
    for i in range(3):
        if not (math.isfinite(w[i]) and math.isfinite(w[3 + i])):
            finite = False
        mf = max(mf, abs(w[i]))
        mm = max(mm, abs(w[3 + i]))
    return finite, ma, mf, mm


def _rotate_wrench(r, w, out):                               # pragma: no cover (compiled)
    R = _ROT(r)
    for k in range(2):
        for i in range(3):
            out[3 * k + i] = (R[i, 0] * w[3 * k] + R[i, 1] * w[3 * k + 1]
                              + R[i, 2] * w[3 * k + 2])


def _spring_wrench(pose, twist, p0, R0t, k, d, out):        # pragma: no cover (compiled)
    v = _LOG(_ROT(pose[3:]) @ R0t)
    for i in range(3):
        out[i] = -k[i] * (pose[i] - p0[i]) - d[i] * twist[i]
        out[3 + i] = -k[3 + i] * v[i] - d[3 + i] * twist[3 + i]


#: the rotation functions of .kinematics and .admittance compiled (one source of the
#: formulas; set by _jit before anything that calls them is compiled)
_ROT = _LOG = _ROTATE = None
_COMPILED: dict = {}


def _jit(name, func):
    global _ROT, _LOG, _ROTATE
    f = _COMPILED.get(name)
    if f is None:
        import numba
        if _ROT is None:
            from .admittance import rotation_log
            from .kinematics import _rot, rotate_pose
            _ROT = numba.njit(cache=True)(_rot)
            _LOG = numba.njit(cache=True)(rotation_log)
            _ROTATE = numba.njit(cache=True)(rotate_pose)
        f = _COMPILED[name] = numba.njit(cache=True)(func)
    return f


def reading_extremes(a, w):
    """``(finite, max|a|, max|f|, max|m|)`` of encoder angles ``a`` (L,) rad and the
    wrench ``w`` (6,) N, N·m (NaN or inf anywhere: ``finite`` False)."""
    return _jit("reading_extremes", _reading_extremes)(a, w)


def rotate_wrench(r, w):
    """``(R f, R m)`` (6,) for R = Rz Ry Rx of the angles ``r`` (3,) rad (the rotation
    of :func:`.kinematics._rot`), ``w = (f, m)`` (6,)."""
    out = np.empty(6)
    _jit("rotate_wrench", _rotate_wrench)(np.asarray(r, dtype=float),
                                          np.asarray(w, dtype=float), out)
    return out


def spring_wrench(pose, twist, p0, R0t, k, d):
    """:meth:`.admittance.Spring.wrench` compiled: ``-k e - d twist`` (6,) with
    ``e = (p - p0, log(R(pose) R0ᵀ))``."""
    out = np.empty(6)
    _jit("spring_wrench", _spring_wrench)(np.asarray(pose, dtype=float),
                                          np.asarray(twist, dtype=float), p0, R0t, k, d, out)
    return out


def rotate_pose(pose, dpos, dw):
    """:func:`.kinematics.rotate_pose` compiled (the same function under numba)."""
    _jit("reading_extremes", _reading_extremes)
    return _ROTATE(np.asarray(pose, dtype=float), np.asarray(dpos, dtype=float),
                   np.asarray(dw, dtype=float))


def build(kernels, L: int) -> CycleKernels:
    """Compile the cycle kernels of one mechanism.

    Parameters
    ----------
    kernels : KernelSet
        ``mech.kernels("scalar")`` (functions ``ik``, ``reach``, ``jacobian``,
        ``closure`` of a generated module).
    L : int
        Number of legs.
    """
    key = (kernels.ik, kernels.jacobian, kernels.closure, int(L))
    got = _BUILT.get(key)
    if got is not None:
        return got
    import numba
    nj = numba.njit(cache=True)
    ik_k, reach_k = nj(kernels.ik), nj(kernels.reach)
    jac_k, clo_k = nj(kernels.jacobian), nj(kernels.closure)
    solve = numba.njit(_solve_into)
    _jit("reading_extremes", _reading_extremes)
    rotate = _ROTATE

    @numba.njit
    def ik(pose, q):                                         # pragma: no cover (compiled)
        r = ik_k(pose)
        s = reach_k(pose)
        m = s[0]
        for i in range(len(r)):
            q[i] = r[i]
            if s[i] < m:                                     # Python's min(): first, then <
                m = s[i]
        return m >= 0.0

    @numba.njit
    def jacobian(pose, J):                                   # pragma: no cover (compiled)
        r = jac_k(pose)
        for i in range(len(r)):
            row = r[i]
            for j in range(6):
                J[i, j] = row[j]

    @numba.njit
    def closure(q, pose, C):                                 # pragma: no cover (compiled)
        r = clo_k(q, pose)
        for i in range(len(r)):
            row = r[i]
            for j in range(7):
                C[i, j] = row[j]

    @numba.njit
    def forward(q, guess, tol, max_iter, out):               # pragma: no cover (compiled)
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

    @numba.njit
    def singular_values(J, S):                               # pragma: no cover (compiled)
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

    @numba.njit
    def project(J, tau, w, out):                             # pragma: no cover (compiled)
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

    ck = CycleKernels(int(L), ik, jacobian, closure, forward, singular_values, project)
    # compile now: the first control cycle must not wait for the compiler
    pose = np.zeros(6)
    q = np.zeros(L)
    Jb = np.zeros((L, 6))
    ik(pose, q)
    jacobian(pose, Jb)
    closure(q, pose, np.zeros((L, 7)))
    forward(q, pose, 1e-4, 1, np.zeros(6))
    singular_values(np.ones((L, 6)), np.ones(6))
    project(np.ones((L, 6)), np.zeros(L), np.zeros(6), np.zeros(L))
    reading_extremes(np.zeros(L), np.zeros(6))
    rotate_wrench(np.zeros(3), np.zeros(6))
    spring_wrench(np.zeros(6), np.zeros(6), np.zeros(3), np.eye(3), np.zeros(6), np.zeros(6))
    rotate_pose(np.zeros(6), np.zeros(3), np.zeros(3))
    _BUILT[key] = ck
    return ck
