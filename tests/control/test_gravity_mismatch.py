"""A simulated world whose gravity differs from the controller's compensation is warned
about at load (``[simulator] gravity`` against :data:`distkin.control.controller.GRAVITY`,
with ``pd.gravity_compensation`` on): the compensation pushes the platform by its mass
times the difference.  Reference for that claim, a second route: the wrench Jᵀτ of the
controller's command at rest at home equals the platform's weight m·9.81 upward
(its mass from the model), whatever the simulator's gravity."""

import numpy as np
import pytest

from distkin.control.config import loads_control_scene
from distkin.control.controller import GRAVITY, Controller
from distkin.control.kinematics import model_of
from distkin.control.plant import Plant
from distkin.control.protocol import MODE_RUN, FrameDecoder, encode_state

from control_helpers import scene_text


def _scene(gravity=None, compensation=None):
    text = scene_text()
    if gravity is not None:
        text = text.replace("[simulator]\n", f"[simulator]\ngravity = {gravity}\n")
    if compensation is not None:
        text = text.replace("[pd]", f"[pd]\ngravity_compensation = {compensation}", 1)
    return loads_control_scene(text, "s.toml")


def test_default_scene_has_no_gravity_warning():
    assert [f for f, _ in _scene().warnings if f == "simulator.gravity"] == []
    assert [f for f, _ in _scene(gravity=GRAVITY).warnings] == []


@pytest.mark.parametrize("g", [0, 1.62])
def test_another_gravity_warns_naming_both(g):
    w = dict(_scene(gravity=g).warnings)
    assert "simulator.gravity" in w
    assert f"{g:g} m/s²" in w["simulator.gravity"] and "9.81 m/s²" in w["simulator.gravity"]
    assert "gravity_compensation = false" in w["simulator.gravity"]


def test_no_warning_without_compensation():
    assert dict(_scene(gravity=0, compensation="false").warnings) == {}


def test_the_compensation_pushes_by_the_assumed_weight():
    sc = _scene(gravity=0)
    m = model_of(sc, compiled=False)                    # the reference route
    ctl = Controller(sc, m)
    p = Plant(m, sc.simulator.motors)
    dec = FrameDecoder()
    for k in range(3):                                  # at rest at home, no hand
        fr = dec.feed(encode_state(k + 1, 1000 * (k + 1), 0, p.encoders(), np.zeros(6)))[0]
        r = ctl.compute(fr, 1e-3)
    assert r.mode == MODE_RUN
    w = m.jacobian(m.home).T @ np.asarray(r.torques)
    weight = float(m.mass[0, 0]) * GRAVITY
    assert w[2] == pytest.approx(weight, rel=0.02)
    assert np.abs(w[:2]).max() < 0.02 * weight
