"""A joint end stop stops its joint, not the platform (distkin.control.plant).

Before, a step that took any crank past its range froze all six DOF: a platform pressed
against one crank's stop by a steady hand force hung where it was (759 of 1000 steps
frozen in the scenario below) instead of sliding along the stop.  Now the stop takes an
inelastic impulse in the kinetic-energy metric and the platform moves on with what the
other legs allow.  References, independent of the plant: the mechanism's own ranges
(``in_revolute_range`` of the leg table, ``RSSMechanism.reachable``), the rate of the
stopped joint from the Jacobian (zero after the impact), and the work-energy balance
(kinetic energy never above the work the hand has done: the stop only takes energy)."""

import numpy as np
import pytest

from distkin.control.config import load_control_scene
from distkin.control.kinematics import model_of
from distkin.control.plant import HandScript, Motors, Plant
from distkin.control.protocol import MODE_ZERO_TORQUE
from distkin.mechanisms.legs import in_revolute_range

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
FREE = Motors(friction=0.0, gravity=0.0, force_noise=0.0, torque_noise=0.0)
#: a pose offset (m, rad) whose legs close but whose first crank is at 107.5°
#: (tests/control/test_joint_range_end_stop.py)
OUT = np.array([-0.021, 0.082, 0.012, 0.188, -0.734, 0.062])


@pytest.fixture(scope="module", params=[False, True], ids=["numpy", "compiled"])
def rus8(request):
    from distkin.app.scene import load_scene
    scene = load_control_scene(ROOT / "examples" / "control_rus8.toml",
                               mechanism_loader=lambda p: load_scene(p).mechanism)
    m = model_of(scene, compiled=request.param)
    s = np.linspace(0, 1, 401)
    inside = [m.in_range(m.ik(m.home + t * OUT)[0]) for t in s]
    return m, m.home + s[np.argmin(inside) - 1] * OUT       # the last pose within range


def _kinetic(p, m):
    J = m.jacobian(p.pose)
    return 0.5 * p.twist @ p.M @ p.twist + 0.5 * p.motors.joint_inertia * np.sum(
        (J @ p.twist) ** 2)


def test_an_impact_stops_the_joint_and_the_platform_slides_on(rus8):
    m, edge = rus8
    p = Plant(m, FREE)
    p.pose, p.q = edge.copy(), m.ik(edge)[0]
    p.twist = OUT / np.linalg.norm(OUT) * 0.2                     # towards the stop
    E0 = _kinetic(p, m)
    for _ in range(50):
        pose, hits = p.pose.copy(), p.end_stop_hits
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        if p.end_stop_hits > hits:
            break
    assert p.end_stop_hits == 1
    assert not np.array_equal(p.pose, pose) and np.abs(p.twist).max() > 0   # not frozen
    rates = m.jacobian(p.pose) @ p.twist                    # at the pose the step ends at
    assert abs(rates[0]) < 1e-9 * np.abs(rates).max()       # crank 1 stopped
    E1 = _kinetic(p, m)
    assert 0.0 < E1 < E0                                    # inelastic: energy taken
    for _ in range(100):                                    # and then it coasts
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
    assert p.end_stop_hits == 1
    assert _kinetic(p, m) == pytest.approx(E1, rel=0.05)
    assert in_revolute_range(p.q, m.joint_lo, m.joint_hi).all()


@pytest.mark.parametrize("force", [2.0, 20.0])
def test_pressed_against_the_stop_it_slides_within_range(rus8, force):
    m, edge = rus8
    d = OUT[:3] / np.linalg.norm(OUT[:3])
    p = Plant(m, FREE, HandScript(((0.0, *(force * d)),)))
    p.pose, p.q = edge.copy(), m.ik(edge)[0]
    start = p.pose[:3].copy()
    frozen = at_stop = 0
    for _ in range(1000):
        pose = p.pose.copy()
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        frozen += np.array_equal(p.pose, pose)
        assert in_revolute_range(p.q, m.joint_lo, m.joint_hi).all()
        assert m.mech.reachable(p.pose)
        at_stop += min(np.abs(p.q - m.joint_lo).min(), np.abs(p.q - m.joint_hi).min()) < 1e-4
    assert p.end_stop_hits > 10 and at_stop > 300           # it was pressed on the stop
    assert frozen == 0                                      # and moved on (759 of 1000)
    work = force * d @ (p.pose[:3] - start)                 # the hand's work, J
    assert 0.0 < _kinetic(p, m) <= work * 1.01 + 1e-9


def test_a_joint_already_past_its_range_moves_back_freely(rus8):
    """A state with crank 1 past its range (set from outside) moving back inward takes
    a free step: no end stop, the same step as on the mechanism without ranges
    (review: it was stopped as if moving outward); moving outward it meets its stop."""
    import copy
    m, edge = rus8
    free = copy.copy(m)
    free.joint_lo = free.joint_hi = None
    past = edge + 0.02 * OUT
    q, ok = m.ik(past)
    assert ok and m.range_excess(q)[0] > 0 and m.range_excess(q)[1:].max() == 0
    inward = -OUT / np.linalg.norm(OUT) * 0.2
    plants = []
    for model in (m, free):
        p = Plant(model, FREE)
        p.pose, p.q, p.twist = past.copy(), q.copy(), inward.copy()
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        plants.append(p)
    p, ref = plants
    assert p.end_stop_hits == 0
    assert np.array_equal(p.pose, ref.pose) and np.array_equal(p.twist, ref.twist)
    assert 0 < m.range_excess(p.q)[0] < m.range_excess(q)[0]        # on its way back
    p = Plant(m, FREE)
    p.pose, p.q, p.twist = past.copy(), q.copy(), -inward
    p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
    assert p.end_stop_hits == 1
    assert m.range_excess(p.q)[0] <= m.range_excess(q)[0] + 1e-12    # held, not further


def test_a_joint_past_its_range_pressed_further_is_held_not_frozen(rus8):
    """From a state with crank 1 past its range, random twists that turn it further out:
    the step stops crank 1 where it was and moves on (review: put back exactly onto
    its old excess it stayed an ulp past, and the correction rounds ran out: 22 of
    ~500 such steps froze)."""
    m, edge = rus8
    rng = np.random.default_rng(0)
    for k in (0.005, 0.02):
        start = edge + k * OUT
        q0 = m.ik(start)[0]
        ex0 = m.range_excess(q0)[0]
        assert ex0 > 0
        J = m.jacobian(start)
        steps = 0
        while steps < 40:
            V = rng.normal(size=6) * [0.1, 0.1, 0.1, 1, 1, 1]
            V += OUT / np.linalg.norm(OUT) * rng.uniform(0.01, 0.5)
            if (J @ V)[0] <= 0:
                continue                                    # not outward: no contact
            p = Plant(m, FREE)
            p.pose, p.q, p.twist = start.copy(), q0.copy(), V
            p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
            steps += 1
            assert p.end_stop_hits == 1 and not np.array_equal(p.pose, start)
            assert m.range_excess(p.q)[0] <= ex0               # held, not further out

