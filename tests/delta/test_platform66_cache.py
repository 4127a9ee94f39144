"""The built 6-6 platform is reused for the same raw inputs (the 6-6 forward kinematics
parsed the mechanism's string coordinates with sympy on every call; BENCHMARKS (49)),
and only for the same inputs: a value of another type, a changed list, or an input the
key does not know is built again.  Independent check: the platform built afresh
through the uncached builder."""

from fractions import Fraction

import numpy as np
import pytest

from distkin.delta import equivalent_platform
from distkin.delta import platform66 as p66
from distkin.delta.exact_input import _input_key
from distkin.errors import InputError

BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
OFFS = ["12/5", "6/5"] * 3


def test_same_inputs_give_the_same_object_as_an_uncached_build():
    import sympy as sp
    a = equivalent_platform((BASE, PLAT), OFFS)
    b = equivalent_platform(([list(p) for p in BASE], [list(p) for p in PLAT]), list(OFFS))
    assert a is b
    # sympy values have no key: built through the uncached path, equal by value
    sym = equivalent_platform((BASE, PLAT), [sp.Rational(12, 5), sp.Rational(6, 5)] * 3)
    assert sym.base_joints == a.base_joints and sym.platform_joints == a.platform_joints
    # [1] Fig. 6: joint 1 moved from P1 by delta1/d12 = (12/5)/12 = 1/5 along P1 -> P2
    assert a.base_joints[0] == (sp.Rational(6, 5), 6 * sp.sqrt(3) / 5, 0)


def test_a_changed_list_is_built_again():
    offs = list(OFFS)
    a = equivalent_platform((BASE, PLAT), offs)
    offs[0] = "5/2"
    b = equivalent_platform((BASE, PLAT), offs)
    assert a is not b
    assert str(a.transform.offsets[0]) == "12/5" and str(b.transform.offsets[0]) == "5/2"


@pytest.mark.parametrize("x, y", [(1.0, 1), (1.0, "1.0"), (0.1, "0.1"), (True, 1),
                                  (np.float32(0.1), 0.1), (Fraction(1, 2), "1/2")])
def test_values_read_differently_never_share_a_key(x, y):
    assert _input_key(x) != _input_key(y)


def test_floats_key_by_their_bits_and_arrays_by_dtype_and_shape():
    assert _input_key(0.1) == _input_key(np.float64(0.1))
    assert _input_key(np.zeros((3, 3))) != _input_key(np.zeros((9,)))
    assert _input_key(np.zeros(3, dtype=np.int64)) != _input_key(np.zeros(3))
    assert _input_key(object()) is None and _input_key([1, object()]) is None


def test_bad_input_is_refused_every_time_and_never_cached():
    bad = list(OFFS)
    bad[2] = "nan"
    for _ in range(2):
        with pytest.raises(InputError, match=r"offsets\[2\]|delta3"):
            equivalent_platform((BASE, PLAT), bad)
    assert _input_key(((BASE, PLAT), bad)) not in p66._built


def test_cache_is_bounded():
    for k in range(80):
        equivalent_platform((BASE, PLAT), [f"1/{k + 3}"] + OFFS[1:])
    assert len(p66._built) <= 64
