r"""Second-order Taylor models with binary64 coefficients, batched over boxes.

:class:`Quadratics` is the model of :class:`.taylor.Quadratic` (the same set

.. math:: \Bigl\{\, c + \sum_k a_k \varepsilon_k + \sum_{k, l} q_{kl}\,
          \varepsilon_k \varepsilon_l + \delta \;:\; \varepsilon \in [-1, 1]^n,\;
          |\delta| \le e \,\Bigr\},

``q`` a full symmetric matrix) for ``B`` boxes at once: ``c`` (B,), ``a`` (B, n),
``q`` (B, n, n), ``e`` (B,) are numpy float64 arrays.  The generated ``arb`` kernels run
on it unchanged (``+ - * /``, ``abs``, ``sqrt``, ``sin``, ``cos``), one numpy call per
operation for the whole batch instead of one arb call per coefficient and box; this is
the cost of a box divided by about 30 (``python -m benchmarks certify``).

Why the models stay rigorous (every rounding goes into ``e``)
------------------------------------------------------------
Binary64 arithmetic rounds to nearest (numpy on IEEE 754 hardware); ``u = 2^-53``.
We use three facts about it, with gradual underflow and away from overflow:

(R1) For a single operation ``+ - * /`` or ``sqrt`` with exact real result ``x`` and
     computed double ``y``: ``pred(y) <= x <= succ(y)`` (``np.nextafter``).  So
     :func:`up` ``(fl(a op b))`` is an upper bound of ``a op b``; the ends of the
     ranges are rounded outwards this way.
(R2) A monotone expression of ``+`` and ``×`` on non-negative doubles, evaluated to
     nearest with at most 64 roundings on any path from an input to the result (in any
     order of summation), is at least its exact value times ``(1 - u)^64`` less the
     underflow losses of its products (at most ``2^-1075`` each; Higham, *Accuracy and
     Stability of Numerical Algorithms*, 2nd ed., SIAM 2002, Thm 2.2 and Lemma 3.1;
     additions have no underflow error).  So :func:`fin`, ``up(x * (1 + 2^-44))``,
     bounds it from above once ``TINY`` is among its terms; every remainder and
     magnitude (``e``, norms, ranges) is computed this way.  The losses stay below
     ``TINY``: a product that can underflow is multiplied afterwards only by factors
     below ``2^500`` (``|f''(c)| / 2``, the third-derivative bound) and ``2^300``
     (``dev^2``), which :meth:`Quadratics._expand` checks.  Sums have at most 37 terms
     (``n <= 6`` box coordinates).
(R3) A coefficient computed as a sum of at most 4 products of at most 3 doubles (every
     formula of this module; at most 16 roundings) differs from its exact value by at
     most ``γ_16`` times the sum of the magnitudes of its terms, plus an underflow
     error: each product can lose ``2^-1075`` absolutely (Higham, Sec. 2.1, Thm 2.2 and
     eq. (3.4)-(3.5)); the lost amount is multiplied by at most one further factor,
     below ``2^500`` (R2), so it is below ``2^-575``.
     The coefficients of every operation are rounded to nearest, and the operation adds
     to ``e`` the bound ``G * M + TINY`` with ``G = 2^-48 >= γ_16``, ``M`` an upper
     bound (R1, R2) of the sum over all coefficients of the magnitudes of their terms
     (for a product of two models ``M <= N_1 N_2`` with ``N = |c| + Σ|a| + Σ|q|``) and
     ``TINY = 2^-400`` (far above the at most 200 underflow losses).  As ``|ε_k| <= 1``,
     a coefficient changed by ``d`` changes the model's values by at most ``|d|``, so
     the rounded model with the larger ``e`` still contains every exact value.

Elementary functions ``f`` are expanded to second order at the double centre ``c``,
:math:`f(c) + f'(c) D + f''(c) D^2 / 2` with ``D = x - c``, as :class:`.taylor.Quadratic`
does; the derivatives at ``c`` are doubles ``f_i`` with certified errors
``|f^{(i)}(c) - f_i| <= e_i``, and ``e_0 + e_1 dev + e_2 dev^2 / 2`` joins the remainder
(``dev`` bounds ``|D|``).  ``1/x`` and ``sqrt`` take ``f_i`` from at most 5 correctly
rounded operations on a centre in ``[2^-200, 2^200]`` (no underflow), so
``e_i = 2^-50 |f_i|``; ``sin`` and ``cos`` take ``f_i`` and ``e_i`` from python-flint
(``arb.sin_cos``, once per model and box: no libm accuracy is assumed).  The third
derivative is bounded over the operand's range by upward-rounded operations (R1):
``6 / m^4`` (``1/x``), ``3 / (8 lo^(5/2))`` (``sqrt``), ``1`` (``sin``) and
``min(1, max |x|)`` (``cos``).  Unlike :class:`.taylor.Quadratic` there is no Chebyshev
alternative (:mod:`.linearize`) for ``sqrt`` and ``1/x``: a box that needs it is split.

A remainder that is not finite (``nan`` or ``inf``: an operation not smooth on the
range, an overflow) certifies nothing; every test here is a comparison that ``nan``
fails.
"""

from __future__ import annotations

import numpy as np

from .linearize import ModelArithmetic

__all__ = ["Quadratics", "variables", "up", "down", "fin", "sum_up", "G", "TINY"]

G = 2.0 ** -48            # >= gamma_16 = 16 u / (1 - 16 u)
TINY = 2.0 ** -400        # covers the underflow losses of one operation (R3)
_BIG = 2.0 ** 500
_DEV = 2.0 ** 150         # an underflow of h = f2 / 2 times dev^2 stays below TINY
_REL = 2.0 ** -50         # relative error of the derivative doubles of 1/x and sqrt
_LO, _HI = 2.0 ** -200, 2.0 ** 200
_FIN = 1.0 + 2.0 ** -44   # > (1 - u)^-64


def up(x):
    """The double above the rounded-to-nearest ``x`` (R1: an upper bound)."""
    return np.nextafter(x, np.inf)


def down(x):
    """The double below the rounded-to-nearest ``x`` (R1: a lower bound)."""
    return np.nextafter(x, -np.inf)


def fin(x):
    """An upper bound of a non-negative expression ``x`` computed to nearest (R2)."""
    return np.nextafter(x * _FIN, np.inf)


def sum_up(x, axis):
    """An upper bound of the exact sum of the non-negative ``x`` along ``axis`` (R2)."""
    return fin(x.sum(axis=axis))


def _const(o):
    """A kernel constant as (double, error bound): python floats and ints are exact; an
    arb ball is its midpoint with its distance to it."""
    if isinstance(o, (float, int)):
        return float(o), 0.0
    from flint import arb
    if isinstance(o, arb):
        m = float(o.mid())
        d = abs(o - arb(m)).upper()
        err = 0.0 if d == 0 else float(up(float(d)))
        return m, err
    raise TypeError(f"expected a float, int or arb constant, got {type(o).__name__}")


def variables(mid, half):
    """The box coordinates ``mid_k + half_k ε_k`` as :class:`Quadratics`.

    Parameters
    ----------
    mid : ndarray (B, n)
        Centres (doubles).
    half : ndarray (B, n)
        Upper bounds of the half-widths (m or rad).

    Returns
    -------
    list of n Quadratics
    """
    B, n = mid.shape
    out = []
    for k in range(n):
        a = np.zeros((B, n))
        a[:, k] = half[:, k]
        out.append(Quadratics(mid[:, k].copy(), a, np.zeros((B, n, n)), np.zeros(B)))
    return out


class Quadratics(ModelArithmetic):
    """``B`` second-order Taylor models in ``n`` box coordinates (module docstring).

    ``x ** n`` and ``k / x`` come from :class:`.linearize.ModelArithmetic`; ``abs`` is
    per box (the shared one decides for a single model).

    Parameters
    ----------
    c : ndarray (B,)
    a : ndarray (B, n)
    q : ndarray (B, n, n)
        Symmetric.
    e : ndarray (B,)
        Remainder bounds (>= 0; ``nan``/``inf``: nothing certified).
    """

    __slots__ = ("c", "a", "q", "e", "_nrm", "_sc")

    def __init__(self, c, a, q, e):
        self.c = c
        self.a = a
        self.q = q
        self.e = e

    def __repr__(self):
        return f"Quadratics(B={len(self.c)}, n={self.a.shape[1]})"

    def take(self, idx) -> "Quadratics":
        """The models of the boxes ``idx``."""
        out = Quadratics(self.c[idx], self.a[idx], self.q[idx], self.e[idx])
        sc = getattr(self, "_sc", None)
        if sc is not None:
            out._sc = tuple(x[idx] for x in sc)
        return out

    # -- bounds (all rounded outwards, R1-R2) ------------------------------------------
    def norms(self):
        """(L, Q, N): upper bounds of ``Σ|a_k|``, ``Σ|q_kl|`` and ``|c| + L + Q``."""
        try:
            return self._nrm
        except AttributeError:
            pass
        L = fin(np.abs(self.a).sum(axis=1))
        Q = fin(np.abs(self.q).sum(axis=(1, 2)))
        N = fin(np.abs(self.c) + L + Q)
        self._nrm = (L, Q, N)
        return self._nrm

    def deviation(self):
        """Upper bound of ``|x - c|`` over the model."""
        L, Q, _ = self.norms()
        return fin(L + Q + self.e)

    def bounds(self):
        """(lo, hi) doubles with every value of the model in ``[lo, hi]``."""
        B, n = self.a.shape
        L, _, _ = self.norms()
        d = np.diagonal(self.q, axis1=1, axis2=2)
        off = np.abs(self.q).reshape(B, -1)           # a new array
        off[:, ::n + 1] = 0.0
        common = fin(L + off.sum(axis=1) + self.e)
        plus = fin(common + np.maximum(d, 0.0).sum(axis=1))
        minus = fin(common + np.maximum(-d, 0.0).sum(axis=1))
        with np.errstate(invalid="ignore", over="ignore"):
            return down(self.c - minus), up(self.c + plus)

    # -- arithmetic -------------------------------------------------------------------
    def _round(self, e, M):
        """e + G M + TINY, rounded up (R3)."""
        return fin(e + G * M + TINY)

    def __add__(self, o):
        if isinstance(o, Quadratics):
            N1, N2 = self.norms()[2], o.norms()[2]
            return Quadratics(self.c + o.c, self.a + o.a, self.q + o.q,
                              self._round(self.e + o.e, N1 + N2))
        k, ek = _const(o)
        e = self._round(self.e + ek, np.abs(self.c) + abs(k))
        return Quadratics(self.c + k, self.a, self.q, e)

    __radd__ = __add__

    def __neg__(self):
        return Quadratics(-self.c, -self.a, -self.q, self.e)

    def __pos__(self):
        return self

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def _scale(self, k, ek):
        ak = abs(k)
        _, _, N = self.norms()
        e = self._round(ak * self.e + ek * (N + self.e), ak * N)
        return Quadratics(self.c * k, self.a * k, self.q * k, e)

    def __mul__(self, o):
        if not isinstance(o, Quadratics):
            return self._scale(*_const(o))
        L1, Q1, N1 = self.norms()
        L2, Q2, N2 = o.norms()
        c1, c2 = self.c, o.c
        a1, a2 = self.a, o.a
        outer = a1[:, :, None] * a2[:, None, :]
        if o is self:
            sym = outer
        else:
            sym = 0.5 * (outer + (a2[:, :, None] * a1[:, None, :]))
        q = c1[:, None, None] * o.q + c2[:, None, None] * self.q + sym
        a = c1[:, None] * a2 + c2[:, None] * a1
        r1, r2 = Q1 + self.e, Q2 + o.e
        e = np.abs(c1) * o.e + np.abs(c2) * self.e + L1 * r2 + r1 * (L2 + r2)
        return Quadratics(c1 * c2, a, q, self._round(e, N1 * N2))

    __rmul__ = __mul__

    def _divide(self, k, ek):
        if ek or not k:
            return self * (1.0 / Quadratics._point(k, ek, self))
        ak = abs(k)
        _, _, N = self.norms()
        e = self._round(up(self.e / ak), up(N / ak))     # R1 for the divisions
        return Quadratics(self.c / k, self.a / k, self.q / k, e)

    @staticmethod
    def _point(k, ek, like):
        B, n = like.a.shape
        return Quadratics(np.full(B, k), np.zeros((B, n)), np.zeros((B, n, n)),
                          np.full(B, ek))

    def __truediv__(self, o):
        if isinstance(o, Quadratics):
            return self * o._recip()
        return self._divide(*_const(o))

    # -- elementary functions -----------------------------------------------------------
    def _expand(self, f0, f1, f2, f3max, e0, e1, e2):
        """f(c) + f'(c) D + f''(c) D^2 / 2, D = x - c (module docstring); ``f_i`` doubles
        with ``|f^(i)(c) - f_i| <= e_i``, ``f3max >= sup |f'''|`` over the range."""
        with np.errstate(all="ignore"):
            L, Q, _ = self.norms()
            h = 0.5 * f2
            a = self.a
            q = f1[:, None, None] * self.q + h[:, None, None] * (a[:, :, None] * a[:, None, :])
            ah, af1 = np.abs(h), np.abs(f1)
            rest = Q + self.e
            dev = fin(L + rest)
            dev2 = dev * dev
            # 1/6 rounded up: 1/6 + 2^-50 > 1/6 exactly
            e = (af1 * self.e + ah * (2.0 * L * rest + rest * rest)
                 + f3max * (dev2 * dev) * (1.0 / 6.0 + 2.0 ** -50)
                 + e0 + e1 * dev + 0.5 * e2 * dev2)
            M = af1 * (L + Q) + ah * (L * L)
            e = self._round(e, M)
            big = ~((ah <= _BIG) & (dev <= _DEV) & (f3max <= _BIG))
            e = np.where(big, np.inf, e)
            return Quadratics(f0, f1[:, None] * a, q, e)

    def _nan_where(self, bad):
        self.e = np.where(bad, np.nan, self.e)
        return self

    def _recip(self):
        lo, hi = self.bounds()
        c = self.c
        m = np.where(lo > 0, lo, -hi)              # a lower bound of min |x| on the range
        ok = ((lo > 0) | (hi < 0)) & (m > _LO) & (np.abs(c) < _HI)
        with np.errstate(all="ignore"):
            cc = np.where(ok, c, 1.0)
            f0 = 1.0 / cc
            f1 = -(f0 * f0)
            f2 = -2.0 * (f0 * f1)
            mm = np.where(ok, m, 1.0)
            m2 = down(mm * mm)
            f3 = up(6.0 / down(m2 * m2))
            out = self._expand(f0, f1, f2, f3, up(_REL * np.abs(f0)), up(_REL * np.abs(f1)),
                               up(_REL * np.abs(f2)))
        return out._nan_where(~ok)

    def sqrt(self):
        lo, _ = self.bounds()
        c = self.c
        ok = (lo > _LO) & (c < _HI)
        with np.errstate(all="ignore"):
            cc = np.where(ok, c, 1.0)
            ll = np.where(ok, lo, 1.0)
            f0 = np.sqrt(cc)
            f1 = 0.5 / f0
            f2 = -0.5 * (f1 / cc)
            den = down(down(ll * ll) * down(np.sqrt(ll)))
            f3 = up(0.375 / den)
            out = self._expand(f0, f1, f2, f3, up(_REL * np.abs(f0)), up(_REL * np.abs(f1)),
                               up(_REL * np.abs(f2)))
        return out._nan_where(~ok)

    def _sincos(self):
        """(s, es, co, eco): doubles and error bounds of sin c and cos c (arb)."""
        sc = getattr(self, "_sc", None)
        if sc is not None:
            return sc
        from flint import arb
        B = len(self.c)
        s, es, co, eco = (np.empty(B) for _ in range(4))
        for i, ci in enumerate(self.c.tolist()):
            if not np.isfinite(ci):
                s[i], co[i], es[i], eco[i] = 0.0, 0.0, np.nan, np.nan
                continue
            sa, ca = arb(ci).sin_cos()
            s[i], co[i] = float(sa.mid()), float(ca.mid())
            es[i] = float(abs(sa - arb(s[i])).upper())
            eco[i] = float(abs(ca - arb(co[i])).upper())
        self._sc = (s, up(es), co, up(eco))
        return self._sc

    def sin(self):
        s, es, co, eco = self._sincos()
        return self._expand(s, co, -s, np.ones(len(s)), es, eco, es)

    def cos(self):
        s, es, co, eco = self._sincos()
        lo, hi = self.bounds()
        f3 = np.minimum(1.0, np.maximum(np.abs(lo), np.abs(hi)))    # |sin x| <= |x|
        return self._expand(co, -s, -co, f3, eco, es, eco)

    def __abs__(self):
        lo, hi = self.bounds()
        sgn = np.where(lo > 0, 1.0, np.where(hi < 0, -1.0, np.nan))
        out = Quadratics(self.c * sgn, self.a * sgn[:, None], self.q * sgn[:, None, None],
                         self.e.copy())
        return out._nan_where(np.isnan(sgn))


def as_models(g, like):
    """A kernel output as Quadratics (constant entries are printed as numbers)."""
    if isinstance(g, Quadratics):
        return g
    k, ek = _const(g)
    return Quadratics._point(k, ek, like)
