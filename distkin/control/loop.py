"""The control loop of :class:`.controller.Controller`: frames in, commands out, the
safety state machine (Kühne et al. Sec. III-D: one cycle per state frame at 1 kHz).

:func:`run_loop` is :meth:`.controller.Controller.run` (its docstring holds the
contract).  The states: ``RUN`` (torque control), ``FAULT`` (zero torque) and
``STOPPED`` (hold, near a singular pose, entered from ``RUN`` only: a singular pose
measured in the fault state keeps zero torque).  A rejected frame (:func:`.safety.check_reading`)
is answered with a keep-alive repeating the last decision, as a missing one is, until
the watchdog window (``safety.watchdog_ms``, wall time or device time since the last
valid frame) has passed: then the fault state and zero torque, from ``RUN`` and from
``STOPPED`` alike.  A valid frame that comes after such a gap (this process or the
device was held up, or the frames between were lost) trips the watchdog too, and is
the first frame of the recovery.  A frame with the ``ESTOP`` bit gives the fault state
and zero torque at once, also before the first valid frame (a device whose e-stop is
held when the run starts).  A run of rejected frames is logged by its first frame,
then once a second (event ``bad_reading`` with the frames so far; the summary's
``rejected_frames`` counts them all).  The fault state is left
after ``safety.recover_frames`` consecutive valid frames at measured poses inside the
safe workspace (``safety.workspace_m``, ``workspace_rad``; when enough valid frames
came but the pose is outside, the controller logs ``recovery_held`` once and keeps zero
torque), and only once the platform is nearly at rest: its mean speed over those
frames at most ``safety.recover_speed_m_s`` and ``recover_rate_rad_s``
(:func:`platform_moving`; at least 3 frames, a speed needs two poses; while it moves,
``recovery_held`` once per run of frames); a rejected frame, an empty read or a pose
outside starts the count again.
The first measured pose is checked too: outside the safe workspace the run starts in
the fault state (event ``outside_workspace``).  A loop oscillating at the torque limit
(over the last ``safety.saturation_ms`` of device time at least
``safety.saturation_share`` of the cycles saturated, the commands reversing sign:
:class:`.safety.SaturationWatch`) enters the fault state too (event
``saturation_fault``), and leaves it as after any fault.
A cycle whose computed efforts are not all finite (NaN or ±inf: e.g. an unstable
derivative filter) sends zero torque instead and enters the fault state (event
``nonfinite_torque`` naming the joints; the summary's ``nonfinite_cycles`` counts them):
a NaN passes every ``>`` of the saturation and must never reach the wire.
"""

from __future__ import annotations

import gc
import signal
import time
from collections import deque

import numpy as np

from ..errors import LinkError
from .protocol import (FLAG_KEEPALIVE, MODE_HOLD, MODE_RUN, MODE_ZERO_TORQUE, STATUS_ESTOP,
                       CommandFrame)
from .runlog import run_summary
from .safety import FAULT, RUN, STOPPED, DeviceStatus, SaturationWatch
from .scheduling import realtime, restore

__all__ = ["run_loop", "platform_moving", "BAD_READING_EVERY_S"]

#: the states the watchdog guards (a fault has zero torque already)
WATCHED = (RUN, STOPPED)
#: a run of rejected frames is logged by its first frame, then once per this long (s)
BAD_READING_EVERY_S = 1.0


def _enter_fault(ctl, last, event, t0, frame, **info):
    """The fault state from now (logged as ``event``): the decision the keep-alives
    repeat becomes zero torque."""
    ctl.state = FAULT
    ctl._event(event, t0, frame, **info)
    return CommandFrame(last.seq, last.ack, MODE_ZERO_TORQUE, 0, np.zeros(ctl.L))


def platform_moving(safety, poses) -> str:
    """Why the platform is not at rest for a recovery ("" if it is): its mean speed
    between the first and the last of ``poses`` ((t_us, pose) pairs, the estimates of
    the last ``recover_frames`` valid frames) beyond ``safety.recover_speed_m_s``
    (x, y, z) or ``recover_rate_rad_s`` (rx, ry, rz); fewer than two poses: not known
    yet.  Re-arming at the measured pose of a moving platform leaves the servo (Kühne
    et al. Sec. III-D, little damping through the 700 ms filter) to stop that motion:
    at about 1 m/s it sat at the torque limit (QA)."""
    if len(poses) < 2 or poses[-1][0] <= poses[0][0]:
        return "platform speed not known yet (fewer than 2 poses)"
    (t_a, a), (t_b, b) = poses[0], poses[-1]
    dt = (t_b - t_a) * 1e-6
    v = float(np.linalg.norm(b[:3] - a[:3])) / dt
    w = float(np.linalg.norm(b[3:] - a[3:])) / dt
    if not v <= safety.recover_speed_m_s:
        return (f"platform moving at {v:.3g} m/s, beyond recover_speed_m_s "
                f"{safety.recover_speed_m_s:g} m/s")
    if not w <= safety.recover_rate_rad_s:
        return (f"platform turning at {w:.3g} rad/s, beyond recover_rate_rad_s "
                f"{safety.recover_rate_rad_s:g} rad/s")
    return ""


def _keepalive(link, seq, ack, last):
    """Send a keep-alive repeating the last decision (mode and torques); returns it."""
    cmd = CommandFrame(seq, ack, last.mode, FLAG_KEEPALIVE, last.torques)
    link.write_command(cmd)
    return cmd


def run_loop(ctl, link, seconds: float, wall_limit: float | None = None) -> dict:
    """:meth:`.controller.Controller.run` of ``ctl`` over ``link`` (see there)."""
    wall_limit = 2.0 * seconds + 10.0 if wall_limit is None else wall_limit
    t0 = time.perf_counter()
    cpu0 = time.thread_time()
    poll = min(0.005, ctl.safety.watchdog_ms * 1e-3 / 4)
    seq = 0
    last = CommandFrame(0, 0, MODE_ZERO_TORQUE, 0, np.zeros(ctl.L))
    last_valid = last_t_dev = last_t_us = None
    fk_failures = 0
    t_first = t_prev_us = None
    t_prev_cycle = None
    recover_count = inside_count = 0
    bad_streak, bad_said = 0, -float("inf")
    compute, compute_cpu, periods = [], [], []
    cycles = 0
    sat_watch = SaturationWatch(ctl.safety.saturation_ms * 1e3,
                                ctl.safety.saturation_share)
    # the pose estimates (t_us, pose) of the current run of consecutive valid frames
    # in the fault state: the platform's speed before the recovery
    fault_poses = deque(maxlen=max(ctl.safety.recover_frames, 2))
    gc0 = sum(g["collections"] for g in gc.get_stats())
    reason = "completed"
    ctl.error = None
    # device time (µs) between valid frames with the controller not in RUN (fault or
    # hold) at either end of the interval: the summary's fault_seconds
    ctl.fault_us = 0
    state_after = RUN
    stop = {"sig": None}

    def _on_signal(signum, _frame):
        stop["sig"] = signum

    rt = None
    if getattr(ctl.scene, "realtime", False):
        rt, why = realtime()
        if why:
            ctl._event("realtime_refused", t0, None, message=why)
    old = {}
    for s in (signal.SIGINT, signal.SIGTERM):
        try:
            old[s] = signal.signal(s, _on_signal)
        except ValueError:  # not in the main thread
            pass
    try:
        while True:
            if stop["sig"] is not None:
                reason = "interrupted"
                break
            now = time.perf_counter()
            if now - t0 > wall_limit:
                reason = "wall_limit"
                done = 0.0 if t_first is None else (t_prev_us - t_first) * 1e-6
                ctl.error = (f"expected {seconds:g} s of device time within the wall-time "
                             f"limit of {wall_limit:g} s, got {done:.3f} s (a device too "
                             f"slow or held up)")
                break
            if t_first is None and now - t0 > ctl.STARTUP_TIMEOUT_S:
                reason = "no_device"
                ctl.error = (f"expected state frames from the device, got none in "
                             f"{ctl.STARTUP_TIMEOUT_S:g} s")
                bad = getattr(getattr(link, "stats", None), "bad_frames", 0)
                if bad:                        # bytes came, none formed a frame
                    ctl.error += (f" but {bad} bad frames (bytes that formed no valid "
                                  f"frame: a wrong baud rate, or a device speaking "
                                  f"another protocol than docs/protocol.md's?)")
                if ctl.rejected_frames:       # frames came, none could be used
                    reason = "no_valid_frames"
                    ctl.error = (f"expected a valid state frame from the device, got "
                                 f"{ctl.rejected_frames} rejected in "
                                 f"{ctl.STARTUP_TIMEOUT_S:g} s (last: "
                                 f"{ctl.last_rejection})")
                break
            frame = link.read_state(poll)
            t_rx = time.perf_counter()
            c_rx = time.thread_time()
            if frame is None:
                recover_count = 0              # recovery needs consecutive frames
                if last_valid is not None and ctl.state in WATCHED and \
                        t_rx - last_valid > ctl.safety.watchdog_ms * 1e-3:
                    last = _enter_fault(ctl, last, "watchdog_trip", t0, None,
                                        t_dev=last_t_dev,
                                        silent_ms=round((t_rx - last_valid) * 1e3, 1))
                if last_valid is not None:
                    seq += 1
                    last = _keepalive(link, seq, last.ack, last)
                continue
            n = frame.angles.shape[0] if frame.angles.ndim == 1 else -1
            if n != ctl.L and t_first is None:
                # the first frame already says it: another device than the scene's
                reason = "device_mismatch"
                ctl.error = (f"device sends {n} joint angles, scene has {ctl.L} legs "
                             f"(expected state frames with {ctl.L} encoder angles: is "
                             f"the scene the device's?)")
                ctl._event("device_mismatch", t0, frame, joints=n, legs=ctl.L)
                break
            if frame.status & DeviceStatus.MASK:
                for name, count in ctl.device_status.note(frame.status, frame.t_us):
                    ctl._event(name, t0, frame, frames=count)
            why = ctl.check_reading(frame)
            if why:
                ctl.rejected_frames += 1
                ctl.last_rejection = why
                recover_count = 0              # recovery needs consecutive frames
                bad_streak += 1
                if bad_streak == 1 or t_rx - bad_said >= BAD_READING_EVERY_S:
                    # the first of a run of rejected frames, then one a second
                    ctl._event("bad_reading", t0, frame, reason=why, frames=bad_streak)
                    bad_said = t_rx
                if frame.status & STATUS_ESTOP and ctl.state != FAULT:
                    # the e-stop: zero torque from this frame on (before the first
                    # valid frame too: a device whose e-stop is held when we start)
                    last = _enter_fault(ctl, last, "estop", t0, frame)
                elif last_valid is not None and ctl.state in WATCHED and (
                        t_rx - last_valid > ctl.safety.watchdog_ms * 1e-3
                        or frame.t_us - last_t_us > ctl.safety.watchdog_ms * 1e3):
                    # only rejected frames for the watchdog window (device or wall
                    # time): as if the device were silent
                    silent = max(t_rx - last_valid, (frame.t_us - last_t_us) * 1e-6)
                    last = _enter_fault(ctl, last, "watchdog_trip", t0, frame,
                                        reason=why, silent_ms=round(silent * 1e3, 1))
                if last_valid is not None or ctl.state == FAULT:
                    seq += 1
                    last = _keepalive(link, seq, frame.seq, last)
                continue
            bad_streak = 0
            if last_valid is not None and ctl.state in WATCHED and (
                    t_rx - last_valid > ctl.safety.watchdog_ms * 1e-3
                    or frame.t_us - last_t_us > ctl.safety.watchdog_ms * 1e3):
                # a valid frame, but the last one came longer ago than the watchdog
                # window (this process or the device was held up, or the frames
                # between were lost): as after a silence, zero torque and the
                # recovery; this frame is the first of it
                silent = max(t_rx - last_valid, (frame.t_us - last_t_us) * 1e-6)
                recover_count = inside_count = 0
                last = _enter_fault(ctl, last, "watchdog_trip", t0, frame,
                                    reason="late frame", silent_ms=round(silent * 1e3, 1))
            last_valid = t_rx
            last_t_us = frame.t_us
            last_t_dev = frame.t_us * 1e-6
            if t_first is None:
                t_first = frame.t_us
            dt = ctl.dt_nominal
            if t_prev_us is not None:
                dt = min(max((frame.t_us - t_prev_us) * 1e-6, 0.2 * dt), 5.0 * dt)
            if t_prev_us is not None and (state_after != RUN or ctl.state != RUN):
                ctl.fault_us += max(frame.t_us - t_prev_us, 0)
            t_prev_us = frame.t_us
            if ctl.state == FAULT:
                recover_count += 1
                if recover_count == 1:
                    fault_poses.clear()        # a new run of consecutive frames
                # of the consecutive valid frames, those at poses inside the safe
                # workspace (the last estimate of the pose, tracked in the fault state)
                away = ctl.outside_workspace(ctl.pose)
                inside_count = 0 if away else min(inside_count + 1, recover_count)
                moving = "" if away else platform_moving(ctl.safety, fault_poses)
                if moving and inside_count == ctl.safety.recover_frames and len(fault_poses) > 1:
                    # enough valid frames inside, but the platform is not at rest:
                    # said once per run of them; the recovery waits for rest
                    ctl._event("recovery_held", t0, frame, reason=moving)
                if inside_count >= ctl.safety.recover_frames and not moving:
                    ctl.state = RUN
                    ctl._event("recovered", t0, frame, frames=recover_count)
                    ctl.started = False    # re-initialise at the measured pose
                elif away and recover_count == ctl.safety.recover_frames:
                    # enough valid frames, at a pose outside: said once per run of them
                    ctl._event("recovery_held", t0, frame, reason=away)
            was_refusing = ctl.refusing
            was_started = ctl.started
            res = ctl.compute(frame, dt)
            if ctl.state == FAULT and res.reason != "fk_failed":
                fault_poses.append((frame.t_us, np.array(ctl.pose, dtype=float)))
            if not was_started and ctl.started and ctl.state == RUN:
                away = ctl.outside_workspace(ctl.pose)     # (re)started: inside?
                if away:
                    recover_count = 0
                    last = _enter_fault(ctl, last, "outside_workspace", t0, frame,
                                        reason=away)
            if res.reason != "fk_failed":
                fk_failures = 0
            if res.reason in ("unreachable", "singular"):
                ctl.refusing = True
                if not was_refusing:
                    ctl._event("pose_refused", t0, frame, reason=res.reason)
            elif res.accepted:
                ctl.refusing = False
            if res.reason == "fk_failed":
                fk_failures += 1
                ctl._event("fk_failed", t0, frame, residual=res.fk_residual)
                if fk_failures > ctl.MAX_FK_FAILURES and ctl.state == RUN:
                    recover_count = 0         # pose unknown: zero torque until it is
                    last = _enter_fault(ctl, last, "fk_lost", t0, frame,
                                        failures=fk_failures)
                seq += 1
                last = _keepalive(link, seq, frame.seq, last)
                continue
            # a singular stop holds a running device; it never lifts a fault (zero
            # torque until the recovery's own conditions hold)
            if res.reason == "singular_stop" and ctl.state == RUN:
                ctl.state = STOPPED
                ctl._event("singular_stop", t0, frame)
            if ctl.state == FAULT:
                mode, tau = MODE_ZERO_TORQUE, np.zeros(ctl.L)
            elif ctl.state == STOPPED:
                mode, tau = MODE_HOLD, np.zeros(ctl.L)
            else:
                mode, tau = res.mode, res.torques
            if mode == MODE_RUN and not np.all(np.isfinite(tau)):
                # a NaN or infinite effort (an unstable filter, an overflow): never on
                # the wire (the saturation's comparisons are False for NaN); zero
                # torque and the fault state from this cycle on
                ctl.nonfinite_cycles += 1
                bad = [i for i in range(ctl.L) if not np.isfinite(tau[i])]
                last = _enter_fault(ctl, last, "nonfinite_torque", t0, frame, joints=bad)
                recover_count = inside_count = 0
                mode, tau = MODE_ZERO_TORQUE, np.zeros(ctl.L)
                res.saturated = False
            seq += 1
            last = CommandFrame(seq, frame.seq, mode, 0, tau)
            link.write_command(last)
            t_done = time.perf_counter()
            compute_cpu.append(time.thread_time() - c_rx)
            cycles += 1
            compute.append(t_done - t_rx)
            period = 0.0 if t_prev_cycle is None else t_rx - t_prev_cycle
            if t_prev_cycle is not None:
                periods.append(period)
            t_prev_cycle = t_rx
            if res.saturated:
                ctl.saturated_cycles += 1
            if ctl.state != RUN:
                sat_watch.reset()
            elif sat_watch.note(frame.t_us, res.saturated, tau):
                # oscillating at the torque limit: zero torque from the next cycle
                last = _enter_fault(ctl, last, "saturation_fault", t0, frame,
                                    reversals=sat_watch.reversals,
                                    saturated_ms=round((frame.t_us - sat_watch.since_us)
                                                       * 1e-3, 1))
                recover_count = inside_count = 0
                sat_watch.reset()
            ctl.max_abs_torque = max(ctl.max_abs_torque, float(np.max(np.abs(tau))))
            state_after = ctl.state
            p = res.pose if res.pose is not None else ctl.pose
            d = res.desired if res.desired is not None else ctl.adm.pose
            wr = res.wrench if res.wrench is not None else np.zeros(6)
            ctl.log.add((t_rx - t0, frame.t_us * 1e-6, frame.seq, frame.status,
                         ctl.state, mode,
                         t_done - t_rx, period, res.fk_iterations, res.fk_residual,
                         0 if res.accepted else 1, 1 if res.saturated else 0,
                         *p, *d, *wr, *tau))
            if (frame.t_us - t_first) * 1e-6 >= seconds:
                reason = "completed"
                break
    except LinkError as exc:
        # a SIGINT/SIGTERM that came with the link's end is the interrupt, not the
        # device's (Ctrl-C reaches a simulator in our process group too, which closes
        # the port first: QA, 1 run in 5 ended "disconnect", exit 2)
        reason = "disconnect" if stop["sig"] is None else "interrupted"
        ctl.error = exc.message if stop["sig"] is None else None
        ctl._event("disconnect", t0, None, message=exc.message)
    except Exception as exc:  # no run ends in a traceback: record, zero torque, exit 1
        reason = "internal_error"
        ctl.error = f"{type(exc).__name__}: {exc}"
        ctl._event("internal_error", t0, None, message=ctl.error)
    finally:
        sent = _zero_torque(ctl, link, seq, last.ack)
        ctl._event("zero_torque", t0, None, sent=sent)
        for s, h in old.items():
            signal.signal(s, h)
        restore(rt)
        ctl.log.flush()
    wall = time.perf_counter() - t0
    ctl.loop_cpu_s = time.thread_time() - cpu0
    ctl.gc_collections = sum(g["collections"] for g in gc.get_stats()) - gc0
    return run_summary(ctl, link, cycles, wall, t_first, t_prev_us, compute, compute_cpu,
                       periods, reason, zero_torque_sent=sent)


def _zero_torque(ctl, link, seq, ack) -> bool:
    """Send zero torque three times; True if at least one frame was written whole."""
    sent = False
    for i in range(3):
        try:
            sent |= link.write_command(CommandFrame(seq + 1 + i, ack, MODE_ZERO_TORQUE, 0,
                                                    np.zeros(ctl.L)))
        except LinkError:
            break
    return sent
