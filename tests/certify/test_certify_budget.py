"""Boxes left by a spent box budget are flagged, not "undecided at the resolution"
(QA F4), and the lower-level entry points check their mechanism, form and budget
(QA F8).

Independent route for the flags: a box is at the resolution exactly when no coordinate
is wider than ``min_width`` (:func:`~distkin.certify.boxes.split_dimension`), so the
flagged boxes must be the undecided ones still wider than that; with a budget large
enough the same region has no flag and every undecided box is at the resolution."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.app.queries.certify import certificate_json, certificate_text
from distkin.certify import branch_and_prune, certify_box, certify_workspace
from distkin.certify.batch import branch_and_prune_batched
from distkin.certify.boxes import UNDECIDED
from distkin.errors import InputError
from distkin.mechanisms import preset

#: QA F4's region: the radial HEXA, the 150 mm cube at zero rotation (m, rad)
LO = np.array([-0.075, -0.075, 0.225, 0, 0, 0])
HI = np.array([0.075, 0.075, 0.375, 0, 0, 0])
MINW = 0.15 / 8


@pytest.fixture(scope="module")
def hexa():
    return preset("hexa", layout="radial")


def _wide(r, minw=MINW):
    return np.any(r["hi"] - r["lo"] > minw, axis=1)


@pytest.mark.parametrize("entry", [branch_and_prune, branch_and_prune_batched])
def test_budget_flags_are_the_undecided_boxes_not_at_the_resolution(hexa, entry):
    small = entry(hexa, LO, HI, MINW, max_boxes=5)
    und = small["status"] == UNDECIDED
    assert small["budget"].any()
    assert np.array_equal(small["budget"], und & _wide(small))
    big = entry(hexa, LO, HI, MINW, max_boxes=100_000)
    assert not big["budget"].any()
    assert not np.any((big["status"] == UNDECIDED) & _wide(big))
    # the budget's boxes hide decided ones: the full run splits and decides them
    assert (big["status"] != UNDECIDED).sum() > (small["status"] != UNDECIDED).sum()


def test_certificate_reports_the_spent_budget(hexa):
    cert = certify_workspace(hexa, LO, HI, MINW, max_boxes=5, tighten=0)
    s = cert.summary()
    flags = cert.budget_mask()
    assert s["budget_exhausted"] and s["undecided_budget"]["boxes"] == int(flags.sum()) > 0
    assert s["undecided_budget"]["volume"] == pytest.approx(
        float(np.prod((cert.hi - cert.lo)[flags][:, :3], axis=1).sum()))
    assert np.array_equal(flags, (cert.status == UNDECIDED) & _wide({"lo": cert.lo, "hi": cert.hi}))
    text = certificate_text(cert, "mm", "deg")
    assert "warning: the box budget ran out (max_boxes = 5" in text
    js = certificate_json(cert)
    assert "budget" in js["certificate"] and js["boxes"]["budget"].sum() == flags.sum()
    full = certify_workspace(hexa, LO, HI, MINW, max_boxes=100_000, tighten=0)
    assert not full.summary()["budget_exhausted"]
    assert "budget ran out" not in certificate_text(full, "mm", "deg")
    assert "budget" not in certificate_json(full)["certificate"]


@pytest.mark.parametrize("call, field", [
    (lambda m: certify_workspace(None, LO, HI, MINW), "mech"),
    (lambda m: certify_workspace("hunt", LO, HI, MINW), "mech"),
    (lambda m: branch_and_prune(None, LO, HI, MINW), "mech"),
    (lambda m: branch_and_prune(m, LO, HI, MINW, form="bogus"), "form"),
    (lambda m: branch_and_prune(m, LO, HI, MINW, max_boxes=0), "max_boxes"),
    (lambda m: branch_and_prune(m, LO, HI, MINW, max_boxes=-5), "max_boxes"),
    (lambda m: branch_and_prune_batched(m, LO, HI, MINW, max_boxes=0), "max_boxes"),
    (lambda m: certify_box(m, m.kernels("arb"), LO, HI, form="quadratic64"), "form"),
])
def test_lower_level_entry_points_check_their_input(hexa, call, field):
    """QA F8: these raised AttributeError or a bare ValueError, or (max_boxes <= 0)
    returned the whole region as one undecided box."""
    with pytest.raises(InputError) as exc:
        call(hexa)
    assert exc.value.field == field
