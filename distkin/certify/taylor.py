r"""Second-order Taylor models over a box, in python-flint ``arb`` balls.

A :class:`Quadratic` stands for the set

.. math:: \Bigl\{\, c + \sum_k a_k \varepsilon_k + \sum_{k \le l} q_{kl}\,
          \varepsilon_k \varepsilon_l + \delta \;:\; \varepsilon \in [-1, 1]^n,\;
          |\delta| \le e \,\Bigr\}

over the box coordinates ``ε`` (scaled to [-1, 1]).  The constant, linear and quadratic
coefficients propagate exactly (as balls) through ``+ - *`` and through the
second-order expansion of ``1/x``, ``sqrt``, ``sin`` and ``cos`` at the centre; only
third-order parts go into the remainder ``e`` (Taylor's theorem with the third
derivative enclosed over the operand's range).  Compared with the first-order form
(:class:`.intervals.Affine`), whose remainder grows with the square of the box width and
collects every product of deviations, the remainder here is cubic, so cancellations of
second-order terms (the IK closure ``rho^2 - C^2``, the rows of ``Jx``) are kept and
much wider boxes certify (Berz & Makino, Verified integration of ODEs and flows using
differential algebraic methods on high-order Taylor models, *Reliable Computing* 4
(1998), doi:10.1023/A:1009958918582; here of order 2, with ball coefficients).

Quadratic coefficients are packed by :func:`pairs`: (0,0), (0,1), ..., (0,n-1), (1,1),
....  The generated ``arb`` kernels run on it unchanged (they use only ``+ - * /``,
integer powers, ``abs``, ``sqrt``, ``sin``, ``cos``).
"""

from __future__ import annotations

from functools import lru_cache

from .linearize import ModelArithmetic, chebyshev_recip, chebyshev_sqrt

__all__ = ["Quadratic", "pairs", "variable"]


@lru_cache(maxsize=None)
def pairs(n: int) -> tuple:
    """The packed index pairs (k, l), k <= l, of ``n`` variables."""
    return tuple((k, l) for k in range(n) for l in range(k, n))


def _arb(x):
    from flint import arb
    return x if isinstance(x, arb) else arb(x)


def variable(centre, half, j: int, n: int) -> "Quadratic":
    """The box coordinate ``centre + half * ε_j`` as a :class:`Quadratic` in ``n``
    variables (``half`` a ball containing the half-width)."""
    from flint import arb
    z = arb(0)
    return Quadratic(_arb(centre), [half if i == j else z for i in range(n)],
                     [z] * (n * (n + 1) // 2), z)


def constant(value, n: int) -> "Quadratic":
    from flint import arb
    z = arb(0)
    return Quadratic(_arb(value), [z] * n, [z] * (n * (n + 1) // 2), z)


class Quadratic(ModelArithmetic):
    """A second-order Taylor model: centre ``c``, linear ``a`` (n), quadratic ``q``
    (packed, :func:`pairs`) and remainder bound ``e`` (all arb balls).

    Parameters
    ----------
    c : flint.arb
    a : list of flint.arb
    q : list of flint.arb
    e : flint.arb
        Upper bound of the remainder (>= 0); non-finite where an operation is not
        smooth on its operand's range (then nothing is certified from the model).
    """

    __slots__ = ("c", "a", "q", "e", "_lq")

    def __init__(self, c, a, q, e):
        self.c = c
        self.a = a
        self.q = q
        self.e = e

    def __repr__(self):
        return f"Quadratic({self.c}, {self.a}, {self.q}, {self.e})"

    # -- bounds ---------------------------------------------------------------------
    def _mags(self):
        """(sup |linear part|, sup |quadratic part|), cached (the models are immutable)."""
        try:
            return self._lq
        except AttributeError:
            pass
        from flint import arb
        zero = arb(0)
        self._lq = (sum(map(abs, self.a), zero), sum(map(abs, self.q), zero))
        return self._lq

    def range(self):
        """An arb ball containing every value of the model."""
        from flint import arb
        unit = arb(0, 1)
        half = arb(0.5, 0.5)                   # [0, 1]: the range of ε_k^2
        s = self.c + self.e * unit
        for x in self.a:
            s += x * unit
        for (k, l), x in zip(pairs(len(self.a)), self.q):
            s += x * (half if k == l else unit)
        return s

    def deviation(self):
        """sup |x - c| over the model."""
        lin, quad = self._mags()
        return lin + quad + self.e

    # -- arithmetic -----------------------------------------------------------------
    def __add__(self, o):
        if isinstance(o, Quadratic):
            return Quadratic(self.c + o.c, [x + y for x, y in zip(self.a, o.a)],
                             [x + y for x, y in zip(self.q, o.q)], self.e + o.e)
        return Quadratic(self.c + o, self.a, self.q, self.e)

    __radd__ = __add__

    def __sub__(self, o):
        if isinstance(o, Quadratic):
            return Quadratic(self.c - o.c, [x - y for x, y in zip(self.a, o.a)],
                             [x - y for x, y in zip(self.q, o.q)], self.e + o.e)
        return Quadratic(self.c - o, self.a, self.q, self.e)

    def __rsub__(self, o):
        return Quadratic(o - self.c, [-x for x in self.a], [-x for x in self.q], self.e)

    def __neg__(self):
        return Quadratic(-self.c, [-x for x in self.a], [-x for x in self.q], self.e)

    def __pos__(self):
        return self

    def __mul__(self, o):
        if not isinstance(o, Quadratic):
            return Quadratic(self.c * o, [x * o for x in self.a], [x * o for x in self.q],
                             self.e * abs(o))
        c1, c2 = self.c, o.c
        a1, a2 = self.a, o.a
        # L1 L2 = sum_k a1_k a2_k e_k^2 + sum_{k<l} (a1_k a2_l + a1_l a2_k) e_k e_l
        q = [c1 * y + c2 * x + (a1[k] * a2[k] if k == l else a1[k] * a2[l] + a1[l] * a2[k])
             for (k, l), x, y in zip(pairs(len(a1)), self.q, o.q)]
        l1, q1 = self._mags()
        l2, q2 = o._mags()
        e = (abs(c1) * o.e + abs(c2) * self.e + l1 * (q2 + o.e)
             + (q1 + self.e) * (l2 + q2 + o.e))
        return Quadratic(c1 * c2, [c1 * y + c2 * x for x, y in zip(a1, a2)], q, e)

    __rmul__ = __mul__

    def _expand(self, f0, f1, f2, f3max):
        """f(c) + f'(c) D + f''(c) D^2 / 2 to second order, D = x - c; ``f3max`` bounds
        |f'''| over the range."""
        a = self.a
        h = f2 / 2
        q = []
        for (k, l), x in zip(pairs(len(a)), self.q):
            t = f1 * x
            q.append(t + h * a[k] * a[k] if k == l else t + f2 * a[k] * a[l])
        lin, quad = self._mags()
        rest = quad + self.e
        dev = lin + rest
        e = abs(f1) * self.e + abs(h) * (2 * lin * rest + rest * rest) + \
            f3max * dev * dev * dev / 6
        return Quadratic(f0, [f1 * x for x in a], q, e)

    def _linear(self, cheb):
        al, zeta, delta = cheb
        return Quadratic(al * self.c + zeta, [al * x for x in self.a],
                         [al * x for x in self.q], abs(al) * self.e + delta)

    def _recip(self):
        # the third derivative 6 / x^4 is largest at the smallest |x| of the range
        r = self.range()
        m = r.abs_lower()
        c = self.c
        ic = 1 / c
        m2 = m * m
        return self._better(self._expand(ic, -ic * ic, 2 * ic * ic * ic, 6 / (m2 * m2)),
                            chebyshev_recip(r))

    def __truediv__(self, o):
        if isinstance(o, Quadratic):
            return self * o._recip()
        return Quadratic(self.c / o, [x / o for x in self.a], [x / o for x in self.q],
                         self.e / abs(o))

    def _not_smooth(self, r):
        from flint import arb
        return Quadratic(r, [x * 0 for x in self.a], [x * 0 for x in self.q], arb("nan"))

    def sqrt(self):
        r = self.range()
        lo = r.lower()              # the third derivative 3 x^(-5/2) / 8 is largest there
        s = self.c.sqrt()
        f1 = 1 / (2 * s)
        f2 = -f1 / (2 * self.c)
        return self._better(self._expand(s, f1, f2, 3 / (8 * lo * lo * lo.sqrt())),
                            chebyshev_sqrt(r))

    def sin(self):
        r = self.range()
        s, c = self.c.sin_cos()
        return self._expand(s, c, -s, abs(r.cos()))

    def cos(self):
        r = self.range()
        s, c = self.c.sin_cos()
        return self._expand(c, -s, -c, abs(r.sin()))
