"""Per-leg actuator limits of the study (Kühne et al. Sec. III-B-3), with units per
actuator type: a revolute actuator's effort is a torque (N·m) and its rate an angular
velocity (rad/s); a prismatic actuator's effort is a force (N) and its rate a speed (m/s).

The study's ``actuators`` table (SI)::

    nominal_torque, stall_torque (N·m), velocity (rad/s)    revolute legs (the paper's)
    nominal_force, stall_force (N), speed (m/s)             prismatic legs

A leg of a leg table (:class:`~distkin.mechanisms.legs.Leg`) with an effort ``limit``
uses it as its nominal (continuous) effort; with asymmetric limits the smaller
magnitude (the symmetric box the study's zonotopes use, a conservative choice).  When
every leg has the same three numbers the study runs its one-facet route on scalars (as
before, bit for bit); otherwise the capabilities are the zonotopes of the generators
scaled leg by leg (:func:`per_leg_capabilities`).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["REVOLUTE_KEYS", "PRISMATIC_KEYS", "KEY_UNITS", "leg_limits", "uniform_limits", "limit_text",
           "per_leg_capabilities", "transmission_lengths"]

#: the keys of the actuators table for revolute and for prismatic legs (same order:
#: nominal effort, stall effort, rate)
REVOLUTE_KEYS = ("nominal_torque", "stall_torque", "velocity")
PRISMATIC_KEYS = ("nominal_force", "stall_force", "speed")
#: the unit of each actuator figure (a scene's ``actuators`` table, the study's JSON)
KEY_UNITS = {"nominal_torque": "N·m", "stall_torque": "N·m", "velocity": "rad/s",
             "nominal_force": "N", "stall_force": "N", "speed": "m/s"}
_UNITS = {"nominal_torque": "N·m", "stall_torque": "N·m", "velocity": "rad/s",
          "nominal_force": "N", "stall_force": "N", "speed": "m/s"}


def _prismatic(mech):
    legs = getattr(mech, "leg_table", None)
    if legs is None:
        return np.zeros(mech.L, bool), None
    return np.array([leg.prismatic for leg in legs]), legs


def leg_limits(mech, actuators, field: str = "actuators") -> dict:
    """Per-leg limits: ``nominal``, ``stall``, ``rate`` arrays (L,) (SI, the leg's own
    unit) and ``prismatic`` (L,) bool.

    Raises
    ------
    InputError
        A prismatic leg without a force limit or without ``nominal_force`` /
        ``stall_force`` / ``speed`` in the table (never a torque taken for a force); a
        limit of the table that is not a positive finite number (a zero limit makes
        every capability 0, a negative one flips its sign)."""
    pris, legs = _prismatic(mech)
    out = {k: np.empty(mech.L) for k in ("nominal", "stall", "rate")}
    for i in range(mech.L):
        keys = PRISMATIC_KEYS if pris[i] else REVOLUTE_KEYS
        own = None if legs is None or legs[i].limit is None else legs[i].limit
        for name, key in zip(("nominal", "stall", "rate"), keys):
            if name == "nominal" and own is not None:
                lo, hi = own
                if not lo < 0 < hi:
                    unit = "N" if pris[i] else "N·m"
                    raise InputError(f"expected an effort limit straddling 0, got "
                                     f"[{lo:g}, {hi:g}] {unit}",
                                     field=f"mechanism.leg[{i}].limit")
                out[name][i] = min(-lo, hi)
                continue
            if key not in actuators:
                kind = "prismatic" if pris[i] else "revolute"
                raise InputError(f"expected {key} ({_UNITS[key]}) for the {kind} leg {i}, got "
                                 "nothing", field=f"{field}.{key}")
            x = actuators[key]
            try:
                x = float(x) if not isinstance(x, (bool, np.bool_)) else None
            except (TypeError, ValueError):
                x = None
            if x is None or not (np.isfinite(x) and x > 0):
                raise InputError(f"expected a positive finite limit ({_UNITS[key]}: the "
                                 f"symmetric box ±value), got {actuators[key]!r}",
                                 field=f"{field}.{key}")
            out[name][i] = x
    out["prismatic"] = pris
    return out


def uniform_limits(lim) -> dict | None:
    """The study's scalar actuators dict when every leg has the same three numbers (and
    one actuator type), else None."""
    if lim["prismatic"].any() and not lim["prismatic"].all():
        return None
    vals = [lim[k] for k in ("nominal", "stall", "rate")]
    if any(np.any(v != v[0]) for v in vals):
        return None
    return dict(zip(REVOLUTE_KEYS, (float(v[0]) for v in vals)))


def limit_text(lim, which: str) -> str:
    """The limit ``which`` ("nominal", "stall", "rate") as text with units per type, e.g.
    "2.5 N·m", "50 N", or "2.5 N·m (revolute legs), 50 N (prismatic legs)"."""
    unit = {"nominal": ("N·m", "N"), "stall": ("N·m", "N"), "rate": ("rad/s", "m/s")}[which]
    parts = []
    for pris, label in ((False, "revolute"), (True, "prismatic")):
        sel = lim["prismatic"] == pris
        if not sel.any():
            continue
        v = np.unique(lim[which][sel])
        num = f"{v[0]:.4g}" if len(v) == 1 else f"{v.min():.4g} ... {v.max():.4g}"
        parts.append((f"{num} {unit[pris]}", label))
    if len(parts) == 1:
        return parts[0][0]
    return ", ".join(f"{t} ({label} legs)" for t, label in parts)


def per_leg_capabilities(J, M, lim, capabilities, true_velocities):
    """The capabilities with per-leg limits (zonotopes of the generators with limits
    (L,), :func:`~.capability.worst_case_output`; the true velocity set of the rows
    scaled by the rates, :func:`~.velocity_set.true_velocity_worst`).

    J (N, L, 6); M (6,) the diagonal of M̂; ``capabilities``/``true_velocities`` the
    tables of :mod:`.study`.  Returns name -> (N,)."""
    from .capability import worst_case_output
    from .velocity_set import true_velocity_worst
    Jt = np.swapaxes(J, 1, 2)
    gens = {"wrench": (Jt, lim["nominal"]), "twist": (np.linalg.pinv(J), lim["rate"]),
            "acceleration": (Jt / M[None, :, None], lim["stall"])}
    out = {}
    for name, _, _, gen, _, keep in capabilities:
        G, p = gens[gen]
        out[name] = np.asarray(worst_case_output(G, -p, p, keep=list(keep)), dtype=float)
    Jv = J / lim["rate"][None, :, None]
    for name, _, _, keep in true_velocities:
        out[name] = np.asarray(true_velocity_worst(Jv, 1.0, list(keep)), dtype=float)
    if J.shape[1] == 6:            # J⁻¹·box is the slab set: as the study's uniform route
        for cap in capabilities:
            if cap[3] == "twist":
                out[cap[0]] = out[cap[0] + "_true"].copy()
    return out


def transmission_lengths(mech):
    """(L,) the length each leg's |Jq_ii| is divided by in ``transmission_min``: its crank
    (m; the sine of its transmission angle) for a revolute leg, 1 for a prismatic one
    (|Jq_ii| = 1: full transmission); an RSS description's common l1."""
    legs = getattr(mech, "leg_table", None)
    if legs is None:
        return np.full(mech.L, mech.l1)
    return np.array([1.0 if leg.prismatic else leg.crank for leg in legs])
