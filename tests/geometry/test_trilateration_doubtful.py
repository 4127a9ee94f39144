"""Review of the fast trilateration's error estimate: h^2 negative beyond the tolerance
but within the (pessimistic, ~1e3 x on a nearly collinear base) estimate was clamped to 0
and a point returned with only an accuracy warning, for a configuration the certified
tier proves infeasible.  Now a warning says that the configuration may not exist, and a
``tol`` of the caller's decides alone, as before the estimate.  Reference: the certified
tier on the exact binary values of the same inputs."""

from __future__ import annotations

from fractions import Fraction

import pytest

from distkin.errors import ConditioningWarning, InfeasibleError
from distkin.geometry import trilaterate, trilateration_parts

P = [[0, 0, 0], [1, 0, 0], [2, 3e-6, 0]]          # nearly collinear base
X = [0.5, 3, 0]


def _sq(shift):
    s = [sum((a - b) ** 2 for a, b in zip(X, p)) for p in P]
    s[0] -= shift
    return s


def test_a_doubtful_negative_height_is_said_to_maybe_not_exist():
    sq = _sq(1e-9)
    with pytest.raises(InfeasibleError, match=r"h\^2 = -"):        # the reference
        trilateration_parts([[Fraction(x) for x in r] for r in P],
                            [Fraction(x) for x in sq], method="certified")
    with pytest.warns(ConditioningWarning) as caught:
        trilaterate(P, sq)
    said = [str(w.message) for w in caught]
    assert any("may not exist" in m for m in said)           # and the accuracy warning
    assert any("cannot vouch for its point" in m for m in said)
    with pytest.raises(InfeasibleError):                            # tol decides alone
        trilaterate(P, sq, tol=1e-13)
    with pytest.raises(InfeasibleError):                            # precise: its estimate
        trilaterate(P, sq, method="precise")                        # is small enough


def test_points_on_a_well_conditioned_plane_are_not_said_to_maybe_not_exist():
    """Points in the base's plane (h = 0, feasible: the certified tier places them) of a
    well-conditioned base: h^2 rounds to within the tolerance, no such warning."""
    import warnings
    base = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    for x in (["3/10", "2/5", 0], ["1/10", "7/10", 0], ["5/2", "-5/4", 0]):
        exact = [sum((Fraction(a) - b) ** 2 for a, b in zip(x, p)) for p in base]
        trilaterate(base, exact, method="certified")
        sq = [float(v) for v in exact]
        with warnings.catch_warnings():
            warnings.simplefilter("error", ConditioningWarning)
            trilaterate(base, sq)
