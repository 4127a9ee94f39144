"""The evidence behind a root of det J along a path (QA path24): path_sign_changes
names the two points of opposite signs each root comes from, certify_crossing says
when arb proved one sign at both ends of a bracket (no crossing shown there), and
PosePath.at_precise evaluates the path from its exact ends.  References: exact
rational arithmetic (Fraction) and closed forms."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from distkin.errors import UncertifiedError
from distkin.singularity import PosePath, certify_crossing, path_sign_changes


def test_sign_changes_carry_their_evidence():
    f = lambda s: np.cos(9 * np.asarray(s))  # noqa: E731  roots pi/18 (2k + 1)
    changes, _, _ = path_sign_changes(f, 50, refine=True)
    assert [round(c.s, 12) for c in changes] == [round(np.pi / 18 * k, 12) for k in (1, 3, 5)]
    for c in changes:
        assert c.lo < c.s < c.hi and c.f_lo * c.f_hi < 0
        assert (c.f_lo, c.f_hi) == (float(f(c.lo)), float(f(c.hi)))


def test_root_pair_evidence_is_the_minimum_between_them():
    # (s - 0.5)^2 - 1e-6: roots 0.499, 0.501 inside one of 10 sample intervals
    f = lambda s: (np.asarray(s) - 0.5) ** 2 - 1e-6  # noqa: E731
    a, b = path_sign_changes(f, 10, refine=True)[0]
    assert a.s == pytest.approx(0.499, abs=1e-12) and b.s == pytest.approx(0.501, abs=1e-12)
    assert a.hi == b.lo and a.f_hi < 0 < a.f_lo and b.f_lo < 0 < b.f_hi


def test_certify_crossing_names_brackets_of_one_sign():
    import flint
    # (s - 1/2)^2 + 1/10^6 > 0 exactly: every bracket has + at both ends
    f = lambda s: (flint.fmpq(s) - flint.fmpq(1, 2)) ** 2 + flint.fmpq(1, 10 ** 6)  # noqa: E731
    with pytest.raises(UncertifiedError) as exc:
        certify_crossing(f, 0.5)
    assert exc.value.same_sign and all(sg == 1 for _, _, sg in exc.value.same_sign)
    for a, b, _ in exc.value.same_sign:
        assert (Fraction(a) - Fraction(1, 2)) ** 2 + Fraction(1, 10 ** 6) > 0
    # a ball containing 0 at every bracket: nothing proved, nothing listed
    with pytest.raises(UncertifiedError) as exc:
        certify_crossing(lambda s: flint.arb(0, 1), 0.5)
    assert exc.value.same_sign == []


def test_at_precise_uses_the_exact_ends():
    third = Fraction(1, 3)
    p = PosePath((Fraction(0),) * 3, (Fraction(0),) * 3, (third, Fraction(0), Fraction(1)),
                 (Fraction(0),) * 3)
    import mpmath
    R, t = p.at_precise(Fraction(1, 7), 40)
    with mpmath.workdps(40):
        assert abs(t[0] - mpmath.mpf(1) / 21) < mpmath.mpf(10) ** -38   # 1/3 * 1/7
    assert R[0][0] == 1
