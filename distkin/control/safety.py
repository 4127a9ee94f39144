"""The checks of a state frame and the device's own status bits.

Kühne et al. Sec. III-D run the controller at 1 kHz on the device's readings; this
module decides which readings the cycle may use (:func:`check_reading`: finite, in
range, no ``ESTOP`` or ``SENSOR_FAULT`` bit, see docs/protocol.md) and counts the bits
that report what the device did on its own (:class:`DeviceStatus`: ``DEVICE_WATCHDOG``,
``SATURATED``).  What the loop does with a rejected frame (the watchdog, the e-stop) is
:meth:`.controller.Controller.run`.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from ..errors import InputError
from .cycle_kernels import reading_extremes
from .protocol import STATUS_DEVICE_WATCHDOG, STATUS_ESTOP, STATUS_SATURATED, STATUS_SENSOR_FAULT

__all__ = ["check_reading", "check_limits", "DeviceStatus", "SaturationWatch", "RUN",
           "FAULT", "STOPPED", "MIN_REVERSALS"]

#: the states of :meth:`.controller.Controller.run` (the ``state`` column of cycles.csv):
#: torque control, zero torque (watchdog, e-stop, pose lost), hold (singular stop)
RUN, FAULT, STOPPED = 0, 1, 2
#: a saturated oscillation: at least this many sign reversals of a joint's command
#: within the window of :class:`SaturationWatch` (two full swings)
MIN_REVERSALS = 4


def check_reading(frame, L: int, safety, lo=None, hi=None) -> str:
    """Why a state frame must be rejected ("" if it is acceptable).

    Parameters
    ----------
    frame : StateFrame
        ``angles`` (L,) rad (leg lengths, m, for prismatic legs), ``wrench`` (6,) N, N·m.
    L : int
        Number of legs of the scene.
    safety : SafetyLimits
        ``max_angle`` rad, ``max_force`` N, ``max_torque`` N·m.
    lo, hi : ndarray (L,) or None
        Each prismatic leg's length range, m (None: revolute, ``max_angle``).
    """
    a, w = frame.angles, frame.wrench
    if a.shape != (L,):
        return f"expected {L} encoder angles, got {a.shape[0]}"
    finite, ma, mf, mm = reading_extremes(a, w)
    if not finite:
        return "NaN or inf in the reading"
    if lo is not None:
        out = (a < lo) | (a > hi)
        if out.any():
            i = int(np.argmax(out))
            return (f"leg {i + 1} length {a[i]:.6g} m outside its range "
                    f"[{lo[i]:g}, {hi[i]:g}] m")
    elif ma > safety.max_angle:
        return f"encoder angle {ma:.3g} rad beyond ±{safety.max_angle} rad"
    if mf > safety.max_force or mm > safety.max_torque:
        return "force/torque reading beyond the sensor range"
    if frame.status & STATUS_ESTOP:
        return f"device reports e-stop (status {frame.status:#06x})"
    if frame.status & STATUS_SENSOR_FAULT:
        return f"device reports a sensor fault (status {frame.status:#06x})"
    return ""


def check_limits(pd, safety, unit: str = "N·m") -> None:
    """Refuse a saturation that the controller cannot apply, as the scene loader does
    (``[pd] torque_limit`` a number > 0, ``[safety] saturation_ms`` >= 0,
    ``saturation_share`` in (0, 1], all finite), for a :class:`.config.PDGains` and
    :class:`.config.SafetyLimits` built in Python (``dataclasses.replace`` skips the
    loader).  InputError naming the field and the value, in ``unit`` for the limit.

    Without it a negative ``torque_limit`` made every cycle "saturated" and multiplied
    its efforts by ``limit / peak < 0``: each command reversed, at the limit's size (a
    servo pushing away from its set point; the Octo fell 0.17 m in 0.3 s), and a NaN
    one (every ``peak > limit`` False) switched the saturation off; a NaN
    ``saturation_ms`` or ``saturation_share`` switched the watch for a saturated
    oscillation off (:class:`SaturationWatch`), a negative share let it trip on sign
    reversals alone."""
    def real(v):
        return (isinstance(v, (int, float, np.integer, np.floating))
                and not isinstance(v, bool) and math.isfinite(v))

    lim, ms, share = pd.torque_limit, safety.saturation_ms, safety.saturation_share
    if not (real(lim) and lim > 0):
        raise InputError(f"expected a positive finite number (the saturation of every "
                         f"command), got {lim!r} {unit}", field="pd.torque_limit")
    if not (real(ms) and ms >= 0):
        raise InputError(f"expected a finite number >= 0 (0: no watch), got {ms!r} ms",
                         field="safety.saturation_ms")
    if not (real(share) and 0 < share <= 1):
        raise InputError(f"expected a share of the cycles in (0, 1], got {share!r}",
                         field="safety.saturation_share")


class DeviceStatus:
    """Counts of the frames with the device's ``DEVICE_WATCHDOG`` (the device zeroed its
    torques: no command in time) and ``SATURATED`` (a drive limited the commanded
    torque) bits, and the rate limit of their events.

    :meth:`note` returns the events to log: ``(name, frames)`` at most once per
    ``interval_us`` of device time per bit, ``frames`` the frames with the bit since the
    last event of that bit (the first frame with the bit always gives one).
    """

    BITS = ((STATUS_DEVICE_WATCHDOG, "device_watchdog"), (STATUS_SATURATED, "device_saturated"))
    MASK = STATUS_DEVICE_WATCHDOG | STATUS_SATURATED

    def __init__(self, interval_us: int = 1_000_000):
        self.interval_us = interval_us
        self.frames = {name: 0 for _, name in self.BITS}
        self._last = {}          # name -> (t_us, frames) of its last event

    def note(self, status: int, t_us: int) -> list:
        """Count a frame's ``status`` bits at device time ``t_us`` µs; the events due."""
        due = []
        for bit, name in self.BITS:
            if not status & bit:
                continue
            n = self.frames[name] = self.frames[name] + 1
            last = self._last.get(name)
            if last is None or not 0 <= t_us - last[0] < self.interval_us:
                self._last[name] = (t_us, n)
                due.append((name, n - (0 if last is None else last[1])))
        return due


class SaturationWatch:
    """A loop oscillating at the torque limit: over the last ``window_us`` of device
    time (``safety.saturation_ms``; 0 switches the watch off) at least the share
    ``share`` of the cycles saturated (``safety.saturation_share``, default 0.5), and
    the saturated commands reversing sign at least :data:`MIN_REVERSALS` times in it.

    A limit cycle (a loop made unstable by delay or gains: the linearised loop of
    :mod:`.delay_margin` grows until the limit holds it; Kühne et al. Sec. III-D's PD
    with its 700 ms derivative filter damps little) swings the commands from one limit
    to the other, with a few unsaturated cycles at each crossing; a hand pushing
    steadily into a stiff wall saturates the drives too, but with commands of one sign,
    and is left alone.  A reversal: a joint whose command is at least a quarter of the
    cycle's largest (a joint that carries the swing, not one near zero that noise
    flips) has the opposite sign of its command in the last saturated cycle.  The
    window slides (each cycle enters with its device time and leaves ``window_us``
    later), so unsaturated cycles between the swings do not start the count again; it
    is judged once ``window_us`` has passed since the last :meth:`reset` (the start of
    torque control).  :meth:`note` returns True when the rule is met.
    """

    #: a joint's command counts for the reversals from this share of the cycle's peak
    SIGNIFICANT = 0.25

    def __init__(self, window_us: float, share: float = 0.5):
        self.window_us = float(window_us)
        self.share = float(share)
        self.reset()

    def reset(self) -> None:
        """Start the count again (after a fault, or when torque control (re)starts)."""
        self.since_us = None
        self._cycles = deque()           # (t_us, saturated, reversed) in the window
        self.saturated = 0               # saturated cycles in the window
        self.reversals = 0               # reversals in the window
        self.sign = None                 # the signs of the last saturated cycle

    def note(self, t_us: int, saturated: bool, tau) -> bool:
        """Count a cycle at device time ``t_us`` µs with commands ``tau`` (L,)."""
        if self.window_us <= 0:
            return False
        if self.since_us is None:
            self.since_us = t_us
        rev = False
        if saturated:
            tau = np.asarray(tau, dtype=float)
            a = np.abs(tau)
            sign = np.where(a >= self.SIGNIFICANT * a.max(), np.sign(tau), 0.0)
            rev = self.sign is not None and bool(np.any(sign * self.sign < 0))
            self.sign = sign
        cyc = self._cycles
        cyc.append((t_us, bool(saturated), rev))
        self.saturated += bool(saturated)
        self.reversals += rev
        while cyc and cyc[0][0] <= t_us - self.window_us:
            _, s, r = cyc.popleft()
            self.saturated -= s
            self.reversals -= r
        return (t_us - self.since_us >= self.window_us
                and self.saturated >= self.share * len(cyc)
                and self.reversals >= MIN_REVERSALS)
