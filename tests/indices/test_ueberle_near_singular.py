"""Ueberle's worst case (Kühne et al., eqs. (10)-(12)) near a singular pose (QA 24):
its nested least squares lost accuracy faster than 1/κ (1.4 relative at κ = 1.7e-10,
1.6e-5 at 1e-8) with no warning above RANK_TOL = 1e-12.  Reference: Qhull's hull of
the 2^6 actuator-box vertices (``algorithm="hull"``, an independent route, which agrees
with a 50-digit vertex enumeration there to ~1e-8)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.indices.capability import UEBERLE_KAPPA, output_generators, worst_case_output
from distkin.mechanisms import preset

#: a hexa pose with σmin/σmax of J = 6.5e-11 (QA 24)
SINGULAR = np.array([0.05206663787149503, -0.002424281190568316, 0.28643637034055724,
                     0.9446760757564585, -0.7373721978798313, -0.3366842346570697])
LO, HI = -0.5 * np.ones(6), 0.7 * np.ones(6)


@pytest.mark.parametrize("t", [3e-8, 1e-7, 3e-7, 1e-5, 1e-3, 1e-1])
@pytest.mark.parametrize("keep", [None, [0, 1, 2], [3, 4, 5]])
def test_ueberle_is_accurate_or_says_it_handed_over(t, keep):
    m = preset("hexa")
    p = SINGULAR + t * (m.home - SINGULAR)
    G = output_generators(np.asarray(m.jacobian(p), dtype=float))["twist"]
    sv = np.linalg.svd(G, compute_uv=False)
    kappa = sv[-1] / sv[0]
    ref = worst_case_output(G, LO, HI, keep=keep, algorithm="hull")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ConditioningWarning)
        got = worst_case_output(G, LO, HI, keep=keep, algorithm="ueberle")
    said = any(issubclass(w.category, ConditioningWarning) for w in caught)
    assert said == (kappa <= UEBERLE_KAPPA), kappa
    tol = 1e-7 if said else 1e-10      # handed over: the zonotope kernel's 1e-16/κ
    assert abs(got - ref) <= tol * abs(ref), (kappa, got, ref)
