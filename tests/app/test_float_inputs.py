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
    assert res["inputs_from_float"] == ["query[0].legs[0]", "query[0].legs[4]",
                                        "query[0].legs[5]"]   # 18, 17: TOML ints
    assert f"19.8 is {Decimal(19.8)}" in text
    assert "query[0].legs[0], query[0].legs[4], query[0].legs[5]" in text
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
    """A coordinate in mm given exactly ("sqrt(108) - 1/10**18") reaches the exact tiers
    exactly: the octahedral queries solve the geometry as written, in the scene's
    unit (QA R 4; a conversion to metres by sympy's nsimplify once snapped its small
    irrational part away).  Reference: the same scene without units, whose precise
    roots (irrational squared sides: no certified tier) are bit for bit the same."""
    import sympy as sp

    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = ('[mechanism]\nkind = "octahedral"\n'
            'base = [[0, 0, 0], [6, "sqrt(108) - 1/10**18", 0], [12, 0, 0]]\n'
            'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n[[query]]\n'
            'type = "forward_kinematics"\nlegs = ["19.8", "18", "18", "17", "14.9", "17.8"]\n'
            'method = "precise"\ndps = 40\n')
    mm = loads_scene('[units]\nlength = "mm"\n' + text)
    got = mm.mechanism.base[1][1].value
    assert sp.simplify(got - (sp.sqrt(108) - sp.Rational(1, 10 ** 18))) == 0
    plain = loads_scene('[units]\nlength = "none"\n' + text)
    a, _, wa = run_scene(mm, progress=False)
    b, _, wb = run_scene(plain, progress=False)
    assert wa == wb == 0
    assert a[0]["result"]["real_roots"]["values"] == b[0]["result"]["real_roots"]["values"]
    assert a[0]["result"]["unit"]["s15"] == "mm^2"


def test_float_inputs_are_named_by_their_full_paths_in_every_query():
    """QA: the octahedral and Δ queries named bare-float inputs ``legs[0]`` while
    ``cayley_menger`` and the errors name ``mechanism.points[3][2]``, ``query[2].legs[0]``;
    a scene with several queries must say which one.  Reference: the scene's own input,
    the entries written as bare floats (TOML ints and strings are exact)."""
    exact = '["19.8", "18", "18", "17", "14.9", "17.8"]'
    bare = '["19.8", 18.0, "18", 17.0, "14.9", "17.8"]'     # legs[1], legs[3] bare floats
    floats = [1, 3]
    text = (OCTA.format(legs=exact) + '\n[[query]]\ntype = "forward_kinematics"\n'
            f'legs = {bare}\nmethod = "certified"\n')
    records, texts, worst = run_scene(loads_scene(text), progress=False)
    assert worst == 0, records
    assert records[0]["result"]["inputs_from_float"] == []
    want = [f"query[1].legs[{i}]" for i in floats]
    assert records[1]["result"]["inputs_from_float"] == want
    assert ", ".join(want) in texts[1]
    # the same six roots as the exact legs: 18.0 and 17.0 are exact binary values
    assert records[1]["result"]["real_roots"]["values"] == \
        records[0]["result"]["real_roots"]["values"]


def test_delta_transform_float_inputs_carry_the_query_index():
    """The Δ-transform's own offsets and m-legs, written as bare floats, are named
    ``query[1].offsets[i]`` and ``query[1].m_legs[i]``; the platform66 forward
    kinematics' legs ``query[0].legs[i]``.  Reference: the scene's own input."""
    head = ('[mechanism]\nkind = "platform66"\nbase = [[0, 0, 0], [6, "sqrt(108)", 0], '
            '[12, 0, 0]]\nplatform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
            'offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]\n')
    q0 = ('[[query]]\ntype = "forward_kinematics"\nlegs = [19.5, "18", "18", "17", "15", '
          '"18"]\nmethod = "precise"\n')
    q1 = ('[[query]]\ntype = "delta_transform"\noffsets = [2.4, "6/5", "12/5", "6/5", '
          '"12/5", "6/5"]\nm_legs = ["19", 18.5, "18", "17", "15", "18"]\nsolve = false\n')
    records, texts, worst = run_scene(loads_scene(head + q0 + q1), progress=False)
    assert worst == 0, records
    assert records[0]["result"]["inputs_from_float"] == ["query[0].legs[0]"]
    assert "query[0].legs[0] " in texts[0]
    assert records[1]["result"]["inputs_from_float"] == ["query[1].m_legs[1]",
                                                        "query[1].offsets[0]"]
    assert "query[1].m_legs[1], query[1].offsets[0]" in texts[1]
