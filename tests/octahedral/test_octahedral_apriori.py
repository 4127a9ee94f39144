"""The a priori bounds of the quadratic parts at a point (perf-oct-5,
:func:`distkin.octahedral.error_bounds.part_bounds_into`, used by
:func:`distkin.octahedral.bounded_octic._part` and ``_range``) against exact rational
arithmetic: every exact part, octic value and part range within the claimed bounds,
the worst perturbation of the coefficients within their proved errors included."""

from fractions import Fraction

import numba
import numpy as np
import pytest

from distkin.octahedral import bounded_octic as bo
from distkin.octahedral.error_bounds import ETA_FLOAT, error_cache, part_bounds_into


@numba.njit
def _part_at(d, e, i, x):
    return bo._part(d, e, i, x)


@numba.njit
def _value_at(d, e, x):
    return bo._value(d, e, x)


@numba.njit
def _range_at(d, e, i, x, rho):
    return bo._range(d, e, i, x, rho)


def _problems(n, seed):
    from distkin.octahedral.problem import float_problem
    from distkin.octahedral.reference import random_octahedron
    from distkin.octahedral.single import octic_array
    rng = np.random.default_rng(seed)
    for _ in range(n):
        _, _, _, s2, l2, _, _ = float_problem(*random_octahedron(rng)[:3])
        d = octic_array(s2[0], l2[0])
        e = np.empty(60)
        part_bounds_into(d, s2[0], l2[0], ETA_FLOAT, e, error_cache())
        yield rng, d, e


def _points(rng, d):
    """Points where the parts cancel (near their roots and the octic's), and others."""
    xs = [0.0, float(rng.uniform(-50, 50)), float(rng.normal() * 1e6), 1e-300]
    for i in range(10):
        r = np.roots(d[3 * i:3 * i + 3][::-1])
        xs += [float(v.real) for v in r if abs(v.imag) < 1e-9 * (1 + abs(v))]
    return xs


@pytest.mark.parametrize("seed", [3, 4])
def test_part_bound_covers_the_worst_exact_part(seed):
    """Each part at x, against the exact part with every coefficient moved by its whole
    error bound in the direction that moves the value most (both directions)."""
    for rng, d, e in _problems(25, seed):
        for x in _points(rng, d):
            X = Fraction(x)
            for i in range(10):
                q, eq = _part_at(d, e, i, x)
                for s in (1, -1):
                    exact = sum((Fraction(float(d[3 * i + k])) + s * np.sign(x) ** k
                                 * Fraction(float(e[3 * i + k]))) * X ** k for k in range(3))
                    assert abs(Fraction(q) - exact) <= Fraction(eq), (i, x)


@pytest.mark.parametrize("seed", [5])
def test_octic_value_and_part_ranges_hold_exactly(seed):
    """H(x) = G^2 - 4 R1 R2 from parts with coefficients moved at random within their
    bounds, exactly; and each part over [x - rho, x + rho] (its ends and its vertex)
    has the sign ``_range`` proves."""
    for rng, d, e in _problems(15, seed):
        for x in _points(rng, d):
            X = Fraction(x)
            h, eh = _value_at(d, e, x)
            for _ in range(3):
                c = [Fraction(float(d[k])) + Fraction(float(rng.uniform(-1, 1)))
                     * Fraction(float(e[k])) for k in range(30)]
                q = [c[3 * i] + X * (c[3 * i + 1] + X * c[3 * i + 2]) for i in range(10)]
                H = (q[0] * q[5] + q[1] * q[4] + 2 * q[2] * q[3]) ** 2 \
                    - 4 * q[6] * q[7] * q[8] * q[9]
                assert abs(Fraction(h) - H) <= Fraction(eh), x
            rho = abs(x) * 1e-3 + 1e-3
            for i in range(10):
                s = _range_at(d, e, i, x, rho)
                if s == 0:
                    continue
                for sgn in (1, -1):
                    c = [Fraction(float(d[3 * i + k])) + sgn * Fraction(float(e[3 * i + k]))
                         * (1 if k != 1 else -1) for k in range(3)]
                    ys = [X - Fraction(rho), X + Fraction(rho)]
                    if c[2] != 0:
                        v = -c[1] / (2 * c[2])
                        if ys[0] <= v <= ys[1]:
                            ys.append(v)
                    for y in ys:
                        val = c[0] + y * (c[1] + y * c[2])
                        assert val * s > 0, (i, x)
