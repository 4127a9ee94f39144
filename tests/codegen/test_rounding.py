"""Rigorous rounding bounds of generated kernels (:mod:`distkin.codegen.rounding`).

Two routes: hand-counted depths of small sources (analytic), and the bound of the
octahedral kernel's quadratic parts against their exact values (the ``fmpq`` kernel on
the exact inputs) on random and hard problems -- the bound must hold everywhere, and it
must not be vacuous.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from distkin.codegen.rounding import analyse, magnitude_source

SRC = '''
def k(x, y):
    a = x[0]
    b = x[1]
    c = y[0]
    _c0 = a*b - 3*c
    _c1 = 2*_c0 + a*a*a
    return [_c0, _c1, -_c0*c]
'''


def test_depths_degrees_and_magnitudes_of_a_small_kernel():
    """By hand: a*b (1 rounding) - 3*c (1) -> depth 2, degree 2; 2*_c0 is exact (depth 2),
    a*a*a has depth 2 (two products), the sum 3, degree 3; -_c0*c: 2 + 0 + 1 = 3,
    degree 3.  The magnitude kernel is the same code with absolute values."""
    b = analyse(SRC, "k")
    assert b.depth == (2, 3, 3) and b.degree == (2, 3, 3)
    assert all(u > 0 for u in b.underflow) and max(b.underflow) < 1e-300
    ns = {}
    exec(magnitude_source(SRC, "k", "k_mag", "doc"), ns)
    assert ns["k_mag"]([-2.0, 5.0], [-7.0]) == [10 + 21, 2 * 31 + 8, 31 * 7]


@pytest.mark.parametrize("body", ["x[0] / x[1]", "x[0] ** 5", "math.sqrt(x[0])", "0.5 * x[0]"])
def test_the_analysis_refuses_what_it_does_not_model(body):
    with pytest.raises(ValueError):
        analyse(f"def k(x):\n    a = x[0]\n    return [{body}]\n", "k")


def _exact_parts(s2, l2):
    import flint

    from distkin._generated.octic_general import octic_exact
    q = [flint.fmpq(*Fraction(v).as_integer_ratio()) for v in list(s2) + list(l2)]
    return [Fraction(int(flint.fmpq(c).p), int(flint.fmpq(c).q))
            for c in octic_exact(q[:6], q[6:])[:30]]


def test_part_bounds_hold_and_are_not_vacuous():
    """For 300 random octahedra and the hard set's Griffis-Duffy folds: every computed
    quadratic-part coefficient of the compiled kernel lies within its bound of the exact
    coefficient at the same (float, hence exact) squared lengths; and some actual error
    reaches more than a tenth of its bound (a bound, not a blanket: a single rounding
    of a sum of positive terms reaches 99.9 % of it here, the median is 3 %)."""
    from distkin.octahedral.descartes import part_errors
    from distkin.octahedral.single import octic_array
    from distkin.octahedral.hardset import hard_set
    from distkin.octahedral.problem import float_problem
    from distkin.octahedral.reference import random_octahedron
    rng = np.random.default_rng(21)
    probs = [random_octahedron(rng)[:3] for _ in range(300)]
    probs += [(c.base, c.platform, c.legs) for c in hard_set()[:20]]
    tight = 0.0
    for b, p, l in probs:
        _, _, _, s2, l2, _, _ = float_problem(b, p, l)
        d = octic_array(s2[0], l2[0])
        e = part_errors(d, s2[0], l2[0], 0.0)          # the squared lengths are exact
        exact = _exact_parts(s2[0], l2[0])
        for k in range(30):
            err = abs(Fraction(float(d[k])) - exact[k])
            assert err <= Fraction(e[k]), (k, float(err), e[k])
            if err and e[k]:
                tight = max(tight, float(err) / e[k])
    assert tight > 0.1
    assert math.isfinite(tight)
