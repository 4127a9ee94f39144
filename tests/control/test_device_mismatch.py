"""A controller scene that is not the device's: the first state frame holds another number
of joint angles than the scene has legs.  The run ends at once with ``device_mismatch``,
exit code 2 and one line naming both counts (it used to wait out the 10 s start-up
window, log ~10,000 "expected 6 encoder angles, got 8" events and end as ``no_device``,
exit 1).  Also: a run without a single frame prints "no frames", never "p50 None ms"."""

import subprocess
import sys
import time

import numpy as np
import pytest

from distkin.app.control_commands import builtin_scene, format_summary
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.link import Link
from distkin.control.protocol import encode_state

from control_helpers import ROOT, run_cli


def test_first_frame_with_other_joint_count_ends_the_run_with_exit_code_2():
    scene, model = builtin_scene(), load_model("octo")           # 8 legs
    ctl = Controller(scene, model)
    with Link("loop://") as link:
        link.write_raw(encode_state(1, 0, 0, np.zeros(6), np.zeros(6)))   # a 6-joint device
        t0 = time.perf_counter()
        s = ctl.run(link, 5.0)
        wall = time.perf_counter() - t0
    assert wall < 2.0                          # not the 10 s start-up window
    assert s["exit_reason"] == "device_mismatch" and s["exit_code"] == 2
    assert s["error"].startswith("device sends 6 joint angles, scene has 8 legs")
    events = [e["event"] for e in ctl.events.events]
    assert events == ["device_mismatch", "zero_torque"]      # one event, not one per frame
    text = format_summary(s)
    assert "no frames" in text and "None" not in text


def test_no_frames_summary_says_so():
    ctl = Controller(builtin_scene(), load_model("octo"))
    ctl.STARTUP_TIMEOUT_S = 0.2
    with Link("loop://") as link:
        s = ctl.run(link, 1.0)
    assert s["exit_reason"] == "no_device" and s["cycle_p50_ms"] is None
    text = format_summary(s)
    assert "compute per cycle: no frames" in text and "period between cycles: fewer than two cycles" in text
    assert "None" not in text


@pytest.mark.slow   # 19 s (a second mechanism's cycle compiled); the count check itself is tested in process in this file
def test_gough6_scene_against_the_octo_simulator_exits_2_naming_both_counts(tmp_path):
    """The QA run: ``distkin sim`` (the built-in 8-joint Octo) and ``distkin control
    --scene examples/control_gough6.toml`` (6 prismatic legs)."""
    port_file = tmp_path / "port"
    sim = subprocess.Popen([sys.executable, "-m", "distkin", "sim", "--port-file",
                            str(port_file), "--idle-timeout", "600"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    try:
        for _ in range(600):
            if port_file.exists() and port_file.read_text().strip():
                break
            assert sim.poll() is None, "the simulator did not start"
            time.sleep(0.05)
        url = port_file.read_text().strip()
        proc = run_cli(["control", "--port", url, "--scene",
                        ROOT / "examples" / "control_gough6.toml", "--seconds", 5], tmp_path)
    finally:
        sim.terminate()
        sim.wait(timeout=10)
    assert proc.returncode == 2, proc.stderr
    # (a cold cache adds "distkin: deriving ..." notices before it)
    err = [line for line in proc.stderr.splitlines() if line.startswith("distkin: error")]
    assert err == ["distkin: error: --scene: device sends 8 joint angles, scene has 6 legs "
                   "(expected state frames with 6 encoder angles: is the scene the "
                   "device's?)"], proc.stderr
    assert "device_mismatch" in proc.stdout and "no frames" in proc.stdout
    assert "Traceback" not in proc.stderr
