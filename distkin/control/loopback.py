"""In-process closed loop: the controller and the simulated device in one process.

The same :class:`~.controller.Controller` and :class:`~.plant.Plant` as over a serial
link, with the frames still encoded and decoded by :mod:`.protocol` (float32 values,
CRC), but no I/O and no wall clock: each device period the plant sends a state frame,
the controller answers, and the answer is applied during the next period (the
one-sample delay of a 1 kHz loop whose computation fits in the period).  Used to design
scenes, by the benchmark (compute time per cycle without I/O) and by fast tests.
"""

from __future__ import annotations

import time

import numpy as np

from .controller import Controller
from .plant import Plant
from .protocol import (MODE_ZERO_TORQUE, FrameDecoder, encode_command, encode_state)

__all__ = ["run_loopback"]


def run_loopback(scene, model, seconds: float, *, controller=None, record=True,
                 fast_decode=None):
    """Simulate ``seconds`` of device time.

    Parameters
    ----------
    scene : ControlScene
    model : KinematicModel
    seconds : float
    controller : Controller, optional
        Reuse one (for example with a log prefix).
    fast_decode : bool, optional
        Decode the state frames by the compiled decoder (default: with a compiled
        model) or by the Python route.

    Returns
    -------
    dict
        ``t`` (n,), ``pose`` (n, 6) true poses, ``desired`` (n, 6), ``estimate`` (n, 6),
        ``hand`` (n, 3) hand force (N), ``tau`` (n, L) applied torques, ``compute_s``
        (n,) controller wall time per cycle (from the state frame's bytes to the command
        frame's bytes: decode, checks, the cycle, encode), ``compute_cpu_s`` (n,) its CPU time (the
        thread's; not inflated when another process preempts this one), ``refused``
        (n,) bool, ``tau_cmd`` (n, L) the commands as received by the device.
    """
    ctl = controller or Controller(scene, model)
    plant = Plant(model, scene.simulator.motors, scene.simulator.hand, seed=scene.simulator.seed)
    dt = 1.0 / scene.rate_hz
    fast = None
    if fast_decode is None:                        # the compiled route decodes fast too
        fast_decode = model.compiled is not None
    if fast_decode:
        from .cycle_kernels import state_decoder
        fast = state_decoder()
    dec_host, dec_dev = FrameDecoder(state_decoder=fast), FrameDecoder()
    mode, tau = MODE_ZERO_TORQUE, np.zeros(model.L)
    n = int(round(seconds / dt))
    out = {k: [] for k in ("t", "pose", "desired", "estimate", "hand", "tau", "compute_s",
                           "refused", "tau_cmd", "compute_cpu_s")}
    for k in range(n):
        wire = encode_state(k + 1, int(round(plant.t * 1e6)), plant.status(),
                            plant.encoders(), plant.sensor())
        t0 = time.perf_counter()
        c0 = time.thread_time()
        frame = dec_host.feed(wire)[0]
        why = ctl.check_reading(frame)
        if why:
            res_mode, res_tau, res = MODE_ZERO_TORQUE, np.zeros(model.L), None
        else:
            res = ctl.compute(frame, dt)
            res_mode, res_tau = (mode, tau) if res.mode is None else (res.mode, res.torques)
        wire = encode_command(k + 1, frame.seq, res_mode, res_tau)
        t1 = time.perf_counter()
        c1 = time.thread_time()
        cmd = dec_dev.feed(wire)[0]
        mode, tau = cmd.mode, cmd.torques
        plant.step(tau, mode, dt)
        if record:
            out["t"].append(plant.t)
            out["pose"].append(plant.pose.copy())
            out["desired"].append(ctl.adm.pose.copy())
            out["estimate"].append(ctl.pose.copy())
            out["hand"].append(plant.hand_wrench[:3].copy())
            out["tau"].append(plant.tau.copy())
            out["tau_cmd"].append(np.asarray(tau).copy())
            out["compute_s"].append(t1 - t0)
            out["compute_cpu_s"].append(c1 - c0)
            out["refused"].append(res is not None and not res.accepted)
    return {k: np.asarray(v) for k, v in out.items()}
