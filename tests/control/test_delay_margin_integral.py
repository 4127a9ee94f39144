"""The delay margin with an integral term (KI > 0): control.delay_margin left the
integral out of the linearised loop, so a KI that destabilises the lock-stepped loop
was reported "stable" (the sweep did not change with KI at all).

References: a brute-force run of the nonlinear in-process loop (run_loopback: the
controller's own PD(I), the plant, the frames), on both sides of the boundary the
linearised loop predicts, and the hand-written recurrence of the PID loop without delay
on a single mode (an analytic characteristic polynomial)."""

import dataclasses

import numpy as np
import pytest

from distkin.control.config import default_scene
from distkin.control.delay_margin import closed_loop_matrix, delay_margin
from distkin.control.kinematics import load_model
from distkin.control.loopback import run_loopback
from distkin.control.plant import HandScript


@pytest.fixture(scope="module")
def scene_model():
    """The paper's PD with a derivative filter of 0.7 ms (a damped loop), ideal sensors,
    and a short hand push that excites every mode."""
    sc = default_scene()
    mo = dataclasses.replace(sc.simulator.motors, counts_per_rev=2 ** 40, force_noise=0.0,
                             torque_noise=0.0)
    hand = HandScript(((0.0, 0, 0, 0), (0.005, 0.5, 0.3, 0.4), (0.01, 0, 0, 0)))
    sc = dataclasses.replace(sc, simulator=dataclasses.replace(sc.simulator, motors=mo,
                                                               hand=hand))
    return sc, load_model("octo")


def _ki(scene, ki):
    return dataclasses.replace(scene, pd=dataclasses.replace(scene.pd, ki=ki,
                                                             derivative_filter_s=0.0007))


@pytest.mark.parametrize("ki, verdict", [(880.0, "stable"), (3500.0, "unstable")])
def test_the_integral_moves_the_verdict_where_the_nonlinear_loop_does(scene_model, ki,
                                                                       verdict):
    """KI = 880 N·m/(rad·s): the loop decays (the deviation from the set point falls by
    more than 10x over 1.5 s after the push); KI = 3500: it grows to the torque limit.
    The linearised verdict must say the same (the old matrix said "stable" for both)."""
    scene, model = scene_model
    scene = _ki(scene, ki)
    dm = delay_margin(scene, model, max_periods=0)
    assert dm.lockstep == verdict
    r = run_loopback(scene, model, 1.5)
    dev = np.linalg.norm(r["pose"] - r["desired"], axis=1)
    saturated = np.abs(r["tau_cmd"]).max(axis=1) >= 0.99 * scene.pd.torque_limit
    if verdict == "stable":
        assert dev[-100:].max() < 0.1 * dev[50:200].max() and not saturated.any()
    else:
        assert saturated.any() and dev[-100:].max() > 10 * dev[50:200].max()


class _Diagonal:
    """A stand-in kinematic model: six legs, J = c I, M = m I (six equal decoupled
    modes)."""

    L = 6
    home = np.zeros(6)

    def __init__(self, m, c):
        self.mass, self.c = m * np.eye(6), c

    def jacobian(self, pose):
        return self.c * np.eye(6)


def test_the_pi_loop_has_the_roots_of_its_hand_written_recurrence(scene_model):
    """J = c I, M = m I, KD = 0, no filter, no friction, no rotor: per mode the
    controller's PI (σ_k = σ_{k-1} + h x_k summed with the current error, as
    Controller.joint_torques does) and the plant's semi-implicit Euler are

        V' = V - a (KP x + KI (σ + h x)),  x' = x + h V',  σ' = σ + h x,  a = h c²/m,

    a 3 x 3 recurrence written here by hand; the matrix's nonzero eigenvalues are its
    three, six times over."""
    scene, _ = scene_model
    m, c, h, kp, ki = 0.5, 6.0, 1e-3, 110.0, 3000.0
    a = h * c * c / m
    A = np.array([[1 - h * a * (kp + ki * h), h, -h * a * ki],
                  [-a * (kp + ki * h), 1.0, -a * ki],
                  [h, 0.0, 1.0]])
    want = np.linalg.eigvals(A)
    motors = dataclasses.replace(scene.simulator.motors, friction=0.0, rotor_inertia=0.0)
    sc = dataclasses.replace(scene, rate_hz=1 / h,
                             simulator=dataclasses.replace(scene.simulator, motors=motors),
                             pd=dataclasses.replace(scene.pd, kp=kp, ki=ki, kd=0.0,
                                                    derivative_filter_s=0.0,
                                                    distribution="independent",
                                                    gravity_compensation=False))
    lam = np.linalg.eigvals(closed_loop_matrix(sc, _Diagonal(m, c)))
    got = lam[np.abs(lam) > 1e-9]
    assert got.size == 18
    for w in want:
        assert np.sum(np.abs(got - w) < 1e-6) == 6, (w, got)
    assert np.abs(want).max() > 1          # this KI destabilises the loop
    assert delay_margin(sc, _Diagonal(m, c), max_periods=0).lockstep == "unstable"


def test_a_boolean_count_of_periods_is_refused(scene_model):
    """True was read as 1 period (numpy and int() take it for 1)."""
    from distkin.errors import InputError
    scene, model = scene_model
    with pytest.raises(InputError, match="delay_periods"):
        closed_loop_matrix(scene, model, True)
    with pytest.raises(InputError, match="max_periods"):
        delay_margin(scene, model, max_periods=True)
