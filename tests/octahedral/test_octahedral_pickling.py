"""Results that hold the certified tier's arb balls survive pickle and deepcopy (QA:
python-flint cannot pickle an ``arb``, so a certified result, or an ``auto`` one the
certified tier answered, raised TypeError in pickle.dumps, copy.deepcopy and so in
multiprocessing).  Checked against the balls themselves: every restored ball has the
same exact midpoint and encloses the original one, and the roots are still the
Griffis-Duffy values printed in Rojas et al. (ICRA 2012), Sec. VI."""

from __future__ import annotations

import copy
import pickle

import flint
import pytest

from distkin.exact_roots import ball_ends, pickle_balls, unpickle_balls, working_precision
from distkin.octahedral import forward_kinematics

BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
LEGS = ["19.8", 18, 18, 17, "14.9", "17.8"]
PAPER = [269.2, 328.7, 359.5, 463.6, 497.9, 513.0]      # Sec. VI, the six real roots


def _encloses(outer, inner):
    lo, hi = ball_ends(outer)
    a, b = ball_ends(inner)
    return lo <= a and b <= hi and outer.mid() == inner.mid()


def _balls(native):
    if type(native).__name__ == "arb":
        yield native
    elif isinstance(native, dict):
        for v in native.values():
            yield from _balls(v)
    elif isinstance(native, (list, tuple)):
        for v in native:
            yield from _balls(v)


@pytest.mark.parametrize("roundtrip", [lambda r: pickle.loads(pickle.dumps(r)),
                                       copy.deepcopy], ids=["pickle", "deepcopy"])
def test_certified_result_round_trips_with_its_balls(roundtrip):
    res = forward_kinematics(BASE, PLAT, LEGS, method="certified", tol=1e-30)
    again = roundtrip(res)
    assert again == res and len(again) == 12
    assert [round(r.value, 1) for r in again.assembly_roots] == PAPER
    pairs = [(a.native, b.native) for a, b in zip(res.roots, again.roots)]
    pairs += [(x, y) for p, q in zip(res, again)
              for x, y in zip(_balls(p.native), _balls(q.native))]
    assert len(pairs) == 6 + 12 * (1 + 9 + 9 + 3)
    assert all(_encloses(b, a) for a, b in pairs)
    assert not again[0].points.flags.writeable          # read-only, as built


def test_auto_answered_by_the_certified_tier_pickles():
    # six legs of 1 on the Griffis-Duffy triangles: float64 splits a multiple root,
    # the fast answer is refused (README, verdict 10) and the certified tier answers
    res = forward_kinematics(BASE, PLAT, [1] * 6, method="auto")
    assert res.tier == "certified"
    assert pickle.loads(pickle.dumps(res)) == res


def test_a_wide_precision_ball_keeps_its_midpoint_exactly():
    with working_precision(4000):
        ball = flint.arb(2).sqrt()
    (back,) = unpickle_balls(pickle.loads(pickle.dumps(pickle_balls([ball]))))
    assert _encloses(back, ball)
    with working_precision(4000):
        assert back.contains(flint.arb(2).sqrt()) and back.rad() < flint.arb(2) ** -3990
