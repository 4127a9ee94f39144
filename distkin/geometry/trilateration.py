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
"""

from __future__ import annotations

import numpy as np

from ..errors import DegenerateGeometryError, InfeasibleError, InputError, UncertifiedError
from ..exact import check_method, default_dps, to_tier

__all__ = ["trilaterate", "trilaterate_both", "TrilaterationParts", "trilateration_parts"]

_EPS = np.finfo(float).eps


class TrilaterationParts:
    """Foot of the perpendicular, the normal n, G = |n|^2 and h^2, in one tier.

    Attributes are sequences of three components (numpy arrays when batched).
    """

    __slots__ = ("foot", "normal", "G", "h2", "method")

    def __init__(self, foot, normal, G, h2, method):
        self.foot, self.normal, self.G, self.h2, self.method = foot, normal, G, h2, method

    def point(self, side):
        """The point on ``side`` (+1 or -1, or an array of them when batched)."""
        if self.method == "fast":
            scale = np.sqrt(np.maximum(self.h2, 0.0) / self.G) * side
            return np.stack([f + scale * c for f, c in zip(self.foot, self.normal)], axis=-1)
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


def _components(points, method):
    """Split (…, 3, 3) points into 9 scalars (or arrays) of the tier."""
    if method == "fast":
        P = np.asarray(points, dtype=float)
        if P.shape[-2:] != (3, 3):
            raise InputError(f"expected reference points of shape (..., 3, 3), got {P.shape}",
                             field="points")
        if not np.all(np.isfinite(P)):
            raise InputError("expected finite reference points, got NaN or inf", field="points")
        return [[P[..., r, c] for c in range(3)] for r in range(3)]
    rows = list(points)
    if len(rows) != 3 or any(len(r) != 3 for r in rows):
        raise InputError(f"expected 3 reference points of 3 coordinates, got {np.shape(points)}",
                         field="points")
    return [[to_tier(x, method) for x in r] for r in rows]


def trilateration_parts(points, sq, *, method: str = "fast", dps: int | None = None,
                        tol: float | None = None) -> TrilaterationParts:
    """Compute the pieces of a trilateration and check degeneracy and feasibility.

    Parameters
    ----------
    points : array_like (..., 3, 3)
        Rows :math:`P_a, P_b, P_c`, in any length unit.
    sq : array_like (..., 3)
        Squared distances :math:`s_a, s_b, s_c` from the sought point, same unit squared.
    method : {"fast", "precise", "certified"}
    tol : float, optional
        Relative tolerance of the fast and precise tiers (default: 64 eps for
        ``fast``, 10^(8 - dps) for ``precise``).  The certified tier is exact on
        rational data and decides with balls otherwise.

    Raises
    ------
    DegenerateGeometryError
        Collinear or coincident reference points.
    InfeasibleError
        :math:`h^2 < 0` beyond the tolerance; ``margin`` is :math:`h^2`.
    UncertifiedError
        Certified tier on irrational data whose balls cannot decide the sign.
    """
    check_method(method)
    if method == "precise":
        import mpmath
        dps = default_dps(dps)
        ctx = mpmath.workdps(dps)
        ctx.__enter__()
    try:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = _components(points, method)
        if method == "fast":
            S = np.asarray(sq, dtype=float)
            if S.shape[-1:] != (3,):
                raise InputError(f"expected 3 squared distances per point, got shape {S.shape}",
                                 field="sq")
            if not np.all(np.isfinite(S)):
                raise InputError("expected finite squared distances, got NaN or inf", field="sq")
            sa, sb, sc = S[..., 0], S[..., 1], S[..., 2]
        else:
            if len(sq) != 3:
                raise InputError(f"expected 3 squared distances, got {len(sq)}", field="sq")
            sa, sb, sc = (to_tier(x, method) for x in sq)
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
        foot = (ax + alpha * v2[0] + beta * v3[0],
                ay + alpha * v2[1] + beta * v3[1],
                az + alpha * v2[2] + beta * v3[2])
        h2 = sa - (alpha * w2 + beta * w3)
        scale = _scale(sa, g22, g33, method)
        h2 = _check_feasible(h2, scale, method, dps, tol)
        return TrilaterationParts(foot, n, G, h2, method)
    finally:
        if method == "precise":
            ctx.__exit__(None, None, None)


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
                f"points (|n|^2 = {np.min(G):.3g} <= {t:.1e}*|v2|^2*|v3|^2)",
                field="points")
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


def _check_feasible(h2, scale, method, dps, tol):
    if method == "fast":
        t = 64 * _EPS if tol is None else tol
        bad = h2 < -t * scale
        if np.any(bad):
            worst = float(np.min(h2))
            raise InfeasibleError(
                f"expected distances that close (h^2 >= 0), got h^2 = {worst:.6g} "
                "(squared length units)", margin=worst, field="sq")
        return np.maximum(h2, 0.0)
    if method == "precise":
        import mpmath
        t = mpmath.mpf(10) ** (8 - dps) if tol is None else tol
        if h2 < -t * scale:
            raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                                  f"{mpmath.nstr(h2, 8)}", margin=float(h2), field="sq")
        return max(h2, mpmath.mpf(0))
    if type(h2).__name__ == "fmpq":
        if h2 < 0:
            raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = {h2} "
                                  "exactly", margin=float(h2.p) / float(h2.q), field="sq")
        return h2
    if h2 < 0:
        raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                              f"{h2.str(8, radius=True)}", margin=float(h2.mid()), field="sq")
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

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> trilaterate(P, [1, 2, 2]).round(12).tolist()
    [0.0, 0.0, 1.0]
    """
    if np.any(np.abs(np.asarray(side, dtype=float)) != 1):
        raise InputError(f"expected side = +1 or -1, got {side!r}", field="side")
    parts = trilateration_parts(points, sq, method=method, dps=dps, tol=tol)
    if method == "precise":
        import mpmath
        with mpmath.workdps(default_dps(dps)):
            return parts.point(side)
    return parts.point(side)


def trilaterate_both(points, sq, *, method: str = "fast", dps: int | None = None,
                     tol: float | None = None):
    """Both mirror solutions ``(side=+1, side=-1)``; see :func:`trilaterate`."""
    parts = trilateration_parts(points, sq, method=method, dps=dps, tol=tol)
    if method == "precise":
        import mpmath
        with mpmath.workdps(default_dps(dps)):
            return parts.point(1), parts.point(-1)
    return parts.point(1), parts.point(-1)
