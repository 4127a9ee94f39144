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
Ros, IEEE T-RO 21(1), 2005).  The fast tier runs the sequence compiled, in the
base-adapted frame where the first two trilaterations have closed forms and side -1 is
side +1 reflected (:func:`.placement.assemble_many`); :func:`trilaterate_masked` is a
mask-free numpy trilateration batched over many points (it never raises; it returns the
squared heights so the caller can reject); :func:`assemble_exact` runs the sequence in
the precise tier
(``mpf``) or the certified tier (``arb`` balls, deciding every sign with certainty;
exact ``fmpq`` on rational data, so that a zero height is exactly zero), both through
:func:`~distkin.geometry.trilateration.trilateration_parts`, side -1 again as the
reflection of side +1 except on exact data.  In the certified tier a side face of the
octahedron on its closure limit (its squared sides, exact, close it flat) places its
point on the line of the two others, exactly, instead of deciding a zero height with
balls; and a P5 in the base plane yields each mode with its mirror image from one P5.
"""

from __future__ import annotations

import numpy as np

from ..errors import UncertifiedError
from ..geometry.trilateration import parts_at_working_digits

__all__ = ["trilaterate_masked", "assemble_exact"]


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


def assemble_exact(base, x, sides, legs, *, method: str, dps=None, every=None, tol=None):
    r"""The sequence in the precise or certified tier, for one root.

    Parameters
    ----------
    base : 3 rows of 3 scalars (``mpf``, or ``fmpq``/``arb``)
    x : the root (``mpf``, an ``arb`` ball, or an exact ``fmpq``)
    sides, legs : 6 squared lengths each (same tier)

    tol : precise tier only: relative tolerance of the trilaterations (default theirs,
        10^(8 - dps)); the precise tier passes the root's relative uncertainty when it
        is larger (a multiple root)
    every : precise tier only: keep every candidate whose leg-5 residual is at most
        ``every`` (squared length), distinct as point sets, instead of the best one
        (a multiple root of the octic at which several assembly modes meet: on the
        equilateral octahedron with six equal legs a triple root carries three)

    Returns
    -------
    list of two ``(points, residual)`` for sides +1 and -1 of P5, ``points`` three rows
    P4 P5 P6 of three scalars, ``residual`` the leg-5 residual of the chosen candidate;
    with ``every``, a list of ``(side, points, residual)``, each mode followed by its
    mirror image.

    Raises
    ------
    InfeasibleError, DegenerateGeometryError
        From the trilaterations (a spurious root, a flat face).
    UncertifiedError
        Certified tier: no candidate, or more than one, is compatible with leg 5.
    """
    s14, s24, s25, s35, s36, s16 = legs
    P1, P2, P3 = base
    kw = dict(method=method, digits=dps, tol=tol)   # the solver's working digits
    certified = method == "certified"
    # a side face of the octahedron on its closure limit (a triangle inequality met with
    # equality, decided exactly) puts its point on the line of the two others: placed
    # there exactly, where the balls of a zero height could not decide (QA)
    P5 = _on_flat_face(P2, P3, s25, s35, sides[2]) if certified else None
    if P5 is None:
        parts5 = parts_at_working_digits([P1, P2, P3], [x, s25, s35], **kw)
        if certified and _exact_zero(parts5.h2):
            P5 = list(parts5.foot)
    if P5 is not None:
        # P5 in the base plane: one P5 for both sides, whose candidates hold each mode
        # and its mirror image (QA: "2 placements ... compatible" was refused)
        return _in_plane_modes(_candidates(P1, P2, P5, P3, sides, legs, kw), P1, P2, P3)
    # with enclosures (arb) or mpf, side -1 is the reflection of side +1 in the base
    # plane: an isometry fixing P1 P2 P3, so it maps the candidates of one side onto
    # those of the other with the same leg-5 residuals (rigorous, and half the work);
    # exact rational data keep the explicit sequence (a zero height stays exactly zero)
    explicit = certified and type(x).__name__ != "arb"
    out = []
    for sig in ((1, -1) if explicit else (1,)):
        P5 = _point(parts5, sig, method, dps)
        cands = _candidates(P1, P2, P5, P3, sides, legs, kw)
        if every is not None:   # (precise: one side, never the explicit sequence)
            # each mode followed by its mirror image
            return [m for pts, res in _compatible(cands, every)
                    for m in ((1, pts, res), (-1, _reflect(pts, P1, P2, P3), res))]
        out.append(_choose(cands, method))
    if len(out) == 1:
        out.append((_reflect(out[0][0], P1, P2, P3), out[0][1]))
    return out


def _candidates(P1, P2, P5, P3, sides, legs, kw):
    """The four placements ``([P4, P5, P6], leg-5 residual)`` of a placed P5: P4 on
    either side of the plane P1 P2 P5, P6 on either side of P1 P4 P5 (one where a flat
    face puts the point on a line, :func:`_on_flat_face`)."""
    s45, s46, s56 = sides[3], sides[4], sides[5]
    s14, s24, s25, s35, s36, s16 = legs
    method, dps = kw["method"], kw["digits"]
    certified = method == "certified"
    P4 = (_on_flat_face(P1, P2, s14, s24, sides[0]) or _on_flat_face(P2, P5, s24, s45, s25)
          if certified else None)
    if P4 is None:
        parts4 = parts_at_working_digits([P1, P2, P5], [s14, s24, s45], **kw)
    cands = []
    for tau in ((1,) if P4 is not None else (1, -1)):
        Q4 = P4 if P4 is not None else _point(parts4, tau, method, dps)
        P6 = _on_flat_face(P1, Q4, s16, s46, s14) if certified else None
        if P6 is None:
            parts6 = parts_at_working_digits([P1, Q4, P5], [s16, s46, s56], **kw)
        for rho in ((1,) if P6 is not None else (1, -1)):
            Q6 = P6 if P6 is not None else _point(parts6, rho, method, dps)
            d = [Q6[k] - P3[k] for k in range(3)]
            res = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - s36
            cands.append(([Q4, P5, Q6], res))
    return cands


def _exact_zero(v) -> bool:
    return type(v).__name__ == "fmpq" and v == 0


def _on_flat_face(Y, Z, sxy, sxz, syz):
    """The point X of a face X Y Z whose exact squared sides (``sxy`` = |XY|^2, ...,
    fmpq) close it flat (the Cayley-Menger determinant of the triangle is 0): on the
    line YZ, at
    Y + t (Z - Y), t = (sxy - sxz + syz) / (2 syz); None when the face is not flat or
    the squared sides are not exact."""
    if not all(type(v).__name__ == "fmpq" for v in (sxy, sxz, syz)):
        return None
    from ..geometry.cayley_menger import triangle_area_squared
    if triangle_area_squared({(1, 2): sxy, (1, 3): sxz, (2, 3): syz}, 1, 2, 3) != 0:
        return None
    t = (sxy - sxz + syz) / (2 * syz)
    return [Y[k] + t * (Z[k] - Y[k]) for k in range(3)]


def _in_plane_modes(cands, P1, P2, P3):
    """The placements at a P5 in the base plane (certified): the compatible candidates
    are each mode and its mirror image in the base plane (one, when the mode is its own
    mirror image); anything else raises :class:`UncertifiedError`."""
    ok = []
    for c in cands:     # compatible, and exactly equal candidates (zero heights) once
        if (c[1] == 0 if type(c[1]).__name__ == "fmpq" else c[1].contains(0)) and not any(
                _exact(c[0]) and _exact(d[0]) and _same(c[0], d[0]) for d in ok):
            ok.append(c)
    if len(ok) == 1 and _same(ok[0][0], _reflect(ok[0][0], P1, P2, P3)):
        return ok
    if len(ok) == 2 and not _same(ok[0][0], ok[1][0]) and _same(
            ok[1][0], _reflect(ok[0][0], P1, P2, P3)):
        return ok
    raise UncertifiedError(f"{len(ok)} placements of P4, P6 are compatible with leg 5 "
                           "within the enclosures at a P5 in the base plane, not one mode "
                           "and its mirror image")


def _exact(points) -> bool:
    return all(type(v).__name__ == "fmpq" for row in points for v in row)


def _same(a, b) -> bool:
    """Two point sets that are equal (exact) or whose balls overlap."""
    def eq(u, v):
        if type(u).__name__ == "fmpq" and type(v).__name__ == "fmpq":
            return u == v
        import flint
        return flint.arb(u).overlaps(flint.arb(v))
    return all(eq(u, v) for pa, pb in zip(a, b) for u, v in zip(pa, pb))


def _compatible(cands, tol):
    """The candidates compatible with leg 5 (``every`` of :func:`assemble_exact`,
    precise tier): residual at most ``tol``, distinct as point sets (the best one
    always)."""
    ranked = sorted(cands, key=lambda c: abs(c[1]))
    keep = [ranked[0]]
    for pts, res in ranked[1:]:
        if abs(res) > tol:
            break
        if all(max(abs(a - b) for pa, pb in zip(pts, q) for a, b in zip(pa, pb)) ** 2 > tol
               for q, _ in keep):
            keep.append((pts, res))
    return keep


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
