"""The study's per-pose indices in one compiled pass (Kühne et al., Sec. II-C, eqs. (3)-(7),
(9)-(15); DESIGN.md §6).

:func:`distkin.indices.study.evaluate_poses` computes, at every pose of a grid, the six
worst-case output capabilities (one zonotope facet computation shared by the three
generator matrices, :func:`distkin.indices.study._worst_cases`), the true velocity worst
cases (:mod:`.velocity_set`), J# = pinv(J), and the singular values of four readings of
the scaling (:mod:`.isotropy`).  The numpy route does each step as a batched array
operation, allocating (N, 56, 6) temporaries (about 10 KiB per pose for L = 8); this
module does the same arithmetic in compiled kernels with a few kB of work buffers,
some pose by pose and some over blocks of 32 or 64 poses with the pose as the innermost loop
(branch-free, so that the compiler evaluates four poses per vector instruction):

* the kinematics (reach margins, Jq, J) from the generated ``loop`` kernels compiled
  by numba (:func:`reach_jq_jx`);
* the singular values of the four readings ``ST⁻¹Jᵀ``, ``Jᵀ``, ``ST Jᵀ``, ``ST⁻¹Jxᵀ``,
  J# = pinv(J) and the null space of Jᵀ (:mod:`.jacobi_lanes`, over blocks of poses):
  one Householder QR ``J = QR`` serves the three readings of J (``σ(D Jᵀ) = σ(R D)``),
  ``J# = R⁻¹Q₁ᵀ`` and the null space (the last columns of Q), a second QR the reading
  of Jx; one-sided (Hestenes) Jacobi rotates the rows of each 6 × 6 ``R D`` until they
  are orthogonal to 1e-15 of their norms, and the singular values are the row norms
  (relative accuracy of order 1e-15·κ, like LAPACK's SVD);
* L = 8: the facets of the wrench zonotope ``Jᵀ·box`` from the null space of Jᵀ and J#,
  with the twist and acceleration normals ``JᵀJ n = Jᵀ y`` and ``M̂ n`` and the slice
  ratios of :func:`.zonotope._ratio_min` (:mod:`.facets_lanes`, over blocks of poses);
* 6 <= L < 8: the facets pose by pose exactly as :func:`.zonotope._facets` (pivoted
  Gram-Schmidt, ``B⁻¹G = [I | C]``, generalised cross products of the columns of C;
  unit box, so the offset is ``Σ|n·g_i|``), the twist and acceleration normals ``JᵀJ n``
  and ``M̂ n``, and the slice ratios;
* the true velocity worst cases, pose by pose; for L = 6 they are also the velocity and
  angular velocity of eq. (5): J is square, so ``{J⁻¹q̇ : |q̇|∞ <= q̇max}`` is the slab set
  ``{ẋ : |J ẋ|∞ <= q̇max}`` and the worst case of its slice ``q̇max / max_l ||J_{l,S}||``
  (:mod:`.velocity_set`), computed from J itself: accurate to rounding where the
  facets through J⁻¹ lose about eps/κ, and continuous through a singularity, where
  the flat route of J⁻ᵀ's zonotope gave exactly 0.

Poses that the kernels do not vouch for (σmin/σmax of Jᵀ below
:data:`~.zonotope.RANK_TOL`, by the exact σ for L = 8 and the pivots of Gram-Schmidt
otherwise: the flat route of :func:`.zonotope._flat_worst`; a Jacobi that did not
converge in 60 sweeps; σ that are not finite, as an exactly zero column of J gives the
QR) are flagged, and the caller computes them by
the numpy route.  Agreement with that route (tests/indices/test_study_compiled.py):
relative differences of a few 1e-13 on the presets' Table II grids.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .facets_lanes import capabilities_lanes
from .jacobi_lanes import jacobi_lanes
from .zonotope import RANK_TOL, _groups

__all__ = ["study_kernel_tables", "study_indices", "reach_jq_jx"]

#: output dimension (a compile-time constant of the kernel)
_D = 6


@lru_cache(maxsize=None)
def study_kernel_tables(L: int, d: int = 6):
    """The facet normals of ``_groups(d, L)`` flattened: ``m`` (K,), ``rows`` (K, 3)
    and ``cset`` (K, 2) (-1 padded), in the order of :func:`.zonotope._facets`."""
    ms, rows, csets = [], [], []
    for m, cset, rr in _groups(d, L):
        for r in rr:
            ms.append(m)
            rows.append(list(r) + [-1] * (3 - len(r)))
            csets.append(list(cset) + [-1] * (2 - len(cset)))
    return (np.array(ms, np.int64), np.array(rows, np.int64), np.array(csets, np.int64))


@lru_cache(maxsize=1)
def _kernel():
    import numba

    @numba.njit(cache=True)
    def ratio_min(h, nn, lim, s0, vb):                       # pragma: no cover (compiled)
        """:func:`.zonotope._ratio_min` for the slice of coordinates s0..s0+2, with
        h >= 0 (unit box offsets; a vacuous normal gives +inf) and without a square root
        and a division per normal: the smallest ``h_k / ||n_k||`` is found by comparing
        ``h_k² ||n_j||²`` with ``h_j² ||n_k||²``, and only its quotient is formed (the
        same expression as the reference's; near-ties within rounding may pick either)."""
        K = h.shape[0]
        tot = 0.0
        for k in range(K):
            v = nn[k, s0] * nn[k, s0] + nn[k, s0 + 1] * nn[k, s0 + 1] \
                + nn[k, s0 + 2] * nn[k, s0 + 2]
            tot += v
            vb[k] = v
        thr = 1e-15 * (np.sqrt(tot) + 1e-300)
        thr2 = thr * thr
        bk = -1
        hb = 0.0
        vbest = 1.0
        for k in range(K):
            v = vb[k]
            if v <= thr2:
                continue
            hk = h[k] * lim
            if bk < 0 or hk * hk * vbest < hb * hb * v:
                bk = k
                hb = hk
                vbest = v
        if bk < 0:
            return np.inf
        return hb / np.sqrt(vbest)

    @numba.njit(cache=True)
    def run(J, M, lims, NM, NR, NC, caps, flag):           # pragma: no cover (compiled)
        """The six capabilities pose by pose from the pivoted facets (any 6 <= L <= 8)."""
        N, L, _ = J.shape
        d = _D
        K = NM.shape[0]
        G = np.empty((d, L))
        R = np.empty((d, L))
        perm = np.empty(L, np.int64)
        piv = np.empty(d)
        qv = np.empty(d)
        B = np.empty((d, 2 * d))
        C = np.empty((d, max(L - d, 1)))
        nw = np.empty((K, d))
        nt = np.empty((K, d))
        na = np.empty((K, d))
        h = np.empty(K)
        vb = np.empty(K)
        JtJ = np.empty((d, d))
        v = np.empty(3)
        for n in range(N):
            for i in range(d):
                for l in range(L):
                    G[i, l] = J[n, l, i]
                    R[i, l] = J[n, l, i]
            # ---- pivoted modified Gram-Schmidt (zonotope._pivot)
            for l in range(L):
                perm[l] = l
            for k in range(d):
                j = k
                bestn = -1.0
                for l in range(k, L):
                    s = 0.0
                    for i in range(d):
                        s += R[i, l] * R[i, l]
                    if s > bestn:
                        bestn = s
                        j = l
                for i in range(d):
                    t = R[i, k]
                    R[i, k] = R[i, j]
                    R[i, j] = t
                t2 = perm[k]
                perm[k] = perm[j]
                perm[j] = t2
                s = 0.0
                for i in range(d):
                    s += R[i, k] * R[i, k]
                nk = np.sqrt(s)
                piv[k] = nk
                for i in range(d):
                    qv[i] = R[i, k] / nk if nk > 0 else 0.0
                for l in range(k + 1, L):
                    pr = 0.0
                    for i in range(d):
                        pr += qv[i] * R[i, l]
                    for i in range(d):
                        R[i, l] -= qv[i] * pr
            ratio = piv.min() / piv[0] if piv[0] > 0 else 0.0
            if not ratio > RANK_TOL:
                flag[n] = True
                continue
            if L == d:
                for l in range(L):
                    perm[l] = l
            # ---- B⁻¹ by Gauss-Jordan with partial pivoting on [B | I]
            for i in range(d):
                for j in range(d):
                    B[i, j] = G[i, perm[j]]
                    B[i, d + j] = 1.0 if i == j else 0.0
            for c in range(d):
                p = c
                for i in range(c + 1, d):
                    if abs(B[i, c]) > abs(B[p, c]):
                        p = i
                if B[p, c] == 0.0:
                    flag[n] = True
                    break
                if p != c:
                    for j in range(2 * d):
                        t = B[c, j]
                        B[c, j] = B[p, j]
                        B[p, j] = t
                pv = B[c, c]
                for j in range(2 * d):
                    B[c, j] /= pv
                for i in range(d):
                    if i != c:
                        f = B[i, c]
                        if f != 0.0:
                            for j in range(2 * d):
                                B[i, j] -= f * B[c, j]
            if flag[n]:
                continue
            # Binv = B[:, d:]; C = Binv Gp[:, d:]
            for i in range(d):
                for l in range(L - d):
                    s = 0.0
                    for j in range(d):
                        s += B[i, d + j] * G[j, perm[d + l]]
                    C[i, l] = s
            # ---- facet normals and offsets (unit box: h = Σ|n·g_i|)
            for k in range(K):
                m = NM[k]
                if m == 0:
                    v[0] = 1.0
                elif m == 1:
                    c0 = NC[k, 0]
                    v[0] = C[NR[k, 1], c0]
                    v[1] = -C[NR[k, 0], c0]
                else:
                    c0 = NC[k, 0]
                    c1 = NC[k, 1]
                    a0, a1, a2 = C[NR[k, 0], c0], C[NR[k, 1], c0], C[NR[k, 2], c0]
                    b0, b1, b2 = C[NR[k, 0], c1], C[NR[k, 1], c1], C[NR[k, 2], c1]
                    v[0] = a1 * b2 - a2 * b1
                    v[1] = a2 * b0 - a0 * b2
                    v[2] = a0 * b1 - a1 * b0
                hk = 0.0
                for i in range(d):
                    nw[k, i] = 0.0
                for j in range(m + 1):
                    r = NR[k, j]
                    hk += abs(v[j])
                    for i in range(d):
                        nw[k, i] += v[j] * B[r, d + i]
                for l in range(L - d):
                    s = 0.0
                    for j in range(m + 1):
                        s += v[j] * C[NR[k, j], l]
                    hk += abs(s)
                h[k] = hk
            # ---- twist (JᵀJ n) and acceleration (M̂ n) normals
            for i in range(d):
                for j in range(d):
                    s = 0.0
                    for l in range(L):
                        s += J[n, l, i] * J[n, l, j]
                    JtJ[i, j] = s
            for k in range(K):
                for j in range(d):
                    s = 0.0
                    for i in range(d):
                        s += nw[k, i] * JtJ[i, j]
                    nt[k, j] = s
                    na[k, j] = nw[k, j] * M[j]
            caps[n, 0] = ratio_min(h, nw, lims[0], 0, vb)
            caps[n, 1] = ratio_min(h, nw, lims[0], 3, vb)
            caps[n, 2] = ratio_min(h, nt, lims[2], 0, vb)
            caps[n, 3] = ratio_min(h, nt, lims[2], 3, vb)
            caps[n, 4] = ratio_min(h, na, lims[1], 0, vb)
            caps[n, 5] = ratio_min(h, na, lims[1], 3, vb)

    @numba.njit(cache=True)
    def readings(J, lims, truev):                            # pragma: no cover (compiled)
        """The true velocity worst cases: q̇max / max_l ||J_l,S|| (:mod:`.velocity_set`)."""
        N, L, _ = J.shape
        for n in range(N):
            for a in range(2):
                mx = 0.0
                for l in range(L):
                    s = 0.0
                    for i in range(3 * a, 3 * a + 3):
                        s += J[n, l, i] * J[n, l, i]
                    mx = max(mx, np.sqrt(s))
                truev[n, a] = lims[2] / mx
    return run, readings


_LOOPS: dict = {}


def _compiled_loop(fn, module):
    """A generated ``loop`` kernel (:mod:`distkin.codegen.emit`) of ``module`` compiled
    by numba once per process (machine code kept in numba's disk cache beside the
    kernel's module); numpy's error model, so a division by zero gives inf as in the
    batched kernel.  A derived geometry's module (loaded from the derivation cache, not
    importable) is registered under its name first: numba's disk cache records the
    module of what it compiled and imports it by that name when another process loads
    the machine code (it would record '<dynamic>' and the next process fail)."""
    import sys
    f = _LOOPS.get(fn)
    if f is None:
        import numba
        sys.modules.setdefault(module.__name__, module)
        f = _LOOPS[fn] = numba.njit(cache=True, error_model="numpy")(fn)
    return f


def reach_jq_jx(mech, poses):
    """The study's kinematics: (ok (N,) bool, Jq (N, L), J (N, L, 6)): every leg's
    reach margin >= 0 and J finite, eq. (1)'s diagonal Jq and J = Jq⁻¹Jx, from the
    compiled ``loop``
    twins of the generated ``reach`` and ``jq_jx`` kernels (the same formulas as the
    batched kernels with :mod:`math` instead of numpy: equal to rounding, about 1e-16
    relative), or None where the mechanism has none (the numeric route, an older
    derived module) or joint ranges (whose test needs the crank angles)."""
    ranges = getattr(mech, "_joint_ranges", None)
    if getattr(mech, "route", "generated") != "generated" or ranges is None \
            or ranges()[0] is not None:
        return None
    kset = mech.kernels("batched")
    loops = getattr(kset, "loops", {})
    if "reach" not in loops or "jq_jx" not in loops:
        return None
    P = np.ascontiguousarray(poses, dtype=float)
    N, L = len(P), mech.L
    margin = np.empty((N, L))
    out = np.empty((N, L, 7))
    ok = np.empty(N, np.bool_)
    Jq = np.empty((N, L))
    J = np.empty((N, L, 6))
    if N:
        _compiled_loop(loops["reach"], kset.module)(P, margin)
        _compiled_loop(loops["jq_jx"], kset.module)(P, out)
        _split_kernel()(margin, out, ok, Jq, J)
    return ok, Jq, J


@lru_cache(maxsize=1)
def _split_kernel():
    import numba

    @numba.njit(cache=True, error_model="numpy")
    def split(margin, out, ok, Jq, J):                     # pragma: no cover (compiled)
        """Jq = out[..., 0], J = out[..., 1:] / Jq (as numpy divides), ok = every
        margin >= 0 and J finite."""
        N, L, _ = out.shape
        for n in range(N):
            good = True
            for l in range(L):
                q = out[n, l, 0]
                Jq[n, l] = q
                good &= margin[n, l] >= 0.0
                for i in range(6):
                    x = out[n, l, 1 + i] / q
                    J[n, l, i] = x
                    good &= np.isfinite(x)
            ok[n] = good
    return split


def study_indices(J, Jq, M, actuators, ST):
    """The compiled part of :func:`~.study.evaluate_poses` (module docstring).

    Parameters
    ----------
    J : ndarray (N, L, 6)
        Jacobian, q̇ = J (v, ω); 6 <= L <= 8.
    Jq : ndarray (N, L)
        Diagonal of eq. (1)'s Jq (m), for the ``jx`` reading.
    M : ndarray (6,)
        diag(M̂) (kg, kg·m²).
    actuators : dict
        ``nominal_torque``, ``stall_torque`` (N·m), ``velocity`` (rad/s).
    ST : 6 floats

    Returns
    -------
    caps : ndarray (N, 6)
        force, torque, velocity, angular velocity, acceleration, angular acceleration
        (the order of :data:`~.study.CAPABILITIES`).
    truev : ndarray (N, 2)
        Translational, angular velocity of the true set (:mod:`.velocity_set`).
    twist : ndarray (N, 6, L)
        J# (only for L > 6; zeros for L = 6).
    sig : ndarray (N, 8)
        (σmin, σmax) of ST⁻¹Jᵀ, Jᵀ, ST·Jᵀ, ST⁻¹Jxᵀ.
    flag : ndarray (N,) bool
        True where the values are not vouched for (compute those by the numpy route).
    """
    J = np.ascontiguousarray(J, dtype=float)
    N, L, d = J.shape
    if d != 6 or not 6 <= L <= 8:
        raise ValueError(f"expected J of shape (N, L, 6) with 6 <= L <= 8, got {J.shape}")
    NM, NR, NC = study_kernel_tables(L, d)
    lims = np.array([actuators["nominal_torque"], actuators["stall_torque"],
                     actuators["velocity"]], dtype=float)
    caps = np.empty((N, 6))
    truev = np.empty((N, 2))
    twist = np.empty((N, d, L)) if L > d else np.zeros((N, d, L))   # J# fills it
    sig = np.empty((N, 8))
    flag = np.zeros(N, bool)
    if N:
        st = np.asarray(ST, dtype=float)
        run, readings = _kernel()
        Jq = np.ascontiguousarray(Jq, dtype=float)
        M = np.asarray(M, dtype=float)
        Z = jacobi_lanes(J, Jq, st, sig, twist, flag)
        # an exactly zero column of J (or of J·Jq) stops the Householder QR (0/0): its
        # σ come out inf/0 or NaN, which the rank test below would pass; flagged here
        flag |= ~np.isfinite(sig).all(axis=1)
        if L == 8:
            # facets from the null space of Jᵀ and J# (facets_lanes); the rank test on
            # the exact σ of Jᵀ instead of the pivots of Gram-Schmidt
            flag |= ~(sig[:, 2] > RANK_TOL * sig[:, 3])
            capabilities_lanes(J, twist, Z, M, lims, caps)
        else:
            run(J, M, lims, NM, NR, NC, caps, flag)
        readings(J, lims, truev)
        if L == d:
            # J⁻¹·box is the slab set {ẋ : |J ẋ|∞ <= q̇max}: its worst cases from J itself,
            # continuous through a singularity (module docstring)
            caps[:, 2:4] = truev
    return caps, truev, twist, sig, flag
