"""Fault injection on a real socket: a device that sends bytes which never form a frame.

Issue 14: ``distkin control --port socket://...`` hung (no output, ``--wall-limit`` and
SIGINT ignored) when bytes kept arriving, because the read loop checked its deadline
only when nothing came.  The "device" here is a TCP server thread that streams random
bytes (bad COBS chunks, bad CRCs) for as long as the client is connected and records
what the client sends.  No test measures time: each runs the read, or the whole CLI,
under a generous timeout, so that a hang fails the test instead of stalling the suite.
"""

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from control_helpers import run_cli

from distkin.control.link import Link
from distkin.control.protocol import MODE_ZERO_TORQUE, CommandFrame, FrameDecoder

_HANG = 30          # s: far beyond every deadline below; reaching it means a hang
#: s: a CLI's start-up until it connects, a cold compile of the control cycle under load
#: included (each test worker's private cache starts empty): it took more than 30 s at a
#: load of ~4 on 2 cores (a full suite beside two other jobs), and the SIGINT test failed
_START = 300


class GarbageDevice:
    """A TCP server for one client: streams random bytes without a pause (so that some
    are always waiting) until stopped, and keeps what the client wrote
    (``received``)."""

    def __init__(self):
        self._srv = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._srv.bind(("127.0.0.1", 0))
        self._srv.listen(1)
        self.url = f"socket://127.0.0.1:{self._srv.getsockname()[1]}"
        self.received = bytearray()
        self.connected = threading.Event()
        self._stop = threading.Event()
        self._threads = [threading.Thread(target=self._serve, daemon=True)]
        self._threads[0].start()

    def _serve(self):
        self._srv.settimeout(_START)
        try:
            conn, _ = self._srv.accept()
        except OSError:
            return
        self._conn = conn
        self.connected.set()
        reader = threading.Thread(target=self._receive, daemon=True)
        reader.start()
        self._threads.append(reader)
        rng = np.random.default_rng(14)
        garbage = rng.integers(0, 256, 1 << 16, dtype=np.uint8).tobytes()
        conn.settimeout(0.05)
        k = 0
        while not self._stop.is_set():
            try:
                conn.sendall(garbage[k:k + 256])
            except socket.timeout:
                continue
            except OSError:
                break
            k = (k + 256) % len(garbage)

    def _receive(self):
        # keeps reading after stop until the client's bytes are drained (EOF, or a
        # quiet 0.05 s), so that the last command frames are never lost to a race
        # between this thread and close()
        while True:
            try:
                data = self._conn.recv(65536)
            except socket.timeout:
                if self._stop.is_set():
                    break
                continue
            except OSError:
                break
            if not data:
                break
            self.received += data

    def commands(self):
        """The command frames the client sent, decoded."""
        return [m for m in FrameDecoder().feed(bytes(self.received))
                if isinstance(m, CommandFrame)]

    def close(self):
        self._stop.set()
        for t in self._threads:           # sender first, then the draining receiver
            t.join(timeout=_HANG)
        conn = getattr(self, "_conn", None)
        if conn is not None:
            conn.close()
        self._srv.close()


def test_read_deadline_fires_while_garbage_keeps_arriving():
    """read_state(0.2) on a socket that never stops delivering garbage returns None (a
    timeout, counted), having read and rejected the bytes, instead of reading forever."""
    dev = GarbageDevice()
    try:
        with Link(dev.url) as link:
            out = {}
            reader = threading.Thread(target=lambda: out.update(frame=link.read_state(0.2)),
                                      daemon=True)
            reader.start()
            reader.join(timeout=_HANG)
            assert not reader.is_alive(), "read_state did not return: its deadline never fired"
            assert out["frame"] is None
            assert link.stats.timeouts == 1
            assert link.stats.bytes_in > 0 and link.stats.bad_frames > 0
    finally:
        dev.close()


def test_control_cli_ends_and_commands_zero_torque_against_garbage(tmp_path):
    """``distkin control --port socket://...`` against the garbage device ends by itself
    (the start-up timeout or --wall-limit, whichever first), exits 2 with its summary
    (the device ended the run; 1 is an internal failure, QA S 7),
    and its last frames on the wire command zero torque."""
    dev = GarbageDevice()
    try:
        proc = run_cli(["control", "--port", dev.url, "--seconds", 2, "--wall-limit", 3,
                        "--json", "-"], tmp_path, timeout=_START + 60)
    finally:
        dev.close()
    assert proc.returncode == 2, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["exit_reason"] in ("wall_limit", "no_device")
    assert summary["bad_frames"] > 0 and summary["cycles"] == 0
    cmds = dev.commands()
    assert cmds and cmds[-1].mode == MODE_ZERO_TORQUE and not np.any(cmds[-1].torques)


@pytest.mark.slow   # 14 s; garbage: the test above; a SIGINT's zero torque: tests/control/test_interrupt_not_disconnect.py
def test_control_cli_sigint_against_garbage_ends_with_zero_torque(tmp_path):
    """SIGINT while the controller reads garbage ends the run (exit 130, "interrupted")
    with zero torque commanded, however long --seconds and --wall-limit are."""
    dev = GarbageDevice()
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    proc = subprocess.Popen([sys.executable, "-m", "distkin", "control", "--port", dev.url,
                             "--seconds", "600", "--wall-limit", "1200", "--json", "-"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=tmp_path, env=env)
    try:
        assert dev.connected.wait(_START), "the controller never connected"
        time.sleep(0.5)                       # well inside its reading loop
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=_HANG)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
        dev.close()
    assert proc.returncode == 130, err
    summary = json.loads(out)
    assert summary["exit_reason"] == "interrupted"
    cmds = dev.commands()
    assert cmds and cmds[-1].mode == MODE_ZERO_TORQUE and not np.any(cmds[-1].torques)
    # the summary says so (QA 2026-11-29: it read "state: run at the end")
    assert summary["zero_torque_sent"] is True


def test_sim_on_tcp_without_a_client_stops(tmp_path):
    """``distkin sim --tcp 0`` with nobody connecting stops after its idle timeout."""
    proc = run_cli(["sim", "--tcp", 0, "--idle-timeout", 1], tmp_path, timeout=_START + 30)
    assert proc.returncode == 0, proc.stderr
    assert "serving on socket://" in proc.stdout
    assert "stopped (idle)" in proc.stdout
