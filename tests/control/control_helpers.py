"""Helpers of the control tests: scene variants, running the CLI, the controller's estimate
against the simulator's true pose, and a scripted device on a simulated clock
(:class:`ScriptedLink`, :func:`state_frames`)."""

import os
import subprocess
import sys
import types
from pathlib import Path

import numpy as np

import distkin.control.link as link_mod
import distkin.control.loop as loop_mod
from distkin.control.link import Link, LinkStats
from distkin.control.protocol import FrameDecoder
from distkin.errors import LinkError

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "control_octo.toml"


def scene_text(**replace) -> str:
    """The example scene with some ``key = value`` lines replaced (first occurrence)."""
    lines = EXAMPLE.read_text(encoding="utf-8").splitlines()
    for key, value in replace.items():
        for i, line in enumerate(lines):
            if line.split("=")[0].strip() == key:
                lines[i] = f"{key} = {value}"
                break
        else:
            raise KeyError(key)
    return "\n".join(lines) + "\n"


def run_cli(args, cwd, timeout=600):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "distkin", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, env=env, timeout=timeout)


def robust_scene_text(**replace) -> str:
    """:func:`scene_text` with the watchdog windows (2 s) and the simulator's wait for
    each answer (1 s) widened: a loaded machine then slows a run down instead of
    changing its physics.  For tests whose subject is not the watchdog."""
    replace.setdefault("watchdog_ms", 2000)
    return widen_timing(scene_text(**replace))


def widen_timing(text: str) -> str:
    """A control scene's text with the simulator's wait for each answer (1 s) and its
    watchdog (2 s) widened, and the controller's ``watchdog_ms = 20`` (if present) made
    2000: a loaded machine slows the run instead of tripping a watchdog."""
    text = text.replace("\nwatchdog_ms = 20 ", "\nwatchdog_ms = 2000 ").replace(
        "\nwatchdog_ms = 20\n", "\nwatchdog_ms = 2000\n")
    return text.replace(
        "[simulator]\n", "[simulator]\nreply_timeout_ms = 1000\ndevice_watchdog_ms = 2000\n")


def estimate_and_truth(prefix):
    """The controller's position estimate and the simulator's true position (n, 3), m,
    of the same device states (a cycle answers the state frame of the same sequence
    number), from the logs ``PREFIX.cycles.csv`` and ``PREFIX.device.csv``."""
    from distkin.control.runlog import read_csv
    cyc, dev = read_csv(f"{prefix}.cycles.csv"), read_csv(f"{prefix}.device.csv")
    at = {int(q): i for i, q in enumerate(dev["seq"])}
    rows = [(i, at[int(q)]) for i, q in enumerate(cyc["seq"]) if int(q) in at]
    ci, di = map(np.array, zip(*rows))
    est = np.stack([cyc[f"x_{k}"][ci] for k in ("x", "y", "z")], axis=-1)
    true = np.stack([dev[f"x_{k}"][di] for k in ("x", "y", "z")], axis=-1)
    return est, true


class ScriptedLink(Link):
    """A device that plays a script through the real :class:`~distkin.control.link.Link`
    read path (decoder, sequence numbers, counters) on a simulated clock.

    ``script`` holds one item per device period: the bytes the device sends in that
    period (one or more encoded frames) or None (silence).  Every read of the link
    takes one period, so device time, the clock the loop sees (:meth:`patch` replaces
    ``time`` in :mod:`distkin.control.loop` and :mod:`distkin.control.link`) and the
    script index agree: the tests assert in device periods, never in wall time.  The
    commands are recorded as ``(tick, CommandFrame)``, ``tick`` the script index of
    the period in which the host answered.  The end of the script is a disconnect.
    """

    def __init__(self, script, period_s=1e-3):      # no port: not Link.__init__
        self.url, self.closed, self._fd = "script://", False, None
        self.poll_s, self.busy_wait_s = 0.002, 0.0
        self._ser = types.SimpleNamespace(in_waiting=0)
        self._dec, self.stats = FrameDecoder(), LinkStats()
        self._last_seq, self._missing = None, 0
        self.script, self.tick, self.period = list(script), -1, period_s
        self.commands = []

    def perf_counter(self):
        return (self.tick + 1) * self.period

    thread_time = perf_counter

    def _read_some(self, wait=0.0):        # one period a read, whatever the wait
        self.tick += 1
        if self.tick >= len(self.script):
            raise LinkError("expected a connected device, got the end of the script",
                            field="port")
        data = self.script[self.tick] or b""
        self.stats.bytes_in += len(data)
        return data

    def write_command(self, cmd):
        self.commands.append((self.tick, cmd))
        self.stats.frames_out += 1
        return True

    def close(self):
        self.closed = True

    def patch(self, monkeypatch):
        """Run the loop and the link on this device's clock; returns self."""
        clock = types.SimpleNamespace(perf_counter=self.perf_counter,
                                      thread_time=self.thread_time)
        monkeypatch.setattr(loop_mod, "time", clock)
        monkeypatch.setattr(link_mod, "time", clock)
        return self


def state_frames(model, seqs, status=0, angles=None, wrench=None):
    """Encoded state frames of ``model`` at its home pose, one per ``seqs`` entry, with
    ``t_us = 1000 seq`` (list of bytes)."""
    from distkin.control.protocol import encode_state
    a = model.ik(model.home)[0] if angles is None else np.asarray(angles, dtype=float)
    w = np.zeros(6) if wrench is None else np.asarray(wrench, dtype=float)
    return [encode_state(s, 1000 * s, status, a, w) for s in seqs]


class PlantLink(ScriptedLink):
    """The simulated device (:class:`~distkin.control.plant.Plant`: rigid platform,
    drives, encoders, sensor noise, the scene's scripted hand) behind the real link's
    read path, lock-stepped on a simulated clock: each read is one device period, in
    which the plant advances under the command the host last wrote (``delay``
    periods later: a loaded host answering late; zero torque until one arrives) and
    sends its state frame.  ``drop`` lists ``(t, n)``: the n frames from device time
    t s are not sent (``distkin sim --faults drop@t:n``); the plant moves on.  The
    run is deterministic: the same frames and physics on any machine, however loaded.
    ``trace`` holds ``(t, pose (6,), twist (6,), mode, tau (L,))`` after each step.
    """

    def __init__(self, scene, model, periods, *, drop=(), delay=0):
        super().__init__([None] * int(periods), 1.0 / scene.rate_hz)
        from distkin.control.plant import Plant
        self.plant = Plant(model, scene.simulator.motors, scene.simulator.hand,
                           seed=scene.simulator.seed)
        self.drop, self.delay = [list(d) for d in drop], int(delay)
        self.queue, self.cmd, self.seq, self.trace = [], None, 0, []

    def _read_some(self, wait=0.0):
        from distkin.control.protocol import MODE_ZERO_TORQUE, encode_readings
        self.tick += 1
        if self.tick >= len(self.script):
            raise LinkError("expected a connected device, got the end of the script",
                            field="port")
        p = self.plant
        if self.cmd is not None:           # physics starts with the first command
            self.queue.append(self.cmd)
            c = self.queue.pop(0) if len(self.queue) > self.delay else None
            mode, tau = (MODE_ZERO_TORQUE, np.zeros(p.model.L)) if c is None else \
                (c.mode, c.torques)
            p.step(tau, mode, self.period)
            self.trace.append((p.t, p.pose.copy(), p.twist.copy(), mode, p.tau.copy()))
        self.seq += 1
        for d in self.drop:
            if d[1] > 0 and p.t >= d[0] - 1e-9:
                d[1] -= 1
                return b""
        data = encode_readings(self.seq, int(round(p.t * 1e6)), p.status(), p.readings())
        self.stats.bytes_in += len(data)
        return data

    def write_command(self, cmd):
        self.cmd = cmd
        return super().write_command(cmd)
