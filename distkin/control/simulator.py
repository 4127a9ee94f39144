"""The device simulator: serves the distkin protocol on a pseudo-terminal or a TCP socket.

It plays the device of Kühne et al. Fig. 9 (motors, capstans, encoders, F/T sensor,
platform; physics in :mod:`.plant`) so that the whole loop runs and is tested on a
machine without hardware.  Every device period (1 ms) it

1. sends a state frame (encoders, F/T reading, status), through the fault injector;
2. collects the commands that arrived; in *lockstep* mode it waits (up to
   ``reply_timeout_ms`` of wall time) for the answer to the frame just sent, so that a
   slow or loaded host slows the simulation instead of changing its physics;
3. waits for the next tick of its clock; when the process was held up (a loaded or
   virtual machine), the late ticks follow back to back until the schedule is met, as
   a device with its own clock would send them (up to ``catch_up_ms`` late; a longer
   hold re-bases the schedule, a *slip*);
4. advances the physics by one period under the latest command (zero torque if none
   arrived within ``device_watchdog_ms``).

Physics time starts with the first command; until then the device rests at its home
pose (held by its brakes) and its clock stands at 0.

The device's own log (``PREFIX.device.csv``: true pose, applied torques, hand force,
mode) is the ground truth against which the tests judge the controller.
"""

from __future__ import annotations

import errno
import os
import re
import select
import signal
import socket
import sys
import tempfile
import time
import tty
from pathlib import Path

import numpy as np

from ..errors import InputError
from .faults import DISCONNECT, FaultInjector
from .plant import Plant
from .protocol import (FLAG_KEEPALIVE, MODE_ZERO_TORQUE, STATUS_DEVICE_WATCHDOG,
                       CommandFrame, FrameDecoder, encode_readings)
from .runlog import EXIT_CODES, CsvLog, EventLog
from .scheduling import realtime, restore, tight_timer_slack

__all__ = ["PtyTransport", "TcpTransport", "Disconnected", "Simulator", "serve",
           "IDLE_TIMEOUT_S", "INTERRUPTED_EXIT", "check_port_file", "write_port_file",
           "closing_line"]

#: the exit code of a simulator stopped by SIGINT or SIGTERM (as every distkin command)
INTERRUPTED_EXIT = EXIT_CODES["interrupted"]

#: ``distkin sim`` stops when no client connects, or no command arrives, for this long (s)
IDLE_TIMEOUT_S = 60.0


class Disconnected(Exception):
    """The host side went away."""


class _FdTransport:
    fd: int

    def wait_readable(self, timeout: float) -> bool:
        if timeout < 0:
            timeout = 0
        r, _, _ = select.select([self.fd], [], [], timeout)
        return bool(r)

    def read(self) -> bytes:
        try:
            data = os.read(self.fd, 65536)
        except BlockingIOError:
            return b""
        except OSError as exc:
            if exc.errno == errno.EIO:      # pty: no process has the other end open
                raise Disconnected("the host closed the port") from None
            raise Disconnected(str(exc)) from None
        if not data:
            raise Disconnected("end of file")
        return data

    def write(self, data: bytes) -> int:
        """Write without blocking; returns the bytes not written (dropped)."""
        try:
            n = os.write(self.fd, data)
        except BlockingIOError:
            return len(data)
        except OSError as exc:
            raise Disconnected(str(exc)) from None
        return len(data) - n


class PtyTransport(_FdTransport):
    """A pseudo-terminal: the simulator keeps the master; ``url`` is the slave path
    (open it with pyserial on the host side)."""

    def __init__(self):
        self.fd, self._slave = os.openpty()
        tty.setraw(self._slave)            # no echo, no line discipline: binary frames
        os.set_blocking(self.fd, False)
        self.url = os.ttyname(self._slave)

    def client_attached(self) -> None:
        """Drop our own handle on the slave once the host has opened it, so that the
        host closing its end reads as a disconnect (EIO)."""
        if self._slave is not None:
            os.close(self._slave)
            self._slave = None

    def close(self) -> None:
        self.client_attached()
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None


class TcpTransport(_FdTransport):
    """A TCP server for one client; ``url`` is the ``socket://`` URL for pyserial."""

    def __init__(self, port: int = 0, host: str = "127.0.0.1"):
        self._srv = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            self._srv.bind((host, port))
        except (OSError, OverflowError) as exc:
            self._srv.close()
            raise InputError(f"expected a free TCP port in 0..65535 on {host}, got {port!r} "
                             f"({getattr(exc, 'strerror', None) or exc})",
                             field="tcp_port") from None
        self._srv.listen(1)
        self.url = f"socket://{host}:{self._srv.getsockname()[1]}"
        self._conn = None
        self.fd = None

    def accept(self, timeout: float) -> bool:
        r, _, _ = select.select([self._srv], [], [], timeout)
        if not r:
            return False
        self._conn, _ = self._srv.accept()
        self._conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._conn.setblocking(False)
        self.fd = self._conn.fileno()
        return True

    def client_attached(self) -> None:
        pass

    def close(self) -> None:
        for s in (self._conn, self._srv):
            if s is not None:
                s.close()
        self._conn = self._srv = None
        self.fd = None


class Simulator:
    """The simulated device behind one transport.

    Parameters
    ----------
    scene : distkin.control.config.ControlScene
        Device preset, rate and the ``[simulator]`` table (hand, motors, pacing).
    model : distkin.control.kinematics.KinematicModel
    transport : PtyTransport or TcpTransport
    faults : sequence of distkin.control.faults.Fault
    log_prefix : str or None
        Write ``PREFIX.device.csv`` and ``PREFIX.device-events.jsonl``.
    """

    def __init__(self, scene, model, transport, *, faults=(), log_prefix=None):
        cfg = scene.simulator
        self.cfg = cfg
        self.model = model
        self.plant = Plant(model, cfg.motors, cfg.hand, seed=cfg.seed)
        self.transport = transport
        self.period = 1.0 / scene.rate_hz
        self.realtime = scene.realtime
        self.faults = FaultInjector(faults, seed=cfg.seed + 1)
        # frames by the compiled codec when the model has compiled kernels (the same
        # bytes and values; the Python route is the reference)
        self._encode = encode_readings
        fast = None
        if model.compiled is not None:
            from .frame_codec import command_decoder, state_encoder
            self._encode, fast = state_encoder(), command_decoder()
        self.decoder = FrameDecoder(fast=fast)
        L = model.L
        cols = (["t", "wall", "seq", "ack", "mode", "status"]
                + [f"x_{n}" for n in ("x", "y", "z", "rx", "ry", "rz")]
                + [f"v_{n}" for n in ("x", "y", "z", "wx", "wy", "wz")]
                + ["hand_x", "hand_y", "hand_z"]
                + [f"tau_cmd_{i}" for i in range(L)] + [f"tau_{i}" for i in range(L)])
        self.log = CsvLog(f"{log_prefix}.device.csv" if log_prefix else None, cols)
        self.events = EventLog(f"{log_prefix}.device-events.jsonl" if log_prefix else None)
        self.command = CommandFrame(0, 0, MODE_ZERO_TORQUE, 0, np.zeros(L))
        self.armed = False
        #: bytes of state frames the transport could not take (a host not reading);
        #: ``dropped_before_host`` of them before the host's first command (the frames
        #: the simulator streams into a pty or socket nobody reads yet: QA 2026-11-29
        #: saw 131599 "dropped" beside 0 bad and 0 missing frames at the host)
        self.dropped_bytes = 0
        self.dropped_before_host = 0
        self.commands = 0
        self.stop = False
        #: the name of the signal that set :attr:`stop` (``serve``), for the closing event
        self.stop_signal = None
        #: stop :meth:`run` after this long without a command (s of wall time; None: never)
        self.idle_timeout = None
        #: ticks that started late (their wall time past their schedule), the largest
        #: lateness (s), the times the schedule was re-based (late beyond
        #: ``catch_up_ms``) and the wall time those re-basings gave up (s)
        self.late_ticks = 0
        self.max_late = 0.0
        self.slips = 0
        self.slipped = 0.0

    def _collect(self, wait_for: int | None, deadline: float) -> None:
        """Read commands until ``deadline``; with ``wait_for`` return as soon as the
        answer to that state frame (or a keep-alive) has arrived."""
        while True:
            remaining = deadline - time.perf_counter()
            if not self.transport.wait_readable(max(remaining, 0.0)):
                if remaining <= 0:
                    return
                continue
            got_answer = False
            for msg in self.decoder.feed(self.transport.read()):
                if not isinstance(msg, CommandFrame) or msg.torques.size != self.model.L:
                    continue
                if not self.armed:
                    self.armed = True
                    self.transport.client_attached()
                    self.events.add(self.plant.t, "armed")
                self.command = msg
                self.last_command_wall = time.perf_counter()
                self.commands += 1
                if wait_for is not None and (msg.ack == wait_for or msg.flags & FLAG_KEEPALIVE):
                    got_answer = True
            if got_answer or time.perf_counter() >= deadline:
                return

    def run(self, seconds: float | None = None) -> str:
        """Serve until the host disconnects, a disconnect fault, a signal, or
        ``seconds`` of device time.  Returns the reason."""
        tight_timer_slack()
        rt = None
        if self.realtime:
            rt, why = realtime()
            if why:
                self.events.add(self.plant.t, "realtime_refused", message=why)
        seq = 0
        next_tick = time.perf_counter()
        self.last_command_wall = None
        reason = "stopped"
        started = time.perf_counter()
        try:
            while not self.stop:
                p = self.plant
                if seconds is not None and p.t >= seconds:
                    reason = "time"
                    break
                if self.idle_timeout is not None and time.perf_counter() - (
                        self.last_command_wall or started) > self.idle_timeout:
                    reason = f"idle: no command for {self.idle_timeout:g} s"
                    break
                status = p.status()
                watchdog = (self.armed and self.last_command_wall is not None and
                            time.perf_counter() - self.last_command_wall
                            > self.cfg.device_watchdog_ms * 1e-3)
                if watchdog:
                    status |= STATUS_DEVICE_WATCHDOG
                seq = (seq + 1) & 0xFFFFFFFF
                frame = self._encode(seq, int(round(p.t * 1e6)), status, p.readings())
                out = self.faults.outgoing(p.t, frame) if self.armed else frame
                if out is DISCONNECT:
                    self.events.add(p.t, "disconnect_fault")
                    reason = "disconnect_fault"
                    break
                stall = self.faults.take_stall_ms()
                if stall:
                    self.events.add(p.t, "stall", ms=stall)
                    self._stall(stall * 1e-3)
                    next_tick = time.perf_counter()
                    continue
                if self.armed:
                    # take in what arrived since the last tick first, so that a
                    # keep-alive the host sent before this frame cannot release the
                    # lock-step wait for the answer to this frame
                    self._collect(None, time.perf_counter())
                if out:
                    lost = self.transport.write(out)
                    self.dropped_bytes += lost
                    if not self.armed:
                        self.dropped_before_host += lost
                sent_ok = out == frame
                if self.cfg.lockstep and self.armed and sent_ok:
                    self._collect(seq, time.perf_counter() + self.cfg.reply_timeout_ms * 1e-3)
                next_tick += self.period
                late = time.perf_counter() - next_tick
                if late > 0:
                    self.late_ticks += 1
                    self.max_late = max(self.max_late, late)
                    if late > self.cfg.catch_up_ms * 1e-3:
                        next_tick += late         # held up too long: re-base, a slip
                        self.slips += 1
                        self.slipped += late
                self._collect(None, next_tick)
                if self.armed:
                    self._step(seq, watchdog)
        except Disconnected as exc:
            reason = "host_disconnected"
            self.events.add(self.plant.t, "host_disconnected", message=str(exc),
                            last_mode=int(self.command.mode),
                            last_max_abs_torque=float(np.max(np.abs(self.command.torques))))
        finally:
            if self.stop and self.stop_signal:
                # SIGINT/SIGTERM: the event log says how it ended, as after a disconnect
                reason = f"signal {self.stop_signal}"
                self.events.add(self.plant.t, "stopped_by_signal", signal=self.stop_signal,
                                last_mode=int(self.command.mode),
                                last_max_abs_torque=float(np.max(np.abs(
                                    self.command.torques))))
            restore(rt)
            self.log.flush()
        return reason

    def _stall(self, duration: float) -> None:
        """Send nothing for ``duration`` s of wall time; physics and commands go on."""
        end = time.perf_counter() + duration
        tick = time.perf_counter()
        while time.perf_counter() < end and not self.stop:
            tick += self.period
            self._collect(None, min(tick, end))
            if self.armed:
                self._step(None, False)

    def _step(self, seq, watchdog: bool) -> None:
        cmd = self.command
        mode = MODE_ZERO_TORQUE if watchdog else cmd.mode
        p = self.plant
        bad = p.nonfinite_commands
        p.step(cmd.torques, mode, self.period)
        if p.nonfinite_commands and not bad:         # the first one: say so, once
            self.events.add(p.t, "nonfinite_command", seq=int(cmd.seq),
                            message="a command held NaN or inf: zero effort on those joints")
        if self.log.path is None:
            return                               # no device log: no row to make
        self.log.add((p.t, time.perf_counter(), -1 if seq is None else seq, cmd.ack, mode,
                      p.status(), *p.pose, *p.twist, *p.hand_wrench[:3], *cmd.torques, *p.tau))


#: what a port file of ``distkin sim`` holds: one URL, a device path or a TCP socket
_PORT_FILE = re.compile(r"(/dev/\S+|socket://\S+)\n?")


def check_port_file(path) -> None:
    """Refuse a ``port_file`` that would replace something else (QA 23 D12): a
    symbolic link (it was replaced by a regular file), anything but a regular file,
    and a regular file that is not a port file of an earlier ``distkin sim`` (one line,
    a ``/dev/...`` path or a ``socket://`` URL), which is overwritten.  InputError
    naming ``port_file``."""
    p = Path(path)
    if not os.path.lexists(p):
        return
    why = ("a symbolic link (the port file is never written through one)" if p.is_symlink()
           else None if p.is_file() else "not a regular file")
    if why is None:
        try:
            with p.open("rb") as fh:
                head = fh.read(4097)
            text = head.decode("utf-8")
        except (OSError, UnicodeDecodeError):
            text = ""
        if len(head) > 4096 or not _PORT_FILE.fullmatch(text):
            why = "an existing file that is not a port file of distkin sim (one URL line)"
    if why:
        raise InputError(f"expected a new file or an earlier port file to replace, got "
                         f"{str(path)!r}, {why}", field="port_file",
                         hint="name another file, or remove it first")


def write_port_file(path, url: str) -> None:
    """Write ``url`` to ``path`` atomically: a temporary file of its own in the same
    folder (never an existing ``PATH.tmp``), then renamed over ``path``."""
    p = Path(path)
    fd, tmp = tempfile.mkstemp(dir=p.parent, prefix=f".{p.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(url + "\n")
        os.replace(tmp, p)
    except BaseException:
        if os.path.lexists(tmp):
            os.unlink(tmp)
        raise


def serve(scene, *, port_file=None, tcp_port=None, faults=(), log_prefix=None,
          seconds=None, announce=sys.stdout, idle_timeout=IDLE_TIMEOUT_S) -> int:
    """Start a simulator, announce its port, serve until done.  Returns an exit code:
    0, or :data:`INTERRUPTED_EXIT` (130) when SIGINT or SIGTERM stopped it (README:
    Ctrl-C stops any command with exit 130).

    Parameters
    ----------
    scene : ControlScene
    port_file : path or None
        The port URL is also written here (atomically) for the host to pick up.
    tcp_port : int or None
        Serve on TCP (0 = any free port) instead of a pseudo-terminal.
    faults : sequence of Fault
    log_prefix : str or None
    seconds : float or None
        Stop after this much device time.
    idle_timeout : float or None
        Stop when no client has connected (TCP), or no command has arrived, for this
        long (s of wall time; default :data:`IDLE_TIMEOUT_S`; None: never).
    """
    from .kinematics import model_of
    if port_file:
        check_port_file(port_file)
    model = model_of(scene)
    transport = TcpTransport(tcp_port) if tcp_port is not None else PtyTransport()
    sim = Simulator(scene, model, transport, faults=faults, log_prefix=log_prefix)

    def _on_signal(signum, _frame):
        sim.stop = True
        sim.stop_signal = signal.Signals(signum).name

    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    print(f"distkin sim: {model.L}-leg '{scene.preset}' device serving on {transport.url}",
          file=announce, flush=True)
    if port_file:
        write_port_file(port_file, transport.url)
    sim.idle_timeout = idle_timeout
    try:
        if isinstance(transport, TcpTransport):
            end = None if idle_timeout is None else time.perf_counter() + idle_timeout
            while not sim.stop and not transport.accept(0.2):
                if end is not None and time.perf_counter() > end:
                    print(f"distkin sim: stopped (idle): no client connected to "
                          f"{transport.url} within {idle_timeout:g} s", file=announce,
                          flush=True)
                    return 0
            if sim.stop:
                print(f"distkin sim: stopped (signal {sim.stop_signal}) before a client "
                      f"connected to {transport.url}", file=announce, flush=True)
                return INTERRUPTED_EXIT
        reason = sim.run(seconds)
    finally:
        transport.close()
    print(closing_line(sim, reason, transport.url), file=announce, flush=True)
    return INTERRUPTED_EXIT if sim.stop_signal else 0


def closing_line(sim, reason: str, url: str) -> str:
    """``distkin sim``'s last line: how it stopped and what it served.  Without a host
    (no command ever arrived) it says so, instead of counting device time that never
    started and frames nobody read (QA 23 D4).  Otherwise: device time, commands, bad
    frames, the state frames' bytes the port could not take, the *late ticks* (ticks that
    started after their time because the process was held up: sent back to back, so the
    device's clock keeps its schedule) and the *schedule slips* (a hold-up longer than
    ``[simulator] catch_up_ms``: the schedule re-based, that much device time lost)."""
    if not sim.armed:
        return (f"distkin sim: stopped ({reason}); no host sent a command on {url} (its "
                f"device time never started; the {sim.dropped_bytes} bytes of state "
                f"frames streamed meanwhile went unread)")
    return (f"distkin sim: stopped ({reason}); {sim.plant.t:.3f} s device time, "
            f"{sim.commands} commands received, {sim.decoder.bad_frames} bad frames, "
            f"{sim.dropped_bytes} bytes of state frames dropped"
            + (f" ({sim.dropped_before_host} before the host's first command)"
               if sim.dropped_before_host else "")
            + f", {sim.late_ticks} ticks late (max {sim.max_late * 1e3:.1f} ms; sent back "
            f"to back to keep the device's clock), {sim.slips} schedule slips "
            f"({sim.slipped * 1e3:.1f} ms of device time lost to hold-ups beyond "
            f"catch_up_ms = {sim.cfg.catch_up_ms:g} ms)")
