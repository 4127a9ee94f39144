"""The simulated device stops a crank at its joint range (distkin.control.plant).

Review finding: the plant's end stop came only from the legs' closure (the IK's reach),
so the rus8 device of examples/rus8_device.toml (cranks within ±90°) let a crank turn
to 107° while the mechanism itself (RSSMechanism.reachable) calls that pose out of
reach.  Reference: the mechanism's own joint ranges and reachable()."""

import numpy as np
import pytest

from distkin.control.config import load_control_scene
from distkin.control.kinematics import model_of
from distkin.control.plant import Motors, Plant
from distkin.control.protocol import MODE_ZERO_TORQUE

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def rus8():
    from distkin.app.scene import load_scene
    scene = load_control_scene(ROOT / "examples" / "control_rus8.toml",
                               mechanism_loader=lambda p: load_scene(p).mechanism)
    return model_of(scene, compiled=False)


#: a pose offset (m, rad) whose legs close but whose first crank is at 107.5°
OUT = np.array([-0.021, 0.082, 0.012, 0.188, -0.734, 0.062])


def test_a_crank_past_its_range_is_an_end_stop(rus8):
    m = rus8
    q, closes = m.ik(m.home + OUT)
    assert closes and np.degrees(q[0]) > 100                     # closes, but at 107°
    assert not m.mech.reachable(m.home + OUT)                    # the mechanism says no
    assert m.joint_hi[0] == pytest.approx(np.pi / 2)
    # the last pose on the way from home with every crank within range
    s = np.linspace(0, 1, 401)
    inside = [m.in_range(m.ik(m.home + t * OUT)[0]) for t in s]
    edge = s[np.argmin(inside) - 1]
    assert all(m.ik(m.home + t * OUT)[1] for t in s)             # closes all the way
    p = Plant(m, Motors(friction=0.0, gravity=0.0, force_noise=0.0, torque_noise=0.0))
    p.pose = m.home + edge * OUT
    p.q, _ = m.ik(p.pose)
    p.twist = OUT / np.linalg.norm(OUT) * 0.2                     # towards the range
    p.qdot = m.jacobian(p.pose) @ p.twist
    worst = -np.inf
    for _ in range(200):
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        worst = max(worst, float(np.max(p.q - m.joint_hi)))
    assert p.end_stop_hits >= 1 and worst <= 0.0
    assert m.mech.reachable(p.pose)


def test_mechanisms_without_ranges_are_unchanged():
    from distkin.control.kinematics import load_model
    m = load_model("octo", compiled=False)
    assert m.joint_lo is None and m.in_range(np.full(m.L, 10.0))
