"""Review of QA Z1's filter check: the load check accepts a derivative filter T of at
least one period h, but the loop steps the forward-Euler low-pass with the *measured*
gap dt (up to 5 h), and ``1 - dt/T`` below -1 made the filtered derivative diverge
(-1e17 after 60 late frames at T = h, dt = 3h).  The step is now at most
max(T, h)/T (1 for an accepted T): the filtered derivative is a convex combination of
the raw difference quotients seen, so it never exceeds their largest magnitude (the
independent bound checked here); for dt <= h nothing changes (the fused cycle against the Python steps, as in
test_cycle_kernels.py)."""

import dataclasses
import math

import numpy as np
import pytest

from distkin.control.config import builtin_scene
from distkin.control.controller import Controller
from distkin.control.kinematics import load_model
from distkin.control.protocol import StateFrame


@pytest.fixture(scope="module")
def model():
    return load_model("octo")


def _scene(T):
    sc = builtin_scene()
    return dataclasses.replace(sc, preset="octo",
                               pd=dataclasses.replace(sc.pd, derivative_filter_s=T))


@pytest.mark.parametrize("gap", [1.0, 3.0, 5.0])
def test_late_frames_keep_the_filtered_derivative_within_the_raw_ones(model, gap):
    sc = _scene(1e-3)                                 # T = h at 1 kHz: accepted at load
    ctl = Controller(sc, model, fused=False)
    dt = gap * 1e-3
    raw, out = [], []
    prev = None
    for k in range(60):
        e = np.full(ctl.L, 1e-3 * math.sin(0.7 * k))
        if prev is not None:
            raw.append(np.max(np.abs((e - prev) / dt)))
        out.append(np.max(np.abs(ctl.filter_derivative(e, dt))))
        prev = e
    assert np.all(np.isfinite(out))
    assert max(out) <= max(raw) * (1 + 1e-12)


def _frames(model, n, dt):
    rng = np.random.default_rng(5)
    for k in range(n):
        pose = model.home + np.array([0.02 * math.sin(k / 40), 0.01, 0.0, 0.02, 0.0, 0.01])
        q, _ = model.ik(pose)
        q = q + 2e-4 * rng.standard_normal(model.L)
        yield StateFrame(k, int(1e6 * dt * k), 0, q,
                         np.array([2.0, -0.5, 1.0, 0.05, -0.02, 0.01])), dt


@pytest.mark.parametrize("dt", [1e-3, 3e-3])
def test_the_fused_cycle_clamps_as_the_python_steps(model, dt):
    """The compiled cycle (cycle_wrappers.py) against the Python steps with T = h: the
    same torques cycle by cycle, finite, with frames on time and three periods late."""
    sc = _scene(1e-3)
    a, b = Controller(sc, model), Controller(sc, model, fused=False)
    assert a._fused is not None and b._fused is None
    for frame, step in _frames(model, 200, dt):
        ra, rb = a.compute(frame, step), b.compute(frame, step)
        assert (ra.accepted, ra.reason, ra.mode) == (rb.accepted, rb.reason, rb.mode)
        if rb.torques is not None:
            assert np.all(np.isfinite(ra.torques))
            np.testing.assert_allclose(ra.torques, rb.torques, rtol=1e-10, atol=1e-12)
