"""Bad input to the Δ-transform API: every entry point raises an error of
:mod:`distkin.errors` naming the field, what was expected and what was received, and
every tier refuses the same data the same way (no raw ValueError / IndexError, no
InfeasibleError for data that are malformed rather than infeasible).

Reference values: the Griffis-Duffy example of Rojas, Borràs, Thomas, *The Octahedral
Manipulator Revisited*, Sec. VI (docs/design.md §5): d12 = 12, d45 = 6.
"""

import re

import pytest

from distkin.delta import (delta_transform, equivalent_platform, forward_kinematics66,
                           griffis_duffy_approximation)
from distkin.errors import DegenerateGeometryError, InputError
from distkin.octahedral.scaling import MAX_EXP

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
OFF = ["12/5", "6/5"] * 3
M_LEGS = ["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)",
          "1/25*sqrt(136210)", "1/5*sqrt(8153)"]
METHODS = ("fast", "auto", "precise", "certified")
ENTRY_POINTS = {
    "delta_transform": lambda g: delta_transform(g, OFF),
    "equivalent_platform": lambda g: equivalent_platform(g, OFF),
    "forward_kinematics66": lambda g: forward_kinematics66(g, OFF, M_LEGS),
    "griffis_duffy_approximation": lambda g: griffis_duffy_approximation(g, 1),
}


@pytest.mark.parametrize("entry", sorted(ENTRY_POINTS))
@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_coordinate_names_the_coordinate(entry, bad):
    base = [[0, 0, 0], [6, bad, 0], [12, 0, 0]]
    with pytest.raises(InputError, match="finite") as err:
        ENTRY_POINTS[entry]((base, GD[1]))
    assert err.value.field == "base[1][1]" and repr(bad) in str(err.value)


@pytest.mark.parametrize("entry", sorted(ENTRY_POINTS))
def test_malformed_points_name_the_field(entry):
    with pytest.raises(InputError, match=r"expected 3 points, got 2") as err:
        ENTRY_POINTS[entry](([[0, 0, 0], [6, 0, 0]], GD[1]))
    assert err.value.field == "base"
    with pytest.raises(InputError, match=r"expected a point of 3 coordinates, got \[3, 5\]") as err:
        ENTRY_POINTS[entry]((GD[0], [[0, 0, 0], [6, 0, 0], [3, 5]]))
    assert err.value.field == "platform[2]"
    with pytest.raises(InputError, match="pair") as err:
        ENTRY_POINTS[entry](GD[0])
    assert err.value.field == "octahedral"


@pytest.mark.parametrize("legs, field, pattern", [
    ([float("inf")] + [18] * 5, "m_legs[0]", r"expected a finite leg length, got inf"),
    ([18, float("nan")] + [18] * 4, "m_legs[1]", r"expected a finite leg length, got nan"),
    ([1e200] * 6, "m_legs[0]", rf"expected lengths below 2\^{MAX_EXP}.*got 1e\+200"),
    ([18] * 5 + [-1], "m_legs[5]", r"expected a positive leg length, got -1"),
    (["x"] + M_LEGS[1:], "m_legs[0]", r"cannot parse 'x' as an exact number"),
    ([True] + M_LEGS[1:], "m_legs[0]", r"expected a leg length, got True"),
    (M_LEGS[:5], "m_legs", r"expected 6 leg lengths, got 5"),
])
def test_every_tier_refuses_bad_m_legs_alike(legs, field, pattern):
    """The same InputError (field, message) in all four tiers; the octahedral solver's
    internal names (``legs``, mapped expressions) never leak into it."""
    messages = set()
    for method in METHODS:
        with pytest.raises(InputError, match=pattern) as err:
            forward_kinematics66(GD, OFF, legs, method=method)
        assert err.value.field == field, method
        assert "sqrt(" not in err.value.message
        messages.add(str(err.value))
    assert len(messages) == 1


@pytest.mark.parametrize("offset, cls", [(13, InputError), (-1, InputError),
                                         ("12", DegenerateGeometryError),
                                         (0, DegenerateGeometryError)])
def test_offsets_outside_the_edge_are_refused_with_one_message(offset, cls):
    """0 < delta_i < d_i (the joint moves along the edge, Fig. 6): beyond the edge an
    InputError, at its ends (joints merged again) a DegenerateGeometryError, both
    saying "expected 0 < delta1 < d12 = 12 ..., got delta1 = <value>"."""
    want = re.escape(f"expected 0 < delta1 < d12 = 12 (length units) so that every joint "
                     f"is single and on its edge, got delta1 = {offset} (length units)")
    for call in (lambda: equivalent_platform(GD, [offset] + OFF[1:]),
                 lambda: forward_kinematics66(GD, [offset] + OFF[1:], M_LEGS)):
        with pytest.raises(cls, match=want) as err:
            call()
        assert err.value.field == "offsets[0]"
    with pytest.raises(InputError, match=r"0 < delta2 < d45 = 6 .*, got delta2 = 7"):
        equivalent_platform(GD, ["12/5", 7] + OFF[2:])


def test_the_offsets_in_range_still_build_the_platform():
    """Just inside both ends of every edge: accepted (the rule is strict, not shifted)."""
    for offs in (["1/1000", "1/1000"] * 3, ["11999/1000", "5999/1000"] * 3):
        plat = equivalent_platform(GD, offs)
        assert len(set(plat.base_joints)) == 6 and len(set(plat.platform_joints)) == 6



def test_coincident_points_name_the_field():
    """QA J 9: a zero-length side named no field; P1 = P2 (d12 = 0, by coordinates)."""
    from distkin.errors import DegenerateGeometryError
    with pytest.raises(DegenerateGeometryError, match="d12 = 0") as exc:
        equivalent_platform(([[0, 0, 0], [0, 0, 0], [12, 0, 0]], GD[1]), OFF)
    assert exc.value.field == "base[1]"


def test_singular_offsets_without_symmetry_name_the_closed_form_factor():
    """QA J 9: offsets 4, 4, 8, 2, 6, 3 (det A = 0; prod(d - delta) = 8*2*4*4*6*3 = 4608 =
    prod(delta), by hand) printed a 60-term expansion; now the closed form."""
    from distkin.errors import DegenerateGeometryError
    with pytest.raises(DegenerateGeometryError) as exc:
        equivalent_platform(GD, [4, 4, 8, 2, 6, 3])
    text = str(exc.value)
    assert "(12 - delta1)*(6 - delta2)*(12 - delta3)*(6 - delta4)*(12 - delta5)*(6 - delta6)" \
        in text and "delta1*delta2*delta3*delta4*delta5*delta6" in text
    assert len(text) < 400
