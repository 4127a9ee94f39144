r"""Where the offsets of Fig. 2 (b)-(d) move the singular locus (Rojas, Borràs, Thomas,
*The Octahedral Manipulator Revisited*, ICRA 2012, Sec. IV, eqs. (5), (6), and Sec.
V-VI; the approximations of :mod:`.approximations`, compared in :mod:`.offset_study`).

:math:`\det\mathbf J` of eq. (5) (normalised Plücker coordinates, moment columns divided
by the platform circumradius L, dimensionless) along straight lines in pose space
(:class:`PoseLine`); each zero of the octahedral one is matched with the nearest zero of
each approximation, and the shift is measured as pose-space distance
:math:`\sqrt{|\Delta t|^2 + L^2|\Delta w|^2}` (length units,
:func:`singularity_shift`).  For Fig. 2(d), :math:`\hat{\mathbf J}_{66} = \mathbf
A\,\hat{\mathbf J}` exactly (eq. (6) with the unnormalised matrices),
:func:`plucker_identity_residual`.

The zeros are the sign changes of det J on ``samples`` points, refined by Brent's
method, and the root pairs between two samples that a local minimum of |det J| reveals
(:func:`~distkin.singularity.paths.path_crossings` with ``refine``): a line that grazes
the locus crosses it twice within one sample interval.  Pairs that leave no such minimum
can still be missed, so the zeros found are a lower bound on those of the line.

Tiers: ``fast`` (brentq) and ``certified`` (each zero bracketed by arb-certified
opposite signs of det J, :func:`~distkin.singularity.paths.certify_crossing`; the shift
is then a certified interval).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..argcheck import positive_int, positive_number
from ..errors import InputError
from ..exact import check_method
from ..singularity.conditions import jacobian_det, plucker_jacobian
from ..singularity.paths import (certify_crossing, path_crossings, pose_points,
                                 rotation_from_vector)
from .approximations import octahedral_as_66
from .platform66 import Platform66
from .pose_input import check_platform66, check_rotation, check_translation

__all__ = [
    "platform_frame",
    "plucker_identity_residual",
    "PoseLine",
    "det_along",
    "normal_line",
    "Shift",
    "singularity_shift",
]


def platform_frame(octahedral):
    """``(centroid (3,), circumradius L)`` of the platform triangle P4 P5 P6 in its own
    frame (float, length units): the reference point of the position error and the
    length converting rotations to pose-space distance."""
    q = octahedral_as_66(octahedral).joints("fast")[1]
    c = q.mean(axis=0)
    return c, float(np.max(np.linalg.norm(q - c, axis=1)))


def plucker_identity_residual(octahedral, platform: Platform66, rotation, translation):
    r"""Eq. (6) as a matrix identity: :math:`\hat{\mathbf J}_{66} = \mathbf A\hat{\mathbf J}`
    (unnormalised Plücker matrices, :math:`\operatorname{diag}(m)\dot m = \mathbf A
    \operatorname{diag}(l)\dot l`).  Returns :math:`\max|\hat{\mathbf J}_{66} -
    \mathbf A\hat{\mathbf J}| / \max|\hat{\mathbf J}_{66}|` (float, dimensionless) for
    a Griffis-Duffy platform at a pose."""
    if check_platform66(platform).transform is None:
        raise InputError("expected a Griffis-Duffy (Δ) platform with a transform, got one "
                         "without", field="platform")
    A = np.array(platform.transform.A.tolist(), dtype=float)
    R, t = check_rotation(rotation), check_translation(translation)
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
    ``certified``: one arb pose, an arb ball.  Other tiers are refused
    (:class:`~distkin.errors.InputError` naming ``method``): ``precise`` computed in
    float64 here (QA); :func:`~distkin.singularity.conditions.jacobian_det` has it."""
    check_method(method, allowed=("fast", "certified"))
    b, q = check_platform66(platform).joints("certified" if method == "certified" else "fast")
    if method == "certified":
        world = pose_points(q, rotation, translation)
        return jacobian_det(b, world, length_scale=length_scale, method="certified")
    world = pose_points(q, np.asarray(rotation, float), np.asarray(translation, float))
    return jacobian_det(np.broadcast_to(b, world.shape), world, length_scale=length_scale,
                        warn=False)


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
        ``half_length`` not a positive finite number (named), a bad pose; the local
        search found no singular pose.
    """
    from ..singularity.paths import nearest_singularity
    half_length = positive_number(half_length, "half_length")
    _, L = platform_frame(octahedral)
    oct66 = octahedral_as_66(octahedral)
    f = lambda R, t: det_along(oct66, R, t, L)  # noqa: E731
    ns = nearest_singularity(f, check_rotation(rotation), check_translation(translation), L)
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
    platforms : mapping kind -> Platform66
        E.g. ``{"standard": standard_approximation(oc, 0.1)}``.
    line : PoseLine
        E.g. from :func:`normal_line`.
    samples : int
        Grid points on the line (>= 2).
    method : {"fast", "certified"}
        ``certified`` brackets every zero by rational parameters at which arb proves
        opposite signs of det J (:func:`~distkin.singularity.paths.certify_crossing`,
        raising :class:`~distkin.errors.UncertifiedError` otherwise) and returns
        certified shift intervals in ``bounds``.

    Raises
    ------
    InputError
        ``platforms`` not a mapping of names to Platform66, ``line`` not a PoseLine,
        ``samples`` not an integer >= 2, another ``method`` (each named).
    """
    check_method(method, allowed=("fast", "certified"))
    samples = positive_int(samples, "samples", minimum=2)
    if not isinstance(platforms, Mapping):
        raise InputError(f"expected a mapping of approximation names to Platform66, e.g. "
                         f"{{'standard': standard_approximation(oc, delta)}}, got "
                         f"{type(platforms).__name__}", field="platforms")
    for name, plat in platforms.items():
        if not isinstance(name, str):
            raise InputError(f"expected approximation names (strings) as keys, got "
                             f"{name!r}", field="platforms")
        check_platform66(plat, f"platforms[{name!r}]")
    if not isinstance(line, PoseLine):
        raise InputError(f"expected a PoseLine (e.g. from normal_line), got "
                         f"{type(line).__name__}", field="line")
    _, L = platform_frame(octahedral)
    span = line.length(L)
    allp = {"octahedral": octahedral_as_66(octahedral), **platforms}
    zeros, brackets = {}, {}
    for name, plat in allp.items():
        f = lambda s, p=plat: det_along(p, *line.at(s), L)  # noqa: E731
        zeros[name] = tuple(path_crossings(f, samples, refine=True)[0])
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
