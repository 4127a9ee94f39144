r"""Reference data of the octahedral seed paper, and random assembled octahedra.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. VI
(the Griffis-Duffy example, docs/design.md §5).  :func:`eq11_agreement` compares an octic
with the printed eq. (11) *digit by digit*: the printed coefficients are rounded (most
to 5 significant digits), so we ask whether a single normalisation factor
:math:`\lambda` makes every one of our coefficients round to the printed digits, i.e.
whether the intervals :math:`[p_k \pm \tfrac12 \mathrm{ulp}_k]/c_k` intersect.  The roots
of the printed polynomial are never used (it has only 2 real roots: the octic is very
ill-conditioned).
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import numpy as np

__all__ = [
    "GD_BASE",
    "GD_PLATFORM",
    "GD_LEGS",
    "GD_ROOTS",
    "EQ11_PRINTED",
    "eq11_agreement",
    "random_octahedron",
    "random_rational_octahedron",
    "random_triangle",
]

#: Sec. VI: P1, P2, P3 (exact strings)
GD_BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
#: an equilateral platform of side 6 in its own frame (P4, P5, P6)
GD_PLATFORM = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
#: l1..l6 = 198/10, 18, 18, 17, 149/10, 178/10
GD_LEGS = ["19.8", "18", "18", "17", "14.9", "17.8"]
#: the six real roots printed after eq. (11), to the printed digits
GD_ROOTS = ("269.2", "328.7", "359.5", "463.6", "497.9", "513.0")
#: eq. (11) as printed, highest degree first (decimal strings keep the printed digits)
EQ11_PRINTED = ("2.5720", "-7719.2542", "1.0078e7", "-7.4833e9", "3.4607e12",
                "-1.0220e15", "1.8843e17", "-1.9854e19", "9.1598e20")


def _half_ulp(text: str) -> Fraction:
    d = Decimal(text)
    return Fraction(1, 2) * Fraction(10) ** d.as_tuple().exponent


def eq11_agreement(coeffs):
    """Does the octic agree with the printed eq. (11) to the printed digits?

    Parameters
    ----------
    coeffs : 9 exact coefficients (Fractions, fmpq or ints), highest degree first

    Returns
    -------
    ok : bool
        True when one factor lambda makes every ``lambda * coeffs[k]`` round to the
        printed value (half a unit in its last printed digit).
    lam : (Fraction, Fraction)
        The interval of admissible normalisation factors (empty if lo > hi).
    rel : list of float
        ``lambda * c_k / p_k - 1`` at the middle lambda, per coefficient.
    """
    from ..exact import to_fraction
    c = [to_fraction(v) for v in coeffs]
    lo, hi = None, None
    for ck, text in zip(c, EQ11_PRINTED):
        p, h = Fraction(Decimal(text)), _half_ulp(text)
        a, b = (p - h) / ck, (p + h) / ck
        a, b = min(a, b), max(a, b)
        lo = a if lo is None else max(lo, a)
        hi = b if hi is None else min(hi, b)
    mid = (lo + hi) / 2
    rel = [float(mid * ck / Fraction(Decimal(t)) - 1) for ck, t in zip(c, EQ11_PRINTED)]
    return lo <= hi, (lo, hi), rel


def random_triangle(rng):
    """A random triangle (3, 3) in the plane z = 0, vertices in [-1, 1]^2, aspect ratio
    up to ~1:8 (twice its area above 0.05 times its longest side squared)."""
    while True:
        P = np.column_stack([rng.uniform(-1, 1, (3, 2)), np.zeros(3)])
        a = np.cross(P[1] - P[0], P[2] - P[0])[2]
        sides = [np.linalg.norm(P[i] - P[j]) for i, j in ((0, 1), (0, 2), (1, 2))]
        if abs(a) > 0.05 * max(sides) ** 2:
            return P


def random_octahedron(rng, *, scale=1.0, shape="random"):
    """A random assembled octahedral manipulator (float64).

    Parameters
    ----------
    rng : numpy.random.Generator
    scale : float
        Overall size (base circumradius ~ ``scale``).
    shape : {"random", "regular"}
        ``"regular"``: equilateral base and platform; ``"random"``: arbitrary triangles
        (aspect ratios up to ~1:8), platform size 0.2-1.5 x base, random pose above
        or below the base.

    Returns
    -------
    base (3, 3), platform (3, 3) in its own frame, legs (6,), points (3, 3) the true
    P4 P5 P6 in the base frame, R (3, 3), t (3,)
    """
    from .problem import LEG_PAIRS

    def tri(kind):
        if kind == "regular":
            ang = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3]) + rng.uniform(0, 2 * np.pi)
            return np.stack([np.cos(ang), np.sin(ang), np.zeros(3)], -1)
        return random_triangle(rng)
    base = tri(shape) * scale
    plat = tri(shape) * scale * rng.uniform(0.2, 1.5)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    R = q * np.sign(np.linalg.det(q))
    t = np.array([*rng.uniform(-0.5, 0.5, 2), rng.choice([-1, 1]) * rng.uniform(0.3, 2.0)])
    t = t * scale
    pts = plat @ R.T + t
    allp = np.vstack([base, pts])
    legs = np.array([np.linalg.norm(allp[i - 1] - allp[j - 1]) for i, j in LEG_PAIRS])
    return base, plat, legs, pts, R, t


def random_rational_octahedron(rng, *, size=12):
    """Six points with small rational coordinates (all squared distances and
    tetrahedron volumes rational), as a list of 6 tuples of Fractions."""
    while True:
        P = [tuple(Fraction(int(rng.integers(-size, size + 1)), int(rng.integers(1, 4)))
                   for _ in range(3)) for _ in range(6)]
        P[0], P[1], P[2] = ((P[0][0], P[0][1], Fraction(0)), (P[1][0], P[1][1], Fraction(0)),
                            (P[2][0], P[2][1], Fraction(0)))

        def vol6(a, b, c, d):
            u = [b[k] - a[k] for k in range(3)]
            v = [c[k] - a[k] for k in range(3)]
            w = [d[k] - a[k] for k in range(3)]
            return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                    + u[2] * (v[0] * w[1] - v[1] * w[0]))
        idx = [(4, 3, 0, 1), (4, 3, 0, 5), (2, 4, 0, 1), (2, 4, 0, 5)]
        if all(vol6(*(P[i] for i in q)) != 0 for q in idx):
            return P
