r"""Input of the octahedral forward kinematics: points and legs, checked, in every tier.

Labels follow docs/design.md §3 and Rojas et al. (ICRA 2012) Fig. 4: base P1 P2 P3, platform
P4 P5 P6; leg 1 = P1-P4, 2 = P2-P4, 3 = P2-P5, 4 = P3-P5, 5 = P3-P6, 6 = P1-P6.  The
squared lengths are computed exactly when the data are exact (``"19.8"`` is 99/5,
``"sqrt(108)"`` squares to 108), so the certified tier works on exact rationals.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
import math
from fractions import Fraction
from functools import lru_cache

import numba
import numpy as np

from ..argcheck import no_booleans
from ..errors import DegenerateGeometryError, InputError
from ..exact import Exact, exact_to_float, parse_exact
from .banana import LEG_PAIRS, SIDE_PAIRS
from .exact_input import (check_triangle_exact, irrational_inputs, positive, square,
                          square_distance, tiny_leg)
from .scaling import KEEP, check_range, exponent, exponents, scale_problem

__all__ = ["Problem", "exact_problem", "float_problem", "float_single", "LEG_PAIRS",
           "SIDE_PAIRS", "REASONS", "sides_into", "check_triangle",
           "check_triangle_exact"]

#: status codes of the real roots the fast tier finds, and what they mean
REASONS = {
    0: "assembly mode",
    1: "spurious: outside the triangle bounds of s15 (a triangle through P1 P5 cannot close)",
    2: "spurious: a tetrahedron of the bananas has negative squared volume (complex assembly)",
    3: "rejected: the trilateration sequence or the leg check failed at this root",
}


@dataclass(frozen=True)
class Problem:
    """One forward-kinematics problem with exact data where available.

    Attributes
    ----------
    base, platform : tuple of 3 tuples of 3 values (Fraction, or sympy expressions
        when irrational); platform in its own frame.
    legs : tuple of 6 leg lengths (same types).
    sides2 : tuple of 6 squared sides s12 s13 s23 s45 s46 s56 (Fraction when rational).
    legs2 : tuple of 6 squared legs (Fraction when rational).
    from_float : bool
        Some value was a bare float, taken as its exact binary value.
    exponent : int
        Every length here is the given one divided by ``2**exponent``
        (:mod:`.scaling`); answers are scaled back by the caller.
    float_fields : tuple of (field, float)
        The bare floats of the data (:meth:`float_note`).
    irrational : tuple of (field, text, squares)
        The irrational inputs that make a squared length irrational (what the certified
        tier needs rational): a coordinate of an end of an irrational squared side, or
        a leg with an irrational square; ``squares`` names those squared lengths.
    """

    base: tuple
    platform: tuple
    legs: tuple
    sides2: tuple
    legs2: tuple
    from_float: bool
    exponent: int = 0
    float_fields: tuple = ()
    irrational: tuple = ()

    def float_note(self) -> str:
        """What an exact tier's ``accuracy`` adds when some data were bare floats
        (docs/design.md §3: "the result says so", QA T 3): their fields, and the exact
        value of the first one; "" when none."""
        if not self.float_fields:
            return ""
        from decimal import Decimal
        name, value = self.float_fields[0]
        more = ", ".join(n for n, _ in self.float_fields[1:4])
        if len(self.float_fields) > 4:
            more += f" and {len(self.float_fields) - 4} more"
        return (f"; of the data as given: bare floats are taken as their exact binary "
                f"values ({name} = {value!r} is {Decimal(value)}"
                + (f"; also {more}" if more else "") + "), so the answer is theirs")

    @property
    def rational(self) -> bool:
        """All squared lengths exact rationals (needed by the certified tier)."""
        return all(isinstance(v, Fraction) for v in self.sides2 + self.legs2)

    def floats(self):
        """``(base (3,3), platform (3,3), legs (6,))`` as float64 arrays."""
        f = lambda rows: np.array([[float(v) for v in r] for r in rows])  # noqa: E731
        return f(self.base), f(self.platform), np.array([float(v) for v in self.legs])


def _exact(value, field):
    if isinstance(value, Exact):
        return value
    if isinstance(value, (np.floating, np.integer)):
        value = value.item()
    if isinstance(value, str):
        return _parse_text(value, field)
    return parse_exact(value, field)


@lru_cache(maxsize=512)
def _parse_text(text, field):
    """Parsing ``"sqrt(108)"`` goes through sympy (ms); the same text parses once."""
    return parse_exact(text, field)


def _rows(value, field):
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise InputError(f"expected 3 points of 3 coordinates, got {value!r}", field=field)
    out = []
    for i, r in enumerate(value):
        if isinstance(r, np.ndarray):
            r = r.tolist()
        if not isinstance(r, (list, tuple)) or len(r) != 3:
            raise InputError(f"expected 3 coordinates, got {r!r}", field=f"{field}[{i}]")
        out.append(tuple(_exact(v, f"{field}[{i}][{j}]") for j, v in enumerate(r)))
    return tuple(out)


def check_triangle(sq, names, field):
    """Refuse a collinear or coincident triangle from its three squared sides ``sq``
    (exact or float): 16 area^2 by Heron's formula against 1e-12 (a + b + c)^2, the test
    of every route of the solver (:func:`float_problem`, :func:`float_single` inline it);
    :class:`DegenerateGeometryError` naming the points ``names`` and ``field``."""
    a, b, c = (float(v) for v in sq)
    # 16 A^2 = 2(ab + bc + ca) - (a^2 + b^2 + c^2), relative to the largest side (the test
    # is homogeneous: a triangle tiny against the legs must not underflow to "flat")
    m = max(a, b, c)
    a, b, c = (a / m, b / m, c / m) if m > 0 else (a, b, c)
    a16 = 2 * (a * b + b * c + c * a) - (a * a + b * b + c * c)
    if not a16 > 1e-12 * (a + b + c) ** 2:
        r = a16 / (a + b + c) ** 2 if a + b + c > 0 else 0.0
        # (Heron's form cancels: below ~1e-15 float64 cannot tell thin from collinear)
        # (its computed value there is rounding, often exactly 0: not printed, QA R 6)
        shown = (f"= {r:.3g}" if r > 1e-15 else
                 "<= 1e-15, below what float64 resolves: collinear or just thin")
        raise DegenerateGeometryError(
            f"expected a proper triangle {names}, got collinear or coincident points, or "
            f"points within the solver's tolerance of that (16 area^2 / (sum of squared "
            f"sides)^2 {shown}, not above 1e-12)", field=field)


def _largest(B, Q, L):
    """The largest modulus of a coordinate or a leg (floats), and its field."""
    best, field = -1.0, "legs"
    for name, rows in (("base", B), ("platform", Q)):
        for i, r in enumerate(rows):
            for j, v in enumerate(r):
                if abs(v) > best:
                    best, field = abs(v), f"{name}[{i}][{j}]"
    for i, v in enumerate(L):
        if v > best:
            best, field = v, f"legs[{i}]"
    return best, field


def exact_problem(base, platform, legs) -> Problem:
    """Parse and check the data exactly (precise and certified tiers), normalised by a
    power of two (:mod:`.scaling`; ``Problem.exponent``).

    Raises
    ------
    InputError
        Wrong shapes, unparsable numbers, non-positive legs, lengths beyond float64's
        range (:func:`.scaling.check_range`).
    DegenerateGeometryError
        A collinear base or platform triangle.
    """
    B = _rows(base, "base")
    Q = _rows(platform, "platform")
    if isinstance(legs, np.ndarray):
        legs = legs.tolist()
    if not isinstance(legs, (list, tuple)) or len(legs) != 6:
        raise InputError(f"expected 6 leg lengths, got {legs!r}", field="legs")
    L = tuple(_exact(v, f"legs[{i}]") for i, v in enumerate(legs))
    # every value through exact_to_float with its field (float(v) named none, QA)
    fB, fQ = ([[exact_to_float(v, f"{name}[{i}][{j}]") for j, v in enumerate(r)]
               for i, r in enumerate(rows)] for name, rows in (("base", B), ("platform", Q)))
    fL = [exact_to_float(v, f"legs[{i}]") for i, v in enumerate(L)]
    for i, (v, f) in enumerate(zip(L, fL)):
        if not f > 0:
            if f == 0 and positive(v.value):
                raise tiny_leg(v.text, f"legs[{i}]")
            raise InputError(f"expected a positive leg length, got {v.text}", field=f"legs[{i}]")
    largest, field = _largest(fB, fQ, fL)
    check_range(largest, field)
    pts = {1: B[0], 2: B[1], 3: B[2], 4: Q[0], 5: Q[1], 6: Q[2]}
    sides2 = tuple(square_distance(pts[i], pts[j]) for i, j in SIDE_PAIRS)
    legs2 = tuple(square(v) for v in L)
    named = ([(f"legs[{i}]", v) for i, v in enumerate(L)]
             + [(f"{w}[{i}][{j}]", v) for w, rows in (("base", B), ("platform", Q))
                for i, r in enumerate(rows) for j, v in enumerate(r)])
    floats = tuple((n, float(v.value)) for n, v in named if v.from_float)
    k = exponent(largest)
    problem = scale_problem(Problem(tuple(tuple(v.value for v in r) for r in B),
                                    tuple(tuple(v.value for v in r) for r in Q),
                                    tuple(v.value for v in L), sides2, legs2,
                                    bool(floats)), k)
    check_triangle_exact(problem.sides2[:3], "P1 P2 P3", "base")
    check_triangle_exact(problem.sides2[3:], "P4 P5 P6", "platform")
    return replace(problem, exponent=k, float_fields=floats,
                   irrational=irrational_inputs(B, Q, L, sides2, legs2))


def _floats(value, field):
    """(float array, exact array): the values as floats, and whether each float is the
    value itself (False where a string, a large integer or a Fraction was rounded).
    Numeric strings go through the exact parser (``"sqrt(108)"``)."""
    try:
        raw = np.asarray(value)
    except ValueError:
        raise InputError(f"expected a regular array of numbers, got {value!r}",
                         field=field) from None
    no_booleans(value, field)
    if raw.dtype.kind == "f":
        return raw.astype(float), np.ones(raw.shape, bool)
    if raw.dtype.kind in "iu":
        a = raw.astype(float)
        with np.errstate(invalid="ignore"):
            return a, np.abs(raw) < 2 ** 53
    # element by element (not np.vectorize: its floating-point error check would report
    # flags raised by the lazy sympy import inside the first parse)
    obj = np.asarray(value, dtype=object)
    vals, exact = [], []
    for k, v in enumerate(obj.ravel()):
        if isinstance(v, (float, np.floating)):
            vals.append(float(v))
            exact.append(True)
            continue
        at = field + "".join(f"[{int(j)}]" for j in np.unravel_index(k, obj.shape))
        x = _exact(v, at)                   # (the element named, as the exact tiers do)
        f = exact_to_float(x, at)           # (beyond float64, "1e400")
        if f == 0 and field == "legs" and x.value != 0:     # as the exact tiers say
            if positive(x.value):
                raise tiny_leg(x.text, at)                  # ("1e-400")
            raise InputError(f"expected a positive leg length, got {x.text}", field=at)
        vals.append(f)
        exact.append(isinstance(x.value, Fraction) and math.isfinite(f)
                     and Fraction(f) == x.value)
    return (np.array(vals, dtype=float).reshape(obj.shape),
            np.array(exact, dtype=bool).reshape(obj.shape))


def float_problem(base, platform, legs, *, flat: str = "raise"):
    """Float arrays for the fast tier, batched, normalised by powers of two
    (:mod:`.scaling`): ``base (N,3,3)``, ``platform (N,3,3)``, ``legs (N,6)``, the
    squared sides ``(N,6)`` and legs ``(N,6)``, the exponents ``k (N,)`` (lengths divided
    by ``2**k``) and ``rounded (N,)``: some input of the problem is not exactly its
    float (a string such as ``"19.8"`` or ``"sqrt(108)"``, parsed exactly, then rounded).

    The arrays returned are C-contiguous (a shared base or platform is copied per
    problem, as :func:`.batched.solve_fast` would copy it).  Float64 arrays
    ``(N, 3, 3)``, ``(N, 3, 3)``, ``(N, 6)`` (C-contiguous) whose problems all pass the
    checks of :func:`float_single` without rescaling (:func:`_arrays_ok`, compiled,
    problem by problem, the squared lengths computed in the same pass: the
    numbers of :func:`_sides2` and of the single solve) are returned as they are, ``k``
    and ``rounded`` zero (issue 17: the general path's ~30 numpy calls cost ~0.3 µs per
    problem); everything else takes the general path, which raises the errors.

    ``flat="mask"``: a problem whose base or platform triangle fails
    :func:`check_triangle` is not refused; its rows are replaced by a placeholder
    problem (an equilateral octahedron) and an eighth array ``flat (N,)`` bool marks it,
    so that one thin triangle does not cost the other problems of a batch their answers
    (QA N 1).  Every other refusal stays.
    """
    if (type(base) is np.ndarray and type(platform) is np.ndarray and type(legs) is np.ndarray
            and base.dtype == _F8 and platform.dtype == _F8 and legs.dtype == _F8
            and base.ndim == 3 and base.shape[0] > 0 and base.shape[1:] == _SHAPE33
            and platform.shape == base.shape and legs.shape == (base.shape[0], 6)
            and base.flags.c_contiguous and platform.flags.c_contiguous
            and legs.flags.c_contiguous):
        n = base.shape[0]
        s2, l2 = np.empty((n, 6)), np.empty((n, 6))
        if _batch_ok(base, platform, legs, s2, l2):
            out = base, platform, legs, s2, l2, np.zeros(n, np.int64), np.zeros(n, bool)
            return out + (np.zeros(n, bool),) if flat == "mask" else out

    def arr(value, field, shape):
        a, exact = _floats(value, field)
        if a.shape[-len(shape):] != shape or a.ndim > len(shape) + 1:   # one batch axis
            dims = ", ".join(map(str, shape))          # (QA: "(..., 6)" suggested more)
            raise InputError(f"expected shape {shape} or (N, {dims}), got {a.shape}",
                             field=field)
        ok = np.isfinite(a)
        if not np.all(ok):
            at = tuple(int(v) for v in np.argwhere(~ok)[0])
            raise InputError(f"expected finite numbers, got {float(a[at])!r}",
                             field=field + "".join(f"[{v}]" for v in at))
        return a, ~exact
    B, rB = arr(base, "base", (3, 3))
    Q, rQ = arr(platform, "platform", (3, 3))
    L, rL = arr(legs, "legs", (6,))
    N = max([a.shape[0] for a, nd in ((B, 3), (Q, 3), (L, 2)) if a.ndim == nd], default=1)
    for a, nd, field, shape in ((B, 3, "base", "3, 3"), (Q, 3, "platform", "3, 3"),
                                (L, 2, "legs", "6")):
        if a.ndim == nd and a.shape[0] != N:
            sizes = ", ".join(f"{f} {x.shape}" for x, d, f in ((B, 3, "base"),
                              (Q, 3, "platform"), (L, 2, "legs")) if x.ndim == d)
            raise InputError(f"expected {N} problems of shape ({N}, {shape}) (or one "
                             f"without a batch axis), got shape {a.shape} ({sizes})",
                             field=field)
    # a field is named as the value was given: problem index first where that array has
    # a batch axis (legs[1][0]: problem 1, leg 0), as the finite-numbers check above does
    axis = {"base": B.ndim == 3, "platform": Q.ndim == 3, "legs": L.ndim == 2}

    def at(i, where):
        name = where.split("[", 1)[0]
        return f"{name}[{i}]{where[len(name):]}" if axis[name] else where
    B = np.broadcast_to(B, (N, 3, 3))
    Q = np.broadcast_to(Q, (N, 3, 3))
    L = np.broadcast_to(L, (N, 6))
    rounded = (np.broadcast_to(rB, (N, 3, 3)).any(axis=(1, 2))
               | np.broadcast_to(rQ, (N, 3, 3)).any(axis=(1, 2))
               | np.broadcast_to(rL, (N, 6)).any(axis=1))
    if np.any(L <= 0):
        i = tuple(int(v) for v in np.argwhere(L <= 0)[0])
        raise InputError(f"expected a positive leg length, got {float(L[i])!r}",
                         field=at(i[0], f"legs[{i[1]}]"))
    largest = np.maximum(np.maximum(np.abs(B).max(axis=(1, 2)), np.abs(Q).max(axis=(1, 2))),
                         L.max(axis=1))
    bad = ~((largest < 2.0 ** 510) & (largest >= 2.0 ** -500))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        big, where = _largest(B[i].tolist(), Q[i].tolist(), L[i].tolist())  # as the others
        check_range(big, at(i, where))
    k = exponents(largest)
    if k.any():
        B = np.ldexp(B, -k[:, None, None])
        Q = np.ldexp(Q, -k[:, None, None])
        L = np.ldexp(L, -k[:, None])
    sides2 = _sides2(B, Q)
    thin = np.zeros(N, bool)
    for (j, names, fld) in ((0, "P1 P2 P3", "base"), (3, "P4 P5 P6", "platform")):
        a, b, c = sides2[:, j], sides2[:, j + 1], sides2[:, j + 2]
        m = np.maximum(np.maximum(a, b), c)       # (relative: no underflow, see
        m = np.where(m > 0, m, 1.0)               # check_triangle)
        a, b, c = a / m, b / m, c / m
        a16 = 2 * (a * b + b * c + c * a) - (a * a + b * b + c * c)
        bad = ~(a16 > 1e-12 * (a + b + c) ** 2)
        if np.any(bad) and flat != "mask":
            i = int(np.flatnonzero(bad)[0])
            check_triangle(sides2[i, j:j + 3], names + (f" of problem {i}" if N > 1 else ""),
                           f"{fld}[{i}]" if N > 1 else fld)
        thin |= bad
    # C-contiguous copies (np.array of a broadcast keeps its odd strides: the rows B[i],
    # Q[i] then differ in layout, which the compiled callees must not see; QA: a batch
    # with a thin triangle and rounded inputs crashed with a numba TypingError)
    B, Q, L = (np.ascontiguousarray(a) for a in (B, Q, L))
    if flat != "mask":
        return B, Q, L, sides2, L * L, k, rounded
    if thin.any():                  # placeholders, solved and then blanked by the caller
        B, Q, L = (np.array(a, order="C") for a in (B, Q, L))
        B[thin], Q[thin], L[thin] = _PLACEHOLDER
        sides2 = _sides2(B, Q)
    return B, Q, L, sides2, L * L, k, rounded, thin


#: the problem solved in place of one with a flat triangle (``float_problem(flat="mask")``):
#: equilateral base of side 1, platform of side 1/2, legs 1 (its answers are discarded)
_PLACEHOLDER = (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.75 ** 0.5, 0.0]]),
                np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.25, 0.1875 ** 0.5, 0.0]]),
                np.ones(6))


@numba.njit(cache=True)
def _sides2(B, Q):
    """The squared sides s12 s13 s23 s45 s46 s56 (N, 6) of the base and platform
    triangles B, Q (N, 3, 3), compiled: :func:`sides_into` row by row, so that a batched
    solve and a single one (:func:`.companion._squares`) start from the same squared
    lengths, bit for bit (before, numpy's ``einsum`` summed in another order: a quarter
    of the values differed in the last bit on random data)."""
    out = np.empty((B.shape[0], 6))
    for i in range(B.shape[0]):
        sides_into(B[i], Q[i], out[i])
    return out


@numba.njit(cache=True)
def sides_into(B, Q, out):
    """The squared sides s12 s13 s23 s45 s46 s56 (the pairs of
    :data:`~.banana.SIDE_PAIRS`) of the triangles B, Q (3, 3) into ``out`` (6,):
    :math:`(x_i - x_j)^2 + (y_i - y_j)^2 + (z_i - z_j)^2`, summed left to right.  The one
    formula of the fast tier's squared sides, single and batched."""
    for k in range(2):
        P = B if k == 0 else Q
        for m in range(3):
            i, j = (0, 0, 1)[m], (1, 2, 2)[m]
            dx, dy, dz = P[i, 0] - P[j, 0], P[i, 1] - P[j, 1], P[i, 2] - P[j, 2]
            out[3 * k + m] = dx * dx + dy * dy + dz * dz


def float_single(base, platform, legs):
    """One problem for the fast tier, with the checks of :func:`float_problem` at a
    fraction of its cost, normalised by a power of two (:mod:`.scaling`).

    Returns
    -------
    base, platform : lists of 3 lists of 3 floats (rows), divided by ``2**k`` (or the
        given (3, 3) float64 arrays themselves, on the fast path below)
    legs : list of 6 floats, divided by ``2**k`` (or the given (6,) array)
    k : int
    rounded : bool
        Some input is not exactly its float (see :func:`float_problem`).

    Float64 arrays of the right shapes whose values need no rescaling and pass every
    check are returned as they are (the checks compiled, :func:`_arrays_ok`); other
    plain numbers (and numpy arrays of them) take a path in plain Python floats; other
    inputs (numeric strings such as ``"sqrt(108)"``, wrong shapes) go through
    :func:`float_problem` and raise the same errors.
    """
    if (type(base) is np.ndarray and type(platform) is np.ndarray and type(legs) is np.ndarray
            and base.shape == _SHAPE33 and platform.shape == _SHAPE33
            and legs.shape == _SHAPE6 and base.dtype == _F8 and platform.dtype == _F8
            and legs.dtype == _F8 and base.flags.c_contiguous and platform.flags.c_contiguous
            and legs.flags.c_contiguous and _arrays_ok(base, platform, legs)):
        return base, platform, legs, 0, False
    try:
        B = _float_rows(base)
        Q = _float_rows(platform)
        L = _float_row(legs.tolist() if isinstance(legs, np.ndarray) else legs, 6)
    except (TypeError, ValueError):             # (unpacking a wrong shape: ValueError)
        for value, field, shape in ((base, "base", _SHAPE33), (platform, "platform", _SHAPE33),
                                    (legs, "legs", _SHAPE6)):
            try:
                got = np.shape(value)
            except ValueError:                  # (ragged)
                got = None
            if field == "legs" and got == ():     # a string, None: as the exact tiers say
                raise InputError(f"expected 6 leg lengths, got {value!r}", field=field)
            if got is not None and got != shape:
                raise InputError(f"expected shape {shape}, got {got}", field=field,
                                 hint="use forward_kinematics_batched for many problems"
                                 if len(got) > len(shape) else None)
        B, Q, L, _, _, k, rounded = float_problem(base, platform, legs)
        return B[0].tolist(), Q[0].tolist(), L[0].tolist(), int(k[0]), bool(rounded[0])
    isfinite = math.isfinite
    flat = B[0] + B[1] + B[2] + Q[0] + Q[1] + Q[2]
    if not all(map(isfinite, flat + L)):
        raise InputError("expected finite numbers, got NaN or inf", field="legs")
    if min(L) <= 0:
        i = next(i for i, v in enumerate(L) if v <= 0)
        raise InputError(f"expected a positive leg length, got {L[i]!r}", field=f"legs[{i}]")
    largest = max(max(flat), -min(flat), max(L))
    k = 0 if _SMALL <= largest < _LARGE else exponent(largest)
    if k:
        largest, field = _largest(B, Q, L)
        check_range(largest, field)
        B = [[math.ldexp(v, -k) for v in r] for r in B]
        Q = [[math.ldexp(v, -k) for v in r] for r in Q]
        L = [math.ldexp(v, -k) for v in L]
    for P, names, fld in ((B, "P1 P2 P3", "base"), (Q, "P4 P5 P6", "platform")):
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = P
        a = (ax - bx) ** 2 + (ay - by) ** 2 + (az - bz) ** 2
        b = (ax - cx) ** 2 + (ay - cy) ** 2 + (az - cz) ** 2
        c = (bx - cx) ** 2 + (by - cy) ** 2 + (bz - cz) ** 2
        if not 2 * (a * b + b * c + c * a) - (a * a + b * b + c * c) > 1e-12 * (a + b + c) ** 2:
            check_triangle((a, b, c), names, fld)   # (relative: a tiny triangle is not flat)
    return B, Q, L, k, False


_SMALL, _LARGE = 2.0 ** -KEEP, 2.0 ** KEEP       # lengths not rescaled (.scaling)
_SHAPE33, _SHAPE6, _F8 = (3, 3), (6,), np.dtype(np.float64)


@numba.njit(cache=True)
def _arrays_ok(B, Q, L):
    """The checks of :func:`float_single` on float64 arrays B, Q (3, 3), L (6,), compiled
    (issue 17): every value finite, legs positive, the largest modulus in
    [_SMALL, _LARGE) (no rescaling), both triangles proper (the same formula and
    threshold).  False sends the data down the general path, which raises the error."""
    return _row_ok(B, Q, L, np.empty(6))


@numba.njit(cache=True)
def _row_ok(B, Q, L, s2):
    """:func:`_arrays_ok`, the squared sides left in ``s2`` (6,) (:func:`sides_into`;
    the triangle test reads them: the same numbers as the general path's)."""
    largest = 0.0
    for i in range(3):
        for j in range(3):
            v, w = B[i, j], Q[i, j]
            if not (math.isfinite(v) and math.isfinite(w)):
                return False
            largest = max(largest, abs(v), abs(w))
    for i in range(6):
        v = L[i]
        if not (math.isfinite(v) and v > 0):
            return False
        largest = max(largest, v)
    if not _SMALL <= largest < _LARGE:
        return False
    sides_into(B, Q, s2)
    for t in (0, 3):
        a, b, c = s2[t], s2[t + 1], s2[t + 2]
        if not 2 * (a * b + b * c + c * a) - (a * a + b * b + c * c) > 1e-12 * (a + b + c) ** 2:
            return False
    return True


@numba.njit(cache=True)
def _batch_ok(B, Q, L, s2, l2):
    """:func:`_row_ok` for every problem of (N, 3, 3), (N, 3, 3), (N, 6) arrays, the
    squared sides and legs written to ``s2``, ``l2`` (N, 6)."""
    for i in range(B.shape[0]):
        if not _row_ok(B[i], Q[i], L[i], s2[i]):
            return False
        for j in range(6):
            l2[i, j] = L[i, j] * L[i, j]
    return True


def _float_row(r, n):
    """n plain floats, or TypeError/ValueError (then the general path): a value comes
    this way only when its float compares equal to it (floats, numpy floats, integers
    below 2^53), so that every float here is exactly the value given; strings,
    Fractions, large integers and sympy numbers take the general path, which says when
    it rounds."""
    if len(r) != n or any(type(v) is bool for v in r):
        raise ValueError
    row = list(map(float, r))
    if row != list(r):            # exact comparisons: "19.8" or 1/3 is not its float
        raise ValueError
    return row


def _float_rows(value):
    """3 rows of 3 plain floats (the rule of :func:`_float_row`)."""
    if isinstance(value, np.ndarray):
        if value.shape != (3, 3) or value.dtype.kind != "f":
            raise ValueError
        return value.tolist()
    (a, b, c), (d, e, f), (g, h, i) = value
    x = _float_row((a, b, c, d, e, f, g, h, i), 9)
    return [x[0:3], x[3:6], x[6:9]]
