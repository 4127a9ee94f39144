"""No command frame carries a NaN or an infinite torque (docs/protocol.md: every
``torques`` value on the wire is a finite float32, in every mode).

QA: ``protocol.encode_command`` and the compiled ``frame_codec.command_encoder()`` sent
NaN, inf, and 1e40 (inf as float32) torques to the device; ``run_loopback`` passed a
diverged controller's NaN on; a negative or NaN ``[pd] torque_limit`` built in Python
(``dataclasses.replace`` skips the loader) reversed every command or switched the
saturation off.  The expectations come from the documented rule, from numpy's own
float32 cast (the independent judge of what float32 cannot hold finite, not the
encoders' threshold) and from the scene loader's refusals.  The device side keeps
decoding such frames (another host may send them) and applies zero effort on those
joints; state frames keep carrying NaN readings (the host rejects those frames).
"""

import dataclasses
import struct
import time
import zlib

import numpy as np
import pytest

from distkin.control import frame_codec as fc
from distkin.control.config import builtin_scene, loads_control_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.link import Link
from distkin.control.loopback import run_loopback
from distkin.control.plant import Plant
from distkin.control.protocol import (MODE_NAMES, MODE_RUN, TYPE_COMMAND, VERSION,
                                      CommandFrame, FrameDecoder, cobs_decode, cobs_encode,
                                      decode_payload, encode_command, encode_readings)
from distkin.errors import InputError

from control_helpers import scene_text

ENCODERS = {"reference": encode_command, "compiled": fc.command_encoder()}
_EDGE = 2.0 ** 128 - 2.0 ** 103            # float32's rounding midpoint to inf
CANDIDATES = [np.nan, np.inf, -np.inf, 1e40, -1e300, _EDGE, -_EDGE,
              float(np.nextafter(_EDGE, 0.0)), -float(np.nextafter(_EDGE, 0.0)),
              3.4028235e38, 3.5e38, 1e38, 0.0, -2.5]


def _float32_finite(x) -> bool:
    with np.errstate(over="ignore"):
        return bool(np.isfinite(np.float32(x)))


def _raw_command(seq, tau) -> bytes:
    """A command frame on the wire built from docs/protocol.md's layout by hand (not by
    the encoders, which refuse what it may hold)."""
    t = np.asarray(tau, dtype="<f4")
    body = struct.pack("<IIBBB", seq, 0, MODE_RUN, 0, t.size) + t.tobytes()
    payload = struct.pack("<BBH", VERSION, TYPE_COMMAND, len(body)) + body
    return cobs_encode(payload + struct.pack("<I", zlib.crc32(payload))) + b"\x00"


def test_both_encoders_refuse_exactly_what_float32_cannot_carry_finite():
    # the rounding midpoint itself goes to inf, the float64 just below it does not
    assert not _float32_finite(_EDGE) and _float32_finite(np.nextafter(_EDGE, 0.0))
    for x in CANDIDATES:
        for j in (0, 5):
            tau = np.linspace(-1.0, 1.0, 8)
            tau[j] = x
            for mode in MODE_NAMES:
                errors, frames = [], []
                for name, enc in ENCODERS.items():
                    if _float32_finite(x):
                        frames.append(enc(9, 8, mode, tau, 0))
                        continue
                    with pytest.raises(InputError) as exc:
                        enc(9, 8, mode, tau, 0)
                    e = exc.value
                    assert e.field == f"torques[{j}]", name
                    assert f"got {float(x)!r} at joint {j}" in e.message, name
                    errors.append(str(e))
                assert len(set(errors)) <= 1           # the same error on both routes
                if frames:
                    assert frames[0] == frames[1]
                    got = decode_payload(cobs_decode(frames[0][:-1])).torques[j]
                    assert got == float(np.float32(x)) and np.isfinite(got)
    # lists and float32 arrays take the reference route: the same refusal
    for bad in ([0.5, float("nan"), 0.1], np.array([0.5, 0.2, np.inf], dtype=np.float32)):
        msgs = set()
        for enc in ENCODERS.values():
            with pytest.raises(InputError) as exc:
                enc(1, 0, MODE_RUN, bad)
            msgs.add(str(exc.value))
        assert len(msgs) == 1


def test_state_frames_still_carry_nan_readings():
    """Fault injection of NaN readings (tests/control/test_safety_faults.py) needs it."""
    vals = np.concatenate([[0.1, np.nan, 0.3], [1.0, np.inf, 0, 0, 0, -np.inf]])
    wire = encode_readings(3, 1000, 0, vals)
    assert fc.state_encoder()(3, 1000, 0, vals) == wire
    frame = decode_payload(cobs_decode(wire[:-1]))
    assert np.isnan(frame.angles[1]) and frame.wrench[1] == np.inf


def test_a_refused_command_writes_nothing():
    with Link("loop://") as link:
        tau = np.zeros(8)
        tau[3] = np.nan
        with pytest.raises(InputError) as exc:
            link.write_command(CommandFrame(1, 0, MODE_RUN, 0, tau))
        assert exc.value.field == "torques[3]"
        assert (link.stats.frames_out, link.stats.bytes_out) == (0, 0)
        assert link._ser.in_waiting == 0              # loop:// echoes what was written


class _OneRead:
    """A transport that delivers ``data`` once, then nothing."""
    fd = None

    def __init__(self, data):
        self.data = data

    def wait_readable(self, timeout):
        return bool(self.data)

    def read(self):
        data, self.data = self.data, b""
        return data

    def client_attached(self):
        pass


@pytest.mark.parametrize("compiled", [True, False], ids=["compiled", "python"])
def test_the_device_decodes_a_nonfinite_command_and_applies_zero_effort(compiled):
    from distkin.control.simulator import Simulator
    scene = builtin_scene()
    model = load_model("octo", compiled=compiled)
    tau = np.linspace(-0.2, 0.2, model.L)
    tau[2], tau[6] = np.nan, -np.inf
    wire = _raw_command(7, tau)
    for dec in (FrameDecoder(), FrameDecoder(fast=fc.command_decoder())):
        (cmd,) = dec.feed(wire)                   # decoded, not dropped as a bad frame
        assert np.isnan(cmd.torques[2]) and cmd.torques[6] == -np.inf
    sim = Simulator(scene, model, _OneRead(wire))
    sim._collect(None, time.perf_counter())
    assert sim.commands == 1 and np.isnan(sim.command.torques[2])
    sim._step(1, False)
    # the same step under the command with zeros on those joints (a second plant)
    ref = Plant(model, scene.simulator.motors, scene.simulator.hand, seed=scene.simulator.seed)
    ref.step(np.where(np.isfinite(tau), tau.astype(np.float32), 0.0), MODE_RUN, sim.period)
    assert sim.plant.tau[2] == 0.0 and sim.plant.tau[6] == 0.0
    np.testing.assert_array_equal(sim.plant.tau, ref.tau)
    np.testing.assert_array_equal(sim.plant.pose, ref.pose)
    ev = [e for e in sim.events.events if e["event"] == "nonfinite_command"]
    assert len(ev) == 1 and ev[0]["seq"] == 7 and sim.plant.nonfinite_commands == 1


@pytest.fixture(scope="module")
def model():
    return load_model("octo")


@pytest.mark.parametrize("table, key, value", [
    ("pd", "torque_limit", "nan"), ("pd", "torque_limit", "-0.5"), ("pd", "torque_limit", "0"),
    ("pd", "torque_limit", "inf"), ("safety", "saturation_ms", "nan"),
    ("safety", "saturation_ms", "-1"), ("safety", "saturation_ms", "inf"),
    ("safety", "saturation_share", "nan"), ("safety", "saturation_share", "-0.1"),
    ("safety", "saturation_share", "0"), ("safety", "saturation_share", "1.5")])
def test_a_saturation_the_loader_refuses_is_refused_by_the_controller(model, table, key,
                                                                      value):
    with pytest.raises(InputError) as want:        # the loader: the reference
        loads_control_scene(scene_text(**{key: value}), "s.toml")
    assert want.value.field == f"{table}.{key}"
    s = builtin_scene()
    v = float(value)
    s = dataclasses.replace(s, **{table: dataclasses.replace(getattr(s, table), **{key: v})})
    for fused in (True, False):
        with pytest.raises(InputError) as got:
            Controller(s, model, fused=fused)
        assert got.value.field == want.value.field and repr(v) in got.value.message


def test_a_saturation_the_loader_takes_is_taken(model):
    s = builtin_scene()
    for table, key, v in (("pd", "torque_limit", 1e-3), ("safety", "saturation_ms", 0.0),
                          ("safety", "saturation_share", 1.0)):
        loads_control_scene(scene_text(**{key: repr(v)}), "s.toml")
        Controller(dataclasses.replace(
            s, **{table: dataclasses.replace(getattr(s, table), **{key: v})}), model)


@pytest.mark.parametrize("fused", [True, False])
def test_the_loopback_sends_zero_torque_for_a_nonfinite_effort(model, fused):
    """kd = 0 and T = 0.1 ms at 1 kHz: the derivative filter diverges (its forward-Euler
    eigenvalue 1 - h/T = -9, test_nonfinite_and_fault_time.py) and the cycle's efforts
    become NaN after about 330 cycles."""
    s = builtin_scene()
    s = dataclasses.replace(s, pd=dataclasses.replace(s.pd, kd=0.0, derivative_filter_s=1e-4))
    with np.errstate(all="ignore"):                # the reference route overflows
        r = run_loopback(s, model, 0.35, controller=Controller(s, model, fused=fused))
    bad = r["nonfinite"]
    assert bad.any() and not bad[:100].any()
    assert np.all(np.isfinite(r["tau_cmd"]))
    assert not np.any(r["tau_cmd"][bad])           # zero torque on those cycles
