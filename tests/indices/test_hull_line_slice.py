"""``worst_case_output(..., method="hull")`` on a 1-D slice that misses the set (QA IX 5):
it returned -inf where ``zonotope`` and ``ueberle`` return the signed distance (the
minimum over the facet hyperplanes within the slice, negative: the origin is outside),
in 253 of 292 random 6 × 6 cases with one-sided limits.  References: an analytic case
and the three methods against one another on random cases (L = 6: all three; L = 8:
zonotope and hull)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from distkin.indices import worst_case_output

METHODS = ("zonotope", "hull", "ueberle")


def test_analytic_line_that_misses_the_box():
    """x0 = (p0 − p2)/√2, x2 = (p0 + p2)/√2, the other outputs p1, p3, p4, p5.  On the
    line x0 = 0 (others 0) p0 = p2, impossible with p0 in [0.5, 1.5] and p2 in
    [-1, 0.25]: the slice is empty.  Within it the facet hyperplanes are x2 = 0.5√2
    (p0 >= 0.5, the origin on the wrong side: −1/√2), 1.5√2, 0.25√2 and −√2 (inside):
    the signed distance is −1/√2."""
    c = 1 / math.sqrt(2)
    G = np.eye(6)
    G[[0, 0, 2, 2], [0, 2, 0, 2]] = [c, -c, c, c]
    lo = np.array([0.5, -1, -1, -1, -1, -1.0])
    hi = np.array([1.5, 1, 0.25, 1, 1, 1.0])
    for m in METHODS:
        assert worst_case_output(G, lo, hi, keep=[2], method=m) == pytest.approx(-c,
                                                                                 rel=1e-12)
    # the line through the box's other side (p2 in [-1, 1]) meets it: [0.5√2, √2]
    hi[2] = 1.0
    for m in METHODS:
        assert worst_case_output(G, lo, hi, keep=[2], method=m) == pytest.approx(-c,
                                                                                 rel=1e-12)


@pytest.mark.parametrize("L", [6, 8])
@pytest.mark.parametrize("keep", [[0], [2], [4], [0, 1], [0, 1, 2], [3, 4, 5]])
def test_the_methods_agree_on_random_one_sided_limits(L, keep):
    rng = np.random.default_rng(100 * L + keep[0] + len(keep))
    methods = METHODS if L == 6 else METHODS[:2]
    missed = 0
    for _ in range(40 if L == 6 else 12):
        G = rng.normal(size=(6, L))
        lo = rng.uniform(-1.0, 0.6, L)
        hi = lo + rng.uniform(0.1, 2.0, L)
        v = [worst_case_output(G, lo, hi, keep=keep, method=m) for m in methods]
        assert all(math.isfinite(x) for x in v), (L, keep, v)
        for x in v[1:]:
            assert x == pytest.approx(v[0], rel=1e-8, abs=1e-10), (L, keep, v)
        missed += v[0] < 0
    assert missed > 0                   # the case of the defect is among them


def test_batched_hull_matches_zonotope_on_a_line():
    rng = np.random.default_rng(7)
    G = rng.normal(size=(30, 6, 8))
    lo = rng.uniform(-1.0, 0.6, (30, 8))
    hi = lo + 1.0
    z = worst_case_output(G, lo, hi, keep=[1])
    h = worst_case_output(G, lo, hi, keep=[1], method="hull")
    np.testing.assert_allclose(h, z, rtol=1e-8, atol=1e-10)
