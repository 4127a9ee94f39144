"""The simulated device's clock: it keeps its schedule through a hold-up of its process.

A device with its own clock sends a state frame every period whatever the host's
scheduler does; the simulator is a process on that host, so when it is held up (a
loaded or virtual machine) the ticks it owes follow back to back until the schedule is
met, up to ``[simulator] catch_up_ms`` late; a longer hold re-bases the schedule (a
*slip*).  The wall clock is replaced by a virtual one, so that the tests are exact and
independent of the machine's load: waiting advances it by the time waited, and the
transport holds the process up by advancing it at one chosen frame.
"""

import types

import numpy as np
import pytest
from control_helpers import scene_text

from distkin.control import simulator as simmod
from distkin.control.config import loads_control_scene
from distkin.control.kinematics import model_of
from distkin.errors import InputError

PERIOD = 1e-3


class VirtualClock:
    def __init__(self):
        self.t = 100.0

    def perf_counter(self):
        return self.t


class HeldTransport:
    """No host on the other end: it records the (virtual) time of every state frame,
    holds the process up for ``hold`` s after frame ``hold_at`` and stops the
    simulator after ``frames`` frames."""

    def __init__(self, clock, frames, hold_at, hold):
        self.clock, self.frames, self.hold_at, self.hold = clock, frames, hold_at, hold
        self.times = []
        self.sim = None

    def wait_readable(self, timeout):
        self.clock.t += max(timeout, 0.0)
        return False

    def read(self):
        return b""

    def write(self, data):
        self.times.append(self.clock.t)
        if len(self.times) == self.hold_at:
            self.clock.t += self.hold
        if len(self.times) >= self.frames:
            self.sim.stop = True
        return 0

    def client_attached(self):
        pass


def _run(monkeypatch, catch_up_ms, hold, frames=400, hold_at=100):
    clock = VirtualClock()
    monkeypatch.setattr(simmod, "time", types.SimpleNamespace(perf_counter=clock.perf_counter))
    text = scene_text().replace("[simulator]\n", f"[simulator]\ncatch_up_ms = {catch_up_ms}\n")
    scene = loads_control_scene(text)
    assert scene.rate_hz == 1 / PERIOD
    tr = HeldTransport(clock, frames, hold_at, hold)
    sim = simmod.Simulator(scene, model_of(scene, compiled=False), tr)
    tr.sim = sim
    assert sim.run() == "stopped"
    return sim, np.array(tr.times) - tr.times[0]


def test_a_hold_up_shorter_than_catch_up_is_caught_up(monkeypatch):
    sim, t = _run(monkeypatch, 50, 0.020)
    k = np.arange(t.size)
    # every frame after the hold is sent as soon as the process can (back to back) and
    # no earlier than its schedule; the schedule is met again 20 periods later
    assert np.all(t >= k * PERIOD - 1e-12)
    assert t[99] == pytest.approx(99 * PERIOD)
    assert np.all(t[100:120] == pytest.approx(99 * PERIOD + 0.020))
    assert np.allclose(t[121:], k[121:] * PERIOD)
    assert sim.slips == 0 and sim.slipped == 0.0
    assert sim.late_ticks == 19         # ticks 100..118 ms; the one of 119 ms is on time
    assert sim.max_late == pytest.approx(0.020 - PERIOD)


def test_a_longer_hold_up_re_bases_the_schedule(monkeypatch):
    sim, t = _run(monkeypatch, 5, 0.020)
    k = np.arange(t.size)
    # late by 19 ms > 5 ms: one slip, and every later frame keeps the period from there
    assert sim.slips == 1
    assert sim.slipped == pytest.approx(0.020 - PERIOD)
    assert np.allclose(t[100:], k[100:] * PERIOD + sim.slipped)
    assert np.allclose(np.diff(t[100:]), PERIOD)


def test_catch_up_zero_never_catches_up(monkeypatch):
    sim, t = _run(monkeypatch, 0, 0.003)
    assert sim.slips == 1
    assert t[-1] == pytest.approx((t.size - 1) * PERIOD + 0.003 - PERIOD)


def test_catch_up_ms_must_be_a_number_at_least_zero():
    text = scene_text().replace("[simulator]\n", "[simulator]\ncatch_up_ms = -1\n")
    with pytest.raises(InputError) as exc:
        loads_control_scene(text)
    assert "simulator.catch_up_ms" in str(exc.value) and "-1" in str(exc.value)


class DroppingTransport(HeldTransport):
    """A link that takes no byte of the state frames (a host not reading: every write
    is dropped whole), and one command from the host after frame ``host_at``."""

    def __init__(self, clock, frames, host_at, L):
        super().__init__(clock, frames, hold_at=-1, hold=0.0)
        self.host_at, self.pending, self.sizes = host_at, b"", []
        from distkin.control.protocol import encode_command
        self._command = encode_command(1, 0, 1, np.zeros(L))

    def wait_readable(self, timeout):
        if self.pending:
            return True
        return super().wait_readable(timeout)

    def read(self):
        out, self.pending = self.pending, b""
        return out

    def write(self, data):
        self.sizes.append((len(data), self.sim.armed))
        super().write(data)
        if len(self.times) == self.host_at:
            self.pending = self._command
        return len(data)


def test_dropped_bytes_say_how_many_were_before_the_host(monkeypatch):
    """The closing line's dropped bytes split off those written before the host's first
    command (QA 2026-11-29: 131599 bytes "dropped" beside 0 bad frames at the host were
    the frames streamed into a pty nobody read yet), counted against the transport."""
    clock = VirtualClock()
    monkeypatch.setattr(simmod, "time", types.SimpleNamespace(perf_counter=clock.perf_counter))
    scene = loads_control_scene(scene_text())
    model = model_of(scene, compiled=False)
    tr = DroppingTransport(clock, 200, 50, model.L)
    sim = simmod.Simulator(scene, model, tr)
    tr.sim = sim
    assert sim.run() == "stopped"
    before = sum(n for n, armed in tr.sizes if not armed)
    assert sim.armed and 0 < before < sum(n for n, _ in tr.sizes)
    assert sim.dropped_before_host == before
    assert sim.dropped_bytes == sum(n for n, _ in tr.sizes)
