r"""Singularities of six-leg platforms: Plücker Jacobian, Cayley-Menger and four-planes tests.

Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited* (ICRA 2012), Sec. IV.

Three characterisations of the parallel singularities of the octahedral manipulator
(labels of docs/design.md §3; legs P1–P4, P2–P4, P2–P5, P3–P5, P3–P6, P1–P6):

1. :math:`\det \mathbf J = 0`, :math:`\mathbf J` the matrix of normalised Plücker
   coordinates of the six leg lines, eq. (5) (:func:`plucker_jacobian`).
2. The pure condition in Cayley-Menger form (paper, Sec. IV, citing ref. [21]):
   :math:`C = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) - D(1,2,3,4)D(2,4,5,6)D(1,3,5,6) = 0`
   (:func:`cm_pure_condition`).
3. The planes :math:`P_1P_2P_4`, :math:`P_2P_3P_5`, :math:`P_3P_1P_6`, :math:`P_4P_5P_6`
   meet in a point (:func:`four_planes`).

What we found (checked in ``derivations/delta_transform.py`` and ``tests/singularity``).
With signed volumes :math:`a = V_{1245}V_{3456}V_{1236}` and
:math:`b = V_{1234}V_{2456}V_{1356}`, and :math:`\hat{\mathbf J}` the *unnormalised*
Plücker matrix (rows :math:`(p_k-b_k,\; b_k\times(p_k-b_k))`, i.e.
:math:`\operatorname{diag}(l)\,\mathbf J`):

* :math:`\det\hat{\mathbf J} = -216\,(a+b)`, and the four-planes determinant
  :math:`F` equals :math:`\det\hat{\mathbf J}` exactly;
* since :math:`D(i,j,k,l) = 288\,V_{ijkl}^2`, the paper's form is
  :math:`C = 288^3 (a^2-b^2) = -110592\,(a-b)\det\hat{\mathbf J}`.  The extra factor
  :math:`a-b` vanishes at non-singular poses (e.g. the symmetric home pose of a
  3-fold symmetric manipulator), so :math:`C = 0` is necessary, not sufficient;
* the *signed* Cayley-Menger form, built from the bideterminants
  :math:`D(I;J) = 288\,V_I V_J`,
  :math:`K = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) + D(1,2,4,5;1,2,3,4)D(3,4,5,6;2,4,5,6)D(1,2,3,6;1,3,5,6)
  = 288^3\,a\,(a+b) = -110592\,a\,\det\hat{\mathbf J}`
  (:func:`signed_cm_condition`), has the ratio :math:`-110592\,a` to
  :math:`\det\hat{\mathbf J}`: one sign wherever none of the tetrahedra
  :math:`P_1P_2P_4P_5`, :math:`P_3P_4P_5P_6`, :math:`P_1P_2P_3P_6` is flat.

Number types: ``fast`` (float64, batched over leading axes), ``precise`` (mpmath object
arrays), ``certified`` (flint ``fmpq`` exact or ``arb`` balls; a sign that a ball cannot
decide raises :class:`~distkin.errors.UncertifiedError`).  sympy is never imported
here unless the caller passes sympy numbers (exact symbolic checks).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..argcheck import positive_number
from ..errors import DegenerateGeometryError, DistkinError, InputError, UncertifiedError
from .cm_error import exact_relative as _relative
from .planes import PLANES, FourPlanes, four_planes, volume_factors
from .tiers import (_at, _check_legs, _cross, _det, _digits, _float_or_str, _kind, _precision,
                    _prepare, _sqrt, _sympify, _to_flint)

__all__ = [
    "OCTAHEDRAL_LEGS",
    "octahedral_joints",
    "plucker_jacobian",
    "jacobian_det",
    "cm_pure_condition",
    "signed_cm_condition",
    "volume_factors",
    "four_planes",
    "FourPlanes",
    "certified_sign",
    "RATIO_CONSTANT",
    "PLANES",
]

#: legs of the octahedral manipulator as (base label, platform label), docs/design.md §3
OCTAHEDRAL_LEGS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))

#: 288^3 / 216: C = -RATIO_CONSTANT (a - b) det(Jhat), K = -RATIO_CONSTANT a det(Jhat)
RATIO_CONSTANT = 110592


# ----------------------------------------------------------------------- the Jacobian

def octahedral_joints(points):
    """Leg end points of the octahedral manipulator.

    Parameters
    ----------
    points : array (..., 6, 3)
        P1..P6 in the base frame (length units).

    Returns
    -------
    base_joints, platform_joints : arrays (..., 6, 3)
        Leg k runs from ``base_joints[..., k, :]`` to ``platform_joints[..., k, :]``
        (:data:`OCTAHEDRAL_LEGS`).
    """
    pts = np.asarray(points) if not isinstance(points, np.ndarray) else points
    if pts.shape[-2:] != (6, 3):
        raise InputError(f"expected points of shape (..., 6, 3), got {pts.shape}", field="points")
    bi = [b - 1 for b, _ in OCTAHEDRAL_LEGS]
    pi = [p - 1 for _, p in OCTAHEDRAL_LEGS]
    return pts[..., bi, :], pts[..., pi, :]


def plucker_jacobian(base_joints, platform_joints, *, normalised: bool = True,
                     reference=None, method: str | None = None, dps: int | None = None):
    r"""The Jacobian of eq. (5): Plücker coordinates of the six leg lines.

    Row :math:`k` is :math:`(u_k,\; (b_k - c)\times u_k)` with
    :math:`u_k = (p_k - b_k)/l_k` (``normalised=True``, the :math:`\mathbf J` of
    eq. (5): :math:`\dot l = \mathbf J (v, \Omega)`) or :math:`u_k = p_k - b_k`
    (``normalised=False``: :math:`\hat{\mathbf J} = \operatorname{diag}(l)\mathbf J`,
    :math:`\operatorname{diag}(l)\dot l = \hat{\mathbf J}(v,\Omega)`).  ``c`` is the
    reference point (default the base origin); :math:`v` is the velocity of the
    platform point at :math:`c`, :math:`\Omega` the angular velocity.  The choice of
    :math:`c` does not change :math:`\det\mathbf J`.

    Parameters
    ----------
    base_joints, platform_joints : array (..., 6, 3)
        Joint centres in the base frame (length units).
    normalised : bool
    reference : array (3,), optional
    method : {"fast", "precise", "certified"} or None
        None keeps the input's number type.
    dps : int, optional
        Decimal digits of the precise tier (5..1233, default 30), set locally
        (``mpmath.workdps``; mpmath's global ``mp.dps`` is not used); only with
        ``method="precise"``.

    Returns
    -------
    array (..., 6, 6)
        Direction columns dimensionless (normalised) or in length units; moment
        columns one length unit more.

    Raises
    ------
    InputError
        Booleans, NaN or inf, or wrong shapes in the joints or ``reference``.
    DegenerateGeometryError
        ``normalised=True`` and a leg of zero length (named), in every tier.
    """
    with _precision(dps, method, base_joints, platform_joints):
        return _plucker(base_joints, platform_joints, normalised, reference, method)[0]


def _plucker(base_joints, platform_joints, normalised, reference, method):
    """``(J, b)``: :func:`plucker_jacobian` at the working precision, and the base
    joints in its tier."""
    b, kind = _prepare(base_joints, method, "base_joints")
    tier = kind if kind in ("fast", "precise", "certified") else None
    p, _ = _prepare(platform_joints, tier, "platform_joints")
    if kind == "sympy" and _kind(p) != "sympy":
        p = np.vectorize(_sympify, otypes=[object])(p)
    if b.shape[-2:] != (6, 3) or p.shape[-2:] != (6, 3):
        raise InputError(f"expected joints of shape (..., 6, 3), got {b.shape} and {p.shape}",
                         field="base_joints" if b.shape[-2:] != (6, 3) else "platform_joints")
    if b.shape != p.shape:
        try:
            np.broadcast_shapes(b.shape, p.shape)
        except ValueError:
            raise InputError(f"expected base and platform joints of matching batch shapes, got "
                             f"{b.shape} and {p.shape}", field="platform_joints") from None
    u = p - b
    if normalised:
        sq = np.sum(u * u, axis=-1)
        _check_legs(sq, kind)
        u = u / _sqrt(sq, kind)[..., None]
    arm = b
    if reference is not None:
        ref, _ = _prepare(reference, tier, "reference")
        if ref.shape != (3,):
            raise InputError(f"expected a reference point of shape (3,), got {ref.shape}",
                             field="reference")
        if kind == "sympy":
            ref = np.vectorize(_sympify, otypes=[object])(ref)
        arm = b - ref
    return np.concatenate([u, _cross(arm, u)], axis=-1), b


def jacobian_det(base_joints, platform_joints, *, normalised: bool = True,
                 length_scale=None, method: str | None = None, with_error: bool = False,
                 dps: int | None = None, warn: bool = True):
    r""":math:`\det\mathbf J` of eq. (5) (or of :math:`\hat{\mathbf J}`).

    With ``length_scale`` L (a finite number > 0, length units) the moment columns are
    divided by L, so that the normalised determinant is dimensionless
    (:math:`\det/L^3`).

    Accuracy.  The fast (float64, LU) value is not vouched for: near a singularity it
    loses digits (QA: 49 of 200 near-singular poses off by more than 1e-6 relative).
    ``with_error=True`` returns ``(value, error)``, the rounding-error estimate of
    :func:`.float_range.det_error` (fast, precise; an estimate, not a bound; 0 only for
    an exact 0), the ball's radius (arb) or 0 (fmpq, sympy): where ``|value| > error``
    the sign is trustworthy by the estimate; ``method="certified"`` proves it.  Fast:
    where the estimate exceeds :math:`|\det|` a
    :class:`~distkin.errors.ConditioningWarning` names the value and the estimate (QA
    23: ill-conditioned leg lines gave -1.56 for -26.79 without a word); it costs a
    bound of the estimate per pose (:func:`.float_range.det_error_bound`) and the
    estimate itself only where that bound fails.  ``warn=False`` leaves the warning
    out, for callers that drive det J to 0 on purpose (root finding along a path: the
    singularity queries, :mod:`distkin.delta.singular_locus`) or read ``with_error``
    themselves.
    The precise tier works at ``dps`` digits (5..1233, default 30, set locally; only
    with ``method="precise"``), never at mpmath's global ``mp.dps``.  Fast: a value (or estimate) outside
    :math:`2^{\pm 960}`, or a leg whose squared length underflowed, is computed again
    from joints scaled by a power of two (exact; :mod:`.float_range`); a value outside
    the float64 range then warns (:class:`~distkin.geometry.cm_float.FloatRangeWarning`:
    0.0 or inf, the value as a decimal; QA: inf at 1e80 with a RuntimeWarning only).

    Raises
    ------
    InputError
        Booleans, NaN or inf in the joints, wrong shapes, ``length_scale`` <= 0 or not
        finite (the error names the field).
    DegenerateGeometryError
        ``normalised=True`` with a leg of zero length (the leg is named), in every tier.

    Returns
    -------
    float array (batch shape) | mpf | arb or fmpq (certified; exact for rational
    joints with ``normalised=False``); with ``with_error`` a pair (value, error)
    """
    from . import float_range
    Lf = None if length_scale is None else positive_number(length_scale, "length_scale")
    args = (normalised, length_scale, Lf, method, with_error)
    if not (method == "fast" or (method is None and _kind(base_joints) == "fast"
                                 and _kind(platform_joints) == "fast")):
        with _precision(dps, method, base_joints, platform_joints):
            return _jdet(base_joints, platform_joints, *args, None)[0]
    if dps is not None:
        _digits(dps, method)             # dps with the fast tier: InputError
    try:                  # unscaled first: the hot path pays one range check of the value
        with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
            out, note = _jdet(base_joints, platform_joints, *args, None)
        if float_range.det_in_range(out[0] if with_error else out) and (
                not with_error or bool(np.all((out[1] > 0) & (out[1] < np.inf)))):
            return _said(out, note, warn)
    except DegenerateGeometryError:      # a leg's squared length underflowed? (rescaled)
        pass
    b, p = (_prepare(x, "fast", f)[0] for x, f in ((base_joints, "base_joints"),
                                                   (platform_joints, "platform_joints")))
    b, p, scale = float_range.scaled_joints(b, p)
    return _said(*_jdet(b, p, *args, scale), warn)


def _said(out, note, warn_):
    """``out``, after the ConditioningWarning ``note`` (if any, and ``warn_``) at the
    caller's line."""
    if note is not None and warn_:
        from ..errors import ConditioningWarning, warn
        warn(note, ConditioningWarning)
    return out


def _jdet(base_joints, platform_joints, normalised, length_scale, Lf, method, with_error,
          scale):
    """``(out, note)``: :func:`jacobian_det` of joints scaled by :math:`2^{-e}`
    (``scale`` e, fast; None: unscaled), the value (and error) scaled back, and the
    fast tier's ConditioningWarning text where the estimate exceeds the value (else
    None)."""
    from . import float_range
    J, arm = _plucker(base_joints, platform_joints, normalised, None, method)  # caller's dps
    kind = _kind(J) if method is None else method
    if kind == "exact":
        kind = "certified"
    d = _det(J, kind)
    err = flag = None
    if (with_error and kind == "precise") or kind == "fast":
        if with_error or not float_range.det_resolved(d, J, arm, normalised):   # (fast)
            err = float_range.det_error(J, arm, J[..., :3], kind)
        if kind == "fast" and err is not None:
            flag = np.asarray(err > np.abs(d))
    if length_scale is not None:
        L = length_scale if isinstance(length_scale, (int, float, Fraction)) else Lf
        L = {"fast": float, "precise": _float_or_str, "certified": _to_flint}.get(kind, _sympify)(L)
        if scale is not None:                   # the joints were scaled: L alike
            L = np.ldexp(L, -scale)
        d = d / L ** 3
        err = None if err is None else err / abs(L) ** 3
    degree = (3 if normalised else 9) - (0 if length_scale is None else 3)
    if scale is not None and degree:    # homogeneous of that degree in the coordinates
        d = float_range.scale_back(d, scale, degree, "det J" if normalised else "det Jhat",
                                   "a length_scale")
        err = None if err is None else float_range.scale_error(err, scale, degree)
    note = None
    if flag is not None and flag.any():
        note = float_range.unresolved_note(d, err, flag, "det J" if normalised else "det Jhat")
    if not with_error:
        return d, note
    return (d, (_radius(d) if err is None else err)), note


def certified_sign(value) -> int:
    """The sign of an ``arb``/``fmpq`` value (0 only for an exact zero), or
    :class:`UncertifiedError` when a ball of non-zero radius contains 0.

    Examples
    --------
    >>> import flint
    >>> certified_sign(flint.arb(2, 0.5)), certified_sign(flint.fmpq(-1, 3)), certified_sign(flint.arb(0))
    (1, -1, 0)
    >>> certified_sign(flint.arb(0, 1e-9))
    Traceback (most recent call last):
    ...
    distkin.errors.UncertifiedError: expected a ball excluding 0, got [+/- 1.01e-9] (hint: raise flint.ctx.prec (arb working precision, bits) and recompute, or move away from the singularity)
    """
    name = type(value).__name__
    if name in ("fmpq", "fmpz"):
        return (value > 0) - (value < 0)
    if name == "arb":
        if value > 0:
            return 1
        if value < 0:
            return -1
        if value.is_zero():              # radius 0, midpoint 0: exactly zero
            return 0
        raise UncertifiedError(f"expected a ball excluding 0, got {value.str(5, radius=True)}",
                               hint="raise flint.ctx.prec (arb working precision, bits) and "
                                    "recompute, or move away from the singularity")
    raise InputError(f"expected an arb or fmpq value to certify, got {name}")


# ------------------------------------------------------------- Cayley-Menger conditions

def cm_pure_condition(points, *, method: str | None = None, relative: bool = False,
                      dps: int | None = None, with_error: bool = False):
    r"""The paper's pure condition in Cayley-Menger form (Sec. IV):

    .. math:: C = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) - D(1,2,3,4)D(2,4,5,6)D(1,3,5,6).

    :math:`C = -110592\,(a-b)\det\hat{\mathbf J}` (module docstring): it vanishes at
    every singularity but also where :math:`a = b`.

    Parameters
    ----------
    points : array (..., 6, 3)
        P1..P6, base frame (length units).
    method : {"fast", "precise", "certified"} or None
        None keeps the input's number type.
    relative : bool
        Divide by :math:`D(1,2,4,5)D(3,4,5,6)D(1,2,3,6) + D(1,2,3,4)D(2,4,5,6)D(1,3,5,6)`
        (dimensionless, in [-1, 1]).
    dps : int, optional
        Decimal digits of the precise tier (5..1233, default 30), set locally
        (``mpmath.workdps``); only with ``method="precise"``.
    with_error : bool
        Return ``(value, error)``: the rounding-error estimate of :mod:`.cm_error`
        (fast, precise), the ball's radius (arb) or 0 (exact).

    Returns
    -------
    number or float array (length units^18 unless relative); NaN where a fast or
    precise relative value is undefined (both products within their rounding error of 0,
    :class:`~distkin.geometry.cm_float.CancellationWarning` saying so); a relative
    value whose error estimate exceeds 1e-6 warns too.  The absolute form does not warn
    (it is near 0 at every singularity): ``with_error`` gives its estimate, 0 only for
    an exact value.  Fast: coordinates whose squared distances leave :math:`2^{\pm 64}`
    are scaled by a power of two (:mod:`.float_range`; exact, the relative value is
    scale-free); an absolute value beyond the float64 range reads 0.0 or inf with a
    :class:`~distkin.geometry.cm_float.FloatRangeWarning` giving it as a decimal.
    Precise and certified: a batch (..., 6, 3) is computed one point set at a time
    (object arrays).

    Raises
    ------
    DegenerateGeometryError
        ``relative`` where both products vanish exactly (a flat tetrahedron in each,
        named; then :math:`C = 0` exactly and its relative value is 0/0).
    UncertifiedError
        ``relative``, certified, where the denominator's ball contains 0.
    InputError
        ``dps`` out of range or given with another method.
    """
    return _condition(points, method, dps, relative, with_error, signed=False)


def signed_cm_condition(points, *, method: str | None = None, relative: bool = False,
                        dps: int | None = None, with_error: bool = False):
    r"""The signed pure condition from Cayley-Menger (bi)determinants:

    .. math:: K = D(1,2,4,5)D(3,4,5,6)D(1,2,3,6)
              + D(1,2,4,5;1,2,3,4)\,D(3,4,5,6;2,4,5,6)\,D(1,2,3,6;1,3,5,6)
              = 288^3\,a\,(a+b) = -110592\,a\,\det\hat{\mathbf J}.

    Distances only, and :math:`K = 0` exactly at the singularities (where
    :math:`a \ne 0`).  ``relative`` divides by
    :math:`|D(1,2,4,5)D(3,4,5,6)D(1,2,3,6)| + |D(\dots;\dots)D(\dots;\dots)D(\dots;\dots)|`;
    where that vanishes (a flat tetrahedron in each product) a
    :class:`~distkin.errors.DegenerateGeometryError` names them.  ``method``, ``dps``,
    ``with_error``, NaN and warnings as in :func:`cm_pure_condition`.
    """
    return _condition(points, method, dps, relative, with_error, signed=True)


_BIDETS = (((1, 2, 4, 5), (1, 2, 3, 4)), ((3, 4, 5, 6), (2, 4, 5, 6)),
           ((1, 2, 3, 6), (1, 3, 5, 6)))


def _condition(points, method, dps, relative, with_error, signed):
    with _precision(dps, method, points):    # local precision, not mpmath.mp's (QA V 3)
        pts, kind = _prepare(points, method)
        if pts.shape[-2:] != (6, 3):
            raise InputError(f"expected points P1..P6 of shape (..., 6, 3), got {pts.shape}",
                             field="points")
        if kind == "fast" or pts.ndim == 2:
            return _condition1(pts, kind, relative, with_error, signed)
        vals, errs = (np.empty(pts.shape[:-2], dtype=object) for _ in range(2))
        for idx in np.ndindex(pts.shape[:-2]):   # exact tiers: one point set at a time
            try:
                out = _condition1(pts[idx], kind, relative, True, signed)
            except DistkinError as exc:
                raise type(exc)(exc.message + _at(idx), field=exc.field,
                                hint=exc.hint) from None
            vals[idx], errs[idx] = out
        return (vals, errs) if with_error else vals


def _condition1(pts, kind, relative, with_error, signed):
    """:func:`_condition` of one point set (exact tiers) or a float batch.  The fast tier
    works on coordinates scaled by a power of two where their squared distances leave
    :math:`2^{\\pm 64}` (:mod:`.float_range`), the absolute value and its error scaled
    back (degree 18)."""
    from ..geometry.cayley_menger import squared_distances
    from . import float_range
    if kind == "fast":
        sq, scale = float_range.scaled_squared_distances(pts)
    else:
        sq, scale = squared_distances(pts), None
    tets = {t: _D(sq, t) for t in (_TETS[:3] if signed else _TETS)}
    first = tets[1, 2, 4, 5] * tets[3, 4, 5, 6] * tets[1, 2, 3, 6]
    if signed:
        bidets = [_D(sq, r, c) for r, c in _BIDETS]
        second = bidets[0] * bidets[1] * bidets[2]
        num, den = first + second, abs(first) + abs(second)
        what = "signed Cayley-Menger condition"
        all_tets = lambda: {**tets, **{t: _D(sq, t) for t in _TETS[3:]}}  # noqa: E731
    else:
        second = tets[1, 2, 3, 4] * tets[2, 4, 5, 6] * tets[1, 3, 5, 6]
        num, den = first - second, first + second
        what = "Cayley-Menger condition"
        all_tets = lambda: tets  # noqa: E731
    if kind not in ("fast", "precise"):
        val = _relative(num, den, kind, all_tets, what) if relative else num
        return (val, _radius(val)) if with_error else val
    if not relative and not with_error:       # the hot path: no estimate asked for
        return num if scale is None else float_range.scale_back(num, scale, 18, what)
    from . import cm_error
    e1 = cm_error.product_error([tets[t] for t in _TETS[:3]],
                                [cm_error.det_error(sq, t, None, kind) for t in _TETS[:3]],
                                kind)
    if signed:
        e2 = cm_error.product_error(bidets, [cm_error.det_error(sq, r, c, kind)
                                             for r, c in _BIDETS], kind)
    else:
        e2 = cm_error.product_error([tets[t] for t in _TETS[3:]],
                                    [cm_error.det_error(sq, t, None, kind)
                                     for t in _TETS[3:]], kind)
    err = e1 + e2
    if not relative:
        if scale is not None:
            num = float_range.scale_back(num, scale, 18, what)
            err = float_range.scale_error(err, scale, 18)
        return (num, err) if with_error else num
    if np.any(np.asarray(den == 0)):         # exactly 0/0: the tetrahedra are named
        _relative(num, den, kind, all_tets, what)
    val, e = cm_error.relative(num, den, err, kind, what)
    return (val, e) if with_error else val


def _radius(v):
    name = type(v).__name__
    if name == "arb":
        return float(v.rad())
    return 0.0


def _D(sq, rows, cols=None):
    """:func:`~distkin.geometry.cayley_menger` without its fast tier's
    CancellationWarning: here determinants near 0 are the point (a flat tetrahedron,
    a singularity), and the conditions state their accuracy themselves (``relative``,
    the tiers)."""
    import warnings
    from ..geometry.cayley_menger import CancellationWarning, cayley_menger
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CancellationWarning)
        return cayley_menger(sq, rows, cols)


#: the six tetrahedra of the Cayley-Menger conditions: a's three, then b's three
_TETS = ((1, 2, 4, 5), (3, 4, 5, 6), (1, 2, 3, 6), (1, 2, 3, 4), (2, 4, 5, 6), (1, 3, 5, 6))
