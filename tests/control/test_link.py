"""The pyserial link over loop:// : newest frame wins, counters, deadlines, disconnects."""

import os
import subprocess
import sys
import time

import numpy as np
import pytest

from distkin.control.link import Link
from distkin.control.protocol import MODE_RUN, CommandFrame, encode_state
from distkin.errors import LinkError


def _state(seq):
    return encode_state(seq, 1000 * seq, 0, np.full(8, 0.001 * seq), np.zeros(6))


def test_loop_returns_newest_and_counts_stale_and_gaps():
    with Link("loop://") as link:
        link.write_raw(_state(1) + _state(2) + _state(5))
        msg = link.read_state(0.5)
        assert msg.seq == 5
        assert link.stats.stale_frames == 2
        assert link.stats.seq_gaps == 2          # 3 and 4 never arrived
        assert link.stats.frames_in == 3


def test_loop_counts_bad_frames_and_resyncs():
    with Link("loop://") as link:
        bad = bytearray(_state(2))
        bad[10] ^= 0xFF
        junk = np.random.default_rng(5).integers(0, 256, 40, dtype=np.uint8).tobytes()
        link.write_raw(_state(1) + junk + b"\x00" + bytes(bad) + _state(3))
        seen = []
        while True:
            m = link.read_state(0.05)
            if m is None:
                break
            seen.append(m.seq)
        assert seen[-1] == 3
        assert link.stats.bad_frames >= 2
        assert link.stats.resyncs == 1
        assert link.stats.timeouts == 1


def test_read_respects_its_deadline_and_counts_timeouts():
    with Link("loop://", poll_s=0.001) as link:
        assert link.read_state(0.01) is None
        assert link.read_state(0.0) is None
        assert link.stats.timeouts == 2


def test_commands_are_written_as_frames():
    with Link("loop://") as link:
        link.write_command(CommandFrame(1, 0, MODE_RUN, 0, np.ones(8)))
        # loop:// echoes: the command comes back and is counted as unexpected
        assert link.read_state(0.05) is None
        assert link.stats.unexpected_frames == 1
        assert link.stats.frames_out == 1


def test_unopenable_port_is_a_link_error():
    with pytest.raises(LinkError, match="port"):
        Link("/dev/does-not-exist-distkin")


def test_pty_disconnect_is_a_link_error():
    import tty
    master, slave = os.openpty()
    tty.setraw(slave)
    path = os.ttyname(slave)
    link = Link(path)
    os.close(slave)
    os.write(master, _state(1))
    assert link.read_state(0.5).seq == 1
    os.close(master)
    with pytest.raises(LinkError, match="disconnect"):
        link.read_state(0.5)
    link.close()


def test_import_control_pulls_in_neither_sympy_nor_serial():
    code = ("import sys, distkin.control, distkin.control.controller, "
            "distkin.control.simulator, distkin.app.control_commands\n"
            "print('sympy' in sys.modules, 'serial' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=os.path.dirname(os.path.dirname(os.path.dirname(
                             os.path.abspath(__file__)))))
    assert out.stdout.split() == ["False", "False"]


def test_running_the_controller_and_simulator_never_imports_sympy():
    # the generated kernels are plain Python: a whole in-process closed loop (scene,
    # mechanism preset, controller, plant) runs without sympy
    code = ("import sys\n"
            "from distkin.app.control_commands import builtin_scene\n"
            "from distkin.control.kinematics import load_model\n"
            "from distkin.control.loopback import run_loopback\n"
            "sc = builtin_scene(); r = run_loopback(sc, load_model(sc.preset), 0.05)\n"
            "print(len(r['t']), 'sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=os.path.dirname(os.path.dirname(os.path.dirname(
                             os.path.abspath(__file__)))))
    assert out.stdout.split() == ["50", "False"]


def test_late_and_duplicate_frames_are_dropped_counted_and_fill_their_gap():
    """QA 24: a late frame moved the last seq backwards (then 701 'missing' for swapped
    neighbours) and was returned as fresh data."""
    with Link("loop://") as link:
        got = []
        for s in (1, 3, 2, 3, 5, 4, 6):
            link.write_raw(_state(s))
            msg = link.read_state(0.05)
            got.append(None if msg is None else msg.seq)
        assert got == [1, 3, None, None, 5, None, 6]
        st = link.stats
        assert st.late_frames == 2 and st.duplicate_frames == 1
        assert st.seq_gaps == 0                  # 2 and 4 came, late
        link.write_raw(_state(10))
        assert link.read_state(0.05).seq == 10
        assert link.stats.seq_gaps == 3          # 7, 8, 9 never came
        link.write_raw(_state(1))                # far behind: late, no gap filled
        assert link.read_state(0.05) is None
        assert link.stats.late_frames == 3 and link.stats.seq_gaps == 3


def test_sequence_numbers_wrap_at_2_to_the_32():
    """docs/protocol.md: seq is a u32 that wraps; 0 follows 2^32 - 1."""
    top = 2 ** 32
    with Link("loop://") as link:
        for s in (top - 2, top - 1, 0, 1):
            link.write_raw(_state(s))
            assert link.read_state(0.05).seq == s
        link.write_raw(_state(top - 1))          # from before the wrap: late
        assert link.read_state(0.05) is None
        link.write_raw(_state(3))
        assert link.read_state(0.05).seq == 3
        st = link.stats
        assert st.seq_gaps == 1 and st.late_frames == 1 and st.duplicate_frames == 0


def test_a_pty_backlog_is_read_to_its_newest_frame():
    """QA K 2: a tty read hands out at most 4095 bytes; the link took a read shorter
    than 4096 bytes for 'all there was' and returned seq 50 of 200 waiting (the
    controller then acted on readings up to 150 ms old)."""
    import tty
    master, slave = os.openpty()
    tty.setraw(slave)
    link = Link(os.ttyname(slave))
    try:
        os.close(slave)
        wire = b"".join(_state(s) for s in range(1, 151))     # 12 KB: 3 reads' worth
        os.set_blocking(master, False)           # a pty takes ~20 KB, a write less at once
        sent = 0
        for _ in range(500):
            try:
                sent += os.write(master, wire[sent:])
            except BlockingIOError:
                pass
            if sent == len(wire):
                break
            time.sleep(0.002)                    # the kernel moves bytes to the reader
        assert sent == len(wire)
        time.sleep(0.1)
        msg = link.read_state(0.5)
        assert msg.seq == 150                    # the newest, in one call
        assert link.stats.stale_frames == 149
        assert link.stats.frames_in == 150 and link.stats.seq_gaps == 0
    finally:
        link.close()
        os.close(master)


def test_a_url_port_read_waits_no_longer_than_its_deadline():
    """QA K 5: on loop:// and socket:// a read waited pyserial's fixed timeout (poll_s)
    whatever was left of the deadline; the wait given to pyserial is now the deadline's
    remainder (checked on the port's timeout, not on the wall clock)."""
    with Link("loop://", poll_s=0.002) as link:
        assert link.read_state(0.0005) is None
        assert link._ser.timeout <= 0.0005
        link.write_raw(_state(1))
        assert link.read_state(0.5).seq == 1
