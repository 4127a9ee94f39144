"""A leg length that is positive but rounds to 0 in float64 (``"1e-400"``) is refused as
such, not as "expected a positive leg length" (QA: the message denied what the user
wrote).  Reference: the exact value is positive (10^-400 > 0) and its float64 rounding
is 0 (below the smallest subnormal, 2^-1074 ~ 4.9e-324)."""

from fractions import Fraction

import pytest

from distkin.app.scene import loads_scene
from distkin.errors import InputError

OCTA = ('[mechanism]\nkind = "octahedral"\n'
        'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
        'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n')
P66 = ('[mechanism]\nkind = "platform66"\n'
       'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
       'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
       'offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]\n')


def _fk(head, first):
    return head + f'[[query]]\ntype = "forward_kinematics"\nlegs = [{first}, 18, 18, 17, 15, 18]\n'


def test_the_reference():
    assert Fraction(1, 10 ** 400) > 0 and float(Fraction(1, 10 ** 400)) == 0.0


@pytest.mark.parametrize("head", [OCTA, P66], ids=["octahedral", "platform66"])
@pytest.mark.parametrize("first", ['"1e-400"', '"sqrt(2)*10**-400"'])
def test_a_positive_length_below_float64_is_refused_as_such(head, first):
    with pytest.raises(InputError) as err:
        loads_scene(_fk(head, first))
    msg = err.value.one_line()
    assert err.value.field == "query[0].legs[0]"
    assert "rounds to 0" in msg and "expected a positive leg length" not in msg


@pytest.mark.parametrize("head", [OCTA, P66], ids=["octahedral", "platform66"])
@pytest.mark.parametrize("first", ['"-3"', "0", '"-1e-400"'])
def test_a_length_that_is_not_positive_is_refused_as_before(head, first):
    with pytest.raises(InputError) as err:
        loads_scene(_fk(head, first))
    assert "expected a positive leg length" in err.value.one_line()
    assert err.value.field == "query[0].legs[0]"


def test_delta_transform_m_legs_too():
    scene = (OCTA + '[[query]]\ntype = "delta_transform"\noffsets = ["12/5", "6/5", "12/5", '
             '"6/5", "12/5", "6/5"]\nm_legs = ["1e-400", 18, 18, 17, 15, 18]\n')
    with pytest.raises(InputError) as err:
        loads_scene(scene)
    assert err.value.field == "query[0].m_legs[0]" and "rounds to 0" in err.value.one_line()
