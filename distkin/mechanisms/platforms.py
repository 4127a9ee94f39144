"""Prismatic leg mechanisms from the platforms of Rojas et al.: the octahedral
manipulator, a 6-6 platform (the Δ 6-6 platform of Sec. VI) and the offset
approximations of Fig. 2 (b)-(d), as :class:`~.kinematics.LegMechanism` tables of six
SPS (or UPS) legs, so that every analysis of the Octopod paper (capabilities with
prismatic force limits, GII, dexterous and certified workspace) runs on them.

The platforms of :mod:`distkin.delta` are unitless and their platform frame is the
octahedral one (origin at P4 in the Sec. VI example).  Here ``unit`` says what one of
their length units is in metres (our choice for a unitless example: say so), and
``origin`` moves the end-effector frame to a point of the platform (default: the mean of
the six platform joints, the centroid of the platform triangle for the octahedral
manipulator itself), so that rotations turn the platform about its centre; a platform
whose joints run the other way round than the base's is turned over (180 deg about x),
so that its symmetric home pose has zero rotation.  Leg ``k``
joins ``base_joints[k]`` and ``platform_joints[k]``; for the octahedral manipulator that
is :data:`~distkin.singularity.conditions.OCTAHEDRAL_LEGS` ``[k]`` (docs/design.md §3), so
its table has the octahedral topology and its FK comes from the exact octic.

>>> from distkin.mechanisms.platforms import platform_mechanism
>>> base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
>>> plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
>>> m = platform_mechanism((base, plat), unit=0.01, height=17)
>>> m.L, m.leg_table[0].type, m.octahedral() is not None
(6, 'SPS', True)
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .kinematics import LegMechanism

__all__ = ["platform_mechanism", "symmetric_home"]


def _platform66(platform):
    """A :class:`~distkin.delta.platform66.Platform66` (as given) from a Platform66 or an
    octahedral manipulator (an ``Octahedral`` or ``(base, platform)``)."""
    from ..delta.platform66 import Platform66
    if isinstance(platform, Platform66):
        return platform
    from ..delta.approximations import octahedral_as_66
    return octahedral_as_66(platform)


def _joints(platform):
    b, p = _platform66(platform).joints("fast")
    return np.array(b, dtype=float), np.array(p, dtype=float)


def _fit(b, p):
    """(rz, score): the rotation about z that best turns the platform joints' centroid
    directions onto the base joints' of the same legs (2-D Procrustes), and its fit."""
    gb = b - b.mean(axis=0)
    s = np.sum(p[:, 0] * gb[:, 1] - p[:, 1] * gb[:, 0])
    c = np.sum(p[:, 0] * gb[:, 0] + p[:, 1] * gb[:, 1])
    return float(np.arctan2(s, c)), float(np.hypot(s, c))


def _frame(b, p, origin):
    """Platform joints in the end-effector frame: moved to ``origin`` and, when the
    platform's joints run the other way round than the base's (the octahedral
    manipulator of Sec. VI: P4 P5 P6 anticlockwise, P1 P2 P3 clockwise seen from
    above; its symmetric pose has the platform turned over, rx = 180 deg), turned by
    180 deg about x, so that the symmetric pose has zero rotation."""
    p = p - origin
    flipped = p * np.array([1.0, -1.0, -1.0])
    return flipped if _fit(b, flipped)[1] > _fit(b, p)[1] + 1e-12 else p


def symmetric_home(platform, height: float, *, unit: float = 1.0, origin=None):
    """The home pose (m, rad) of :func:`platform_mechanism`: the end-effector origin
    above the centroid of the base joints at ``height`` (platform units), turned about
    z so that the platform joints' directions from their centre best match (least
    squares) the base joints' of the same legs; for the Sec. VI example the platform
    vertices lie above the midpoints of the base edges, zero rotation."""
    b, p = _joints(platform)
    o = np.mean(p, axis=0) if origin is None else np.asarray(origin, dtype=float)
    rz = _fit(b, _frame(b, p, o))[0]
    rz = 0.0 if abs(rz) < 1e-12 else rz
    cx, cy = b.mean(axis=0)[:2]
    return (float(cx) * unit, float(cy) * unit, float(height) * unit, 0.0, 0.0, rz)


def platform_mechanism(platform, *, unit: float = 1.0, home=None, height=None, origin=None,
                       stroke=None, force=None, leg_type: str = "SPS",
                       name: str = "platform66", mass: float = 1.0, inertia: float = 1e-3,
                       route: str = "generated") -> LegMechanism:
    """The six-leg prismatic mechanism of a 6-6 or octahedral platform (module docstring).

    Parameters
    ----------
    platform : Platform66, Octahedral or (base, platform)
        :func:`distkin.delta.equivalent_platform`, :func:`distkin.delta.approximation`,
        :func:`distkin.delta.octahedral_as_66` or an octahedral manipulator.
    unit : float
        Metres per length unit of ``platform`` (e.g. 0.01: its numbers are cm).
    home : 6 floats (m, rad), optional
        The home pose; default :func:`symmetric_home` at ``height`` (platform units).
    origin : 3 floats (platform units), optional
        The end-effector frame origin in the platform frame (default: the mean of the
        platform joints).
    stroke : (min, max) in platform units, optional
        Leg length range of every leg.
    force : float or (min, max), N, optional
        Actuator force limit of every leg.
    leg_type : "SPS" or "UPS"
    name, mass (kg), inertia (kg m^2), route
        As :class:`~.kinematics.LegMechanism`.
    """
    if not (isinstance(unit, (int, float)) and not isinstance(unit, bool) and unit > 0
            and np.isfinite(unit)):
        raise InputError(f"expected a positive number of metres per unit, got {unit!r}",
                         field="unit")
    if leg_type not in ("SPS", "UPS"):
        raise InputError(f"expected leg_type SPS or UPS, got {leg_type!r}", field="leg_type")
    b, p = _joints(platform)
    if origin is None:
        o = p.mean(axis=0)
    else:
        o = np.asarray(origin, dtype=float)
        if o.shape != (3,) or not np.all(np.isfinite(o)):
            raise InputError(f"expected 3 finite numbers, got {origin!r}", field="origin")
    if home is None:
        if height is None:
            raise InputError("expected a home pose or a height, got neither", field="home")
        home = symmetric_home(platform, height, unit=unit, origin=o)
    rng = None if stroke is None else tuple(float(s) * unit for s in stroke)
    legs = [dict(type=leg_type, base=tuple(bk * unit), platform=tuple(pk * unit),
                 range=rng, limit=force) for bk, pk in zip(b, _frame(b, p, o))]
    return LegMechanism(name, tuple(legs), tuple(home), mass, inertia, None, route)
