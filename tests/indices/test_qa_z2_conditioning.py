"""QA Z2 1-4: near-flat generator matrices, Ueberle's feasibility tolerance, nearly
singular Jacobians and the float64 range, against independent 50-digit references
(facet normals from cofactors, vertex enumeration in mpmath), never outputs of the
code itself."""

import itertools
import warnings

import mpmath as mp
import numpy as np
import pytest

from indices_helpers import mp_slice_sensitivity

from distkin.errors import ConditioningWarning, FloatRangeWarning
from distkin.indices import best_case_output as B
from distkin.indices import max_sensitivities as MS
from distkin.indices import worst_case_output as W

DPS = 50


def ref_worst(G, lo, hi, S=None):
    """min over facet normals (cofactors of every d−1 generators) of
    min(h(n), h(−n)) / ||P_S n||, in mpmath (QA Z2's /tmp/qaZ2/s/ref.py)."""
    with mp.workdps(DPS):
        G = mp.matrix([[mp.mpf(float(x)) for x in row] for row in np.asarray(G)])
        d, L = G.rows, G.cols
        S = list(range(d)) if S is None else list(S)
        best = mp.inf
        for sub in itertools.combinations(range(L), d - 1):
            n = []
            for i in range(d):
                cols = [c for c in range(d) if c != i]
                M = mp.matrix([[G[c, j] for c in cols] for j in sub])
                n.append((-1) ** i * mp.det(M))
            nn = mp.sqrt(sum(x ** 2 for x in n))
            if nn == 0:
                continue
            n = [x / nn for x in n]
            ps = mp.sqrt(sum(n[i] ** 2 for i in S))
            if ps == 0:
                continue
            for sg in (1, -1):
                h = 0
                for j in range(L):
                    t = sg * sum(n[i] * G[i, j] for i in range(d))
                    h += max(t * mp.mpf(float(hi[j])), t * mp.mpf(float(lo[j])))
                best = min(best, h / ps)
        return float(best)


def _near_flat(seed, L, e):
    """G = base + e·pert with base of rank 5 whose null direction is a pure torque."""
    rng = np.random.default_rng(seed)
    if seed == 11:
        for _ in range(2):
            rng.normal(size=(6, 6))
    n = np.array([0, 0, 0, 1, 2, -1.]) / np.sqrt(6)
    Q, _ = np.linalg.qr(np.column_stack([n, rng.normal(size=(6, 5))]))
    base = Q[:, 1:] @ rng.normal(size=(5, L))
    return base + e * np.outer(n, rng.normal(size=L))


def _caught(fn):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        out = fn()
    return out, [x for x in w if issubclass(x.category, ConditioningWarning)]


def test_near_flat_force_slice_is_flagged_not_the_flat_value():
    """κ = 1.8e-14: the flat route gave 2.169 for 1.5815, silently (QA Z2 1)."""
    G = _near_flat(1, 8, 1e-13)
    ref = ref_worst(G, -np.ones(8), np.ones(8), [0, 1, 2])
    val, w = _caught(lambda: W(G, -1, 1, keep=[0, 1, 2]))
    assert np.isnan(val) or abs(val - ref) <= 1e-6 * ref, (val, ref)
    if np.isnan(val):
        assert len(w) == 1 and "1 of 1 pose" in str(w[0].message)
    # batched: only the near-flat pose is flagged, the regular one is exact
    G2 = np.stack([G, np.random.default_rng(5).normal(size=(6, 8))])
    vals, _ = _caught(lambda: W(G2, -1, 1, keep=[0, 1, 2]))
    ref2 = ref_worst(G2[1], -np.ones(8), np.ones(8), [0, 1, 2])
    assert abs(vals[1] - ref2) <= 1e-12 * ref2


def test_ueberle_near_singular_is_finite_and_right():
    """κ = 2e-9 gave inf (every facet rejected by 1e-9·||bc||); the exact flat pose gave
    ~4e-16 (QA Z2 2)."""
    G = _near_flat(11, 6, 1e-8)
    ref = ref_worst(G, -np.ones(6), np.ones(6), [0, 1, 2])
    with pytest.warns(ConditioningWarning, match="Ueberle"):   # κ = 2e-9 <= UEBERLE_KAPPA
        val = W(G, -1, 1, keep=[0, 1, 2], method="ueberle")
    assert abs(val - ref) <= 1e-6 * ref, (val, ref)
    flat = _near_flat(11, 6, 0.0)
    val, w = _caught(lambda: W(flat, -1, 1, keep=[0, 1, 2], method="ueberle"))
    assert np.isfinite(val) and val == W(flat, -1, 1, keep=[0, 1, 2])
    assert len(w) == 1 and "Ueberle" in str(w[0].message)


def _ref_sens(J, S):
    """:func:`indices_helpers.mp_slice_sensitivity` at this file's DPS."""
    return mp_slice_sensitivity(J, S, DPS)


def test_nearly_singular_jacobian_sensitivities_flagged():
    """σ6/σ1 = 3.3e-14: pinv gave 2.7833 for 1.98385 (QA Z2 3)."""
    rng = np.random.default_rng(2)
    L = 7
    U, _ = np.linalg.qr(rng.normal(size=(L, L)))
    V, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    J = U[:, :6] @ np.diag([3, 2, 1.5, 1, .7, 1e-13]) @ V.T
    ref = _ref_sens(J, (0, 1, 2))
    m, w = _caught(lambda: MS(J))
    t = m["translational"]
    assert np.isnan(t) or abs(t - ref) <= 1e-6 * ref, (t, ref)
    if np.isnan(t):
        assert len(w) == 1 and "nearly singular J" in str(w[0].message)


def _box(L):
    return np.array(list(itertools.product((-1.0, 1.0), repeat=L)))


def test_float_range_rescaled():
    """G·1e-155 gave inf (QA Z2 4): references from homogeneity and brute force."""
    G = np.random.default_rng(3).normal(size=(6, 8))
    ref = ref_worst(G, -np.ones(8), np.ones(8))
    assert abs(W(G * 2.0 ** -515, -1, 1) / 2.0 ** -515 - ref) <= 1e-12 * ref
    # a result beyond float64 warns
    with pytest.warns(FloatRangeWarning):
        assert W(G * 1e300, -1e300, 1e300) == np.inf


def test_float_range_rescaled_best_and_sensitivities():
    """B(G·1e155) and MS(Gᵀ·1e-155) gave inf (QA Z2 4): brute force over box vertices."""
    G = np.random.default_rng(3).normal(size=(6, 8))
    # the farthest box vertex (the whole set), scaled up
    far = np.max(np.linalg.norm(_box(8) @ G.T, axis=1))
    assert abs(B(G * 2.0 ** 515, -1, 1) / 2.0 ** 515 - far) <= 1e-12 * far
    # projection sensitivities of J = G.T·2^-515: force ~ 2^-515, translation ~ 2^515
    J = G.T * 2.0 ** -515
    m = MS(J, "projection")
    f = np.max(np.linalg.norm(_box(8) @ G.T[:, :3], axis=1))
    Jp = np.linalg.pinv(G.T)
    t = np.max(np.linalg.norm(_box(8) @ Jp[:3].T, axis=1))
    assert abs(m["force"] / 2.0 ** -515 - f) <= 1e-12 * f
    assert abs(m["translational"] / 2.0 ** 515 - t) <= 1e-9 * t


def test_hull_survives_negligible_generators():
    """Two generators 1e-9 of the others made Qhull fail ("flat", σmin/σmax = 0.108) on
    a well-conditioned set (QA Z2 5); the answer is now within the dropped generators'
    contribution of the 50-digit reference and of the brute-force farthest vertex."""
    rng = np.random.default_rng(7)
    for _ in range(4):
        rng.normal(size=(6, 8))
    G = rng.normal(size=(6, 8))
    G[:, [6, 7]] = G[:, [0, 1]] * 1e-9
    bound = np.linalg.norm(G[:, 6:], axis=0).sum()
    ones = np.ones(8)
    for keep in (None, [0, 1, 2]):
        ref = ref_worst(G, -ones, ones, keep)
        assert abs(W(G, -1, 1, keep, method="hull") - ref) <= 10 * bound + 1e-12
    far = np.max(np.linalg.norm(_box(8) @ G.T, axis=1))
    assert abs(B(G, -1, 1, method="hull") - far) <= bound + 1e-12
