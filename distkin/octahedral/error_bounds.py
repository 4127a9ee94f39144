r"""Running error bounds of the octic kernel's quadratic parts in float64 (the proof of
:mod:`.descartes`, steps 1-3 of its docstring): rigorous bounds of the rounding errors of
the kernel's outputs (from its generated source: ``parts_magnitude`` and the constants
``PARTS_DEPTH``, ``PARTS_DEGREE``, ``PARTS_UNDERFLOW`` of
``distkin/_generated/octic_general.py``, :mod:`distkin.codegen.rounding`), of the feasible
interval's ends, and of the input's own rounding.  Rojas, Borràs and Thomas, *The
Octahedral Manipulator Revisited*, ICRA 2012, eq. (3).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._generated.octic_general import (PARTS_DEGREE, PARTS_DEPTH, PARTS_UNDERFLOW,
                                        parts_magnitude)

__all__ = ["part_errors", "part_errors_into", "part_bounds_into", "error_cache", "margin", "eta_rounded", "U",
           "ETA_FLOAT", "LEAF_BOUND", "LEAF_MIN", "GAMMA4", "UNDERFLOW"]

#: the functions that allocate nothing and return no array, compiled without numba's
#: reference counting (``_nrt=False``, perf-oct-4; :mod:`.signscan` says why); the others
#: say ``_nrt=True`` explicitly, since a callee compiled first from a ``_nrt=False``
#: caller would inherit it
_jit = numba.njit(cache=True, _nrt=True)
_leaf = numba.njit(cache=True, _nrt=False)

_magnitude_into = numba.njit(cache=True, _nrt=False)(parts_magnitude)

#: unit roundoff of binary64
U = 2.0 ** -53
#: relative error of a squared length computed from exact float coordinates
#: (a difference, a square, two sums: gamma_5) and of a squared leg (gamma_1 < gamma_5);
#: 2^-60 more covers squares of components in the subnormal range (each off by at most
#: 2^-1075, against a squared length of at least 2^-1000: LEAF_MIN)
ETA_FLOAT = 5 * U / (1 - 5 * U) + 2.0 ** -60
#: the squared lengths the bounds cover: in [LEAF_MIN, LEAF_BOUND] (after the
#: normalisation of :mod:`.scaling`, lengths are below 2^10, squared sides below 2^24)
LEAF_BOUND = 2.0 ** 24
LEAF_MIN = 2.0 ** -1000
_TINY = 2.0 ** -1074          # underflow of one product
_SAFE = 1.0 + 2.0 ** -30      # the bounds' own rounding (module docstring, step 3)
#: :math:`\gamma_4 = 4u/(1 - 4u)`, rounded up: the rounding of Horner's rule on a
#: quadratic (Higham, *Accuracy and Stability of Numerical Algorithms*, eq. (5.3):
#: :math:`\gamma_{2n}`)
GAMMA4 = 4.0 * U * (1.0 + 8.0 * U)
#: a normal number above the underflow of a bounded Horner evaluation at a float x,
#: once multiplied by (1 + |x|)^2 (:func:`part_bounds_into`; a subnormal term would
#: cost microcode assists)
UNDERFLOW = 2.0 ** -1000
_DEPTH = np.array(PARTS_DEPTH, dtype=np.float64)
_DEGREE = np.array(PARTS_DEGREE, dtype=np.float64)
_UNDER = np.array(PARTS_UNDERFLOW, dtype=np.float64)


@numba.njit(cache=True, inline="always")
def _add(a, ea, b, eb):
    v = a + b
    return v, ea + eb + U * abs(v)


@numba.njit(cache=True, inline="always")
def _mul(a, ea, b, eb):
    v = a * b
    return v, abs(a) * eb + abs(b) * ea + ea * eb + U * abs(v) + _TINY


@_jit
def part_errors(d, s2, l2, eta):
    r"""Rigorous bounds ``(30,)`` of the errors of the kernel's quadratic parts ``d[:30]``
    against the exact parts at the exact squared lengths (module docstring, step 2), or
    all ``inf`` outside the bounds' range.

    Parameters
    ----------
    d : (>= 30,) the kernel output (:func:`.single.octic_array` or a row of the
        batched kernel) at the float squared lengths ``s2``, ``l2`` (each in
        [LEAF_MIN, LEAF_BOUND])
    eta : relative error bound of those squared lengths
    """
    out = np.empty(30)
    part_errors_into(d, s2, l2, eta, out, error_cache())
    return out


@_jit
def error_cache():
    """The work array (61,) of :func:`part_errors_into`: the eta its factors are for
    (NaN: none yet), then the factors."""
    c = np.empty(61)
    c[0] = np.nan
    return c


@_leaf
def part_errors_into(d, s2, l2, eta, out, cache):
    r""":func:`part_errors` into ``out`` (30,) (or (60,): then :func:`part_bounds_into`'s
    coefficients too, in the same pass).  Per part :math:`k`, with
    :math:`t = d_k u + g_k\eta` (depth and degree of the generated kernel) and
    :math:`\gamma = t/(1-t)`: :math:`(1+u)^d(1+\eta)^g - 1 \le \gamma` and
    :math:`(1+\eta)^g/(1-u)^d \le 1/(1-t)`, so the error is at most
    :math:`\gamma(\hat A_k + U_k)/(1-t) + U_k` (:mod:`distkin.codegen.rounding`),
    computed as :math:`f_k(\hat A_k + U_k) + U_k` with :math:`f_k = \gamma/(1-t)`
    and rounded up by :data:`_SAFE` (the bounds' own rounding).  The factors
    :math:`f_k` depend on eta only: ``cache`` (:func:`error_cache`) keeps those of the
    last eta, so a batch of problems with one eta divides once."""
    if cache[0] != eta:
        for k in range(30):
            t = _DEPTH[k] * U + _DEGREE[k] * eta
            cache[1 + k] = (t / (1.0 - t)) / (1.0 - t) if t < 0.1 else np.inf
        cache[0] = eta
    ok = True
    for k in range(6):
        if not (LEAF_MIN <= s2[k] <= LEAF_BOUND and LEAF_MIN <= l2[k] <= LEAF_BOUND):
            ok = False
    if not ok:
        for k in range(30):
            out[k] = np.inf
        return
    _magnitude_into(s2, l2, out)
    for k in range(30):
        f = cache[1 + k]
        out[k] = _SAFE * (f * (out[k] + _UNDER[k]) + _UNDER[k]) if f < np.inf else np.inf
    if out.size >= 60:              # (:func:`part_bounds_into`, in the same pass)
        for k in range(30):
            out[30 + k] = _SAFE * (out[k] + GAMMA4 * abs(d[k]))


@_leaf
def part_bounds_into(d, s2, l2, eta, out, cache):
    r""":func:`part_errors_into` into ``out[:30]`` (the bounds :math:`e_k`), and into
    ``out[30:60]`` the coefficients :math:`f_k = e_k + \gamma_4|\hat c_k|` (rounded up
    by :data:`_SAFE`) of the *a priori* bound of a quadratic part at a float x
    (perf-oct-5): Horner's rule on the float coefficients is within
    :math:`\gamma_4\sum_k|\hat c_k||x|^k` of the float polynomial at x (Higham,
    *Accuracy and Stability of Numerical Algorithms*, eq. (5.3)), which is within
    :math:`\sum_k e_k|x|^k` of the exact part, so the part is within
    :math:`\sum_k f_k|x|^k` (:func:`.bounded_octic._part`; the same sum, by Horner's
    rule on non-negative floats, times :math:`1 + 8u`, plus
    :data:`UNDERFLOW` :math:`(1 + |x|)^2` for underflow).  It bounds what the running
    bound of each operation bounded before, at a third of the operations, and is at most
    a few per cent wider (the data's :math:`e_k` dominate both)."""
    part_errors_into(d, s2, l2, eta, out, cache)
    if not out[0] < np.inf:         # (outside the bounds' range: all inf)
        for k in range(30, 60):
            out[k] = np.inf


@_leaf
def margin(s2, l2, eta):
    r"""A rigorous bound on the error of the float triangle bounds of :math:`s_{15}`
    (:func:`.single.bounds`): for :math:`x, y` with relative errors at most
    :math:`\eta`, :math:`(\sqrt x \pm \sqrt y)^2` moves by at most
    :math:`(2\eta + \eta^2)(\sqrt x + \sqrt y)^2`, and the float square roots, the sum or
    difference and the square add at most :math:`6u` of the same; twice that, over the
    four triangles."""
    big = 0.0
    for a, b in ((l2[0], s2[3]), (s2[0], l2[2]), (l2[5], s2[5]), (s2[1], l2[3])):
        r = math.sqrt(a) + math.sqrt(b)
        big = max(big, r * r)
    return _SAFE * 2.0 * (2.0 * eta + eta * eta + 6.0 * U) * big * (1.0 + 4.0 * U)


@_jit
def eta_rounded(B, Q, L):
    r"""Relative error bound of the squared lengths when the coordinates ``B``, ``Q``
    (3, 3) and legs ``L`` (6,) are themselves the floats nearest to exact values
    (:math:`|x - x^*| \le u|x^*| \le 2u|x|`): per side, each difference is off by
    :math:`e = 2u(|a| + |b|) + u|\hat d|`, its square by :math:`2|\hat d|e + e^2`, and
    the squares and sums add :math:`\gamma_3` (taken as :math:`4u`) of the sum; a leg's
    square is off by at most :math:`(1 + 2u)^2(1 + u) - 1 < 6u`.

    ``B`` and ``Q`` may have different memory layouts (a row of a broadcast or copied
    batch): each triangle goes through :func:`_eta_triangle` on its own, never as a
    tuple of the two, which numba cannot iterate when their types differ (QA: a batch
    with a thin triangle and rounded inputs crashed with a TypingError)."""
    worst = max(6.0 * U, _eta_triangle(B), _eta_triangle(Q))
    return worst * (1.0 + 16.0 * U) + 2.0 ** -60


@_jit
def _eta_triangle(P):
    """The worst relative error bound of the three squared sides of the triangle ``P``
    (3, 3) under the rounding of :func:`eta_rounded`; ``inf`` when a side's bound
    covers the side."""
    worst = 0.0
    for i, j in ((0, 1), (0, 2), (1, 2)):
        s = 0.0
        err = 0.0
        for c in range(3):
            dx = P[i, c] - P[j, c]
            e = 2.0 * U * (abs(P[i, c]) + abs(P[j, c])) + U * abs(dx)
            s += dx * dx
            err += 2.0 * abs(dx) * e + e * e
        err = (err + 4.0 * U * s) * (1.0 + 16.0 * U)
        if not s - err > 0:
            return np.inf
        worst = max(worst, err / (s - err))
    return worst
