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
           "hand_range_warnings", "gravity_warnings", "WORKSPACE_SIZE_FACTOR"]


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
    size = max(float(np.linalg.norm(kin.home[:3])), float(length_scale))
    if safety.workspace_m > WORKSPACE_SIZE_FACTOR * size:
        return (("safety.workspace_m",
                 f"±{safety.workspace_m:g} m is more than {WORKSPACE_SIZE_FACTOR:g} x the "
                 f"device's size ({size:.3g} m): the safe workspace limits nothing (a "
                 f"value in mm typed as m? 75 mm is 0.075)"),)
    return ()


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
