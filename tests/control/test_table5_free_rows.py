"""Table V emulated (distkin.control.table5): what the free velocity row measures.

Review finding: the emulated velocity (4.4 m/s) exceeds the analysis' worst case (2.24
m/s) with nothing in the result saying why.  The analysis' velocity is that of its slice
(zero angular velocity, Kühne et al. eqs. (14)-(15)); the free platform leaves the slice.
Reference: the slice's bound at the worst pose from the Jacobian alone, the largest
speed s along d with every crank within its no-load speed, |J (s d, 0)|_∞ <= w_nl."""

import numpy as np
import pytest

from distkin.control.config import builtin_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.table5 import _free

#: the Octo's worst velocity pose and direction over the 25 mm / 10° grid at ±30°
#: (table5.worst_cases): a corner of the dexterous cube turned -30° about every axis
POSE = np.array([-0.075, 0.075, 0.375, -np.pi / 6, -np.pi / 6, -np.pi / 6])
DIRECTION = np.array([0.4186191, -0.42555584, -0.80228441, 0, 0, 0])


def test_a_velocity_beyond_the_slice_bound_comes_with_a_rotation():
    from dataclasses import replace
    scene = builtin_scene()
    model = load_model("octo")
    stall = replace(scene, pd=replace(scene.pd, torque_limit=34.2, hand_feedforward=False))
    d = DIRECTION / np.linalg.norm(DIRECTION)
    motors = scene.simulator.motors
    bound = motors.no_load_speed / np.abs(model.jacobian(POSE) @ d).max()
    v, a, hits, off = _free(Controller(stall, model), model, POSE, d, motors,
                            angular=False, amplitude=0.04, rise=0.02, seconds=0.15,
                            dt=1e-3)
    assert hits == 0 and a > 0
    assert v > 1.5 * bound                       # 4.4 m/s against 2.4 m/s
    assert off > 20.0                            # rad/s: the platform does not stay at
    #                                              zero angular velocity (87 rad/s)


@pytest.mark.parametrize("kw, field", [({"trials": 0}, "trials"), ({"trials": True}, "trials"),
                                       ({"trials": 2.5}, "trials"),
                                       ({"step_m": 0.0}, "step_m"),
                                       ({"step_rad": float("nan")}, "step_rad"),
                                       ({"free_s": -1.0}, "free_s")])
def test_bad_run_parameters_are_refused_before_any_work(kw, field):
    """trials = 0 gave rows of NaN (the mean of nothing) with a RuntimeWarning only."""
    from distkin.control.table5 import run_table5
    from distkin.errors import InputError
    with pytest.raises(InputError) as exc:
        run_table5("octo", **kw)
    assert exc.value.field == field and repr(next(iter(kw.values()))) in str(exc.value)


@pytest.mark.parametrize("angular, amplitude", [(False, 1.0), (True, 7.0)])
def test_a_step_that_leaves_the_workspace_is_refused(angular, amplitude):
    """QA 2026-11-29: step = 1000 mm drove the controller towards a pose no leg closes at
    and reported 17.3 m/s (7.7 times the analysis) without a word.  Reference: the
    mechanism's own IK valid flags along the step from the worst pose (POSE, DIRECTION
    for the translation; the same pose about DIRECTION's axis for the rotation)."""
    from distkin.control.table5 import _reachable_step
    from distkin.errors import InputError
    from distkin.mechanisms import preset
    from distkin.spatial import rotate_pose_scalar
    model = load_model("octo")
    d = DIRECTION / np.linalg.norm(DIRECTION)
    w = {"pose": POSE, "direction": np.r_[0, 0, 0, d] if angular else np.r_[d, 0, 0, 0]}
    mech = preset("octo")

    def closes(a):
        return all(mech.inverse_kinematics(rotate_pose_scalar(
            POSE, (0 if angular else s) * a * d, (s if angular else 0) * a * d))[1].all()
            for s in np.linspace(0.125, 1.0, 8))

    assert closes(0.4 if angular else 0.04) and not closes(amplitude)       # (premise)
    _reachable_step(model, "velocity", w, angular, 0.4 if angular else 0.04, None)
    with pytest.raises(InputError) as exc:
        _reachable_step(model, "velocity", w, angular, amplitude, None)
    assert exc.value.field == ("step_rad" if angular else "step_m")
    assert "whose targets the device reaches" in str(exc.value)
