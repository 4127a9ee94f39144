"""A controller scene whose device is a distkin scene's mechanism (``[device] mechanism``):
the 8-RUS leg table of examples/rus8_device.toml under admittance control (issue 16:
the controller on every mechanism; prismatic legs in test_prismatic_device.py)."""

import json
import shutil

import numpy as np
import pytest

from distkin.app.control_commands import _scene
from distkin.app.scene import load_scene
from distkin.control.config import loads_control_scene
from distkin.errors import InputError

from control_helpers import ROOT, estimate_and_truth, run_cli, widen_timing

EXAMPLES = ROOT / "examples"


def _copy(tmp_path, *names):
    for n in names:
        shutil.copy(EXAMPLES / n, tmp_path / n)


def test_the_device_is_the_scenes_mechanism(tmp_path):
    _copy(tmp_path, "rus8_device.toml", "control_rus8.toml")
    scene = _scene(tmp_path / "control_rus8.toml")
    mech = load_scene(tmp_path / "rus8_device.toml").mechanism
    assert scene.mechanism == mech and scene.preset == mech.name == "rus8"
    # the centring spring is anchored at the mechanism's home, not at a preset's
    spring = scene.environment[0]
    assert np.allclose(spring.anchor, mech.home)


def test_ambiguous_or_missing_devices_are_refused(tmp_path):
    _copy(tmp_path, "rus8_device.toml")
    text = (EXAMPLES / "control_rus8.toml").read_text(encoding="utf-8")

    def load(t):
        p = tmp_path / "c.toml"
        p.write_text(t, encoding="utf-8")
        return _scene(p)

    # (prismatic legs: tests/control/test_prismatic_device.py)
    with pytest.raises(InputError, match="either device.preset or device.mechanism"):
        load(text.replace("[device]\n", '[device]\npreset = "octo"\n'))
    with pytest.raises(InputError, match="does not exist"):
        load(text.replace('"rus8_device.toml"', '"missing.toml"'))
    # without the application's scene parser the control layer says what it needs
    with pytest.raises(InputError, match="needs the scene parser"):
        loads_control_scene(text, str(tmp_path / "c.toml"))
    proc = run_cli(["control", "--sim", "--scene", tmp_path / "c.toml", "--seconds", 1],
                   tmp_path)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


def test_closed_loop_on_a_user_leg_table(tmp_path):
    """Two processes (controller and simulator, both on the leg table's kernels): the run
    completes, and the controller's forward kinematics from the quantised encoders agrees
    with the simulator's true pose (an independent route: the plant integrates the pose,
    the controller only sees crank angles)."""
    _copy(tmp_path, "rus8_device.toml", "control_rus8.toml")
    text = widen_timing((tmp_path / "control_rus8.toml").read_text(encoding="utf-8"))
    (tmp_path / "control_rus8.toml").write_text(text, encoding="utf-8")
    proc = run_cli(["control", "--sim", "--scene", tmp_path / "control_rus8.toml",
                    "--seconds", 1.5, "--log", tmp_path / "run", "--json", "-"], tmp_path,
                   timeout=300)
    assert proc.returncode == 0, proc.stderr
    s = json.loads(proc.stdout)
    assert s["exit_reason"] == "completed" and s["safety_events"] == 0
    est, true = estimate_and_truth(tmp_path / "run")
    assert len(est) > 1000
    # encoder quantum: 2π / (2000 counts x gear 13) rad at a 60 mm crank, about 15 µm
    # per leg; the pose from eight legs is within a few of those
    assert np.abs(est - true).max() < 1e-4
    # the hand's 1 N push moved the handle (the loop is not idle)
    assert np.ptp(true[:, 1]) > 1e-4
