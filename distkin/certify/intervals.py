r"""Interval enclosures of the RSS kernels over boxes of poses (python-flint ``arb``).

The ``arb`` flavour of the generated kernels (:mod:`distkin.codegen.emit`,
:mod:`distkin.mechanisms.kernels`) evaluates the reach margins and ``[Jq_ii, Jx_i]`` of
Kühne et al., Sec. II-C, eq. (1), on balls.  This module evaluates them over a box

.. math:: X = [\underline p_1, \overline p_1] \times \dots \times
          [\underline p_6, \overline p_6]

of poses ``p = (x, y, z, r_x, r_y, r_z)`` (m, rad; :mod:`distkin.spatial`)
in four forms (:data:`FORMS`), all from the same generated kernel, run on different
number types:

``plain``
    the kernel on the six interval balls: the natural interval extension
    :math:`f(X)`, overestimated by the dependency problem (every occurrence of a
    variable varies independently);
``centred``
    the mean-value (centred) form

    .. math:: f(X) \subseteq f(m) + \sum_k \nabla_k f(X)\,(X_k - m_k),

    with ``m`` the box's midpoint (a point evaluation, a tight ball) and the
    derivatives :math:`\nabla_k f(X)` enclosed by running the kernel on forward-mode
    derivative balls (:class:`Grad`).  Its overestimation shrinks with the square of the
    box width instead of linearly (Moore, Kearfott & Cloud, *Introduction to Interval
    Analysis*, SIAM 2009, Sec. 6.4).  The derivative enclosures themselves are plain
    interval evaluations, so on the RSS kernels (closed-form IK with a square root of
    the nearly cancelling ``rho^2 - C^2``) this form certifies only small boxes;
``affine``
    the centred form applied at every operation: first-order Taylor models
    (:class:`Affine`), linear in the box coordinates with a remainder bound;
``quadratic`` (the default)
    second-order Taylor models (:class:`.taylor.Quadratic`); their remainder is cubic in
    the box width.  Both Taylor forms use the better of a Taylor expansion and a
    Chebyshev linear enclosure (:mod:`.linearize`) for ``sqrt`` and ``1/x``.

Every form returns :class:`BoxEnclosure`: ``Jx ∈ J0 + Σ T_k ε_k ± e`` with
``ε ∈ [-1, 1]``, which the certificates of :mod:`.boxes` use term by term.

The mean-value theorem needs ``f`` differentiable on the box.  :class:`Grad` returns a
non-finite derivative ball wherever an operation is not differentiable on its argument
(``abs`` or ``sqrt`` of a ball containing 0, division by a ball containing 0), so a
finite derivative enclosure *is* the proof that the theorem applies; the Taylor models
likewise return a non-finite remainder.

The margins a box is reachable by are the legs' reach margins and, for a leg table with
revolute joint ranges, the range margins of those legs (:func:`margins`: the arb kernel
``ranges`` of :mod:`distkin.mechanisms.symbolic`, ``rho^2 (cos(q - m) - cos w)``, > 0 iff
the crank angle is strictly inside its range): every certificate of :mod:`.boxes` reads
them alike (all > 0: reachable; one < 0 over the box: unreachable).

Balls carry no units; reach and range margins are m^2, ``Jq`` and the force columns of
``Jx`` (L x 6, its first three) are dimensionless, its moment columns (last three) m (the
kernels' conventions).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .linearize import ModelArithmetic, chebyshev_recip, chebyshev_sqrt

__all__ = ["Grad", "Affine", "FORMS", "box_balls", "BoxEnclosure", "enclose_box", "point_values",
           "margins"]


def margins(kernels, pose) -> list:
    """The margins of reachability at ``pose`` (balls, models or floats, whatever the
    kernels are run on): the L reach margins, then the range margins of the revolute legs
    with a joint range (:func:`distkin.mechanisms.kernels.range_legs`, in that order; none
    for a kernel set without the ``ranges`` kernel).  All > 0: every leg closes with its
    crank strictly inside its range."""
    out = list(kernels.reach(pose))
    ranges = getattr(kernels, "ranges", None)
    return out + list(ranges(pose)) if ranges is not None else out


def _nan():
    from flint import arb
    return arb("nan")


class Grad:
    """A forward-mode derivative ball: value ``v`` and gradient ``d`` (arb balls).

    Implements what the ``arb`` kernels use (``+ - * /``, integer ``**``, ``abs``,
    ``sqrt``, ``sin``, ``cos``) by the chain rule on balls, so that running a kernel on
    ``Grad`` inputs seeded with unit gradients encloses its value and its gradient over
    the inputs' balls.

    Parameters
    ----------
    v : flint.arb
    d : list of flint.arb
        Derivatives with respect to the seeded variables, all of the same length.
    """

    __slots__ = ("v", "d")

    def __init__(self, v, d):
        self.v = v
        self.d = d

    def __repr__(self):
        return f"Grad({self.v}, {list(self.d)})"

    # -- arithmetic ---------------------------------------------------------------
    def __add__(self, o):
        if isinstance(o, Grad):
            return Grad(self.v + o.v, [a + b for a, b in zip(self.d, o.d)])
        return Grad(self.v + o, self.d)

    __radd__ = __add__

    def __sub__(self, o):
        if isinstance(o, Grad):
            return Grad(self.v - o.v, [a - b for a, b in zip(self.d, o.d)])
        return Grad(self.v - o, self.d)

    def __rsub__(self, o):
        return Grad(o - self.v, [-a for a in self.d])

    def __neg__(self):
        return Grad(-self.v, [-a for a in self.d])

    def __pos__(self):
        return self

    def __mul__(self, o):
        if isinstance(o, Grad):
            v, w = self.v, o.v
            return Grad(v * w, [a * w + v * b for a, b in zip(self.d, o.d)])
        return Grad(self.v * o, [a * o for a in self.d])

    __rmul__ = __mul__

    def __truediv__(self, o):
        if isinstance(o, Grad):
            w = o.v
            q = self.v / w
            return Grad(q, [(a - q * b) / w for a, b in zip(self.d, o.d)])
        return Grad(self.v / o, [a / o for a in self.d])

    def __rtruediv__(self, o):
        q = o / self.v
        f = -q / self.v
        return Grad(q, [f * a for a in self.d])

    def __pow__(self, n):
        if not isinstance(n, int) or n < 0:
            raise ValueError(f"expected a non-negative integer power, got {n!r}")
        out = None
        for _ in range(n):
            out = self if out is None else out * self
        return out if out is not None else Grad(self.v * 0 + 1, [a * 0 for a in self.d])

    # -- functions ----------------------------------------------------------------
    def __abs__(self):
        if self.v > 0:
            return self
        if self.v < 0:
            return -self
        # not differentiable on a ball containing 0: the derivative is not enclosed
        nan = _nan()
        return Grad(abs(self.v), [a if a.is_zero() else nan for a in self.d])

    def sqrt(self):
        s = self.v.sqrt()
        h = 1 / (2 * s)                   # non-finite if the ball contains 0
        return Grad(s, [h * a for a in self.d])

    def sin(self):
        s, c = self.v.sin_cos()
        return Grad(s, [c * a for a in self.d])

    def cos(self):
        s, c = self.v.sin_cos()
        return Grad(c, [-s * a for a in self.d])


class Affine(ModelArithmetic):
    r"""A first-order Taylor model (affine form) over the box: value set
    :math:`\{c + \sum_k a_k \varepsilon_k + \delta : \varepsilon \in [-1, 1]^n,
    |\delta| \le e\}` with ball coefficients ``c``, ``a_k`` and a remainder bound ``e``.

    Linear dependencies on the box coordinates ``ε_k`` propagate exactly through
    ``+ - *`` and through the linearisation of ``sqrt``, ``1/x``, ``sin``, ``cos``
    (Taylor's theorem with a Lagrange remainder enclosed over the operand's range);
    only the second-order parts go into ``e``.  This is the centred form applied at
    every operation of the kernel instead of once at its end, so cancellations inside
    the closed-form inverse kinematics (``rho^2 - C^2``) cost nothing at first order
    (de Figueiredo & Stolfi, *Affine arithmetic: concepts and applications*, Numer.
    Algorithms 37 (2004), doi:10.1023/B:NUMA.0000049462.70970.b6; Berz & Makino's
    Taylor models of order 1).

    Parameters
    ----------
    c : flint.arb
    a : list of flint.arb
    e : flint.arb
        An upper bound (>= 0) of the remainder; non-finite where an operation is not
        smooth on its operand's range (then nothing is certified).
    """

    __slots__ = ("c", "a", "e", "_m")

    def __init__(self, c, a, e):
        self.c = c
        self.a = a
        self.e = e

    def __repr__(self):
        return f"Affine({self.c}, {list(self.a)}, {self.e})"

    def range(self):
        """An arb ball containing every value of the form."""
        unit = _unit()
        s = self.c + self.e * unit
        for x in self.a:
            s += x * unit
        return s

    def _mag(self):
        # sup |x - c| over the form (cached: the forms are immutable)
        try:
            return self._m
        except AttributeError:
            pass
        s = self.e
        for x in self.a:
            s += abs(x)
        self._m = s
        return s

    def __add__(self, o):
        if isinstance(o, Affine):
            return Affine(self.c + o.c, [x + y for x, y in zip(self.a, o.a)],
                          self.e + o.e)
        return Affine(self.c + o, self.a, self.e)

    __radd__ = __add__

    def __sub__(self, o):
        if isinstance(o, Affine):
            return Affine(self.c - o.c, [x - y for x, y in zip(self.a, o.a)],
                          self.e + o.e)
        return Affine(self.c - o, self.a, self.e)

    def __rsub__(self, o):
        return Affine(o - self.c, [-x for x in self.a], self.e)

    def __neg__(self):
        return Affine(-self.c, [-x for x in self.a], self.e)

    def __pos__(self):
        return self

    def __mul__(self, o):
        if isinstance(o, Affine):
            c1, c2 = self.c, o.c
            if o is self:        # x*x: the quadratic part lies in [0, mag^2]
                m = self._mag()
                h = m * m / 2
                return Affine(c1 * c1 + h, [2 * c1 * x for x in self.a],
                              2 * abs(c1) * self.e + h)
            e = abs(c1) * o.e + abs(c2) * self.e + self._mag() * o._mag()
            return Affine(c1 * c2, [c1 * y + c2 * x for x, y in zip(self.a, o.a)], e)
        return Affine(self.c * o, [x * o for x in self.a], self.e * abs(o))

    __rmul__ = __mul__

    def _unary(self, f0, f1, f2max):
        """f(c) + f'(c)(x - c) + remainder, |f''| <= f2max on the range."""
        m = self._mag()
        return Affine(f0, [f1 * x for x in self.a], abs(f1) * self.e + f2max * m * m / 2)

    def _linear(self, cheb):
        al, zeta, delta = cheb
        return Affine(al * self.c + zeta, [al * x for x in self.a], abs(al) * self.e + delta)

    def _recip(self):
        # |f''| = 2 / |x|^3 is largest at the smallest |x| of the range (a point: a
        # product of wide mid-radius balls would overestimate)
        r = self.range()
        m = r.abs_lower()
        c = self.c
        return self._better(self._unary(1 / c, -1 / (c * c), 2 / (m * m * m)),
                            chebyshev_recip(r))

    def __truediv__(self, o):
        if isinstance(o, Affine):
            return self * o._recip()
        return Affine(self.c / o, [x / o for x in self.a], self.e / abs(o))

    def _not_smooth(self, r):
        return Affine(r, [x * 0 for x in self.a], _nan())

    def sqrt(self):
        r = self.range()
        lo = r.lower()                     # |f''| = x^(-3/2) / 4 is largest at the bottom
        s = self.c.sqrt()
        return self._better(self._unary(s, 1 / (2 * s), 1 / (4 * lo * lo.sqrt())),
                            chebyshev_sqrt(r))

    def sin(self):
        s, c = self.c.sin_cos()
        return self._unary(s, c, abs(self.range().sin()))

    def cos(self):
        s, c = self.c.sin_cos()
        return self._unary(c, -s, abs(self.range().cos()))


def _unit():
    from flint import arb
    return arb(0, 1)


def box_balls(lo, hi):
    """Balls of a box and of its offsets from the midpoint.

    Parameters
    ----------
    lo, hi : array (6,)
        Box corners (m, rad); ``lo <= hi``, a zero width fixes a coordinate.

    Returns
    -------
    mid : ndarray (6,)
        The midpoint (doubles inside the box).
    X : list of 6 arb
        Balls containing ``[lo_k, hi_k]`` (exact points where ``lo_k == hi_k``).
    R : list of 6 arb
        Balls containing ``[lo_k - mid_k, hi_k - mid_k]``.
    vary : tuple of int
        The coordinates of non-zero width.
    """
    from flint import arb
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    mid = np.clip(lo + 0.5 * (hi - lo), lo, hi)
    X, R, vary = [], [], []
    for k in range(len(lo)):
        if hi[k] > lo[k]:
            a, b, c = arb(float(lo[k])), arb(float(hi[k])), arb(float(mid[k]))
            X.append(a.union(b))
            R.append((a - c).union(b - c))
            vary.append(k)
        else:
            X.append(arb(float(lo[k])))
            R.append(arb(0))
    return mid, X, R, tuple(vary)


def _as_grad(g, n):
    """A kernel output as a Grad (constant entries, printed as numbers, have d = 0)."""
    if isinstance(g, Grad):
        return g
    from flint import arb
    return Grad(arb(g), (arb(0),) * n)


def _as_affine(g, n):
    if isinstance(g, Affine):
        return g
    from flint import arb
    return Affine(arb(g), (arb(0),) * n, arb(0))


def _as_arb(v):
    from flint import arb
    return v if isinstance(v, arb) else arb(v)


def point_values(kernels, pose):
    """Certified ``(reach, Jq, Jx)`` at one pose of doubles.

    Parameters
    ----------
    kernels : KernelSet
        The ``arb`` kernels (``mech.kernels("arb")``).
    pose : array (6,)

    Returns
    -------
    reach : list of arb (m^2)
        The margins of :func:`margins` (L reach margins, then the range margins).
    jq : list of L arb
    jx : list of L lists of 6 arb
    """
    from flint import arb
    P = [arb(float(v)) for v in pose]
    out = [[_as_arb(v) for v in row] for row in kernels.jq_jx(P)]
    return ([_as_arb(v) for v in margins(kernels, P)], [row[0] for row in out],
            [row[1:] for row in out])


FORMS = ("quadratic", "affine", "centred", "plain")


@dataclass
class BoxEnclosure:
    r"""Enclosures over one box, in the shape every form shares.

    For every pose ``p`` of the box there are ``ε ∈ [-1, 1]^n`` such that

    .. math:: J_x(p) \in J_0 + \sum_k T_k\,\varepsilon_k + [-e, e]

    entrywise (balls), where ``n = len(vary)``.

    Attributes
    ----------
    mid : ndarray (6,)
        Midpoint.
    vary : tuple of int
        The coordinates of non-zero width.
    reach : list of arb
        The margins of :func:`margins` over the box (m^2): L reach margins, then the
        range margins of the legs with a revolute joint range.
    reach_weights : ndarray (len(reach), n)
        |d reach_i / d ε_k| (for choosing the coordinate to split; floats).
    jq : list of L arb or None
        ``Jq_ii`` over the box (None when the Jacobian was not evaluated).
    jx0 : L x 6 arb or None
        ``J_0``: ``Jx`` at the midpoint (affine, centred) or over the box (plain).
    jx_terms : list of n L x 6 lists of arb
        ``T_k`` (affine: coefficients; centred: ``dJx/dp_k(X) (X_k - m_k)``; plain: none).
    jx_err : L x 6 arb or None
        ``e`` (remainder of the Taylor models; None: 0).
    term_dims : list of tuple of int
        Per term ``T_k``: the indices into ``vary`` of the coordinates it depends on
        (one for a linear term, two for a mixed quadratic one).
    """

    mid: np.ndarray
    vary: tuple
    reach: list
    reach_weights: np.ndarray
    jq: list | None = None
    jx0: list | None = None
    jx_terms: list = field(default_factory=list)
    jx_err: list | None = None
    term_dims: list = field(default_factory=list)


def _centre(mid_val, terms, plain):
    """mid + sum(terms), intersected with the plain enclosure."""
    s = mid_val
    for t in terms:
        s = s + t
    try:
        return s.intersection(plain)
    except ValueError:               # disjoint balls cannot both enclose f(X)
        raise AssertionError("centred and plain enclosures are disjoint") from None


def _mag(x) -> float:
    return float(abs(x).upper().mid()) if x.is_finite() else math.inf


def enclose_box(kernels, lo, hi, *, form: str = "quadratic",
                jacobian: bool = True) -> BoxEnclosure:
    """Enclose the reach margins, ``Jq`` and ``Jx`` of a mechanism over a box.

    Parameters
    ----------
    kernels : KernelSet
        ``mech.kernels("arb")``.
    lo, hi : array (6,)
        The box (m, rad).
    form : {"quadratic", "affine", "centred", "plain"}
        See the module docstring, :class:`Affine` and :class:`.taylor.Quadratic`.
    jacobian : bool
        Also enclose ``Jq`` and ``Jx``; skipped anyway unless every reach margin is
        certified > 0 (the Jacobian is then of no use to a certificate).

    Returns
    -------
    BoxEnclosure
    """
    from flint import arb
    if form not in FORMS:
        raise ValueError(f"expected a form in {FORMS}, got {form!r}")
    mid, X, R, vary = box_balls(lo, hi)
    n = len(vary)
    if form == "plain" or n == 0:
        reach = [_as_arb(v) for v in margins(kernels, X)]
        enc = BoxEnclosure(mid, vary, reach, np.zeros((len(reach), n)))
        if jacobian and all(r > 0 for r in reach):
            out = [[_as_arb(v) for v in row] for row in kernels.jq_jx(X)]
            enc.jq = [row[0] for row in out]
            enc.jx0 = [row[1:] for row in out]
        return enc
    zero, one = arb(0), arb(1)
    if form == "quadratic":
        return _enclose_quadratic(kernels, X, R, mid, vary)
    if form == "affine":
        A = []
        for k in range(6):
            if k in vary:
                j = vary.index(k)
                half = abs(R[k]).upper()
                A.append(Affine(arb(float(mid[k])), [half if i == j else zero
                                                          for i in range(n)], zero))
            else:
                A.append(Affine(X[k], (zero,) * n, zero))
        ra = [_as_affine(g, n) for g in margins(kernels, A)]
        reach = [a.range() for a in ra]
        w = np.array([[_mag(x) for x in a.a] for a in ra])
        enc = BoxEnclosure(mid, vary, reach, w)
        if jacobian and all(r > 0 for r in reach):
            out = [[_as_affine(g, n) for g in row] for row in kernels.jq_jx(A)]
            enc.jq = [row[0].range() for row in out]
            enc.jx0 = [[g.c for g in row[1:]] for row in out]
            enc.jx_terms = [[[g.a[j] for g in row[1:]] for row in out] for j in range(n)]
            enc.jx_err = [[g.e for g in row[1:]] for row in out]
            enc.term_dims = [(j,) for j in range(n)]
        return enc
    # centred (mean-value) form with forward-mode derivative enclosures
    G = []
    for k in range(6):
        if k in vary:
            j = vary.index(k)
            G.append(Grad(X[k], [one if i == j else zero for i in range(n)]))
        else:
            G.append(Grad(X[k], (zero,) * n))
    Pm = [arb(float(v)) for v in mid]
    Rv = [R[k] for k in vary]
    rg = [_as_grad(g, n) for g in margins(kernels, G)]
    rm = [_as_arb(v) for v in margins(kernels, Pm)]
    terms = [[g.d[j] * Rv[j] for j in range(n)] for g in rg]
    reach = [_centre(rm[i], terms[i], rg[i].v) for i in range(len(rg))]
    w = np.array([[_mag(t) for t in row] for row in terms])
    enc = BoxEnclosure(mid, vary, reach, w)
    if jacobian and all(r > 0 for r in reach):
        og = [[_as_grad(g, n) for g in row] for row in kernels.jq_jx(G)]
        om = [[_as_arb(v) for v in row] for row in kernels.jq_jx(Pm)]
        enc.jq = [_centre(om[i][0], [og[i][0].d[j] * Rv[j] for j in range(n)], og[i][0].v)
                  for i in range(len(og))]
        enc.jx0 = [row[1:] for row in om]
        enc.jx_terms = [[[og[i][c].d[j] * Rv[j] for c in range(1, 7)] for i in range(len(og))]
                        for j in range(n)]
        enc.term_dims = [(j,) for j in range(n)]
    return enc


def _enclose_quadratic(kernels, X, R, mid, vary):
    """``enclose_box`` with second-order Taylor models (:mod:`.taylor`)."""
    from flint import arb
    from .taylor import Quadratic, constant, pairs, variable
    n = len(vary)
    Q = []
    for k in range(6):
        if k in vary:
            Q.append(variable(arb(float(mid[k])), abs(R[k]).upper(), vary.index(k), n))
        else:
            Q.append(constant(X[k], n))

    def model(g):
        return g if isinstance(g, Quadratic) else constant(g, n)
    rq = [model(g) for g in margins(kernels, Q)]
    reach = [m.range() for m in rq]
    w = np.array([[_mag(x) for x in m.a] for m in rq])
    enc = BoxEnclosure(mid, vary, reach, w)
    if all(r > 0 for r in reach):
        out = [[model(g) for g in row] for row in kernels.jq_jx(Q)]
        P = pairs(n)
        enc.jq = [row[0].range() for row in out]
        # J = c + sum a_k e_k + sum_{k<l} q_kl e_k e_l + sum_k q_kk e_k^2 + delta, and
        # q_kk e_k^2 = q_kk / 2 + (q_kk / 2)(2 e_k^2 - 1) with 2 e_k^2 - 1 in [-1, 1]
        diag = [p for p, (k, l) in enumerate(P) if k == l]
        jx0 = []
        for row in out:
            r0 = []
            for g in row[1:]:
                v = g.c
                for p in diag:
                    v = v + g.q[p] / 2
                r0.append(v)
            jx0.append(r0)
        enc.jx0 = jx0
        terms, dims = [], []
        for j in range(n):
            terms.append([[g.a[j] for g in row[1:]] for row in out])
            dims.append((j,))
        for p, (k, l) in enumerate(P):
            f = 2 if k == l else 1
            terms.append([[g.q[p] / f for g in row[1:]] for row in out])
            dims.append((k,) if k == l else (k, l))
        enc.jx_terms = terms
        enc.term_dims = dims
        enc.jx_err = [[g.e for g in row[1:]] for row in out]
    return enc
