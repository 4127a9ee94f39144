"""QA 23 D1, D2: Ctrl-C on ``distkin control --sim`` (the whole process group, as a
terminal's) reported ``disconnect``, exit 2, 1 run in 5: the simulator child got the
SIGINT too and closed the port before the controller's loop looked at its own signal.
And ``distkin sim`` exited 0 on SIGINT/SIGTERM.  README: Ctrl-C (and SIGTERM) stops any
command with ``distkin: error: interrupted``, exit 130.

The race itself is not replayed (it depends on timing); its two halves are, each
deterministic: a signal that arrives with the link's end (the loop), and our own
simulator stopped by a signal while the controller got none (the command)."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from control_helpers import ScriptedLink, state_frames

from distkin.app.control_summary import simulator_interrupt
from distkin.control.config import builtin_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import model_of
from distkin.control.runlog import EXIT_CODES
from distkin.errors import LinkError

ROOT = Path(__file__).resolve().parents[2]


class _InterruptedAtTheEnd(ScriptedLink):
    """The script's device, whose last read delivers SIGINT to this process and then
    finds the port closed: what the controller saw when Ctrl-C stopped its simulator."""

    def _read_some(self, wait=0.0):
        if self.tick + 1 >= len(self.script):
            os.kill(os.getpid(), signal.SIGINT)       # the process group's Ctrl-C
            raise LinkError("expected a connected device, got a disconnect (closed)",
                            field="port")
        return super()._read_some(wait)


def test_a_signal_with_the_links_end_is_an_interrupt(monkeypatch):
    scene = builtin_scene()
    model = model_of(scene)
    dev = _InterruptedAtTheEnd(state_frames(model, range(1, 200))).patch(monkeypatch)
    s = Controller(scene, model).run(dev, 5.0)
    assert (s["exit_reason"], s["exit_code"]) == ("interrupted", EXIT_CODES["interrupted"])
    assert s["error"] is None
    # without the signal the same end is the device's
    dev = ScriptedLink(state_frames(model, range(1, 200))).patch(monkeypatch)
    s = Controller(scene, model).run(dev, 5.0)
    assert (s["exit_reason"], s["exit_code"]) == ("disconnect", EXIT_CODES["disconnect"])


def test_a_disconnect_by_our_signalled_simulator_is_an_interrupt():
    for code in (130, -signal.SIGINT, -signal.SIGTERM):
        s = {"exit_reason": "disconnect", "exit_code": 2, "error": "got a disconnect (x)"}
        simulator_interrupt(s, code)
        assert (s["exit_reason"], s["exit_code"], s["error"]) == ("interrupted", 130, None)
        assert "got a disconnect (x)" in s["simulator_stopped"]
    for code, reason in ((0, "disconnect"), (1, "disconnect"), (130, "completed")):
        s = {"exit_reason": reason, "exit_code": EXIT_CODES[reason], "error": None}
        simulator_interrupt(s, code)                     # untouched
        assert s["exit_reason"] == reason and "simulator_stopped" not in s


def _env():
    return dict(os.environ, OPENBLAS_NUM_THREADS="1",
                PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


def _children(pid):
    try:
        return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def test_the_simulator_child_stopped_by_sigterm_ends_the_run_interrupted(tmp_path):
    """Only the simulator is signalled (the controller gets nothing): the run is
    interrupted (130), not ended by the device (2)."""
    prefix = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "distkin", "control", "--sim",
                             "--seconds", "60", "--wall-limit", "300", "--log", str(prefix),
                             "--json", "-"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=_env(), cwd=tmp_path)
    try:
        spill = Path(f"{prefix}.cycles.csv.part")
        end = time.monotonic() + 240
        # the controller's first block of 4096 cycles: connected and running
        while time.monotonic() < end and proc.poll() is None and not (
                spill.exists() and spill.stat().st_size > 0):
            time.sleep(0.1)
        kids = _children(proc.pid)
        assert proc.poll() is None and kids, proc.stderr.read()
        os.kill(kids[0], signal.SIGTERM)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    err = err.decode()
    assert proc.returncode == 130, err
    errors = [line for line in err.splitlines() if line.startswith("distkin: error")]
    assert errors == ["distkin: error: interrupted"], err
    s = json.loads(out)
    assert s["exit_reason"] == "interrupted" and s["simulator_exit_code"] == 130
    assert "stopped by a signal" in s["simulator_stopped"]


def test_distkin_sim_exits_130_on_sigint_and_sigterm(tmp_path):
    for sig in (signal.SIGINT, signal.SIGTERM):
        port = tmp_path / f"port-{sig.name}"
        proc = subprocess.Popen([sys.executable, "-m", "distkin", "sim", "--port-file",
                                 str(port), "--idle-timeout", "60"], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, env=_env())
        try:
            end = time.monotonic() + 120
            while not port.exists() and time.monotonic() < end and proc.poll() is None:
                time.sleep(0.02)
            assert port.exists(), proc.stderr.read()
            proc.send_signal(sig)
            out, err = proc.communicate(timeout=60)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        assert proc.returncode == 130, err
        assert err.decode().strip().splitlines() == ["distkin: error: interrupted"]
        assert f"stopped (signal {sig.name})".encode() in out
