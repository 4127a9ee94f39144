"""A set point with a crank past its leg's range is refused as unreachable, by the
Python steps (Controller.check_pose) and by the fused compiled cycle alike (QA: the
rus8 example device, cranks limited to ±90° in its scene file, accepted a set point
that turned crank 1 to 105.7°: the legs close there, so the closure flag passed, while
the mechanism's own reachable() says no)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from distkin.app.scene import load_scene
from distkin.control.config import load_control_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import model_of
from distkin.control.protocol import StateFrame

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
OUT = np.array([-0.021, 0.082, 0.012, 0.188, -0.734, 0.062])     # m, rad from home


@pytest.fixture(scope="module")
def rus8():
    sc = load_control_scene(EXAMPLES / "control_rus8.toml",
                            mechanism_loader=lambda p: load_scene(p).mechanism)
    return sc, model_of(sc)


def test_check_pose_refuses_a_crank_past_its_range(rus8):
    sc, m = rus8
    pose = m.home + OUT
    q, closes = m.ik(pose)
    assert closes and np.all(np.isfinite(q))                 # the legs close there ...
    assert np.degrees(np.abs(q)).max() > 90.0                # ... past the file's ±90°
    assert "range = [-90, 90]" in (EXAMPLES / "rus8_device.toml").read_text()
    assert not m.mech.reachable(pose)                        # the mechanism agrees
    why, q2 = Controller(sc, m).check_pose(pose)
    assert why == "unreachable" and q2 is None


def _edge(m):
    """The largest t in [0, 1] (bisection) with every crank of home + t·OUT in range."""
    lo, hi = 0.0, 1.0
    for _ in range(40):
        t = 0.5 * (lo + hi)
        q, ok = m.ik(m.home + t * OUT)
        lo, hi = (t, hi) if ok and m.in_range(q) else (lo, t)
    return lo


@pytest.mark.parametrize("fused", [True, False])
def test_both_routes_refuse_a_candidate_past_the_range(rus8, fused):
    """The admittance set point just inside the range, moving outward: the candidate of
    the next cycle is refused (reason 'unreachable'); with the ranges taken away, the
    same cycle accepts it (so the range, not the closure, decided)."""
    sc, m = rus8
    t = _edge(m)
    q_in, _ = m.ik(m.home + t * OUT)
    q_out, ok_out = m.ik(m.home + min(1.0, t + 0.05) * OUT)
    assert ok_out and not m.in_range(q_out)                  # the legs still close there
    frame = StateFrame(1, 1000, 0, q_in, np.zeros(6))
    reasons = []
    for ranged in (True, False):
        ctl = Controller(sc, m, fused=fused)
        assert (ctl._fused is not None) == fused
        if not ranged:
            if fused:
                ctl._ranges = np.array([np.full(m.L, -np.inf), np.full(m.L, np.inf)])
            else:
                ctl.model = _NoRanges(m)
        ctl.start_at(m.home + t * OUT)
        ctl.started = True
        ctl.adm.twist[:] = 0.05 * OUT / 1e-3                 # 5 % of OUT in one period
        reasons.append(ctl.compute(frame, 1e-3).reason)
    assert reasons == ["unreachable", ""], reasons


class _NoRanges:
    """The model with its ranges hidden (in_range always true)."""

    def __init__(self, m):
        self._m = m

    def __getattr__(self, name):
        return getattr(self._m, name)

    def in_range(self, q):
        return True

    def range_excess(self, q):
        return np.zeros(len(q))


# ---------------------------------------------------------- review: ranges modulo 2π

def _shifted(tmp_path, rus8, text):
    """The rus8 scene with every range written as ``text``: its scene, and the example's
    compiled model with the ranges a KinematicModel of the shifted mechanism reads
    (built uncompiled: the ranges do not change the kernels, and a compile costs ~10 s)."""
    import copy
    from distkin.control.kinematics import KinematicModel
    for name in ("control_rus8.toml", "rus8_device.toml"):
        src = (EXAMPLES / name).read_text()
        (tmp_path / name).write_text(src.replace("range = [-90, 90]", text))
    sc = load_control_scene(tmp_path / "control_rus8.toml",
                            mechanism_loader=lambda p: load_scene(p).mechanism)
    plain = KinematicModel(sc.mechanism, compiled=False)
    m = copy.copy(rus8[1])
    m.joint_lo, m.joint_hi = plain.joint_lo, plain.joint_hi
    return sc, m, plain


def test_a_range_written_past_180_degrees_is_the_same_arc(tmp_path, rus8):
    """[270, 450] deg is the arc ±90° (the mechanisms' reading, legs.in_revolute_range):
    the controller and the plant read it so (the plain lo <= q <= hi test refused every
    set point and froze the simulated platform), and [0, 360] is no range at all."""
    from distkin.mechanisms.legs import in_revolute_range
    sc0, m0 = rus8
    sc, m, plain = _shifted(tmp_path, rus8, "range = [270, 450]")
    assert np.degrees(plain.joint_lo).round(6).tolist() == [270.0] * m.L
    rng = np.random.default_rng(3)
    for _ in range(200):
        q = rng.uniform(-np.pi, np.pi, m.L)
        assert m.in_range(q) == bool(in_revolute_range(q, m0.joint_lo, m0.joint_hi).all())
        assert m.in_range(q) == m0.in_range(q) == plain.in_range(q)
    for fused in (True, False):
        ctl = Controller(sc, m, fused=fused)
        assert (ctl._fused is not None) == fused
        assert ctl.check_pose(m.home)[0] == ""
        assert ctl.check_pose(m.home + OUT)[0] == "unreachable"
    _, full, _ = _shifted(tmp_path, rus8, "range = [0, 360]")
    assert all(full.in_range(rng.uniform(-np.pi, np.pi, m.L)) for _ in range(50))


@pytest.mark.parametrize("fused", [True, False])
def test_a_set_point_that_starts_past_a_limit_can_move_back(rus8, fused):
    """The admittance set point just past crank 1's limit (as a pose estimated from
    quantised encoders can be, review): a candidate back towards the range is accepted,
    one further out refused (it was refused both ways: stuck for good)."""
    sc, m = rus8
    t = _edge(m)
    past = m.home + min(1.0, t + 0.002) * OUT
    assert not m.in_range(m.ik(past)[0])
    q_past, _ = m.ik(past)
    frame = StateFrame(1, 1000, 0, q_past, np.zeros(6))
    reasons = []
    for sign in (-1.0, 1.0):
        ctl = Controller(sc, m, fused=fused)
        ctl.start_at(past)
        ctl.started = True
        ctl.adm.twist[:] = sign * 0.01 * OUT / 1e-3
        reasons.append(ctl.compute(frame, 1e-3).reason)
    assert reasons == ["", "unreachable"], reasons
