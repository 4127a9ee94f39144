"""The exact capability and sensitivity kernels count what they enumerate before they
allocate it (QA round L, items 6, 8, 9): C(L, d−1) facet normals, 2^L box vertices,
C(L, 3)·2^(L−3) slice-vertex candidates.  The counts in the messages are checked against
math.comb; facet normals against their defining property (orthogonal to d − 1
generators); the zero-limit hull against the zonotope's value of a point set (0)."""

from __future__ import annotations

from math import comb

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices import best_case_output, max_sensitivities, worst_case_output
from distkin.indices.zonotope import facet_normals

RNG = np.random.default_rng(0)


@pytest.mark.parametrize("call, count", [
    (lambda: max_sensitivities(RNG.normal(size=(1, 20, 6))), comb(20, 3) * 2 ** 17),
    (lambda: max_sensitivities(RNG.normal(size=(1, 60, 6))), comb(60, 3) * 2 ** 57),
    (lambda: best_case_output(RNG.normal(size=(6, 22)), -1, 1), 2 ** 22),
    (lambda: best_case_output(RNG.normal(size=(6, 40)), -1, 1), 2 ** 40),
    (lambda: best_case_output(RNG.normal(size=(6, 20)), -1, 1, keep=[0, 1, 2]),
     comb(20, 3) * 2 ** 17),
    (lambda: worst_case_output(RNG.normal(size=(6, 200)), -1, 1), comb(200, 5)),
    (lambda: facet_normals(RNG.normal(size=(6, 200))), comb(200, 5)),
])
def test_a_large_L_is_refused_with_its_cost(call, count):
    """The old kernels ran for hours or raised a raw MemoryError (L = 200, 40)."""
    from distkin.indices.zonotope import MAX_CANDIDATES
    assert count > MAX_CANDIDATES
    with pytest.raises(InputError) as err:
        call()
    assert f"got {count:,} for L = " in str(err.value)
    assert err.value.field in ("G", "J")


def test_the_hull_refuses_what_qhull_cannot_take():
    with pytest.raises(InputError, match=f"got {2 ** 17:,} for L = 17"):
        worst_case_output(RNG.normal(size=(6, 17)), -1, 1, method="hull")


def test_a_study_device_with_too_many_legs_is_refused_before_the_sweep():
    from distkin.app.queries.indices import _check_legs_cost
    _check_legs_cost(8, "mechanism")                           # the Octopod: well within
    with pytest.raises(InputError, match=f"got {comb(13, 3) * 2 ** 10:,} for L = 13") as err:
        _check_legs_cost(13, "query[0].devices[1]")
    assert err.value.field == "query[0].devices[1]"


def test_facet_normals_of_one_matrix():
    """(d, L) as every other entry point takes it: C(L, d−1) normals, each orthogonal to
    d − 1 of the generators, equal to the batched call's."""
    G = RNG.normal(size=(6, 8))
    n, P, regular = facet_normals(G)
    assert n.shape == (comb(8, 5), 6) and P.shape == (comb(8, 5), 8) and regular is True
    assert np.allclose(P, n @ G)
    scale = np.abs(P).max(axis=1, keepdims=True)
    assert np.all(np.sum(np.abs(P) <= 1e-12 * scale, axis=1) >= 5)
    nb, Pb, rb = facet_normals(G[None])
    assert np.array_equal(nb[0], n) and np.array_equal(Pb[0], P) and rb.tolist() == [True]


@pytest.mark.parametrize("G, match", [
    (np.ones(5), r"shape \(d, L\) or \(N, d, L\)"),
    (np.ones((6, 4)), r"L >= d"),
    (np.full((6, 8), np.nan), "finite"),
    ([["a"] * 8] * 6, "numeric"),
])
def test_facet_normals_refuses_bad_input(G, match):
    with pytest.raises(InputError, match=match) as err:
        facet_normals(G)
    assert err.value.field == "G"


def test_zero_limits_in_the_hull_name_the_limits_not_the_geometry():
    """pmin = pmax = 0: the output set is the point {0} for a well-conditioned G, whose
    worst case the zonotope gives as 0; the hull route named G's conditioning."""
    G = np.random.default_rng(3).normal(size=(6, 8))
    assert worst_case_output(G, 0, 0) == 0.0
    with pytest.raises(InputError, match=r"pmin = pmax at actuators \[0, 1, 2, 3, 4, 5, 6, 7\]") \
            as err:
        worst_case_output(G, 0, 0, method="hull")
    assert err.value.field == "pmax"
