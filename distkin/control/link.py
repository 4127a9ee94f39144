"""The host end of the serial link (the only distkin module that imports ``serial``).

:class:`Link` opens any pyserial URL -- a device path (``/dev/ttyACM0``), a
pseudo-terminal path (``/dev/pts/7``), ``loop://`` or ``socket://host:port`` -- and
exchanges the frames of :mod:`distkin.control.protocol` with a device.  Reads have a
deadline and never block the control loop for longer; everything that goes wrong on
the line is counted in :class:`LinkStats`.
"""

from __future__ import annotations

import errno
import os
import select
import stat
import time
from dataclasses import asdict, dataclass

from ..errors import LinkError
from .protocol import CommandFrame, FrameDecoder, StateFrame, encode_command

__all__ = ["Link", "LinkStats", "open_link", "not_a_serial_device"]


@dataclass
class LinkStats:
    """Counters of one link (all since it was opened).

    ``bad_frames`` chunks rejected by the decoder (garbage, corrupted, truncated);
    ``resyncs`` times the decoder found a valid frame again after bad ones;
    ``timeouts`` reads that reached their deadline with no valid frame;
    ``seq_gaps`` state frames missing by sequence number (dropped or destroyed; a
    frame that arrives late is no longer missing);
    ``stale_frames`` valid frames skipped because a newer one was already waiting;
    ``late_frames`` state frames dropped because they arrived after a newer one
    (their ``seq`` is behind the last accepted one, mod 2^32);
    ``duplicate_frames`` state frames dropped because their ``seq`` repeats the last
    accepted one;
    ``write_timeouts`` command writes that timed out (tolerated up to
    :attr:`Link.dead_after_s`).
    """

    frames_in: int = 0
    frames_out: int = 0
    bytes_in: int = 0
    bytes_out: int = 0
    bad_frames: int = 0
    resyncs: int = 0
    garbage_bytes: int = 0
    timeouts: int = 0
    seq_gaps: int = 0
    stale_frames: int = 0
    late_frames: int = 0
    duplicate_frames: int = 0
    unexpected_frames: int = 0
    write_timeouts: int = 0

    def as_dict(self) -> dict:
        return asdict(self)


def _fast_codec():
    """The compiled state-frame decoder and command encoder (:mod:`.frame_codec`), or
    (None, None) (the Python route) where numba cannot compile or cache them."""
    try:
        from .frame_codec import command_encoder, state_decoder
        return state_decoder(), command_encoder()
    except (ImportError, OSError):
        return None, None


class Link:
    """A framed, counted, deadline-bounded connection to a device.

    Parameters
    ----------
    url : str
        Anything :func:`serial.serial_for_url` accepts.
    baudrate : int
        Ignored by ptys, ``loop://`` and sockets; used by real UARTs.
    poll_s : float
        Granularity of one blocking read, s (a read never waits longer than its deadline).
    write_timeout_s : float
        Longest a single write may block, s.
    dead_after_s : float
        Writes that keep timing out for this long mean the device is gone, s.
    busy_wait_s : float
        A device file (a UART, a pty): poll it for up to this long (s) before sleeping
        until bytes arrive.  Sleeping costs a wake-up when they come (on the 2-core
        virtual machine of BENCHMARKS.md, a pty round trip through an echoing process
        takes 62 µs at the median when both sides sleep and 40 µs when they poll); polling
        keeps a core busy for the whole wait.  0 (the default): sleep at once.
    """

    def __init__(self, url: str, *, baudrate: int = 1_000_000, poll_s: float = 0.002,
                 write_timeout_s: float = 0.05, dead_after_s: float = 1.0,
                 busy_wait_s: float = 0.0):
        import serial  # the only place distkin imports pyserial
        self._serial_mod = serial
        self.url = url
        self.poll_s = poll_s
        self.busy_wait_s = float(busy_wait_s)
        # the codec first: on an empty numba cache it compiles for seconds, which must
        # happen before the device sees a connection, not while it streams to us
        decoder, encoder = _fast_codec()
        not_tty = not_a_serial_device(url)
        if not_tty:
            raise LinkError(f"expected a serial device (a tty) or a URL, got {url!r}, "
                            f"which is {not_tty}", field="port")
        try:
            self._ser = serial.serial_for_url(url, baudrate=baudrate, timeout=poll_s,
                                              write_timeout=write_timeout_s)
        except (serial.SerialException, OSError, ValueError) as exc:
            if f"({errno.ENOTTY}," in str(exc) or getattr(exc, "errno", None) == errno.ENOTTY:
                raise LinkError(f"expected a serial device (a tty) or a URL, got {url!r}, "
                                f"which is not a serial device (tty): it takes no serial "
                                f"line settings ({exc})", field="port") from None
            raise LinkError(f"expected an openable serial URL, got {url!r} ({exc})",
                            field="port") from None
        # a device file (a UART, a pty): read it by os.read on its non-blocking
        # descriptor, everything available in one call, and wait by select; other
        # URLs (loop://, socket://) through pyserial's read
        self._fd = None
        posix = getattr(serial, "serialposix", None)
        if posix is not None and isinstance(self._ser, posix.Serial):
            self._fd = self._ser.fileno()
        self._dec = FrameDecoder(fast=decoder)
        self._encode = encoder or encode_command
        self.stats = LinkStats()
        self._last_seq = None
        self._missing = 0
        self._last_write_ok = time.perf_counter()
        self.dead_after_s = dead_after_s
        self.closed = False

    # -- reading -------------------------------------------------------------------
    def _sync_decoder_stats(self) -> None:
        s, d = self.stats, self._dec
        s.bad_frames, s.resyncs, s.garbage_bytes = d.bad_frames, d.resyncs, d.garbage_bytes

    def _read_fd(self, wait: float) -> bytes:
        """Everything the device file holds now; if nothing, wait up to ``wait`` s for
        bytes to arrive and take what came.  b"" if nothing arrived."""
        fd = self._fd
        try:
            try:
                data = os.read(fd, 65536)       # VMIN = 0 (pyserial): b"" if empty
            except BlockingIOError:
                data = b""
            if not data:
                if wait <= 0 or not self._wait_readable(fd, wait):
                    return b""
                data = os.read(fd, 65536)
                if not data:                    # pyserial's reading of this case too
                    raise OSError("the device reports data to read but returned none")
        except BlockingIOError:
            return b""
        except OSError as exc:
            raise LinkError(f"expected a connected device on {self.url}, got a "
                            f"disconnect ({exc})", field="port") from None
        self.stats.bytes_in += len(data)
        return data

    @property
    def polling_s(self) -> float:
        """How long a read polls before it sleeps (s): ``busy_wait_s`` on a device
        file; 0 on a URL port (socket://, loop://), which pyserial reads."""
        return self.busy_wait_s if self._fd is not None else 0.0

    def _wait_readable(self, fd: int, wait: float) -> bool:
        """Whether ``fd`` becomes readable within ``wait`` s: polled for up to
        ``busy_wait_s`` of it, then slept for in select."""
        spin = min(wait, self.busy_wait_s)
        if spin > 0:
            clock, sel = time.perf_counter, select.select
            end = clock() + spin
            while True:
                if sel([fd], [], [], 0)[0]:
                    return True
                if clock() >= end:
                    break
            wait -= spin
            if wait <= 0:
                return False
        return bool(select.select([fd], [], [], wait)[0])

    def _read_some(self, wait: float) -> bytes:
        """A URL port (socket://, loop://): what is waiting, or the first byte to come
        within ``wait`` s and what came with it (pyserial's read, its timeout set to the
        wait, so that a read keeps the caller's deadline)."""
        try:
            n = self._ser.in_waiting
            if n == 0:
                wait = max(wait, 0.0)
                if self._ser.timeout != wait:
                    self._ser.timeout = wait
            data = self._ser.read(n if n > 0 else 1)
            if data and n == 0:
                m = self._ser.in_waiting
                if m:
                    data += self._ser.read(m)
        except (self._serial_mod.SerialException, OSError) as exc:
            raise LinkError(f"expected a connected device on {self.url}, got a "
                            f"disconnect ({exc})", field="port") from None
        self.stats.bytes_in += len(data)
        return data

    #: a read of a device file this long (bytes) or longer may have left bytes waiting:
    #: read again (about a dozen frames; the usual read holds one or two)
    LONG_READ = 1024

    #: how far back (in sequence numbers) a late frame is still matched to the gap it
    #: left, so that ``seq_gaps`` counts only frames that never came
    SEQ_WINDOW = 64

    def _note_seq(self, seq: int) -> bool:
        """Account for a state frame's ``seq`` (u32, wraps at 2^32: docs/protocol.md);
        False if the frame is not newer than the last accepted one (a duplicate or a
        late arrival, counted; the caller drops it).

        Serial-number arithmetic: ``seq`` is newer when ``(seq - last) mod 2^32`` is in
        1 .. 2^31 - 1.  ``_missing`` has bit ``d`` set while ``last - d`` is missing
        (d < :attr:`SEQ_WINDOW`)."""
        last = self._last_seq
        if last is None:
            self._last_seq, self._missing = seq, 0
            return True
        ahead = (seq - last) & 0xFFFFFFFF
        if 0 < ahead < 0x80000000:
            gap = ahead - 1
            if gap:
                self.stats.seq_gaps += gap
            if ahead < self.SEQ_WINDOW:
                self._missing = ((self._missing << ahead) | ((1 << ahead) - 2)) \
                    & ((1 << self.SEQ_WINDOW) - 1)
            else:
                self._missing = (1 << self.SEQ_WINDOW) - 2
            self._last_seq = seq
            return True
        if ahead == 0:
            self.stats.duplicate_frames += 1
            return False
        behind = (last - seq) & 0xFFFFFFFF
        self.stats.late_frames += 1
        if behind < self.SEQ_WINDOW and self._missing >> behind & 1:
            self._missing &= ~(1 << behind)       # it came after all: not missing
            self.stats.seq_gaps -= 1
        return False

    def read_state(self, timeout_s: float) -> StateFrame | None:
        """The newest valid state frame that arrives within ``timeout_s``, or None.

        Every frame already waiting is decoded; older ones are counted as stale and only
        the newest is returned, so the controller always acts on the latest reading.  A
        frame whose ``seq`` is not newer than the last one accepted (a duplicate, or one
        that arrived after a newer one) is dropped and counted (``duplicate_frames``,
        ``late_frames``): a device that only repeats old frames reads as a silent one.  The
        deadline is checked on every pass, whatever arrives: a line that keeps
        delivering bytes that never form a frame (garbage, a wrong baud rate) ends the
        read at its deadline like a silent one (counted in ``timeouts``), and so does a
        stream of frames that never pauses (the newest is returned).

        Raises
        ------
        LinkError
            The device went away (end of file, I/O error).
        """
        deadline = time.perf_counter() + timeout_s
        latest = None
        fd = self._fd
        while True:
            if fd is not None:
                data = self._read_fd(0.0 if latest is not None else
                                     min(self.poll_s, deadline - time.perf_counter()))
            else:
                data = self._read_some(0.0 if latest is not None else
                                       min(self.poll_s, deadline - time.perf_counter()))
            if data:
                for msg in self._dec.feed(data):
                    if isinstance(msg, StateFrame):
                        self.stats.frames_in += 1
                        if not self._note_seq(msg.seq):
                            continue            # old news: as if it never came
                        if latest is not None:
                            self.stats.stale_frames += 1
                        latest = msg
                    else:
                        self.stats.unexpected_frames += 1
                self._sync_decoder_stats()
                # return once nothing more is waiting.  A device file: a short read
                # took all there was; after a long one (a backlog: the tty line
                # discipline hands out at most 4095 bytes a read) read again without
                # waiting, until a read comes back short or empty
                if latest is not None and (len(data) < self.LONG_READ if fd is not None
                                           else self._ser.in_waiting == 0):
                    return latest
            elif latest is not None:
                return latest
            if time.perf_counter() >= deadline:
                if latest is None:
                    self.stats.timeouts += 1
                return latest

    # -- writing -------------------------------------------------------------------
    def write_command(self, cmd: CommandFrame) -> bool:
        """Send one command frame; False if the write timed out (counted).

        A write that times out (the device is not reading, or this process was not
        scheduled in time) may leave a partial frame on the line, which the device's
        decoder drops as a bad frame.  Timeouts are tolerated for ``dead_after_s``; a
        device that takes nothing for longer is gone.

        Raises
        ------
        LinkError
            The write failed (device gone) or nothing could be written for
            ``dead_after_s``.
        InputError
            A torque that is NaN, inf or beyond float32 (the joint and the value named;
            :func:`.protocol.check_efforts`), or a frame field out of range: nothing is
            written (the control loop never sends one: it sends zero torque instead,
            event ``nonfinite_torque``).
        """
        data = self._encode(cmd.seq, cmd.ack, cmd.mode, cmd.torques, cmd.flags)
        try:
            if self._fd is not None:
                self._write_fd(data)
            else:
                self._ser.write(data)
        except self._serial_mod.SerialTimeoutException:
            now = time.perf_counter()
            self.stats.write_timeouts += 1
            if self._last_write_ok is not None and now - self._last_write_ok > self.dead_after_s:
                raise LinkError(f"expected {self.url} to take commands, got none written for "
                                f"{now - self._last_write_ok:.2f} s", field="port") from None
            return False
        except (self._serial_mod.SerialException, OSError) as exc:
            raise LinkError(f"expected to write to {self.url}, got {exc}", field="port") from None
        self._last_write_ok = time.perf_counter()
        self.stats.frames_out += 1
        self.stats.bytes_out += len(data)
        return True

    def _write_fd(self, data: bytes) -> None:
        """Write all of ``data`` to the device file (os.write on the non-blocking
        descriptor; pyserial's write would also wait for the port to be writable
        again after every complete write); wait for room at most ``write_timeout_s``
        (then pyserial's SerialTimeoutException, with part of the frame maybe sent)."""
        fd = self._fd
        view = memoryview(data)
        deadline = None
        while True:
            try:
                n = os.write(fd, view)
            except BlockingIOError:
                n = 0
            if n == len(view):
                return
            view = view[n:]
            now = time.perf_counter()
            if deadline is None:
                deadline = now + self._ser.write_timeout
            if now >= deadline or not select.select([], [fd], [], deadline - now)[1]:
                raise self._serial_mod.SerialTimeoutException("Write timeout")

    def write_raw(self, data: bytes) -> None:
        """Send raw bytes (tests and fault injection on loopback links)."""
        try:
            self._ser.write(data)
        except (self._serial_mod.SerialException, OSError) as exc:
            raise LinkError(f"expected to write to {self.url}, got {exc}", field="port") from None

    def close(self) -> None:
        if not self.closed:
            self.closed = True
            try:
                self._ser.close()
            except (self._serial_mod.SerialException, OSError):
                pass  # closing a dead port must not mask the reason it died

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def not_a_serial_device(url: str) -> str:
    """What the path ``url`` names when it exists and is no character device (a regular
    file, a directory, a pipe, a socket: pyserial's "Inappropriate ioctl for device"
    otherwise); "" for a URL (``socket://``, ``loop://``), a character device, or a
    path that does not exist (pyserial says so)."""
    if "://" in url:
        return ""
    try:
        mode = os.stat(url).st_mode
    except (OSError, ValueError):
        return ""
    if stat.S_ISCHR(mode):
        return ""
    what = next((name for test, name in ((stat.S_ISREG, "a regular file"),
                                         (stat.S_ISDIR, "a directory"),
                                         (stat.S_ISFIFO, "a pipe"),
                                         (stat.S_ISSOCK, "a socket")) if test(mode)),
                "a special file")
    return f"{what}, not a serial device (tty)"


def open_link(url: str, **kw) -> Link:
    """Open a :class:`Link` (see its parameters)."""
    return Link(url, **kw)
