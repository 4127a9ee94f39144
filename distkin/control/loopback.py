"""In-process closed loop: the controller and the simulated device in one process.

The same :class:`~.controller.Controller` and :class:`~.plant.Plant` as over a serial
link, with the frames still encoded and decoded (float32 values, CRC; by
:mod:`.frame_codec` or by the reference :mod:`.protocol`), but no I/O and no wall clock: each device period the plant sends a state frame,
the controller answers, and the answer is applied during the next period (the
one-sample delay of a 1 kHz loop whose computation fits in the period).  Used to design
scenes, by the benchmark (compute time per cycle without I/O) and by fast tests.
"""

from __future__ import annotations

import time
from collections import deque

import numpy as np

from ..errors import InputError
from .controller import Controller
from .plant import Plant
from .protocol import (F32_OVERFLOW, MODE_ZERO_TORQUE, FrameDecoder, encode_command,
                       encode_readings)

__all__ = ["run_loopback"]


def run_loopback(scene, model, seconds: float, *, controller=None, record=True,
                 fast_codec=None, delay_periods: int = 0):
    """Simulate ``seconds`` of device time.

    Parameters
    ----------
    scene : ControlScene
    model : KinematicModel
    seconds : float
        Device time, s: a positive finite number (InputError naming ``seconds``
        otherwise, as ``distkin control --seconds``).
    controller : Controller, optional
        Reuse one (for example with a log prefix).
    fast_codec : bool, optional
        Encode and decode the frames by the compiled codec (default: with a compiled
        model) or by the Python route.
    delay_periods : int
        Extra command delay: the device applies each command this many periods later
        than the lock-stepped loop does (zero torque until the first one arrives); the
        delay margin of :mod:`.delay_margin` is checked against it.

    Returns
    -------
    dict
        ``t`` (n,), ``pose`` (n, 6) true poses, ``desired`` (n, 6), ``estimate`` (n, 6),
        ``hand`` (n, 3) hand force (N), ``tau`` (n, L) applied torques, ``compute_s``
        (n,) controller wall time per cycle (from the state frame's bytes to the command
        frame's bytes: decode, checks, the cycle, encode), ``compute_cpu_s`` (n,) its CPU time (the
        thread's; not inflated when another process preempts this one), ``refused``
        (n,) bool, ``tau_cmd`` (n, L) the commands as received by the device,
        ``nonfinite`` (n,) bool: the cycle computed an effort that is NaN, inf or beyond
        float32 (no frame carries it, :func:`.protocol.check_efforts`) and sent zero
        torque instead, as :func:`.loop.run_loop` does (which also enters the fault
        state; here the next cycle computes again, as after a rejected reading).
    """
    if isinstance(seconds, bool) or not isinstance(seconds, (int, float, np.integer,
                                                             np.floating)) \
            or not 0 < seconds < float("inf"):
        raise InputError(f"expected a positive finite number of seconds (device time), "
                         f"got {seconds!r}", field="seconds",
                         hint="distkin control --seconds takes the same")
    ctl = controller or Controller(scene, model)
    plant = Plant(model, scene.simulator.motors, scene.simulator.hand, seed=scene.simulator.seed)
    dt = 1.0 / scene.rate_hz
    fast = fast_dev = None
    enc_state, enc_command = encode_readings, encode_command
    if fast_codec is None:                         # the compiled route codes fast too
        fast_codec = model.compiled is not None
    if fast_codec:
        from .frame_codec import (command_decoder, command_encoder, state_decoder,
                                  state_encoder)
        fast, fast_dev = state_decoder(), command_decoder()
        enc_state, enc_command = state_encoder(), command_encoder()
    dec_host, dec_dev = FrameDecoder(fast=fast), FrameDecoder(fast=fast_dev)
    mode, tau = MODE_ZERO_TORQUE, np.zeros(model.L)
    nd = int(delay_periods)
    if nd != delay_periods or nd < 0:
        raise InputError(f"expected delay_periods a whole number >= 0, got "
                         f"{delay_periods!r}", field="delay_periods")
    queue = deque([(MODE_ZERO_TORQUE, np.zeros(model.L))] * nd)
    n = int(round(seconds / dt))
    if n < 1:
        raise InputError(f"expected seconds of at least half a device period "
                         f"({dt / 2:.3g} s at {scene.rate_hz:g} Hz), got {seconds!r}",
                         field="seconds")
    out = {k: [] for k in ("t", "pose", "desired", "estimate", "hand", "tau", "compute_s",
                           "refused", "tau_cmd", "compute_cpu_s", "nonfinite")}
    for k in range(n):
        wire = enc_state(k + 1, int(round(plant.t * 1e6)), plant.status(), plant.readings())
        t0 = time.perf_counter()
        c0 = time.thread_time()
        frame = dec_host.feed(wire)[0]
        why = ctl.check_reading(frame)
        if why:
            res_mode, res_tau, res = MODE_ZERO_TORQUE, np.zeros(model.L), None
        else:
            res = ctl.compute(frame, dt)
            res_mode, res_tau = (mode, tau) if res.mode is None else (res.mode, res.torques)
        bad = not np.abs(res_tau).max() < F32_OVERFLOW       # NaN, inf: never sent
        if bad:
            res_mode, res_tau = MODE_ZERO_TORQUE, np.zeros(model.L)
        wire = enc_command(k + 1, frame.seq, res_mode, res_tau)
        t1 = time.perf_counter()
        c1 = time.thread_time()
        cmd = dec_dev.feed(wire)[0]
        mode, tau = cmd.mode, cmd.torques              # the host repeats these
        applied = (mode, tau)
        if nd:
            queue.append(applied)
            applied = queue.popleft()
        plant.step(applied[1], applied[0], dt)
        if record:
            out["t"].append(plant.t)
            out["pose"].append(plant.pose.copy())
            out["desired"].append(ctl.adm.pose.copy())
            out["estimate"].append(ctl.pose.copy())
            out["hand"].append(plant.hand_wrench[:3].copy())
            out["tau"].append(plant.tau.copy())
            out["tau_cmd"].append(np.asarray(applied[1]).copy())
            out["compute_s"].append(t1 - t0)
            out["compute_cpu_s"].append(c1 - c0)
            out["refused"].append(res is not None and not res.accepted)
            out["nonfinite"].append(bad)
    return {k: np.asarray(v) for k, v in out.items()}
