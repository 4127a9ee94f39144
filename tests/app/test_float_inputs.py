"""A bare float in a scene is taken as its exact binary value "and the result says so"
(docs/design.md §3): the exact queries name every such input in their JSON
(``inputs_from_float``) and their text, with the exact value of one.  They used not to
say so at all, although a certified answer then belongs to 19.800000000000000710... and
not to 19.8.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene

OCTA = """
[mechanism]
kind = "octahedral"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]

[[query]]
type = "forward_kinematics"
legs = {legs}
method = "certified"
"""

POINTS = """
[mechanism]
kind = "points"
points = [[0, 0, 0], [{x}, 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
method = "certified"
"""


def _run(text):
    records, texts, worst = run_scene(loads_scene(text), progress=False)
    assert worst == 0, records
    return records[0]["result"], texts[0]


def test_octahedral_legs_given_as_floats_are_named():
    res, text = _run(OCTA.format(legs="[19.8, 18, 18, 17, 14.9, 17.8]"))
    assert res["inputs_from_float"] == ["legs[0]", "legs[4]", "legs[5]"]   # 18, 17: TOML ints
    assert f"19.8 is {Decimal(19.8)}" in text and "legs[0], legs[4], legs[5]" in text
    # [1] Sec. VI: six real roots, which the binary values keep
    assert res["real_roots"]["count"] == 6 and len(res["poses"]) == 12
    res, text = _run(OCTA.format(legs='["19.8", "18", "18", "17", "14.9", "17.8"]'))
    assert res["inputs_from_float"] == [] and "bare floats" not in text


def test_points_given_as_floats_are_named_and_used_exactly():
    """D(1,2,3,4) of the corner with edges x, 1, 1 is 288 (x/6)^2 = 8 x^2 exactly; with
    x = 0.1 written bare that is 8 Fraction(0.1)^2, not 2/25."""
    res, text = _run(POINTS.format(x="0.1"))
    assert res["inputs_from_float"] == ["mechanism.points[1][0]"]
    exact = 8 * Fraction(0.1) ** 2
    assert res["determinants"][0]["value"] == f"{exact.numerator}/{exact.denominator}"
    assert f"0.1 is {Decimal(0.1)}" in text
    res, text = _run(POINTS.format(x='"0.1"'))
    assert res["inputs_from_float"] == [] and res["determinants"][0]["value"] == "2/25"


def test_scene_units_keep_exact_coordinates_exact():
    """A coordinate in mm given exactly ("sqrt(108) - 1/10**18") is converted to metres
    exactly: sympy's nsimplify used to snap its small irrational part away (so that the
    certified tier would solve a neighbouring problem)."""
    from fractions import Fraction

    import sympy as sp

    from distkin.app.queries.octahedral import _si
    from distkin.exact import parse_exact
    v = parse_exact("sqrt(108) - 1/10**18", "base[1][1]")
    got = _si(v, Fraction(1, 1000)).value
    assert sp.simplify(got - (sp.sqrt(108) - sp.Rational(1, 10 ** 18)) / 1000) == 0
    assert got != sp.sqrt(108) / 1000
