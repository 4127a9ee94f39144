"""The forward kinematics' ``max_iter`` and ``max_condition`` (QA fix-mech2).  Before:
max_iter 0 or -1 ran no step and reported ``iterations`` -1, 2.5 raised a bare
TypeError, True ran one step; max_condition NaN never flagged a singularity (ok True
with any condition), 'a' raised numpy's UFuncTypeError.  Now InputErrors naming the
field; the reference for a valid value is the pose whose inverse kinematics gave q."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import ConditioningWarning, InputError
from distkin.mechanisms import preset


@pytest.fixture(scope="module")
def hunt_case():
    m = preset("hunt")
    X = m.home + np.array([0.01, 0.005, -0.01, 0.05, 0.02, -0.03])
    return m, X, m.inverse_kinematics(X)[0]


@pytest.mark.parametrize("kw", [dict(max_iter=0), dict(max_iter=-1), dict(max_iter=2.5),
                                dict(max_iter=True), dict(max_condition=float("nan")),
                                dict(max_condition=0.5), dict(max_condition="a"),
                                dict(max_condition=True)])
@pytest.mark.parametrize("batched", [False, True])
def test_bad_options_refused(hunt_case, kw, batched):
    m, X, q = hunt_case
    with pytest.raises(InputError) as exc:
        m.forward_kinematics(np.tile(q, (2, 1)) if batched else q, X + 0.001, **kw)
    assert exc.value.field == next(iter(kw))


@pytest.mark.parametrize("kw", [dict(max_iter=np.int64(20)), dict(max_condition=np.inf),
                                dict(max_condition=np.float64(50.0)), dict(max_iter=1)])
def test_valid_options(hunt_case, kw):
    m, X, q = hunt_case
    if kw.get("max_iter") == 1:        # stopped short: flagged, and said (fast or warn)
        with pytest.warns(ConditioningWarning, match="converged False"):
            res = m.forward_kinematics(q, X + 0.001, **kw)
        assert res.iterations == 1 and not res.converged
    else:
        res = m.forward_kinematics(q, X + 0.001, **kw)
        assert res.ok and np.abs(res.pose - X).max() < 1e-12
