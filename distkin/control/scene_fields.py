"""The value checks of the controller scene's fields (:mod:`.config`): numbers, flags,
vectors, the virtual environment (Kühne et al. Fig. 9's admittance scheme renders it)
and the simulator's hand script.  Each error names the field (``pd.kp``,
``environment[1].normal``) and says what was expected and what was got.
"""

from __future__ import annotations

import numpy as np

from ..argcheck import as_table, check_keys, choice, float_array, require
from ..errors import InputError
from .admittance import Spring, Wall
from .plant import HandScript

__all__ = ["num", "FIELD_UNITS", "pd_units", "share", "bool_field", "numbers_only", "vec", "environment", "hand_script"]


#: the unit of each number field of the controller scene that has one unit (SI, as the
#: scene is written); the efforts and gains, whose unit is the legs' (N·m/rad or N/m),
#: are :func:`pd_units`'
FIELD_UNITS = {
    "device.rate_hz": "Hz", "device.busy_wait_us": "µs", "pd.derivative_filter_s": "s",
    "safety.watchdog_ms": "ms", "safety.max_force": "N", "safety.max_torque": "N·m",
    "safety.max_angle": "rad", "safety.max_fk_residual": "m", "safety.workspace_m": "m",
    "safety.workspace_rad": "rad", "safety.saturation_ms": "ms",
    "safety.recover_speed_m_s": "m/s", "safety.recover_rate_rad_s": "rad/s",
    "simulator.reply_timeout_ms": "ms", "simulator.device_watchdog_ms": "ms",
    "simulator.catch_up_ms": "ms", "simulator.force_noise": "N",
    "simulator.torque_noise": "N·m", "simulator.gravity": "m/s²",
    "simulator.rotor_inertia": "kg·m²", "simulator.lead": "m/rev"}


def pd_units(joint: str) -> dict:
    """The units of ``[pd]`` kp, ki, kd, torque_limit and of ``[simulator] friction``
    for legs that are ``joint`` ("revolute": crank angles, torques; "prismatic": leg
    lengths, forces)."""
    if joint == "prismatic":
        return {"kp": "N/m", "ki": "N/(m·s)", "kd": "N·s/m", "torque_limit": "N",
                "friction": "N·s/m"}
    return {"kp": "N·m/rad", "ki": "N·m/(rad·s)", "kd": "N·m·s/rad", "torque_limit": "N·m",
            "friction": "N·m·s/rad"}


def num(t, key, fld, default, *, positive=False, nonneg=False, unit=None):
    """``t[key]`` (or ``default``) as a finite float: a TOML number, not a string or a
    boolean; ``positive`` (> 0) or ``nonneg`` (>= 0) when asked.  The error states the
    value received in ``unit`` (default: :data:`FIELD_UNITS` of the field)."""
    v = t.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise InputError(f"expected a number, got {v!r}", field=f"{fld}.{key}")
    v = float(v)
    if not np.isfinite(v) or (positive and v <= 0) or (nonneg and v < 0):
        want = "a positive number" if positive else "a number >= 0" if nonneg else "a finite number"
        u = FIELD_UNITS.get(f"{fld}.{key}", "") if unit is None else unit
        raise InputError(f"expected {want}, got {v!r}{' ' + u if u else ''}",
                         field=f"{fld}.{key}")
    return v


def share(t, key, default):
    """``safety.KEY``, a share of the cycles in (0, 1]."""
    v = num(t, key, "safety", default, positive=True)
    if v > 1:
        raise InputError(f"expected a share of the cycles in (0, 1], got {v!r}",
                         field=f"safety.{key}")
    return v


def bool_field(t, key, fld, default):
    """``t[key]`` (or ``default``), a TOML boolean."""
    v = t.get(key, default)
    if not isinstance(v, bool):
        raise InputError(f"expected true or false, got {v!r}", field=f"{fld}.{key}")
    return v


def numbers_only(raw, fld, what):
    """Refuse strings and booleans in a (nested) list of numbers: ``float_array`` reads
    "1" and "sqrt(2)" (distkin's exact scenes), but the controller scene is SI numbers,
    as ``kp = "110"`` is refused by :func:`num` (QA X1 D8)."""
    items = raw if isinstance(raw, list) else [raw]
    for v in items:
        if isinstance(v, list):
            numbers_only(v, fld, what)
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"expected {what} (SI, TOML numbers), got {v!r} in {raw!r}",
                             field=fld)


def vec(t, key, fld, n, *, positive=False, nonneg=False, default=None):
    """``t[key]``, ``n`` finite TOML numbers (not strings: the controller scene is SI
    numbers, as ``num`` reads them), as a tuple of floats."""
    if key not in t and default is not None:
        return tuple(default)
    raw = require(t, key, fld)
    numbers_only(raw, f"{fld}.{key}", f"{n} numbers")
    arr = float_array(raw, f"{fld}.{key}", (n,))
    if positive and np.any(arr <= 0):
        raise InputError(f"expected {n} positive numbers, got {arr.tolist()}", field=f"{fld}.{key}")
    if nonneg and np.any(arr < 0):
        raise InputError(f"expected {n} numbers >= 0, got {arr.tolist()}", field=f"{fld}.{key}")
    return tuple(float(v) for v in arr)


def environment(items, home):
    """The ``[[environment]]`` tables: springs (anchored at ``home`` by default) and
    walls (:mod:`.admittance`)."""
    if not isinstance(items, list):
        raise InputError(f"expected a list of [[environment]] tables, got {items!r}",
                         field="environment")
    out = []
    for i, raw in enumerate(items):
        fld = f"environment[{i}]"
        t = as_table(raw, fld)
        kind = choice(require(t, "kind", fld), f"{fld}.kind", ("spring", "wall"))
        if kind == "spring":
            check_keys(t, {"kind", "anchor", "stiffness", "damping"}, fld)
            anchor = t.get("anchor", "home")
            anchor = (tuple(home) if anchor == "home"
                      else vec(t, "anchor", fld, 6))
            out.append(Spring(anchor, vec(t, "stiffness", fld, 6, nonneg=True),
                              vec(t, "damping", fld, 6, nonneg=True, default=(0.0,) * 6)))
        else:
            check_keys(t, {"kind", "normal", "offset", "stiffness", "damping"}, fld)
            n = np.asarray(vec(t, "normal", fld, 3))
            norm = float(np.linalg.norm(n))
            if norm < 1e-12:
                raise InputError(f"expected a non-zero normal, got {n.tolist()}",
                                 field=f"{fld}.normal")
            require(t, "offset", fld)
            require(t, "stiffness", fld)
            out.append(Wall(tuple(float(v) for v in n / norm),
                            num(t, "offset", fld, None, unit="m") / norm,
                            num(t, "stiffness", fld, None, positive=True, unit="N/m"),
                            num(t, "damping", fld, 0.0, nonneg=True, unit="N·s/m")))
    return tuple(out)


def hand_script(raw, fld):
    """``simulator.hand``: knots ``[t s, fx, fy, fz N]``, sorted by time."""
    numbers_only(raw, fld, "knots [t s, fx, fy, fz N]")
    arr = float_array(raw, fld, (None, 4))
    if arr.shape[0] and arr[0, 0] < 0:      # device time starts at 0
        raise InputError(f"expected knot times >= 0 s (device time starts at 0), got "
                         f"{arr[0, 0]:g} s", field=fld)
    if np.any(np.diff(arr[:, 0]) < 0):
        raise InputError(f"expected knots sorted by time, got times {arr[:, 0].tolist()}",
                         field=fld)
    return HandScript(tuple(tuple(float(v) for v in row) for row in arr))
