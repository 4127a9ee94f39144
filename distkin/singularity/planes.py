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


def _vol(pts, i, j, k, l):
    a = pts[..., i - 1, :]
    return np.sum((pts[..., j - 1, :] - a) * _cross(pts[..., k - 1, :] - a, pts[..., l - 1, :] - a),
                  axis=-1) / 6


def volume_factors(points, *, method: str | None = None, dps: int | None = None):
    r"""Signed-volume products :math:`a = V_{1245}V_{3456}V_{1236}` and
    :math:`b = V_{1234}V_{2456}V_{1356}` (length units^9).

    :math:`\det\hat{\mathbf J} = -216(a+b)`; the ratio of the paper's condition to
    :math:`\det\hat{\mathbf J}` is :math:`-110592(a-b)`, that of the signed one
    :math:`-110592\,a`.  ``points`` (..., 6, 3): P1..P6; another shape is an
    :class:`~distkin.errors.InputError`.  ``dps``: digits of the precise tier (5..1233,
    default 30, set locally), only with ``method="precise"``.  Fast: coordinates
    scaled by a power of two (module docstring); a product beyond float64 reads 0.0
    or inf with a :class:`~distkin.errors.FloatRangeWarning` (QA 23: a silent
    ``(-0.0, 0.0)`` at 1e-100, inf at 1e50, NaN at 1e150).
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
        a = _vol(pts, 1, 2, 4, 5) * _vol(pts, 3, 4, 5, 6) * _vol(pts, 1, 2, 3, 6)
        b = _vol(pts, 1, 2, 3, 4) * _vol(pts, 2, 4, 5, 6) * _vol(pts, 1, 3, 5, 6)
    if scale is None:
        return a, b
    from .float_range import scale_back
    ab = scale_back(np.stack([a, b]), scale, 9, "volume factors (a, b)",
                    "their ratio a / b (scale-free)")
    return (ab[0], ab[1]) if np.ndim(a) else (float(ab[0]), float(ab[1]))


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
    """

    det: object
    relative: object
    point: object
    spread: object


def four_planes(points, *, length_scale: float | None = None, method: str | None = None,
                dps: int | None = None) -> FourPlanes:
    r"""Do the planes :math:`P_1P_2P_4`, :math:`P_2P_3P_5`, :math:`P_3P_1P_6`,
    :math:`P_4P_5P_6` meet in a point? (Rojas et al., Sec. IV, ref. [19]).

    Four planes :math:`n_i\cdot x = c_i` have a common (possibly ideal) point iff
    :math:`\det[n_i, -c_i] = 0`.  ``point`` and ``spread`` are computed in float64
    whatever the tier, from plane rows scaled by powers of two (exact: the relative
    value does not depend on the length unit; module docstring).

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
        if kind == "fast":
            from .float_range import scaled_points
            pts, scale = scaled_points(pts)
            M = _rows(pts)
            _check_normals(M[..., :3] != 0)
            F = np.linalg.det(M)
            if scale is not None:
                from .float_range import scale_back
                F = scale_back(F, scale, 9, "four-planes det F", "its relative value")
            rows, pf = _row_scaled(M), pts
        else:
            M = _rows(pts)
            _check_normals(_nonzero(M[..., :3], kind))
            F = _det(M, kind)
            rows, pf, scale = _float_rows(M, pts)
    L = length_scale
    if L is not None and scale is not None:
        L = np.ldexp(L, -np.asarray(scale))
    rel, x, spread = _geometry(rows, pf, L)
    if scale is not None:
        from ..geometry.pow2_scale import scale_back
        advice = "the relative value, or another length unit"
        x = scale_back(x, np.asarray(scale)[..., None], "four-planes common point", advice)[0]
        spread = scale_back(spread, scale, "four-planes spread", advice)[0]
    if np.ndim(rel) == 0:
        rel, spread = float(rel), float(spread)
    return FourPlanes(F, rel, x, spread)


def _rows(pts):
    """The rows :math:`(n_i, -n_i\\cdot P_i)` of :math:`F` (..., 4, 4), in the points'
    number type."""
    rows = []
    for i, j, k in PLANES:
        a = pts[..., i - 1, :]
        n = _cross(pts[..., j - 1, :] - a, pts[..., k - 1, :] - a)
        c = np.asarray(np.sum(n * a, axis=-1), dtype=n.dtype)
        rows.append(np.concatenate([n, -c[..., None]], axis=-1))
    return np.stack(rows, axis=-2)


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
