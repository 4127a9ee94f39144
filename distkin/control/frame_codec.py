"""The device protocol's frames encoded and decoded by compiled code.

:mod:`.protocol` is the reference: COBS framing (Cheshire & Baker 1999), CRC-32
(IEEE 802.3, the table of :func:`zlib.crc32`) and the little-endian layouts written down
in ``docs/protocol.md``, in pure Python.  A frame through it costs 5-15 µs of Python
(struct packing, byte strings, numpy casts), which at 4 kHz is a tenth of the period on
each side of the link.  Here the same bytes are produced and read by one numba call per
frame:

* :func:`state_encoder` -> ``encode(seq, t_us, status, vals) -> bytes`` with ``vals``
  the L joint readings followed by the six sensor values (float64; sent as float32):
  :func:`.protocol.encode_readings`;
* :func:`command_encoder` -> ``encode(seq, ack, mode, torques, flags=0) -> bytes``:
  :func:`.protocol.encode_command`;
* :func:`state_decoder` and :func:`command_decoder` -> ``decode(chunk)``: a COBS chunk
  (no delimiter) -> the :class:`.protocol.StateFrame` / :class:`.protocol.CommandFrame`
  it holds, or None for anything else (the fast route of
  :class:`.protocol.FrameDecoder`, which then takes the Python route and says why).

The encoders take the arguments and give the bytes of :func:`.protocol.encode_readings`
and :func:`.protocol.encode_command`, and the decoders the values of
:func:`.protocol.cobs_decode` + :func:`.protocol.decode_payload`, bit for bit
(tests/control/test_frame_codec.py); input the reference would refuse (a mode or a
joint count out of range, a mode that is not an int) goes through the reference, so its
errors are the same; so does a command whose torques the wire would carry as NaN or
inf (the kernel checks ``|torque| < F32_OVERFLOW`` at each joint, a compare per joint,
and hands such a command back: the reference's InputError names the joint and the
value, docs/protocol.md); a strided or read-only array is copied first, so that each
kernel has one compiled signature.
Each factory compiles its kernel before it returns (numba's disk cache: a second or two
on the first start on a machine), so that no frame waits for the compiler.

Imported by :mod:`.link`, :mod:`.simulator` and :mod:`.loopback` when they use the
compiled route (it imports numba).
"""

from __future__ import annotations

import numba
import numpy as np

from .protocol import (F32_OVERFLOW, MAX_JOINTS, MODE_NAMES, TYPE_COMMAND, TYPE_STATE,
                       VERSION, CommandFrame, StateFrame, encode_command, encode_readings)

__all__ = ["state_encoder", "command_encoder", "state_decoder", "command_decoder",
           "MAX_WIRE"]

_jit = numba.njit(cache=True)

#: the longest frame on the wire: a state frame of MAX_JOINTS joints (payload 4 + 15 +
#: 4 (L + 6) + 4 bytes), its COBS overhead and the delimiter
MAX_WIRE = 4 + 15 + 4 * (MAX_JOINTS + 6) + 4 + 2 + 1
_STATE_HEAD = 15      # seq u32, t_us u64, status u16, n u8
_COMMAND_HEAD = 11    # seq u32, ack u32, mode u8, flags u8, n u8
_U64 = 0xFFFFFFFFFFFFFFFF


def _crc_table():
    t = np.empty(256, dtype=np.uint32)
    for i in range(256):
        c = i
        for _ in range(8):
            c = (0xEDB88320 ^ (c >> 1)) if c & 1 else c >> 1
        t[i] = c
    return t


#: CRC-32 (IEEE 802.3, reflected: the table of zlib.crc32)
_CRC32 = _crc_table()


@_jit
def _crc32(p, k):                                            # pragma: no cover (compiled)
    """CRC-32 of ``p[:k]`` (zlib.crc32)."""
    crc = np.uint32(0xFFFFFFFF)
    for j in range(k):
        crc = _CRC32[(crc ^ p[j]) & np.uint32(0xFF)] ^ (crc >> np.uint32(8))
    return crc ^ np.uint32(0xFFFFFFFF)


@_jit
def _unstuff(enc, p):                                        # pragma: no cover (compiled)
    """:func:`.protocol.cobs_decode` of ``enc`` into ``p``: the payload's length, or -1
    if ``enc`` is not valid COBS."""
    m = enc.shape[0]
    k = 0
    i = 0
    while i < m:
        code = np.int64(enc[i])
        if code == 0 or i + code > m:
            return -1
        for j in range(i + 1, i + code):
            p[k] = enc[j]
            k += 1
        i += code
        if code < 0xFF and i < m:
            p[k] = 0
            k += 1
    return k


@_jit
def _stuff(p, k, out):                                       # pragma: no cover (compiled)
    """:func:`.protocol.cobs_encode` of ``p[:k]`` into ``out``, then the 0x00
    delimiter; returns the bytes written.  Like the reference, a run of 254 non-zero
    bytes or more is cut into 0xFF blocks of 254 and what is left (maybe nothing)."""
    o = 0
    start = 0
    for end in range(k + 1):
        if end < k and p[end] != 0:
            continue
        n = end - start                   # the run p[start:end], then a zero (or the end)
        s = start
        while n >= 254:
            out[o] = 0xFF
            o += 1
            for j in range(254):
                out[o] = p[s + j]
                o += 1
            s += 254
            n -= 254
        out[o] = n + 1
        o += 1
        for j in range(n):
            out[o] = p[s + j]
            o += 1
        start = end + 1
    out[o] = 0
    return o + 1


@_jit
def _put_u(p, at, value, nbytes):                            # pragma: no cover (compiled)
    v = np.uint64(value)
    for j in range(nbytes):
        p[at + j] = np.uint8((v >> np.uint64(8 * j)) & np.uint64(0xFF))


@_jit
def _finish(p, length, out):                                 # pragma: no cover (compiled)
    """Header length, CRC and COBS of a payload whose body of ``length`` bytes is in
    ``p[4:]``; the wire bytes into ``out``, returns their number."""
    p[0] = VERSION
    _put_u(p, 2, length, 2)
    k = 4 + length
    _put_u(p, k, _crc32(p, k), 4)
    return _stuff(p, k + 4, out)


@_jit
def _put_f32(p, at, vals):                                   # pragma: no cover (compiled)
    n = vals.shape[0]
    f = np.empty(n, dtype=np.float32)
    for j in range(n):
        f[j] = np.float32(vals[j])
    fb = f.view(np.uint8)
    for j in range(4 * n):
        p[at + j] = fb[j]


@_jit
def _encode_state(seq, t_us, status, vals, out):             # pragma: no cover (compiled)
    n = vals.shape[0] - 6
    p = np.empty(4 + _STATE_HEAD + 4 * (n + 6) + 4, dtype=np.uint8)
    p[1] = TYPE_STATE
    _put_u(p, 4, seq, 4)
    _put_u(p, 8, t_us, 8)
    _put_u(p, 16, status, 2)
    p[18] = n
    _put_f32(p, 19, vals)
    return _finish(p, _STATE_HEAD + 4 * (n + 6), out)


@_jit
def _encode_command(seq, ack, mode, flags, torques, out):   # pragma: no cover (compiled)
    """The command frame into ``out``: its length, or -1 (nothing written) when a torque
    is NaN, ±inf or beyond float32 (``not |t| < F32_OVERFLOW``): the reference refuses
    it (:func:`.protocol.check_efforts`)."""
    n = torques.shape[0]
    for j in range(n):
        if not abs(torques[j]) < F32_OVERFLOW:
            return -1
    p = np.empty(4 + _COMMAND_HEAD + 4 * n + 4, dtype=np.uint8)
    p[1] = TYPE_COMMAND
    _put_u(p, 4, seq, 4)
    _put_u(p, 8, ack, 4)
    p[12] = mode
    p[13] = flags
    p[14] = n
    _put_f32(p, 15, torques)
    return _finish(p, _COMMAND_HEAD + 4 * n, out)


@_jit
def _payload(enc, ftype, head):                              # pragma: no cover (compiled)
    """The payload of a COBS chunk if it is a valid frame of ``ftype`` with a body of
    ``head`` + 4 n bytes (n, the joint count, in the body's last header byte, 1..32,
    plus 6 sensor values for a state frame); else an empty array."""
    p = np.empty(enc.shape[0], dtype=np.uint8)
    k = _unstuff(enc, p)
    bad = p[:0]
    if k < 8:
        return bad
    want = (np.uint32(p[k - 4]) | (np.uint32(p[k - 3]) << np.uint32(8))
            | (np.uint32(p[k - 2]) << np.uint32(16)) | (np.uint32(p[k - 1]) << np.uint32(24)))
    length = np.int64(p[2]) | (np.int64(p[3]) << 8)
    if _crc32(p, k - 4) != want or p[0] != VERSION or p[1] != ftype or length != k - 8 \
            or length < head:
        return bad
    n = np.int64(p[3 + head])
    extra = 6 if ftype == TYPE_STATE else 0
    if n < 1 or n > MAX_JOINTS or length != head + 4 * (n + extra):
        return bad
    return p[:k]


@_jit
def _get_u(p, at, nbytes):                                   # pragma: no cover (compiled)
    v = np.uint64(0)
    for j in range(nbytes):
        v |= np.uint64(p[at + j]) << np.uint64(8 * j)
    return v


@_jit
def _get_f32(p, at, vals, count):                            # pragma: no cover (compiled)
    f = np.empty(count, dtype=np.float32)
    fb = f.view(np.uint8)
    for j in range(4 * count):
        fb[j] = p[at + j]
    for j in range(count):
        vals[j] = f[j]


@_jit
def _decode_state(enc, vals):                                # pragma: no cover (compiled)
    """``(ok, seq, t_us, status, n)`` and ``vals[:n + 6]`` of a valid state frame; ok
    False for anything else."""
    p = _payload(enc, TYPE_STATE, _STATE_HEAD)
    if p.shape[0] == 0:
        return False, 0, np.uint64(0), 0, 0
    n = np.int64(p[18])
    _get_f32(p, 19, vals, n + 6)
    return (True, np.int64(_get_u(p, 4, 4)), _get_u(p, 8, 8), np.int64(_get_u(p, 16, 2)), n)


@_jit
def _decode_command(enc, vals):                              # pragma: no cover (compiled)
    """``(ok, seq, ack, mode, flags, n)`` and ``vals[:n]`` of a valid command frame; ok
    False for anything else (a mode out of range too: the reference names it)."""
    p = _payload(enc, TYPE_COMMAND, _COMMAND_HEAD)
    if p.shape[0] == 0 or p[12] > 2:
        return False, 0, 0, 0, 0, 0
    n = np.int64(p[14])
    _get_f32(p, 15, vals, n)
    return (True, np.int64(_get_u(p, 4, 4)), np.int64(_get_u(p, 8, 4)), np.int64(p[12]),
            np.int64(p[13]), n)


def state_encoder():
    """``encode(seq, t_us, status, vals) -> bytes``: :func:`.protocol.encode_readings`
    (``vals``: the L joint readings, then the six sensor values) by one compiled call."""
    out = np.empty(MAX_WIRE, dtype=np.uint8)
    f = _encode_state
    f(1, np.uint64(0), 0, np.zeros(7), out)                 # compile now (one signature)
    u64, f64, ndarray = np.uint64, np.float64, np.ndarray

    def encode(seq, t_us, status, vals):
        if type(vals) is not ndarray or vals.dtype != f64 or vals.ndim != 1 \
                or not 7 <= vals.shape[0] <= MAX_JOINTS + 6 or type(seq) is not int or seq < 0:
            return encode_readings(seq, t_us, status, vals)          # says what is wrong
        if not (vals.flags.c_contiguous and vals.flags.writeable):
            vals = vals.copy()                  # the compiled signature's layout
        m = f(seq & 0xFFFFFFFF, u64(int(t_us) & _U64), status & 0xFFFF, vals, out)
        return out[:m].tobytes()

    return encode


def command_encoder():
    """``encode(seq, ack, mode, torques, flags=0) -> bytes``:
    :func:`.protocol.encode_command` by one compiled call (its errors too: a NaN, inf
    or float32-overflowing torque is its InputError naming the joint and the value)."""
    out = np.empty(MAX_WIRE, dtype=np.uint8)
    f = _encode_command
    f(1, 0, 0, 0, np.zeros(1), out)                          # compile now (one signature)
    f64, ndarray = np.float64, np.ndarray

    def encode(seq, ack, mode, torques, flags=0):
        if type(torques) is not ndarray or torques.dtype != f64 or torques.ndim != 1 \
                or not 1 <= torques.shape[0] <= MAX_JOINTS or type(mode) is not int \
                or mode not in MODE_NAMES or type(seq) is not int or seq < 0 \
                or type(ack) is not int or ack < 0:
            return encode_command(seq, ack, mode, torques, flags)      # says what is wrong
        if not (torques.flags.c_contiguous and torques.flags.writeable):
            torques = torques.copy()            # the compiled signature's layout
        m = f(seq & 0xFFFFFFFF, ack & 0xFFFFFFFF, mode, flags & 0xFF, torques, out)
        if m < 0:                               # a torque the wire cannot carry finite
            return encode_command(seq, ack, mode, torques, flags)      # says which
        return out[:m].tobytes()

    return encode


def _warm(f, vals):
    for buf in (b"\x01", bytearray(b"\x01")):           # compile now: both signatures
        f(np.frombuffer(buf, dtype=np.uint8), vals)


def state_decoder():
    """A fast route for :class:`.protocol.FrameDecoder`: a COBS chunk -> its
    :class:`.protocol.StateFrame` (the reference's values, bit for bit), or None for
    anything that is not a valid state frame."""
    f = _decode_state
    _warm(f, np.empty(MAX_JOINTS + 6))
    frombuffer, u8 = np.frombuffer, np.uint8

    def decode(chunk):
        v = np.empty(MAX_JOINTS + 6)
        ok, seq, t_us, status, n = f(frombuffer(chunk, dtype=u8), v)
        if not ok:
            return None
        return StateFrame(seq, int(t_us), status, v[:n], v[n:n + 6])

    return decode


def command_decoder():
    """A fast route for :class:`.protocol.FrameDecoder`: a COBS chunk -> its
    :class:`.protocol.CommandFrame` (the reference's values, bit for bit), or None for
    anything that is not a valid command frame."""
    f = _decode_command
    _warm(f, np.empty(MAX_JOINTS))
    frombuffer, u8 = np.frombuffer, np.uint8

    def decode(chunk):
        v = np.empty(MAX_JOINTS)
        ok, seq, ack, mode, flags, n = f(frombuffer(chunk, dtype=u8), v)
        if not ok:
            return None
        return CommandFrame(seq, ack, mode, flags, v[:n])

    return decode
