"""Crank angles are read modulo 2π by the simulator and the controller.

The inverse kinematics gives crank angles in (-π, π]: a crank that passes ±180° jumps
by 2π between two readings 1e-6 rad apart.  Review: the simulator took the joint rate
as the raw difference (a 2π/dt spike, 6283 rad/s at 1 kHz), the controller's PD saw a
2π error, and a joint end stop at ±180° read its side from the sign of that
difference.  The reference here is the device itself: the same rus8 device
(examples/rus8_device.toml) written with every crank frame turned by θ about its
axis (``crank0``, ``crank90`` rotated, the ranges moved by -θ) is the same machine, its
crank angles those of the original minus θ.  θ = π puts the home cranks (about
horizontal: q ≈ 0) at ±180°; θ = π/2 puts the lower end stops (-90°) at ±180°.  The
turned device must move as the original does, pressed against its end stops by a hand
and under the admittance controller alike.  Uncompiled models (the reference routes;
the compiled cycle's wrap is checked on the example's compiled model by readings
shifted by whole turns)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from distkin.app.scene import load_scene
from distkin.control.config import load_control_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import KinematicModel, model_of, range_excess, range_side
from distkin.control.loopback import run_loopback
from distkin.control.plant import HandScript, Motors, Plant
from distkin.control.protocol import MODE_HOLD, MODE_ZERO_TORQUE, StateFrame

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FREE = Motors(friction=0.0, gravity=0.0, force_noise=0.0, torque_noise=0.0)
#: from home towards a pose whose first crank is past its +90° (test_joint_end_stop_slide)
OUT = np.array([-0.021, 0.082, 0.012, 0.188, -0.734, 0.062])


def _vec(text):
    return np.array([float(v.strip().strip('"')) for v in text.split(",")])


def _turned_text(theta: float) -> str:
    """rus8_device.toml with every crank frame turned by ``theta`` (rad) about its axis:
    ``crank0' = cos θ crank0 + sin θ crank90``, ``crank90' = -sin θ crank0 + cos θ
    crank90`` (the crank at q' points where the original's does at q = q' + θ) and the
    ranges [-90, 90] deg moved by -θ."""
    src = (EXAMPLES / "rus8_device.toml").read_text()
    c, s = round(math.cos(theta), 15), round(math.sin(theta), 15)
    # each leg's IK branch as the original resolves it (the file leaves it to the
    # solution nearer q = 0 at home, which the turn moves; a turn about the axis keeps
    # the branch's sign)
    branches = iter([leg.branch for leg in
                     load_scene(EXAMPLES / "rus8_device.toml").mechanism.leg_table])

    def turn(m):
        c0, c90 = _vec(m.group(1)), _vec(m.group(2))
        a, b = c * c0 + s * c90, -s * c0 + c * c90
        fmt = lambda v: ", ".join(f"{x:.15g}" for x in v + 0.0)           # noqa: E731
        return (f"crank0 = [{fmt(a)}]\ncrank90 = [{fmt(b)}]\n"
                f"branch = {next(branches)}")

    out, n = re.subn(r"crank0 = \[([^\]]*)\]\ncrank90 = \[([^\]]*)\]", turn, src)
    assert n == 8
    d = math.degrees(theta)
    return out.replace("range = [-90, 90]", f"range = [{-90 - d:.12g}, {90 - d:.12g}]")


@pytest.fixture(scope="module")
def devices(tmp_path_factory):
    """{θ: (control scene, uncompiled model)} for θ = 0, π/2, π."""
    out = {}
    for theta in (0.0, math.pi / 2, math.pi):
        d = tmp_path_factory.mktemp(f"turn{int(round(math.degrees(theta)))}")
        (d / "rus8_device.toml").write_text(_turned_text(theta))
        (d / "control_rus8.toml").write_text((EXAMPLES / "control_rus8.toml").read_text())
        sc = load_control_scene(d / "control_rus8.toml",
                                mechanism_loader=lambda p: load_scene(p).mechanism)
        out[theta] = (sc, KinematicModel(sc.mechanism, compiled=False))
    return out


def _wrapped(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def test_the_turned_devices_are_the_same_machine(devices):
    """The premise: same poses reachable, crank angles q - θ (mod 2π), same Jacobian;
    θ = π has home cranks on both sides of ±180°, θ = π/2 lower stops at ±180°."""
    _, m0 = devices[0.0]
    rng = np.random.default_rng(5)
    for theta, (_, m) in devices.items():
        for _ in range(20):
            pose = m0.home + rng.uniform(-1, 1, 6) * [0.02, 0.02, 0.02, 0.2, 0.2, 0.2]
            q0, ok0 = m0.ik(pose)
            q, ok = m.ik(pose)
            assert ok == ok0
            np.testing.assert_allclose(_wrapped(q - (q0 - theta)), 0.0, atol=1e-12)
            np.testing.assert_allclose(m.jacobian(pose), m0.jacobian(pose), atol=1e-9)
            assert m.in_range(q) == m0.in_range(q0)
    q_home = devices[math.pi][1].ik(m0.home)[0]
    assert (np.abs(q_home) > 3.0).all()                  # rad: all cranks at ±180°
    assert np.allclose(np.abs(devices[math.pi / 2][1].joint_lo), np.pi)


def test_joint_step_and_range_side_against_brute_force():
    """joint_step is the difference modulo 2π in [-π, π); range_side names the end of
    the arc nearer going round (distances measured forward from hi and back from lo)."""
    rng = np.random.default_rng(11)
    mixed, cranks = (KinematicModel.__new__(KinematicModel) for _ in range(2))
    mixed.L, mixed.revolute = 4, np.array([True, True, True, False])
    mixed._wraps, mixed._all_revolute = True, False
    cranks.L, cranks.revolute, cranks._wraps, cranks._all_revolute = 4, np.ones(4, bool), \
        True, True
    for _ in range(500):
        a, b = rng.uniform(-4, 4, 4), rng.uniform(-4, 4, 4)
        d = mixed.joint_step(a, b)
        k = (d[:3] - (a - b)[:3]) / (2 * np.pi)
        np.testing.assert_allclose(k, np.round(k), atol=1e-12)
        assert (d[:3] >= -np.pi).all() and (d[:3] < np.pi).all() and d[3] == a[3] - b[3]
        np.testing.assert_array_equal(cranks.joint_step(a, b)[:3], d[:3])
        lo = rng.uniform(-2 * np.pi, 2 * np.pi)
        hi = lo + rng.uniform(0.1, 2 * np.pi - 0.1)
        q = rng.uniform(-4, 4)
        side = range_side(q, lo, hi)
        past_hi, before_lo = (q - hi) % (2 * np.pi), (lo - q) % (2 * np.pi)
        inside = any(lo <= q + 2 * np.pi * j <= hi for j in range(-3, 4))
        assert (side == 0.0) == inside == (range_excess(q, lo, hi) == 0.0)
        if not inside:
            assert side == (1.0 if past_hi <= before_lo else -1.0)
            assert range_excess(q, lo, hi) == pytest.approx(min(past_hi, before_lo))
    assert range_side(float("nan"), 0.0, 1.0) == 0.0
    assert range_side(2.0, -math.inf, math.inf) == 0.0


def _pressed(m, theta, force, n=600):
    """The platform pressed against crank 1's end stop by a steady hand (zero torque):
    poses (n, 6), joint rates (n, L), end-stop hits."""
    d = OUT[:3] / np.linalg.norm(OUT[:3])
    s = np.linspace(0, 1, 401)
    inside = [m.in_range(m.ik(m.home + t * OUT)[0]) for t in s]
    edge = m.home + s[np.argmin(inside) - 1] * OUT
    p = Plant(m, FREE, HandScript(((0.0, *(force * d)),)))
    p.pose, p.q = edge.copy(), m.ik(edge)[0]
    poses, rates = [], []
    for _ in range(n):
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        poses.append(p.pose.copy())
        rates.append(p.qdot.copy())
        assert m.in_range(p.q)
    return np.array(poses), np.array(rates), p.end_stop_hits


@pytest.mark.parametrize("theta", [math.pi / 2, math.pi], ids=["90deg", "180deg"])
def test_the_simulator_moves_the_turned_device_as_the_original(devices, theta):
    """Pressed by 20 N against its end stops (two of them at ±180° for θ = π/2): same
    poses and joint rates as the original (before: a 2π/dt rate whenever a crank passed
    ±180°, and a stop at ±180° that took its side from the raw difference froze or
    threw the platform)."""
    P0, R0, h0 = _pressed(devices[0.0][1], 0.0, 20.0)
    P, R, h = _pressed(devices[theta][1], theta, 20.0)
    # (the contacts make the motion chaotic: the two part by rounding, 2.4e-9 m after
    # 600 steps here, 7e-7 after 1500 (review); the tolerances leave room for another
    # machine's rounding, far below the 2π/dt of the bug)
    assert h0 > 10 and abs(h - h0) <= max(2, 0.02 * h0)
    np.testing.assert_allclose(P, P0, rtol=0, atol=1e-6)
    np.testing.assert_allclose(R, R0, rtol=0, atol=1e-3 * np.abs(R0).max())
    assert np.abs(R).max() < 50.0                        # rad/s; 2π/dt = 6283


def test_the_drives_hold_across_180_degrees(devices):
    """MODE_HOLD keeps the cranks where the hold began (θ = π: home cranks at ±180°);
    the hold torque is the original's (before: kp·2π on a crank that crossed)."""
    poses = {}
    for theta in (0.0, math.pi):
        m = devices[theta][1]
        p = Plant(m, Motors(force_noise=0.0, torque_noise=0.0),
                  HandScript(((0.0, 3.0, -2.0, 5.0),)))
        taus, qs = [], []
        for _ in range(300):
            p.step(np.zeros(m.L), MODE_HOLD, 1e-3)
            taus.append(p.tau.copy())
            qs.append(p.q.copy())
        poses[theta] = (np.array(taus), p.pose.copy(), np.array(qs))
    q = poses[math.pi][2]
    assert ((q > 0).any(axis=0) & (q < 0).any(axis=0)).any()     # a crank crossed ±180°
    np.testing.assert_allclose(poses[math.pi][0], poses[0.0][0], atol=1e-6)
    np.testing.assert_allclose(poses[math.pi][1], poses[0.0][1], atol=1e-9)
    assert np.abs(poses[math.pi][0]).max() < 1.5          # N·m, within the drives


def test_the_controller_drives_the_turned_device_as_the_original(devices):
    """The example's closed loop (admittance, PD, the scripted hand) for 0.6 s on the
    device turned by π, whose cranks sit at ±180° and cross it: the same motion as the
    original's.  Encoders of 2^20 times the example's counts: with the real ones
    (0.24 mrad) a pose 1e-9 apart flips a count now and then, kp x one count is
    0.01 N·m, and the two runs part by a few counts however right both are.  The
    agreement left is the forward kinematics' (it stops after a step under 1e-4, so
    the two estimates differ by ~2e-9 and the loop carries that)."""
    from dataclasses import replace
    runs = {}
    for theta in (0.0, math.pi):
        sc, m = devices[theta]
        mo = replace(sc.simulator.motors, counts_per_rev=sc.simulator.motors.counts_per_rev
                     * 2 ** 20)
        runs[theta] = run_loopback(replace(sc, simulator=replace(sc.simulator, motors=mo)),
                                   m, 0.6)
    a, b = runs[0.0], runs[math.pi]
    assert a["refused"].sum() == b["refused"].sum() == 0
    m = devices[math.pi][1]
    q = np.array([m.ik(p)[0] for p in b["pose"]])
    assert ((q > 0).any(axis=0) & (q < 0).any(axis=0)).any()     # a crank crossed ±180°
    motion = np.ptp(a["pose"], axis=0).max()
    assert motion > 5e-3                                          # m: the hand moved it
    np.testing.assert_allclose(b["pose"], a["pose"], atol=1e-4 * motion)
    tau_scale = np.abs(a["tau"]).max()
    assert tau_scale > 0.01                                       # N·m
    np.testing.assert_allclose(b["tau"], a["tau"], atol=1e-3 * tau_scale)


@pytest.fixture(scope="module")
def rus8_compiled():
    sc = load_control_scene(EXAMPLES / "control_rus8.toml",
                            mechanism_loader=lambda p: load_scene(p).mechanism)
    return sc, model_of(sc)


@pytest.mark.parametrize("fused", [True, False])
def test_a_reading_a_whole_turn_off_gives_the_same_torques(rus8_compiled, fused):
    """Encoder angles q + 2πk (k = -1, 0, 1 per crank) are the same crank positions:
    one cycle, fused compiled or Python steps, gives the same torques as for q
    (before: kp·2π more on every shifted crank, saturating the drives)."""
    sc, m = rus8_compiled
    rng = np.random.default_rng(2)
    pose = m.home + rng.uniform(-1, 1, 6) * [0.01, 0.01, 0.01, 0.1, 0.1, 0.1]
    q, ok = m.ik(pose)
    assert ok and m.in_range(q)
    k = rng.integers(-1, 2, m.L)
    k[0], k[1] = 1, -1
    ws = np.array([0.4, -0.3, 0.8, 0.01, 0.02, -0.01])
    taus = []
    for angles in (q, q + 2 * np.pi * k):
        ctl = Controller(sc, m, fused=fused)
        assert (ctl._fused is not None) == fused
        ctl.start_at(pose + 1e-3)          # a set point off the pose: a PD error
        ctl.started = True
        r1 = ctl.compute(StateFrame(1, 1000, 0, angles, ws), 1e-3)
        r2 = ctl.compute(StateFrame(2, 1000, 0, angles + 1e-4, ws), 1e-3)
        assert r1.reason == r2.reason == ""
        taus.append(np.concatenate([r1.torques, r2.torques]))
    assert np.abs(taus[0]).max() > 1e-3
    np.testing.assert_allclose(taus[1], taus[0], atol=1e-9 * np.abs(taus[0]).max())
