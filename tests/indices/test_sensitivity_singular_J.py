"""Twist sensitivities at a singular J (σmin/σmax below RANK_TOL; QA round H 3): a null
twist J ẋ = 0 moves the platform with the actuators locked, so a part it reaches is +inf,
the limit of the regular neighbours, whose values grow like 1/t as the smallest singular
value t goes to 0.  Before, pinv(J) truncated that direction: L = 8 slice 0.84 beside
neighbours of 1.5e9, L = 6 projection 3.1 below a slice of +inf."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.indices import max_sensitivities
from distkin.indices.study import ACTUATORS, _indices_compiled, _indices_numpy


#: the exactly singular J's finite twist sensitivities warn (discontinuous there)
_MOORE_PENROSE = "ignore:maximum sensitivities.*Moore-Penrose:distkin.errors.ConditioningWarning"


def _with_null(L, w, t=0.0, seed=0):
    """A random J (1, L, 6) whose unit twist w has |J w| = t (t = 0: J w = 0)."""
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(L, 6))
    w = np.asarray(w, float) / np.linalg.norm(w)
    J = J - np.outer(J @ w, w) + t * np.outer(rng.normal(size=L) / np.sqrt(L), w)
    return J[None]


def _both(J):
    """Both modes at an exactly singular J: a finite twist sensitivity on a J# route
    (projection, and slice for L > 6) warns, once, that it is discontinuous there
    (tests/indices/test_sensitivity_exact_singular.py); nothing else warns."""
    out = []
    for mode in ("slice", "projection"):
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            v = max_sensitivities(J, mode)
        pinv_route = mode == "projection" or J.shape[1] > 6
        finite = any(np.isfinite(v[k][0]) for k in ("translational", "rotational"))
        assert [(w.category, "Moore-Penrose" in str(w.message)) for w in rec] == \
            ([(ConditioningWarning, True)] if pinv_route and finite else []), mode
        out.append(v)
    return tuple(out)


@pytest.mark.parametrize("L", [6, 7, 8])
@pytest.mark.parametrize("w, part", [((0, 0, 1, 0, 0, 0), "translational"),
                                     ((0, 0, 0, 0.6, 0, 0.8), "rotational")])
def test_a_null_twist_inside_one_part_makes_it_unbounded(L, w, part):
    other = "rotational" if part == "translational" else "translational"
    s, p = _both(_with_null(L, w))
    assert s[part][0] == np.inf and p[part][0] == np.inf
    assert np.isfinite(s[other][0]) and p[other][0] >= s[other][0] * (1 - 1e-12)
    for mode in ("slice", "projection"):
        near = [max_sensitivities(_with_null(L, w, t), mode)[part][0] for t in (1e-4, 1e-7)]
        # the neighbours grow like 1/t: the limit is +inf (no finite value fits)
        assert 300 < near[1] / near[0] < 3000, (mode, near)
        assert near[1] > 1e5


def test_a_mixed_null_twist_leaves_the_slices_finite_and_continuous():
    """L = 6, null twist with translational and rotational parts: no null vector has a
    zero other part, so the slices stay finite and equal the regular neighbour's (slab
    route); every projection is unbounded and so never smaller than the slice."""
    w = (0.3, -0.5, 0.2, 0.4, 0.6, -0.3)
    s, p = _both(_with_null(6, w))
    sn = max_sensitivities(_with_null(6, w, 1e-10), "slice")
    for part in ("translational", "rotational"):
        assert np.isfinite(s[part][0]) and p[part][0] == np.inf
        assert s[part][0] == pytest.approx(sn[part][0], rel=1e-6)


def test_regular_poses_are_untouched():
    """κ above RANK_TOL: the values of the vertex enumeration, with or without kappa."""
    J = np.random.default_rng(3).normal(size=(5, 8, 6))
    a = max_sensitivities(J)
    b = max_sensitivities(J, kappa=np.ones(5))
    for k in a:
        assert np.array_equal(a[k], b[k]) and np.all(np.isfinite(a[k]))


@pytest.mark.parametrize("L", [6, 8])
@pytest.mark.filterwarnings(_MOORE_PENROSE)
def test_the_study_routes_agree_at_a_singular_J(L):
    J = np.concatenate([_with_null(L, (0, 0, 1, 0, 0, 0), seed=1),
                        _with_null(L, (0, 0, 1, 0, 0, 0), 1.0, seed=1)])
    Jq = np.full((2, L), 0.03)
    M = np.array([0.17] * 3 + [3e-4] * 3)
    args = (J, Jq, M, dict(ACTUATORS), (15, 15, 15, 1, 1, 1))
    for mode in ("slice", "projection"):
        c, n = _indices_compiled(*args, mode), _indices_numpy(*args, mode)
        assert c["sens_translational"][0] == n["sens_translational"][0] == np.inf
        assert np.isfinite(c["sens_translational"][1])
        np.testing.assert_allclose(c["sens_rotational"], n["sens_rotational"], rtol=1e-10)
