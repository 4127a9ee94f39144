"""QA T 2, T 8, T 9: the precise tier at legs that do not close, read-only tier results,
and ``bits`` on the IK and Jacobian entry points.

Independent routes: whether a leg closes is decided by the certified tier's arb balls
(its ``infeasible`` flags) and by the float64 reach margin; the 200-bit balls are
checked against the default 128-bit ones (each must enclose the other's midpoint within
the sum of radii, and be narrower)."""

import numpy as np
import pytest

from distkin.errors import InfeasibleError, InputError
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics_tiers import ik_tier, jacobian_tier

FAR = [0.0, 0.0, 3.0, 0.0, 0.0, 0.0]          # every Octopod leg: margin about -796 m^2
MIXED = [0.32, 0.0, 0.3, 0.0, 0.0, 0.0]        # legs 3..8 do not close, 1 and 2 do


@pytest.fixture(scope="module")
def octopod():
    return preset("octopod")


@pytest.mark.parametrize("pose", [FAR, MIXED])
def test_precise_jacobian_legs_that_do_not_close_have_no_error_estimate(octopod, pose):
    cert = ik_tier(octopod, pose, "certified")
    open_ = cert.infeasible[0]                  # certainly does not close (arb balls)
    assert open_.any()
    assert np.array_equal(open_, octopod.reach_margin(pose) < 0)
    prec = jacobian_tier(octopod, pose, "precise")
    fast = jacobian_tier(octopod, pose, "fast")
    # the old code gave these rows an error of ~1e-17 on meaningless numbers
    assert np.all(np.isinf(prec.J_error[0][open_]))
    assert np.all(np.isinf(prec.Jq_error[0][open_]))
    assert np.all(np.isinf(prec.Jx_error[0][open_]))
    assert not prec.valid[0][open_].any()
    # as the fast tier: the same legs flagged, with the same (inf) error
    assert np.array_equal(np.isinf(prec.J_error).all(axis=-1),
                          np.isinf(fast.J_error).all(axis=-1))
    assert np.array_equal(prec.valid, fast.valid)
    # the legs that close keep a small estimate
    shut = ~open_
    assert np.all(prec.J_error[0][shut] < 1e-12)
    with pytest.raises(InfeasibleError):
        octopod.jacobian(pose, method="certified")


@pytest.mark.parametrize("pose", [FAR, MIXED])
def test_precise_ik_legs_that_do_not_close_have_no_error_estimate(octopod, pose):
    open_ = ik_tier(octopod, pose, "certified").infeasible[0]
    prec = ik_tier(octopod, pose, "precise")
    assert np.all(np.isinf(prec.q_error[0][open_]))
    assert not prec.valid[0][open_].any()
    assert np.all(prec.q_error[0][~open_] < 1e-12)
    fast = ik_tier(octopod, pose, "fast")       # float64 answer agrees where both vouch
    assert np.all(np.abs(fast.q[0][~open_] - prec.q[0][~open_]) <= fast.q_error[0][~open_])
    assert np.all(np.isinf(fast.q_error[0][open_]))     # and neither vouches where open


def test_precise_reachable_pose_unchanged(octopod):
    prec = jacobian_tier(octopod, octopod.home, "precise")
    assert np.all(np.isfinite(prec.J_error)) and prec.J_error.max() < 1e-12


def _writes(arr):
    with pytest.raises(ValueError):
        arr[(0,) * arr.ndim] = 5


def test_forward_results_are_read_only(octopod):
    q = np.array(octopod.inverse_kinematics(octopod.home)[0])
    for method in ("fast", "precise", "certified"):
        r = octopod.forward_kinematics(q, method=method)
        arrays = [r.pose, r.error] if method != "fast" else [r.pose]
        for a in arrays:
            _writes(a)
    res = octopod.forward_kinematics(np.stack([q, q]))             # batched FKResult
    for a in (res.pose, res.converged, res.residual, res.condition):
        _writes(a)
    assert q.flags.writeable                     # the caller's array is not frozen
    np.testing.assert_allclose(res.pose[0], octopod.home, atol=1e-12)


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_kinematics_tier_results_are_read_only(octopod, method):
    X = np.array([octopod.home])
    ik = ik_tier(octopod, X, method)
    jac = jacobian_tier(octopod, X, method)
    for a in (ik.q, ik.q_error, ik.reach_margin, ik.valid, jac.J, jac.J_error, jac.Jq,
              jac.Jx_error, jac.valid):
        _writes(a)
    if method != "fast":
        _writes(ik.values)
        _writes(jac.values)
    assert X.flags.writeable


@pytest.mark.parametrize("name", ["inverse_kinematics", "jacobian", "jq_jx"])
def test_bits_with_certified(octopod, name):
    pose = [0.01, -0.02, 0.31, 0.02, 0.01, -0.03]
    f = getattr(octopod, name)
    wide, fine = f(pose, method="certified"), f(pose, method="certified", bits=256)
    a, b = np.ravel(wide[0]), np.ravel(fine[0])       # J; q; Jq
    for x, y in zip(a, b):
        assert abs(float(x.mid()) - float(y.mid())) <= float(x.rad()) + float(y.rad()) + 1e-300
        assert float(y.rad()) < float(x.rad()) or float(x.rad()) == 0.0
    for method in ("fast", "precise"):
        with pytest.raises(InputError) as exc:
            f(pose, method=method, bits=256)
        assert exc.value.field == "bits"
    with pytest.raises(InputError) as exc:
        f(pose, method="certified", bits=20)
    assert exc.value.field == "bits" and "53..4096" in str(exc.value)
