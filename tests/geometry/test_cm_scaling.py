"""Cayley-Menger determinants of badly scaled but regular point sets, in every tier.

The corner tetrahedron with edges x, 1, 1 along the axes has D(1,2,3,4) = 288 V^2 =
288 (x / 6)^2 = 8 x^2 (analytic).  With x = 1e20 the bordered matrix mixes squared
distances 1e40 and 1: float64 LU gets 8e40 to 1e-13, but mpmath.det called the matrix
singular (a pivot below eps times its norm) and the precise tier answered 0.
"""

from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene
from distkin.exact import mp_det
from distkin.geometry import cayley_menger, squared_distances

SCENE = """
[mechanism]
kind = "points"
points = [[0, 0, 0], ["{x}", 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
method = "{method}"
"""


@pytest.mark.parametrize("x", ["1e20", "1e40"])
def test_precise_tier_on_a_badly_scaled_tetrahedron(x):
    exact = 8 * Fraction(x) ** 2
    with mpmath.workdps(30):
        P = [[mpmath.mpf(0)] * 3, [mpmath.mpf(x), 0, 0], [0, 1, 0], [0, 0, 1]]
        P = [[mpmath.mpf(v) for v in row] for row in P]
        d = cayley_menger(squared_distances(P), (1, 2, 3, 4))
        assert abs(d / mpmath.mpf(exact.numerator) - 1) < mpmath.mpf(10) ** -25
    for method in ("fast", "precise", "certified"):
        records, _, worst = run_scene(loads_scene(SCENE.format(x=x, method=method)),
                                      progress=False)
        assert worst == 0
        value = records[0]["result"]["determinants"][0]["value"]
        value = float(Fraction(value)) if isinstance(value, str) else value
        assert value == pytest.approx(float(exact), rel=1e-12), method


def test_mp_det_is_exactly_zero_only_for_a_zero_pivot():
    """A singular matrix gives 0; a regular one whose pivot is far below eps * norm
    keeps its determinant (1e-40 here, which mpmath.det at 30 digits calls 0)."""
    with mpmath.workdps(30):
        assert mp_det([[1, 2], [2, 4]]) == 0
        assert abs(mp_det([[1e20, 0], [0, 1e-60]]) / mpmath.mpf("1e-40") - 1) < 1e-15
        assert mpmath.det(mpmath.matrix([[1e20, 0], [0, 1e-60]])) == 0   # what it replaces
        assert mp_det([[0, 1], [1, 0]]) == -1


# ------------------------------- QA J 4: an underflow is not a flat tetrahedron

_TET = [[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4]]   # V = |det[[6,0,0],[2,5,0],[1,1,4]]|/6 = 20


def test_fast_underflow_warns_with_the_value_from_coordinates():
    """D = 288 V^2 with V = 20e-180 (coordinates): 1.152e-355, below float64: the fast tier
    returns 0.0 (the nearest float) and warns with the value, as for an overflow."""
    import numpy as np
    from distkin.geometry import FloatRangeWarning, tetrahedron_volume_squared
    P = np.array(_TET, float) * 1e-60
    with pytest.warns(FloatRangeWarning, match="below the smallest") as rec:
        v = tetrahedron_volume_squared(squared_distances(P), 1, 2, 3, 4)
    assert v == 0.0
    assert float(mpmath.mpf(rec[0].message.value) / mpmath.mpf("1.152e-355")) == \
        pytest.approx(1.0, rel=1e-5)
    with pytest.warns(FloatRangeWarning, match="beyond the largest"):
        assert cayley_menger(squared_distances(np.array(_TET, float) * 1e60), (1, 2, 3, 4)) \
            == float("inf")


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_cm_query_reports_underflow_not_zero_volume(method):
    scene = loads_scene(f"""
[units]
length = "mm"
[mechanism]
kind = "points"
points = [[0, 0, 0], ["6e-60", 0, 0], ["2e-60", "5e-60", 0], ["1e-60", "1e-60", "4e-60"]]
[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
method = "{method}"
""")
    records, texts, worst = run_scene(scene)
    assert worst == 0, records
    entry = records[0]["result"]["determinants"][0]
    assert entry["tetrahedron_volume_squared"] is None
    assert "volume^2 below the float64 range, not 0" in texts[0]
    assert "1.152e-355" in texts[0]                     # 288 * (20e-180)^2, coordinates
    if method == "certified":
        assert Fraction(entry["value"]) == 288 * Fraction(20, 10 ** 180) ** 2


def test_batched_rescale_touches_only_the_odd_rows():
    """A batch with a normal, an underflowing, a degenerate (all points equal) and a tiny
    but representable tetrahedron: each row as D = 288 V^2 with V = 20 s^3 (coordinates)."""
    import numpy as np
    from distkin.geometry import FloatRangeWarning
    P = np.array(_TET, float)
    B = np.stack([P, P * 1e-60, P * 0, P * 1e-40])
    with pytest.warns(FloatRangeWarning):
        d = cayley_menger(squared_distances(B), (1, 2, 3, 4))
    np.testing.assert_allclose(d, [288 * 400.0, 0.0, 0.0, 288 * 400.0 * 1e-240], rtol=1e-12)
