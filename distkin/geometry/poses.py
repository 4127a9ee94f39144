r"""Rigid poses from three points, and three points from a pose.

A pose maps platform-frame coordinates :math:`q` to base coordinates
:math:`p = R\,q + t` with :math:`R \in SO(3)`.  Three non-collinear points fix it: with
the orthonormal frame of a triangle

.. math:: e_1 = \frac{a_2 - a_1}{\|a_2 - a_1\|},\quad
          e_3 = \frac{(a_2 - a_1)\times(a_3 - a_1)}{\|\cdot\|},\quad e_2 = e_3 \times e_1,

built once from the platform-frame points (:math:`F_q`) and once from the base-frame
points (:math:`F_p`), :math:`R = F_p F_q^{\mathsf T}` and :math:`t = \bar p - R\bar q`
(centroids).  Both frames are right-handed, so :math:`\det R = +1` even for the mirror
image of a planar triangle (a planar triangle and its mirror image are congruent by a
proper motion).  Used for the octahedral platform triangle :math:`P_4P_5P_6` (Rojas et
al., ICRA 2012, Fig. 4 and Sec. III).

Every function runs in the three tiers: numpy ``float64`` arrays (batched over leading
axes), ``mpmath.mpf`` and ``flint.arb`` (nested lists of scalars).
"""

from __future__ import annotations

import numpy as np

from ..errors import DegenerateGeometryError, InputError, UncertifiedError
from ..exact import check_method

__all__ = ["triangle_frame", "pose_from_points", "points_from_pose"]


def _sqrt(x, method):
    if method == "fast":
        return np.sqrt(x)
    if method == "precise":
        import mpmath
        return mpmath.sqrt(x)
    import flint
    return flint.arb(x).sqrt()


def _sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _tier_rows(points, method, what):
    """Three points as 3x3 nested lists in the number type of the precise (mpf) or
    certified (fmpq, or arb when irrational) tier, converted exactly first: a float is
    its binary value, a numeric string is parsed exactly (as :func:`.trilaterate`), so
    the certified frame encloses the exact frame of the inputs (QA J 2, 8)."""
    from .trilateration import _three_rows, _tier_scalar
    rows = _three_rows(points, "points", what)
    native = _NATIVE[method]
    return [[x if type(x).__name__ in native else _tier_scalar(x, method, f"{what}[{i}][{j}]")
             for j, x in enumerate(r)] for i, r in enumerate(rows)]


#: number types a tier takes as they are (the solvers' own values: no conversion cost)
_NATIVE = {"precise": ("mpf",), "certified": ("arb", "fmpq")}


def _check_nonzero(n2, scale, method, what):
    if method == "fast":
        if np.any(n2 <= 1e-24 * scale):
            raise DegenerateGeometryError(f"expected a proper triangle of {what}, got "
                                          "collinear or coincident points", field=what)
    elif method == "precise":
        if n2 == 0:
            raise DegenerateGeometryError(f"expected a proper triangle of {what}, got "
                                          "collinear or coincident points", field=what)
    else:
        import flint
        v = flint.arb(n2)
        if v.is_zero():
            raise DegenerateGeometryError(f"expected a proper triangle of {what}, got "
                                          "collinear points (exactly)", field=what)
        if not v > 0:
            raise UncertifiedError(f"cannot decide whether the points of {what} are collinear")


def triangle_frame(points, *, method: str = "fast", what: str = "points"):
    """Orthonormal right-handed frame of a triangle.

    Parameters
    ----------
    points : array_like (..., 3, 3) or 3 rows of 3 scalars
        Rows :math:`a_1, a_2, a_3` in any length unit.

    Returns
    -------
    F : (..., 3, 3) array (columns e1 e2 e3) for ``fast``; else a 3x3 nested list
        ``F[row][col]``.

    Raises
    ------
    DegenerateGeometryError
        Collinear or coincident points.
    """
    check_method(method)
    if method == "fast":
        P = np.asarray(points, dtype=float)
        if P.shape[-2:] != (3, 3):
            raise InputError(f"expected points of shape (..., 3, 3), got {P.shape}", field=what)
        d1 = P[..., 1, :] - P[..., 0, :]
        d2 = P[..., 2, :] - P[..., 0, :]
        # in units of 2^e, the power of two just above the largest coordinate difference
        # (exact): the frame is scale-free, and a triangle of size 1e-100 or 1e150 must
        # not look flat through an underflow or an overflow of |n|^2
        big = np.maximum(np.max(np.abs(d1), axis=-1), np.max(np.abs(d2), axis=-1))
        if not np.all(np.isfinite(big)):
            raise InputError("expected finite points (and differences within the float64 "
                             "range), got NaN or inf", field=what)
        e = np.frexp(np.where(big > 0, big, 1.0))[1][..., None]
        d1, d2 = np.ldexp(d1, -e), np.ldexp(d2, -e)
        n = np.cross(d1, d2)
        n2 = np.einsum("...k,...k->...", n, n)
        l1 = np.einsum("...k,...k->...", d1, d1)
        l2 = np.einsum("...k,...k->...", d2, d2)
        _check_nonzero(n2, l1 * l2, method, what)
        e1 = d1 / np.sqrt(l1)[..., None]
        e3 = n / np.sqrt(n2)[..., None]
        e2 = np.cross(e3, e1)
        return np.stack([e1, e2, e3], axis=-1)
    return _frame(_tier_rows(points, method, what), method, what)


def _frame(rows, method, what):
    """:func:`triangle_frame` of rows already in the tier's number type (precise,
    certified)."""
    d1, d2 = _sub(rows[1], rows[0]), _sub(rows[2], rows[0])
    n = _cross(d1, d2)
    n2, l1 = _dot(n, n), _dot(d1, d1)
    _check_nonzero(n2, None, method, what)
    s1, sn = _sqrt(l1, method), _sqrt(n2, method)
    e1 = [c / s1 for c in d1]
    e3 = [c / sn for c in n]
    e2 = _cross(e3, e1)
    return [[e1[r], e2[r], e3[r]] for r in range(3)]


def pose_from_points(local, world, *, method: str = "fast"):
    r"""The pose :math:`(R, t)` carrying three platform-frame points onto base-frame points.

    Parameters
    ----------
    local : array_like (3, 3) (or (..., 3, 3), fast)
        Rows :math:`q_4, q_5, q_6` in the platform frame.
    world : array_like (..., 3, 3)
        Rows :math:`p_4, p_5, p_6` in the base frame (a congruent triangle).
    method : {"fast", "precise", "certified"}

    Returns
    -------
    R : (..., 3, 3), proper rotation with :math:`p_i = R q_i + t`
    t : (..., 3)
        Nested lists of ``mpf`` / ``arb`` for the precise / certified tiers.  Exact when
        the triangles are exactly congruent; otherwise the frame fit above (it does not
        spread the error like a least-squares fit would).

    Examples
    --------
    >>> import numpy as np
    >>> q = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0]])
    >>> R, t = pose_from_points(q, q + [1., 2, 3])
    >>> np.allclose(R, np.eye(3)), t.round(12).tolist()
    (True, [1.0, 2.0, 3.0])
    """
    check_method(method)
    if method == "fast":
        q = np.asarray(local, dtype=float)
        p = np.asarray(world, dtype=float)
        Fq = triangle_frame(q, method=method, what="platform")
        Fp = triangle_frame(p, method=method, what="points")
        R = Fp @ np.swapaxes(Fq, -1, -2)
        t = p.mean(axis=-2) - np.einsum("...ij,...j->...i", R, q.mean(axis=-2))
        return R, t
    local = _tier_rows(local, method, "platform")
    world = _tier_rows(world, method, "points")
    Fq = _frame(local, method, "platform")
    Fp = _frame(world, method, "points")
    R = [[sum(Fp[i][k] * Fq[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    qc = [sum(local[r][c] for r in range(3)) / 3 for c in range(3)]
    pc = [sum(world[r][c] for r in range(3)) / 3 for c in range(3)]
    t = [pc[i] - sum(R[i][k] * qc[k] for k in range(3)) for i in range(3)]
    return R, t


def points_from_pose(R, t, local, *, method: str = "fast"):
    r"""Base-frame points :math:`p_i = R q_i + t` of platform-frame points.

    Parameters
    ----------
    R : (..., 3, 3)
    t : (..., 3)
    local : (k, 3) platform-frame points (rows)

    Returns
    -------
    (..., k, 3) array for ``fast``; nested lists otherwise.
    """
    check_method(method)
    if method == "fast":
        R = np.asarray(R, dtype=float)
        t = np.asarray(t, dtype=float)
        q = np.asarray(local, dtype=float)
        return np.einsum("...ij,kj->...ki", R, q) + t[..., None, :]
    return [[sum(R[i][k] * row[k] for k in range(3)) + t[i] for i in range(3)] for row in local]
