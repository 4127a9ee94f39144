"""Protocol framing: COBS against published vectors, round trips, CRC, resynchronisation."""

import struct
import zlib

import numpy as np
import pytest

from distkin.control.protocol import (FLAG_KEEPALIVE, MODE_HOLD, MODE_RUN, CommandFrame,
                                      FrameDecoder, ProtocolError, StateFrame, cobs_decode,
                                      cobs_encode, decode_payload, encode_command,
                                      encode_state)

# COBS examples from Cheshire & Baker (1999) as tabulated on the COBS Wikipedia page
COBS_VECTORS = [
    (b"\x00", b"\x01\x01"),
    (b"\x00\x00", b"\x01\x01\x01"),
    (b"\x00\x11\x00", b"\x01\x02\x11\x01"),
    (b"\x11\x22\x00\x33", b"\x03\x11\x22\x02\x33"),
    (b"\x11\x22\x33\x44", b"\x05\x11\x22\x33\x44"),
    (b"\x11\x00\x00\x00", b"\x02\x11\x01\x01\x01"),
    (bytes(range(1, 255)), b"\xff" + bytes(range(1, 255)) + b"\x01"),
]


@pytest.mark.parametrize("raw, enc", COBS_VECTORS)
def test_cobs_published_vectors(raw, enc):
    # the 254-byte case: our encoder appends the (valid, non-minimal) trailing 0x01
    # group; the published minimal form omits it -- both decode to the same bytes
    assert cobs_encode(raw) == enc
    assert cobs_decode(enc) == raw
    if len(raw) == 254:
        assert cobs_decode(enc[:-1]) == raw


def test_cobs_round_trip_random():
    rng = np.random.default_rng(3)
    for n in (0, 1, 253, 254, 255, 600):
        raw = rng.integers(0, 4, n, dtype=np.uint8).tobytes()   # many zeros
        enc = cobs_encode(raw)
        assert b"\x00" not in enc
        assert cobs_decode(enc) == raw


def test_state_frame_round_trip_and_layout():
    angles = np.array([0.0, 0.1, -0.2, 0.3, 1.5, -1.5, 2.5, -3.0])
    wrench = np.array([1.5, -2.0, 3.25, 0.01, -0.02, 0.03])
    wire = encode_state(5, 123456789, 0x0008, angles, wrench)
    assert wire.endswith(b"\x00") and b"\x00" not in wire[:-1]
    assert len(wire) == 81                      # docs/protocol.md: 81 bytes for L = 8
    payload = cobs_decode(wire[:-1])
    # header: version 1, type 'S', body length 71 (docs/protocol.md)
    assert payload[:4] == struct.pack("<BBH", 1, 0x53, 71)
    assert struct.unpack("<I", payload[-4:])[0] == zlib.crc32(payload[:-4])
    msg = decode_payload(payload)
    assert isinstance(msg, StateFrame)
    assert (msg.seq, msg.t_us, msg.status) == (5, 123456789, 0x0008)
    np.testing.assert_array_equal(msg.angles, angles.astype(np.float32))
    np.testing.assert_array_equal(msg.wrench, wrench.astype(np.float32))


def test_command_frame_round_trip_and_layout():
    tau = np.linspace(-2.5, 2.5, 8)
    wire = encode_command(7, 6, MODE_HOLD, tau, flags=FLAG_KEEPALIVE)
    assert len(wire) == 53                      # docs/protocol.md
    payload = cobs_decode(wire[:-1])
    assert payload[:4] == struct.pack("<BBH", 1, 0x43, 43)
    # body: seq u32, ack u32, mode u8, flags u8, L u8, then float32 torques
    assert payload[4:15] == struct.pack("<IIBBB", 7, 6, MODE_HOLD, FLAG_KEEPALIVE, 8)
    msg = decode_payload(payload)
    assert isinstance(msg, CommandFrame)
    assert (msg.seq, msg.ack, msg.mode, msg.flags) == (7, 6, MODE_HOLD, FLAG_KEEPALIVE)
    np.testing.assert_array_equal(msg.torques, tau.astype(np.float32))


def test_every_single_byte_corruption_is_detected():
    wire = encode_command(1, 1, MODE_RUN, np.arange(8.0))
    for i in range(len(wire) - 1):
        bad = bytearray(wire)
        bad[i] ^= 0x40 if bad[i] != 0x40 else 0x41
        dec = FrameDecoder()
        assert dec.feed(bytes(bad) + b"\x00") == []
        assert dec.bad_frames >= 1


@pytest.mark.parametrize("payload, reason", [
    (b"\x01\x53", "short"),
    (struct.pack("<BBH", 2, 0x53, 0) + struct.pack("<I", zlib.crc32(struct.pack("<BBH", 2, 0x53, 0))), "version"),
    (struct.pack("<BBH", 1, 0x99, 0) + struct.pack("<I", zlib.crc32(struct.pack("<BBH", 1, 0x99, 0))), "type"),
    (struct.pack("<BBH", 1, 0x53, 9) + struct.pack("<I", zlib.crc32(struct.pack("<BBH", 1, 0x53, 9))), "length"),
])
def test_decode_payload_reasons(payload, reason):
    with pytest.raises(ProtocolError) as exc:
        decode_payload(payload)
    assert exc.value.reason == reason


def test_decoder_resynchronises_after_garbage_and_truncation():
    frames = [encode_state(i, 1000 * i, 0, np.full(8, 0.01 * i), np.zeros(6)) for i in range(1, 7)]
    rng = np.random.default_rng(0)
    garbage = rng.integers(0, 256, 300, dtype=np.uint8).tobytes()
    stream = (frames[0] + garbage + b"\x00" + frames[1]       # garbage burst, then resync
              + frames[2][:30] + frames[3]                     # truncated: takes frame 4 along
              + frames[4] + frames[5])
    dec = FrameDecoder()
    got = []
    for i in range(0, len(stream), 7):                         # arbitrary chunking
        got += dec.feed(stream[i:i + 7])
    assert [m.seq for m in got] == [1, 2, 5, 6]
    assert dec.bad_frames >= 2
    assert dec.resyncs == 2
    assert dec.frames == 4


def test_decoder_discards_oversize_runs():
    dec = FrameDecoder(max_frame=100)
    assert dec.feed(b"\x11" * 250) == []
    assert dec.reasons.get("oversize", 0) >= 1
    good = encode_state(9, 0, 0, np.zeros(8), np.zeros(6))
    assert [m.seq for m in dec.feed(b"\x11" * 10 + b"\x00" + good)] == [9]


def test_encode_rejects_bad_sizes():
    with pytest.raises(ValueError, match="wrench"):
        encode_state(1, 0, 0, np.zeros(8), np.zeros(5))
    with pytest.raises(ValueError, match="joints"):
        encode_command(1, 0, MODE_RUN, np.zeros(0))
    with pytest.raises(ValueError, match="mode"):
        encode_command(1, 0, 7, np.zeros(8))


def test_random_streams_never_raise():
    """Random bytes (seeded): the decoder never raises, never invents a frame (a random
    chunk passing the CRC-32 and the header checks has odds of about 2^-40) and counts
    what it rejects; a valid frame after the garbage still comes through (resync)."""
    rng = np.random.default_rng(97)
    dec = FrameDecoder()
    for _ in range(50):
        assert dec.feed(rng.integers(0, 256, 97, dtype=np.uint8).tobytes()) == []
    assert dec.bad_frames > 0 and dec.frames == 0
    good = encode_state(42, 7, 0, np.arange(8.0), np.zeros(6))
    assert [m.seq for m in dec.feed(b"\x00" + good)] == [42]


def test_the_compiled_state_decoder_gives_the_python_frames_bit_for_bit():
    """frame_codec.state_decoder against cobs_decode + decode_payload: random state
    frames (L = 1..32, NaN and inf, sequence and clock at their limits) give equal
    fields and the same float bits; anything else (corrupted, truncated, a command
    frame, garbage) is left to the Python route, so the decoder's counters and reasons
    are those of the pure-Python decoder."""
    from distkin.control.frame_codec import state_decoder
    fast = state_decoder()
    rng = np.random.default_rng(11)
    for k in range(300):
        n = int(rng.integers(1, 33))
        a = rng.normal(0, 2, n)
        w = rng.normal(0, 50, 6)
        if k % 7 == 0:
            a[rng.integers(n)] = [np.nan, np.inf, -np.inf][k % 3]
        seq = [0, 2**32 - 1, int(rng.integers(2**32))][k % 3]
        t_us = [0, 2**64 - 1, int(rng.integers(2**62))][k % 3]
        chunk = encode_state(seq, t_us, int(rng.integers(2**16)), a, w)[:-1]
        ref = decode_payload(cobs_decode(chunk))
        got = fast(bytearray(chunk))
        assert (got.seq, got.t_us, got.status) == (ref.seq, ref.t_us, ref.status)
        assert all(type(x) is int for x in (got.seq, got.t_us, got.status))
        assert got.angles.tobytes() == ref.angles.tobytes()
        assert got.wrench.tobytes() == ref.wrench.tobytes()
    good = encode_state(5, 1000, 0, np.zeros(8), np.zeros(6))
    others = [good[:-1][:-3], bytes([good[0] ^ 0x40]) + good[1:-1], b"\x05abc",
              encode_command(1, 2, 1, np.ones(8))[:-1], bytes(rng.integers(1, 256, 60))]
    for chunk in others:
        assert fast(bytearray(chunk)) is None
    stream = b"".join([good, b"\x07garbage\x00", good[:20] + b"\x00", good,
                       encode_command(1, 2, 1, np.ones(8)), good])
    d_py, d_fast = FrameDecoder(), FrameDecoder(fast=fast)
    out_py, out_fast = d_py.feed(stream), d_fast.feed(stream)
    assert [type(m) for m in out_py] == [type(m) for m in out_fast]
    assert (d_py.bad_frames, d_py.resyncs, d_py.reasons) == \
        (d_fast.bad_frames, d_fast.resyncs, d_fast.reasons)
