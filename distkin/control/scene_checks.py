"""Checks of a controller scene's values against each other and against the device
(:func:`.config.loads_control_scene` calls them): the derivative filter against the
period, the safety limits against the device's own home pose.  Errors name the field,
the value and the bound, with units.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = ["check_filter_period", "check_safety_at_home", "check_busy_wait",
           "hand_range_warnings", "gravity_warnings", "unit_slip_warnings", "device_size",
           "beyond_device", "WORKSPACE_SIZE_FACTOR", "MIN_HAPTIC_RATE_HZ", "MAX_FILTER_S",
           "VIRTUAL_MASS_FACTOR", "SERVO_STIFFNESS_FACTOR"]

#: ``[device] rate_hz`` below this is a warning (and, with a derivative filter shorter
#: than its period, the refusal names the rate): the joint PD loop's own modes are at
#: 10-30 Hz (``distkin control --delay-margin``), so a slower loop samples them fewer
#: than 3 times a period; the paper's runs at 1 kHz: a value in kHz typed as Hz
MIN_HAPTIC_RATE_HZ = 100.0
#: ``pd.derivative_filter_s`` above this (s) is a warning: a low-pass this slow passes
#: only motions below 1/(2π 10 s) = 0.016 Hz, far below a hand's, so the derivative
#: term does nothing (14 x the paper's 700 ms: a value in ms typed as s)
MAX_FILTER_S = 10.0
#: a virtual mass (``[admittance] mass``, per axis) above this many times the device's
#: own apparent mass at home (platform + reflected rotors, M + J_r JᵀJ: 0.40 kg along x
#: for the Octo, which renders 1 kg in the paper's example) is a warning: a value in g
#: typed as kg
VIRTUAL_MASS_FACTOR = 100.0
#: a spring's or wall's translational stiffness above this many times the servo's own
#: stiffness along that direction at home (KP JᵀJ, :mod:`.stiffness`: 1.3 N/mm along x
#: for the Octo) is a warning: the joint PD acts in series with the rendered
#: environment, so the device renders at most its servo's stiffness (k_s k/(k_s + k):
#: above 10 x within 10 % of k_s); a value in N/mm typed as N/m
SERVO_STIFFNESS_FACTOR = 10.0


def check_filter_period(pd, rate_hz):
    """Refuse a derivative filter shorter than one period (0 < T < h = 1/rate_hz).

    The forward-Euler low-pass ``d_f[k] = d_f[k-1] + (h/T)(d[k-1] - d_f[k-1])`` has the
    eigenvalue ``1 - h/T``: for T < h it is negative (the filtered derivative alternates
    in sign every period, no low-pass), for T < h/2 below -1 (it diverges whatever the
    gains, and ``kd = 0`` does not help: ``0 x inf`` is NaN, QA).  T = h is a one-period
    delay of the raw difference quotient; T = 0 passes it through unfiltered.  (The
    loop steps with the measured gap and clamps the step to 1: a late frame cannot make
    an accepted filter diverge; :meth:`.controller.Controller.filter_derivative`.)"""
    T, h = pd.derivative_filter_s, 1.0 / rate_hz
    if 0.0 < T < h and rate_hz < MIN_HAPTIC_RATE_HZ:       # the rate is the likely slip
        raise InputError(
            f"expected device.rate_hz of a haptic loop, at least {MIN_HAPTIC_RATE_HZ:g} Hz "
            f"(Kühne et al.: 1 kHz), or a pd.derivative_filter_s of at least its period, "
            f"got {rate_hz:g} Hz, a period of {h * 1e3:.6g} ms longer than the filter's "
            f"{T * 1e3:.6g} ms (a value in kHz typed as Hz? 1 kHz is 1000)",
            field="device.rate_hz", hint="rate_hz is in Hz: 1 kHz is 1000")
    if 0.0 < T < h:
        raise InputError(
            f"expected pd.derivative_filter_s 0 (no filter) or at least one period "
            f"1/device.rate_hz = {h * 1e3:.6g} ms (the forward-Euler low-pass has the "
            f"eigenvalue 1 - h/T = {1.0 - h / T:.4g}: below one period it rings at the "
            f"Nyquist frequency, below {h * 0.5e3:.6g} ms it diverges whatever kp and kd), "
            f"got {T * 1e3:.6g} ms", field="pd.derivative_filter_s",
            hint=f"use 0 or at least {h * 1e3:.6g} ms (Kühne et al.: 700 ms)")


#: ``safety.workspace_m`` beyond this many times the device's size (the larger of the
#: home position's distance from the base origin and the mechanism's length scale) is
#: warned about: a box the platform cannot reach is no limit (75 m: mm typed as m)
WORKSPACE_SIZE_FACTOR = 10.0


def check_safety_at_home(safety, kin, joint, length_scale):
    """Check ``safety`` against the device's own home pose (``kin`` a Python-route
    :class:`~.kinematics.KinematicModel`, ``length_scale`` its mechanism's, m).  Refused (InputError): ``workspace_rad``
    beyond π (a rotation box of ±π already holds every orientation: a number in degrees
    typed as rad), and a home pose that the singularity guard itself calls near-singular
    (σmin of ``J S^-1`` below ``sigma_min``, or its condition number above
    ``max_condition``): the device would sit at zero torque or hold for the whole run,
    reported ``completed`` (QA: ``sigma_min = 50``).  Returns the warnings: a
    ``workspace_m`` beyond :data:`WORKSPACE_SIZE_FACTOR` times the device's size."""
    from .controller import SCALING
    if safety.workspace_rad > math.pi:
        raise InputError(f"expected workspace_rad at most π = 3.1416 rad (a box of ±π "
                         f"holds every orientation), got {safety.workspace_rad:g} rad "
                         f"({math.degrees(safety.workspace_rad):.4g}°)",
                         field="safety.workspace_rad",
                         hint="the value is in rad: 30° is 0.5236")
    J = np.asarray(kin.jacobian(kin.home), dtype=float) / SCALING
    sv = np.linalg.svd(J, compute_uv=False) if np.all(np.isfinite(J)) else None
    unit = "m" if joint == "prismatic" else "rad"
    if sv is None or not sv[-1] >= safety.sigma_min:
        got = "not finite" if sv is None else f"{sv[-1]:.4g} {unit}"
        raise InputError(f"expected safety.sigma_min at most the device's own σmin of "
                         f"J S^-1 at its home pose, {got}, got {safety.sigma_min:g} {unit}: "
                         f"the singularity guard would hold the device the whole run",
                         field="safety.sigma_min")
    cond = sv[0] / sv[-1]
    if not cond <= safety.max_condition:
        raise InputError(f"expected safety.max_condition at least the condition number of "
                         f"J S^-1 at the device's home pose, {cond:.4g}, got "
                         f"{safety.max_condition:g}: the singularity guard would hold the "
                         f"device the whole run", field="safety.max_condition")
    return beyond_device("safety.workspace_m", f"±{safety.workspace_m:g} m",
                         safety.workspace_m, device_size(kin, length_scale),
                         "the safe workspace limits nothing", "75 mm is 0.075")


def device_size(kin, length_scale) -> float:
    """The device's size, m: the larger of its home position's distance from the base
    origin and its mechanism's length scale (the yardstick of :func:`beyond_device`)."""
    return max(float(np.linalg.norm(kin.home[:3])), float(length_scale))


def beyond_device(field, shown, length, size, meaning, example):
    """The warning ``(field, message)`` for a length (m) beyond
    :data:`WORKSPACE_SIZE_FACTOR` times the device's ``size`` (:func:`device_size`),
    which the platform cannot reach: "a value in mm typed as m?"; () otherwise.
    ``shown`` the value as the message states it, ``meaning`` what follows from it,
    ``example`` a value in mm and in m ("75 mm is 0.075")."""
    if abs(length) <= WORKSPACE_SIZE_FACTOR * size:
        return ()
    return ((field, f"{shown} is more than {WORKSPACE_SIZE_FACTOR:g} x the device's size "
                    f"({size:.3g} m): {meaning} (a value in mm typed as m? {example})"),)


def check_busy_wait(busy_us, rate_hz):
    """Refuse a ``[device] busy_wait_us`` longer than one period ``1e6/rate_hz`` µs: the
    loop would poll through the next frame's arrival instead of answering it."""
    period_us = 1e6 / rate_hz
    if busy_us > period_us:
        raise InputError(f"expected busy_wait_us at most one period 1e6/device.rate_hz = "
                         f"{period_us:.6g} µs (a frame comes once a period), got "
                         f"{busy_us:g} µs", field="device.busy_wait_us")


def gravity_warnings(motors, pd):
    """A warning when the simulated world's gravity (``[simulator] gravity``, m/s²)
    differs from the one the controller's gravity compensation assumes
    (:data:`.controller.GRAVITY`, a real device's 9.81 m/s²) while ``pd.gravity_compensation``
    is on: the compensation then pushes the platform by its mass times the difference
    (with ``gravity = 0`` the Octo's 0.17 kg platform is lifted by 1.67 N that nothing
    asked for)."""
    from .controller import GRAVITY
    g = float(motors.gravity)
    if pd.gravity_compensation and g != GRAVITY:
        return (("simulator.gravity",
                 f"the simulator applies {g:g} m/s², the controller's gravity compensation "
                 f"assumes {GRAVITY:g} m/s² (a real device's): the platform is pushed by "
                 f"its mass x {GRAVITY - g:+g} m/s²; set pd.gravity_compensation = false "
                 f"for a weightless run"),)
    return ()


def hand_range_warnings(hand, safety):
    """A warning when the scripted hand (``[simulator] hand``, N) pushes harder than the
    sensor range ``safety.max_force`` (N) in some component: the controller rejects
    those readings, and the run sits at zero torque through the watchdog."""
    peak = max((abs(float(v)) for k in hand.points for v in k[1:]), default=0.0)
    if peak > safety.max_force:
        return (("simulator.hand",
                 f"a force component of {peak:g} N is beyond the sensor range "
                 f"safety.max_force = {safety.max_force:g} N: those readings are rejected "
                 f"and the watchdog stops the servo"),)
    return ()


def unit_slip_warnings(rate_hz, pd, mass, environment, kin, length_scale, motors):
    """Warnings ``(field, message)`` for values that load but look like a unit slip
    (QA: each passed silently): ``device.rate_hz`` below :data:`MIN_HAPTIC_RATE_HZ`, a
    ``pd.derivative_filter_s`` above :data:`MAX_FILTER_S`, a wall farther from home than
    :func:`beyond_device` allows, a virtual mass above :data:`VIRTUAL_MASS_FACTOR` times
    the device's apparent mass, and a spring or wall stiffer than
    :data:`SERVO_STIFFNESS_FACTOR` times the servo along its direction at home.

    ``mass`` (6,) kg x3, kg·m² x3; ``environment`` the springs and walls
    (:mod:`.admittance`), in the scene's order; ``kin`` a Python-route
    :class:`~.kinematics.KinematicModel`; ``length_scale`` m; ``motors`` the drives
    (their ``joint_inertia``)."""
    from ..errors import DistkinError
    from .kinematics import apparent_mass
    from .stiffness import servo_stiffness
    out = []
    if rate_hz < MIN_HAPTIC_RATE_HZ:
        out.append(("device.rate_hz",
                    f"{rate_hz:g} Hz is below {MIN_HAPTIC_RATE_HZ:g} Hz: the joint PD "
                    f"loop's own 10-30 Hz modes are sampled fewer than 3 times a period "
                    f"(a value in kHz typed as Hz? Kühne et al.'s 1 kHz is 1000)"))
    T = pd.derivative_filter_s
    if T > MAX_FILTER_S:
        out.append(("pd.derivative_filter_s",
                    f"{T:g} s is more than {MAX_FILTER_S:g} s: the filtered derivative "
                    f"follows only motions slower than {1 / (2 * math.pi * T):.2g} Hz, "
                    f"so the kd term does nothing (a value in ms typed as s? Kühne et "
                    f"al.'s 700 ms is 0.7)"))
    home = np.asarray(kin.home, dtype=float)
    size = device_size(kin, length_scale)
    for i, e in enumerate(environment):
        if e.kind == "wall":
            d = e.offset - float(np.dot(e.normal, home[:3]))
            out.extend(beyond_device(f"environment[{i}].offset",
                                     f"a wall {abs(d):.4g} m from home", d, size,
                                     "the platform never reaches it", "20 mm is 0.02"))
    J = np.asarray(kin.jacobian(home), dtype=float)
    if np.all(np.isfinite(J)):
        own = np.diag(apparent_mass(kin.mass, motors.joint_inertia, J))
        heavy = [i for i in range(6) if mass[i] > VIRTUAL_MASS_FACTOR * own[i]]
        if heavy:
            axes = ", ".join(f"{'x y z rx ry rz'.split()[i]} {mass[i]:g} "
                             f"{'kg' if i < 3 else 'kg·m²'} against {own[i]:.3g}"
                             for i in heavy)
            out.append(("admittance.mass",
                        f"more than {VIRTUAL_MASS_FACTOR:g} x the device's own apparent "
                        f"mass at home (platform and reflected rotors): {axes} (a value "
                        f"in g typed as kg? 1000 g is 1)"))
    springs = [(i, k) for i, e in enumerate(environment) if e.kind == "spring"
               for k in range(3) if e.stiffness[k] > 0]
    walls = [i for i, e in enumerate(environment) if e.kind == "wall"]
    if pd.kp <= 0 or not (springs or walls):
        return tuple(out)
    dirs = [np.eye(3)[k] for _, k in springs] + [environment[i].normal for i in walls]
    try:
        servo = servo_stiffness(kin.mech, pd.kp, home, dirs)[0]
    except DistkinError:                 # no finite servo stiffness at home: no yardstick
        return tuple(out)
    asked = ([(f"environment[{i}].stiffness", "xyz"[k], environment[i].stiffness[k])
              for i, k in springs]
             + [(f"environment[{i}].stiffness", "its normal", environment[i].stiffness)
                for i in walls])
    said = set()                          # one line per field: its first axis beyond
    for (fld, along, k), ks in zip(asked, servo):
        if k > SERVO_STIFFNESS_FACTOR * ks and fld not in said:
            said.add(fld)
            out.append((fld, f"{k:g} N/m along {along} is more than "
                             f"{SERVO_STIFFNESS_FACTOR:g} x the servo's own stiffness "
                             f"there at home (KP JᵀJ: {ks:.4g} N/m): the joint PD, in "
                             f"series with it, renders at most about that (a unit slip? "
                             f"stiffness is in N/m: 1 N/mm is 1000)"))
    return tuple(out)
