"""The sharper σmin bound of a certified-regular region (distkin.certify.tighten), against
sampled poses: the float singular values of Jx at random poses of the region (and of
each final box) never fall below the certified bound."""

import numpy as np
import pytest

from distkin.certify import REGULAR, certify_workspace, tighten_sigma
from distkin.mechanisms import preset


@pytest.fixture(scope="module")
def hunt_cube():
    """The Hunt-type preset's 150 mm cube at zero rotation (the Fig. 3 analogue)."""
    m = preset("hunt")
    h = m.home
    lo = np.r_[h[:3] - 0.075, 0.0, 0.0, 0.0]
    hi = np.r_[h[:3] + 0.075, 0.0, 0.0, 0.0]
    return m, lo, hi, certify_workspace(m, lo, hi, [0.15 / 16] * 3 + [1.0] * 3)


def _smin(m, X):
    _, Jx = m.jq_jx(X)
    return np.linalg.svd(Jx, compute_uv=False)[:, -1]


def test_the_region_bound_holds_at_sampled_poses_and_is_sharper(hunt_cube):
    m, lo, hi, cert = hunt_cube
    s = cert.summary()
    assert s["counts"]["regular"] == len(cert.status)        # the whole cube is regular
    boxes_only = float(cert.sigma_lower[cert.status == REGULAR].min())
    assert s["sigma_lower_min_boxes"] == boxes_only
    assert s["sigma_tightening"]["boxes"] > 0
    bound = s["sigma_lower_min"]
    assert bound == cert.sigma_bound.value
    X = lo + np.random.default_rng(3).uniform(size=(4000, 6)) * (hi - lo)
    sampled = _smin(m, X).min()
    assert boxes_only <= bound <= sampled
    # the point of it: the classification's bound was ~300x below the sampled minimum
    assert bound > 10 * boxes_only and bound > sampled / 10


def test_every_final_box_holds_its_own_bound_and_they_cover_the_region(hunt_cube):
    m, lo, hi, cert = hunt_cube
    tb = cert.sigma_bound
    vol = np.prod((tb.hi - tb.lo)[:, :3], axis=1).sum()
    assert vol == pytest.approx(np.prod(hi[:3] - lo[:3]), rel=1e-12)
    assert tb.sigma.min() == tb.value and tb.initial <= tb.value
    rng = np.random.default_rng(4)
    for i in np.argsort(tb.sigma)[:25]:                      # the weakest boxes
        X = tb.lo[i] + rng.uniform(size=(60, 6)) * (tb.hi[i] - tb.lo[i])
        assert _smin(m, X).min() >= tb.sigma[i]


def test_no_budget_keeps_the_classification_bound(hunt_cube):
    m, _, _, cert = hunt_cube
    reg = cert.status == REGULAR
    tb = tighten_sigma(m, cert.lo[reg], cert.hi[reg], cert.sigma_lower[reg], budget=0)
    assert tb.evaluated == 0 and tb.value == tb.initial == cert.sigma_lower[reg].min()
    off = certify_workspace(m, cert.lower, cert.upper, cert.min_width, tighten=0)
    s = off.summary()
    assert off.sigma_bound is None and "sigma_tightening" not in s
    assert s["sigma_lower_min"] == s["sigma_lower_min_boxes"] == tb.initial
