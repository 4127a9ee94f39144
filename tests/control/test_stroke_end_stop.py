"""A prismatic leg at the end of its stroke stops that leg, not the platform.

The strokes of an all-prismatic device are in its inverse kinematics' flag (the reach
margin (q - qmin)(qmax - q), distkin.mechanisms.legs), so before, a step that took any
leg past its stroke was a "mechanical end stop" that froze all six DOF: the 6-UPS
platform of examples/control_gough6.toml pressed by a hand against one leg's lower
stroke end hung where it was.  Now the stroke is that leg's end stop, as a crank's
range is (distkin.control.end_stops).  References, independent of the plant: the
mechanism's own reachability (``RSSMechanism.reachable``: closure and strokes), the
leg lengths read from the geometry (|P - B|), the stopped leg's rate from the
Jacobian, and the work-energy balance (review: at a stroke end both poses of the rotor term's central
difference left the stroke, J̇V was cut to zero and the sliding platform gained 2.3 J
more than the hand gave it in 1 s)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from distkin.app.scene import load_scene
from distkin.control.config import load_control_scene
from distkin.control.kinematics import model_of
from distkin.control.plant import HandScript, LinearDrives, Plant
from distkin.control.protocol import MODE_ZERO_TORQUE

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FREE = LinearDrives(friction=0.0, gravity=0.0, force_noise=0.0, torque_noise=0.0)


@pytest.fixture(scope="module", params=[False, True], ids=["numpy", "compiled"])
def gough6(request):
    """The model, the push direction d (the translation that shortens leg 1 fastest)
    and the last pose from home along d whose legs are all within their strokes."""
    sc = load_control_scene(EXAMPLES / "control_gough6.toml",
                            mechanism_loader=lambda p: load_scene(p).mechanism)
    m = model_of(sc, compiled=request.param)
    J = m.jacobian(m.home)
    d = -J[0, :3] / np.linalg.norm(J[0, :3])
    lo, hi = 0.0, 0.5
    for _ in range(50):                                   # bisection on the stroke
        t = 0.5 * (lo + hi)
        lo, hi = (t, hi) if m.ik(m.home + np.r_[t * d, 0, 0, 0])[1] else (lo, t)
    return m, d, m.home + np.r_[lo * d, 0, 0, 0]


def _lengths(m, pose):
    """|P - B| of each leg from the leg geometry (m), not from the kernels."""
    g = m.mech.points(pose, q=np.zeros(m.L))     # (P and B do not depend on q)
    return np.linalg.norm(g["P"] - g["B"], axis=-1)


def _kinetic(p, m):
    J = m.jacobian(p.pose)
    return 0.5 * p.twist @ p.M @ p.twist + 0.5 * p.motors.joint_inertia * np.sum(
        (J @ p.twist) ** 2)


def test_the_device_has_strokes_and_the_push_meets_one(gough6):
    m, d, edge = gough6
    assert np.allclose(m.stroke_lo, 0.35) and np.allclose(m.stroke_hi, 0.55)     # m
    q = _lengths(m, edge)
    assert q[0] == pytest.approx(0.35, abs=1e-9) and (q[1:] > 0.35 + 1e-3).all()
    assert not m.ik(edge + np.r_[1e-4 * d, 0, 0, 0])[1]   # a step further: past it


@pytest.mark.parametrize("force", [20.0, 200.0])
def test_pressed_against_a_stroke_end_it_slides_within_the_strokes(gough6, force):
    m, d, edge = gough6
    p = Plant(m, FREE, HandScript(((0.0, *(force * d)),)))
    p.pose, p.q = edge.copy(), m.ik(edge)[0]
    start = p.pose[:3].copy()
    frozen = 0
    for _ in range(1000):
        pose, hits = p.pose.copy(), p.end_stop_hits
        p.step(np.zeros(m.L), MODE_ZERO_TORQUE, 1e-3)
        frozen += np.array_equal(p.pose, pose)
        assert m.mech.reachable(p.pose)
        q = _lengths(m, p.pose)
        assert (q >= 0.35 - 1e-9).all() and (q <= 0.55 + 1e-9).all()
        if p.end_stop_hits > hits == 0:                   # the first contact: leg 1
            rates = m.jacobian(p.pose) @ p.twist          # m/s at the step's end
            assert q[0] == pytest.approx(0.35, abs=1e-6)
            assert -rates[0] <= 1e-9 * np.abs(rates).max()          # not shortening
            assert np.abs(rates).max() > 0                          # the rest moves
    assert p.end_stop_hits > 100                          # it was pressed on the stop
    assert frozen == 0                                    # and moved on
    work = force * d @ (p.pose[:3] - start)               # J
    assert 0.0 < _kinetic(p, m) <= work * 1.01 + 1e-9


def test_a_nan_leg_length_is_out_of_range_with_or_without_its_stroke(gough6):
    """range_excess is inf for NaN, as the crank's scalar range_excess (review: a leg
    without a stroke beside legs with one gave NaN, and in_range said True)."""
    import copy
    m, _, _ = gough6
    part = copy.copy(m)
    part.stroke_lo, part.stroke_hi = m.stroke_lo.copy(), m.stroke_hi.copy()
    part.stroke_lo[5], part.stroke_hi[5] = -np.inf, np.inf       # leg 6: no stroke
    q = m.ik(m.home)[0]
    for model in (m, part):
        for i in (0, 5):
            bad = q.copy()
            bad[i] = np.nan
            assert model.range_excess(bad)[i] == np.inf and not model.in_range(bad)
