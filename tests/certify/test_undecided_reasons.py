"""Why a box is left undecided at the resolution (distkin.certify.boxes.REASONS), kept
per box through the chunks into the certificate, its summary and the JSON: checked
against float sampling of the reach margins (a second route) and for bookkeeping."""

import numpy as np
import pytest

from distkin.certify.boxes import REASONS, SINGULAR, UNDECIDED, branch_and_prune
from distkin.certify.workspace import certify_workspace
from distkin.mechanisms import preset


@pytest.fixture(scope="module")
def hunt_edge():
    """Hunt's 150 mm square column from z = 150 to 375 mm: its lower part leaves the
    reachable set, so boxes straddle its edge."""
    m = preset("hunt")
    lo = np.array([-0.075, -0.075, 0.15, 0, 0, 0])
    hi = np.array([0.075, 0.075, 0.375, 0, 0, 0])
    return m, certify_workspace(m, lo, hi, 0.0375, tighten=0)


def test_reach_boxes_straddle_the_edge_of_the_reachable_set(hunt_edge):
    """On this column every box undecided for 'reach' holds poses where some leg cannot
    close and poses where every leg closes, by the float reach margins on a 6 x 6 x 6
    grid of it.  (A diagnosis in general: an enclosure wider than the margin leaves
    'reach' on a box on one side of the edge too, QA P 2; not here.)"""
    m, c = hunt_edge
    sel = np.flatnonzero((c.status == UNDECIDED) & (c.reason == REASONS["reach"]))
    assert sel.size > 0
    g = np.linspace(0.0, 1.0, 6)
    P = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    for i in sel:
        pts = np.zeros((len(P), 6))
        pts[:, :3] = c.lo[i, :3] + P * (c.hi[i, :3] - c.lo[i, :3])
        worst = np.asarray(m.reach_margin(pts)).min(axis=1)
        assert worst.min() < 0 < worst.max(), i


def test_reasons_account_for_the_undecided_volume(hunt_edge):
    _, c = hunt_edge
    s = c.summary()
    why = s["undecided_reasons"]
    assert set(why) <= {"reach", "jq", "rank", "other"}
    assert sum(v["boxes"] for v in why.values()) == s["counts"]["undecided"]
    assert sum(v["volume"] for v in why.values()) == pytest.approx(s["undecided_volume"])
    assert np.all(c.reason[c.status != UNDECIDED] == 0)


def test_budget_leaves_carry_no_reason():
    """Boxes left unsplit by a spent budget are flagged ``budget``, not given a reason
    of the resolution."""
    m = preset("hunt")
    r = branch_and_prune(m, np.array([-0.075, -0.075, 0.15, 0, 0, 0]),
                         np.array([0.075, 0.075, 0.375, 0, 0, 0]), 0.0375, max_boxes=5)
    assert r["budget"].any() and np.all(r["reason"][r["budget"]] == 0)


def test_a_box_with_a_sign_change_is_singular_whatever_jq_does():
    """At the resolution, a box where every leg closes but a Jq entry is not enclosed
    away from 0 is still singular when det Jx changes sign in it (Jx is continuous
    where every leg closes; it used to be left undecided as 'jq', QA P).  The loose
    ``plain`` form on the radial Hexa leaves such boxes; the second route: float reach
    margins positive on a grid of each box and float det Jx of both signs there."""
    m = preset("hexa", layout="radial")
    lo = np.array([-0.075, -0.075, 0.225, 0, 0, 0])
    hi = np.array([0.075, 0.075, 0.375, 0, 0, 0])
    r = branch_and_prune(m, lo, hi, 0.0375, form="plain")
    assert np.all(r["reason"][r["status"] != UNDECIDED] == 0)
    g = np.linspace(0.0, 1.0, 5)
    P = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    singular = np.flatnonzero(r["status"] == SINGULAR)
    assert singular.size > 0
    for i in singular:
        pts = np.zeros((len(P), 6))
        pts[:, :3] = r["lo"][i, :3] + P * (r["hi"][i, :3] - r["lo"][i, :3])
        assert np.asarray(m.reach_margin(pts)).min() > 0, i
        d = np.linalg.det(m.jq_jx(pts)[1])
        assert d.min() < 0 < d.max(), i
    # none of the boxes left 'jq' holds a sign change the corner test would see
    from distkin.certify.boxes import sign_change_certificate
    ks = m.kernels("arb")
    for i in np.flatnonzero((r["status"] == UNDECIDED) & (r["reason"] == REASONS["jq"])):
        assert sign_change_certificate(m, ks, r["lo"][i], r["hi"][i]) is None
