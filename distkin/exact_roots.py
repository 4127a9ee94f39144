r"""Certified real roots of exact rational polynomials (python-flint).

FLINT's ``arb_fmpz_poly_complex_roots`` (exposed as ``fmpz_poly.complex_roots``)
isolates every complex root of an exact integer polynomial in disjoint balls, with its
multiplicity (after a square-free factorisation).  Because the polynomial is real and
the balls are isolating, a root whose ball meets the real line alone is *proved* real
and is returned with an imaginary part exactly 0 (docs/design.md §6).  The count of real
roots is therefore certified; the balls are refined by re-isolating at a higher working
precision.  Nothing here returns an undecided answer as certain: where a question cannot
be settled within ``max_bits`` the functions raise
:class:`~distkin.errors.UncertifiedError`.

References
----------
F. Johansson, *Arb: efficient arbitrary-precision midpoint-radius interval arithmetic*,
IEEE Trans. Computers 66(8), 2017, doi:10.1109/TC.2017.2690633.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass, replace
from fractions import Fraction

from .errors import InputError, UncertifiedError

__all__ = [
    "RealRoot",
    "exact_poly",
    "working_precision",
    "real_roots",
    "count_real_roots",
    "refine_roots",
    "sign_at_root",
    "ball_ends",
    "pickle_balls",
    "unpickle_balls",
]

#: default cap on the working precision (bits) before giving up
MAX_BITS = 8192


@contextmanager
def working_precision(bits: int):
    """Set ``flint.ctx.prec`` to ``bits`` inside the block, and restore it after."""
    import flint
    old = flint.ctx.prec
    flint.ctx.prec = int(bits)
    try:
        yield
    finally:
        flint.ctx.prec = old


@dataclass(frozen=True)
class RealRoot:
    """A certified real root: an enclosing ``arb`` ball and its multiplicity.

    ``index`` is the root's position among the distinct real roots in increasing order;
    ``from_float`` names the coefficients that were bare floats (exact binary values).
    """

    ball: object
    multiplicity: int
    index: int
    bits: int
    #: positions (highest degree first) of the coefficients given as bare floats, each
    #: taken at its exact binary value (DESIGN §3: the result says so); () when none
    from_float: tuple = ()

    @property
    def mid(self) -> float:
        return float(self.ball.mid())

    @property
    def rad(self) -> float:
        """The ball's radius, about its exact midpoint (not about the float :attr:`mid`:
        :func:`~distkin.exact.float_ball` gives that one)."""
        return float(self.ball.rad())

    def __float__(self) -> float:
        return self.mid


def exact_poly(coeffs, *, field: str = "coefficients"):
    """An ``fmpz_poly`` with the roots of the rational polynomial ``coeffs``.

    Parameters
    ----------
    coeffs : sequence or flint.fmpq_poly / fmpz_poly
        Coefficients **highest degree first**: integers (Python or numpy: exact),
        Fractions, fmpq, fmpz, sympy Rationals, numeric strings parsed exactly
        (``"19.8"`` is 99/5, ``"12/5"``; an irrational one such as ``"sqrt(2)"`` is
        refused), or finite floats (Python or numpy), each taken as its exact binary
        value (``0.1`` is 3602879701896397/2**55, not 1/10; write ``"0.1"`` for 1/10),
        exactly as the end points of :func:`count_real_roots`.  :func:`real_roots`
        names the float coefficients in :attr:`RealRoot.from_float`.  A flint
        polynomial is taken as it is.

    Returns
    -------
    flint.fmpz_poly
        The numerator of the rational polynomial (same roots, same multiplicities).
    """
    return _exact_poly(coeffs, field)[0]


def _exact_poly(coeffs, field="coefficients"):
    """(:func:`exact_poly`, positions of the coefficients that were bare floats)."""
    import flint
    if isinstance(coeffs, flint.fmpz_poly):
        return coeffs, ()
    if isinstance(coeffs, flint.fmpq_poly):
        return coeffs.numer(), ()
    if isinstance(coeffs, (str, bytes)) or not hasattr(coeffs, "__iter__"):
        raise InputError(f"expected a sequence of coefficients (highest degree first), got "
                         f"{type(coeffs).__name__} {coeffs!r}", field=field)
    out, floats = [], []
    for i, c in enumerate(coeffs):
        q, is_float = _coefficient(c, f"{field}[{i}]")
        out.append(q)
        if is_float:
            floats.append(i)
    return flint.fmpq_poly(out[::-1]).numer(), tuple(floats)


def _coefficient(c, field):
    """(exact fmpq of one coefficient, whether it was a bare float), or InputError."""
    import flint
    name = type(c).__name__
    if name in ("fmpq", "fmpz"):
        return flint.fmpq(c), False
    if isinstance(c, bool) or (type(c).__module__ == "numpy" and c.dtype.kind == "b"):
        raise InputError(f"expected a rational number, got the boolean {c!r}", field=field)
    if hasattr(c, "dtype") and getattr(c, "shape", None) == () and c.dtype.kind in "iuf":
        c = c.item()                                   # numpy scalar: exact as Python's
    if isinstance(c, str):
        from .exact import parse_exact
        c = parse_exact(c, field).value                # Fraction / int, or irrational
    if isinstance(c, float):
        import math
        if not math.isfinite(c):
            raise InputError(f"expected a finite rational number, got {c!r}", field=field)
        f = Fraction(c)
        return flint.fmpq(f.numerator, f.denominator), True
    if isinstance(c, (int, Fraction)) and not isinstance(c, bool):
        f = Fraction(c)
        return flint.fmpq(f.numerator, f.denominator), False
    if getattr(c, "is_Rational", False):
        return flint.fmpq(int(c.p), int(c.q)), False
    raise InputError(f"expected a rational number (an integer, Fraction, fmpq, a numeric "
                     f"string or a float at its exact binary value), got {name} {c!r}",
                     field=field, hint="the certified root isolation needs a rational "
                     "polynomial; enclose irrational data another way")


def _bits(value, field, minimum=2):
    """A working precision in bits: an integer >= ``minimum`` (FLINT needs 2), or an
    :class:`InputError` naming ``field`` (QA: ``bits=0`` raised FLINT's bare ValueError
    and ``bits=2.5`` was kept as a float in :attr:`RealRoot.bits`)."""
    import numbers
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < minimum:
        raise InputError(f"expected {field} as an integer >= {minimum} (a working precision "
                         f"in bits), got {value!r}", field=field)
    return int(value)


def _isolate(p, bits):
    with working_precision(bits):
        return p.complex_roots()


def real_roots(coeffs, *, bits: int = 64) -> list[RealRoot]:
    """Every distinct real root, certified, in increasing order.

    Parameters
    ----------
    coeffs : see :func:`exact_poly`
    bits : int
        Working precision of the isolation; the balls have roughly this many
        correct bits.

    Returns
    -------
    list of RealRoot
        Disjoint balls, each proved to hold exactly one real root (of the given
        multiplicity) and no other root.

    Raises
    ------
    InputError
        The zero polynomial (every number is a root).

    Examples
    --------
    >>> [round(r.mid, 12) for r in real_roots([1, 0, -2])]
    [-1.414213562373, 1.414213562373]
    """
    p, floats = _exact_poly(coeffs)
    bits = _bits(bits, "bits")
    if p.is_zero():
        raise InputError("expected a nonzero polynomial, got the zero polynomial",
                         field="coefficients")
    if p.degree() < 1:
        return []
    roots = [(c.real, m) for c, m in _isolate(p, bits) if c.imag.is_zero()]
    roots.sort(key=lambda r: float(r[0].mid()))
    for (a, _), (b, _) in zip(roots, roots[1:]):
        if a.overlaps(b):  # cannot happen for isolating balls; never guess if it did
            raise UncertifiedError(f"real root enclosures {a} and {b} overlap")
    return [RealRoot(b, m, i, bits, floats) for i, (b, m) in enumerate(roots)]


def count_real_roots(coeffs, lo=None, hi=None, *, bits: int = 64,
                     max_bits: int = MAX_BITS) -> int:
    """Certified number of distinct real roots in the closed interval ``[lo, hi]``.

    ``None`` means unbounded; an end point is an exact rational, read by the rules of
    the coefficients (:func:`exact_poly`: integers of any kind, Fractions, fmpq,
    numeric strings, or a float taken at its exact binary value).  Each root's ball is
    compared with the end points exactly (its ends are binary rationals), and refined while it
    straddles one; a root exactly at an end point (``p(lo) == 0`` exactly) counts.
    Raises :class:`InputError` for an end point that is not a finite rational, or
    ``lo > hi``, and :class:`UncertifiedError` if ``max_bits`` does not suffice (it
    always does: a root that is not at a rational end point is separated from it at
    some precision).
    """
    p = exact_poly(coeffs)
    bits = _bits(bits, "bits")
    max_bits = _bits(max_bits, "max_bits")
    ends = [None if e is None else _fmpq_end(e, name) for e, name in ((lo, "lo"), (hi, "hi"))]
    if ends[0] is not None and ends[1] is not None and ends[0] > ends[1]:
        raise InputError(f"expected lo <= hi, got lo = {lo!r} and hi = {hi!r}", field="lo")
    at_end = [e is not None and p(e) == 0 for e in ends]
    while True:
        roots = real_roots(p, bits=bits)
        n, undecided = 0, False
        for r in roots:
            lower, upper = ball_ends(r.ball)
            inside = True
            for k, e in enumerate(ends):
                if e is None:
                    continue
                if lower <= e <= upper:
                    if at_end[k]:
                        continue  # the root at the end point (the only ball holding it)
                    undecided = True
                    break
                if (k == 0 and upper < e) or (k == 1 and lower > e):
                    inside = False
            if undecided:
                break
            n += inside
        if not undecided:
            return n
        if bits >= max_bits:
            raise UncertifiedError(f"cannot separate a root from an interval end point at "
                                   f"{bits} bits")
        bits *= 2


def _fmpq_end(e, name):
    """An interval end point as an exact ``fmpq``, by the rules of the coefficients
    (:func:`exact_poly`: integers of any kind, rationals, numeric strings, a finite float
    at its exact binary value); InputError naming ``lo`` or ``hi`` otherwise."""
    try:
        return _coefficient(e, name)[0]
    except InputError as exc:
        raise InputError(f"expected an exact rational end point: {exc.message}", field=name,
                         hint=exc.hint) from None


def ball_ends(ball):
    """The exact ends ``(lower, upper)`` (fmpq) of an ``arb`` ball: mid -/+ rad are binary
    rationals.  Compare with them, not with ``flint.arb(q)``, to place a rational ``q``
    against a ball narrower than q's rounding at the context precision."""
    def exact(x):
        man, exp = (int(v) for v in x.man_exp())
        return _fmpq_pow2(man, exp)
    m, r = exact(ball.mid()), exact(ball.rad())
    return m - r, m + r


class _Ball(tuple):
    """A pickled ``arb`` ball: ``(mid man, mid exp, rad man, rad exp)``, Python ints."""

    __slots__ = ()


def pickle_balls(obj):
    """``obj`` with every ``arb`` ball (inside lists, tuples and dicts) replaced by its
    exact binary state: python-flint cannot pickle (nor deep-copy) an ``arb``, and a
    result that holds balls (the certified tier's) could not be sent to another process
    (QA).  :func:`unpickle_balls` restores them."""
    if type(obj).__name__ == "arb":
        return _Ball(int(v) for part in (obj.mid(), obj.rad()) for v in part.man_exp())
    if isinstance(obj, dict):
        return {k: pickle_balls(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)) and not isinstance(obj, _Ball):
        return type(obj)(pickle_balls(v) for v in obj)
    return obj


def unpickle_balls(obj):
    """The inverse of :func:`pickle_balls`: each ball with the same exact midpoint and a
    radius at least as large (FLINT rounds a radius up to its 30-bit mantissa, so it may
    grow by one unit there): an enclosure of whatever the original enclosed."""
    import flint
    if isinstance(obj, _Ball):
        m, e, r, re = obj
        with working_precision(max(64, m.bit_length() + 8)):     # the midpoint exactly
            mid, rad = (flint.arb(a) * flint.arb(2) ** b if b >= 0 else
                        flint.arb(a) / flint.arb(2) ** -b for a, b in ((m, e), (r, re)))
            return flint.arb(mid, rad)
    if isinstance(obj, dict):
        return {k: unpickle_balls(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(unpickle_balls(v) for v in obj)
    return obj


def _fmpq_pow2(man, exp):
    import flint
    return flint.fmpq(man * 2 ** exp) if exp >= 0 else flint.fmpq(man, 2 ** -exp)


def refine_roots(coeffs, rel_tol: float, *, bits: int = 64, max_bits: int = MAX_BITS):
    """Real roots whose balls have relative radius below ``rel_tol``.

    Doubles the working precision until every ball satisfies
    ``rad <= rel_tol * |mid|`` (compared exactly: the ends of an ``arb`` ball are binary
    rationals, and so is a float ``rel_tol``; an exact ball, ``rad == 0``, always does);
    raises :class:`UncertifiedError` beyond ``max_bits``, and :class:`InputError` for a
    ``rel_tol`` that is not a finite number > 0.
    """
    import math
    import numbers
    p, floats = _exact_poly(coeffs)
    if isinstance(rel_tol, bool) or not isinstance(rel_tol, numbers.Real) or not (
            math.isfinite(rel_tol) and rel_tol > 0):
        # (QA: 0, -1 and NaN were accepted, and the answer was no narrower for them)
        raise InputError(f"expected rel_tol as a finite number > 0 (a relative radius), "
                         f"got {rel_tol!r}", field="rel_tol")
    tol = _coefficient(float(rel_tol), "rel_tol")[0]
    bits, max_bits = _bits(bits, "bits"), _bits(max_bits, "max_bits")
    while True:
        roots = [replace(r, from_float=floats) for r in real_roots(p, bits=bits)]
        # exactly, not in float64: float(rad) underflowed to 0 below about 1e-308 and
        # float(mid) overflowed to inf beyond 1e308, which passed any rel_tol (QA)
        if all(_narrow(r.ball, tol) for r in roots):
            return roots
        if bits >= max_bits:
            raise UncertifiedError(f"root enclosures still wider than {rel_tol:.1e} "
                                   f"(relative) at {bits} bits")
        bits *= 2


def _narrow(ball, tol) -> bool:
    """Is the ball's radius at most ``tol`` (fmpq) times the modulus of its midpoint,
    exactly?"""
    lower, upper = ball_ends(ball)
    mid, rad = (lower + upper) / 2, (upper - lower) / 2
    return rad == 0 or rad <= tol * abs(mid)


def sign_at_root(coeffs, other, root: RealRoot, *, max_bits: int = MAX_BITS) -> int:
    """Certified sign (-1, 0, +1) of the polynomial ``other`` at a real root of ``coeffs``.

    The sign is read from a ball evaluation, refining the root while the ball contains
    0.  When it keeps containing 0, an exact test decides: ``other`` vanishes at the
    root iff the root is also a root of ``gcd(coeffs, other)``.

    Parameters
    ----------
    coeffs, other : see :func:`exact_poly` (both highest degree first)
    root : RealRoot
        A root of ``coeffs`` from :func:`real_roots`.
    """
    import flint
    p = exact_poly(coeffs)
    q = flint.fmpq_poly(exact_poly(other, field="other"))
    max_bits = _bits(max_bits, "max_bits")
    bits = root.bits
    ball = root.ball
    checked_gcd = False
    while True:
        with working_precision(bits):
            val = _eval_arb(q, ball)
        if val > 0:
            return 1
        if val < 0:
            return -1
        if not checked_gcd:
            checked_gcd = True
            g = p.gcd(exact_poly(other))
            if g.degree() >= 1 and _shares_root(p, g, root):
                return 0
        if bits >= max_bits:
            raise UncertifiedError(f"cannot decide the sign at root {root.ball} within "
                                   f"{max_bits} bits")
        bits *= 2
        ball = real_roots(p, bits=bits)[root.index].ball


def _eval_arb(q, x):
    import flint
    acc = flint.arb(0)
    for c in reversed(q.coeffs()):
        acc = acc * x + flint.arb(c)
    return acc


def _shares_root(p, g, root: RealRoot) -> bool:
    """Is the real root ``root`` of ``p`` also a root of its factor ``g``?"""
    bits = root.bits
    while True:
        groots = real_roots(g, bits=bits)
        proots = real_roots(p, bits=bits)
        target = proots[root.index].ball
        hits = [r for r in groots if r.ball.overlaps(target)]
        if not hits:
            return False
        # every root of g is a root of p; p's balls are disjoint, so a g-ball inside
        # the target (and no other p-ball) is the target root itself
        if all(sum(r.ball.overlaps(pr.ball) for pr in proots) == 1 for r in hits):
            return True
        if bits >= MAX_BITS:
            raise UncertifiedError("cannot match the roots of a common factor")
        bits *= 2
