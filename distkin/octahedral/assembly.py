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
Ros, IEEE T-RO 21(1), 2005).  :func:`assemble_fast` is a mask-based numpy version
batched over many roots (it never raises; it returns the squared heights so the caller
can reject); :func:`assemble_exact` runs the sequence in the precise tier (``mpf``) or
the certified tier (``arb`` balls, deciding every sign with certainty; on exactly
rational data through :func:`~distkin.geometry.trilateration.trilateration_parts`, so
that a zero height is exactly zero).
"""

from __future__ import annotations

import numpy as np

from ..errors import DegenerateGeometryError, InfeasibleError, UncertifiedError

__all__ = ["trilaterate_masked", "assemble_fast", "assemble_exact"]


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


def assemble_fast(base, x, sides, legs):
    r"""Both mirror placements of P4 P5 P6 for many roots at once (float64).

    Parameters
    ----------
    base : (M, 3, 3) rows P1 P2 P3 (base frame) of each root's problem
    x : (M,) roots :math:`s_{15}`
    sides : (M, 6) squared sides s12 s13 s23 s45 s46 s56
    legs : (M, 6) squared legs s14 s24 s25 s35 s36 s16

    Returns
    -------
    points : (M, 2, 3, 3) rows P4 P5 P6 for side +1 and side -1 of P5
    h2min : (M, 2) the smallest relative squared height met (negative: infeasible)
    r36 : (M, 2) relative leg-5 residual of the chosen (P4, P6)
    """
    P1, P2, P3 = base[:, 0], base[:, 1], base[:, 2]
    s45, s46, s56 = sides[:, 3], sides[:, 4], sides[:, 5]
    s14, s24, s25, s35, s36, s16 = (legs[:, k] for k in range(6))
    f5, o5, h5 = trilaterate_masked(P1, P2, P3, x, s25, s35)
    sig = np.array([1.0, -1.0])
    P5 = f5[:, None, :] + sig[None, :, None] * o5[:, None, :]            # (M,2,3)
    e = lambda a: a[:, None]  # noqa: E731  (broadcast helper over the side axis)
    f4, o4, h4 = trilaterate_masked(e(P1), e(P2), P5, e(s14), e(s24), e(s45))
    P4 = f4[:, :, None, :] + sig[None, None, :, None] * o4[:, :, None, :]  # (M,2,2,3)
    ee = lambda a: a[:, None, None]  # noqa: E731
    f6, o6, h6 = trilaterate_masked(ee(P1), P4, P5[:, :, None, :],
                                    ee(s16), ee(s46), ee(s56))
    P6 = f6[..., None, :] + sig[None, None, None, :, None] * o6[..., None, :]  # (M,2,2,2,3)
    d = P6 - P3[:, None, None, None, :]
    r = (_dot(d, d) - ee(s36)[..., None]) / (ee(s36)[..., None] + ee(s35)[..., None] + 1e-300)
    flat = np.abs(r).reshape(r.shape[0], 2, 4)
    best = flat.argmin(-1)                                                   # (M,2)
    tau, rho = best // 2, best % 2
    m = np.arange(r.shape[0])[:, None]
    s = np.arange(2)[None, :]
    P4b = P4[m, s, tau]
    P6b = P6[m, s, tau, rho]
    points = np.stack([P4b, P5, P6b], axis=-2)
    h2min = np.minimum(np.minimum(h5[:, None], h4), h6[m, s, tau])
    return points, h2min, flat[m, s, best]


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
    if method == "precise":
        trilateration_parts = _parts_mpf
    elif type(x).__name__ == "arb":
        trilateration_parts = _parts_arb
    else:  # exact rational data: the foundation's exact trilateration (h^2 = 0 exactly)
        from ..geometry.trilateration import trilateration_parts
    parts5 = trilateration_parts([P1, P2, P3], [x, s25, s35], **kw)
    out = []
    for sig in (1, -1):
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
    return out


def _point(parts, side, method, dps):
    if method == "certified" and type(parts.h2).__name__ == "fmpq" and parts.h2 == 0 and all(
            type(f).__name__ == "fmpq" for f in parts.foot):
        return list(parts.foot)          # exactly in the plane: keep it exact
    return parts.point(side)


class _MpfParts:
    """Foot, normal, |n|^2 and h^2 of one trilateration in ``mpf`` (current precision)."""

    def __init__(self, foot, normal, G, h2):
        self.foot, self.normal, self.G, self.h2 = foot, normal, G, h2

    def point(self, side):
        import mpmath
        scale = mpmath.sqrt(self.h2 / self.G) * side
        return [f + scale * c for f, c in zip(self.foot, self.normal)]


def _gram(points, sq):
    A, B, C = points
    sa, sb, sc = sq
    v2 = [B[k] - A[k] for k in range(3)]
    v3 = [C[k] - A[k] for k in range(3)]
    g22 = v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]
    g33 = v3[0] * v3[0] + v3[1] * v3[1] + v3[2] * v3[2]
    g23 = v2[0] * v3[0] + v2[1] * v3[1] + v2[2] * v3[2]
    n = [v2[1] * v3[2] - v2[2] * v3[1], v2[2] * v3[0] - v2[0] * v3[2],
         v2[0] * v3[1] - v2[1] * v3[0]]
    G = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
    return A, v2, v3, g22, g33, g23, n, G, sa, sb, sc


def _foot(A, v2, v3, g22, g33, g23, G, sa, sb, sc):
    w2 = (sa + g22 - sb) / 2
    w3 = (sa + g33 - sc) / 2
    alpha = (w2 * g33 - w3 * g23) / G
    beta = (w3 * g22 - w2 * g23) / G
    foot = [A[k] + alpha * v2[k] + beta * v3[k] for k in range(3)]
    return foot, sa - (alpha * w2 + beta * w3)


class _ArbParts:
    """Foot, normal, |n|^2 and h^2 of one trilateration in ``arb`` balls."""

    def __init__(self, foot, normal, G, h2):
        self.foot, self.normal, self.G, self.h2 = foot, normal, G, h2

    def point(self, side):
        scale = (self.h2 / self.G).sqrt() * side
        return [f + scale * c for f, c in zip(self.foot, self.normal)]


def _parts_arb(points, sq, *, method="certified", dps=None):
    """Gram-form trilateration (as :mod:`distkin.geometry.trilateration`) on ``arb``
    balls, deciding with certainty: a height that is certainly negative is infeasible, a
    ball of h^2 or of |n|^2 that contains 0 is :class:`UncertifiedError`."""
    import flint
    A, v2, v3, g22, g33, g23, n, G, sa, sb, sc = _gram(
        [[flint.arb(c) for c in p] for p in points], [flint.arb(v) for v in sq])
    if not G > 0:
        if G.is_zero():
            raise DegenerateGeometryError("expected three non-collinear reference points, "
                                          "got collinear points (exactly)", field="points")
        raise UncertifiedError("cannot decide whether the reference points are collinear: "
                               f"|n|^2 = {G.str(5, radius=True)}")
    foot, h2 = _foot(A, v2, v3, g22, g33, g23, G, sa, sb, sc)
    if h2 < 0:
        raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                              f"{h2.str(8, radius=True)}", margin=float(h2.mid()), field="sq")
    if not h2 > 0:
        raise UncertifiedError(f"cannot decide whether the distances close: h^2 = "
                               f"{h2.str(8, radius=True)} contains 0")
    return _ArbParts(foot, n, G, h2)


def _parts_mpf(points, sq, *, method="precise", dps=None):
    """Gram-form trilateration (as :mod:`distkin.geometry.trilateration`) on ``mpf``
    values at the caller's working precision; h^2 within 10^(8-dps) relative of 0 is
    taken as 0."""
    import mpmath
    A, B, C = points
    sa, sb, sc = sq
    v2 = [B[k] - A[k] for k in range(3)]
    v3 = [C[k] - A[k] for k in range(3)]
    g22 = sum(c * c for c in v2)
    g33 = sum(c * c for c in v3)
    g23 = sum(a * b for a, b in zip(v2, v3))
    n = [v2[1] * v3[2] - v2[2] * v3[1], v2[2] * v3[0] - v2[0] * v3[2],
         v2[0] * v3[1] - v2[1] * v3[0]]
    G = sum(c * c for c in n)
    tol = mpmath.mpf(10) ** (8 - mpmath.mp.dps)
    if G <= tol * g22 * g33:
        raise DegenerateGeometryError("expected three non-collinear reference points, got "
                                      f"|n|^2 = {mpmath.nstr(G, 5)}", field="points")
    w2 = (sa + g22 - sb) / 2
    w3 = (sa + g33 - sc) / 2
    alpha = (w2 * g33 - w3 * g23) / G
    beta = (w3 * g22 - w2 * g23) / G
    foot = [A[k] + alpha * v2[k] + beta * v3[k] for k in range(3)]
    h2 = sa - (alpha * w2 + beta * w3)
    if h2 < -tol * (abs(sa) + g22 + g33):
        raise InfeasibleError(f"expected distances that close (h^2 >= 0), got h^2 = "
                              f"{mpmath.nstr(h2, 8)}", margin=float(h2), field="sq")
    return _MpfParts(foot, n, G, max(h2, mpmath.mpf(0)))


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
