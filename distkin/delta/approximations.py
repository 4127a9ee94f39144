r"""Approximations of the octahedral manipulator by 6-6 platforms with single spherical
joints, and what their offsets cost: Rojas, Borràs, Thomas, *The Octahedral Manipulator
Revisited* (ICRA 2012), Sec. I, Fig. 2 (b)-(d), and Sec. III-VI (eqs. (4), (5), (8)-(9)).

Each double-ball joint of the octahedral manipulator (labels of docs/design.md §3: base
P1 P2 P3, platform P4 P5 P6; leg 1 = P1-P4, 2 = P2-P4, 3 = P2-P5, 4 = P3-P5, 5 = P3-P6,
6 = P1-P6) is split into two single joints whose centres are ``delta`` apart (length
units; the same meaning for all three):

``"standard"`` (Fig. 2(b))
    Both joints move by ``delta/2`` from the original centre V, in opposite directions
    along the tangential direction :math:`\tau` (in the triangle's plane, perpendicular
    to the radial direction :math:`\rho = (V-G)/|V-G|`, G the triangle's centroid).  The
    leg from V to the opposite vertex X takes the side of :math:`\tau` that points
    towards the neighbour of V in the same triangle that is also joined to X (leg 1
    at P1 moves towards P2, at P4 towards P6), so legs do not cross.  The paper draws
    the split but does not specify it; this symmetric tangential split (the usual
    paired-joint hexapod) is our reading.
``"stoughton_arai"`` (Fig. 2(c), ref. [8] there)
    Both joints move by ``delta/2`` radially, one inwards (towards G), one outwards,
    "equidistant to the original center" (Sec. I).  Which leg goes inwards is not
    stated in the paper; ours (``pattern="mixed"``): legs 1, 3, 5 inwards at the
    base and outwards on the platform, legs 2, 4, 6 the reverse, so that every joint
    has one leg in and one out and every leg one inner and one outer end.
    ``pattern="paired"``: legs 1, 3, 5 inwards at both ends, 2, 4, 6 outwards.
``"griffis_duffy"`` (Fig. 2(d), Fig. 6)
    The Δ 6-6 platform of Sec. V-VI, built by :func:`~.platform66.equivalent_platform`
    with :math:`\delta_1 = \dots = \delta_6 = ` ``delta``: one leg keeps the original
    centre, the other (legs 1, 3, 5 at the base, 2, 4, 6 on the platform) moves by
    ``delta`` along the triangle edge towards the same neighbour as above (rows of
    eq. (9), :data:`~.transform.ROWS`).  Its squared legs are affine in the octahedral
    ones (eq. (8)), so it has the octahedral assembly modes and singularities.

Offsets.  The paper introduces (b) and (c) as approximations "with small offsets"
(Sec. I); for (d) the Δ-transform needs :math:`0 < \delta_i < d_i`, the side along which
the joint moves (Sec. V, eq. (9); :func:`~.platform66.check_offsets`).  For (b) and (c)
we refuse (:class:`~distkin.errors.InputError` naming ``delta``) an offset of the
shortest side of the base or platform triangle or more: there the single joints land a
side length or more apart and no longer approximate a double-ball joint (QA: delta 100 on
a base of side 12 was accepted).  Below it, a radially inward joint stays short of the
centroid (the circumradius is :math:`d/\sqrt 3 > d/2` for an equilateral triangle).

The measured comparison (:func:`neglected_offset_error`, :func:`singularity_shift`,
:func:`compare_approximations`) lives in :mod:`.offset_study`.
"""

from __future__ import annotations

from ..errors import InputError
from ..singularity.conditions import OCTAHEDRAL_LEGS
from .platform66 import Platform66, _show, equivalent_platform
from .exact_input import _as_sym, _base_platform, _exact_form, _sym_points

__all__ = [
    "KINDS",
    "octahedral_as_66",
    "standard_approximation",
    "stoughton_arai_approximation",
    "griffis_duffy_approximation",
    "approximation",
    "joint_offsets",
]

#: the approximations of Fig. 2 (b), (c), (d), in that order
KINDS = ("standard", "stoughton_arai", "griffis_duffy")


def _points(octahedral):
    """P1..P6 as sympy 3-vectors (base frame for P1..P3, platform frame for P4..P6)."""
    import sympy as sp
    base, platform = _base_platform(octahedral)      # 3 points of 3 coordinates each
    return [sp.Matrix(p) for p in _sym_points(base, platform)]


def _delta(delta):
    d = _as_sym(delta, "delta", allow_symbols=False)
    if not d.is_number or not d.is_positive:
        shown = getattr(delta, "text", None) or str(d)     # an Exact as written (QA J 9)
        raise InputError(f"expected a positive offset delta (length units), got {shown} "
                         "(length units)", field="delta")
    return d


def _small_offset(octahedral, delta, d):
    """Refuse an offset that is not small: ``delta`` at least the shortest side of the
    base or platform triangle (:class:`InputError` naming ``delta``; module docstring,
    "Offsets")."""
    import sympy as sp
    pts = _points(octahedral)
    sides = [(pts[i] - pts[j]).dot(pts[i] - pts[j])
             for i, j in ((0, 1), (1, 2), (0, 2), (3, 4), (4, 5), (3, 5))]
    k = min(range(6), key=lambda i: float(sides[i]))
    if sp.N(d ** 2 - sides[k], 30) >= 0:
        names = ("P1P2", "P2P3", "P1P3", "P4P5", "P5P6", "P4P6")
        shown = getattr(delta, "text", None) or _show(d)
        raise InputError(f"expected 0 < delta < {_show(sp.sqrt(sides[k]))} (the "
                         f"shortest triangle side, {names[k]}: the split approximates a "
                         f"double-ball joint by a small offset), got {shown} (length units)",
                         field="delta",
                         hint="joints split by a side length or more are no approximation "
                              "of the octahedral manipulator")


def _partner(vertex: int, other: int) -> int:
    """The neighbour of ``vertex`` in its own triangle that is also joined to ``other``
    (the vertex at the far end of the leg)."""
    for b, p in OCTAHEDRAL_LEGS:
        if other in (b, p):
            cand = p if other == b else b
            if cand != vertex:
                return cand
    raise AssertionError("unreachable")  # pragma: no cover


def _unit(v):
    import sympy as sp
    n = sp.sqrt(_exact_form(v.dot(v)))      # exact: no rounding of float data
    return v / n


def _directions(pts, vertex):
    """Outward radial and (unsigned) tangential unit vectors at P<vertex> (sympy)."""
    tri = (0, 1, 2) if vertex <= 3 else (3, 4, 5)
    G = sum((pts[i] for i in tri), pts[0] * 0) / 3
    V = pts[vertex - 1]
    a, b, c = (pts[i] for i in tri)
    n = (b - a).cross(c - a)
    rho = _unit(V - G)
    tau = _unit(n.cross(rho))
    return rho, tau


def octahedral_as_66(octahedral) -> Platform66:
    """The octahedral manipulator itself written as six legs (δ = 0: the joints of each
    double-ball joint coincide); leg k joins the base and platform points of
    :data:`~distkin.singularity.conditions.OCTAHEDRAL_LEGS` ``[k]``."""
    pts = _points(octahedral)
    return Platform66(tuple(tuple(pts[b - 1]) for b, _ in OCTAHEDRAL_LEGS),
                      tuple(tuple(pts[p - 1]) for _, p in OCTAHEDRAL_LEGS))


def _split(octahedral, move) -> Platform66:
    """Move each of the 12 leg ends: ``move(k, end, pts, V, far)`` -> displacement
    (sympy 3-vector), ``end`` 0 (base) or 1 (platform), leg ``k`` 1-based."""
    import sympy as sp
    pts = _points(octahedral)
    bj, pj = [], []
    for k, (b, p) in enumerate(OCTAHEDRAL_LEGS, start=1):
        for end, (v, far), out in ((0, (b, p), bj), (1, (p, b), pj)):
            new = pts[v - 1] + move(k, end, pts, v, far)
            out.append(tuple(sp.radsimp(x) for x in new))
    return Platform66(tuple(bj), tuple(pj))


def standard_approximation(octahedral, delta) -> Platform66:
    r"""Fig. 2(b): every double-ball joint split tangentially, each single joint
    ``delta/2`` from the original centre (module docstring for the exact rule).

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
        P1..P3 (base frame) and P4..P6 (platform frame), length units.
    delta : number or exact string
        Centre distance of the two single joints (length units), > 0 and less than the
        shortest side of the base and platform triangles (module docstring, "Offsets").

    Returns
    -------
    Platform66
        ``transform`` is None: no affine leg map (eq. (4)) exists.
    """
    d = _delta(delta)
    _small_offset(octahedral, delta, d)

    def move(k, end, pts, v, far):
        _, tau = _directions(pts, v)
        toward = pts[_partner(v, far) - 1] - pts[v - 1]
        sign = 1 if float(tau.dot(toward)) > 0 else -1
        return sign * d / 2 * tau

    return _split(octahedral, move)


def stoughton_arai_approximation(octahedral, delta, *, pattern: str = "mixed") -> Platform66:
    r"""Fig. 2(c): every double-ball joint split radially, one joint ``delta/2`` inwards,
    the other ``delta/2`` outwards (Rojas et al., Sec. I, after Stoughton and Arai).

    Parameters
    ----------
    octahedral, delta : as :func:`standard_approximation`
    pattern : {"mixed", "paired"}
        Which leg goes inwards (the paper leaves it open).  ``"mixed"``: legs 1, 3, 5
        inwards at the base and outwards on the platform, legs 2, 4, 6 the reverse.
        ``"paired"``: legs 1, 3, 5 inwards at both ends, legs 2, 4, 6 outwards.

    Returns
    -------
    Platform66
    """
    if not isinstance(pattern, str) or pattern not in ("mixed", "paired"):
        raise InputError(f"expected pattern 'mixed' or 'paired', got {pattern!r}",
                         field="pattern")
    d = _delta(delta)
    _small_offset(octahedral, delta, d)

    def move(k, end, pts, v, far):
        rho, _ = _directions(pts, v)
        inward = (k % 2 == 1) == (end == 0 or pattern == "paired")
        return (-1 if inward else 1) * d / 2 * rho

    return _split(octahedral, move)


def griffis_duffy_approximation(octahedral, delta) -> Platform66:
    r"""Fig. 2(d): the Δ 6-6 platform of Sec. V-VI with every :math:`\delta_i` =
    ``delta`` (:func:`~.platform66.equivalent_platform`; one joint of each pair stays,
    the other moves ``delta`` along the triangle edge, eq. (9)).

    Returns
    -------
    Platform66
        With its :class:`~.transform.DeltaTransform` (``transform.A``, ``transform.b``).
    """
    d = _delta(delta)
    return equivalent_platform(octahedral, [d] * 6)


def approximation(octahedral, kind: str, delta, *, pattern: str | None = None) -> Platform66:
    """The approximation ``kind`` (one of :data:`KINDS`) with offset ``delta`` (length
    units).

    Parameters
    ----------
    octahedral, delta : as :func:`standard_approximation`
    kind : {"standard", "stoughton_arai", "griffis_duffy"}
    pattern : {"mixed", "paired"} or None
        Stoughton-Arai only (:func:`stoughton_arai_approximation`; None: ``"mixed"``).
        Given with another kind it is refused: those splits have no pattern to choose.

    Raises
    ------
    InputError
        An unknown ``kind``; a ``pattern`` with a kind other than ``"stoughton_arai"``
        or not one of its patterns; a bad ``delta`` or ``octahedral``.
    """
    makers = {"standard": standard_approximation,
              "stoughton_arai": stoughton_arai_approximation,
              "griffis_duffy": griffis_duffy_approximation}
    if not isinstance(kind, str) or kind not in makers:
        raise InputError(f"expected one of {', '.join(map(repr, KINDS))}, got {kind!r}",
                         field="kind")
    if kind == "stoughton_arai":
        return stoughton_arai_approximation(octahedral, delta,
                                            pattern="mixed" if pattern is None else pattern)
    if pattern is not None:
        raise InputError(f"expected no pattern for kind {kind!r} (only 'stoughton_arai' "
                         f"has one), got {pattern!r}", field="pattern")
    return makers[kind](octahedral, delta)


def joint_offsets(octahedral, platform: Platform66):
    """Displacements of the 12 leg ends from the octahedral double-ball joints.

    Returns
    -------
    base, platform : float arrays (6, 3), length units
        ``platform66 joint - octahedral joint`` per leg (base frame / platform frame).
    """
    ob, op = octahedral_as_66(octahedral).joints("fast")
    b, p = platform.joints("fast")
    return b - ob, p - op
