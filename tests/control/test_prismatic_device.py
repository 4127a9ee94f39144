"""The controller and the simulator on a device with prismatic legs (issue 16): the
6-UPS Gough-Stewart platform of examples/gough_stewart_6ups.toml driven by ball screws
(examples/control_gough6.toml).  Joint values are leg lengths (m), efforts forces (N)."""

import json
import math
import shutil
from types import SimpleNamespace

import numpy as np
import pytest

from distkin.app.control_commands import _scene
from distkin.control.config import PDGains, SafetyLimits, loads_control_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import model_of
from distkin.control.loopback import run_loopback
from distkin.control.plant import LinearDrives, Motors, Plant
from distkin.control.protocol import StateFrame
from distkin.errors import InputError

from control_helpers import ROOT, estimate_and_truth, run_cli, widen_timing

EXAMPLES = ROOT / "examples"


@pytest.fixture(scope="module")
def gough(tmp_path_factory):
    d = tmp_path_factory.mktemp("gough6")
    for n in ("gough_stewart_6ups.toml", "control_gough6.toml"):
        shutil.copy(EXAMPLES / n, d / n)
    scene = _scene(d / "control_gough6.toml")
    return SimpleNamespace(dir=d, scene=scene, model=model_of(scene, compiled=False))


def test_ball_screw_drives_at_the_leg():
    """The motor of :class:`Motors`, motor side, through a screw of lead p: force =
    torque x 2π/p, speed / (2π/p), inertia x (2π/p)², one count = p / counts (the
    power and the kinetic energy at the motor equal those at the leg)."""
    d, m = LinearDrives(lead=0.005), Motors()
    r = 2 * math.pi / 0.005
    tau_m, w_m = m.stall_torque / m.gear, m.nominal_speed * m.gear
    assert d.stall_effort == pytest.approx(tau_m * r, rel=1e-14)
    assert d.nominal_effort * d.nominal_speed == pytest.approx(
        m.nominal_torque * m.nominal_speed, rel=1e-14)              # same power
    v = 0.3                                                           # m/s at the leg
    assert 0.5 * d.joint_inertia * v ** 2 == pytest.approx(
        0.5 * m.rotor_inertia * (v * r) ** 2, rel=1e-14)              # same energy
    assert d.resolution == pytest.approx(0.005 / m.counts_per_rev, rel=1e-15)
    assert d.friction == pytest.approx(m.friction / m.gear ** 2 * r ** 2, rel=1e-14)
    # the hold gains: the rotary ones at the motor, through the screw
    kp, kd = d.hold_gains
    assert kp / r ** 2 == pytest.approx(m.hold_gains[0] / m.gear ** 2, rel=1e-14)
    assert kd / r ** 2 == pytest.approx(m.hold_gains[1] / m.gear ** 2, rel=1e-14)
    assert LinearDrives(friction=5.0).friction == 5.0


def test_the_scene_reads_lengths_and_forces(gough):
    sc = gough.scene
    assert sc.joint == "prismatic" and (sc.joint_unit, sc.effort_unit) == ("m", "N")
    assert sc.joint_range == ((0.35, 0.55),) * 6            # the legs' 350 ... 550 mm
    assert isinstance(sc.simulator.motors, LinearDrives) and sc.simulator.motors.lead == 0.01
    # without [pd] and [safety] the prismatic defaults apply, in N/m and m
    text = (gough.dir / "control_gough6.toml").read_text(encoding="utf-8")
    head = text.split("[pd]")[0]
    bare = loads_control_scene(head, str(gough.dir / "bare.toml"),
                               mechanism_loader=lambda p: gough.scene.mechanism)
    assert bare.pd == PDGains.for_drives(LinearDrives())
    assert bare.pd.kp == pytest.approx(110 * (2 * math.pi / 0.01 / 13) ** 2, rel=1e-14)
    assert bare.pd.torque_limit == pytest.approx(LinearDrives().nominal_effort)
    # the defaults follow the scene's screw: half the lead, four times the stiffness
    half = loads_control_scene(head + "[simulator]\nlead = 0.005\n",
                               str(gough.dir / "half.toml"),
                               mechanism_loader=lambda p: gough.scene.mechanism)
    assert half.pd.kp == pytest.approx(4 * bare.pd.kp, rel=1e-14)
    # the paper's gains are the revolute drives' defaults
    assert PDGains.for_drives(Motors()) == PDGains()
    assert bare.safety == SafetyLimits.for_joint("prismatic")


def _load(gough, text, name="c.toml"):
    p = gough.dir / name
    p.write_text(text, encoding="utf-8")
    return _scene(p)


def test_refusals_name_the_field_and_the_values(gough):
    text = (gough.dir / "control_gough6.toml").read_text(encoding="utf-8")
    with pytest.raises(InputError, match=r"max_angle .* each leg's range") as e:
        _load(gough, text.replace("[safety]\n", "[safety]\nmax_angle = 3\n"))
    assert e.value.field == "safety.max_angle"
    with pytest.raises(InputError, match=r"legs' actuator limit 1000 N, got 1200") as e:
        _load(gough, text.replace("torque_limit = 120 ", "torque_limit = 1200 "))
    assert e.value.field == "pd.torque_limit"
    with pytest.raises(InputError, match=r"stall force 1653 N, got 2000"):
        _load(gough, text.replace("torque_limit = 120 ", "torque_limit = 2000 "))
    # a leg without a range: the readings could not be checked
    mech = (gough.dir / "gough_stewart_6ups.toml").read_text(encoding="utf-8")
    (gough.dir / "norange.toml").write_text(mech.replace("range = [350, 550]\n", "", 1),
                                            encoding="utf-8")
    with pytest.raises(InputError, match=r"range .* got none on legs \[1\]"):
        _load(gough, text.replace('"gough_stewart_6ups.toml"', '"norange.toml"'))
    # a lead on a revolute device, and a device mixing both kinds of leg
    octo = (EXAMPLES / "control_octo.toml").read_text(encoding="utf-8")
    with pytest.raises(InputError, match="expected no lead") as e:
        loads_control_scene(octo.replace("[simulator]\n", "[simulator]\nlead = 0.01\n"))
    assert e.value.field == "simulator.lead"
    legs = gough.scene.mechanism.leg_description().leg_table
    mixed = SimpleNamespace(leg_description=lambda: SimpleNamespace(
        leg_table=legs[:5] + (SimpleNamespace(prismatic=False, range=None, limit=None),)))
    with pytest.raises(InputError, match=r"revolute legs \[6\] and prismatic legs "
                                         r"\[1, 2, 3, 4, 5\]"):
        loads_control_scene(text, str(gough.dir / "m.toml"), mechanism_loader=lambda p: mixed)


def test_a_reading_outside_a_legs_range_is_rejected(gough):
    ctl = Controller(gough.scene, gough.model, fused=False)
    q, ok = gough.model.ik(gough.model.home)
    assert ok
    frame = StateFrame(1, 0, 0, q.copy(), np.zeros(6))
    assert ctl.check_reading(frame) == ""
    frame.angles[3] = 0.56
    assert ctl.check_reading(frame) == "leg 4 length 0.56 m outside its range [0.35, 0.55] m"


def test_the_platform_rests_on_statically_balanced_leg_forces(gough):
    """Leg forces from statics (the minimum-norm ``J (JᵀJ)⁻¹ (0, 0, m g, 0, 0, 0)``)
    hold the 10 kg platform at home: an analytic equilibrium, not the controller."""
    model = gough.model
    plant = Plant(model, LinearDrives(force_noise=0, torque_noise=0))
    J = model.jacobian(model.home)
    tau = J @ np.linalg.solve(J.T @ J, np.array([0, 0, 10 * 9.81, 0, 0, 0]))
    for _ in range(500):
        plant.step(tau, 1, 1e-3)                       # MODE_RUN
    assert np.abs(plant.pose - model.home).max() < 1e-9
    # 10 % short: it starts to fall, from rest with the acceleration of the equations
    # of motion (distkin.control.plant): (M̂ + Jᵀ J_r J) a = Jᵀ 0.9 tau - m g e_z (the
    # screws' reflected mass makes it 0.27 m/s², not 0.1 g); semi-implicit Euler gives
    # z_n - z_0 = a dt² n(n+1)/2
    drives = plant.motors
    a = np.linalg.solve(np.asarray(model.mass) + drives.joint_inertia * J.T @ J,
                        J.T @ (0.9 * tau) - [0, 0, 10 * drives.gravity, 0, 0, 0])
    z0 = plant.pose[2]
    for _ in range(5):
        plant.step(tau * 0.9, 1, 1e-3)
    assert plant.pose[2] - z0 == pytest.approx(a[2] * 1e-6 * 15, rel=1e-2)
    for _ in range(95):
        plant.step(tau * 0.9, 1, 1e-3)
    assert plant.pose[2] < model.home[2] - 1e-3


def test_the_admittance_renders_the_spring(gough):
    """In-process loop (Python route): the hand's 2 N against the scene's 200 N/m
    centring spring settles at F/k = 10 mm (the servo, 2.57e5 N/m per leg, is in series
    and adds about 0.01 mm); the controller's FK from 5 µm length counts tracks the
    plant's pose."""
    r = run_loopback(gough.scene, gough.model, 1.0)
    y = r["pose"][:, 1]
    assert y[999] == pytest.approx(2.0 / 200.0, rel=0.01)
    assert not r["refused"].any()
    # the estimate is that of the frame the cycle answered (one period behind the plant)
    lag = np.abs(r["estimate"][1:, :3] - r["pose"][:-1, :3]).max()
    assert lag < 2e-5
    assert np.abs(r["tau"]).max() < gough.scene.pd.torque_limit


def test_two_process_run_over_the_pty(gough, tmp_path):
    """``distkin control --sim`` on the prismatic device: completed without safety
    events, the summary in N, and the controller's FK agrees with the simulator's true
    pose frame by frame."""
    text = widen_timing((gough.dir / "control_gough6.toml").read_text(encoding="utf-8"))
    for n in ("gough_stewart_6ups.toml",):
        shutil.copy(gough.dir / n, tmp_path / n)
    (tmp_path / "c.toml").write_text(text, encoding="utf-8")
    proc = run_cli(["control", "--sim", "--scene", tmp_path / "c.toml", "--seconds", 1.2,
                    "--log", tmp_path / "run", "--json", "-"], tmp_path, timeout=300)
    assert proc.returncode == 0, proc.stderr
    s = json.loads(proc.stdout)
    assert s["exit_reason"] == "completed" and s["safety_events"] == 0
    assert "max_abs_torque_Nm" not in s and s["force_limit_N"] == 120
    assert 0 < s["max_abs_force_N"] <= 120
    est, true = estimate_and_truth(tmp_path / "run")
    assert len(est) > 1000
    # one count is 5 µm of leg length; the pose from six legs is within a few counts
    assert np.abs(est - true).max() < 5e-5
    assert np.ptp(true[:, 1]) > 5e-3                  # the 2 N push moved the handle
