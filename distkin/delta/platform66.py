r"""The 6-6 platform equivalent to an octahedral manipulator under a Δ-transform, and its
forward kinematics from the octahedral one (Rojas, Borràs, Thomas, *The Octahedral
Manipulator Revisited*, ICRA 2012, Sec. V-VI, eq. (8): :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)`
exact, then the octahedral assembly modes moved to the 6-6 attachment points).

Number types as in :mod:`.transform`: ``fast`` float64, ``precise`` mpmath, ``certified``
flint (arb balls for the poses)."""

from __future__ import annotations

import threading
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property, lru_cache

import numpy as np

from ..errors import DegenerateGeometryError, InputError, warn as _warn
from ..exact import METHODS_AUTO, check_method, default_dps
from .exact_input import (_as_sym, _base_platform, _check_leg_range, _exact_form,
                          _float_legs, _input_key, _readable, _sym_points)
from .transform import ROWS, DeltaTransform, delta_transform

__all__ = [
    "Platform66",
    "equivalent_platform",
    "check_offsets",
    "forward_kinematics66",
    "Pose66",
    "FK66Result",
]


# ----------------------------------------------------------- the equivalent 6-6 platform

@dataclass(frozen=True)
class Platform66:
    r"""A 6-6 platform: leg :math:`k` joins ``base_joints[k]`` to ``platform_joints[k]``.

    Attributes
    ----------
    base_joints : tuple of 6 points (sympy, base frame, length units)
    platform_joints : tuple of 6 points (sympy, platform frame, length units)
    transform : DeltaTransform or None
        The Δ-transform it was built from (Rojas et al., Fig. 6).
    """

    base_joints: tuple
    platform_joints: tuple
    transform: DeltaTransform | None = None

    kind = "platform66"

    def joints(self, method: str = "fast"):
        """Joint coordinates as arrays ``(6, 3)`` (base frame) and ``(6, 3)`` (platform
        frame) in the tier's number type (float / mpf / arb); the float64 arrays are
        computed once (read-only)."""
        if method == "fast":
            return self._fast_joints
        return _tier_array(self.base_joints, method), _tier_array(self.platform_joints, method)

    @cached_property
    def _fast_joints(self):
        b = _tier_array(self.base_joints, "fast")
        p = _tier_array(self.platform_joints, "fast")
        b.flags.writeable = False
        p.flags.writeable = False
        return b, p


def _tier_array(points, method):
    from ..exact import sympy_to_arb
    if method == "fast":
        return np.array([[float(x) for x in p] for p in points], dtype=float)
    if method == "precise":
        import mpmath
        return np.array([[mpmath.mpf(x.evalf(mpmath.mp.dps + 5)) for x in p] for p in points],
                        dtype=object)
    return np.array([[sympy_to_arb(x) for x in p] for p in points], dtype=object)


def equivalent_platform(octahedral, offsets) -> Platform66:
    r"""Build the 6-6 platform of Fig. 6 from an octahedral one and offsets δ1..δ6.

    Row :math:`i` of :data:`ROWS` moves one end of leg :math:`i` from :math:`P_s` to
    :math:`P_s + (\delta_i/d_i)(P_e - P_s)` on the edge :math:`(P_s, P_e)`; the other
    end stays at the shared point.  Leg :math:`k` of the 6-6 platform has length
    :math:`m_k`.

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
    offsets : 6 numbers (numeric; symbols are not allowed here)

    Returns
    -------
    Platform66
        Exact joint positions; base joints in the base frame, platform joints in the
        platform frame of the octahedral mechanism.

    Raises
    ------
    InputError
        Malformed points or offsets (NaN, not 3 points of 3 coordinates, not 6 offsets,
        symbols), or an offset outside :math:`0 < \delta_i < d_i` (the joint would
        leave the triangle edge it moves along).
    DegenerateGeometryError
        Offsets making :math:`\det\mathbf A = 0`, or an offset of 0 or :math:`d_i` that
        would merge two joints again (the platform would not be 6-6).
    """
    key = _input_key((octahedral, offsets))
    if key is None:
        return _equivalent_platform(octahedral, offsets)
    try:
        return _built[key]
    except KeyError:
        pass
    plat = _equivalent_platform(octahedral, offsets)
    with _built_lock:
        if len(_built) >= 64:                       # a bound, not an LRU: drop the oldest
            del _built[next(iter(_built))]
        _built[key] = plat
    return plat


_built: dict = {}   # raw inputs (as _input_key) -> Platform66; only successful builds
_built_lock = threading.Lock()


def _equivalent_platform(octahedral, offsets) -> Platform66:
    tr = delta_transform(octahedral, offsets)
    if tr.free_symbols:
        raise InputError(f"expected numeric offsets to build a platform, got symbols "
                         f"{', '.join(map(str, tr.free_symbols))}", field="offsets")
    check_offsets(tr)
    tr.check_regular()
    base, platform = _base_platform(octahedral)
    return _build_platform(_sym_points(base, platform), tr)


def check_offsets(tr: DeltaTransform, field: str = "offsets") -> None:
    r"""Each numeric :math:`\delta_i` strictly inside its edge, :math:`0 < \delta_i < d_i`
    (Rojas et al., Sec. V, Fig. 6: the joint moves along the edge).  At an end the two
    joints of a double-ball joint merge again (DegenerateGeometryError); beyond it the
    offset is not one of a Δ-transform (InputError); both say the same.  A symbolic
    offset (``Delta1``) is a parameter, not checked.  The one check of the offsets, at
    load time, for ``kind = "platform66"``, its queries and ``delta_transform``
    (``field``: where the scene has them)."""
    for spec, d, delta in zip(ROWS, tr.sides, tr.offsets):
        if delta.free_symbols:
            continue
        at_end = delta == 0 or _exact_form(delta - d) == 0
        if at_end or not (delta.is_positive and (d - delta).is_positive):
            cls = DegenerateGeometryError if at_end else InputError
            raise cls(f"expected 0 < delta{spec.row} < {spec.side} = {_show(d)} (length "
                      f"units) so that every joint is single and on its edge, got "
                      f"delta{spec.row} = {_show(delta)} (length units)",
                      field=f"{field}[{spec.row - 1}]")


def _show(x) -> str:
    """An exact number for a message: as written when rational, else with its value."""
    return str(x) if x.is_Rational and len(str(x)) <= 40 else _readable(x, 10)


@lru_cache(maxsize=64)
def _build_platform(points: tuple, tr: DeltaTransform) -> Platform66:
    r"""The joints of Fig. 6 (cached per geometry and transform), exact: the moved joint
    is :math:`P_s + (\delta/d)(P_e - P_s)`, expanded only (no rounding to "nice"
    numbers, so float data keep their exact binary values)."""
    import sympy as sp
    pts = [sp.Matrix(p) for p in points]
    bj, pj = [], []
    for spec, d, delta in zip(ROWS, tr.sides, tr.offsets):
        s, e = spec.edge
        t = delta / d
        new = (pts[s - 1] + t * (pts[e - 1] - pts[s - 1])).applyfunc(_exact_form)
        shared = pts[spec.shared - 1]
        if spec.moved == "base":
            bj.append(tuple(new))
            pj.append(tuple(shared))
        else:
            bj.append(tuple(shared))
            pj.append(tuple(new))
    return Platform66(tuple(bj), tuple(pj), tr)


# ------------------------------------------------------------- forward kinematics 6-6

@dataclass(frozen=True)
class Pose66:
    """One assembly mode of the 6-6 platform.

    Attributes
    ----------
    rotation : array (3, 3)
        Platform frame -> base frame.
    translation : array (3,), length units
    base_joints, platform_joints : array (6, 3), base frame, length units
    max_leg_error : float
        max_k | |b_k - p_k| - m_k | on the 6-6 platform's own geometry (length units);
        in the certified tier a rigorous upper bound (arb).
    octahedral_pose : object
        The octahedral pose it comes from.
    """

    rotation: np.ndarray
    translation: np.ndarray
    base_joints: np.ndarray
    platform_joints: np.ndarray
    max_leg_error: float
    octahedral_pose: object


@dataclass(frozen=True)
class FK66Result:
    """Result of :func:`forward_kinematics66`.

    Attributes
    ----------
    platform : Platform66
    l_sq, l_legs : tuples of sympy numbers, or float64 arrays (6,) in the fast tier
        The equivalent octahedral legs (exact in the precise and certified tiers).
    octahedral : object
        The octahedral forward-kinematics result.
    poses : tuple of Pose66
    max_leg_error : float
        Worst m-leg residual over all poses (length units).
    """

    platform: Platform66
    l_sq: tuple
    l_legs: tuple
    octahedral: object
    poses: tuple
    max_leg_error: float


def forward_kinematics66(octahedral, offsets, m_legs, *, method: str = "fast",
                         dps: int | None = None) -> FK66Result:
    r"""Forward kinematics of the 6-6 platform equivalent to an octahedral one.

    Rojas et al., Sec. V-VI: map the m-legs to the l-legs by eq. (8),
    :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)` (exact), solve the octahedral forward
    kinematics (:func:`distkin.octahedral.forward_kinematics`) and move the 6-6
    platform (:func:`equivalent_platform`) by each of its poses.  Each pose is then
    checked on the 6-6 platform's own joints, independently of the affine map:
    ``max_leg_error`` = :math:`\max_k \bigl|\,|b_k - (R q_k + t)| - m_k\bigr|`.

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
    offsets : 6 numbers (length units)
    m_legs : 6 leg lengths (Exact, numeric strings like ``"6/25*sqrt(6170)"``)
    method : {"fast", "precise", "certified", "auto"}
        Passed to the octahedral solver; its accuracy statement applies.  ``"auto"``
        maps the legs exactly and lets the octahedral solver choose its tier
        (``result.octahedral.tier`` / ``.tier_reason``); the residual check then runs in
        the tier that answered.  The residual
        check runs in float64 (fast), mpmath at ``dps`` (precise) or arb balls
        (certified: a rigorous upper bound).  ``"fast"`` maps the legs in float64,
        except where its rounding-error bound cannot prove every :math:`l_k^2 > 0`: the
        exact map then decides (:func:`.leg_map_rounding.map_legs_fast`), so
        ``InfeasibleError`` is raised only for a proved :math:`l_k^2 \le 0`.
    dps : int, optional
        Digits of ``precise`` (and of ``auto``'s precise fallback); refused with
        ``fast`` and ``certified``, which would ignore it.

    Returns
    -------
    FK66Result

    Raises
    ------
    InputError
        Malformed, non-finite, non-positive or symbolic m-legs, m-legs beyond the
        octahedral solver's range (largest below :math:`2^{510}`), in every tier alike
        (the field is ``m_legs[i]``); and see :func:`equivalent_platform`.
    DegenerateGeometryError, InfeasibleError
        See :meth:`DeltaTransform.map_legs` and :func:`equivalent_platform`.
    """
    check_method(method, allowed=METHODS_AUTO)
    if dps is not None and method not in ("precise", "auto"):     # QA T 9
        raise InputError(f"expected 'dps' only with method 'precise' or 'auto' (the "
                         f"mpmath digits), got method {method!r}", field="dps")
    dps = default_dps(dps) if dps is not None else None
    plat = equivalent_platform(octahedral, offsets)
    from ..octahedral import forward_kinematics
    base, platform = _base_platform(octahedral)
    # every tier refuses the same m-legs the same way, naming m_legs[i] and the value
    m_float = _float_legs(m_legs, "m_legs")
    _check_leg_range(m_float, "m_legs")
    if method == "fast":  # float64 throughout: no algebra on this path
        m_exact = None
    else:
        m_exact = [_as_sym(x, f"m_legs[{i}]", allow_symbols=False)
                   for i, x in enumerate(m_legs)]
    if method == "auto":  # exact l-legs, so that an escalation certifies this problem
        l_sq, l = plat.transform.map_legs(m_exact)
        with _mapped_legs():
            res = forward_kinematics(base, platform, [_legs_arg(x) for x in l],
                                     method="auto", dps=dps)
        tier = res.tier
        m = list(m_float) if tier == "fast" else m_exact
        poses = [_pose66(plat, *_pose_arrays(pose, tier), m, tier, dps, pose)
                 for pose in res.poses]
        worst = max((p.max_leg_error for p in poses), default=0.0)
        return FK66Result(plat, l_sq, l, res, tuple(poses), worst)
    if method == "fast":
        # float64, or the exact map where float64 cannot prove the sign of an l^2
        from .leg_map_rounding import map_legs_fast
        l_sq, l, rho, _ = map_legs_fast(plat.transform, m_legs, "m_legs", m_float=m_float)
        with _mapped_legs():
            res = _fast_octahedral(base, platform, [float(x) for x in l], rho)
        m = list(m_float)
        poses = [_pose66(plat, *_pose_arrays(pose, "fast"), m, "fast", dps, pose)
                 for pose in res.poses]
        worst = max((p.max_leg_error for p in poses), default=0.0)
        return FK66Result(plat, l_sq, l, res, tuple(poses), worst)
    l_sq, l = plat.transform.map_legs(m_exact)
    if method == "certified":
        _check_certifiable(plat.transform, l_sq)
    legs = [_legs_arg(x) for x in l]
    m = m_exact
    kwargs = {"method": method}
    if dps is not None:
        kwargs["dps"] = dps
    with _mapped_legs():
        res = forward_kinematics(base, platform, legs, **kwargs)
    poses = []
    for pose in res.poses:
        R, t = _pose_arrays(pose, method)
        poses.append(_pose66(plat, R, t, m, method, dps, pose))
    worst = max((p.max_leg_error for p in poses), default=0.0)
    return FK66Result(plat, l_sq, l, res, tuple(poses), worst)


def _fast_octahedral(base, platform, legs, rho):
    r"""The octahedral fast tier on l-legs mapped in float64 (eq. (8)), its proof
    (:mod:`distkin.octahedral.descartes`) run with the squared lengths' relative error
    bound :math:`\eta` widened by :math:`2\rho` (:meth:`DeltaTransform.map_error_float`):
    its ``trusted`` and "proved" radii then cover the exact 6-6 problem, not only the
    rounded l-legs (QA J 1).  Where the rounding of the map is too large for a proof
    (near an architectural singularity, cond(A)·u) the proof fails, and the result warns
    (ConditioningWarning) like any fast answer it cannot vouch for."""

    from ..errors import ConditioningWarning
    from ..octahedral.batched import scan_single
    from ..octahedral.conditioning import eta_of
    from ..octahedral.forward import proved_single
    from ..octahedral.problem import float_single
    B, Q, L, k, _ = float_single(base, platform, legs)
    # the legs are rounded (from the map): eta_rounded covers them within 2u, plus rho
    eta = (eta_of(B, Q, L, True) + 2.0 * rho) * (1.0 + 2.0 ** -40)
    res, cond = proved_single(B, Q, L, k, eta, scan_single(B, Q, L))
    if not cond.trusted:
        _warn(f"fast tier: the real-root count is not proved ({cond.reason}); the "
                      f"float64 map of eq. (8) may move l^2 by {rho:.3g} relative "
                      "(cond(A)·u); use method='auto' or 'certified'", ConditioningWarning)
    return res


class _mapped_legs:
    """Context manager: an InputError of the octahedral solver about its ``legs`` is
    about the l-legs mapped from ``m_legs`` by eq. (8); re-anchor it there."""

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError) and (exc.field or "").startswith("legs"):
            exc.field = "m_legs"
            exc.message += " (in the l-legs mapped from the m-legs by eq. (8))"
            exc.args = (exc.one_line(),)
        return False


def _legs_arg(x):
    """An l-leg as the octahedral solver's input: an :class:`~distkin.exact.Exact`
    holding the exact value (a Fraction when rational, else the sympy expression, which
    may be long: the text form would exceed the parser's size bound)."""
    from ..exact import Exact
    if x.is_Rational:
        return Exact(Fraction(int(x.p), int(x.q)), str(x))
    return Exact(x, str(x) if len(str(x)) <= 60 else f"{float(x)!r} (exact algebraic)")


def _check_certifiable(tr: DeltaTransform, l_sq) -> None:
    r"""The certified octahedral tier needs rational squared l-legs; say why they are not.

    :math:`l^2 = \mathbf A^{-1}(m^2 + \mathbf b)` (eq. (8)) is rational when the m-legs
    squared, the offsets and the sides :math:`d_i` are; a side is irrational when its
    square (rational, from the points) is not the square of a rational, as with most
    float coordinates."""
    bad = [i for i, x in enumerate(l_sq) if not x.is_Rational]
    if not bad:
        return
    sides = [f"{spec.side}" for spec, d in zip(ROWS, tr.sides) if not d.is_Rational]
    why = (f"the sides {', '.join(sides)} are irrational (square roots of non-square "
           "rationals)" if sides else "the m-legs or the offsets are irrational")
    i = bad[0]
    raise InputError(f"expected rational squared l-legs for the certified tier, got "
                     f"{len(bad)} irrational one(s), l{i + 1}^2 = {float(l_sq[i]):.10g} "
                     f"(exact algebraic) after eq. (8), because {why}", field="m_legs",
                     hint="use method='precise', or 'auto' (it escalates to precise)")


def _pose_arrays(pose, method):
    """Rotation and translation of an octahedral pose: float64 (fast) or the tier-native
    values (mpf / arb) when the solver provides them."""
    native = getattr(pose, "native", None)
    if method != "fast" and native and "rotation" in native and "translation" in native:
        return (np.asarray(native["rotation"], dtype=object),
                np.asarray(native["translation"], dtype=object))
    return np.asarray(pose.rotation), np.asarray(pose.translation)


def _pose66(plat, R, t, m, method, dps, pose):
    if method == "fast":
        bj, pj = plat.joints("fast")
        Rf, tf = R.astype(float), t.astype(float)
        world = pj @ Rf.T + tf
        lens = np.linalg.norm(world - bj, axis=1)
        err = float(np.max(np.abs(lens - np.array([float(x) for x in m]))))
        return Pose66(Rf, tf, bj, world, err, pose)
    if method == "certified" and R.dtype == object and type(R.ravel()[0]).__name__ == "arb":
        return _pose66_arb(plat, R, t, m, pose)
    import mpmath
    with mpmath.workdps(dps or 30):
        bj, pj = plat.joints("precise")
        Rm = np.array([[_mpf(x) for x in row] for row in R], dtype=object)
        tm = np.array([_mpf(x) for x in t], dtype=object)
        world = np.array([Rm.dot(p) + tm for p in pj], dtype=object)
        errs = []
        for k in range(6):
            diff = world[k] - bj[k]
            lk = mpmath.sqrt(sum(x * x for x in diff))
            errs.append(abs(lk - mpmath.mpf(m[k].evalf(mpmath.mp.dps + 5))))
        err = float(max(errs))
        return Pose66(Rm, tm, bj, world, err, pose)


def _pose66_arb(plat, R, t, m, pose):
    """Certified tier: the residual is a rigorous upper bound from arb balls (the pose
    enclosures of the octahedral solver, the exact joints and m-legs as balls)."""
    import flint

    from ..exact import sympy_to_arb
    from ..exact_roots import working_precision
    from ..octahedral.certified import segment_error_bounds
    # the joints and legs at the pose balls' precision (the context's 53 bits left the
    # bound at ~2e-14 m for poses enclosed to ~1e-23: their joints' own balls)
    with working_precision(max(flint.ctx.prec, 128)):
        bj, pj = plat.joints("certified")
        world = np.array([R.dot(p) + t for p in pj], dtype=object)
        # rounded up to a float64 (float() of the ball's upper end rounded to nearest)
        err = segment_error_bounds(world, bj, [sympy_to_arb(x) for x in m])[0]
    return Pose66(R, t, bj, world, err, pose)


def _mpf(x):
    import mpmath
    if type(x).__name__ == "arb":
        return mpmath.mpf(x.mid().str(mpmath.mp.dps + 5, radius=False))
    if isinstance(x, Fraction):
        return mpmath.mpf(x.numerator) / x.denominator
    if type(x).__name__ == "fmpq":
        return mpmath.mpf(int(x.p)) / int(x.q)
    return mpmath.mpf(x)
