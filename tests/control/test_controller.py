"""The control cycle in-process: kinematics, admittance, distribution, saturation, guards."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.linalg import null_space
from scipy.optimize import minimize_scalar

from distkin.control.admittance import Admittance, Spring, Wall
from distkin.app.control_commands import builtin_scene
from distkin.control.controller import SCALING, Controller
from distkin.control.kinematics import load_model
from distkin.spatial import rotate_pose_scalar as rotate_pose
from distkin.control.loopback import run_loopback
from distkin.control.plant import HandScript
from distkin.control.protocol import STATUS_ESTOP, StateFrame


@pytest.fixture(scope="module")
def model():
    return load_model("octo")


@pytest.fixture(scope="module")
def scene():
    return builtin_scene()


def _random_poses(model, n, seed=0):
    rng = np.random.default_rng(seed)
    P = model.home + np.concatenate([rng.uniform(-0.06, 0.06, (n, 3)),
                                     rng.uniform(-0.35, 0.35, (n, 3))], axis=1)
    return P[model.mech.reachable(P)]


def test_forward_kinematics_matches_the_mechanism_route(model):
    # second route: distkin.mechanisms' own Gauss-Newton (batched, dimensionless)
    for pose in _random_poses(model, 12):
        q, ok = model.ik(pose)
        assert ok
        guess = rotate_pose(pose, [0.004, -0.003, 0.002], [0.02, -0.01, 0.015])
        mine = model.forward(q, guess, tol=1e-12, max_iter=40)
        ref = model.mech.forward_kinematics(q, guess)
        assert mine.converged and ref.converged
        np.testing.assert_allclose(mine.pose, ref.pose, atol=1e-10)
        np.testing.assert_allclose(mine.pose, pose, atol=1e-10)


def test_jacobian_kernel_against_finite_differences_of_batched_ik(model):
    S = SCALING
    for pose in _random_poses(model, 5, seed=1):
        J = model.jacobian(pose)
        eps = 1e-6
        cols = []
        for i in range(6):
            d = np.zeros(6)
            d[i] = eps
            plus = rotate_pose(pose, d[:3], d[3:])
            minus = rotate_pose(pose, -d[:3], -d[3:])
            qp, _ = model.mech.inverse_kinematics(plus)
            qm, _ = model.mech.inverse_kinematics(minus)
            cols.append((qp - qm) / (2 * eps))
        np.testing.assert_allclose(J, np.array(cols).T, atol=1e-6 * np.abs(J).max())
        assert np.linalg.svd(J / S, compute_uv=False)[-1] > 0.02


def test_admittance_spring_step_matches_the_analytic_response():
    # m x'' + d x' + k x = f, x(0) = x'(0) = 0: underdamped closed form
    m, d, k, f = 1.0, 6.0, 100.0, 2.0
    adm = Admittance([m] * 3 + [0.01] * 3, [d] * 3 + [0.1] * 3,
                     [Spring((0, 0, 0.3, 0, 0, 0), (k, k, k, 1, 1, 1))])
    adm.reset((0, 0, 0.3, 0, 0, 0))
    dt = 1e-4
    wn, z = math.sqrt(k / m), d / (2 * math.sqrt(k * m))
    wd = wn * math.sqrt(1 - z * z)
    errs = []
    for n in range(1, 10001):
        adm.commit(*adm.propose(np.array([0, f, 0, 0, 0, 0.0]), dt))
        t = n * dt
        x = f / k * (1 - math.exp(-z * wn * t) * (math.cos(wd * t) + z * wn / wd * math.sin(wd * t)))
        errs.append(abs(adm.pose[1] - x))
    assert max(errs) < 2e-3 * f / k               # semi-implicit Euler, dt = 0.1 ms
    assert abs(adm.pose[0]) < 1e-15 and abs(adm.pose[3]) < 1e-15


def test_wall_pushes_only_when_penetrated():
    w = Wall((1.0, 0.0, 0.0), 0.02, 300.0, damping=5.0)
    free = w.wrench(np.array([0.019, 0, 0.3, 0, 0, 0]), np.array([0.1, 0, 0, 0, 0, 0]))
    assert np.all(free == 0)
    inside = w.wrench(np.array([0.025, 0, 0.3, 0, 0, 0]), np.zeros(6))
    np.testing.assert_allclose(inside, [-300 * 0.005, 0, 0, 0, 0, 0])
    leaving = w.wrench(np.array([0.0201, 0, 0.3, 0, 0, 0]), np.array([-1.0, 0, 0, 0, 0, 0]))
    # leaving fast: a two-sided damper would pull (300*1e-4 - 5*1 < 0); the wall only
    # damps inward motion, so it still pushes with its spring force
    np.testing.assert_allclose(leaving, [-300 * 1e-4, 0, 0, 0, 0, 0], atol=1e-12)


def _frame(model, pose, dq=None, wrench=None, status=0):
    q, _ = model.ik(pose)
    if dq is not None:
        q = q + dq
    return StateFrame(1, 1000, status, q, np.zeros(6) if wrench is None else np.asarray(wrench))


def _controller(scene, model, **pd):
    s = dataclasses.replace(scene, pd=dataclasses.replace(scene.pd, **pd))
    ctl = Controller(s, model)
    return ctl


def test_projected_distribution_keeps_the_wrench_and_removes_internal_forces(scene, model):
    pose = model.home + np.array([0.01, -0.02, 0.015, 0.1, -0.05, 0.08])
    # a set point away from the measurement, and joint readings inconsistent with any
    # pose (an internal-force component in the PD torques)
    rng = np.random.default_rng(2)
    dq = 2e-3 * rng.standard_normal(model.L)
    out = {}
    for dist in ("projected", "independent"):
        ctl = _controller(scene, model, distribution=dist, torque_limit=30.0)
        f0 = _frame(model, pose)
        ctl.compute(f0, 1e-3)                           # initialise at the pose
        ctl.adm.reset(rotate_pose(pose, [0.003, 0, 0], [0, 0, 0]))
        res = ctl.compute(_frame(model, pose, dq, wrench=[0.5, -0.3, 0.2, 0, 0, 0]), 1e-3)
        assert res.accepted and not res.saturated
        out[dist] = (res.torques, model.jacobian(ctl.pose))
    tp, J = out["projected"]
    ti, _ = out["independent"]
    np.testing.assert_allclose(J.T @ tp, J.T @ ti, rtol=1e-9, atol=1e-9)
    N = null_space(J.T)                                 # internal-force directions (L x 2)
    assert N.shape == (model.L, 2)
    assert np.abs(N.T @ tp).max() < 1e-9 * np.abs(tp).max()
    assert np.abs(N.T @ ti).max() > 1e-3 * np.abs(ti).max()


def test_saturation_scales_all_torques_by_one_factor(scene, model):
    pose = model.home
    big = _controller(scene, model, torque_limit=34.2)
    small = _controller(scene, model, torque_limit=2.5)
    for ctl in (big, small):
        ctl.compute(_frame(model, pose), 1e-3)
        ctl.adm.reset(rotate_pose(pose, [0.0, 0.03, 0.0], [0, 0, 0]))
    rb = big.compute(_frame(model, pose), 1e-3)
    rs = small.compute(_frame(model, pose), 1e-3)
    assert not rb.saturated and rs.saturated
    assert np.abs(rs.torques).max() == pytest.approx(2.5, rel=1e-12)
    np.testing.assert_allclose(rs.torques, rb.torques * 2.5 / np.abs(rb.torques).max(),
                               rtol=1e-9)


def _singular_pose(model):
    """A singular pose found without the Jacobian kernel: rotation about z at which the
    finite-difference Jacobian of the batched IK loses rank (about 97 deg)."""
    def smin(rz):
        pose = model.home.copy()
        pose[5] = rz
        eps = 1e-6
        cols = []
        for i in range(6):
            d = np.zeros(6)
            d[i] = eps
            qp, _ = model.mech.inverse_kinematics(rotate_pose(pose, d[:3], d[3:]))
            qm, _ = model.mech.inverse_kinematics(rotate_pose(pose, -d[:3], -d[3:]))
            cols.append((qp - qm) / (2 * eps))
        return np.linalg.svd(np.array(cols).T / SCALING, compute_uv=False)[-1]

    r = minimize_scalar(smin, bounds=(math.radians(80), math.radians(110)), method="bounded",
                        options={"xatol": 1e-10})
    pose = model.home.copy()
    pose[5] = r.x
    return pose, r.fun, smin(0.0)


def test_singular_and_unreachable_commanded_poses_are_refused(scene, model):
    ctl = Controller(scene, model)
    pose, s_sing, s_home = _singular_pose(model)
    assert s_sing < 1e-4 * s_home                       # a genuine rank loss
    assert model.mech.reachable(pose)
    why, q = ctl.check_pose(pose)
    assert why == "singular" and q is None
    far = model.home + np.array([0, 0, 0.3, 0, 0, 0])
    assert not model.mech.reachable(far)
    assert ctl.check_pose(far)[0] == "unreachable"
    why, q = ctl.check_pose(model.home)
    assert why == "" and np.allclose(q, model.ik(model.home)[0])


def test_readings_with_nan_out_of_range_or_estop_are_rejected(scene, model):
    ctl = Controller(scene, model)
    good = _frame(model, model.home)
    assert ctl.check_reading(good) == ""
    bad_angles = good.angles.copy()
    bad_angles[3] = np.nan
    assert "NaN" in ctl.check_reading(StateFrame(1, 0, 0, bad_angles, good.wrench))
    assert "NaN" in ctl.check_reading(StateFrame(1, 0, 0, good.angles,
                                                 np.array([0, np.inf, 0, 0, 0, 0.0])))
    far = good.angles.copy()
    far[0] = 4.0
    assert "beyond" in ctl.check_reading(StateFrame(1, 0, 0, far, good.wrench))
    assert "sensor range" in ctl.check_reading(
        StateFrame(1, 0, 0, good.angles, np.array([0, 0, 500.0, 0, 0, 0])))
    assert "e-stop" in ctl.check_reading(StateFrame(1, 0, STATUS_ESTOP, good.angles,
                                                    good.wrench))
    assert "expected 8" in ctl.check_reading(StateFrame(1, 0, 0, good.angles[:6], good.wrench))


def test_set_point_pushed_out_of_reach_is_held_at_the_boundary(scene, model):
    # no spring: a steady 20 N along -x drives the admittance beyond the reach of the
    # legs (in-process loop, no I/O).  Sideways, because straight up the Octo meets a
    # near-singular region (sigma_min guard, about z0 + 0.16 m) before its reach limit.
    s = dataclasses.replace(
        scene, environment=(),
        simulator=dataclasses.replace(scene.simulator,
                                      hand=HandScript(((0.0, 0, 0, 0), (0.05, -20.0, 0, 0)))))
    r = run_loopback(s, model, 1.5)
    assert r["refused"].sum() > 0
    assert np.all(model.mech.reachable(r["desired"]))
    held = r["desired"][-1]
    assert model.home[0] - held[0] > 0.1              # it got far (beyond Table II's 75 mm)
    beyond = held.copy()
    beyond[0] -= 2e-3                                  # one admittance step is ~1.3 mm
    assert not model.mech.reachable(beyond)            # and stopped at the reach boundary
    assert np.ptp(r["desired"][-100:, 0]) < 1e-4       # where it stays put
    assert np.abs(r["tau_cmd"]).max() <= scene.pd.torque_limit + 1e-6


def test_measured_pose_near_a_singularity_stops_the_device(scene, model):
    from distkin.control.protocol import MODE_HOLD
    pose, _, _ = _singular_pose(model)
    ctl = Controller(scene, model)
    ctl.pose = pose.copy()                       # warm start at the measured pose
    ctl.started = True
    ctl.adm.reset(pose)
    res = ctl.compute(_frame(model, pose), 1e-3)
    assert res.reason == "singular_stop" and res.mode == MODE_HOLD
    assert np.all(res.torques == 0)


@pytest.mark.parametrize("fused", [True, False])
def test_fk_failing_near_a_singularity_is_a_singular_stop(scene, model, fused):
    """Readings the FK cannot close (one crank 0.3 rad off): near a singularity (the
    last estimate's J, by :func:`_singular_pose`) that is the singular stop, hold mode
    and zero torque at the last estimate; at a regular last estimate it stays an FK
    failure (the loop repeats its last command).  Fused cycle and Python steps alike."""
    from distkin.control.protocol import MODE_HOLD
    pose, _, _ = _singular_pose(model)
    dq = np.zeros(model.L)
    dq[2] = 0.3
    for start, want in ((pose, "singular_stop"), (model.home, "fk_failed")):
        ctl = Controller(scene, model, fused=fused)
        ctl.pose = start.copy()
        ctl.started = True
        ctl.adm.reset(start)
        res = ctl.compute(_frame(model, start, dq=dq), 1e-3)
        assert res.reason == want
        if want == "singular_stop":
            assert res.mode == MODE_HOLD and np.all(res.torques == 0)
            assert np.array_equal(res.pose, start) and np.array_equal(ctl.pose, start)
        else:
            assert res.mode is None


def test_default_fk_tolerance_is_far_below_one_encoder_count(model):
    # one warm-started step from 0.1 mm / 1 mrad away (more than a 1 ms cycle moves)
    pose = model.home + np.array([0.02, 0.01, -0.01, 0.05, 0.1, -0.05])
    q, _ = model.ik(pose)
    fk = model.forward(q, rotate_pose(pose, [1e-4, -1e-4, 5e-5], [1e-3, -1e-3, 5e-4]))
    assert fk.converged
    err = np.abs(fk.pose - pose)
    count = 2 * math.pi / (2000 * 13) * 0.157           # one encoder count at the crank tip
    assert err[:3].max() < 0.01 * count and err[3:].max() < 1e-5


def test_a_port_without_a_device_ends_with_no_device_and_zero_torque(scene, model):
    from distkin.control.link import Link
    ctl = Controller(scene, model)
    ctl.STARTUP_TIMEOUT_S = 0.3
    with Link("loop://") as link:
        s = ctl.run(link, 1.0)
        assert link.stats.frames_out == 3               # the zero-torque frames
        assert link.stats.timeouts > 0
    # exit 2: the device ended the run (QA S 7: 1 is an internal failure only)
    assert s["exit_reason"] == "no_device" and s["exit_code"] == 2
    assert s["cycles"] == 0 and "got none" in s["error"]
    assert [e["event"] for e in ctl.events.events] == ["zero_torque"]


def test_without_feedforward_the_servo_softens_the_wall_like_springs_in_series(scene, model):
    # the paper's scheme (admittance + PD only): the position servo, of stiffness
    # KP JᵀJ, is in series with the rendered environment, 1/k = 1/k_virtual + 1/k_servo
    s = dataclasses.replace(scene, pd=dataclasses.replace(scene.pd, hand_feedforward=False))
    r = run_loopback(s, model, 4.4)
    spring, wall = s.environment
    x = r["pose"][:, 0] - model.home[0]
    t = r["t"]
    contact = (t > 2.4) & (x > wall.offset + 0.002)
    slope = np.polyfit(x[contact], r["hand"][contact, 0], 1)[0]
    J = model.jacobian(model.home + np.array([0.026, 0, 0, 0, 0, 0]))
    k_servo = 1.0 / np.linalg.inv(s.pd.kp * J.T @ J)[0, 0]
    k_virtual = spring.stiffness[0] + wall.stiffness
    assert slope == pytest.approx(1.0 / (1.0 / k_virtual + 1.0 / k_servo), rel=0.05)
    assert slope < 0.9 * k_virtual


def test_derivative_filter_is_forward_euler(scene, model):
    """Sec. III-D: the error derivative is low-pass filtered (T = 700 ms) "using the
    forward Euler method".  A ramp error e[k] = r k dt makes the raw derivative a step of
    height r from k = 1; forward Euler of T ḋ_f = d - d_f then gives, in closed form,
    d_f[k] = r (1 - (1 - dt/T)^(k-1)) for k >= 1 (backward Euler would give
    r (1 - (T/(T + dt))^k))."""
    ctl = _controller(scene, model)
    T, dt, r = ctl.pd.derivative_filter_s, 1e-3, 0.2
    assert T == 0.7
    out = [ctl.filter_derivative(np.full(ctl.L, r * k * dt), dt)[0] for k in range(2000)]
    k = np.arange(2000)
    want = np.where(k >= 1, r * (1 - (1 - dt / T) ** np.maximum(k - 1, 0)), 0.0)
    np.testing.assert_allclose(out, want, rtol=0, atol=1e-12)
    backward = r * (1 - (T / (T + dt)) ** k)
    assert np.abs(np.asarray(out) - backward).max() > 1e-4      # distinguishable
    # T = 0: no filter, the raw difference quotient
    ctl0 = _controller(scene, model, derivative_filter_s=0.0)
    ctl0.filter_derivative(np.zeros(ctl0.L), dt)
    np.testing.assert_allclose(ctl0.filter_derivative(np.full(ctl0.L, 0.5), dt), 500.0)


@pytest.mark.slow   # 9 s; Table V's rows are also checked by tests/control/test_table5_*.py (the Octo)
def test_table5_blocked_experiment_reproduces_the_analysis_for_six_legs():
    """Table V emulated (distkin.control.table5): with the end effector blocked at the
    analysis' worst-force pose and the set point stepped along the worst direction, the
    saturated joint PD pushes the block with exactly the worst-case force and torque of
    the zonotope (L = 6: the torques of a wrench are unique), to the sensor noise; the
    free rows run without hitting an end stop."""
    from distkin.control.table5 import run_table5
    from distkin.indices.workspace import table2_grid
    from distkin.mechanisms import preset
    m = preset("hexa")
    g = table2_grid(m.z0, step=0.025, rot_deg=20.0, rot_step_deg=10.0)
    r = run_table5("hexa", poses=g.poses(np.arange(g.n_positions)), trials=3)
    assert r["force"]["emulated"] == pytest.approx(r["force"]["analysis"], rel=2e-3)
    assert r["torque"]["emulated"] == pytest.approx(r["torque"]["analysis"], rel=2e-3)
    assert all(v["end_stop_hits"] == 0 for v in r.values())
    assert all(v["emulated"] > 0 for v in r.values())
    assert r["force"]["paper_experiment"] == 15.27                 # Table V


def test_a_singular_pose_measured_in_the_fault_state_keeps_zero_torque(monkeypatch, scene,
                                                                        model):
    """QA X1 (noticed by the fix): in the fault state (zero torque: the drives are off
    after a watchdog trip) a measured pose near a singularity switched the loop to the
    singular stop, whose HOLD mode re-energises the drives (the device's own position
    hold) without the recovery's conditions.  Reference: docs/protocol.md, a fault is
    zero torque until recovery; the script trips the watchdog (40 missing frames), then
    reports the singular pose of :func:`_singular_pose`."""
    from control_helpers import ScriptedLink, state_frames
    from distkin.control.protocol import MODE_HOLD, MODE_ZERO_TORQUE, encode_state
    pose, _, _ = _singular_pose(model)
    script = state_frames(model, range(100)) + [None] * 40
    # from home, turned about z to the singular pose in 200 frames (the FK follows it
    # from frame to frame; 8 rad/s, above recover_rate_rad_s, and beyond workspace_rad
    # after 65 frames: no recovery), then held there
    for k in range(300):
        p = model.home.copy()
        p[5] = pose[5] * min(k, 200) / 200
        q, ok = model.ik(p)
        assert ok
        s = 140 + k
        script.append(encode_state(s, 1000 * s, 0, q, np.zeros(6)))
    dev = ScriptedLink(script).patch(monkeypatch)
    ctl = Controller(scene, model)
    ctl.run(dev, 1000.0)
    assert ctl.near_singular(model.jacobian(ctl.pose))           # it got there
    assert ctl.events.count("watchdog_trip") >= 1 and ctl.events.count("recovered") == 0
    after = [c.mode for t, c in dev.commands if t >= 140]
    assert after and MODE_HOLD not in after
    assert all(m == MODE_ZERO_TORQUE for m in after)
