"""Printing details of the generated kernels that a numeric comparison must catch.

Second route: sympy's own ``lambdify`` of the same expression (exact mpmath evaluation
for the float literals).
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp

from distkin.codegen.emit import Kernel, kernel_source, nearest_double


def _compile(k):
    ns = {"math": math, "numpy": np, "np": np}
    exec(kernel_source(k), ns)
    return ns[k.name]


@pytest.mark.parametrize("flavour", ["scalar", "batched"])
def test_power_in_a_denominator(flavour):
    """a / x**2 must not print as a/x*x (read by Python as (a/x)*x)."""
    x, a = sp.symbols("x a")
    expr = [a / x ** 2 + 3 / (x + a) ** 3, a * x ** 4 / (2 * x ** 2)]
    f = _compile(Kernel("f", (("z", (x, a)),), expr, flavour=flavour, cse=False))
    z = [1.7, -0.3]
    got = np.asarray(f(np.array(z) if flavour == "batched" else z), float)
    ref = np.array(sp.lambdify((x, a), expr, "mpmath")(*z), float)
    np.testing.assert_allclose(got, ref, rtol=1e-15)


@pytest.mark.parametrize("flavour", ["scalar", "batched"])
def test_binary64_parameters_print_exactly(flavour):
    """A parameter substituted as a binary64 float (0.1 + 0.2, a preset length) is
    printed so that it reads back as the same double (sympy's default prints 15 digits,
    here 0.300000000000000, one ulp off)."""
    x = sp.Symbol("x")
    c = 0.1 + 0.2
    f = _compile(Kernel("g", (("z", (x,)),), [sp.Float(c) * x], flavour=flavour, cse=False))
    got = f(np.array([1.0]) if flavour == "batched" else [1.0])
    assert float(np.ravel(got)[0]) == c


#: sqrt of this integer was printed numpy.sqrt(7188024561708202275234453794882), an
#: object-dtype call numpy refuses (the squared side of a platform66 scene in inches)
BIG = 7188024561708202275234453794882


def _correctly_rounded_sqrt(n: int, r: float) -> bool:
    """Exact check, in integers and Fractions: ``r`` is the double nearest sqrt(n), i.e.
    n lies between the squares of the midpoints to r's neighbours."""
    lo = (Fraction(math.nextafter(r, 0)) + Fraction(r)) / 2
    hi = (Fraction(r) + Fraction(math.nextafter(r, math.inf))) / 2
    return lo * lo <= n <= hi * hi


@pytest.mark.parametrize("flavour", ["scalar", "batched"])
def test_constants_of_big_integers_print_as_correctly_rounded_doubles(flavour):
    """Constant irrational subexpressions (a square root of a big integer or rational,
    a product or sum of constants, pi) print as the correctly rounded double: the kernel
    runs in numpy (no Python int reaches numpy.sqrt) and agrees with mpmath's exact
    evaluation of the same expressions (second route)."""
    x = sp.Symbol("x")
    big_q = sp.Rational(2 ** 1100 + 1, 3 ** 600)             # p, q beyond float64
    expr = [sp.sqrt(BIG), sp.sqrt(BIG) * x, 3 * sp.sqrt(2) * x / 7, x + 1 + sp.sqrt(2),
            (x - sp.sqrt(5)) ** 2, sp.pi * x ** 3, sp.sqrt(big_q) * x, x ** (sp.sqrt(2) - 2),
            sp.cos(2) ** 6 * x]
    k = Kernel("h", (("z", (x,)),), expr, flavour=flavour)
    src = kernel_source(k)
    assert "sqrt(7188" not in src and "numpy.pi" not in src
    f = _compile(k)
    z = 1.7
    got = np.ravel(np.asarray(f(np.array([[z]]) if flavour == "batched" else [z]), float))
    with mpmath.workdps(40):
        ref = np.array(sp.lambdify(x, expr, "mpmath")(mpmath.mpf(z)), float)
    np.testing.assert_allclose(got, ref, rtol=4e-16 * 8)
    assert _correctly_rounded_sqrt(BIG, float(got[0]))
    with mpmath.workprec(200):
        assert got[0] == float(mpmath.sqrt(BIG))


def test_nearest_double_is_correctly_rounded():
    """nearest_double against exact integer checks (square roots) and mpmath at 200 bits
    (rounded once); overflow gives an infinity, a complex constant None."""
    rng = np.random.default_rng(1)
    for _ in range(200):
        n = int(rng.integers(1, 2 ** 62)) * 10 ** int(rng.integers(0, 60)) + 1
        assert _correctly_rounded_sqrt(n, nearest_double(sp.sqrt(n)))
    for e in (sp.pi, sp.E, sp.sqrt(2) + sp.sqrt(3), sp.cbrt(BIG), sp.sin(1)):
        assert nearest_double(e) == float(mpmath.mpf(sp.N(e, 70), prec=200))
    assert nearest_double(sp.sqrt(10 ** 700 + 1)) == math.inf
    assert nearest_double(-sp.sqrt(10 ** 700 + 1)) == -math.inf
    assert nearest_double(sp.sqrt(-2)) is None
