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
axes), ``mpmath.mpf`` and ``flint.fmpq`` (exact) or ``flint.arb`` (balls), as nested lists
of scalars.  :func:`pose_from_points` refuses triangles that are not congruent within a
relative tolerance (QA T 7), :func:`points_from_pose` a matrix that is not a proper
rotation (QA T 1).
"""

from __future__ import annotations

import numpy as np

from ..errors import DegenerateGeometryError, InputError, UncertifiedError, warn as _warn
from ..exact import check_method

__all__ = ["triangle_frame", "pose_from_points", "points_from_pose", "frame_fit", "FRAME_RTOL"]


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


def _tier_rows(points, method, what, noun="points"):
    """Three points as 3x3 nested lists in the number type of the precise (mpf) or
    certified (fmpq, or arb when irrational) tier, converted exactly first: a float is
    its binary value, a numeric string is parsed exactly (as :func:`.trilaterate`), so
    the certified frame encloses the exact frame of the inputs (QA J 2, 8)."""
    from .trilateration import _three_rows, _tier_scalar
    rows = _three_rows(points, noun, what)
    native = _NATIVE[method]
    return [[x if type(x).__name__ in native else _tier_scalar(x, method, f"{what}[{i}][{j}]")
             for j, x in enumerate(r)] for i, r in enumerate(rows)]


#: number types a tier takes as they are (the solvers' own values: no conversion cost)
_NATIVE = {"precise": ("mpf",), "certified": ("arb", "fmpq")}


def _fast_points(points, what):
    """Points (..., 3, 3) as float64, checked as in the other tiers
    (:func:`.trilateration._fast_floats`): numeric strings parsed exactly then rounded
    once, booleans, complex numbers, ragged lists, other shapes and values beyond the
    float64 range refused with an :class:`InputError` naming ``what``."""
    from .trilateration import _fast_floats
    P = _fast_floats(points, what, "points of shape (..., 3, 3)", 3)
    if P.shape[-2:] != (3, 3):
        raise InputError(f"expected points of shape (..., 3, 3), got shape {P.shape}",
                         field=what)
    return P


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
            raise UncertifiedError(f"cannot decide whether the triangle of {what} is proper: "
                                   f"the enclosure of its normal's squared length, {v}, "
                                   f"holds 0 (collinear points) at this precision")


def triangle_frame(points, *, method: str = "fast", what: str = "points"):
    r"""Orthonormal right-handed frame of a triangle.

    Parameters
    ----------
    points : array_like (..., 3, 3) or 3 rows of 3 scalars
        Rows :math:`a_1, a_2, a_3` in any length unit: numbers of any tier or numeric
        strings, parsed exactly in every tier (rounded once for ``fast``).

    Returns
    -------
    F : (..., 3, 3) array (columns e1 e2 e3) for ``fast``; else a 3x3 nested list
        ``F[row][col]``.

    Raises
    ------
    InputError
        Another shape (a ragged list names its row), booleans, complex numbers,
        non-numbers, NaN or inf, values beyond the float64 range in ``fast``.
    DegenerateGeometryError
        Collinear or coincident points.

    Warns
    -----
    ConditioningWarning
        Fast tier, once per call: a nearly collinear triangle whose frame's error
        estimate :math:`4\varepsilon/\sin\theta` (:math:`\theta` its angle at
        :math:`a_1`) exceeds :data:`FRAME_RTOL` (1e-6); without it the frame's entries
        are within that of the exact frame of the float64 input.
    """
    check_method(method)
    if method == "fast":
        F, rho = _frame_fast(_fast_points(points, what), what)
        _warn_frame(rho, what)
        return F
    return _frame(_tier_rows(points, method, what), method, what)


#: the accuracy the fast tier's frame (and pose) vouches for: an error estimate above it
#: (a nearly collinear triangle) warns
FRAME_RTOL = 1e-6
_EPS = float(np.finfo(float).eps)


def _frame_fast(P, what):
    r"""The fast tier's frames of triangles ``P`` (..., 3, 3) and the error estimate
    of their entries (:math:`4\varepsilon/\sin\theta`, :math:`\theta` the angle at
    :math:`a_1`: the normal of a nearly collinear triangle is the difference of nearly
    equal products)."""
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
    _check_nonzero(n2, l1 * l2, "fast", what)
    e1 = d1 / np.sqrt(l1)[..., None]
    e3 = n / np.sqrt(n2)[..., None]
    e2 = np.cross(e3, e1)
    # e3's direction is off by about 4 eps |d1||d2| / |n| = 4 eps / sin(angle at a1)
    rho = 4 * _EPS * np.sqrt(l1 * l2 / n2)
    return np.stack([e1, e2, e3], axis=-1), rho


def _warn_frame(rho, what):
    """One ConditioningWarning where the frame error estimate ``rho`` exceeds
    :data:`FRAME_RTOL` (the worst of a batch)."""
    if not np.any(rho > FRAME_RTOL):
        return
    from ..errors import ConditioningWarning
    worst = float(np.max(rho))
    w = ConditioningWarning(
        f"{what}: the fast tier's frame of a nearly collinear triangle may be off by "
        f"{worst:.2g} (error estimate 4 eps / sin of its angle at the first point, above "
        f"{FRAME_RTOL:g}); use method='precise' or method='certified'")
    w.estimate = worst
    _warn(w)


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


def pose_from_points(local, world, *, method: str = "fast", rtol: float | None = None):
    r"""The pose :math:`(R, t)` carrying three platform-frame points onto base-frame points.

    Parameters
    ----------
    local : array_like (3, 3) (or (..., 3, 3), fast)
        Rows :math:`q_4, q_5, q_6` in the platform frame.
    world : array_like (..., 3, 3)
        Rows :math:`p_4, p_5, p_6` in the base frame (a congruent triangle).
    method : {"fast", "precise", "certified"}
    rtol : float, optional
        Congruence test: every squared side of ``world`` must equal the same side of
        ``local`` within ``rtol`` times the largest squared side of ``local``, else
        :class:`InputError` (no rigid motion carries one triangle onto the other, so any
        pose would be wrong).  Default 1e-9 (fast, certified) and
        ``max(1e-9, 10**(-dps/3))`` (precise, at the working ``mpmath.mp.dps``): rounding
        of float64 data, and of points computed in the tier, passes; a scaled or
        misplaced point does not.  For measured data pass the measurement's relative
        accuracy (e.g. ``rtol=1e-4``); ``rtol=0`` asks for exact congruence (certified
        with rational data).  The certified tier refuses only a mismatch that is
        certain (balls of irrational or computed data pass while they overlap).

    Returns
    -------
    R : (..., 3, 3), proper rotation with :math:`p_i = R q_i + t`
    t : (..., 3)
        Nested lists of ``mpf`` / ``arb`` for the precise / certified tiers.  Exact when
        the triangles are exactly congruent; otherwise (within ``rtol``) the frame fit
        above (it does not spread the error like a least-squares fit would).

    Raises
    ------
    InputError
        Triangles that are not congruent within ``rtol`` (QA T 7), malformed input (as
        :func:`triangle_frame`; numeric strings are parsed exactly in every tier).
    DegenerateGeometryError
        Collinear or coincident points.

    Warns
    -----
    ConditioningWarning
        Fast tier, once per call: a frame of either triangle cannot be vouched for to
        :data:`FRAME_RTOL` (as :func:`triangle_frame`).

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
        q = _fast_points(local, "platform")
        p = _fast_points(world, "points")
        (Fq, rq), (Fp, rp) = _frame_fast(q, "platform"), _frame_fast(p, "points")
        _warn_frame(np.maximum(np.max(rq), np.max(rp)), "platform and points")
        _congruent_fast(q, p, 1e-9 if rtol is None else _tolerance(rtol))
        R = Fp @ np.swapaxes(Fq, -1, -2)
        t = p.mean(axis=-2) - np.einsum("...ij,...j->...i", R, q.mean(axis=-2))
        return R, t
    local = _tier_rows(local, method, "platform")
    world = _tier_rows(world, method, "points")
    _congruent_tier(local, world, method, rtol)
    return _fit(local, world, method)


def frame_fit(local, world, method: str):
    """:func:`pose_from_points` of the ``precise`` and ``certified`` tiers without the
    congruence check: for callers whose triangles are congruent by construction (the
    octahedral tiers' trilateration places P4 P5 P6 at the platform's own sides; the
    check cost their certified solve ~0.4 ms of ~4.3).  Returns ``(R, t)`` as
    :func:`pose_from_points`."""
    check_method(method)
    if method == "fast":
        raise InputError("expected method 'precise' or 'certified' (the fast tier's "
                         "check is vectorised: use pose_from_points), got 'fast'",
                         field="method")
    return _fit(_tier_rows(local, method, "platform"), _tier_rows(world, method, "points"),
                method)


def _fit(local, world, method):
    Fq = _frame(local, method, "platform")
    Fp = _frame(world, method, "points")
    R = [[sum(Fp[i][k] * Fq[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    qc = [sum(local[r][c] for r in range(3)) / 3 for c in range(3)]
    pc = [sum(world[r][c] for r in range(3)) / 3 for c in range(3)]
    t = [pc[i] - sum(R[i][k] * qc[k] for k in range(3)) for i in range(3)]
    return R, t


_PAIRS = ((0, 1), (0, 2), (1, 2))


def _tolerance(value, name="rtol"):
    """A tolerance ``name`` (``rtol``, ``atol``): a number 0 <= value < 1, or InputError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not 0 <= value < 1:
        raise InputError(f"expected a tolerance 0 <= {name} < 1, got {value!r}", field=name)
    return float(value)


def _refuse_congruence(pair, sp, sq, rel, rtol, where=""):
    i, j = pair
    raise InputError(f"expected a triangle congruent to the platform triangle (squared sides "
                     f"equal within rtol = {rtol:g} of its largest), got s({i + 1},{j + 1}) = "
                     f"{sp:.12g} against {sq:.12g} in the platform frame (relative mismatch "
                     f"{rel:.3g}){where}", field="points",
                     hint="no rigid motion carries one triangle onto the other; for measured "
                     "data pass rtol at the measurement's relative accuracy")


def _congruent_fast(q, p, rtol):
    """Refuse (…, 3, 3) triangles ``p`` whose squared sides differ from those of ``q`` by
    more than ``rtol`` times q's largest squared side (vectorised; both scaled by the same
    power of two first, exact, so that huge or tiny triangles neither over- nor
    underflow)."""
    try:
        q, p = np.broadcast_arrays(q, p)
    except ValueError:
        raise InputError(f"expected platform points {q.shape} and points {p.shape} whose "
                         "batch shapes broadcast, got ones that do not", field="points") from None
    dq = q[..., [1, 2, 2], :] - q[..., [0, 0, 1], :]
    dp = p[..., [1, 2, 2], :] - p[..., [0, 0, 1], :]
    big = np.maximum(np.abs(dq).max(axis=(-2, -1)), np.abs(dp).max(axis=(-2, -1)))
    e = np.frexp(np.where(big > 0, big, 1.0))[1][..., None, None]
    dq, dp = np.ldexp(dq, -e), np.ldexp(dp, -e)
    sq = np.einsum("...k,...k->...", dq, dq)
    sp = np.einsum("...k,...k->...", dp, dp)
    scale = sq.max(axis=-1, keepdims=True)
    bad = np.abs(sp - sq) > rtol * scale
    if bad.any():
        idx = tuple(int(x) for x in np.argwhere(bad)[0])
        rel = float(np.abs(sp - sq)[idx] / scale[idx[:-1] + (0,)])
        with np.errstate(over="ignore", under="ignore"):
            ex = 2 * np.broadcast_to(e[..., 0], sq.shape)[idx]
            a, b = (float(np.ldexp(v[idx], ex)) for v in (sq, sp))
        _refuse_congruence(_PAIRS[idx[-1]], b, a, rel, rtol,
                           f" (batch index {idx[:-1]})" if len(idx) > 1 else "")


def _congruent_tier(local, world, method, rtol):
    """:func:`_congruent_fast` for one triangle in the precise or certified tier (the
    certified tier refuses only a certain mismatch)."""
    sides = [[_dot(_sub(T[j], T[i]), _sub(T[j], T[i])) for i, j in _PAIRS]
             for T in (local, world)]
    if method == "precise":
        import mpmath
        rtol = max(1e-9, 10.0 ** (-mpmath.mp.dps / 3)) if rtol is None else _tolerance(rtol)
        scale = max(sides[0])
        for k, (a, b) in enumerate(zip(*sides)):
            if abs(b - a) > rtol * scale:
                _refuse_congruence(_PAIRS[k], float(b), float(a), float(abs(b - a) / scale),
                                   rtol)
        return
    import flint
    from ..exact import to_fmpq
    rtol = 1e-9 if rtol is None else _tolerance(rtol)
    if all(type(x).__name__ == "fmpq" for T in sides for x in T):
        scale, tol = max(sides[0]), to_fmpq(rtol)          # exact comparison
        bad = [abs(b - a) > tol * scale for a, b in zip(*sides)]
    else:
        # balls: the sum of the squared sides bounds the largest from above, so a
        # refusal is certain
        scale = flint.arb(sides[0][0]) + sides[0][1] + sides[0][2]
        bad = [abs(flint.arb(b) - a) > rtol * scale for a, b in zip(*sides)]
    if any(bad):
        k = bad.index(True)
        a, b = (float(flint.arb(x).mid()) for x in (sides[0][k], sides[1][k]))
        sc = max(float(flint.arb(x).mid()) for x in sides[0])
        _refuse_congruence(_PAIRS[k], b, a, abs(b - a) / sc, rtol)


def points_from_pose(R, t, local, *, method: str = "fast", dps: int | None = None,
                     atol: float = 1e-9):
    r"""Base-frame points :math:`p_i = R q_i + t` of platform-frame points (the pose map of
    the module docstring; Rojas et al., ICRA 2012, Sec. III).

    Parameters
    ----------
    R : (..., 3, 3) (fast) or 3 rows of 3 scalars
        A proper rotation: :math:`\max|R^{\mathsf T}R - I| \le` ``atol`` and
        :math:`\det R > 0`, else :class:`InputError` (a scaled matrix or a reflection is
        not a pose).  Float rotations are orthogonal only to rounding, hence ``atol``.
    t : (..., 3) or 3 scalars, length unit
    local : (k, 3) platform-frame points (rows), length unit
    method : {"fast", "precise", "certified"}
        ``fast``: float64, batched over the leading axes of ``R`` and ``t``.
        ``precise``: ``mpmath.mpf`` at ``dps`` digits (default 30, as every precise
        tier: never mpmath's global ``mp.dps``, 15 unless set, QA 23b).  ``certified``: exact
        ``flint.fmpq`` when every input is rational, ``flint.arb`` balls otherwise.
        In the precise and certified tiers every entry (numbers of any tier, numeric
        strings parsed exactly: ``"19.8"`` is 99/5, ``"sqrt(27)"``) is converted exactly
        first; a bare float is its exact binary value, so the certified result is exactly
        (fmpq) or provably (arb) :math:`R q + t` of the values given.
    dps : int, optional
        Decimal digits of the precise tier.
    atol : float
        Tolerance of the rotation test (in the certified tier a refusal is certain).

    Returns
    -------
    (..., k, 3) float array for ``fast``; a nested list ``out[i][c]`` (k rows of 3) of
    ``mpf`` (precise) or ``fmpq`` / ``arb`` (certified: exact, or a certified radius)
    otherwise.

    Examples
    --------
    >>> out = points_from_pose([[0, -1, 0], [1, 0, 0], [0, 0, 1]], [1, 2, 3],
    ...                        [["19.8", 0, 0]], method="certified")
    >>> [str(c) for c in out[0]]
    ['1', '109/5', '3']
    """
    check_method(method)
    atol = _tolerance(atol, "atol")
    if method == "fast":
        from .trilateration import _fast_floats
        R = _fast_floats(R, "R", "a rotation matrix of shape (..., 3, 3)", 3)
        t = _fast_floats(t, "t", "a translation of shape (..., 3)", 3)
        q = _fast_floats(local, "local", "platform-frame points of shape (k, 3)", 3)
        for name, arr, want, ok in (("R", R, "(..., 3, 3)", R.shape[-2:] == (3, 3)),
                                    ("t", t, "(..., 3)", t.shape[-1:] == (3,)),
                                    ("local", q, "(k, 3)", q.ndim == 2 and q.shape[1] == 3)):
            if not ok:
                raise InputError(f"expected shape {want}, got {arr.shape}", field=name)
            if not np.all(np.isfinite(arr)):
                raise InputError("expected finite numbers, got NaN or inf", field=name)
        try:
            batch = np.broadcast_shapes(R.shape[:-2], t.shape[:-1])
        except ValueError:
            raise InputError(f"expected batch shapes of R {R.shape} and t {t.shape} that "
                             "broadcast, got ones that do not", field="t") from None
        from ..spatial import rotation_defect
        ortho, det = rotation_defect(R)
        if not (ortho <= atol and np.all(det > 0)):
            _refuse_rotation(ortho, float(np.min(det)), atol)
        out = np.einsum("...ij,kj->...ki", R, q) + t[..., None, :]
        return np.broadcast_to(out, batch + q.shape).copy() if out.shape != batch + q.shape \
            else out
    if method == "precise":
        import mpmath
        from ..exact import default_dps
        with mpmath.workdps(default_dps(dps)):
            return _points_tier(R, t, local, method, atol)
    return _points_tier(R, t, local, method, atol)


def _refuse_rotation(ortho, det, atol):
    if det < 0:
        what, hint = "a reflection", "a rigid motion has det R = +1; a reflection maps the " \
            "points onto their mirror image"
    else:
        what, hint = "not a rotation", "orthonormalise R first (e.g. scipy's " \
            "Rotation.from_matrix(R).as_matrix()), or pass a larger atol"
    raise InputError(f"expected a proper rotation R (max|R^T R - I| <= {atol:g}, det R = +1), "
                     f"got max|R^T R - I| = {ortho:.3g} and det R = {det:.6g} ({what})",
                     field="R", hint=hint)


def _points_tier(R, t, local, method, atol):
    """:func:`points_from_pose` in the precise or certified tier (one pose)."""
    rows = _tier_rows(R, method, "R", noun="rows")
    tv = _tier_vector(t, method, "t")
    q = _tier_points(local, method, "local")
    dev = [[_dot([rows[k][i] for k in range(3)], [rows[k][j] for k in range(3)])
            - (1 if i == j else 0) for j in range(3)] for i in range(3)]
    det = _dot(rows[0], _cross(rows[1], rows[2]))
    if method == "precise":
        ortho = max(abs(d) for r in dev for d in r)
        if ortho > atol or det <= 0:
            _refuse_rotation(float(ortho), float(det), atol)
    else:
        import flint
        balls = [flint.arb(d) for r in dev for d in r]
        if any(abs(b) > atol for b in balls) or flint.arb(det) < 0:
            ortho = max(float(abs(b).mid()) for b in balls)
            _refuse_rotation(ortho, float(flint.arb(det).mid()), atol)
        if not flint.arb(det) > 0:
            raise UncertifiedError("cannot decide the sign of det R", field="R")
    # an exact zero of R times a ball is exactly zero (keeps an exact coordinate exact)
    return [[sum((rows[i][k] * row[k] for k in range(3) if not _exact_zero(rows[i][k])),
                 tv[i]) for i in range(3)] for row in q]


def _exact_zero(x):
    return type(x).__name__ == "fmpq" and x == 0


def _tier_vector(v, method, field):
    """Three scalars in the tier's number type (see :func:`_tier_rows`)."""
    from .trilateration import _show, _tier_scalar
    if isinstance(v, np.ndarray):
        v = v.tolist()
    try:
        vals = list(v)
    except TypeError:
        vals = None
    if vals is None or len(vals) != 3 or any(isinstance(x, (list, tuple)) for x in vals):
        raise InputError(f"expected 3 scalars, got {_show(v)}", field=field)
    native = _NATIVE[method]
    return [x if type(x).__name__ in native else _tier_scalar(x, method, f"{field}[{i}]")
            for i, x in enumerate(vals)]


def _tier_points(points, method, field):
    """k rows of 3 coordinates in the tier's number type."""
    from .trilateration import _show
    if isinstance(points, np.ndarray):
        points = points.tolist()
    try:
        rows = list(points)
    except TypeError:
        rows = None
    if rows is None or not all(isinstance(r, (list, tuple)) for r in rows):
        raise InputError(f"expected platform-frame points of shape (k, 3), got "
                         f"{_show(points)}", field=field)
    return [_tier_vector(r, method, f"{field}[{i}]") for i, r in enumerate(rows)]
