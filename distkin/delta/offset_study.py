r"""What the joint offsets of Fig. 2 (b)-(d) cost: the pose error of neglecting them and
the movement of the singular locus (Rojas, Borràs, Thomas, *The Octahedral Manipulator
Revisited*, ICRA 2012, Sec. I, IV-VI; approximations built by :mod:`.approximations`).

Pose error of neglecting the offsets (:func:`neglected_offset_error`): at a true pose
:math:`(R, t)` the 6-6 platform's legs :math:`m_k = |R q_k + t - b_k|` are taken as the
octahedral legs :math:`l_k`, the octic forward kinematics gives every assembly mode
(:func:`distkin.octahedral.forward_kinematics`), and the mode nearest the true pose is
compared with it: displacement of the platform centroid (length units) and rotation
angle of :math:`R^T R'` (rad).  First order, the error is the twist
:math:`\mathbf J^{-1}(m - l)` of eq. (5) (``first_order_*``).  For the Griffis-Duffy
modification the offsets can also be handled exactly: :math:`l^2 = \mathbf A^{-1}(m^2 +
\mathbf b)` (eq. (8), :func:`~.platform66.forward_kinematics66`), ``exact_*``.

The movement of the singular locus (:func:`singularity_shift`, eq. (6)) is measured in
:mod:`.singular_locus`; its names are re-exported here.

Tiers: pose errors ``auto`` (default: the fast tier when it proves its assembly roots,
else the certified one), ``fast`` (float64) and ``precise`` (mpmath legs, poses and
errors at ``dps``); in ``fast`` and ``precise`` an unproved solve gives
``trusted=False`` and a :class:`~distkin.errors.ConditioningWarning` (never a silent
wrong branch).  ``certified`` is refused: the squared 6-6 legs of a float pose are not
exact rationals of the octahedral problem the certified solver could prove.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import ConditioningWarning, warn as _warn
from ..exact import check_method, default_dps
from ..singularity.conditions import plucker_jacobian
from ..singularity.paths import pose_points
from .approximations import KINDS, approximation, octahedral_as_66
from .platform66 import Platform66, forward_kinematics66
from .exact_input import _as_sym, _base_platform
from .pose_input import check_platform66, check_poses, check_rotation, check_translation
from .singular_locus import (PoseLine, Shift, det_along, normal_line, platform_frame,
                             plucker_identity_residual, singularity_shift)

__all__ = [
    "PoseError",
    "platform_frame",
    "leg_lengths",
    "neglected_offset_error",
    "plucker_identity_residual",
    "PoseLine",
    "det_along",
    "normal_line",
    "Shift",
    "singularity_shift",
    "Comparison",
    "compare_approximations",
]


def leg_lengths(platform: Platform66, rotation, translation):
    """Leg lengths :math:`|R q_k + t - b_k|` (..., 6), length units (float, batched over
    poses ``rotation`` (..., 3, 3), ``translation`` (..., 3))."""
    b, q = platform.joints("fast")
    return np.linalg.norm(pose_points(q, np.asarray(rotation, float),
                                      np.asarray(translation, float)) - b, axis=-1)


def _angle(Rrel, kind="fast"):
    """Rotation angle (rad) of a rotation matrix: atan2 of the skew part and the trace
    (accurate near 0 and near pi)."""
    sk = [Rrel[2][1] - Rrel[1][2], Rrel[0][2] - Rrel[2][0], Rrel[1][0] - Rrel[0][1]]
    tr = Rrel[0][0] + Rrel[1][1] + Rrel[2][2]
    if kind == "precise":
        import mpmath
        return mpmath.atan2(mpmath.sqrt(sum(x * x for x in sk)) / 2, (tr - 1) / 2)
    return float(np.arctan2(0.5 * np.linalg.norm(sk), 0.5 * (tr - 1.0)))


@dataclass(frozen=True)
class PoseError:
    """Result of :func:`neglected_offset_error` at one pose.

    Attributes
    ----------
    position, orientation : float
        Error of neglecting the offsets: centroid displacement (length units) and
        rotation angle (rad) of the nearest octahedral assembly mode; ``nan`` when the
        octahedral manipulator cannot be assembled with the 6-6 legs.
    first_order_position, first_order_orientation : float
        The same from the linearisation :math:`\\mathbf J^{-1}(m-l)` (eq. (5)).
    exact_position, exact_orientation : float
        Griffis-Duffy only: error of the exact route through eq. (8) (else ``nan``).
    trusted : bool
        Every octahedral solve behind the errors (the neglected route and, for
        Griffis-Duffy, the Δ route) proved its assembly roots (fast tier), answered
        in the certified tier, or (precise) did not warn that its count may be wrong.
        False: the errors may measure the distance to another branch; a
        ConditioningWarning was issued.
    leg_change : float
        :math:`\\max_k |m_k - l_k|` (length units).
    """

    position: float
    orientation: float
    first_order_position: float
    first_order_orientation: float
    exact_position: float = float("nan")
    exact_orientation: float = float("nan")
    trusted: bool = True
    leg_change: float = 0.0


def _nearest(poses, R, t, c, L, kind):
    """(position error, angle) of the pose in ``poses`` ((R', t') pairs) nearest (R, t)."""
    best = (float("inf"), float("nan"), float("nan"))
    for Rp, tp in poses:
        if kind == "precise":
            dp = Rp.dot(c) + tp - (R.dot(c) + t)
            import mpmath
            pos = mpmath.sqrt(sum(x * x for x in dp))
            ang = _angle(R.T.dot(Rp), "precise")
            pos, ang = float(pos), float(ang)
        else:
            pos = float(np.linalg.norm(Rp @ c + tp - (R @ c + t)))
            ang = _angle(R.T @ Rp)
        dist = np.hypot(pos, L * ang)
        if dist < best[0]:
            best = (dist, pos, ang)
    return best[1], best[2]


def _mpf_fraction(x):
    man, exp = x.man_exp
    return Fraction(int(man) * 2 ** exp) if exp >= 0 else Fraction(int(man), 2 ** -exp)


def neglected_offset_error(octahedral, platform: Platform66, rotation, translation, *,
                           method: str = "auto", dps: int | None = None) -> PoseError:
    r"""The pose error of treating the 6-6 platform's legs as octahedral legs.

    Rojas et al., Sec. I ("if the offsets are neglected ... errors arise"): the legs
    :math:`m_k` of ``platform`` at the true pose are given to the octahedral forward
    kinematics (Sec. III, eq. (3)); the assembly mode nearest the true pose (distance
    :math:`\sqrt{|\Delta c|^2 + L^2\theta^2}`, :func:`platform_frame`) is the answer.
    For a Griffis-Duffy platform (``platform.transform`` set) the exact route of
    eq. (8) is measured as well.

    The answer is only as good as the list of assembly modes: a mode the solver misses
    (near the symmetric poses of the Griffis-Duffy example, for instance, the fast
    tier's octic has clustered roots) makes the nearest *found* mode another branch,
    and the "error" then is the distance between branches (QA: 3.4 instead of 0.048).
    Hence the default ``auto``, which keeps the fast answer only when the fast tier
    proves its real-root count and otherwise solves again in the certified tier.

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
    platform : Platform66
        An approximation of ``octahedral`` (:mod:`.approximations`).
    rotation : (3, 3), translation : (3,)
        The true pose (platform frame -> base frame; length units).  The rotation must
        be orthonormal within :data:`~.pose_input.ROTATION_TOL` with determinant +1.
    method : {"auto", "fast", "precise"}
        Tier of the octahedral solves.  ``auto`` (default): fast when proved, else
        certified (:mod:`distkin.octahedral.auto`).  ``fast``: float64 only.
        ``precise``: legs, poses and errors in mpmath at ``dps`` digits (default 30).
        ``certified`` is refused (module docstring).  In every tier, a solve that is
        not proved (the fast tier's real-root count, or a precise solve that warns
        its count may be wrong) gives ``trusted=False`` *and* one
        :class:`~distkin.errors.ConditioningWarning`: its errors may be those of
        another assembly mode.  ``auto`` does not leave one unproved.

    Returns
    -------
    PoseError

    Raises
    ------
    InputError
        A rotation that is not one (wrong shape, NaN, not orthonormal, a reflection), a
        translation that is not a finite 3-vector, a platform that is not a
        :class:`Platform66`, an unknown method.

    Warns
    -----
    ConditioningWarning
        An octahedral solve (or the Δ route's) was not proved (``trusted`` is False).
    """
    check_method(method, allowed=("fast", "auto", "precise"))
    R, t = check_rotation(rotation), check_translation(translation)
    err, doubt = _neglected(octahedral, check_platform66(platform), R, t, method, dps)
    if doubt:
        _warn(_doubt_message(err, doubt, method), ConditioningWarning)
    return err


def _doubt_message(err, doubt, method):
    exact = "" if np.isnan(err.exact_position) else f", Δ route {err.exact_position:.4g}"
    return (f"{method} tier: {doubt}, so the nearest assembly mode found may be another "
            f"branch (position error {err.position:.4g}, first-order estimate "
            f"{err.first_order_position:.4g}{exact}); PoseError.trusted is False; use "
            "method='auto' (the default)")


def _neglected(octahedral, platform, R, t, method, dps):
    """(PoseError, doubt): doubt names the unproved solves ('' when none)."""
    from ..octahedral import forward_kinematics
    base, plat = _base_platform(octahedral)
    c, L = platform_frame(octahedral)
    oct66 = octahedral_as_66(octahedral)
    m = leg_lengths(platform, R, t)
    l0 = leg_lengths(oct66, R, t)
    # first order: J (v, Omega) = m - l, J of eq. (5) about the platform centroid
    ob, oq = oct66.joints("fast")
    J = plucker_jacobian(ob, pose_points(oq, R, t), reference=R @ c + t)
    _check_regular_pose(J, t)
    tw = np.linalg.solve(J, m - l0)
    fo_pos, fo_ang = float(np.linalg.norm(tw[:3])), float(np.linalg.norm(tw[3:]))
    if method == "precise":
        import mpmath
        with mpmath.workdps(default_dps(dps)):
            mp = mpmath.mpf
            Rm = np.array([[mp(float(x)) for x in row] for row in R], dtype=object)
            tm = np.array([mp(float(x)) for x in t], dtype=object)
            cm = np.array([mp(float(x)) for x in c], dtype=object)
            b, q = platform.joints("precise")
            legs = [mpmath.sqrt(sum(x * x for x in (Rm.dot(q[k]) + tm - b[k])))
                    for k in range(6)]
            exact_legs = [_mpf_fraction(x) for x in legs]
            res, why = _solve(forward_kinematics, base, plat, exact_legs, method="precise",
                              dps=dps)
            poses = [(np.asarray(p.native["rotation"], dtype=object),
                      np.asarray(p.native["translation"], dtype=object)) for p in res.poses]
            pos, ang = _nearest(poses, Rm, tm, cm, L, "precise")
            ex = _exact_route(octahedral, platform, exact_legs, "precise", dps, Rm, tm, cm, L)
    else:
        res, why = _solve(forward_kinematics, base, plat, [float(x) for x in m],
                          method=method)
        pos, ang = _nearest([(p.rotation, p.translation) for p in res.poses], R, t, c, L,
                            "fast")
        ex = _exact_route(octahedral, platform, [float(x) for x in m], method, dps, R, t, c, L)
    doubts = [f"{what} is not proved ({w})" for what, w in
              (("the octahedral solve", why), ("the Δ route's octahedral solve", ex[2]))
              if w]
    err = PoseError(pos, ang, fo_pos, fo_ang, ex[0], ex[1], not doubts,
                    float(np.max(np.abs(m - l0))))
    return err, " and ".join(doubts)


#: sigma_min / sigma_max of the Plücker Jacobian below which the true pose is taken as
#: singular: the first-order estimate J^-1 (m - l) would be rounding noise times 1/that
SINGULAR_RCOND = 1e-10


def _check_regular_pose(J, t):
    r"""Refuse a true pose at (or numerically at) a singularity of the octahedral
    manipulator: the first-order error :math:`J^{-1}(m - l)` (eq. (5)) does not exist
    there, and the nearest assembly mode is not defined (QA J 7: numpy's LinAlgError, or
    1e14 "errors" with trusted=True).  :math:`\sigma_{\min}/\sigma_{\max}` of the
    Plücker Jacobian (dimensionless rows; moments in length units) below
    :data:`SINGULAR_RCOND` raises :class:`~distkin.errors.SingularConfigurationError`."""
    from ..errors import SingularConfigurationError
    sv = np.linalg.svd(J, compute_uv=False)
    rcond = float(sv[-1] / sv[0]) if sv[0] > 0 and np.all(np.isfinite(sv)) else 0.0
    if not rcond >= SINGULAR_RCOND:
        raise SingularConfigurationError(
            f"expected a true pose away from the singularities of the octahedral "
            f"manipulator (sigma_min/sigma_max of its Plücker Jacobian >= "
            f"{SINGULAR_RCOND:g}), got {rcond:.3g} at translation "
            f"{[round(float(x), 9) for x in t]} (length units): the first-order error "
            "and the nearest assembly mode are not defined there", field="rotation",
            hint="move the pose off the singularity (e.g. a platform parallel to the base "
                 "with the same orientation, or the 90-degree twist, is singular)")


def _solve(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` (an octahedral or Δ forward kinematics) with its
    ConditioningWarnings held back: (result, why), ``why`` the fast tier's reason when
    its real-root count is not proved, else what the solver warned ('' when nothing).
    The caller reports it once, with what it means for the pose error."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ConditioningWarning)
        res = fn(*args, **kwargs)
    said = []
    for w in caught:
        if issubclass(w.category, ConditioningWarning):
            said.append(str(w.message))
        else:                                             # not ours to hold back
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    octa = getattr(res, "octahedral", res)
    cond = getattr(octa, "conditioning", None)
    if getattr(octa, "tier", None) == "fast" and cond is not None and not cond.trusted:
        return res, cond.reason or "the real-root count"
    return res, "; ".join(said)


def _float_pose(R, t):
    """Float64 (R, t) of a pose in any tier (arb balls by their midpoints)."""
    f = lambda x: float(x.mid()) if type(x).__name__ == "arb" else float(x)  # noqa: E731
    return (np.array([[f(x) for x in row] for row in R]), np.array([f(x) for x in t]))


def _exact_route(octahedral, platform, legs, method, dps, R, t, c, L):
    """(position, angle, doubt) of the Δ route (eq. (8)); nan without a transform."""
    if platform.transform is None:
        return float("nan"), float("nan"), ""
    res, why = _solve(forward_kinematics66, octahedral, list(platform.transform.offsets),
                      legs, method=method,
                      dps=dps if method in ("precise", "auto") else None)
    if method == "precise":
        return (*_nearest([(p.rotation, p.translation) for p in res.poses], R, t, c, L,
                          "precise"), why)
    poses = [_float_pose(p.rotation, p.translation) for p in res.poses]
    return (*_nearest(poses, R, t, c, L, "fast"), why)


# ------------------------------------------------------------------ the comparison

@dataclass(frozen=True)
class Comparison:
    """Result of :func:`compare_approximations`.

    Attributes
    ----------
    kinds : tuple of str
    deltas : array (nd,)
        Offsets, length units.
    base_size : float
        Longest base edge (length units); ``deltas / base_size`` is the relative offset.
    position, orientation : dict kind -> array (nd, np)
        Neglected-offset errors (length units, rad) at each offset and pose.
    first_order_position, first_order_orientation : dict kind -> array (nd, np)
    exact_position, exact_orientation : arrays (nd, np)
        Griffis-Duffy, exact route of eq. (8) (``nan`` when it is not among ``kinds``).
    untrusted : int
        Pose errors (pose, offset, kind) with ``trusted=False``: resting on an
        octahedral solve that was not proved (0 with ``auto``).
    shift : dict kind -> array (nd, nz)
        Singular-locus movement (length units) for every octahedral zero on ``lines``.
    identity_residual : array (nd,)
        Worst relative residual of :math:`\\hat J_{66} = A\\hat J` over the poses.
    method : str
    """

    kinds: tuple
    deltas: np.ndarray
    base_size: float
    position: dict
    orientation: dict
    first_order_position: dict
    first_order_orientation: dict
    exact_position: np.ndarray
    exact_orientation: np.ndarray
    untrusted: int
    shift: dict
    identity_residual: np.ndarray
    method: str


def compare_approximations(octahedral, rotations, translations, deltas, *, kinds=KINDS,
                           lines=(), dps: int | None = None,
                           samples: int = 400, progress=None, method: str = "auto"
                           ) -> Comparison:
    """Neglected-offset pose errors and singularity movement of every approximation.

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
    rotations : (np, 3, 3); translations : (np, 3)
        True poses of the octahedral manipulator (length units).
    deltas : (nd,) offsets, length units (numbers or exact strings).
    kinds : subset of :data:`~.approximations.KINDS`
    lines : sequence of :class:`PoseLine` for the singular locus.
    method : {"auto", "fast", "precise"}
        Pose errors as :func:`neglected_offset_error` (default ``auto``); singularity
        shifts in float (``fast``) whatever the pose tier.  Unproved solves
        (``fast``, ``precise``) are counted in ``untrusted`` and, when there are
        any, reported by one :class:`~distkin.errors.ConditioningWarning` for the
        whole comparison.
    progress : callable(str) or None
        Called once per offset (a progress line for long runs).

    Returns
    -------
    Comparison
    """
    check_method(method, allowed=("fast", "auto", "precise"))
    Rs, ts = check_poses(rotations, translations)
    b = octahedral_as_66(octahedral).joints("fast")[0]
    base_size = float(max(np.linalg.norm(b[i] - b[j]) for i in range(6) for j in range(6)))
    nd, npose = len(deltas), len(Rs)
    arr = lambda: {k: np.full((nd, npose), np.nan) for k in kinds}  # noqa: E731
    pos, ang, fpos, fang = arr(), arr(), arr(), arr()
    epos, eang = np.full((nd, npose), np.nan), np.full((nd, npose), np.nan)
    shift = {k: [] for k in kinds}
    resid = np.full(nd, np.nan)
    untrusted = 0
    for i, d in enumerate(deltas):
        if progress is not None:
            progress(f"offset {i + 1}/{nd}: delta = {float(_as_sym(d, 'deltas')):.4g} length units")
        plats = {k: approximation(octahedral, k, d) for k in kinds}
        for j in range(npose):
            for k, plat in plats.items():
                e = _neglected(octahedral, check_platform66(plat), Rs[j], ts[j], method,
                               dps)[0]
                pos[k][i, j], ang[k][i, j] = e.position, e.orientation
                fpos[k][i, j], fang[k][i, j] = e.first_order_position, e.first_order_orientation
                untrusted += not e.trusted
                if plat.transform is not None:
                    epos[i, j], eang[i, j] = e.exact_position, e.exact_orientation
        if "griffis_duffy" in plats:
            resid[i] = max(plucker_identity_residual(octahedral, plats["griffis_duffy"],
                                                     Rs[j], ts[j]) for j in range(npose))
        row = {k: [] for k in kinds}
        for line in lines:
            sh = singularity_shift(octahedral, plats, line, samples=samples)
            for k in kinds:
                row[k].extend(sh.shift[k])
        for k in kinds:
            shift[k].append(row[k])
    if untrusted:
        _warn(f"{method} tier: {untrusted} of {nd * npose * len(kinds)} "
                      "neglected-offset errors rest on octahedral solves that were not "
                      "proved and may measure the distance to another branch "
                      "(Comparison.untrusted); use method='auto' (the default)",
                      ConditioningWarning)
    return Comparison(tuple(kinds), np.array([float(_as_sym(d, "deltas")) for d in deltas]),
                      base_size, pos, ang, fpos, fang, epos, eang, untrusted,
                      {k: np.array(v, dtype=float) for k, v in shift.items()}, resid, method)
