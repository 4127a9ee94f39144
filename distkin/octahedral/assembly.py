r"""From a root :math:`s_{15}` to the platform points: the trilateration sequence of Sec. III.

Rojas, Borràs and Thomas, *The Octahedral Manipulator Revisited*, ICRA 2012, Sec. III:
"computing :math:`p_5` from :math:`p_1, p_2, p_3`, then :math:`p_4` from
:math:`p_1, p_2, p_5`, and finally :math:`p_6` from :math:`p_4, p_5` [and :math:`p_1`].
This leads to up to eight locations for :math:`P_6`.  Those locations that satisfy the
distance imposed by the leg connecting :math:`P_3` and :math:`P_6` correspond to valid
assembly modes."  The two sides of :math:`P_5` are the two mirror poses (reflection in
the base plane); for each, the four :math:`(P_4, P_6)` choices are ranked by the leg-5
residual :math:`\|P_3P_6\|^2 - s_{36}`.

Trilateration in Gram form, as in :mod:`distkin.geometry.trilateration` (Thomas and
Ros, IEEE T-RO 21(1), 2005).  :func:`assemble_components` (and its row-layout wrapper
:func:`assemble_fast`) is a mask-free numpy version batched over many roots, in the
base-adapted frame of :func:`base_frame` where the first two trilaterations have closed
forms and side -1 is side +1 reflected (it never raises; it returns the squared heights
so the caller can reject); :func:`assemble_exact` runs the sequence in the precise tier
(``mpf``) or the certified tier (``arb`` balls, deciding every sign with certainty;
exact ``fmpq`` on rational data, so that a zero height is exactly zero), both through
:func:`~distkin.geometry.trilateration.trilateration_parts`, side -1 again as the
reflection of side +1 except on exact data.
"""

from __future__ import annotations

import numpy as np

from ..errors import UncertifiedError
from ..geometry.trilateration import trilateration_parts

__all__ = ["trilaterate_masked", "base_frame", "assemble_adapted", "assemble_components",
           "assemble_fast", "assemble_exact"]


def _dot(a, b):
    return np.einsum("...k,...k->...", a, b)


def trilaterate_masked(A, B, C, sa, sb, sc):
    """Batched trilateration without checks.

    Parameters
    ----------
    A, B, C : (..., 3) reference points
    sa, sb, sc : (...) squared distances to them

    Returns
    -------
    foot : (..., 3) foot of the perpendicular on plane ABC
    offset : (..., 3) the height vector for side +1 (point = foot + side * offset)
    h2 : (...) squared height relative to the scale ``|sa| + |AB|^2 + |AC|^2``
        (negative: the distances do not close; the offset is then computed from 0)
    """
    v2, v3 = B - A, C - A
    g22, g33, g23 = _dot(v2, v2), _dot(v3, v3), _dot(v2, v3)
    n = np.cross(v2, v3)
    G = _dot(n, n)
    w2 = (sa + g22 - sb) / 2
    w3 = (sa + g33 - sc) / 2
    alpha = (w2 * g33 - w3 * g23) / G
    beta = (w3 * g22 - w2 * g23) / G
    foot = A + alpha[..., None] * v2 + beta[..., None] * v3
    h2 = sa - (alpha * w2 + beta * w3)
    scale = np.abs(sa) + g22 + g33
    off = np.sqrt(np.maximum(h2, 0.0) / G)[..., None] * n
    return foot, off, h2 / scale


def base_frame(base):
    r"""The base-adapted frame: origin P1, e1 along P1P2, e3 along the oriented normal
    :math:`(P_2-P_1)\times(P_3-P_1)`.

    Parameters
    ----------
    base : (..., 3, 3) rows P1 P2 P3

    Returns
    -------
    axes : (..., 3, 3) rows e1 e2 e3 (a proper rotation, base frame -> adapted frame)
    d : (...) :math:`|P_1P_2|`; p3x, p3y : (...) P3 in the adapted frame (p3y > 0 for a
        proper triangle); s12, s13 : (...) squared sides from the coordinates
    """
    v2 = base[..., 1, :] - base[..., 0, :]
    v3 = base[..., 2, :] - base[..., 0, :]
    s12 = _dot(v2, v2)
    s13 = _dot(v3, v3)
    d = np.sqrt(s12)
    e1 = v2 / d[..., None]
    p3x = _dot(v3, e1)
    w = v3 - p3x[..., None] * e1
    p3y = np.sqrt(_dot(w, w))
    e2 = w / p3y[..., None]
    e3 = np.cross(e1, e2)
    return np.stack([e1, e2, e3], axis=-2), d, p3x, p3y, s12, s13


def assemble_adapted(x, sides, legs, frame):
    r"""The trilateration sequence of Sec. III for many roots, in the base-adapted frame.

    In the frame of :func:`base_frame` (P1 at the origin, P2 on the first axis, P3 in
    the plane z = 0) the trilaterations from P1 P2 reduce to closed forms: P5 =
    (X5, Y5, Z5 >= 0) with X5, Y5 linear in :math:`s_{15}`; P4 on the circle
    |P1P4| = l1, |P2P4| = l2, placed by |P4P5| = |P4P5|_platform (two choices
    :math:`	au`); P6 by the Gram-form trilateration from P1 P4 P5 (Thomas and Ros 2005,
    two choices :math:`ho`).  Of the four (P4, P6) candidates the one with the smallest
    leg-5 residual is kept.  This is side +1; side -1 is its reflection z -> -z (the
    sequence commutes with the reflection in the base plane, which fixes P1 P2 P3).
    Mask-free (it never raises): infeasible heights are clipped at 0 and reported.

    Parameters
    ----------
    x : (M,) roots :math:`s_{15}`
    sides : (6, M) squared sides s12 s13 s23 s45 s46 s56 (rows)
    legs : (6, M) squared legs s14 s24 s25 s35 s36 s16 (rows)
    frame : :func:`base_frame` output, gathered per root: only d, p3x, p3y, s12, s13
        (each (M,)) are used

    Returns
    -------
    pts : tuple of 9 (M,) arrays X4 Y4 Z4 X5 Y5 Z5 X6 Y6 Z6 (side +1, adapted frame)
    h2min : (M,) the smallest relative squared height met (negative: infeasible)
    r36 : (M,) relative leg-5 residual :math:`(|P_3P_6|^2 - s_{36})/(s_{36}+s_{35})` of
        the chosen (P4, P6)
    """
    _, d, p3x, p3y, s12, s13 = frame
    s45, s46, s56 = sides[3], sides[4], sides[5]
    s14, s24, s25, s35, s36, s16 = legs
    with np.errstate(divide="ignore", invalid="ignore"):
        # P5 from P1 P2 P3
        X5 = (x - s25 + s12) / (2 * d)
        Y5 = (x - s35 + s13 - 2 * p3x * X5) / (2 * p3y)
        X5s = X5 * X5
        h5 = x - X5s - Y5 * Y5
        Z5 = np.sqrt(np.maximum(h5, 0.0))
        rel5 = h5 / (np.abs(x) + s12 + s13)
        # P4 from P1 P2 P5: (Y4, Z4) . (Y5, Z5) = K4 on the circle of radius^2 r4
        X4 = (s14 - s24 + s12) / (2 * d)
        rho2 = Y5 * Y5 + Z5 * Z5
        g33 = X5s + rho2                                      # |P5|^2
        K4 = 0.5 * (s14 + g33 - s45) - X4 * X5
        a4 = K4 / rho2
        h4 = (s14 - X4 * X4) - K4 * a4
        rel4 = h4 / (s14 + s12 + g33)
        b4 = np.sqrt(np.maximum(h4, 0.0) / rho2)
        aY, aZ, bY, bZ = a4 * Y5, a4 * Z5, b4 * Y5, b4 * Z5
        w3 = 0.5 * (s16 + g33 - s56)
        s36n = 1.0 / (s36 + s35)
        X4s = X4 * X4
        best = None
        # tau = +1, -1 (the Gram normal P1P2 x P1P5 is along (0, -Z5, Y5))
        for Y4, Z4 in ((aY - bZ, aZ + bY), (aY + bZ, aZ - bY)):
            # P6 from P1 P4 P5 (Gram form, P1 at the origin)
            g22 = X4s + Y4 * Y4 + Z4 * Z4
            g23 = X4 * X5 + Y4 * Y5 + Z4 * Z5
            nx = Y4 * Z5 - Z4 * Y5
            ny = Z4 * X5 - X4 * Z5
            nz = X4 * Y5 - Y4 * X5
            G = nx * nx + ny * ny + nz * nz
            w2 = 0.5 * (s16 + g22 - s46)
            al = (w2 * g33 - w3 * g23) / G
            be = (w3 * g22 - w2 * g23) / G
            h6 = s16 - (al * w2 + be * w3)
            rel6 = h6 / (s16 + g22 + g33)
            k6 = np.sqrt(np.maximum(h6, 0.0) / G)
            fx, fy, fz = al * X4 + be * X5, al * Y4 + be * Y5, al * Z4 + be * Z5
            ox, oy, oz = k6 * nx, k6 * ny, k6 * nz
            # leg-5 residuals of rho = +1, -1: |F +- O - P3|^2 - s36, F - P3 = (ex, ey, fz)
            ex, ey = fx - p3x, fy - p3y
            base_ = ex * ex + ey * ey + fz * fz + ox * ox + oy * oy + oz * oz - s36
            cross = 2 * (ex * ox + ey * oy + fz * oz)
            rp = np.abs((base_ + cross) * s36n)
            rm = np.abs((base_ - cross) * s36n)
            rp = np.where(rp == rp, rp, np.inf)
            rm = np.where(rm == rm, rm, np.inf)
            minus = rm < rp
            r = np.where(minus, rm, rp)
            sg = np.where(minus, -1.0, 1.0)
            cand = (Y4, Z4, fx + sg * ox, fy + sg * oy, fz + sg * oz, rel6, r)
            if best is None:
                best = cand
            else:
                take = r < best[6]
                best = tuple(np.where(take, n_, o_) for n_, o_ in zip(cand, best))
    Y4, Z4, X6, Y6, Z6, rel6, r = best
    h2min = np.minimum(np.minimum(rel5, rel4), rel6)
    h2min = np.where(h2min == h2min, h2min, -np.inf)
    X4 = np.broadcast_to(X4, x.shape)
    return (X4, Y4, Z4, X5, Y5, Z5, X6, Y6, Z6), h2min, r


def assemble_components(base, x, sides, legs, frame=None):
    r"""The trilateration sequence of Sec. III for many roots, in component layout, in
    the base frame: :func:`assemble_adapted`, then both mirror placements mapped back
    by the base-adapted frame of :func:`base_frame` (P = P1 + X e1 + Y e2 +- Z e3).

    Parameters
    ----------
    base : (M, 3, 3) rows P1 P2 P3 (base frame) of each root's problem
    x : (M,) roots :math:`s_{15}`
    sides : (M, 6) squared sides s12 s13 s23 s45 s46 s56
    legs : (M, 6) squared legs s14 s24 s25 s35 s36 s16
    frame : optional, :func:`base_frame` of ``base`` (computed once per problem by a
        caller with several roots per problem, then gathered)

    Returns
    -------
    points : (3, 3, 2, M) coordinate c of point P(4+r) for side s (+1, -1) of root m at
        ``points[r, c, s, m]``, base frame
    h2min : (M,) the smallest relative squared height met (negative: infeasible; the
        same for both sides)
    r36 : (M,) relative leg-5 residual :math:`(|P_3P_6|^2 - s_{36})/(s_{36}+s_{35})` of
        the chosen (P4, P6)
    """
    frame = base_frame(base) if frame is None else frame
    adapted, h2min, r36 = assemble_adapted(x, np.ascontiguousarray(sides.T),
                                           np.ascontiguousarray(legs.T), frame)
    # back to the base frame, both sides: P = P1 + X e1 + Y e2 + side Z e3
    P1 = np.ascontiguousarray(base[:, 0, :].T)
    e1, e2, e3 = np.ascontiguousarray(frame[0].transpose(1, 2, 0))   # (3, M) each
    points = np.empty((3, 3, 2, x.shape[0]))
    for k in range(3):
        X, Y, Z = adapted[3 * k:3 * k + 3]
        inplane = P1 + X * e1 + Y * e2
        off = Z * e3
        points[k, :, 0] = inplane + off
        points[k, :, 1] = inplane - off
    return points, h2min, r36


def assemble_fast(base, x, sides, legs):
    r"""Both mirror placements of P4 P5 P6 for many roots at once (float64).

    :func:`assemble_components` with the points in row layout.

    Parameters
    ----------
    base : (M, 3, 3) rows P1 P2 P3 (base frame) of each root's problem
    x : (M,) roots :math:`s_{15}`
    sides : (M, 6) squared sides s12 s13 s23 s45 s46 s56
    legs : (M, 6) squared legs s14 s24 s25 s35 s36 s16

    Returns
    -------
    points : (M, 2, 3, 3) rows P4 P5 P6 (base frame) for side +1 and side -1 of P5
    h2min : (M, 2) the smallest relative squared height met (negative: infeasible)
    r36 : (M, 2) relative leg-5 residual of the chosen (P4, P6)
    """
    points, h2min, r36 = assemble_components(base, x, sides, legs)
    return (points.transpose(3, 2, 0, 1).copy(), np.repeat(h2min[:, None], 2, axis=1),
            np.repeat(r36[:, None], 2, axis=1))


def assemble_exact(base, x, sides, legs, *, method: str, dps=None):
    r"""The sequence in the precise or certified tier, for one root.

    Parameters
    ----------
    base : 3 rows of 3 scalars (``mpf``, or ``fmpq``/``arb``)
    x : the root (``mpf``, an ``arb`` ball, or an exact ``fmpq``)
    sides, legs : 6 squared lengths each (same tier)

    Returns
    -------
    list of two ``(points, residual)`` for sides +1 and -1 of P5, ``points`` three rows
    P4 P5 P6 of three scalars, ``residual`` the leg-5 residual of the chosen candidate.

    Raises
    ------
    InfeasibleError, DegenerateGeometryError
        From the trilaterations (a spurious root, a flat face).
    UncertifiedError
        Certified tier: no candidate, or more than one, is compatible with leg 5.
    """
    s45, s46, s56 = sides[3], sides[4], sides[5]
    s14, s24, s25, s35, s36, s16 = legs
    P1, P2, P3 = base
    kw = dict(method=method, dps=dps)
    parts5 = trilateration_parts([P1, P2, P3], [x, s25, s35], **kw)
    # with enclosures (arb) or mpf, side -1 is the reflection of side +1 in the base
    # plane: an isometry fixing P1 P2 P3, so it maps the candidates of one side onto
    # those of the other with the same leg-5 residuals (rigorous, and half the work);
    # exact rational data keep the explicit sequence (a zero height stays exactly zero)
    explicit = method == "certified" and type(x).__name__ != "arb"
    out = []
    for sig in ((1, -1) if explicit else (1,)):
        P5 = _point(parts5, sig, method, dps)
        parts4 = trilateration_parts([P1, P2, P5], [s14, s24, s45], **kw)
        cands = []
        for tau in (1, -1):
            P4 = _point(parts4, tau, method, dps)
            parts6 = trilateration_parts([P1, P4, P5], [s16, s46, s56], **kw)
            for rho in (1, -1):
                P6 = _point(parts6, rho, method, dps)
                d = [P6[k] - P3[k] for k in range(3)]
                res = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - s36
                cands.append(([P4, P5, P6], res))
        out.append(_choose(cands, method))
    if len(out) == 1:
        out.append((_reflect(out[0][0], P1, P2, P3), out[0][1]))
    return out


def _reflect(points, P1, P2, P3):
    """Reflection of points (rows) in the plane P1 P2 P3, in the points' number type."""
    v2 = [P2[k] - P1[k] for k in range(3)]
    v3 = [P3[k] - P1[k] for k in range(3)]
    n = [v2[1] * v3[2] - v2[2] * v3[1], v2[2] * v3[0] - v2[0] * v3[2],
         v2[0] * v3[1] - v2[1] * v3[0]]
    nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
    out = []
    for p in points:
        k = 2 * ((p[0] - P1[0]) * n[0] + (p[1] - P1[1]) * n[1] + (p[2] - P1[2]) * n[2]) / nn
        out.append([p[0] - k * n[0], p[1] - k * n[1], p[2] - k * n[2]])
    return out


def _point(parts, side, method, dps):
    if method == "certified" and type(parts.h2).__name__ == "fmpq" and parts.h2 == 0 and all(
            type(f).__name__ == "fmpq" for f in parts.foot):
        return list(parts.foot)          # exactly in the plane: keep it exact
    return parts.point(side)


def _flat(points):
    return [v for row in points for v in row]


def _choose(cands, method):
    if method == "precise":
        return min(cands, key=lambda c: abs(c[1]))
    ok = [c for c in cands if (c[1] == 0 if type(c[1]).__name__ == "fmpq" else c[1].contains(0))]
    if ok and all(type(v).__name__ == "fmpq" for v in _flat(ok[0][0])):
        return ok[0]          # exact: equal candidates (a zero height) are one placement
    if len(ok) == 1:
        return ok[0]
    if not ok:
        raise UncertifiedError("no placement of P4, P6 is compatible with leg 5 (P3-P6) "
                               "within the enclosures")
    # candidates that are the same point set (a zero height) are one placement
    first = ok[0][0]
    if all(all(a.overlaps(b) for pa, pb in zip(first, c[0]) for a, b in zip(pa, pb))
           for c in ok[1:]):
        raise UncertifiedError("two placements of P4, P6 overlap: a zero height that the "
                               "enclosures cannot separate")
    raise UncertifiedError(f"{len(ok)} placements of P4, P6 are compatible with leg 5 "
                           "within the enclosures; refine the root")
