"""The public entry points of distkin.certify check their boxes (docs/design.md §4, STYLE
rule 7) and show their progress.

A box given with its corners swapped used to be classified from one corner (the radial
HEXA's region of 48 regular, 62 singular and 58 unreachable leaves came back as one
unreachable leaf), a NaN corner came back undecided with ``lo = nan``, ``min_width=True``
was taken as 1 m, and ``progress=True`` showed nothing without a store.  The checks are
compared with the correctly ordered box (its classification, and float samples of its
poses); the progress bar with the stored run's."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from distkin.certify import branch_and_prune, certify_box, certify_workspace
from distkin.certify.batch import branch_and_prune_batched, certify_batch
from distkin.certify.boxes import REGULAR, SINGULAR, UNREACHABLE
from distkin.errors import InputError
from distkin.mechanisms import preset

#: the radial HEXA, x, y in [-0.3, 0.3] m at z = 0.3 m, rz = 0.3 rad (QA report 03)
LO = np.array([-0.3, -0.3, 0.3, 0.0, 0.0, 0.3])
HI = np.array([0.3, 0.3, 0.3, 0.0, 0.0, 0.3])
MINW = [0.6 / 16] * 6


@pytest.fixture(scope="module")
def hexa():
    return preset("hexa", layout="radial")


def _bnp(mech, lo, hi, minw=MINW):
    return branch_and_prune(mech, lo, hi, minw, max_boxes=2000)


def _bnp64(mech, lo, hi, minw=MINW):
    return branch_and_prune_batched(mech, lo, hi, minw, max_boxes=2000)


def _box(mech, lo, hi, minw=MINW):
    return certify_box(mech, mech.kernels("arb"), lo, hi)


@pytest.mark.parametrize("entry", [_bnp, _bnp64])
def test_swapped_corners_are_refused_not_classified(hexa, entry):
    """The ordered region has regular, singular and unreachable leaves, each confirmed
    by float samples of its poses; the same region with its corners swapped is an
    InputError naming both corners, not a verdict."""
    r = entry(hexa, LO, HI)
    st = r["status"]
    assert {REGULAR, SINGULAR, UNREACHABLE} <= set(st.tolist())
    rng = np.random.default_rng(3)
    for b in np.flatnonzero(np.isin(st, (REGULAR, UNREACHABLE))):
        P = r["lo"][b] + rng.uniform(0, 1, (8, 6)) * (r["hi"][b] - r["lo"][b])
        margin = hexa.reach_margin(P)
        if st[b] == UNREACHABLE:
            assert np.all(np.any(margin < 0, axis=1))
        else:
            assert np.all(margin > 0)
            d = np.linalg.det(hexa.jq_jx(P)[1])
            assert np.all(np.sign(d) == r["det_sign"][b])
    with pytest.raises(InputError) as exc:
        entry(hexa, HI, LO)
    assert exc.value.field == "hi"
    assert "lo[0] = 0.3 > hi[0] = -0.3" in exc.value.message


def test_certify_box_refuses_swapped_corners(hexa):
    """A small box at z = 0.3 m: ordered, its verdict holds at sampled poses (regular:
    σmin(Jx) above the certified bound); swapped, it is refused (it used to come back
    regular)."""
    ks = hexa.kernels("arb")
    lo = np.array([-0.01, -0.01, 0.3, 0, 0, 0])
    hi = np.array([0.01, 0.01, 0.3, 0, 0, 0])
    v = certify_box(hexa, ks, lo, hi)
    assert v.status == REGULAR
    P = lo + np.random.default_rng(1).uniform(0, 1, (16, 6)) * (hi - lo)
    _, Jx = hexa.jq_jx(P)
    assert np.all(np.linalg.svd(Jx, compute_uv=False)[:, -1] >= v.sigma_lower)
    assert np.all(np.sign(np.linalg.det(Jx)) == v.det_sign)
    with pytest.raises(InputError) as exc:
        certify_box(hexa, ks, hi, lo)
    assert exc.value.field == "hi" and "lo[0]" in exc.value.message


@pytest.mark.parametrize("entry", [_bnp, _bnp64, _box])
@pytest.mark.parametrize("lo, hi, field, words", [
    ([np.nan, 0, 0.3, 0, 0, 0], [0.01, 0, 0.3, 0, 0, 0], "lo", "finite"),
    ([0, 0, 0.3, 0, 0, 0], [0.01, np.inf, 0.3, 0, 0, 0], "hi", "finite"),
    ([0, 0, 0.3, 0, 0], [0.01, 0, 0.3, 0, 0, 0], "lo", "shape (6,)"),
    ([False, 0, 0.3, 0, 0, 0], [0.01, 0, 0.3, 0, 0, 0], "lo[0]", "boolean"),
])
def test_corners_must_be_six_finite_numbers(hexa, entry, lo, hi, field, words):
    with pytest.raises(InputError) as exc:
        entry(hexa, lo, hi)
    assert exc.value.field == field and words in exc.value.message


@pytest.mark.parametrize("entry", [_bnp, _bnp64])
@pytest.mark.parametrize("minw, field", [(0.0, "min_width"), (-0.1, "min_width"),
                                         (True, "min_width"),
                                         ([0.1] * 5 + [True], "min_width[5]"),
                                         ([0.1] * 5, "min_width")])
def test_branch_and_prune_checks_its_resolution(hexa, entry, minw, field):
    """A resolution <= 0 would bisect until the budget is spent; True is not 1 m."""
    with pytest.raises(InputError) as exc:
        entry(hexa, LO, HI, minw)
    assert exc.value.field == field


def test_certify_batch_refuses_nan_and_swapped_boxes(hexa):
    """The batch form named no box and let a NaN corner through (nan < x is False)."""
    ks = hexa.kernels("arb")
    lo = np.array([[0.0, 0.0, 0.3, 0, 0, 0], [np.nan, 0.0, 0.3, 0, 0, 0]])
    hi = np.array([[0.01, 0.01, 0.3, 0, 0, 0], [0.01, 0.01, 0.3, 0, 0, 0]])
    with pytest.raises(InputError) as exc:
        certify_batch(hexa, ks, lo, hi, (0, 1))
    assert exc.value.field == "hi" and "box 1" in exc.value.message
    with pytest.raises(InputError, match="box 0"):
        certify_batch(hexa, ks, hi[:1], lo[:1], (0, 1))


@pytest.mark.parametrize("pose", [[0.0, 0.0, 0.3, 0, 0, 0.3], [0.3, 0.3, 0.3, 0, 0, 0.3]])
def test_a_single_pose_is_still_a_box(hexa, pose):
    """lo == hi (a pose, no coordinate varies) is accepted; the verdict agrees with the
    float reach margins and det Jx at that pose (the centre regular, the corner out of
    reach)."""
    pose = np.array(pose)
    r = branch_and_prune(hexa, pose, pose, MINW)
    margin = hexa.reach_margin(pose[None])[0]
    assert len(r["status"]) == 1 and np.array_equal(r["lo"][0], pose)
    if np.all(margin > 0):
        assert r["status"][0] == REGULAR
        assert r["det_sign"][0] == np.sign(np.linalg.det(hexa.jq_jx(pose[None])[1][0]))
    else:
        assert r["status"][0] == UNREACHABLE


# -- certify_workspace: resolution and progress ------------------------------------------

WLO, WHI = [-0.075, -0.075, 0.3, 0, 0, 0], [0.075, 0.075, 0.3, 0, 0, 0]


@pytest.mark.parametrize("minw, field", [(True, "min_width"), (np.True_, "min_width"),
                                         ([0.04] * 3 + [True] * 3, "min_width[3]")])
def test_workspace_refuses_a_boolean_resolution(minw, field):
    """The CLI refuses booleans; from Python min_width=True used to be 1 m, 1 rad."""
    with pytest.raises(InputError) as exc:
        certify_workspace(preset("hunt"), WLO, WHI, minw)
    assert exc.value.field == field and "boolean" in exc.value.message


def test_progress_bar_without_a_store_is_the_stored_runs(tmp_path, capsys):
    """progress=True shows the run store's bar with or without a store: the same
    description and chunk count (split ** varying coordinates); progress=False shows
    nothing; the certificates agree."""
    m = preset("hunt")
    chunks = 2 ** 2                                    # x and y vary, split = 2
    stored = certify_workspace(m, WLO, WHI, 0.075, progress=True, store=tmp_path / "s",
                               tighten=0)
    err_stored = capsys.readouterr().err
    memory = certify_workspace(m, WLO, WHI, 0.075, progress=True, tighten=0)
    err_memory = capsys.readouterr().err
    for err in (err_stored, err_memory):
        assert f"certify {m.name}" in err and f"{chunks}/{chunks}" in err
    certify_workspace(m, WLO, WHI, 0.075, progress=False, tighten=0)
    assert capsys.readouterr().err == ""
    assert np.array_equal(stored.status, memory.status)
    assert np.array_equal(stored.lo, memory.lo) and np.array_equal(stored.hi, memory.hi)


def test_executor_without_a_store_keeps_the_chunk_order(capsys):
    """Chunks on an executor without a store (futures as they finish, with the bar):
    the same boxes in the same order as in process."""
    m = preset("hunt")
    a = certify_workspace(m, WLO, WHI, 0.0375, tighten=0)
    with ThreadPoolExecutor(2) as ex:
        b = certify_workspace(m, WLO, WHI, 0.0375, executor=ex, progress=True, tighten=0)
    assert "4/4" in capsys.readouterr().err
    assert np.array_equal(a.status, b.status)
    assert np.array_equal(a.lo, b.lo) and np.array_equal(a.hi, b.hi)
