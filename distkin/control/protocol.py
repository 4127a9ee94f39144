"""The distkin device protocol: binary frames between a host and a parallel-robot device.

Pure functions and one streaming decoder; no I/O (the bytes go through
:mod:`distkin.control.link` on the host and :mod:`distkin.control.simulator` on the
device side).  The byte layouts are written down in ``docs/protocol.md``.

Framing (both directions)::

    wire   = COBS(payload) 0x00
    payload = version:u8  type:u8  length:u16  body[length]  crc:u32

* ``COBS`` (consistent overhead byte stuffing; S. Cheshire and M. Baker, "Consistent
  overhead byte stuffing", IEEE/ACM Trans. Networking 7(2), 1999,
  doi:10.1109/90.769765) removes every zero byte from the payload, so ``0x00`` only
  ever marks the end of a frame.  A reader that meets garbage discards bytes up to the
  next ``0x00`` and is in step again: that is the resynchronisation.
* ``crc`` is CRC-32 (IEEE 802.3, :func:`zlib.crc32`) over ``version .. body``, little
  endian.  All integers and floats are little endian.

Device -> host, ``type = 0x53`` ('S', :class:`StateFrame`): sequence number, device
clock, status word, L encoder readings (joint side: rad, or m for prismatic legs) and
the six-axis force/torque reading (N, N·m, in the sensor = platform frame).

Host -> device, ``type = 0x43`` ('C', :class:`CommandFrame`): sequence number, the
sequence number of the state it answers, mode (run / hold / zero torque), flags and L
joint effort commands (joint side: N·m after the capstan, or N for prismatic legs).

Finite values: :func:`encode_command` refuses an effort that is NaN, ±inf or beyond
float32's range (it would go out as ±inf; :data:`F32_OVERFLOW`), in every mode: a
haptic device's firmware must never be handed a non-finite torque.  State frames carry
whatever the device measured, NaN included (a faulty sensor: the host rejects such a
frame, :func:`.safety.check_reading`), and both decoders take NaN in either direction
(the simulated device applies zero effort on a joint whose command is not finite).
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = [
    "VERSION",
    "TYPE_STATE",
    "TYPE_COMMAND",
    "MAX_JOINTS",
    "MAX_FRAME",
    "MODE_ZERO_TORQUE",
    "MODE_RUN",
    "MODE_HOLD",
    "MODE_NAMES",
    "FLAG_KEEPALIVE",
    "STATUS_SENSOR_FAULT",
    "STATUS_ESTOP",
    "STATUS_DEVICE_WATCHDOG",
    "STATUS_SATURATED",
    "StateFrame",
    "CommandFrame",
    "ProtocolError",
    "cobs_encode",
    "cobs_decode",
    "encode_state",
    "encode_readings",
    "float32_floor",
    "F32_OVERFLOW",
    "check_efforts",
    "encode_command",
    "decode_payload",
    "FrameDecoder",
]

#: protocol version carried in every frame
VERSION = 1
TYPE_STATE = 0x53      # 'S'
TYPE_COMMAND = 0x43    # 'C'
#: largest L the format allows
MAX_JOINTS = 32
#: largest encoded frame a decoder accepts before it discards and resynchronises (bytes)
MAX_FRAME = 512

MODE_ZERO_TORQUE = 0
MODE_RUN = 1
MODE_HOLD = 2
MODE_NAMES = {MODE_ZERO_TORQUE: "zero_torque", MODE_RUN: "run", MODE_HOLD: "hold"}

#: command flag: the host re-sends its last command because no state arrived in time
FLAG_KEEPALIVE = 0x01

STATUS_SENSOR_FAULT = 0x0001     # force/torque sensor or encoder reports a fault
STATUS_ESTOP = 0x0002            # emergency stop pressed
STATUS_DEVICE_WATCHDOG = 0x0004  # the device zeroed its torques: no command in time
STATUS_SATURATED = 0x0008        # a motor drive limited the commanded torque

#: the least float64 magnitude whose float32 is infinite: the midpoint between float32's
#: largest value (2 - 2^-23) 2^127 and 2^128, which round-to-nearest-even sends to
#: 2^128 = inf (IEEE 754).  An effort must stay below it to go out finite
F32_OVERFLOW = 2.0 ** 128 - 2.0 ** 103

_HEADER = struct.Struct("<BBH")          # version, type, body length
_CRC = struct.Struct("<I")
_STATE_HEAD = struct.Struct("<IQHB")     # seq, t_us, status, n
_COMMAND_HEAD = struct.Struct("<IIBBB")  # seq, ack, mode, flags, n


class ProtocolError(ValueError):
    """A payload that is not a valid frame; ``reason`` is a short counter key."""

    def __init__(self, reason: str, message: str):
        self.reason = reason
        super().__init__(f"{reason}: {message}")


@dataclass(frozen=True)
class StateFrame:
    """Device -> host.

    Attributes
    ----------
    seq : int
        Sequence number, +1 per frame (mod 2**32).
    t_us : int
        Device clock, µs.
    status : int
        Bit field of ``STATUS_*``.
    angles : ndarray, shape (L,)
        Encoder angles on the joint (crank) side, rad (leg lengths, m, for
        prismatic legs).
    wrench : ndarray, shape (6,)
        Force (N) and torque (N·m) measured by the six-axis sensor, sensor frame.
    """

    seq: int
    t_us: int
    status: int
    angles: np.ndarray
    wrench: np.ndarray


@dataclass(frozen=True)
class CommandFrame:
    """Host -> device.

    Attributes
    ----------
    seq : int
        Host sequence number.
    ack : int
        Sequence number of the last state frame the host had received.
    mode : int
        ``MODE_RUN`` (apply the torques), ``MODE_HOLD`` (device holds its position on
        its own) or ``MODE_ZERO_TORQUE``.
    flags : int
        ``FLAG_KEEPALIVE`` when re-sent because no state frame arrived in time.
    torques : ndarray, shape (L,)
        Joint torque commands after the capstan, N·m (leg forces, N, for prismatic
        legs).
    """

    seq: int
    ack: int
    mode: int
    flags: int
    torques: np.ndarray


def cobs_encode(data: bytes) -> bytes:
    """COBS-encode ``data`` (the result contains no zero byte; Cheshire & Baker 1999)."""
    out = bytearray()
    for chunk in bytes(data).split(b"\x00"):
        while len(chunk) >= 254:
            out.append(0xFF)
            out += chunk[:254]
            chunk = chunk[254:]
        out.append(len(chunk) + 1)
        out += chunk
    return bytes(out)


def cobs_decode(enc: bytes) -> bytes:
    """Invert :func:`cobs_encode`; raises :class:`ProtocolError` ("cobs") if malformed."""
    out = bytearray()
    i, n = 0, len(enc)
    while i < n:
        code = enc[i]
        if code == 0:
            raise ProtocolError("cobs", f"expected a non-zero code byte, got 0 at {i}")
        end = i + code
        if end > n:
            raise ProtocolError("cobs", f"expected {code - 1} data bytes at {i + 1}, "
                                        f"got {n - i - 1}")
        out += enc[i + 1:end]
        i = end
        if code < 0xFF and i < n:
            out.append(0)
    return bytes(out)


def _frame(ftype: int, body: bytes) -> bytes:
    payload = _HEADER.pack(VERSION, ftype, len(body)) + body
    return cobs_encode(payload + _CRC.pack(zlib.crc32(payload))) + b"\x00"


def _check_n(n: int, what: str) -> None:
    if not 1 <= n <= MAX_JOINTS:
        raise ValueError(f"{what}: expected 1..{MAX_JOINTS} joints, got {n}")


def _check_frame_args(arrays, counters) -> None:
    """Refuse what no frame can carry (InputError, a ValueError): ``arrays`` ``(name,
    value)`` that are not one-dimensional (a (2, 4) block is not 8 torques), and
    ``counters`` ``(name, value)`` that are not integers >= 0 (a seq of -1 or 2.5; the
    wire's unsigned fields take the value modulo their width, docs/protocol.md)."""
    for name, v in arrays:
        if np.ndim(v) != 1:
            raise InputError(f"expected a one-dimensional array, got shape {np.shape(v)}",
                             field=name)
    for name, v in counters:
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
            raise InputError(f"expected an integer >= 0, got {v!r}", field=name)


def encode_state(seq: int, t_us: int, status: int, angles, wrench) -> bytes:
    """One device -> host frame, delimiter included.

    Parameters
    ----------
    seq, t_us, status : int
        See :class:`StateFrame` (``seq`` is taken mod 2**32).
    angles : array_like, shape (L,)
        Joint angles, rad, or leg lengths, m (sent as float32).
    wrench : array_like, shape (6,)
        Sensor reading (N, N·m; sent as float32).
    """
    _check_frame_args((("angles", angles), ("wrench", wrench)),
                      (("seq", seq), ("t_us", t_us), ("status", status)))
    a = np.asarray(angles, dtype="<f4").ravel()
    w = np.asarray(wrench, dtype="<f4").ravel()
    _check_n(a.size, "angles")
    if w.size != 6:
        raise ValueError(f"wrench: expected 6 values, got {w.size}")
    body = (_STATE_HEAD.pack(seq & 0xFFFFFFFF, int(t_us) & 0xFFFFFFFFFFFFFFFF,
                             status & 0xFFFF, a.size) + a.tobytes() + w.tobytes())
    return _frame(TYPE_STATE, body)


def float32_floor(x: float) -> float:
    """The largest float32 value <= ``x``, as a float: a limit the wire's float32 values
    can keep.  (A torque saturated at 0.3 N·m is sent as float32(0.3) = 0.30000001
    N·m; saturated at ``float32_floor(0.3)`` it is sent as 0.29999998 N·m.)"""
    f = np.float32(x)
    if float(f) > x:
        f = np.nextafter(f, np.float32(-np.inf))
    return float(f)


def encode_readings(seq: int, t_us: int, status: int, vals) -> bytes:
    """:func:`encode_state` of one vector ``vals`` (L + 6,): the L joint readings, then
    the six sensor values (what :meth:`.plant.Plant.readings` gives)."""
    v = np.asarray(vals, dtype=float).ravel()
    return encode_state(seq, t_us, status, v[:-6], v[-6:])


def check_efforts(values) -> None:
    """Refuse efforts that the wire would carry as NaN or ±inf: InputError naming the
    first such joint (0-based, ``torques[i]``) and its value.  A value is refused when
    it is not finite or its float32 is not (``|value| >= F32_OVERFLOW``, e.g. 1e40 N·m,
    which float32 rounds to inf)."""
    v = np.asarray(values, dtype=float).ravel()
    if v.size and not np.abs(v).max() < F32_OVERFLOW:     # (max is NaN if one is)
        i = int(np.argmin(np.abs(v) < F32_OVERFLOW))
        raise InputError(f"expected a finite effort at every joint, below {F32_OVERFLOW!r} "
                         f"in magnitude (sent as float32: the device must never get NaN or "
                         f"inf), got {float(v[i])!r} at joint {i}", field=f"torques[{i}]")


def encode_command(seq: int, ack: int, mode: int, torques, flags: int = 0) -> bytes:
    """One host -> device frame, delimiter included (torques in N·m, sent as float32).

    Raises ValueError for what no frame carries: InputError (a ValueError) for a seq,
    ack or flags that is not an integer >= 0 and torques that are not one-dimensional,
    a plain ValueError for not 1 .. :data:`MAX_JOINTS` torques or a mode not in
    :data:`MODE_NAMES`, and InputError, in every mode, for a torque that is NaN, ±inf or
    whose float32 is infinite (:func:`check_efforts`: the error names the joint and the
    value; docs/protocol.md)."""
    _check_frame_args((("torques", torques),),
                      (("seq", seq), ("ack", ack), ("flags", flags)))
    v = np.asarray(torques, dtype=float).ravel()
    _check_n(v.size, "torques")
    if mode not in MODE_NAMES:
        raise ValueError(f"mode: expected one of {sorted(MODE_NAMES)}, got {mode!r}")
    check_efforts(v)
    t = np.asarray(torques, dtype="<f4").ravel()     # (no overflow left to warn of)
    body = _COMMAND_HEAD.pack(seq & 0xFFFFFFFF, ack & 0xFFFFFFFF, mode, flags & 0xFF,
                              t.size) + t.tobytes()
    return _frame(TYPE_COMMAND, body)


def decode_payload(payload: bytes):
    """Validate and parse one COBS-decoded payload.

    Returns
    -------
    StateFrame or CommandFrame

    Raises
    ------
    ProtocolError
        ``reason`` is one of "short", "crc", "version", "length", "type".
    """
    if len(payload) < _HEADER.size + _CRC.size:
        raise ProtocolError("short", f"expected at least {_HEADER.size + _CRC.size} bytes, "
                                     f"got {len(payload)}")
    (crc,) = _CRC.unpack_from(payload, len(payload) - 4)
    if zlib.crc32(memoryview(payload)[:-4]) != crc:
        raise ProtocolError("crc", "checksum mismatch")
    version, ftype, length = _HEADER.unpack_from(payload, 0)
    if version != VERSION:
        raise ProtocolError("version", f"expected version {VERSION}, got {version}")
    body = memoryview(payload)[_HEADER.size:-4]
    if len(body) != length:
        raise ProtocolError("length", f"expected a body of {length} bytes, got {len(body)}")
    if ftype == TYPE_STATE:
        if length < _STATE_HEAD.size:
            raise ProtocolError("length", f"state body too short ({length} bytes)")
        seq, t_us, status, n = _STATE_HEAD.unpack_from(body, 0)
        if not 1 <= n <= MAX_JOINTS or length != _STATE_HEAD.size + 4 * (n + 6):
            raise ProtocolError("length", f"state body of {length} bytes does not fit "
                                          f"{n} joints")
        vals = np.frombuffer(body, dtype="<f4", offset=_STATE_HEAD.size).astype(float)
        return StateFrame(seq, t_us, status, vals[:n], vals[n:])
    if ftype == TYPE_COMMAND:
        if length < _COMMAND_HEAD.size:
            raise ProtocolError("length", f"command body too short ({length} bytes)")
        seq, ack, mode, flags, n = _COMMAND_HEAD.unpack_from(body, 0)
        if not 1 <= n <= MAX_JOINTS or length != _COMMAND_HEAD.size + 4 * n:
            raise ProtocolError("length", f"command body of {length} bytes does not fit "
                                          f"{n} joints")
        if mode not in MODE_NAMES:
            raise ProtocolError("mode", f"expected a mode in {sorted(MODE_NAMES)}, got {mode}")
        vals = np.frombuffer(body, dtype="<f4", offset=_COMMAND_HEAD.size).astype(float)
        return CommandFrame(seq, ack, mode, flags, vals)
    raise ProtocolError("type", f"expected frame type 0x53 or 0x43, got {ftype:#04x}")


class FrameDecoder:
    """Streaming decoder: feed it bytes as they arrive, get whole valid frames back.

    Bytes are collected up to each ``0x00`` delimiter; the chunk is COBS-decoded and
    validated.  A chunk that fails (garbage, a corrupted or truncated frame) is counted
    and dropped, and decoding continues at the next delimiter.  A run of more than
    :data:`MAX_FRAME` bytes without a delimiter is discarded as garbage.

    Attributes
    ----------
    frames : int
        Valid frames decoded.
    bad_frames : int
        Chunks rejected (the reasons are counted in ``reasons``).
    resyncs : int
        Times a valid frame was found again after one or more rejected chunks.
    garbage_bytes : int
        Bytes discarded.
    """

    def __init__(self, max_frame: int = MAX_FRAME, *, fast=None):
        self.max_frame = max_frame
        #: optional fast route: chunk -> frame, or None to take the Python route
        #: (:func:`distkin.control.frame_codec.state_decoder` and ``command_decoder``)
        self.fast = fast
        self._buf = bytearray()
        self._lost = False
        self.frames = 0
        self.bad_frames = 0
        self.resyncs = 0
        self.garbage_bytes = 0
        self.reasons: dict[str, int] = {}

    def _bad(self, reason: str, nbytes: int) -> None:
        self.bad_frames += 1
        self.garbage_bytes += nbytes
        self.reasons[reason] = self.reasons.get(reason, 0) + 1
        self._lost = True

    def feed(self, data: bytes) -> list:
        """Add ``data``; return the valid frames completed by it, oldest first."""
        out = []
        if not data:
            return out
        self._buf += data
        if b"\x00" not in data:
            if len(self._buf) > self.max_frame:
                self._bad("oversize", len(self._buf))
                self._buf.clear()
            return out
        *chunks, rest = self._buf.split(b"\x00")
        self._buf = bytearray(rest)
        for chunk in chunks:
            if not chunk:
                continue                      # back-to-back delimiters: nothing lost
            if len(chunk) > self.max_frame:
                self._bad("oversize", len(chunk))
                continue
            msg = None if self.fast is None else self.fast(chunk)
            if msg is None:
                try:
                    msg = decode_payload(cobs_decode(chunk))
                except ProtocolError as exc:
                    self._bad(exc.reason, len(chunk))
                    continue
            if self._lost:
                self.resyncs += 1
                self._lost = False
            self.frames += 1
            out.append(msg)
        if len(self._buf) > self.max_frame:
            self._bad("oversize", len(self._buf))
            self._buf.clear()
        return out
