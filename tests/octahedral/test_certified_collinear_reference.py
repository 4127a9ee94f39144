"""P5 exactly on the base edge P1P2 at a rational root: the certified tier's exact path
raised DegenerateGeometryError ('three non-collinear reference points'), so ``auto``
failed outright instead of handing the problem to the precise tier (review).  Now it
is an UncertifiedError, as on the balls' path, and ``auto`` answers, its count marked
not certified."""

from __future__ import annotations

import warnings
from fractions import Fraction as F

import pytest

from distkin.errors import UncertifiedError
from distkin.octahedral import forward_kinematics

PAIRS = [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (0, 2)]
BASE = [[0, 0, 0], [4, 0, 0], [2, 3, 0]]
PLATFORM = [[1, -1, 2], [3, 0, 0], [1, 2, 1]]          # P5 = (3, 0, 0) on P1P2


def _legs():
    sq = lambda a, b: sum((F(x) - F(y)) ** 2 for x, y in zip(a, b))  # noqa: E731
    return [f"sqrt({sq(BASE[i], PLATFORM[j])})" for i, j in PAIRS]


def test_certified_says_uncertified_and_auto_answers():
    with pytest.raises(UncertifiedError, match="trilateration at the certified root"):
        forward_kinematics(BASE, PLATFORM, _legs(), method="certified")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = forward_kinematics(BASE, PLATFORM, _legs(), method="auto")
    assert res.tier == "precise" and "certified" in res.tier_reason
