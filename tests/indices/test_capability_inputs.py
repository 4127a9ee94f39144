"""Bad input to the capability functions is refused naming the field (QA round E):
a string or booleans as the slice's indices, booleans or complex numbers as the
generator or the limits, a singular mass matrix.  Reference for the accepted input:
the worst case of a box of limits is the same through every method."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.indices.capability import output_generators, worst_case_output

RNG = np.random.default_rng(4)
G = RNG.normal(size=(6, 8))
J = RNG.normal(size=(8, 6))


@pytest.mark.parametrize("keep", ["012", ["0", "1", "2"], [True, False]])
def test_keep_must_be_integers(keep):
    with pytest.raises(InputError, match="keep"):
        worst_case_output(G, -1, 1, keep=keep)


@pytest.mark.parametrize("field, args", [
    ("pmax", (G, -1, True)), ("pmin", (G, [False] * 8, 1)),
    ("G", (G.astype(complex) + 1j, -1, 1)), ("G", (G > 0, -1, 1))])
def test_booleans_and_complex_are_refused(field, args):
    with pytest.raises(InputError, match=field):
        worst_case_output(*args)


def test_mass_must_be_positive_definite():
    for bad in (np.zeros((6, 6)), [True] * 6, np.diag([1, 1, 1, 1, 1, -1.0])):
        with pytest.raises(InputError, match="mass"):
            output_generators(J, mass=bad)
    M = np.diag([0.17] * 3 + [3e-4] * 3)
    np.testing.assert_allclose(output_generators(J, mass=M)["acceleration"],
                               np.linalg.solve(M, J.T), rtol=1e-12)


def test_accepted_input_agrees_across_methods():
    keep = [0, 1, 2]
    ref = worst_case_output(G, -2.5, 2.5, keep=keep)
    assert worst_case_output(G, -2.5, 2.5, keep=np.array(keep), method="hull") == \
        pytest.approx(ref, rel=1e-12)
