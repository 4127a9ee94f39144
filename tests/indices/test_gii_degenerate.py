"""``gii`` on degenerate samples (QA IX 3): an empty sample and an all-zero one returned
(0, 0, 0), a GII of 0 that no pose has; both are refused by name now, as every other bad
input.  The reference for the valid case is analytic: J = diag(d) has singular values
|d|, so the GII of two such poses is min |d| / max |d| over both."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices import gii


@pytest.mark.parametrize("smin, smax, field, why", [
    (np.array([]), np.array([]), "smin", "empty sample"),
    ([], [], "smin", "empty sample"),
    ([0.0], [0.0], "smax", "0/0"),
    ([0.0, 0.0], [0.0, 0.0], "smax", "0/0"),
    ([0.1], [np.inf], "smax", "finite"),
    ([np.inf], [np.inf], "smin", "finite")])
def test_degenerate_samples_are_refused(smin, smax, field, why):
    with pytest.raises(InputError, match=why) as err:
        gii(smin, smax)
    assert err.value.field == field


def test_analytic_diagonal_jacobians():
    """Two poses J = diag(d): singular values |d| (analytic), GII = 0.25 / 8."""
    ds = [np.array([1.0, 2.0, -0.5, 3.0, 1.5, 2.5]), np.array([0.25, 8.0, 1, 1, 1, 1])]
    smin = [float(np.min(np.abs(d))) for d in ds]
    smax = [float(np.max(np.abs(d))) for d in ds]
    assert gii(smin, smax) == (0.25 / 8.0, 0.25, 8.0)
    # a zero σmin at one pose (a singular J) with a nonzero σmax: GII 0, defined
    assert gii([0.0, 1.0], [2.0, 4.0]) == (0.0, 0.0, 4.0)
