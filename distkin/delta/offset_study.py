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

Singularities (:func:`singularity_shift`): :math:`\det\mathbf J` of eq. (5) (normalised
Plücker coordinates, moment columns divided by the platform circumradius L,
dimensionless) along straight lines in pose space (:class:`PoseLine`); each zero of the
octahedral one is matched with the nearest zero of each approximation, and the shift is
measured as pose-space distance :math:`\sqrt{|\Delta t|^2 + L^2|\Delta w|^2}` (length
units).  For Fig. 2(d), :math:`\hat{\mathbf J}_{66} = \mathbf A\,\hat{\mathbf J}`
exactly (eq. (6) with the unnormalised matrices), :func:`plucker_identity_residual`.

Tiers: pose errors ``fast``, ``auto`` (escalation of the octahedral solver) and
``precise`` (mpmath legs, poses and errors at ``dps``); ``certified`` is refused: the
squared 6-6 legs of a float pose are not exact rationals of the octahedral problem the
certified solver could prove.  Singularity shifts ``fast`` (brentq) and ``certified``
(each zero bracketed by arb-certified opposite signs of det J, :func:`~distkin.
singularity.paths.certify_crossing`; the shift is then a certified interval).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import ConditioningWarning, InputError
from ..exact import check_method, default_dps
from ..singularity.conditions import jacobian_det, plucker_jacobian
from ..singularity.paths import (certify_crossing, path_crossings, pose_points,
                                 rotation_from_vector)
from .approximations import KINDS, approximation, octahedral_as_66
from .platform66 import Platform66, forward_kinematics66
from .exact_input import _as_sym, _base_platform

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


def platform_frame(octahedral):
    """``(centroid (3,), circumradius L)`` of the platform triangle P4 P5 P6 in its own
    frame (float, length units): the reference point of the position error and the
    length converting rotations to pose-space distance."""
    q = octahedral_as_66(octahedral).joints("fast")[1]
    c = q.mean(axis=0)
    return c, float(np.max(np.linalg.norm(q - c, axis=1)))


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
        The octahedral solver proved its assembly roots (fast tier) or answered in a
        higher tier; False means an unproved fast answer.
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
                           method: str = "fast", dps: int | None = None) -> PoseError:
    r"""The pose error of treating the 6-6 platform's legs as octahedral legs.

    Rojas et al., Sec. I ("if the offsets are neglected ... errors arise"): the legs
    :math:`m_k` of ``platform`` at the true pose are given to the octahedral forward
    kinematics (Sec. III, eq. (3)); the assembly mode nearest the true pose (distance
    :math:`\sqrt{|\Delta c|^2 + L^2\theta^2}`, :func:`platform_frame`) is the answer.
    For a Griffis-Duffy platform (``platform.transform`` set) the exact route of
    eq. (8) is measured as well.

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
    platform : Platform66
        An approximation of ``octahedral`` (:mod:`.approximations`).
    rotation : (3, 3), translation : (3,)
        The true pose (platform frame -> base frame; length units).
    method : {"fast", "auto", "precise"}
        Tier of the octahedral solves; ``precise`` computes legs, poses and errors in
        mpmath at ``dps`` digits (default 30).  ``certified`` is refused (module
        docstring).

    Returns
    -------
    PoseError
    """
    check_method(method, allowed=("fast", "auto", "precise"))
    from ..octahedral import forward_kinematics
    base, plat = _base_platform(octahedral)
    R = np.asarray(rotation, dtype=float)
    t = np.asarray(translation, dtype=float)
    c, L = platform_frame(octahedral)
    oct66 = octahedral_as_66(octahedral)
    m = leg_lengths(platform, R, t)
    l0 = leg_lengths(oct66, R, t)
    # first order: J (v, Omega) = m - l, J of eq. (5) about the platform centroid
    ob, oq = oct66.joints("fast")
    J = plucker_jacobian(ob, pose_points(oq, R, t), reference=R @ c + t)
    tw = np.linalg.solve(J, m - l0)
    fo_pos, fo_ang = float(np.linalg.norm(tw[:3])), float(np.linalg.norm(tw[3:]))
    kind = "precise" if method == "precise" else "fast"
    if kind == "precise":
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
            res = forward_kinematics(base, plat, exact_legs, method="precise", dps=dps)
            poses = [(np.asarray(p.native["rotation"], dtype=object),
                      np.asarray(p.native["translation"], dtype=object)) for p in res.poses]
            pos, ang = _nearest(poses, Rm, tm, cm, L, "precise")
            ex = _exact_route(octahedral, platform, exact_legs, "precise", dps, Rm, tm, cm, L)
        trusted = True
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConditioningWarning)
            res = forward_kinematics(base, plat, [float(x) for x in m], method=method)
        cond = getattr(res, "conditioning", None)
        trusted = res.tier != "fast" or cond is None or bool(cond.trusted)
        pos, ang = _nearest([(p.rotation, p.translation) for p in res.poses], R, t, c, L,
                            "fast")
        ex = _exact_route(octahedral, platform, [float(x) for x in m], method, dps, R, t, c, L)
    return PoseError(pos, ang, fo_pos, fo_ang, ex[0], ex[1], trusted,
                     float(np.max(np.abs(m - l0))))


def _exact_route(octahedral, platform, legs, method, dps, R, t, c, L):
    if platform.transform is None:
        return float("nan"), float("nan")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConditioningWarning)
        res = forward_kinematics66(octahedral, list(platform.transform.offsets), legs,
                                   method=method, dps=dps)
    kind = "precise" if method == "precise" else "fast"
    return _nearest([(p.rotation, p.translation) for p in res.poses], R, t, c, L, kind)


def plucker_identity_residual(octahedral, platform: Platform66, rotation, translation):
    r"""Eq. (6) as a matrix identity: :math:`\hat{\mathbf J}_{66} = \mathbf A\hat{\mathbf J}`
    (unnormalised Plücker matrices, :math:`\operatorname{diag}(m)\dot m = \mathbf A
    \operatorname{diag}(l)\dot l`).  Returns :math:`\max|\hat{\mathbf J}_{66} -
    \mathbf A\hat{\mathbf J}| / \max|\hat{\mathbf J}_{66}|` (float, dimensionless) for
    a Griffis-Duffy platform at a pose."""
    if platform.transform is None:
        raise InputError("expected a Griffis-Duffy (Δ) platform with a transform, got one "
                         "without", field="platform")
    A = np.array(platform.transform.A.tolist(), dtype=float)
    R, t = np.asarray(rotation, float), np.asarray(translation, float)
    mats = []
    for plat in (platform, octahedral_as_66(octahedral)):
        b, q = plat.joints("fast")
        mats.append(plucker_jacobian(b, pose_points(q, R, t), normalised=False))
    return float(np.max(np.abs(mats[0] - A @ mats[1])) / np.max(np.abs(mats[0])))


# ------------------------------------------------------------------ singular locus

@dataclass(frozen=True)
class PoseLine:
    r"""A line in pose space through :math:`(R_0, t_0)`: for :math:`s\in[0,1]`,
    :math:`u = 2s-1`, the platform is turned by :math:`\operatorname{Rot}(u\,w)` about
    the point ``centre`` (base frame) and shifted by :math:`u\,x`:
    :math:`R = \operatorname{Rot}(uw)R_0`,
    :math:`t = \operatorname{Rot}(uw)(t_0 - c) + c + u\,x`.

    Attributes
    ----------
    rotation : (3, 3); translation : (3,) length units
    dx : (3,) length units; dw : (3,) rad (rotation vector, base frame)
    centre : (3,) length units or None
        The fixed point of the rotation; None (default): the platform frame's origin
        :math:`t_0`, so that :math:`t = t_0 + u\,x` as in
        :func:`~distkin.singularity.paths.nearest_singularity`.
    """

    rotation: np.ndarray
    translation: np.ndarray
    dx: np.ndarray
    dw: np.ndarray
    centre: tuple | None = None

    def length(self, L: float) -> float:
        """Pose-space length of the line, :math:`2\\sqrt{|x|^2 + L^2|w|^2}` (length units)."""
        return 2.0 * float(np.hypot(np.linalg.norm(self.dx), L * np.linalg.norm(self.dw)))

    def at(self, s):
        """Float poses at ``s`` (n,): R (n, 3, 3), t (n, 3)."""
        u = 2.0 * np.asarray(s, dtype=float)[:, None] - 1.0
        Rw = rotation_from_vector(u * np.asarray(self.dw, float))
        c = np.asarray(self.translation if self.centre is None else self.centre, float)
        t = np.einsum("nij,j->ni", Rw, np.asarray(self.translation, float) - c) + c
        return Rw @ np.asarray(self.rotation, float), t + u * np.asarray(self.dx, float)

    def at_certified(self, s):
        """arb pose at a rational ``s`` (fmpq): R (3, 3), t (3,) as arb balls (the float
        data taken as exact binary values)."""
        import flint
        u = 2 * flint.arb(s) - 1
        a = lambda v: np.array([flint.arb(float(x)) for x in v], dtype=object)  # noqa: E731
        Rw = rotation_from_vector(u * a(self.dw), method="certified")
        R0 = np.array([a(r) for r in np.asarray(self.rotation, float)], dtype=object)
        c = a(self.translation if self.centre is None else self.centre)
        t = Rw.dot(a(self.translation) - c) + c + u * a(self.dx)
        return Rw.dot(R0), t


def det_along(platform: Platform66, rotation, translation, length_scale: float, *,
              method: str = "fast"):
    r""":math:`\det\mathbf J` of eq. (5) for ``platform`` at poses, moment columns divided
    by ``length_scale`` (dimensionless).  ``fast``: batched (..., 3, 3) / (..., 3) float;
    ``certified``: one arb pose, an arb ball."""
    b, q = platform.joints("certified" if method == "certified" else "fast")
    if method == "certified":
        world = pose_points(q, rotation, translation)
        return jacobian_det(b, world, length_scale=length_scale, method="certified")
    world = pose_points(q, np.asarray(rotation, float), np.asarray(translation, float))
    return jacobian_det(np.broadcast_to(b, world.shape), world, length_scale=length_scale)


def normal_line(octahedral, rotation, translation, half_length: float) -> PoseLine:
    r"""The line through the octahedral singular pose nearest to a pose, along the
    normal of the singular locus there, reaching ``half_length`` (pose-space distance,
    length units) on each side.

    The singular pose :math:`(R_s, t_s)` is found by
    :func:`~distkin.singularity.paths.nearest_singularity` on the octahedral
    :math:`\det\mathbf J` (eq. (5)); the normal is the gradient of
    :math:`g(x, Lw) = \det\mathbf J(\operatorname{Rot}(w)R_s,\; t_s + x)` by central
    differences, L the platform circumradius.

    Raises
    ------
    InputError
        The local search found no singular pose.
    """
    from ..singularity.paths import nearest_singularity
    _, L = platform_frame(octahedral)
    oct66 = octahedral_as_66(octahedral)
    f = lambda R, t: det_along(oct66, R, t, L)  # noqa: E731
    ns = nearest_singularity(f, np.asarray(rotation, float), np.asarray(translation, float), L)
    if not ns.converged:
        raise InputError("expected a singular pose near the given pose, the local search "
                         "found none", field="rotation")
    h = 1e-6 * L
    Y = np.concatenate([np.eye(6), -np.eye(6)]) * h
    vals = f(rotation_from_vector(Y[:, 3:] / L) @ ns.rotation, ns.translation + Y[:, :3])
    n = (vals[:6] - vals[6:]) / (2 * h)
    n = n / np.linalg.norm(n) * half_length
    return PoseLine(ns.rotation, ns.translation, n[:3], n[3:] / L)


@dataclass(frozen=True)
class Shift:
    """Result of :func:`singularity_shift` for one line.

    Attributes
    ----------
    octahedral : tuple of float
        Zeros of the octahedral det J on the line (parameter s in [0, 1]).
    zeros : dict kind -> tuple of float
        Zeros of each approximation's det J.
    shift : dict kind -> array (len(octahedral),)
        Pose-space distance (length units) from each octahedral zero to the nearest
        zero of the approximation; ``nan`` when it has none on the line.
    bounds : dict kind -> list of (lo, hi) or None
        ``certified``: a certified interval (length units) containing each shift.
    """

    octahedral: tuple
    zeros: dict
    shift: dict
    bounds: dict | None = None


def singularity_shift(octahedral, platforms: dict, line: PoseLine, *, samples: int = 400,
                      method: str = "fast") -> Shift:
    """Zeros of det J (eq. (5)) along ``line`` for the octahedral manipulator and each
    approximation in ``platforms`` (kind -> Platform66), and how far they moved.

    Parameters
    ----------
    method : {"fast", "certified"}
        ``certified`` brackets every zero by rational parameters at which arb proves
        opposite signs of det J (:func:`~distkin.singularity.paths.certify_crossing`,
        raising :class:`~distkin.errors.UncertifiedError` otherwise) and returns
        certified shift intervals in ``bounds``.
    """
    check_method(method, allowed=("fast", "certified"))
    _, L = platform_frame(octahedral)
    span = line.length(L)
    allp = {"octahedral": octahedral_as_66(octahedral), **platforms}
    zeros, brackets = {}, {}
    for name, plat in allp.items():
        f = lambda s, p=plat: det_along(p, *line.at(s), L)  # noqa: E731
        zeros[name] = tuple(path_crossings(f, samples)[0])
        if method == "certified":
            g = lambda s, p=plat: det_along(p, *line.at_certified(s), L,  # noqa: E731
                                            method="certified")
            brackets[name] = [certify_crossing(g, z).bracket for z in zeros[name]]
    o = np.array(zeros["octahedral"])
    shift, bounds = {}, ({} if method == "certified" else None)
    for name in platforms:
        z = np.array(zeros[name])
        if z.size == 0:
            shift[name] = np.full(o.size, np.nan)
            if bounds is not None:
                bounds[name] = [None] * o.size
            continue
        idx = [int(np.argmin(np.abs(z - s))) for s in o]
        shift[name] = np.array([abs(z[j] - s) * span for j, s in zip(idx, o)])
        if bounds is not None:
            bounds[name] = [_interval_gap(brackets["octahedral"][i], brackets[name][j], span)
                            for i, j in enumerate(idx)]
    return Shift(zeros["octahedral"], {k: zeros[k] for k in platforms}, shift, bounds)


def _interval_gap(a, b, span):
    """Smallest and largest distance between points of two brackets, times ``span``."""
    lo = max(0.0, float(max(a[0], b[0]) - min(a[1], b[1])))
    hi = float(max(a[1], b[1]) - min(a[0], b[0]))
    return lo * span, hi * span


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
        Octahedral solves the fast tier could not prove.
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
                           lines=(), method: str = "fast", dps: int | None = None,
                           samples: int = 400, progress=None) -> Comparison:
    """Neglected-offset pose errors and singularity movement of every approximation.

    Parameters
    ----------
    octahedral : Octahedral or (base, platform)
    rotations : (np, 3, 3); translations : (np, 3)
        True poses of the octahedral manipulator (length units).
    deltas : (nd,) offsets, length units (numbers or exact strings).
    kinds : subset of :data:`~.approximations.KINDS`
    lines : sequence of :class:`PoseLine` for the singular locus.
    method : {"fast", "auto", "precise"}
        Pose errors as :func:`neglected_offset_error`; singularity shifts in float
        (``fast``) whatever the pose tier.
    progress : callable(str) or None
        Called once per offset (a progress line for long runs).

    Returns
    -------
    Comparison
    """
    check_method(method, allowed=("fast", "auto", "precise"))
    Rs, ts = np.asarray(rotations, float), np.asarray(translations, float)
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
                e = neglected_offset_error(octahedral, plat, Rs[j], ts[j], method=method,
                                           dps=dps)
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
    return Comparison(tuple(kinds), np.array([float(_as_sym(d, "deltas")) for d in deltas]),
                      base_size, pos, ang, fpos, fang, epos, eang, untrusted,
                      {k: np.array(v, dtype=float) for k, v in shift.items()}, resid, method)
