r"""The four-planes test and the signed-volume factors of the octahedral singularity
(Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. IV).

Both are homogeneous in the coordinates: :math:`F` and the volume products
:math:`a, b` of degree 9, the relative :math:`F`, the common point's direction and the
ratios scale-free.  The fast tier computes them from coordinates multiplied by a power
of two (exact; :func:`.float_range.scaled_points`) where the coordinate differences
leave :math:`2^{\pm 32}`, and scales the values back (a value beyond float64 reads 0.0
or inf with a :class:`~distkin.errors.FloatRangeWarning`); the other tiers compute
:math:`F` in their own numbers and the float64 parts (``relative``, ``point``,
``spread``) from their exact plane rows scaled alike, so no tier reads "singular" (0.0)
or "collinear" from an over- or underflow (QA 23: every tier at 1e80 and 1e-100).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..argcheck import positive_number
from ..errors import DegenerateGeometryError, InputError, UncertifiedError
from .tiers import _at, _cross, _det, _float_or_str, _precision, _prepare

__all__ = ["volume_factors", "four_planes", "FourPlanes", "PLANES"]

#: the four planes of the geometric test (Downing, Samuel, Hunt 2002; paper Sec. IV)
PLANES = ((1, 2, 4), (2, 3, 5), (3, 1, 6), (4, 5, 6))
#: :data:`PLANES` as 0-based indices (4, 3)
_PLANE_IDX = np.array(PLANES) - 1


#: the six tetrahedra of :func:`volume_factors`: a's three, then b's
_QUADS = np.array(((1, 2, 4, 5), (3, 4, 5, 6), (1, 2, 3, 6),
                   (1, 2, 3, 4), (2, 4, 5, 6), (1, 3, 5, 6))) - 1


def _edges(pts):
    """The edges (..., 6, 3, 3) from the first vertex of each tetrahedron of
    :data:`_QUADS` (its rows :math:`P_j - P_i, P_k - P_i, P_l - P_i`)."""
    return pts[..., _QUADS[:, 1:], :] - pts[..., _QUADS[:, :1], :]


def _volumes(d):
    r"""Signed volumes (..., 6) :math:`(P_j-P_i)\cdot((P_k-P_i)\times(P_l-P_i))/6` from
    :func:`_edges` (any number type)."""
    return np.sum(d[..., 0, :] * _cross(d[..., 1, :], d[..., 2, :]), axis=-1) / 6


def volume_factors(points, *, method: str | None = None, dps: int | None = None,
                   with_error: bool = False, warn: bool = True):
    r"""Signed-volume products :math:`a = V_{1245}V_{3456}V_{1236}` and
    :math:`b = V_{1234}V_{2456}V_{1356}` (length units^9).

    :math:`\det\hat{\mathbf J} = -216(a+b)`; the ratio of the paper's condition to
    :math:`\det\hat{\mathbf J}` is :math:`-110592(a-b)`, that of the signed one
    :math:`-110592\,a`.  ``points`` (..., 6, 3): P1..P6; another shape is an
    :class:`~distkin.errors.InputError`.  ``dps``: digits of the precise tier (5..1233,
    default 30, set locally), only with ``method="precise"``.  Fast: coordinates
    scaled by a power of two (module docstring); a product beyond float64 reads 0.0
    or inf with a :class:`~distkin.errors.FloatRangeWarning` (QA 23: a silent
    ``(-0.0, 0.0)`` at 1e-100, inf at 1e50, NaN at 1e150).  Fast: where a product's
    rounding-error estimate (:func:`_volume_error`) reaches its value, float64 does not
    resolve its sign; a :class:`~distkin.errors.CancellationWarning` says so where it
    exceeds 1e-6 of the value, as the Cayley-Menger conditions' do (a
    nearly flat tetrahedron read an exact-looking 0.0 or the wrong sign, QA 24;
    ``warn=False``: no warning); ``with_error=True`` returns ``(a, b, err_a, err_b)``
    (the fast estimates; 0.0 in the other tiers, whose digits are their own).
    """
    with _precision(dps, method, points):
        pts, kind = _prepare(points, method)
        if pts.shape[-2:] != (6, 3):
            raise InputError(f"expected points P1..P6 of shape (..., 6, 3), got {pts.shape}",
                             field="points")
        scale = None
        if kind == "fast":
            from .float_range import scaled_points
            pts, scale = scaled_points(pts)
        d = _edges(pts)
        V = _volumes(d)
        a = V[..., 0] * V[..., 1] * V[..., 2]
        b = V[..., 3] * V[..., 4] * V[..., 5]
        if np.ndim(a) == 0 and kind != "fast":
            a, b = a.item() if hasattr(a, "item") else a, b.item() if hasattr(b, "item") else b
    if kind != "fast":
        return (a, b, 0.0, 0.0) if with_error else (a, b)
    ea, eb = _volume_error(V, d)
    flag = (ea > 1e-6 * np.abs(a)) | (eb > 1e-6 * np.abs(b))
    if warn and np.any(flag):
        from ..errors import CancellationWarning
        from ..errors import warn as _warn
        i = int(np.flatnonzero(np.ravel(flag))[0])
        where = (f" at {int(np.sum(flag))} of {np.size(flag)} point set(s) (first: batch "
                 f"index {tuple(int(j) for j in np.unravel_index(i, np.shape(flag)))})"
                 if np.ndim(flag) else "")
        _warn(f"fast volume factors{where}: a = {float(np.ravel(a)[i]):.6g} (estimate "
              f"{float(np.ravel(ea)[i]):.3g}), b = {float(np.ravel(b)[i]):.6g} (estimate "
              f"{float(np.ravel(eb)[i]):.3g}): a rounding-error estimate above 1e-6 of its "
              "product (as the Cayley-Menger conditions'), or above it (the sign not "
              "resolved): a nearly flat tetrahedron; use method='precise' or 'certified'",
              CancellationWarning)
    from .float_range import scale_back, scale_error
    ab = scale_back(np.stack([a, b]), scale, 9, "volume factors (a, b)",
                    "their ratio a / b (scale-free)")
    out = (ab[0], ab[1]) if np.ndim(a) else (float(ab[0]), float(ab[1]))
    if not with_error:
        return out
    ea, eb = scale_error(ea, scale, 9), scale_error(eb, scale, 9)
    return out + ((ea, eb) if np.ndim(a) else (float(ea), float(eb)))


def _volume_error(V, d):
    r"""Rounding-error estimates of the fast products :math:`a` and :math:`b` of the
    signed volumes ``V`` (..., 6) with edges ``d`` (:func:`_edges`): each volume within
    :math:`e_V = 2\cdot 10\,\varepsilon\,\|d_1\|\|d_2\|\|d_3\|/6` of its float (the
    edges rounded once each, the cross product and the dot product: about
    :math:`10\varepsilon` times the product of the edge lengths, times 2), and each
    product within :math:`\prod(|V| + e_V) - \prod|V|` (every order, not only the
    first).  An estimate, not a proof."""
    e = (20 * _U / 6) * np.sqrt(np.prod(np.sum(d * d, axis=-1), axis=-1))
    v = np.abs(V)
    hi = v + e
    out = []
    for q in (slice(0, 3), slice(3, 6)):
        h = np.prod(hi[..., q], axis=-1)
        out.append(h - np.prod(v[..., q], axis=-1) + 4 * _U * h)
    return out[0], out[1]


@dataclass(frozen=True)
class FourPlanes:
    """Result of :func:`four_planes`.

    Attributes
    ----------
    det : number or array
        :math:`F = \\det[n_i,\\; -n_i\\cdot P_i]_{i=1..4}` with
        :math:`n_i = (P_j-P_i)\\times(P_k-P_i)` (length units^9; equals
        :math:`\\det\\hat{\\mathbf J}`).
    relative : float or array
        :math:`F` with unit normals and offsets divided by ``length_scale``
        (dimensionless).
    point : array (..., 3)
        Least-squares common point of the four planes (length units).
    spread : float or array
        Largest distance from ``point`` to one of the planes (length units); 0 when
        the planes meet in a point.
    det_error : float or array or None
        Fast tier: a rounding-error estimate of ``det`` (length units^9; not a proof);
        None in the other tiers (precise: its digits; certified: ``det`` is exact or a
        ball).
    """

    det: object
    relative: object
    point: object
    spread: object
    det_error: object = None


def four_planes(points, *, length_scale: float | None = None, method: str | None = None,
                dps: int | None = None, warn: bool = True) -> FourPlanes:
    r"""Do the planes :math:`P_1P_2P_4`, :math:`P_2P_3P_5`, :math:`P_3P_1P_6`,
    :math:`P_4P_5P_6` meet in a point? (Rojas et al., Sec. IV, ref. [19]).

    Four planes :math:`n_i\cdot x = c_i` have a common (possibly ideal) point iff
    :math:`\det[n_i, -c_i] = 0`.  ``point`` and ``spread`` are computed in float64
    whatever the tier, from plane rows scaled by powers of two (exact: the relative
    value does not depend on the length unit; module docstring).  ``relative`` =
    :math:`F / (L \prod_i \|n_i\|)` is a float64 number in every tier: in the fast
    tier computed from the unit rows, in the others the float nearest the tier's own
    value (precise: mpmath at ``dps``; certified: the midpoint of an arb ball at 128
    bits or more, of F's sign wherever F's ball excludes 0; it read 0.0 or the wrong
    sign near a singularity when taken from float64 rows, QA 24).  The fast tier gives
    ``det_error``, a rounding-error estimate of ``det`` (``relative`` carries the same
    relative error), and warns (:class:`~distkin.errors.ConditioningWarning`) where it
    exceeds :math:`|F|`: float64 does not resolve F's sign there (``warn=False``: no
    warning, for callers that drive F to 0 on purpose).

    Parameters
    ----------
    points : array (..., 6, 3)
        P1..P6, base frame (length units).
    length_scale : float, optional
        For ``relative``: a finite number > 0 (default: the largest distance of a point
        from P1).
    method : {"fast", "precise", "certified"} or None
        None keeps the input's number type.
    dps : int, optional
        Digits of the precise tier (5..1233, default 30, set locally); only with
        ``method="precise"``.

    Raises
    ------
    InputError
        Booleans, NaN or inf in ``points``, a wrong shape, a bad ``length_scale``.
    DegenerateGeometryError
        Three collinear (or coincident) points of a plane: the plane is undefined (named,
        with the batch index); then its row of F vanishes, F = 0.  The fast and precise
        tiers decide it in their arithmetic (a cross product that is exactly 0), the
        certified tier exactly.
    UncertifiedError
        Certified, with arb balls that cannot tell whether a plane's normal is 0.
    """
    if length_scale is not None:
        length_scale = positive_number(length_scale, "length_scale")
    with _precision(dps, method, points):
        pts, kind = _prepare(points, method)
        if pts.shape[-2:] != (6, 3):
            raise InputError(f"expected points of shape (..., 6, 3), got {pts.shape}",
                             field="points")
        err = exact_rel = None
        if kind == "fast":
            from .float_range import scaled_points
            pts, scale = scaled_points(pts)
            M = _rows(pts)
            _check_normals(M[..., :3] != 0)
            F = np.linalg.det(M)
            err = _det_error(M, pts)
            flag = err >= np.abs(F)
            if scale is not None:
                from .float_range import scale_back, scale_error
                F = scale_back(F, scale, 9, "four-planes det F", "its relative value")
                err = scale_error(err, scale, 9)
            rows, pf = _row_scaled(M), pts
        else:
            M = _rows(pts)
            _check_normals(_nonzero(M[..., :3], kind))
            F = _det(M, kind)
            rows, pf, scale = _float_rows(M, pts)
            exact_rel = _tier_relative(F, M, pts, length_scale, kind)
    L = length_scale
    if L is not None and scale is not None:
        L = np.ldexp(L, -np.asarray(scale))
    rel, x, spread = _geometry(rows, pf, L)
    if exact_rel is not None:
        rel = exact_rel
    if err is not None and warn and np.any(flag):
        from ..errors import ConditioningWarning
        from ..errors import warn as _warn
        from .float_range import unresolved_note
        _warn(unresolved_note(F, err, flag, "four-planes det F").replace(
            "(with_error=True returns the estimate)", "(FourPlanes.det_error is the estimate)"),
            ConditioningWarning)
    if scale is not None:
        from ..geometry.pow2_scale import scale_back
        advice = "the relative value, or another length unit"
        x = scale_back(x, np.asarray(scale)[..., None], "four-planes common point", advice)[0]
        spread = scale_back(spread, scale, "four-planes spread", advice)[0]
    if np.ndim(rel) == 0:
        rel, spread = float(rel), float(spread)
        err = None if err is None else float(err)
    return FourPlanes(F, rel, x, spread, err)


#: unit roundoff of float64
_U = 2.0 ** -53


def _det_error(M, pts):
    r"""Rounding-error estimate of the fast :math:`F = \det M` (rows
    :math:`(n_i, -n_i\cdot P_i)` of float points ``pts`` (..., 6, 3)).  With the offset
    column divided by :math:`S = \max_i\|P_i\|` (rows :math:`r'_i`),

    .. math:: e = 2S \sum_i \|\delta_i\| \prod_{j\ne i}\|r'_j\|,\qquad
              \|\delta_i\| = 16\varepsilon\|r'_i\|
              + \varepsilon\|a_i\|\|b_i\|\,(4 + 7\|P_i\|/S),

    first order (Hadamard's inequality bounds the cofactors), as
    :func:`.float_range.det_error` for det J: the edges :math:`a_i, b_i` of plane
    :math:`i` rounded once each and their cross product (:math:`4\varepsilon
    \|a_i\|\|b_i\|`), the offset :math:`n_i\cdot P_i` (that error times
    :math:`\|P_i\|`, and its own :math:`3\varepsilon\|n_i\|\|P_i\|`), and LU's
    backward error (:math:`4n\varepsilon` per row, n = 4; Higham, *Accuracy and Stability
    of Numerical Algorithms*, 2nd ed., Ch. 9), times 2.  An estimate, not a proof (the
    certified tier gives one); relative to F it grows like 1/|F| near a singularity,
    and with the points' distance from the origin (F does not depend on it, its float64
    rounding does)."""
    pn = np.sqrt(np.sum(pts * pts, axis=-1))                      # |P_i|, (..., 6)
    S = np.max(pn, axis=-1)
    S = np.where(S > 0, S, 1.0)
    Ms = np.array(M, dtype=float)
    Ms[..., 3] = Ms[..., 3] / S[..., None]
    norms = np.sqrt(np.sum(Ms * Ms, axis=-1))                     # (..., 4), each > 0
    d = pts[..., _PLANE_IDX[:, 1:], :] - pts[..., _PLANE_IDX[:, :1], :]   # (..., 4, 2, 3)
    ab = np.sqrt(np.prod(np.sum(d * d, axis=-1), axis=-1))
    pert = 16 * _U * norms + _U * ab * (4 + 7 * pn[..., _PLANE_IDX[:, 0]] / S[..., None])
    # the other rows' norms: their product over this row's (a normal is never 0 here)
    return 2 * S * np.sum(pert * (np.prod(norms, axis=-1)[..., None] / norms), axis=-1)


def _tier_relative(F, M, pts, length_scale, kind) -> float:
    r""":math:`F / (L \prod_i \|n_i\|)` in the tier's numbers (one point set), as the
    float nearest it: mpmath (precise) or an arb ball (certified; the working precision
    is at least 128 bits) whose midpoint has F's sign where F's ball excludes 0 (an
    exact F = 0 gives 0.0).  ``L`` the largest distance from P1 unless given."""
    if kind == "precise":
        import mpmath
        sq = lambda v: mpmath.sqrt(sum(mpmath.mpf(x) ** 2 for x in v))  # noqa: E731
        norm = sq
        one = mpmath.mpf
    else:
        import flint

        from .tiers import _to_flint

        def norm(v):
            return flint.arb(sum((flint.arb(_to_flint(x)) ** 2 for x in v),
                                 flint.arb(0))).sqrt()
        one = flint.arb
    if kind == "certified" and type(F).__name__ == "fmpq" and F == 0:
        return 0.0
    if length_scale is None:
        d = [norm([p[c] - pts[0][c] for c in range(3)]) for p in pts[1:]]
        L = max(d, key=lambda v: float(v.mid()) if kind == "certified" else float(v))
    else:
        L = one(float(length_scale)) if kind == "precise" else flint.arb(float(length_scale))
    den = L
    for row in M:
        den = den * norm(row[:3])
    v = (one(F) if kind == "precise" else flint.arb(F)) / den
    return float(v.mid()) if kind == "certified" else float(v)


def _rows(pts):
    r"""The rows :math:`(n_i, -n_i\cdot P_i)` of :math:`F` (..., 4, 4), in the points'
    number type."""
    a = pts[..., _PLANE_IDX[:, 0], :]
    n = _cross(pts[..., _PLANE_IDX[:, 1], :] - a, pts[..., _PLANE_IDX[:, 2], :] - a)
    c = np.asarray(np.sum(n * a, axis=-1), dtype=n.dtype)
    return np.concatenate([n, -c[..., None]], axis=-1)


def _nonzero(normals, kind):
    """(4, 3) bools: entries of the normals that are not 0 in ``kind``'s arithmetic; an
    arb ball containing 0 (not exactly 0) of a plane with no entry proved non-zero is
    an :class:`UncertifiedError` naming the plane."""
    out = np.zeros(normals.shape, dtype=bool)
    for idx, v in np.ndenumerate(normals):
        if type(v).__name__ == "arb":
            out[idx] = v > 0 or v < 0
        else:
            out[idx] = not (v == 0 or getattr(v, "is_zero", None) is True)
    for r, (i, j, k) in enumerate(PLANES):
        balls = [v for v in normals[r] if type(v).__name__ == "arb" and not v.is_zero()]
        if not out[r].any() and balls:
            raise UncertifiedError(f"expected the normal of plane P{i}P{j}P{k} proved non-zero "
                                   f"or exactly 0, got balls containing 0 "
                                   f"({', '.join(b.str(5, radius=True) for b in balls)})",
                                   field="points", hint="exact (rational) points, or raise "
                                   "flint.ctx.prec")
    return out


def _check_normals(nonzero):
    """:class:`DegenerateGeometryError` naming the planes with a zero normal (three
    collinear or coincident points) and the batch index; ``nonzero`` (..., 4, 3)."""
    ok = nonzero.any(axis=-1)
    if ok.all():
        return
    idx = tuple(int(i) for i in np.argwhere(~ok)[0])
    names = "; ".join(f"P{i}P{j}P{k} (P{i}, P{j}, P{k} collinear)"
                      for (i, j, k), z in zip(PLANES, ~ok[idx[:-1]]) if z)
    raise DegenerateGeometryError(
        f"expected four planes through non-collinear points, got undefined plane(s) "
        f"{names}{_at(idx[:-1])}", field="points",
        hint="det J (jacobian_det) is defined there, and its determinant F = det Jhat = 0")


def _row_scaled(M):
    """Each row of float ``M`` times the power of two that puts its normal's largest
    entry in [0.5, 1) (exact): the normal's squared norm then neither under- nor
    overflows (a nearly collinear plane's was 0, read as collinear)."""
    from ..geometry.pow2_scale import exponent
    f = exponent(np.max(np.abs(M[..., :3]), axis=-1))
    return np.ldexp(M, -f[..., None])


def _float_rows(M, pts):
    """``(rows, points, e)`` of one point set of an mpmath, flint or sympy tier in
    float64: the points times :math:`2^{-e}` (their largest coordinate difference from
    P1 in [0.5, 1)), the rows of ``M`` scaled alike (normals by :math:`2^{-2e}`,
    offsets by :math:`2^{-3e}`) and each by its own power of two (:func:`_row_scaled`),
    through mpmath (any exponent), so values beyond float64 (an exact 1e400) do not
    overflow."""
    import mpmath
    with mpmath.workdps(30):
        mp = np.vectorize(_float_or_str, otypes=[object])
        P, Mm = mp(pts), mp(M)
        e = mpmath.frexp(max(abs(v) for v in (P - P[:1]).ravel()))[1]
        rows = []
        for r in Mm:
            n = [mpmath.ldexp(v, -2 * e) for v in r[:3]]
            f = mpmath.frexp(max(abs(v) for v in n))[1]
            rows.append([float(mpmath.ldexp(v, -f)) for v in n]
                        + [float(mpmath.ldexp(r[3], -3 * e - f))])
        pf = np.array([[float(mpmath.ldexp(v, -e)) for v in p] for p in P])
    return np.array(rows), pf, e


def _geometry(rows, pts, L):
    """``(relative, point, spread)`` in float64 from plane rows (..., 4, 4) whose normals
    are of order 1, and the points (..., 6, 3) in the same length unit."""
    if L is None:
        L = np.max(np.linalg.norm(pts - pts[..., :1, :], axis=-1), axis=-1)
    U = rows / np.linalg.norm(rows[..., :3], axis=-1)[..., None]
    Us = U.copy()
    Us[..., 3] = Us[..., 3] / np.asarray(L)[..., None]
    rel = np.linalg.det(Us)
    N, c = U[..., :3], -U[..., 3]
    x = np.einsum("...ij,...j->...i", np.linalg.pinv(N), c)     # least squares, batched
    spread = np.max(np.abs(np.einsum("...ij,...j->...i", N, x) - c), axis=-1)
    return rel, x, spread
