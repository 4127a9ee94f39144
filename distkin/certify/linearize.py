r"""Chebyshev (min-max) linear enclosures of ``sqrt`` and ``1/x`` over an interval.

For a function ``f`` convex or concave on ``[a, b]`` and the slope ``α`` of its secant,
``g(x) = f(x) - α x`` takes its extremes at ``a``, ``b`` and the point ``u`` where
``f'(u) = α``, so

.. math:: f(x) \in \alpha x + \zeta \pm \delta \quad (x \in [a, b])

with ``ζ`` the centre and ``δ`` the half-width of ``g([a, b])``.  This linear enclosure
stays tight on wide ranges, where a Taylor expansion at the centre pays for the growth of
``f''`` towards an end (``sqrt`` near 0: the reach limit of a leg).  Used by
:class:`.intervals.Affine` and :class:`.taylor.Quadratic` for the square root and the
reciprocal (de Figueiredo & Stolfi, *Affine arithmetic: concepts and applications*,
Numer. Algorithms 37 (2004), Sec. 3.7, doi:10.1023/B:NUMA.0000049462.70970.b6).

``α`` is a double (an exact ball) so that the bounds of ``g`` are rigorous for that
slope; all bounds are evaluated in ``arb`` at exact points.
"""

from __future__ import annotations

__all__ = ["chebyshev_sqrt", "chebyshev_recip", "ModelArithmetic"]


def _hull(values):
    lo, hi = values[0].lower(), values[0].upper()
    for v in values[1:]:
        lo = lo.min(v.lower())
        hi = hi.max(v.upper())
    return lo, hi


def _result(alpha, values):
    from flint import arb
    lo, hi = _hull(values)
    zeta = (lo + hi) / 2
    delta = ((hi - lo) / 2).upper()
    if not (zeta.is_finite() and delta.is_finite()):
        return None
    return arb(alpha), zeta, delta


def chebyshev_sqrt(rng):
    """(α, ζ, δ) with sqrt(x) ∈ α x + ζ ± δ for every x of the ball ``rng`` (> 0), or
    None if ``rng`` is not certified positive."""
    from flint import arb
    if not rng > 0:
        return None
    a, b = rng.lower(), rng.upper()
    fa, fb = a.sqrt(), b.sqrt()
    if not b > a:
        return _result(0.0, [fa])
    alpha = float(((fb - fa) / (b - a)).mid())
    if not alpha > 0:
        return None
    al = arb(alpha)
    u = 1 / (4 * al * al)                       # f'(u) = alpha
    vals = [fa - al * a, fb - al * b]
    if u > a and u < b:
        vals.append(u.sqrt() - al * u)
    elif u.overlaps(a.union(b)):
        return None
    return _result(alpha, vals)


def chebyshev_recip(rng):
    """(α, ζ, δ) with 1/x ∈ α x + ζ ± δ for every x of the ball ``rng`` (which must not
    contain 0), or None."""
    from flint import arb
    if not (rng > 0 or rng < 0):
        return None
    a, b = rng.lower(), rng.upper()
    fa, fb = 1 / a, 1 / b
    if not b > a:
        return _result(0.0, [fa])
    alpha = float((-(fa * fb)).mid())           # secant slope -1/(ab)
    if not alpha < 0:
        return None
    al = arb(alpha)
    u = (-1 / al).sqrt()                         # f'(u) = -1/u^2 = alpha, u > 0
    if rng < 0:
        u = -u
    vals = [fa - al * a, fb - al * b]
    if u > a and u < b:
        vals.append(1 / u - al * u)
    elif u.overlaps(a.union(b)):
        return None
    return _result(alpha, vals)


class ModelArithmetic:
    """Operations shared by the Taylor models :class:`.intervals.Affine` and
    :class:`.taylor.Quadratic`, written once on top of their own ``*``, unary ``-``,
    ``_recip``, ``range`` and ``_linear`` (the model of ``al x + zeta +- delta`` for a
    Chebyshev enclosure); ``_not_smooth(r)`` builds a model of the range ``r`` whose
    remainder is not finite (nothing is certified from it)."""

    __slots__ = ()

    def _better(self, taylor, cheb):
        """The enclosure with the smaller remainder: the Taylor model ``taylor`` or the
        Chebyshev linear enclosure ``cheb`` (``(al, zeta, delta)`` or None)."""
        if cheb is None:
            return taylor
        lin = self._linear(cheb)
        return lin if not taylor.e.is_finite() or lin.e.upper() < taylor.e.upper() else taylor

    def __rtruediv__(self, o):
        return self._recip() * o

    def __pow__(self, n):
        if not isinstance(n, int) or n < 1:
            raise ValueError(f"expected a positive integer power, got {n!r}")
        out = self
        for _ in range(n - 1):
            out = out * self
        return out

    def __abs__(self):
        r = self.range()
        if r > 0:
            return self
        if r < 0:
            return -self
        return self._not_smooth(abs(r))         # |x| is not smooth where x changes sign
