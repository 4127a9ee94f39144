"""The simulated device (distkin.control.plant) on bad steps and bad parameters.

Review findings: ``Plant.step`` with dt = 0 made q̇ = 0/0 (NaN for ever after), a
negative dt ran the physics backwards, a command of the wrong length was read past its
end by the compiled dynamics, a NaN command stopped the platform dead in the air and
counted an end stop; ``Motors(stall_torque=0)``, ``Motors(nominal_torque=34.2)`` and
``LinearDrives(lead=0)`` raised ZeroDivisionError; ``HandScript(((0, 1),))`` returned
a force of one component."""

import dataclasses
import math

import numpy as np
import pytest

from distkin.control.kinematics import load_model
from distkin.control.plant import HandScript, LinearDrives, Motors, Plant
from distkin.control.protocol import MODE_RUN
from distkin.errors import InputError


@pytest.fixture(scope="module", params=[True, False], ids=["compiled", "numpy"])
def model(request):
    return load_model("octo", compiled=request.param)


QUIET = Motors(force_noise=0.0, torque_noise=0.0)


@pytest.mark.parametrize("dt", [0.0, -1e-3, math.nan, math.inf, True, "1e-3"])
def test_a_time_step_that_is_not_positive_and_finite_is_refused(model, dt):
    p = Plant(model, QUIET)
    with pytest.raises(InputError) as exc:
        p.step(np.zeros(model.L), MODE_RUN, dt)
    assert exc.value.field == "dt" and repr(dt) in str(exc.value)
    assert p.t == 0.0 and np.all(np.isfinite(p.qdot))


def test_a_command_of_the_wrong_length_is_refused(model):
    p = Plant(model, QUIET)
    with pytest.raises(InputError) as exc:
        p.step(np.zeros(3), MODE_RUN, 1e-3)
    assert exc.value.field == "tau_cmd" and "8" in str(exc.value) and "(3,)" in str(exc.value)


@pytest.mark.parametrize("tau", [["a"] * 8, "12345678", [[0.0], [1.0, 2.0]], ["1"] * 8,
                                 [True] * 8, [1 + 0j] * 8,
                                 np.array(["2026-01-01"] * 8, dtype="datetime64[D]")],
                         ids=["text", "string", "ragged", "numeric-text", "bools",
                              "complex", "dates"])
def test_a_command_that_is_not_numbers_is_refused_and_loses_nothing(model, tau):
    """Text and ragged lists were numpy's ValueError/TypeError (QA note); numeric text,
    bools, complex numbers and dates were converted to torques (review)."""
    p = Plant(model, QUIET)
    before = (p.t, p.pose.copy(), p.q.copy())
    with pytest.raises(InputError) as exc:
        p.step(tau, MODE_RUN, 1e-3)
    assert exc.value.field == "tau_cmd" and "8 joint efforts" in str(exc.value)
    assert p.t == before[0] and np.array_equal(p.pose, before[1])
    assert np.array_equal(p.q, before[2])


def test_a_nonfinite_command_is_zero_effort_on_its_joints(model):
    """NaN on joint 0 and +inf on joint 3 step exactly like 0 on those joints (the
    platform keeps falling under gravity: the first step's height change is a·dt² with
    a from (M̂ + J_r JᵀJ) a = (0, 0, -m g, 0, 0, 0) when all torques are zero), no end
    stop, and the plant counts the bad command."""
    tau = np.full(model.L, 0.05)
    bad = tau.copy()
    bad[0], bad[3] = math.nan, math.inf
    good = tau.copy()
    good[0] = good[3] = 0.0
    a, b = Plant(model, QUIET), Plant(model, QUIET)
    for _ in range(20):
        a.step(bad, MODE_RUN, 1e-3)
        b.step(good, MODE_RUN, 1e-3)
    np.testing.assert_array_equal(a.pose, b.pose)
    assert a.end_stop_hits == 0 and a.nonfinite_commands == 20 and b.nonfinite_commands == 0
    # all NaN: the free fall of the equations of motion
    c = Plant(model, QUIET)
    c.step(np.full(model.L, math.nan), MODE_RUN, 1e-3)
    J = model.jacobian(model.home)
    M = np.asarray(model.mass, dtype=float)
    acc = np.linalg.solve(M + QUIET.joint_inertia * J.T @ J,
                          [0, 0, -M[0, 0] * QUIET.gravity, 0, 0, 0])
    assert c.pose[2] - model.home[2] == pytest.approx(acc[2] * 1e-6, rel=1e-9)
    assert c.end_stop_hits == 0


@pytest.mark.parametrize("kw, field", [
    ({"stall_torque": 0.0}, "stall_torque"), ({"nominal_torque": 34.2}, "stall_torque"),
    ({"nominal_torque": 40.0}, "stall_torque"), ({"gear": 0}, "gear"),
    ({"nominal_speed": -51.0}, "nominal_speed"), ({"friction": math.nan}, "friction"),
    ({"rotor_inertia": -1e-5}, "rotor_inertia"), ({"counts_per_rev": 0}, "counts_per_rev"),
    ({"counts_per_rev": 2.5}, "counts_per_rev"), ({"force_noise": -1}, "force_noise"),
    ({"gravity": math.inf}, "gravity")])
def test_motor_parameters_that_make_no_drive_are_named(kw, field):
    with pytest.raises(InputError) as exc:
        Motors(**kw)
    assert exc.value.field == field and repr(kw[next(iter(kw))]) in str(exc.value)
    assert "expected" in str(exc.value)


@pytest.mark.parametrize("kw, field", [
    ({"lead": 0.0}, "lead"), ({"lead": -0.01}, "lead"),
    ({"lead": 1e-200}, "lead"), ({"lead": 1e6}, "lead"),     # 1e-200: OverflowError
    ({"motor_nominal_torque": 5.0}, "motor_stall_torque"),
    ({"friction": -1.0}, "friction"), ({"motor_friction": -1.0}, "motor_friction")])
def test_ball_screw_parameters_that_make_no_drive_are_named(kw, field):
    with pytest.raises(InputError) as exc:
        LinearDrives(**kw)
    assert exc.value.field == field


def test_the_defaults_and_replace_still_build():
    """The paper's drives (Sec. III-B.3: 34.2 / 2.5 N·m, 51 rad/s) and the replace() the
    tests and Table V use."""
    mo = dataclasses.replace(Motors(), friction=0.0)
    assert mo.no_load_speed == pytest.approx(51.0 / (1 - 2.5 / 34.2))
    assert LinearDrives().stall_effort == pytest.approx(34.2 / 13 * 2 * math.pi / 0.01)


@pytest.mark.parametrize("points, field", [
    (((0.0, 1.0),), "hand[0]"), (((0.0, 1, 2, math.nan),), "hand[0]"),
    (((1.0, 0, 0, 0), (0.5, 0, 0, 0)), "hand"), (((0.0, True, 0, 0),), "hand[0]")])
def test_a_hand_script_that_is_not_knots_is_refused(points, field):
    with pytest.raises(InputError) as exc:
        HandScript(points)
    assert exc.value.field == field


def test_a_body_the_drives_cannot_accelerate_is_refused():
    """No platform mass and no rotor inertia: M̂ + J_r JᵀJ = 0, a singular solve on the
    first step (numpy's LinAlgError before)."""
    m = load_model("octo", compiled=False)
    m.mass = np.zeros((6, 6))
    with pytest.raises(InputError) as exc:
        Plant(m, Motors(rotor_inertia=0.0))
    assert exc.value.field == "mass"
    Plant(m, Motors())                   # massless platform, rotors: a body still


def test_the_simulator_logs_the_first_nonfinite_command_once():
    """The device's event log says that a command held NaN (zero effort on those joints),
    once, with the command's sequence number; the platform keeps moving (no end stop)."""
    from distkin.control.config import builtin_scene
    from distkin.control.protocol import MODE_RUN, CommandFrame
    from distkin.control.simulator import Simulator

    class NoTransport:
        fd = None

    scene = builtin_scene()
    sim = Simulator(scene, load_model("octo", compiled=False), NoTransport())
    tau = np.zeros(sim.model.L)
    tau[2] = math.nan
    for k in range(3):
        sim.command = CommandFrame(7 + k, 0, MODE_RUN, 0, tau)
        sim._step(k, False)
    ev = [e for e in sim.events.events if e["event"] == "nonfinite_command"]
    assert len(ev) == 1 and ev[0]["seq"] == 7
    assert sim.plant.nonfinite_commands == 3 and sim.plant.end_stop_hits == 0
