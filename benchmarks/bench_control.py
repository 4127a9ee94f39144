"""Control loop: compute time per cycle (L = 8 and L = 6) and the rate achieved over a pty.

Issue 7 target: compute p99 under 0.5 ms for L = 8, so that 1 kHz is sustainable in
Python.  Three measurements:

1. compute per cycle in-process (:func:`distkin.control.loopback.run_loopback`, the
   example scene, 3 s of device time = 3000 cycles): everything the controller does
   between a state frame's bytes and the command frame's bytes, decode and encode
   included, p50/p99/max;
2. the parts of one cycle, timed interleaved (medians);
3. the closed loop between two processes over a real pty (``distkin control --sim``):
   cycle rate, period p50/p99 and compute p50/p99, lock-stepped and free-running.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from .harness import fmt_time, interleaved

__all__ = ["TITLE", "DEFAULT", "run"]

TITLE = "Control loop: compute per cycle and rate over a pty"
DEFAULT = True

ROOT = Path(__file__).resolve().parent.parent


def _scene(preset: str):
    from distkin.app.control_commands import builtin_scene
    import dataclasses
    sc = builtin_scene()
    return dataclasses.replace(sc, preset=preset)


def _loopback(preset: str, seconds: float = 3.0, compiled: bool = True):
    from distkin.control.kinematics import load_model
    from distkin.control.loopback import run_loopback
    sc = _scene(preset)
    model = load_model(preset, compiled=compiled)
    run_loopback(sc, model, 0.2)                      # warm up (imports, caches)
    r = run_loopback(sc, model, seconds)
    c = r["compute_s"] * 1e3
    cpu = r["compute_cpu_s"] * 1e3
    return {"L": model.L, "cycles": int(c.size), "p50_ms": float(np.percentile(c, 50)),
            "p99_ms": float(np.percentile(c, 99)), "max_ms": float(c.max()),
            "cpu_p50_ms": float(np.percentile(cpu, 50)),
            "cpu_p99_ms": float(np.percentile(cpu, 99))}


def _parts(compiled: bool = True):
    from distkin.control.controller import Controller
    from distkin.control.kinematics import load_model
    from distkin.control.protocol import FrameDecoder, encode_command, encode_state
    sc = _scene("octo")
    model = load_model("octo", compiled=compiled)
    ctl = Controller(sc, model)
    pose = model.home + np.array([0.01, -0.02, 0.015, 0.1, -0.05, 0.08])
    q, _ = model.ik(pose)
    guess = pose + 1e-5
    J = model.jacobian(pose)
    wire = encode_state(1, 1000, 0, q, np.zeros(6))
    dec = FrameDecoder()
    frame = dec.feed(wire)[0]
    ctl.compute(frame, 1e-3)
    w = np.array([0.5, 1.0, -0.2, 0, 0, 0])
    competitors = {
        "whole cycle (compute)": lambda: ctl.compute(frame, 1e-3),
        "decode state + encode command": lambda: (dec.feed(wire),
                                                  encode_command(1, 1, 1, q)),
        "FK, warm start (Gauss-Newton)": lambda: model.forward(q, guess),
        "IK (scalar kernel)": lambda: model.ik(pose),
        "Jacobian (scalar kernel)": lambda: model.jacobian(pose),
        "sigma_min guard (eigenvalues)": lambda: ctl.sigma_min(J),
        "admittance step": lambda: ctl.adm.propose(w, 1e-3),
        "distribution solve (numpy)": lambda: J @ np.linalg.solve(J.T @ J, J.T @ q),
    }
    if compiled:
        ck = model.compiled
        out = np.empty(model.L)
        competitors["distribution solve (compiled)"] = lambda: ck.project(
            J, q, np.zeros(6), out)
        prm, env = ctl._fused
        buf = np.empty(model.L + 27)
        pd = np.zeros((5, model.L))
        z = np.zeros(6)
        competitors["fused cycle kernel alone (steps 2-8, one call)"] = lambda: ck.cycle(
            frame.angles, frame.wrench, 1e-3, True, True, ctl.pose, pose, z, pd, prm, env,
            buf)
        py = Controller(sc, model, fused=False)
        py.compute(frame, 1e-3)
        competitors["whole cycle, Python steps on the compiled kernels"] = \
            lambda: py.compute(frame, 1e-3)
    return interleaved(competitors, rounds=15, number=200)


def _pty(lockstep: bool, seconds: float = 3.0, rate_hz: int = 1000):
    load_before = os.getloadavg()[:2]
    with tempfile.TemporaryDirectory() as d:
        text = (ROOT / "examples" / "control_octo.toml").read_text(encoding="utf-8")
        if not lockstep:
            text = text.replace("[simulator]\n", "[simulator]\nlockstep = false\n")
        if rate_hz != 1000:
            text = text.replace("rate_hz = 1000 ", f"rate_hz = {rate_hz} ", 1)
        scene = Path(d) / "scene.toml"
        scene.write_text(text, encoding="utf-8")
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
        proc = subprocess.run([sys.executable, "-m", "distkin", "control", "--sim", "--scene",
                               str(scene), "--seconds", str(seconds), "--json", "-"],
                              capture_output=True, text=True, cwd=ROOT, env=env,
                              timeout=120 + 4 * seconds)
        s = json.loads(proc.stdout)
    keys = ("cycles", "seconds", "device_seconds", "rate_hz", "cycle_p50_ms", "cycle_p99_ms",
            "cycle_max_ms", "cycle_cpu_p50_ms", "cycle_cpu_p99_ms", "period_p50_ms",
            "period_p99_ms", "period_max_ms", "bad_frames", "stale_frames", "timeouts",
            "watchdog_trips", "gc_collections", "exit_reason")
    out = {k: s[k] for k in keys}
    out["rate_set_hz"] = rate_hz
    out["load"] = os.getloadavg()[:2]
    out["load_before"] = load_before
    return out


def _load():
    one, five, _ = os.getloadavg()
    return f"{one:.2f} / {five:.2f}"


def run():
    load0 = _load()
    data = {"loopback": {p: _loopback(p) for p in ("octo", "octopod", "hunt")}}
    data["loopback_reference"] = {"octo": _loopback("octo", compiled=False)}
    data["parts_s"] = _parts()
    data["parts_reference_s"] = _parts(compiled=False)
    load1 = _load()
    data["pty"] = {"lockstep": _pty(True), "free_run": _pty(False)}
    data["pty_4khz"] = {"lockstep": _pty(True, 10.0, 4000), "free_run": _pty(False, 10.0, 4000)}
    data["load"] = {"loopback": [load0, load1], "end": _load()}
    lb = data["loopback"]
    rows = "\n".join(f"| {p} | {v['L']} | {v['cycles']} | {v['p50_ms']:.3f} ms | "
                     f"{v['p99_ms']:.3f} ms | {v['max_ms']:.2f} ms | {v['cpu_p50_ms']:.3f} ms | "
                     f"{v['cpu_p99_ms']:.3f} ms |" for p, v in lb.items())
    parts = data["parts_s"]
    whole = parts["whole cycle (compute)"]
    prow = "\n".join(f"| {n} | {fmt_time(t)} | {t / whole:.2f} |" for n, t in parts.items())
    pty = data["pty"]
    trow = "\n".join(
        f"| {m} | {v['cycles']} in {v['seconds']:.2f} s | {v['rate_hz']:.0f} Hz | "
        f"{v['period_p50_ms']:.3f} / {v['period_p99_ms']:.3f} ms | "
        f"{v['cycle_p50_ms']:.3f} / {v['cycle_p99_ms']:.3f} ms | {v['stale_frames']} | "
        f"{v['watchdog_trips']} |" for m, v in pty.items())
    ref = data["loopback_reference"]["octo"]
    rows += (f"\n| octo, reference kinematics (Python + numpy, before issue 17) | {ref['L']} | "
             f"{ref['cycles']} | {ref['p50_ms']:.3f} ms | {ref['p99_ms']:.3f} ms | "
             f"{ref['max_ms']:.2f} ms | {ref['cpu_p50_ms']:.3f} ms | {ref['cpu_p99_ms']:.3f} ms |")
    pref = data["parts_reference_s"]
    prow_ref = "\n".join(f"| {n} | {fmt_time(t)} | {fmt_time(parts[n]) if n in parts else '-'} "
                         f"| {t / parts[n]:.1f}× |" if n in parts else f"| {n} | {fmt_time(t)} | - | - |"
                         for n, t in pref.items())
    p4 = data["pty_4khz"]
    row4 = "\n".join(
        f"| {m} | {v['cycles']} in {v['seconds']:.2f} s | {v['rate_hz']:.0f} Hz | "
        f"{v['period_p50_ms']:.3f} / {v['period_p99_ms']:.3f} ms | "
        f"{v['cycle_p50_ms']:.3f} / {v['cycle_p99_ms']:.3f} ms | {v['stale_frames']} | "
        f"{v['watchdog_trips']} | {v['load'][0]:.2f} / {v['load'][1]:.2f} |" for m, v in p4.items())
    octo = lb["octo"]
    verdict = "meets" if octo["cpu_p99_ms"] <= 0.1 else "misses"
    text = f"""Target (issue 17): compute p99 <= 0.1 ms in-process for L = 8 (issue 7's was
< 0.5 ms for 1 kHz).  The Octo's cycle (L = 8) **{verdict}** it in CPU time: p50
{octo['cpu_p50_ms']:.3f} ms, p99 {octo['cpu_p99_ms']:.3f} ms (reference kinematics in
the same run: p50 {ref['cpu_p50_ms']:.3f} ms, p99 {ref['cpu_p99_ms']:.3f} ms); in wall
time p50 {octo['p50_ms']:.3f} ms, p99 {octo['p99_ms']:.3f} ms (the wall-time tail
includes preemption by other processes on this shared 2-core machine).  Load average
(1 / 5 min) {load0} before the in-process runs, {load1} after.

The kinematics of the cycle are compiled (`distkin/control/cycle_kernels.py`: the
generated scalar kernels under numba, the Gauss-Newton FK, the σ guard, the torque
projection, the spring and SO(3) step, the reading checks); `KinematicModel(compiled=
False)` is the reference route, and tests/control/test_cycle_kernels.py holds the two
together (kernels bit for bit, FK to 1e-13, a 0.5 s closed loop to 1e-9).

**Compute per cycle, in-process** (`run_loopback`, example scene, 3 s of device time;
state-frame decode, checks, FK, admittance, guard, IK, PD, distribution, saturation,
command encode; wall time and the thread's CPU time):

| preset | L | cycles | wall p50 | wall p99 | wall max | CPU p50 | CPU p99 |
|---|---|---|---|---|---|---|---|
{rows}

**Parts of one cycle** (Octo, medians of 15 interleaved rounds of 200 calls; the parts
overlap -- the whole cycle calls the kernels more than once):

| part | median | share of a cycle |
|---|---|---|
{prow}

The same parts with the reference kinematics (Python + numpy), same run:

| part | reference | compiled | ratio |
|---|---|---|---|
{prow_ref}

**Closed loop over a pty between two processes** (`distkin control --sim`, 3 s; the
simulator paces itself at 1 kHz; lock-stepped = it waits for each answer before
advancing the physics):

| simulator | cycles | rate | period p50 / p99 | compute p50 / p99 | stale frames | watchdog trips |
|---|---|---|---|---|---|---|
{trow}

**4 kHz over the pty, 10 s** (the same scene with `rate_hz = 4000` in `[device]`; the
CLI reads the rate from the scene, 1 kHz stays the default; `python -m distkin control
--sim --scene SCENE --seconds 10 --json -`):

| simulator | cycles | rate | period p50 / p99 | compute p50 / p99 | stale frames | watchdog trips | load (1 / 5 min) at the end |
|---|---|---|---|---|---|---|---|
{row4}

What limits it now.  In-process, the compiled kinematics (FK, IK, J, guard,
projection) are about a fifth of the cycle; what is left is Python around them: frame
decode and encode (CRC, COBS; about a third), the admittance step's numpy on 6-vectors,
the PD filter and the controller's bookkeeping, with a tail (p99 about twice the
median) from cache and scheduling effects of the shared machine -- the tail is the same
with the garbage collector off or frozen (measured while writing this).  A compute p99
safely under 0.1 ms needs the rest of the cycle (decode, admittance, PD, encode)
compiled as one kernel, not done this round.  Over the pty at 4 kHz the loop does not
reach 4 kHz: the lock-stepped period is the controller's compute over the link plus
the simulator's own Python step, two pty transfers and two process wake-ups on 2 cores
(the load at the end of each run is in the table: on a quiet machine, load below 1, the
lock-stepped loop still stays under 3 kHz); the free-running simulator
shows the same limit as stale frames, and a late wake-up can trip the 20 ms watchdog.
1 kHz stays the default; at 1 kHz the period p99 is set by the operating system's
scheduling of the two processes, not by the compute time.
"""
    return text, data
