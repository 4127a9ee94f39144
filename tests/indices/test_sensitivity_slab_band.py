"""Twist sensitivities of a nearly singular J (flat_tol < σmin/σmax <= RANK_TOL, QA of
the slab route): the sets are bounded, so +inf is wrong there (it belongs to a part a
null twist of an exactly singular J reaches).  The L = 6 slice depends on the columns
J_S alone: a well-conditioned J_S keeps its value, a nearly singular one is NaN with a
ConditioningWarning (before: +inf and no warning, e.g. 1.14e13 m/rad by the
reference).  References: 60-digit vertex enumerations in mpmath (the slab's and, for
L = 7, the slice of J#·box with J# = (JᵀJ)⁻¹Jᵀ), never outputs of the code itself."""

from __future__ import annotations

import itertools
import warnings

import mpmath as mp
import numpy as np
import pytest

from indices_helpers import mp_slice_sensitivity

from distkin.errors import ConditioningWarning
from distkin.indices import max_sensitivities
from distkin.indices.zonotope import RANK_TOL, flat_tol

DPS = 60
PARTS = {"translational": (0, 1, 2), "rotational": (3, 4, 5)}


def ref_slab(A):
    """Largest ||u|| over {u : |A u|∞ <= 1}, A (L, 3) of full column rank: the vertices
    where three slab planes meet, every one of the C(L, 3)·8 solved in mpmath."""
    with mp.workdps(DPS):
        Am = mp.matrix(np.asarray(A).tolist())
        best = mp.mpf(-1)
        for T in itertools.combinations(range(A.shape[0]), 3):
            B = mp.matrix([[Am[i, k] for k in range(3)] for i in T])
            if mp.det(B) == 0:
                continue
            for s in itertools.product((-1, 1), repeat=3):
                u = mp.lu_solve(B, mp.matrix(list(s)))
                if all(abs(sum(Am[i, k] * u[k] for k in range(3))) <= 1 + mp.mpf(10) ** -40
                       for i in range(A.shape[0])):
                    best = max(best, mp.norm(u))
        return float(best)


def ref_slice(J, S):
    """:func:`indices_helpers.mp_slice_sensitivity` at this file's DPS."""
    return mp_slice_sensitivity(J, S, DPS)


def _kappa(A):
    s = np.linalg.svd(A, compute_uv=False)
    return s[-1] / s[0]


def _run(J, mode="slice"):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        v = max_sensitivities(J, mode)
    return v, [w for w in rec if issubclass(w.category, ConditioningWarning)]


def _near_columns(delta, seed=0):
    """A random 6 × 6 J whose last two columns differ by delta·noise: the rotational
    columns J_R nearly singular, the translational ones regular (QA's construction)."""
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(6, 6))
    J[:, 5] = J[:, 4] + delta * rng.normal(size=6)
    return J


@pytest.mark.parametrize("seed", [0, 1])
def test_L6_nearly_singular_rotational_columns_are_nan_not_inf(seed):
    J = _near_columns(1e-13, seed)
    assert flat_tol(6, 6) < _kappa(J) <= RANK_TOL
    assert flat_tol(3, 6) < _kappa(J[:, 3:]) <= RANK_TOL
    v, w = _run(J)
    # the translational slab (regular columns) keeps its value, to rounding
    assert v["translational"] == pytest.approx(ref_slab(J[:, :3]), rel=1e-13)
    # the rotational slab is bounded (about 1/σmin of J_R): not +inf, and float64
    # cannot give it, so NaN with one warning naming J_S
    ref = ref_slab(J[:, 3:])
    assert 1e12 < ref < np.inf
    assert np.isnan(v["rotational"])
    assert len(w) == 1 and "J_S" in str(w[0].message)


def test_L6_well_conditioned_columns_keep_their_value_at_a_nearly_singular_J():
    """A near-null twist with both parts: σmin/σmax of J in the band, both J_S regular,
    both slab values finite and those of the reference, no warning."""
    rng = np.random.default_rng(4)
    J = rng.normal(size=(6, 6))
    n = np.array([0.3, -0.5, 0.2, 0.4, 0.6, -0.3])
    n /= np.linalg.norm(n)
    J = J - np.outer(J @ n, n) + 3e-14 * np.outer(rng.normal(size=6), n)
    assert flat_tol(6, 6) < _kappa(J) <= RANK_TOL
    v, w = _run(J)
    assert w == []
    for part, S in PARTS.items():
        assert _kappa(J[:, list(S)]) > 1e-3
        assert v[part] == pytest.approx(ref_slab(J[:, list(S)]), rel=1e-12)


def test_L6_exactly_singular_columns_are_unbounded_without_a_warning():
    """J_R of rank 2 (two equal columns): the null twist (0, 0, 0, 0, 1, -1) reaches
    the rotational slice, +inf; the translational one keeps its reference value."""
    J = _near_columns(0.0, 2)
    v, w = _run(J)
    assert w == []
    assert v["rotational"] == np.inf
    assert v["translational"] == pytest.approx(ref_slab(J[:, :3]), rel=1e-13)


def test_L6_zero_J_is_unbounded_and_has_no_force():
    v, w = _run(np.zeros((6, 6)))
    assert w == []
    assert v["translational"] == v["rotational"] == np.inf
    assert v["force"] == v["torque"] == 0.0


@pytest.mark.parametrize("mode", ["slice", "projection"])
def test_J_pinv_route_near_null_twist_in_a_part_is_nan_not_inf(mode):
    """L = 7, a near-null twist that is a pure translation along z (σmin/σmax in the
    band): the translational set is bounded (reference about 1/σmin), so NaN, not +inf
    (before: +inf, and only the rotational NaN); one warning."""
    rng = np.random.default_rng(6)
    J = rng.normal(size=(7, 6))
    e = np.array([0, 0, 1.0, 0, 0, 0])
    J = J - np.outer(J @ e, e) + 1e-13 * np.outer(rng.normal(size=7) / np.sqrt(7), e)
    assert flat_tol(6, 7) < _kappa(J) <= RANK_TOL
    v, w = _run(J, mode)
    if mode == "slice":
        assert 1e11 < ref_slice(J, PARTS["translational"]) < np.inf
    assert np.isnan(v["translational"]) and np.isnan(v["rotational"])
    assert len(w) == 1 and "nearly singular J" in str(w[0].message)
    assert np.isfinite(v["force"]) and np.isfinite(v["torque"])
