"""``max_sensitivities(J, kappa=...)`` checks its κ = σmin/σmax of J (QA IX 2): a wrong
length, text, a negative, NaN or a value above 1 were a builtin reshape ValueError or
accepted silently (NaN or -1 made every pose "singular").  The reference for the valid
case is numpy's SVD of each J, the route taken without ``kappa``."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices import max_sensitivities


def _J(n=2, L=6, seed=3):
    return np.random.default_rng(seed).normal(size=(n, L, 6))


@pytest.mark.parametrize("kappa, why", [
    ([1, 2, 3], "shape"), ("abc", "expected"), ([0.0], "shape"), (-1, "shape"),
    ([0.5, -1.0], "got -1.0 at pose 1"), ([np.nan, 0.5], "got nan at pose 0"),
    ([0.5, 1.5], "got 1.5 at pose 1"), ([True, False], "boolean"),
    (np.zeros((2, 1)), "shape")])
def test_a_bad_kappa_is_refused_by_name(kappa, why):
    with pytest.raises(InputError, match=why) as err:
        max_sensitivities(_J(), kappa=kappa)
    assert err.value.field is not None and err.value.field.startswith("kappa")


@pytest.mark.parametrize("kappa, why", [(-1, "got -1.0"), (np.nan, "got nan"),
                                        ([0.1, 0.2], "shape"), ("x", "expected"),
                                        (2.0, "got 2.0")])
def test_one_J_refuses_a_bad_kappa(kappa, why):
    with pytest.raises(InputError, match=why) as err:
        max_sensitivities(_J(1)[0], kappa=kappa)
    assert err.value.field == "kappa"


@pytest.mark.parametrize("L", [6, 8])
def test_a_valid_kappa_gives_the_svd_route(L):
    """κ from numpy's SVD, passed in, one J or a batch (and κ = 1 exactly, the top of the
    range): the values of the call that computes κ itself."""
    J = _J(3, L)
    s = np.linalg.svd(J, compute_uv=False)
    kappa = s[:, -1] / s[:, 0]
    ref = max_sensitivities(J)
    got = max_sensitivities(J, kappa=kappa)
    for k in ref:
        np.testing.assert_array_equal(got[k], ref[k])
    one = max_sensitivities(J[0], kappa=float(kappa[0]))
    assert one == {k: float(v[0]) for k, v in ref.items()}
    assert max_sensitivities(J[0], kappa=[kappa[0]]) == one
    Q = np.linalg.qr(np.random.default_rng(1).normal(size=(6, 6)))[0]   # κ = 1
    assert max_sensitivities(Q, kappa=1.0) == max_sensitivities(Q)
