"""Checks of the joint values given to the forward kinematics (:mod:`.forward`,
:mod:`.forward_tiers`, the scene query :mod:`distkin.app.queries.forward_kinematics`):
a prismatic leg's length must be positive, every joint value must lie in its leg's
declared range (a crank's arc modulo 2π, a prismatic leg's stroke; outside it there is
no configuration of the device: QA 2026-11-29, a 6-UPS with every leg at 600 mm against
strokes of 350-550 mm got a pose "verified"), and the largest of a set of joint
differences as text, per joint type.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InfeasibleError, InputError
from ..numfmt import apart

__all__ = ["check_joint_values", "joint_ranges", "range_excess", "outside_ranges",
           "check_joint_ranges", "joint_amount"]

_TWO_PI = 2.0 * math.pi


def check_joint_values(mech, q, field: str = "q"):
    """Refuse a prismatic leg's joint value that is not positive (QA R 1).

    A prismatic leg's joint value is its length |P - B| between base and platform joint:
    0 has no line (the closure ``(|P - B|^2 - q^2) / (2 q)`` divides by it) and a negative
    length is none (its square would pass it off as the positive one).  ``q`` (L,) or
    (N, L), rad or m; other shapes are left to the caller's shape check.  One vectorised
    comparison.

    Raises
    ------
    InputError
        naming ``field[j]`` (or ``field[i][j]``), the leg and the value received.
    """
    pris = mech.leg_arrays()["prismatic"]
    if not pris.any():
        return
    try:
        qa = np.asarray(q, dtype=float)
    except (TypeError, ValueError):        # not numbers: the caller's check says so
        return
    if qa.ndim not in (1, 2) or qa.shape[-1] != len(pris):
        return
    bad = pris & ~(np.atleast_2d(qa) > 0.0)
    if bad.any():
        i, j = (int(v) for v in np.argwhere(bad)[0])
        where = f"[{j}]" if qa.ndim == 1 else f"[{i}][{j}]"
        raise InputError(f"expected a positive leg length (m) for prismatic leg {j + 1}, got "
                         f"{float(np.atleast_2d(qa)[i, j]):.6g}", field=field + where,
                         hint="a prismatic leg's joint value is its length from the base "
                              "joint to the platform joint, not an extension from a zero "
                              "point")


def joint_ranges(mech, revolute: bool = False):
    """The declared joint ranges of ``mech``: (lo, hi) arrays (L,) (rad for a crank, m
    for a prismatic leg's stroke; -inf, inf for a leg without one), or None when no leg
    has one (the RSS presets).  ``revolute``: the cranks' ranges only (a prismatic leg's
    stroke is part of its reach margin, :meth:`.kinematics.KernelMethods._valid`)."""
    legs = getattr(mech, "leg_table", None) or ()
    kept = [None if leg.range is None or (revolute and leg.prismatic) else leg.range
            for leg in legs]
    if all(r is None for r in kept):
        return None
    lo = np.array([-np.inf if r is None else float(r[0]) for r in kept])
    hi = np.array([np.inf if r is None else float(r[1]) for r in kept])
    return lo, hi


def range_excess(q: float, lo: float, hi: float) -> float:
    """How far (rad) the crank angle ``q`` lies outside the arc [``lo``, ``hi``] taken
    modulo 2π, as :func:`.legs.in_revolute_range` reads a range (``[90, 270]`` deg is
    the back arc, ``[270, 450]`` the same arc as ±90°): 0 inside it, and where the leg
    has no range (``lo`` = -inf; a full turn is given so by the control code's
    :class:`~distkin.control.kinematics.KinematicModel`); inf for NaN.  Plain ``math``:
    compiled for the control cycle by :mod:`distkin.control.cycle_common`."""
    if q != q:
        return math.inf
    if not lo > -math.inf:
        return 0.0
    qs = q + _TWO_PI * math.ceil((lo - q) / _TWO_PI)   # the shift into [lo, lo + 2π)
    if qs <= hi:
        return 0.0
    return min(qs - hi, lo + _TWO_PI - qs)


def outside_ranges(mech, q):
    """Which joint values ``q`` (L,) or (N, L) (rad, or m for a prismatic leg) lie
    outside their leg's declared range: a bool array of q's shape.  A crank angle is in
    its range when some q + 2πk is (:func:`.legs.in_revolute_range`, as the inverse
    kinematics' ``valid`` and the control code read it); a prismatic leg's length when
    min <= q <= max (the stroke; the IK's reach margin (q - min)(max - q) >= 0), within
    4 ulps of either end.  NaN is outside a declared range; a leg without one is never
    outside."""
    from .legs import in_revolute_range
    qa = np.asarray(q, dtype=float)
    r = joint_ranges(mech)
    if r is None:
        return np.zeros(qa.shape, dtype=bool)
    lo, hi = r
    pris = mech.leg_arrays()["prismatic"]
    ranged = np.isfinite(lo) | np.isfinite(hi)
    # a length within 4 ulps of a stroke end is at the end (a value converted from
    # another unit by a float product may land one ulp beyond it, review 2026-11-29)
    ulps = 4 * np.finfo(float).eps
    with np.errstate(invalid="ignore"):
        inside = np.where(pris, (qa >= lo - ulps * np.abs(lo)) & (qa <= hi + ulps * np.abs(hi)),
                          in_revolute_range(qa, lo, hi))
    return ranged & ~inside


def _range_excess(q, lo, hi, prismatic):
    """How far the joint value ``q`` (float) lies beyond the range [``lo``, ``hi``]: the
    distance to the stroke (m), or to the nearer end of the arc modulo 2π (rad,
    :func:`range_excess`)."""
    return max(lo - q, q - hi, 0.0) if prismatic else range_excess(q, lo, hi)


def check_joint_ranges(mech, q, field: str = "q", units=None):
    """Refuse joint values outside their legs' declared ranges (:func:`outside_ranges`):
    they are no configuration of the device, so no tier of the forward kinematics
    answers them (the inverse kinematics flags such a leg not ``valid``, the control
    code's end stops hold the joints inside them, and ``certify_workspace`` encloses the
    ranges).  ``q`` (L,) or (N, L), rad or m; ``units`` {"length": (name, factor from
    m), "angle": (name, factor from rad)} for the message (default SI).

    Raises
    ------
    InfeasibleError
        naming ``field[j]`` (or ``field[i][j]``) of the first leg outside, its value and
        range in ``units``, the other legs outside, and (``margin``) how far beyond the
        range it lies (m or rad).
    """
    out = outside_ranges(mech, q)
    if not out.any():
        return
    qa = np.atleast_2d(np.asarray(q, dtype=float))
    out2 = np.atleast_2d(out)
    i = int(np.argmax(out2.any(axis=1)))
    bad = np.flatnonzero(out2[i])
    j = int(bad[0])
    lo, hi = joint_ranges(mech)
    pris = bool(mech.leg_arrays()["prismatic"][j])
    name, f = (units or {"length": ("m", 1.0), "angle": ("rad", 1.0)})[
        "length" if pris else "angle"]
    v = float(qa[i, j])
    excess = math.inf if math.isnan(v) else _range_excess(v, lo[j], hi[j], pris)
    what = "length" if pris else "angle"
    where = f"[{j}]" if np.ndim(q) == 1 else f"[{i}][{j}]"
    others = [int(k) + 1 for k in bad[1:]]
    shown = apart(v * f, lo[j] * f, hi[j] * f)     # the value visibly beyond its bound
    raise InfeasibleError(
        f"expected every joint value within its leg's declared range, got leg {j + 1}'s "
        f"{what} {shown[0]} {name} outside its range [{shown[1]}, {shown[2]}] "
        f"{name} ({excess * f:.3g} {name} beyond it)"
        + (f", and legs {others} outside theirs" if others else "")
        + ": not a configuration of the device, so there is no pose to give",
        field=field + where, margin=excess,
        hint="check the joint values and their units against the legs' ranges "
             "(mechanism.leg range)")


def joint_amount(values, prismatic, *, length=("m", 1.0), angle=("rad", 1.0)) -> str:
    """The largest of ``values`` (L,) (joint differences: rad for a crank, m for a
    prismatic leg, NaN counted as inf) with its unit, per joint type: ``"2.28 rad"``,
    ``"0.9 m"`` or ``"2.28 rad (cranks), 0.9 m (prismatic legs)"``.  ``length`` and
    ``angle`` are (unit name, factor from SI), e.g. ("mm", 1000.0) and ("deg", 180/pi)."""
    v = np.asarray(values, dtype=float).reshape(-1)
    v = np.where(np.isnan(v), np.inf, v)
    pris = np.asarray(prismatic, dtype=bool).reshape(-1)
    parts = []
    if (~pris).any():
        parts.append((f"{float(v[~pris].max()) * angle[1]:.3g} {angle[0]}", "cranks"))
    if pris.any():
        parts.append((f"{float(v[pris].max()) * length[1]:.3g} {length[0]}", "prismatic legs"))
    if len(parts) == 1:
        return parts[0][0]
    return ", ".join(f"{a} ({b})" for a, b in parts)
