"""``points(poses, q)`` with joint values given (QA fix-mech2): a q of the wrong shape
raised numpy's reshape ValueError ('cannot reshape array of size 5 into shape (1, 8)';
also through ``interference(..., q=...)``), one row of q for several poses was refused
the same way, and text or NaN passed to numpy.  Reference: the crank tip of the leg
table's formula, B + l1 (cos q u + sin q v) (distkin.mechanisms.legs), written out."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.mechanisms import preset


@pytest.fixture(scope="module")
def octo():
    return preset("octo")


def test_one_row_of_q_for_several_poses(octo):
    X = octo.home + np.array([[0.0] * 6, [0.01, 0.0, 0.02, 0.1, 0.0, 0.0]])
    q = np.linspace(-0.3, 0.4, octo.L)
    pts = octo.points(X, q.tolist())
    t = octo.leg_description().leg_table
    for n in range(2):
        for i, leg in enumerate(t):
            C = np.array(leg.base) + leg.crank * (np.cos(q[i]) * np.array(leg.crank0)
                                                  + np.sin(q[i]) * np.array(leg.crank90))
            np.testing.assert_allclose(pts["C"][n, i], C, atol=1e-15)
            np.testing.assert_allclose(pts["D"][n, i], C + np.array(leg.offset), atol=1e-15)


@pytest.mark.parametrize("q", [np.zeros(5), np.zeros((3, 8)), "abc", [np.nan] * 8,
                               [[0.0] * 8, [0.0]]])
def test_bad_q_is_an_input_error(octo, q):
    X = np.tile(octo.home, (2, 1))
    with pytest.raises(InputError) as exc:
        octo.points(X, q)
    assert exc.value.field == "q"
