"""The compiled frame codec (distkin.control.frame_codec) against the reference
(distkin.control.protocol): the same bytes and values, bit for bit; the plant's
compiled readings against its numpy route; the link's busy wait on a pty."""

import os
import struct
import tty
import zlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from distkin.control import frame_codec as fc
from distkin.control.config import builtin_scene, loads_control_scene
from distkin.control.kinematics import load_model
from distkin.control.link import Link
from distkin.control.plant import Plant
from distkin.control.protocol import (MAX_JOINTS, CommandFrame, FrameDecoder, cobs_decode,
                                      cobs_encode, decode_payload, encode_command,
                                      encode_readings, encode_state)
from distkin.errors import InputError

# values beyond float32 (-1e300) are sent as -inf; the reference's cast says so
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in cast:RuntimeWarning")

ENC_STATE, ENC_COMMAND = fc.state_encoder(), fc.command_encoder()
DEC_STATE, DEC_COMMAND = fc.state_decoder(), fc.command_decoder()
SPECIAL = [np.nan, np.inf, -np.inf, 0.0, -0.0, 1e-45, 3.5e38, -1e300]
#: what a command frame can carry (docs/protocol.md: finite float32 torques only), the
#: largest magnitudes whose float32 is finite included
COMMAND_SPECIAL = [0.0, -0.0, 1e-45, 3.4e38, -3.4028235e38,
                   float(np.nextafter(2.0 ** 128 - 2.0 ** 103, 0.0)), 1e-300]


def _values(rng, n, k, special=SPECIAL):
    v = rng.normal(0, 2, n)
    if k % 5 == 0:
        v[rng.integers(n)] = special[k % len(special)]
    return v


def test_state_frames_are_the_reference_bytes_and_decode_to_its_values():
    rng = np.random.default_rng(3)
    for k in range(400):
        n = int(rng.integers(1, MAX_JOINTS + 1))
        vals = np.concatenate([_values(rng, n, k), rng.normal(0, 50, 6)])
        seq = [0, 2**32 - 1, 2**32 + 7, int(rng.integers(2**32))][k % 4]
        t_us = [0, 2**64 - 1, 2**64 + 5, int(rng.integers(2**63))][k % 4]
        status = [0, 2**16 - 1, 2**16 + 3, int(rng.integers(2**16))][k % 4]
        want = encode_state(seq, t_us, status, vals[:n], vals[n:])
        assert encode_readings(seq, t_us, status, vals) == want
        assert ENC_STATE(seq, t_us, status, vals) == want
        ref = decode_payload(cobs_decode(want[:-1]))
        fast = DEC_STATE(want[:-1])
        assert (fast.seq, fast.t_us, fast.status) == (ref.seq, ref.t_us, ref.status)
        assert fast.angles.tobytes() == ref.angles.tobytes()
        assert fast.wrench.tobytes() == ref.wrench.tobytes()


def test_command_frames_are_the_reference_bytes_and_decode_to_its_values():
    rng = np.random.default_rng(4)
    for k in range(400):
        n = int(rng.integers(1, MAX_JOINTS + 1))
        tau = _values(rng, n, k, COMMAND_SPECIAL)
        if k % 3 == 0:
            tau = np.zeros(2 * n)[::2] + tau       # a strided view
        seq, ack = int(rng.integers(2**33)), int(rng.integers(2**33))
        mode, flags = k % 3, int(rng.integers(512))
        want = encode_command(seq, ack, mode, tau, flags)
        assert ENC_COMMAND(seq, ack, mode, tau, flags) == want
        ref = decode_payload(cobs_decode(want[:-1]))
        fast = DEC_COMMAND(bytearray(want[:-1]))
        assert (fast.seq, fast.ack, fast.mode, fast.flags) == \
            (ref.seq, ref.ack, ref.mode, ref.flags)
        assert all(type(x) is int for x in (fast.seq, fast.ack, fast.mode, fast.flags))
        assert fast.torques.tobytes() == ref.torques.tobytes()


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from([0, 1, 7, 255]) | st.integers(0, 255), max_size=700),
       st.integers(0, 3))
def test_cobs_stuffing_is_the_references(data, runs):
    """The kernels' COBS against protocol.cobs_encode / cobs_decode on any payload,
    long runs without a zero included (254, 255, 508 bytes: the 0xFF blocks, which
    frames of 32 joints or fewer never reach)."""
    data = bytes(data) + bytes([9]) * [0, 254, 255, 508][runs]
    out = np.empty(2 * len(data) + 8, dtype=np.uint8)
    m = fc._stuff(np.frombuffer(data, dtype=np.uint8), len(data), out)
    assert out[:m].tobytes() == cobs_encode(data) + b"\x00"
    p = np.empty(len(data) + 8, dtype=np.uint8)
    k = fc._unstuff(out[:m - 1], p)
    assert p[:k].tobytes() == cobs_decode(cobs_encode(data)) == data


def test_anything_but_a_valid_frame_goes_to_the_reference_decoder():
    """Corrupted, truncated, the other type, a mode out of range, garbage: the fast
    routes say None, so FrameDecoder counts and names them as the reference does."""
    rng = np.random.default_rng(6)
    state = encode_state(5, 1000, 0, np.zeros(8), np.zeros(6))
    cmd = encode_command(1, 5, 1, np.ones(8))
    bad_mode = bytearray(cobs_decode(cmd[:-1]))        # a mode out of range, valid CRC
    bad_mode[12] = 3
    bad_mode[-4:] = struct.pack("<I", zlib.crc32(bytes(bad_mode[:-4])))
    bad_mode = cobs_encode(bytes(bad_mode)) + b"\x00"
    for good, fast, other in ((state, DEC_STATE, cmd), (cmd, DEC_COMMAND, state)):
        flipped = bytearray(good[:-1])
        flipped[7] ^= 0x10
        for chunk in (good[:-1][:-3], bytes(flipped), b"\x05abc", other[:-1],
                      bytes(rng.integers(1, 256, 60, dtype=np.uint8)), b"\x01"):
            assert fast(chunk) is None
    assert DEC_COMMAND(bad_mode[:-1]) is None
    stream = b"".join([cmd, b"\x07garbage\x00", cmd[:9] + b"\x00", bad_mode, cmd, state, cmd])
    d_py, d_fast = FrameDecoder(), FrameDecoder(fast=DEC_COMMAND)
    out_py, out_fast = d_py.feed(stream), d_fast.feed(stream)
    assert [type(m) for m in out_py] == [type(m) for m in out_fast]
    assert (d_py.bad_frames, d_py.resyncs, d_py.reasons) == \
        (d_fast.bad_frames, d_fast.resyncs, d_fast.reasons)
    assert d_py.reasons.get("mode") == 1


def test_the_encoders_refuse_what_the_reference_refuses():
    for bad in (np.zeros(0), np.zeros(MAX_JOINTS + 1)):
        with pytest.raises(ValueError, match="joints") as want:
            encode_command(1, 0, 1, bad)
        with pytest.raises(ValueError) as got:
            ENC_COMMAND(1, 0, 1, bad)
        assert str(got.value) == str(want.value)
    with pytest.raises(ValueError, match="mode"):
        ENC_COMMAND(1, 0, 7, np.zeros(8))
    with pytest.raises(ValueError, match="joints"):
        ENC_STATE(1, 0, 0, np.zeros(6))               # the sensor values, no joint
    # lists and integer arrays take the reference route, to the same bytes
    assert ENC_COMMAND(1, 0, 1, [1, 2, 3]) == encode_command(1, 0, 1, [1, 2, 3])
    assert ENC_STATE(1, 0, 0, list(range(9))) == encode_state(1, 0, 0, [0, 1, 2],
                                                                   [3, 4, 5, 6, 7, 8])


def test_compiled_readings_are_the_plants_encoders_and_sensor():
    """Plant.readings by one compiled call against encoders() + sensor() of a plant on
    the numpy route, same seed, along a driven trajectory: the encoders equal, the
    sensor within rounding of its 3 x 3 products (|Δ| <= 1e-12 N, N·m), the noise the
    same draws."""
    sc = builtin_scene()
    fast = Plant(load_model("octo"), sc.simulator.motors, sc.simulator.hand, seed=7)
    ref = Plant(load_model("octo", compiled=False), sc.simulator.motors, sc.simulator.hand,
                seed=7)
    assert fast._ck is not None and ref._ck is None
    tau = np.array([0.3, -0.2, 0.1, 0.0, 0.2, -0.1, 0.05, 0.1])
    for k in range(Plant.NOISE_BLOCK + 40):          # across a refill of the noise block
        for p in (fast, ref):
            p.hand_wrench = np.array([1.0, -2.0, 0.5, 0.01, 0.02, -0.03])
            p.step(tau, 1, 1e-3)
        ref.pose, ref.q = fast.pose.copy(), fast.q.copy()
        a = fast.readings()
        b = np.concatenate([ref.encoders(), ref.sensor()])
        assert np.array_equal(a[:8], b[:8])
        assert np.max(np.abs(a[8:] - b[8:])) <= 1e-12
    # the noise: six standard normals per reading, scaled, as one draw each
    g = np.random.default_rng(7)
    p = Plant(load_model("octo", compiled=False), sc.simulator.motors, sc.simulator.hand,
              seed=7)
    p.hand_wrench = np.zeros(6)
    for _ in range(5):
        want = g.standard_normal(6) * np.repeat([sc.simulator.motors.force_noise,
                                                 sc.simulator.motors.torque_noise], 3)
        np.testing.assert_array_equal(p.sensor(), want + 0.0)


def _pty_pair():
    master, slave = os.openpty()
    tty.setraw(slave)
    return master, slave, os.ttyname(slave)


@pytest.mark.parametrize("busy", [0.0, 0.002])
def test_busy_wait_reads_the_same_frames_and_keeps_its_deadline(busy):
    master, slave, path = _pty_pair()
    link = Link(path, busy_wait_s=busy)
    try:
        os.close(slave)
        assert link.read_state(0.01) is None                # nothing, to the deadline:
        assert link.stats.timeouts == 1                      # counted once it has passed
        os.write(master, encode_state(3, 3000, 0, np.full(8, 0.25), np.ones(6)))
        got = link.read_state(0.5)
        assert (got.seq, got.angles.tolist()) == (3, [0.25] * 8)
        link.write_command(CommandFrame(4, 3, 1, 0, np.full(8, 0.5)))
        assert os.read(master, 4096) == encode_command(4, 3, 1, np.full(8, 0.5))
    finally:
        link.close()
        os.close(master)


def test_busy_wait_is_read_from_the_scene_and_checked():
    base = _minimal_scene()
    assert loads_control_scene(base).busy_wait_us == 0.0          # sleep at once
    sc = loads_control_scene(base.replace("[device]\n", "[device]\nbusy_wait_us = 250\n"))
    assert sc.busy_wait_us == 250.0
    for bad, why in (("-1", "-1"), ("2e6", "0 .. 1e6"), ('"fast"', "number")):
        with pytest.raises(InputError, match=why) as e:
            loads_control_scene(base.replace("[device]\n", f"[device]\nbusy_wait_us = {bad}\n"))
        assert e.value.field == "device.busy_wait_us"


def _minimal_scene():
    return ("[device]\npreset = \"octo\"\n\n[admittance]\nmass = [1, 1, 1, 0.005, 0.005, "
            "0.005]\ndamping = [15, 15, 15, 0.1, 0.1, 0.1]\n")


def test_strided_read_only_and_odd_inputs_compile_nothing_and_match_the_reference():
    """QA K 10, 11: a strided or read-only array compiled a second signature in the
    middle of a run (0.5-1 s); a float mode was accepted where the reference refuses."""
    tau = np.linspace(-1, 1, 16)
    ro = tau[:8].copy()
    ro.flags.writeable = False
    vals = np.linspace(-2, 2, 28)
    ro_vals = vals[:14].copy()
    ro_vals.flags.writeable = False
    before = (len(fc._encode_command.signatures), len(fc._encode_state.signatures))
    for t in (tau[::2], ro, tau[1::2]):
        assert ENC_COMMAND(3, 2, 1, t) == encode_command(3, 2, 1, t)
    for v in (vals[::2], ro_vals):
        assert ENC_STATE(3, 7, 0, v) == encode_readings(3, 7, 0, v)
    assert (len(fc._encode_command.signatures), len(fc._encode_state.signatures)) == before
    for mode in (1.0, "1", None):
        with pytest.raises(Exception) as want:
            encode_command(1, 2, mode, np.zeros(8))
        with pytest.raises(type(want.value)) as got:
            ENC_COMMAND(1, 2, mode, np.zeros(8))
        assert str(got.value) == str(want.value)


def test_float32_floor_is_the_largest_float32_not_above():
    from distkin.control.protocol import float32_floor
    rng = np.random.default_rng(9)
    for x in [0.3, 0.05, 2.5, 1.0, 1e-30, 3.4e38, 1e39, *rng.uniform(0, 40, 200)]:
        f = float32_floor(x)
        assert f <= x and float(np.float32(f)) == f
        with np.errstate(over="ignore"):            # above float32's largest: inf
            assert float(np.nextafter(np.float32(f), np.float32(np.inf))) > x


@pytest.mark.parametrize("fused", [True, False])
def test_saturated_commands_on_the_wire_keep_the_torque_limit(fused):
    """QA K 6: saturated at 0.3 N·m in float64, the command went out as float32(0.3) =
    0.30000001 N·m.  A limit that float32 cannot hold (0.05) and a hand pushing hard:
    every command as the device decodes it stays within the limit."""
    import dataclasses
    from distkin.control.controller import Controller
    from distkin.control.loopback import run_loopback
    sc = builtin_scene()
    sc = dataclasses.replace(sc, pd=dataclasses.replace(sc.pd, torque_limit=0.05))
    assert float(np.float32(0.05)) > 0.05
    model = load_model("octo")
    r = run_loopback(sc, model, 0.3, controller=Controller(sc, model, fused=fused))
    peak = np.max(np.abs(r["tau_cmd"]))
    assert 0.05 - 1e-8 < peak <= 0.05                 # saturated, and never above


def test_faults_take_ascii_digits_only():
    """QA K 7: '²' passed str.isdigit and int() then failed (an internal error)."""
    from distkin.control.faults import parse_faults
    for spec in ("corrupt@1:²", "drop@1:３", "drop@1:-1", "drop@1:0"):
        with pytest.raises(InputError, match="positive integer") as e:
            parse_faults(spec)
        assert e.value.field == "--faults[0]"
    assert parse_faults("drop@1:3")[0].arg == 3


def test_the_summary_says_the_port_was_polled_only_where_it_was():
    """QA K 8: over socket:// the summary claimed polling that only device files get;
    QA K 9: the refused value is quoted as given, not rounded to the bound."""
    master, slave, path = _pty_pair()
    try:
        link = Link(path, busy_wait_s=250e-6)
        assert link.polling_s == 250e-6
        link.close()
    finally:
        os.close(slave)
        os.close(master)
    with Link("loop://", busy_wait_s=250e-6) as url:
        assert url.polling_s == 0.0
    with pytest.raises(InputError, match="1000001"):
        loads_control_scene(_minimal_scene().replace("[device]\n",
                                                     "[device]\nbusy_wait_us = 1000001\n"))
