r"""Trilateration: the point at given squared distances from three points.

Thomas and Ros, *Revisiting trilateration for robot localization*, IEEE T-RO 21(1),
2005 (ref. [10] of Rojas et al.), written in Gram form so that the same lines run in
every tier.  With :math:`v_2 = P_b - P_a`, :math:`v_3 = P_c - P_a`,
:math:`n = v_2 \times v_3` and :math:`G = \|n\|^2 = -D(a,b,c)/4`:

.. math::

    P = P_a + \alpha v_2 + \beta v_3 \pm \sqrt{h^2 / G}\; n,
    \qquad h^2 = -\frac{D(a,b,c,P)}{2\,D(a,b,c)}

where :math:`h` is the height of :math:`P` over the plane of the three points, so
:math:`h^2 < 0` means the distances cannot close (:class:`InfeasibleError`, with
:math:`h^2` as the margin, in squared length units), and :math:`G = 0` means the three
points are collinear or coincident (:class:`DegenerateGeometryError`).

``side = +1`` puts the point on the side of :math:`n`, i.e.
:math:`(P - P_a)\cdot((P_b-P_a)\times(P_c-P_a)) \ge 0`; ``side = -1`` the mirror.

Inputs are numbers of any tier or numeric strings, parsed exactly in every tier
(``"19.8"`` is 99/5, ``"sqrt(2)"``; :func:`distkin.exact.parse_exact`), then rounded once
in the fast tier.  The fast tier works in units of :math:`2^e`, the power of two just
above the reference triangle's largest coordinate difference (an exact scaling: the
same bits as unscaled, where that neither under- nor overflows), so a triangle of size
1e-100 or 1e150 is not flattened by an underflow of :math:`G` nor lost to an overflow.

The fast tier also estimates its error to first order
(:func:`.trilat_error.fast_error`): the Gram solve loses digits like
:math:`1/\sin^2\theta` on a nearly collinear base (:math:`\theta` its angle at
:math:`P_a`), and the height of a point near the base's plane is known to
:math:`\sqrt\delta` only, :math:`\delta` the error of :math:`h^2`.  Where the estimate
exceeds :data:`~.trilat_error.TRILATERATION_RTOL` (1e-6) of the problem's length scale
:math:`\Lambda = \sqrt{|s_a|+|s_b|+|s_c|+|v_2|^2+|v_3|^2}` it warns, once per call
(:class:`~distkin.errors.ConditioningWarning`; an unwarned answer is within that of the
exact trilateration of its float64 inputs, by the estimate); the estimate is
``TrilaterationParts.error``.  It refuses (:class:`InfeasibleError`) only an :math:`h^2`
negative beyond its error estimate; within it :math:`h^2` is clamped to 0 (the point in
the plane) with a warning that the configuration may not exist (a ``tol`` of the caller's
decides alone).  The precise tier does the same in mpmath at its ``dps``, warning above
:func:`~.trilat_error.precise_rtol` (:math:`10^{2-dps/2}`, 1e-13 at 30 digits); the
library's own solvers (:func:`parts_at_working_digits`) keep their tolerance and no
warning.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ..argcheck import as_floats, no_booleans, positive_number
from ..errors import DegenerateGeometryError, InfeasibleError, InputError, UncertifiedError
from ..exact import Exact, check_method, default_dps, parse_exact, parse_float, to_tier
from .trilat_error import (TRILATERATION_RTOL, fast_error, point_error, precise_rtol,
                           warn_accuracy)
from ..errors import warn as _warn

__all__ = ["trilaterate", "trilaterate_both", "TrilaterationParts", "trilateration_parts",
           "TRILATERATION_RTOL"]

_EPS = np.finfo(float).eps


class TrilaterationParts:
    """Foot of the perpendicular, the normal n, G = |n|^2 and h^2, in one tier.

    Attributes are sequences of three components (numpy arrays when batched).  ``foot``
    is in length units; in the fast tier ``normal``, ``G`` and ``h2`` are those of the
    reference points scaled by :math:`2^{-e}` (exactly), ``e = exponent`` (an integer
    array when batched; 0 in the other tiers): times :math:`4^e`, :math:`16^e` and
    :math:`4^e` in length units, which float64 may not hold.
    """

    __slots__ = ("foot", "normal", "G", "h2", "method", "exponent", "error")

    def __init__(self, foot, normal, G, h2, method, exponent=0, error=None):
        self.foot, self.normal, self.G, self.h2, self.method = foot, normal, G, h2, method
        self.exponent = exponent
        #: fast and precise tiers: the first-order error estimate of the point (length
        #: units; an array when batched), :func:`.trilat_error.fast_error`; None in the
        #: certified tier and in the library's own solvers
        self.error = error

    def point(self, side):
        """The point on ``side`` (+1 or -1, or an array of them when batched)."""
        if self.method == "fast":
            scale = np.sqrt(np.maximum(self.h2, 0.0) / self.G) * side
            return np.stack([f + np.ldexp(scale * c, self.exponent)
                             for f, c in zip(self.foot, self.normal)], axis=-1)
        if self.method == "precise":
            import mpmath
            scale = mpmath.sqrt(max(self.h2, 0) / self.G) * side
            return [f + scale * c for f, c in zip(self.foot, self.normal)]
        import flint
        h2, G = self.h2, self.G
        if type(h2).__name__ == "fmpq" and h2 == 0:
            return list(self.foot)  # in the plane: exact when the data are rational
        scale = (flint.arb(h2) / flint.arb(G)).sqrt() * side
        return [flint.arb(f) + scale * c for f, c in zip(self.foot, self.normal)]


def _fast_floats(value, field, expected, width=None):
    """A float64 array of ``value``: numbers, or numeric strings parsed exactly and
    rounded once (:func:`distkin.exact.parse_float`) as in the other tiers; booleans,
    complex numbers, numbers beyond the float64 range and other things are an
    :class:`InputError` naming the element; with ``width``, a ragged list names its
    first row that has not ``width`` entries."""
    no_booleans(value, field)
    try:
        arr = np.asarray(value)
    except ValueError:                              # ragged
        arr = None
        if width is not None:
            _ragged_rows(value, field, expected, width)
    if arr is not None and arr.dtype.kind in "iuf":
        return arr.astype(float)
    if arr is None or arr.dtype.kind not in "OUSb" or any(
            isinstance(v, (list, tuple, np.ndarray)) for v in arr.flat):
        if arr is not None and arr.dtype.kind == "c":
            raise InputError(f"expected {expected} (real), got complex values "
                             f"{_show(value)}", field=field)
        raise InputError(f"expected {expected}, got {_show(value)}", field=field)
    out = np.empty(arr.shape)
    for idx, v in np.ndenumerate(arr):
        name = field + "".join(f"[{i}]" for i in idx)
        if isinstance(v, (str, bytes)):
            out[idx] = parse_float(str(v) if isinstance(v, str) else v.decode(), name)
        elif isinstance(v, Exact):
            out[idx] = to_tier(v, "fast")
        elif v is None:
            raise InputError("expected a number, got None", field=name)
        else:
            try:
                x = as_floats(v, name, "a number")
            except OverflowError:                   # an int or Fraction beyond float64
                x = np.inf
            if np.isinf(x) and not isinstance(v, (float, np.floating)):
                from .cayley_menger import _show_big
                raise InputError(f"expected a number within the float64 range (|x| < "
                                 f"1.8e308), got {_show_big(v)}", field=name)
            out[idx] = x
    return out


def _ragged_rows(value, field, expected, width):
    """Raise an :class:`InputError` naming the first row (a list of scalars) of the
    nested list ``value`` that has not ``width`` entries (numpy's inhomogeneous-shape
    ValueError does not say which)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple, np.ndarray)):
        return
    if not any(isinstance(v, (list, tuple, np.ndarray)) for v in value):
        if len(value) != width:
            raise InputError(f"expected {expected}, got a row of {len(value)} "
                             f"{'entry' if len(value) == 1 else 'entries'}", field=field)
        return
    for i, v in enumerate(value):
        if not isinstance(v, (list, tuple, np.ndarray)):
            raise InputError(f"expected {expected}, got the scalar {_show(v)} among rows",
                             field=f"{field}[{i}]")
        _ragged_rows(v, f"{field}[{i}]", expected, width)


def _three_rows(points, what: str, field: str) -> list:
    """``points`` as 3 lists of 3 coordinates (any sequence or array), or
    :class:`InputError` naming ``field`` and what came."""
    if isinstance(points, np.ndarray):
        points = points.tolist()
    try:
        rows = [list(r) for r in points]
    except TypeError:
        rows = None
    if rows is None or len(rows) != 3 or any(len(r) != 3 for r in rows):
        raise InputError(f"expected 3 {what} of 3 coordinates, got {_show(points)}",
                         field=field)
    return rows


def _show(value, n=80):
    text = repr(value)
    return text if len(text) <= n else text[:n - 3] + "..."


def _tier_scalar(x, method, field):
    """One coordinate or squared distance in the number type of the precise or certified
    tier: numbers of any tier, or numeric strings parsed exactly (as the fast tier)."""
    no_booleans(x, field)
    if isinstance(x, (np.integer, np.floating)):
        x = x.item()
    if isinstance(x, (str, int, float)):
        x = parse_exact(x, field)      # finite, exact; a string like "12/5" or "sqrt(2)"
    elif not (isinstance(x, (Exact, Fraction)) or type(x).__name__ in ("mpf", "fmpq", "fmpz",
                                                                         "arb")
              or (type(x).__module__ or "").startswith("sympy")):
        raise InputError(f"expected a number or a numeric string, got "
                         f"{type(x).__name__} {_show(x)}", field=field)
    try:
        return to_tier(x, method)
    except InputError as exc:
        raise exc.with_field(field)


def _components(points, method):
    """Split (…, 3, 3) points into 9 scalars (or arrays) of the tier."""
    if method == "fast":
        P = _fast_floats(points, "points", "reference points of shape (..., 3, 3)", 3)
        if P.shape[-2:] != (3, 3):
            raise InputError(f"expected reference points of shape (..., 3, 3), got {P.shape}",
                             field="points")
        if not np.all(np.isfinite(P)):
            raise InputError("expected finite reference points, got NaN or inf", field="points")
        return P
    rows = _three_rows(points, "reference points", "points")
    return [[_tier_scalar(x, method, f"points[{i}][{j}]") for j, x in enumerate(r)]
            for i, r in enumerate(rows)]


def _squared(sq, method):
    """The three squared distances (fast: an array (..., 3)) in the tier's number type."""
    if method == "fast":
        S = _fast_floats(sq, "sq", "squared distances of shape (..., 3)", 3)
        if S.shape[-1:] != (3,):
            raise InputError(f"expected 3 squared distances per point, got shape {S.shape}",
                             field="sq")
        if not np.all(np.isfinite(S)):
            raise InputError("expected finite squared distances, got NaN or inf", field="sq")
        return S
    if isinstance(sq, np.ndarray):
        sq = sq.tolist()
    if not isinstance(sq, (list, tuple)) or len(sq) != 3:
        raise InputError(f"expected 3 squared distances, got {_show(sq)}", field="sq")
    return [_tier_scalar(x, method, f"sq[{i}]") for i, x in enumerate(sq)]


def _check_sides(side, method):
    """``side``: +1 or -1 (fast: an array of them, broadcasting with the batch)."""
    if isinstance(side, (bool, np.bool_)) or (isinstance(side, np.ndarray)
                                              and side.dtype.kind == "b"):
        raise InputError(f"expected side = +1 or -1, got {side!r}", field="side")
    arr = as_floats(side, "side", "side = +1 or -1 (or an array of them)")
    if arr.size == 0 or np.any(np.abs(arr) != 1):
        raise InputError(f"expected side = +1 or -1, got {_show(side)}", field="side")
    if method != "fast":
        if arr.ndim:
            raise InputError(f"expected one side, +1 or -1, in the {method} tier (a batch "
                             f"runs in the fast tier), got shape {arr.shape}", field="side")
        return int(arr)
    return arr


def _broadcast(name, shape, batch):
    try:
        return np.broadcast_shapes(shape, batch)
    except ValueError:
        raise InputError(f"expected batch shapes that broadcast, got {name} batch shape "
                         f"{shape} against {batch}", field=name) from None


def _check_nonnegative(sq, method):
    """Squared distances must be >= 0 (an arb ball only when certainly negative)."""
    if method == "fast":
        bad = np.argwhere(np.asarray(sq) < 0)
        if len(bad):
            idx = tuple(int(i) for i in bad[0])
            raise InputError(f"expected squared distances >= 0, got {float(sq[idx]):.6g}",
                             field="sq" + "".join(f"[{i}]" for i in idx))
        return
    for i, v in enumerate(sq):
        if v < 0:
            raise InputError(f"expected squared distances >= 0, got {v}", field=f"sq[{i}]")


def trilateration_parts(points, sq, *, method: str = "fast", dps: int | None = None,
                        tol: float | None = None) -> TrilaterationParts:
    r"""Compute the pieces of a trilateration and check degeneracy and feasibility.

    Parameters
    ----------
    points : array_like (..., 3, 3)
        Rows :math:`P_a, P_b, P_c`, in any length unit.
    sq : array_like (..., 3)
        Squared distances :math:`s_a, s_b, s_c` from the sought point, same unit squared.
    method : {"fast", "precise", "certified"}
    tol : float, optional
        Relative tolerance of the fast and precise tiers (default: 64 eps for
        ``fast``, 10^(8 - dps) for ``precise``): collinear when :math:`G \le`
        tol :math:`|v_2|^2|v_3|^2`, infeasible when :math:`h^2 <` -tol
        :math:`(|s_a| + |v_2|^2 + |v_3|^2)`; in the fast tier only when :math:`h^2`
        is also below minus its error estimate.  The certified tier is exact on
        rational data and decides with balls otherwise.

    Raises
    ------
    InputError
        Malformed input: shapes, batch shapes that do not broadcast, values that are
        not numbers (or numeric strings), NaN or inf.
    DegenerateGeometryError
        Collinear or coincident reference points.
    InfeasibleError
        :math:`h^2 < 0` beyond the tolerance (fast: and beyond the error estimate of
        :math:`h^2`, else clamped to 0); ``margin`` is :math:`h^2`.  A negative
        squared distance is one such case here (:math:`h^2 \le s < 0`): the octahedral
        solver passes a root :math:`s_{15}` that may be negative and rejects it so;
        :func:`trilaterate` refuses it as an :class:`InputError`.
    UncertifiedError
        Certified tier on irrational data whose balls cannot decide the sign.

    Warns
    -----
    ConditioningWarning
        Fast tier: the error estimate (``.error`` of the result, length units) exceeds
        :data:`~.trilat_error.TRILATERATION_RTOL` times the length scale (see the module
        docstring): a nearly collinear base, or a point near the base's plane.  Precise
        tier: the same above :func:`~.trilat_error.precise_rtol` of ``dps``.
    """
    return _solve(points, sq, _NO_SIDE, method, dps, tol)[0]


def parts_at_working_digits(points, sq, *, method: str, digits: int | None = None,
                            tol: float | None = None):
    """:func:`trilateration_parts` for the library's own solvers: in the precise tier
    ``digits`` are working digits (a dps checked at the solver's entry plus its guard
    digits, :func:`distkin.octahedral.precise.solve_precise`: dps + 20), so they may
    exceed :data:`~distkin.exact.MAX_DPS`, the bound of a user's dps; ``tol`` as for
    :func:`trilateration_parts`."""
    return _solve(points, sq, _NO_SIDE, method, digits, tol, working=True)[0]


_NO_SIDE = object()


def _solve(points, sq, side, method, dps, tol, *, nonnegative=False, working=False):
    """(parts, side): parse and check the input (``side`` too unless _NO_SIDE; squared
    distances >= 0 when ``nonnegative``), then the pieces of the trilateration.
    ``working``: ``dps`` are an internal solver's working digits (not checked)."""
    check_method(method)
    if tol is not None:
        tol = positive_number(tol, "tol")
    if side is not _NO_SIDE:
        side = _check_sides(side, method)
    if method == "precise":
        import mpmath
        dps = dps if working and dps is not None else default_dps(dps)
        ctx = mpmath.workdps(dps)
        ctx.__enter__()
    try:
        P, S = _components(points, method), _squared(sq, method)
        if method == "fast":
            batch = _broadcast("sq", S.shape[:-1], P.shape[:-2])
            if side is not _NO_SIDE:
                _broadcast("side", np.shape(side), batch)
        if nonnegative:
            _check_nonnegative(S, method)
        return _parts(P, S, method, dps, tol, estimate=not working), side
    finally:
        if method == "precise":
            ctx.__exit__(None, None, None)


def _fast_scaled(P, S):
    """The fast tier's inputs in units of 2^e (exact): e per batch element, from the
    largest coordinate difference of the reference triangle."""
    v = P[..., 1:, :] - P[..., :1, :]
    if not np.all(np.isfinite(v)):
        raise InputError("expected reference points whose differences are within the "
                         "float64 range (|x| < 1.8e308)", field="points")
    big = np.max(np.abs(v), axis=(-2, -1))
    e = np.frexp(np.where(big > 0, big, 1.0))[1]
    a = P[..., 0, :]
    u = np.ldexp(v, -e[..., None, None])
    with np.errstate(over="ignore"):
        s = np.ldexp(S, -2 * np.asarray(e)[..., None])
    if not np.all(np.isfinite(s)):
        raise InputError("expected squared distances within the float64 range relative to "
                         "the reference triangle (its size squared times 1.8e308)", field="sq")
    return a, u[..., 0, :], u[..., 1, :], s, e


def _parts(P, S, method, dps, tol, estimate=True):
    if method == "fast":
        a, u2, u3, s, e = _fast_scaled(P, S)
        sa, sb, sc = s[..., 0], s[..., 1], s[..., 2]
        v2 = tuple(u2[..., k] for k in range(3))
        v3 = tuple(u3[..., k] for k in range(3))
    else:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = P
        sa, sb, sc = S
        e = 0
        v2 = (bx - ax, by - ay, bz - az)
        v3 = (cx - ax, cy - ay, cz - az)
    g22 = v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]
    g33 = v3[0] * v3[0] + v3[1] * v3[1] + v3[2] * v3[2]
    g23 = v2[0] * v3[0] + v2[1] * v3[1] + v2[2] * v3[2]
    n = (v2[1] * v3[2] - v2[2] * v3[1],
         v2[2] * v3[0] - v2[0] * v3[2],
         v2[0] * v3[1] - v2[1] * v3[0])
    G = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
    _check_degenerate(G, g22, g33, method, dps, tol)
    w2 = (sa + g22 - sb) / 2
    w3 = (sa + g33 - sc) / 2
    alpha = (w2 * g33 - w3 * g23) / G
    beta = (w3 * g22 - w2 * g23) / G
    off = [alpha * v2[k] + beta * v3[k] for k in range(3)]
    if method == "fast":
        foot = tuple(a[..., k] + np.ldexp(off[k], e) for k in range(3))
    else:
        foot = tuple(P[0][k] + off[k] for k in range(3))
    h2 = sa - (alpha * w2 + beta * w3)
    scale = _scale(sa, g22, g33, method)
    if method == "precise" and estimate:          # a user's call: as the fast tier
        import mpmath
        vals = (sa, sb, sc, g22, g33, g23, G, w2, w3, alpha, beta)
        e_foot, e_h2 = fast_error(*vals, lib=mpmath, eps=mpmath.eps)
        h2 = _check_feasible(h2, scale, method, dps, tol, e, e_h2)
        err, rel = point_error(h2, e_foot, e_h2, vals, 0, foot, True, lib=mpmath,
                               eps=mpmath.eps)
        warn_accuracy(err, rel, precise_rtol(dps), "precise")
        return TrilaterationParts(foot, n, G, h2, method, e, err)
    if method != "fast":          # certified; precise inside the library's solvers
        h2 = _check_feasible(h2, scale, method, dps, tol, e)
        return TrilaterationParts(foot, n, G, h2, method, e)
    vals = (sa, sb, sc, g22, g33, g23, G, w2, w3, alpha, beta)
    one = np.ndim(G) == 0 and np.ndim(sa) == 0 and np.ndim(sb) == 0 and np.ndim(sc) == 0
    # one problem: the estimate in Python floats (numpy's per-call cost on 0-d arrays
    # dominated it); a batch: in numpy
    est = ([float(x) for x in vals], math) if one else (vals, np)
    e_foot, e_h2 = fast_error(*est[0], lib=est[1])
    h2 = _check_feasible(h2, scale, method, dps, tol, e, e_h2)
    err, rel = point_error(h2, e_foot, e_h2, est[0], e, foot, one)
    warn_accuracy(err, rel)
    return TrilaterationParts(foot, n, G, h2, method, e, err)


def _scale(sa, g22, g33, method):
    if method == "fast":
        return np.abs(sa) + g22 + g33
    if method == "precise":
        return abs(sa) + g22 + g33
    return None


def _check_degenerate(G, g22, g33, method, dps, tol):
    if method == "fast":
        t = 64 * _EPS if tol is None else tol
        bad = G <= t * g22 * g33
        if np.any(bad):
            raise DegenerateGeometryError(
                "expected three non-collinear reference points, got collinear or coincident "
                f"points (|v2 x v3|^2 <= {t:.1e}*|v2|^2*|v3|^2)", field="points")
        return
    if method == "precise":
        import mpmath
        t = mpmath.mpf(10) ** (8 - dps) if tol is None else tol
        if G <= t * g22 * g33:
            raise DegenerateGeometryError(
                f"expected three non-collinear reference points, got |n|^2 = {mpmath.nstr(G, 5)}",
                field="points")
        return
    # certified
    if type(G).__name__ == "fmpq":
        if G == 0:
            raise DegenerateGeometryError("expected three non-collinear reference points, got "
                                          "collinear or coincident points (exactly)", field="points")
        return
    if G.is_zero():
        raise DegenerateGeometryError("expected three non-collinear reference points, got "
                                      "collinear points (exactly)", field="points")
    if G.contains(0):
        raise UncertifiedError(f"cannot decide whether the reference points are collinear: "
                               f"|n|^2 = {G.str(5, radius=True)}")


def _warn_doubtful(doubtful, h2, e_h2, tier):
    """Warn where h^2 < 0 beyond the tolerance but within its error estimate (clamped:
    the configuration may not exist; the estimate can be ~1e3 x the error, review)."""
    if doubtful:
        from ..errors import ConditioningWarning
        _warn(ConditioningWarning(
            f"{tier} trilateration: h^2 = {float(np.min(h2)):.3g} is negative but within its "
            f"error estimate {float(np.max(e_h2)):.3g} (squared length units, of the scaled "
            "problem): clamped to 0, the point placed in the base's plane; the configuration"
            " may not exist (method='certified' decides; tol= makes the tolerance decide "
            "alone)"))


def _check_feasible(h2, scale, method, dps, tol, e=0, e_h2=0.0):
    if method == "fast":
        # infeasible only beyond the error estimate of h^2 (e_h2): within it the sign
        # is not known, and h^2 is clamped to 0 (the point in the base's plane; the
        # accuracy warning covers the height error sqrt(e_h2))
        t = 64 * _EPS if tol is None else tol
        # a tol of the caller's decides alone, as before the estimate (review)
        bad = h2 < -(t * scale if tol is not None else np.maximum(t * scale, e_h2))
        _warn_doubtful(np.any((h2 < -t * scale) & ~bad), h2, e_h2, "fast")
        if np.any(bad):
            k = np.unravel_index(np.argmin(h2), np.shape(h2)) if np.ndim(h2) else ()
            ek = int(np.broadcast_to(e, np.shape(h2))[k])
            with np.errstate(over="ignore", under="ignore"):
                worst = float(np.ldexp(h2[k], 2 * ek))                # length units
            shown = f"{worst:.6g}" if worst else f"{float(h2[k]):.6g}*2^{2 * ek}"
            raise InfeasibleError(
                f"expected distances that close (h^2 >= 0), got h^2 = {shown} "
                "(squared length units)", margin=worst, field="sq")
        return np.maximum(h2, 0.0)
    if method == "precise":
        import mpmath
        t = mpmath.mpf(10) ** (8 - dps) if tol is None else tol
        limit = t * scale if tol is not None else max(t * scale, e_h2)
        _warn_doubtful(-limit <= h2 < -t * scale, h2, e_h2, "precise")
        if h2 < -limit:
            raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                                  f"{mpmath.nstr(h2, 8)} (squared length units)",
                                  margin=float(h2), field="sq")
        return max(h2, mpmath.mpf(0))
    if type(h2).__name__ == "fmpq":
        if h2 < 0:
            # a decimal (the exact fraction may run to hundreds of digits), and a margin
            # from mpmath: float(p) / float(q) overflowed beyond 1e308 (QA J 6)
            import mpmath
            with mpmath.workdps(30):
                v = mpmath.mpf(int(h2.p)) / int(h2.q)
                shown, margin = mpmath.nstr(v, 8), float(v)
            raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                                  f"{shown} (squared length units, exact rational)",
                                  margin=margin, field="sq")
        return h2
    if h2 < 0:
        raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                              f"{h2.str(8, radius=True)} (squared length units)",
                              margin=float(h2.mid()), field="sq")
    if not h2 > 0:
        raise UncertifiedError(f"cannot decide whether the distances close: h^2 = "
                               f"{h2.str(8, radius=True)} contains 0")
    return h2


def trilaterate(points, sq, side=1, *, method: str = "fast", dps: int | None = None,
                tol: float | None = None):
    """The point at squared distances ``sq`` from the three rows of ``points``.

    Parameters
    ----------
    points : array_like (..., 3, 3)
        Reference points :math:`P_a, P_b, P_c` (rows).
    sq : array_like (..., 3)
        Squared distances to them.
    side : +1 or -1 (or an array of them, batched)
        Which side of the oriented plane :math:`(P_b-P_a)\\times(P_c-P_a)`.
    method, dps, tol
        See :func:`trilateration_parts`.

    Returns
    -------
    numpy.ndarray (..., 3) for ``fast``; a list of 3 ``mpf`` for ``precise``; a list of
    3 ``flint.arb`` balls for ``certified`` (3 exact ``fmpq`` when the data are rational
    and the point lies in the plane of the reference points).

    Raises
    ------
    InputError
        As :func:`trilateration_parts`, and a negative squared distance or a ``side``
        other than +1 / -1 (one value in the precise and certified tiers).
    DegenerateGeometryError, InfeasibleError, UncertifiedError
        See :func:`trilateration_parts`.

    Warns
    -----
    ConditioningWarning
        Fast tier, once per call: an error estimate above
        :data:`~.trilat_error.TRILATERATION_RTOL` of the problem's length scale
        (:func:`trilateration_parts`); without it the point is within that of the exact
        answer of the float64 inputs, by the estimate.  Precise tier: likewise at
        :func:`~.trilat_error.precise_rtol` of ``dps``.

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> trilaterate(P, [1, 2, 2]).round(12).tolist()
    [0.0, 0.0, 1.0]
    """
    parts, side = _solve(points, sq, side, method, dps, tol, nonnegative=True)
    if method == "precise":
        import mpmath
        with mpmath.workdps(default_dps(dps)):
            return parts.point(side)
    return parts.point(side)


def trilaterate_both(points, sq, *, method: str = "fast", dps: int | None = None,
                     tol: float | None = None):
    """Both mirror solutions ``(side=+1, side=-1)``; see :func:`trilaterate` (the same
    checks, error estimate and warning: one per call for both)."""
    parts = _solve(points, sq, _NO_SIDE, method, dps, tol, nonnegative=True)[0]
    if method == "precise":
        import mpmath
        with mpmath.workdps(default_dps(dps)):
            return parts.point(1), parts.point(-1)
    return parts.point(1), parts.point(-1)
