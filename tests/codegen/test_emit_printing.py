"""Printing details of the generated kernels that a numeric comparison must catch.

Second route: sympy's own ``lambdify`` of the same expression (exact mpmath evaluation
for the float literals).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from distkin.codegen.emit import Kernel, kernel_source


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
