"""max_sensitivities at an exactly singular L = 8 Jacobian whose null twist does not
reach the part (its value is finite): eq. (5) with the Moore-Penrose J# is
discontinuous there, so the value comes with a ConditioningWarning.  Evidence of the
discontinuity, independent of the value at J: regular neighbours approached from
different directions converge to different values (each direction's limit is
stable over four decades of the step)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.indices import max_sensitivities


def _singular_J(seed=5):
    J = np.random.default_rng(seed).normal(size=(8, 6))
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    s[-1] = 0.0
    return (U * s) @ Vt, Vt[-1]


def _quiet(J):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return max_sensitivities(J)


def test_limits_depend_on_the_direction_of_approach():
    J0, n = _singular_J()
    assert np.linalg.norm(n[:3]) > 0.1 and np.linalg.norm(n[3:]) > 0.1   # finite slices
    limits = []
    for seed in (100, 101):
        E = np.random.default_rng(seed).normal(size=J0.shape)
        vals = [_quiet(J0 + h * E)["translational"] for h in (1e-4, 1e-6, 1e-8)]
        assert max(vals) - min(vals) < 1e-3 * vals[-1]        # each direction converges
        limits.append(vals[-1])
    assert abs(limits[0] - limits[1]) > 1e-3 * limits[0]    # ... to different values


def test_exactly_singular_J_warns_and_regular_J_does_not():
    J0, _ = _singular_J()
    with pytest.warns(ConditioningWarning, match="Moore-Penrose J#, which is discontinuous"):
        v = max_sensitivities(J0)
    assert np.isfinite(v["translational"]) and np.isfinite(v["rotational"])
    # the same Jacobian made regular: no warning (every warning an error here)
    J = np.random.default_rng(5).normal(size=(8, 6))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        max_sensitivities(J)
        max_sensitivities(J0[:6] + np.eye(6))          # L = 6 slab route, regular


def test_L6_exactly_singular_slab_route_does_not_warn():
    """L = 6 works on J itself (no J#): continuous, no warning."""
    J = np.random.default_rng(7).normal(size=(6, 6))
    U, s, Vt = np.linalg.svd(J)
    s[-1] = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        max_sensitivities((U * s) @ Vt)


def test_L6_projection_is_discontinuous_too():
    """L = 6, a null twist with no translational part: the translational projection is
    finite at J (J# route) and its limits depend on the direction of approach."""
    rng = np.random.default_rng(11)
    J = rng.normal(size=(6, 6))
    w = np.array([0, 0, 0, 0.48, 0.6, 0.64])
    J0 = J - np.outer(J @ w, w)                           # J0 w = 0, |w| = 1
    limits = []
    for seed in (200, 201, 202):
        E = np.random.default_rng(seed).normal(size=J0.shape)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            vals = [max_sensitivities(J0 + h * E, "projection")["translational"]
                    for h in (1e-5, 1e-7, 1e-9)]
        assert max(vals) - min(vals) < 1e-3 * vals[-1]
        limits.append(vals[-1])
    assert max(limits) - min(limits) > 1e-3 * max(limits)
    with pytest.warns(ConditioningWarning, match="Moore-Penrose"):
        assert np.isfinite(max_sensitivities(J0, "projection")["translational"])


def test_a_callers_kappa_of_zero_at_a_regular_J_flags_nothing():
    """kappa = 0 passed for a regular J (the study passes 0 where its kernel's σ were
    not finite): the pose's own SVD decides, nothing is flagged or warned (review)."""
    J = np.random.default_rng(0).normal(size=(8, 6))
    ref = max_sensitivities(J)
    for mode in ("slice", "projection"):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            got = max_sensitivities(J, mode, kappa=0.0)
        if mode == "slice":
            assert got == ref
