"""The simulated device: statics through Jᵀτ, drive envelope, hold mode, sensors."""

import math

import numpy as np
import pytest

from distkin.control.kinematics import load_model
from distkin.control.plant import HandScript, Motors, Plant
from distkin.control.protocol import MODE_HOLD, MODE_RUN, MODE_ZERO_TORQUE


@pytest.fixture(scope="module")
def model():
    return load_model("octo")


def _balance(model, pose, wrench):
    """Minimum-norm actuator torques whose wrench Jᵀτ cancels ``wrench`` (statics,
    Kühne et al. eq. (3)), from a least-squares solve (not the controller's code)."""
    J = model.jacobian(pose)
    tau, *_ = np.linalg.lstsq(J.T, -np.asarray(wrench), rcond=None)
    return tau


def test_torques_that_balance_gravity_and_the_hand_hold_the_platform_still(model):
    mo = Motors(force_noise=0.0, torque_noise=0.0)
    hand = HandScript(((0.0, 1.0, -2.0, 0.5),))
    p = Plant(model, mo, hand)
    w = np.array([1.0, -2.0, 0.5 - 0.17 * mo.gravity, 0, 0, 0])
    tau = _balance(model, p.pose, w)
    for _ in range(200):
        p.step(tau, MODE_RUN, 1e-3)
    assert np.abs(p.pose - model.home).max() < 1e-9
    # without the hand term the platform accelerates along the hand force
    p2 = Plant(model, mo, hand)
    tau_g = _balance(model, p2.pose, [0, 0, -0.17 * mo.gravity, 0, 0, 0])
    for _ in range(20):
        p2.step(tau_g, MODE_RUN, 1e-3)
    d = p2.pose[:3] - model.home[:3]
    assert np.dot(d, [1.0, -2.0, 0.5]) > 0.9 * np.linalg.norm(d) * math.sqrt(5.25)


def test_zero_torque_lets_the_platform_fall_and_hold_keeps_it(model):
    mo = Motors(force_noise=0.0, torque_noise=0.0)
    fall = Plant(model, mo)
    hold = Plant(model, mo)
    # from rest the fall starts with the acceleration of the equations of motion (module
    # docstring): (M̂ + Jᵀ J_r J) a = -m g e_z with the rotor inertia reflected through
    # J (about 3.1 m/s², not g); semi-implicit Euler gives z_n - z_0 = a dt² n(n+1)/2
    J = model.jacobian(model.home)
    M = np.asarray(model.mass, dtype=float)
    a = np.linalg.solve(M + mo.joint_inertia * J.T @ J, [0, 0, -M[0, 0] * mo.gravity, 0, 0, 0])
    assert -0.5 * mo.gravity < a[2] < 0
    for _ in range(5):
        fall.step(np.zeros(model.L), MODE_ZERO_TORQUE, 1e-3)
    assert fall.pose[2] - model.home[2] == pytest.approx(a[2] * 1e-6 * 15, rel=1e-2)
    fall = Plant(model, mo)
    for _ in range(300):
        fall.step(np.zeros(model.L), MODE_ZERO_TORQUE, 1e-3)
        hold.step(np.zeros(model.L), MODE_HOLD, 1e-3)
    assert fall.pose[2] < model.home[2] - 1e-3                  # falls (mm in 0.3 s)
    assert abs(hold.pose[2] - model.home[2]) < 2e-4             # joint PD at the device


def test_drive_envelope_matches_the_paper_figures(model):
    """Kühne et al. Sec. III-B.3: ±2.5 N·m nominal, ±34.2 N·m stall and ±51 rad/s
    nominal velocity after gearing; Sec. III-D: capstan ratio 1:13.  The drives' linear
    torque-speed line must pass through the paper's two points, stall torque at rest and
    nominal torque at nominal speed: read through Plant.drive (compiled and numpy
    plants), not through the Motors formula for the no-load speed."""
    mo = Motors()
    assert (mo.nominal_torque, mo.stall_torque, mo.nominal_speed, mo.gear) == \
        (2.5, 34.2, 51.0, 13.0)
    for m in (model, load_model("octo", compiled=False)):
        p = Plant(m, mo)
        p.qdot = np.zeros(m.L)
        np.testing.assert_allclose(p.drive(np.full(m.L, 100.0)), 34.2, rtol=1e-15)
        p.qdot = np.full(m.L, 51.0)
        np.testing.assert_allclose(p.drive(np.full(m.L, 100.0)), 2.5, rtol=1e-12)
        p.qdot = np.full(m.L, -51.0)
        np.testing.assert_allclose(p.drive(np.full(m.L, -100.0)), -2.5, rtol=1e-12)


def test_drive_saturates_at_stall_and_falls_with_speed(model):
    p = Plant(model, Motors())
    out = p.drive(np.full(model.L, 100.0))
    assert np.all(out == 34.2) and p.saturated
    p.qdot = np.full(model.L, 0.5 * p.motors.no_load_speed)
    out = p.drive(np.full(model.L, 100.0))
    np.testing.assert_allclose(out, 0.5 * 34.2)
    braking = p.drive(np.full(model.L, -100.0))            # against the motion: full stall
    np.testing.assert_allclose(braking, -34.2)


def test_encoders_are_quantised_and_the_sensor_reads_in_the_platform_frame(model):
    mo = Motors(force_noise=0.0, torque_noise=0.0)
    p = Plant(model, mo, HandScript(((0.0, 3.0, 0.0, 0.0),)))
    p.pose = model.home + np.array([0, 0, 0, 0, 0, math.pi / 2])   # turned 90 deg about z
    p.q, _ = model.ik(p.pose)
    p.hand_wrench = np.array([3.0, 0, 0, 0, 0, 0])
    counts = p.encoders() / mo.resolution
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-9)
    assert np.abs(p.encoders() - p.q).max() <= mo.resolution / 2 + 1e-15
    # a base-frame force along +x is along -y of a platform frame turned by +90 deg
    np.testing.assert_allclose(p.sensor()[:3], [0.0, -3.0, 0.0], atol=1e-12)


def test_sensor_noise_is_three_force_then_three_torque_draws():
    """The F/T reading is the hand wrench in the sensor frame plus N(0, σ_f) on the
    forces and N(0, σ_t) on the torques, drawn in that order from the plant's seeded
    generator (one draw of six scaled standard normals gives the same numbers)."""
    from distkin.control.config import builtin_scene
    from distkin.control.kinematics import _rot
    sc = builtin_scene()
    mo = sc.simulator.motors
    plant = Plant(load_model("octo", compiled=False), mo, sc.simulator.hand, seed=9)
    for _ in range(50):
        plant.step(np.full(plant.model.L, 0.1), 1, 1e-3)
    plant.hand_wrench = np.array([1.0, -2.0, 0.5, 0.01, 0.02, -0.03])
    rng = np.random.default_rng(9)
    rng.bit_generator.state = plant.rng.bit_generator.state
    Rt = _rot(plant.pose[3:]).T
    want = np.concatenate([Rt @ plant.hand_wrench[:3] + rng.normal(0.0, mo.force_noise, 3),
                           Rt @ plant.hand_wrench[3:] + rng.normal(0.0, mo.torque_noise, 3)])
    assert np.array_equal(plant.sensor(), want)
