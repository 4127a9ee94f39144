"""The public fast Jacobian routes (``jacobian``, ``pose_jacobian``,
``joint_mass_matrix``, ``acceleration_map``) apply the fast tier's resolution check
(:func:`distkin.mechanisms.kinematics_tiers.jacobian_tier`'s ``inaccurate``): near a
leg's reach boundary float64 does not give J, and they said nothing (QA: the Octo at
z = 0.46837 m, J[0, 2] 2.697e8 against the precise tier's 2.285e8)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.mechanisms import LegMechanism, preset
from distkin.mechanisms.kinematics_tiers import J_REL_USEFUL, jacobian_tier

ROOT = Path(__file__).resolve().parents[2]
QA_POSE = np.array([0, 0, 0.4683713505659481, 0, 0, 0])
ROUTES = ("jacobian", "pose_jacobian", "joint_mass_matrix", "acceleration_map")


@pytest.mark.parametrize("route", ROUTES)
def test_qa_pose_warns_on_every_route(route):
    m = preset("octo")
    with pytest.warns(ConditioningWarning, match=r"not resolved in float64.*leg\(s\) 1, "
                                                 r".*method='precise'"):
        getattr(m, route)(QA_POSE)


def test_qa_pose_is_really_unresolved():
    """The warning is due: the fast J is off the precise tier's (60 digits) by far more
    than J_REL_USEFUL, and the fast tier's own estimate flags the same pose."""
    m = preset("octo")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        J = m.jacobian(QA_POSE)
        tier = jacobian_tier(m, QA_POSE, "fast")
    P = np.array(m.jacobian(QA_POSE, method="precise", dps=60), dtype=float)
    rel = np.max(np.abs(J - P), axis=-1) / np.max(np.abs(P), axis=-1)
    assert rel.max() > 100 * J_REL_USEFUL and tier.inaccurate.all()


def test_no_warning_over_the_study_box():
    m = preset("octo")
    rng = np.random.default_rng(3)
    X = m.home + np.hstack([rng.uniform(-0.075, 0.075, (500, 3)),
                            rng.uniform(-0.5, 0.5, (500, 3))])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        for route in ROUTES:
            getattr(m, route)(X)


def _boundary_poses(m, rng, directions=3):
    """Poses at 10^-2 .. 10^-16 m inside the reach boundary, along random directions
    from home (bisection on ``reachable``); and some just outside."""
    out = []
    for _ in range(directions):
        d = rng.normal(size=6)
        d[3:] *= 0.3
        d /= np.linalg.norm(d)
        lo, hi = 0.0, 1.0
        while m.reachable(m.home + hi * d):
            hi *= 2
        for _ in range(120):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if m.reachable(m.home + mid * d) else (lo, mid)
        out += [m.home + (lo - 10.0 ** -k) * d for k in range(2, 17)]
        out += [m.home + (hi + 10.0 ** -k) * d for k in (4, 10)]
    return out


def _mechanisms():
    from distkin.app.scene import load_scene
    rus8 = load_scene(ROOT / "examples" / "rus8_device.toml").mechanism
    return [preset("octo"), preset("hunt"), preset("ergin"),
            LegMechanism.from_description(rus8.leg_description(), route="numpy")]


def test_public_route_warns_exactly_where_the_tier_flags():
    """The cheap screen in front of the estimate loses nothing: on poses approaching the
    reach boundary of three presets and an 8-RUS leg table (crank 60 mm, distal 224 mm),
    ``jacobian`` warns at a pose iff ``jacobian_tier(..., "fast")`` flags it; at the
    poses just outside, where a leg does not close (its reach margin, rho^2 - C^2 of
    the IK equation, below 0), it warns that the leg does not close (QA: finite rows
    were returned silently)."""
    rng = np.random.default_rng(7)
    flagged = outside = 0
    for m in _mechanisms():
        for X in _boundary_poses(m, rng):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConditioningWarning)
                res = jacobian_tier(m, X, "fast")
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", ConditioningWarning)
                m.jacobian(X)
            said = [str(w.message) for w in caught
                    if issubclass(w.category, ConditioningWarning)]
            if (m.reach_margin(X) >= 0.0).all():
                assert bool(said) == bool(res.inaccurate[0]), (m.name, X)
                flagged += res.inaccurate[0]
            else:
                assert any("does not close" in t for t in said), (m.name, X)
                outside += 1
    assert flagged > 10 and outside > 10        # the test reaches the boundary


def test_unreachable_poses_named_alike_single_and_batched():
    """A batch with poses 1 m above home among reachable ones: the warning counts and
    names them as the reach margins (batched kernel) say, and one such pose alone (the
    scalar kernel's route) names the same legs."""
    m = preset("octo")
    rng = np.random.default_rng(11)
    X = m.home + np.hstack([rng.uniform(-0.02, 0.02, (6, 3)), np.zeros((6, 3))])
    X[[2, 4], 2] += 1.0
    bad = m.reach_margin(X) < 0.0
    assert bad.any(axis=-1).tolist() == [False, False, True, False, True, False]
    legs = ", ".join(str(j + 1) for j in np.flatnonzero(bad[2]))
    for poses, head in ((X, "at 2 of 6 pose(s)"), (X[2], "at 1 of 1 pose(s)")):
        with pytest.warns(ConditioningWarning, match="does not close") as rec:
            m.jacobian(poses)
        text = " ".join(str(w.message) for w in rec)
        assert head in text and f"leg(s) {legs}:" in text
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        m.jacobian(X[[0, 1, 3, 5]])                  # reachable: nothing to say


def test_jq_jx_names_unreachable_poses_as_jacobian_does():
    """QA 23b 7: ``jq_jx`` (documented "as jacobian") gave the meaningless rows of a pose
    1 m above home without a word.  Now the same poses and legs as the reach margins
    (an independent kernel) say, in one warning; a reachable batch is silent; and
    ``warn=False`` (the study's route, which filters the poses itself) gives the same
    numbers silently."""
    m = preset("octo")
    X = np.array([m.home, m.home + [0, 0, 1.0, 0, 0, 0]])
    bad = m.reach_margin(X) < 0.0
    assert bad.any(axis=-1).tolist() == [False, True]
    legs = ", ".join(str(j + 1) for j in np.flatnonzero(bad[1]))
    with pytest.warns(ConditioningWarning, match=rf"jq_jx: at 1 of 2 pose\(s\) a revolute "
                                                 rf"leg does not close \(first: pose 1, "
                                                 rf"leg\(s\) {legs}:"):
        Jq, Jx = m.jq_jx(X)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        m.jq_jx(X[:1])
        Jq2, Jx2 = m.jq_jx(X, warn=False)
    assert np.array_equal(Jq, Jq2) and np.array_equal(Jx, Jx2)
