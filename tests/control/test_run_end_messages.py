"""QA X1 D3 and D7: a run the device or the link ended (``no_device``,
``no_valid_frames``, ``disconnect``, ``wall_limit``) exits 2 with one line on stderr
naming it (README "Device control", docs/design.md §4: ``distkin: error: FIELD:
expected ..., got ...``); they printed nothing.  A link that delivers only bytes that
never form a frame says so in the ``no_device`` message (it said "got none" with 2166
bad frames counted)."""

import numpy as np
import pytest

from distkin.app.control_commands import ENDED_BY, ended_line
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.runlog import EXIT_CODES
from distkin.app.control_commands import builtin_scene

from control_helpers import ScriptedLink, run_cli


@pytest.mark.parametrize("reason", ["no_device", "no_valid_frames", "disconnect",
                                    "wall_limit"])
def test_each_run_the_device_ended_has_a_line(reason):
    assert EXIT_CODES[reason] == 2 and reason in ENDED_BY          # the contract's list
    s = {"exit_reason": reason, "error": "expected X, got Y"}
    line = ended_line(s, sim=False)
    field = "--wall-limit" if reason == "wall_limit" else "--port"
    assert line == f"distkin: error: {field}: expected X, got Y (exit_reason {reason})"
    assert "\n" not in line
    if reason != "wall_limit":
        assert ended_line(s, sim=True).startswith("distkin: error: --sim: expected X")
    assert ended_line({"exit_reason": reason, "error": None}, sim=False).startswith(
        f"distkin: error: {field}: expected a completed run, got {reason}")


@pytest.mark.parametrize("reason", ["completed", "interrupted", "internal_error",
                                    "device_mismatch"])
def test_other_ends_have_no_such_line(reason):
    assert ended_line({"exit_reason": reason, "error": "x"}, sim=True) == ""


def _one_error_line(proc):
    assert "Traceback" not in proc.stderr
    errs = [ln for ln in proc.stderr.splitlines() if ln.startswith("distkin: error:")]
    assert len(errs) == 1, proc.stderr
    return errs[0]


def test_a_disconnect_prints_one_line(tmp_path):
    proc = run_cli(["control", "--sim", "--seconds", 1, "--faults", "disconnect@0.3"],
                   tmp_path)
    assert proc.returncode == 2
    line = _one_error_line(proc)
    assert line.startswith("distkin: error: --sim: expected a connected device")
    assert line.endswith("(exit_reason disconnect)")
    assert proc.stderr.strip().splitlines() == [line]       # the summary is on stdout


def test_the_wall_limit_prints_one_line(tmp_path):
    # (a wall limit no longer than --seconds is refused before the run: the device
    # stalls for 2 s instead, past the limit)
    proc = run_cli(["control", "--sim", "--seconds", 0.2, "--wall-limit", 0.3,
                    "--faults", "stall@0.01:2000"], tmp_path)
    assert proc.returncode == 2
    line = _one_error_line(proc)
    assert line.startswith("distkin: error: --wall-limit: expected 0.2 s of device time "
                           "within the wall-time limit of 0.3 s, got ")
    assert line.endswith("(exit_reason wall_limit)")


def test_garbage_only_is_named_in_the_no_device_message(monkeypatch):
    """A scripted device on a simulated clock streams random bytes, never a frame; the
    start-up wait shortened to 0.2 s of that clock."""
    rng = np.random.default_rng(7)
    script = [rng.integers(0, 256, 90, dtype=np.uint8).tobytes() for _ in range(400)]
    dev = ScriptedLink(script).patch(monkeypatch)
    ctl = Controller(builtin_scene(), load_model("octo"))
    ctl.STARTUP_TIMEOUT_S = 0.2
    s = ctl.run(dev, 1.0)
    assert s["exit_reason"] == "no_device" and s["bad_frames"] > 0
    assert f"but {s['bad_frames']} bad frames" in s["error"]
    assert "wrong baud rate" in s["error"]
    silent = ScriptedLink([None] * 400).patch(monkeypatch)
    ctl = Controller(builtin_scene(), load_model("octo"))
    ctl.STARTUP_TIMEOUT_S = 0.2
    s = ctl.run(silent, 1.0)
    assert s["error"] == "expected state frames from the device, got none in 0.2 s"
