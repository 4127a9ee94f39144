r"""Certified zero exclusion of det Ĵ along a path of poses of the octahedral manipulator
(Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, eq. (5)), by the
mean-value form over intervals of the path parameter.

For an interval :math:`I = [m - r, m + r]` of s,
:math:`f(I) \subset f(m) + f'(I)\,[-r, r]` (mean value theorem), with
:math:`f = \det\hat{\mathbf J}(s)` (rows :math:`(p_k - b_k,\; b_k\times(p_k - b_k))`,
unnormalised) and :math:`f'(I)` an arb enclosure of its derivative over :math:`I`:
the pose, the six leg lines and the determinant are evaluated as arb power series in
:math:`s = I + x` (python-flint ``arb_series``, two terms).  When the enclosure excludes
0, det J has no zero in :math:`I`; intervals that do not are bisected, down to a width
and a budget, and what is left is reported undecided (QA F2: a grid of float samples
missed two crossings inside one sample interval).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .conditions import OCTAHEDRAL_LEGS

__all__ = ["ZeroExclusion", "det_series", "exclude_zeros", "monotone_on"]


def _series(v):
    import flint
    return v if isinstance(v, flint.arb_series) else flint.arb_series([v], prec=2)


def _rotation(w):
    """Rodrigues (rotation vector ``w``: 3 arb_series, rad) as 3 x 3 arb_series."""
    th2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    th = th2.sqrt()
    a = th.sin() / th
    b = (1 - th.cos()) / th2
    x, y, z = w
    zero = 0 * x
    K = [[zero, -z, y], [z, zero, -x], [-y, x, zero]]
    K2 = [[sum((K[i][k] * K[k][j] for k in range(3)), zero) for j in range(3)] for i in range(3)]
    return [[(1 if i == j else 0) + a * K[i][j] + b * K2[i][j] for j in range(3)]
            for i in range(3)]


def _det(A):
    """Determinant of a 6 x 6 list of arb_series: Laplace expansion along the rows with
    the minors of each column subset computed once (6 2^5 products)."""
    n = len(A)
    memo = {}

    def minor(row, cols):
        if row == n:
            return 1
        key = cols
        if key in memo:
            return memo[key]
        acc = None
        sign = 1
        for j in range(n):
            if cols >> j & 1:
                term = A[row][j] * minor(row + 1, cols & ~(1 << j))
                acc = (term if sign > 0 else -term) if acc is None else \
                    (acc + term if sign > 0 else acc - term)
                sign = -sign
        memo[key] = acc
        return acc
    return minor(0, (1 << n) - 1)


def det_series(path, base, platform, s):
    r"""det Ĵ at :math:`s + x` as an arb_series in x (two terms: the value and the
    derivative in s, each enclosed over the ball ``s``).

    Parameters
    ----------
    path : :class:`~distkin.singularity.PosePath`
    base, platform : array (3, 3) of arb
        P1..P3 (base frame) and P4..P6 (platform frame), length units.
    s : arb
        A ball of the path parameter.

    Returns
    -------
    flint.arb_series
        Coefficient 0 encloses det Ĵ over ``s``, coefficient 1 its derivative (length
        units^9 per unit of s).
    """
    import flint

    from .paths import _arb
    x = flint.arb_series([s, 1], prec=2)          # two terms: value and derivative
    lerp = lambda a, b: [_arb(u) + x * (_arb(v) - _arb(u)) for u, v in zip(a, b)]  # noqa: E731
    t = lerp(path.t0, path.t1)
    if all(_arb(v) == 0 for v in (*path.w0, *path.w1)):
        R = [[_series(flint.arb(int(i == j))) for j in range(3)] for i in range(3)]
    else:                # (a path through a zero rotation vector: sqrt of a ball at 0,
        w = lerp(path.w0, path.w1)            # its intervals there stay undecided)
        if path.deg:
            w = [wi * (flint.arb.pi() / 180) for wi in w]
        R = _rotation(w)
    pts = [[_series(c) for c in row] for row in base]
    for q in platform:
        pts.append([sum((R[i][k] * q[k] for k in range(3)), t[i]) for i in range(3)])
    rows = []
    for i, j in OCTAHEDRAL_LEGS:
        b, p = pts[i - 1], pts[j - 1]
        u = [p[k] - b[k] for k in range(3)]
        rows.append(u + [b[1] * u[2] - b[2] * u[1], b[2] * u[0] - b[0] * u[2],
                         b[0] * u[1] - b[1] * u[0]])
    return _det(rows)


@dataclass(frozen=True)
class ZeroExclusion:
    """Result of :func:`exclude_zeros`.

    Attributes
    ----------
    undecided : list of (float, float)
        Intervals of s on which det J was not proven non-zero.
    proven : float
        Total length of s proven free of zeros of det J.
    evaluations : int
    """

    undecided: list
    proven: float
    evaluations: int


def _ball(a: float, b: float):
    """Midpoint and a radius (float) of a ball that contains [a, b]."""
    m = a + 0.5 * (b - a)
    return m, max(m - a, b - m) * (1 + 2 ** -50) + 5e-324


def exclude_zeros(f_series, intervals, *, min_width: float = 1e-9,
                  budget: int = 4000) -> ZeroExclusion:
    """Prove f != 0 on each interval (lo, hi) of s by the mean-value form, bisecting
    down to ``min_width`` within ``budget`` evaluations.

    Parameters
    ----------
    f_series : callable (arb ball of s) -> arb_series (value, derivative)
    intervals : list of (float, float)
    """
    import flint
    stack = [(float(a), float(b)) for a, b in reversed(intervals) if b > a]
    undecided, proven, n = [], 0.0, 0
    while stack:
        a, b = stack.pop()
        if n >= budget:
            undecided.append((a, b))
            continue
        m, r = _ball(a, b)
        n += 1
        try:
            d = f_series(flint.arb(m, r))[1]
            v = f_series(flint.arb(m))[0]
            e = v + d * flint.arb(0, r)
            ok = e.is_finite() and not e.contains(0)
        except (ZeroDivisionError, ValueError, ArithmeticError):
            ok = False
        if ok:
            proven += b - a
        elif b - a <= min_width:
            undecided.append((a, b))
        else:
            stack.append((m, b))
            stack.append((a, m))
    undecided.sort()
    merged = []
    for a, b in undecided:
        if merged and merged[-1][1] >= a:
            merged[-1] = (merged[-1][0], max(merged[-1][1], b))
        else:
            merged.append((a, b))
    return ZeroExclusion(merged, proven, n)


def monotone_on(f_series, a: float, b: float) -> bool:
    """Whether arb proves f' != 0 on all of [a, b] (s): then f is strictly monotone
    there, and a certified sign change of f in [a, b] is exactly one simple zero (not
    an odd number of them).  The derivative is enclosed over the whole interval by
    coefficient 1 of ``f_series`` (two-term arb power series at the ball [a, b])."""
    import flint
    try:
        d = f_series(flint.arb(*_ball(a, b)))[1]
    except (ZeroDivisionError, ValueError, ArithmeticError):
        return False
    return bool(d.is_finite() and not d.contains(0))
