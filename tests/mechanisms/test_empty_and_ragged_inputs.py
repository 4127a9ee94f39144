"""QA (fix-mech2): an empty batch of poses or joint values and a ragged list in every
tier give the answer of the fast tier's shapes or an InputError, never a numpy
traceback.  Before: ``inverse_kinematics(np.zeros((0, 6)), method="precise")`` raised
a broadcasting ValueError, the certified Jacobian an IndexError, the certified IK
returned q of shape (0,) next to valid of shape (0, 6), ``forward_kinematics`` of an
empty (0, L) batch raised "zero-size array to reduction" (and, through the round
trip's scalar route, "not enough values to unpack"), and the precise or certified
forward kinematics of a ragged list raised numpy's "inhomogeneous shape" ValueError."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.mechanisms import preset

EMPTY = np.zeros((0, 6))


@pytest.fixture(scope="module")
def hunt():
    return preset("hunt")


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_empty_batch_of_poses_has_the_fast_tiers_shapes(hunt, method):
    # the reference is the shape rule of the fast tier: (N, L) and (N, L, 6) with N = 0
    q, valid = hunt.inverse_kinematics(EMPTY, method=method)
    assert q.shape == valid.shape == (0, 6)
    assert hunt.jacobian(EMPTY, method=method).shape == (0, 6, 6)
    jq, jx = hunt.jq_jx(EMPTY, method=method)
    assert jq.shape == (0, 6) and jx.shape == (0, 6, 6)


@pytest.mark.parametrize("method", ["precise", "certified"])
def test_empty_batch_in_the_tier_results(hunt, method):
    from distkin.mechanisms.kinematics_tiers import ik_tier, jacobian_tier
    r = ik_tier(hunt, EMPTY, method)
    assert r.q.shape == r.q_error.shape == r.valid.shape == r.values.shape == (0, 6)
    assert r.reasons == ()
    j = jacobian_tier(hunt, EMPTY, method)
    assert j.J.shape == j.J_error.shape == j.values.shape == (0, 6, 6)
    assert j.Jq.shape == j.certified.shape == (0, 6) and j.inaccurate.shape == (0,)


def test_forward_kinematics_of_an_empty_batch(hunt):
    res = hunt.forward_kinematics(np.zeros((0, 6)))
    assert res.pose.shape == (0, 6) and res.converged.shape == (0,)
    assert "0 of 0 solved" in res.message


@pytest.mark.parametrize("method", ["precise", "certified"])
@pytest.mark.parametrize("q", [[[0.0] * 6, [0.0]], "abc"])
def test_tiered_forward_kinematics_refuses_ragged_and_text(hunt, method, q):
    with pytest.raises(InputError, match="expected 6 joint values") as exc:
        hunt.forward_kinematics(q, method=method)
    assert exc.value.field == "q"
