"""The compiled control-cycle kinematics (distkin.control.cycle_kernels) against the
Python route they replace: the generated scalar kernels as plain Python, numpy's solve
and eigvalsh, the admittance's spring and SO(3) step."""

import dataclasses
import math

import numpy as np
import pytest

from distkin.control.admittance import Spring
from distkin.control.config import builtin_scene
from distkin.control.controller import FAULT, RUN, SCALING, Controller
from distkin.control.cycle_kernels import reading_extremes
from distkin.control.kinematics import _rot, load_model
from distkin.spatial import rotate_pose_scalar as rotate_pose
from distkin.control.loopback import run_loopback
from distkin.control.protocol import StateFrame


@pytest.fixture(scope="module")
def models():
    return load_model("octo"), load_model("octo", compiled=False)


def _poses(model, n, seed):
    rng = np.random.default_rng(seed)
    return model.home + rng.uniform(-1, 1, (n, 6)) * [0.04, 0.04, 0.04, 0.3, 0.3, 0.3]


def test_kernels_give_the_same_bits(models):
    """numba compiles the generated functions themselves: same operations, same bits."""
    fast, ref = models
    for pose in _poses(fast, 50, 1):
        q1, ok1 = fast.ik(pose)
        q2, ok2 = ref.ik(pose)
        assert ok1 == ok2 and np.array_equal(q1, q2)
        assert np.array_equal(fast.jacobian(pose), ref.jacobian(pose))
        c1, D1 = fast.closure(q1, pose + 1e-3)
        c2, D2 = ref.closure(q2, pose + 1e-3)
        assert np.array_equal(c1, c2) and np.array_equal(D1, D2)
        dp, dw = np.array([1e-3, 0, -2e-3]), np.array([0.01, -0.02, 0.005])
        assert np.array_equal(fast.compiled.rotate_pose(pose, dp, dw),
                              rotate_pose(pose, dp, dw))


def test_forward_kinematics_agrees_to_rounding(models):
    """Gauss-Newton from a 1 mm / 0.6° perturbed start: same iterations, poses equal to
    rounding (the 6 × 6 solve is our elimination instead of LAPACK's)."""
    fast, ref = models
    rng = np.random.default_rng(2)
    for pose in _poses(fast, 50, 3):
        q, ok = ref.ik(pose)
        assert ok
        guess = pose + rng.uniform(-1, 1, 6) * [1e-3, 1e-3, 1e-3, 0.01, 0.01, 0.01]
        a, b = fast.forward(q, guess, tol=1e-10), ref.forward(q, guess, tol=1e-10)
        assert a.iterations == b.iterations and a.converged and b.converged
        assert np.max(np.abs(a.pose - b.pose)) < 1e-13
        assert np.max(np.abs(a.pose - pose)) < 1e-9            # and it is the true pose
        assert a.residual == pytest.approx(b.residual, abs=1e-14)


def test_guard_and_distribution_against_numpy(models):
    fast, _ = models
    ck = fast.compiled
    rng = np.random.default_rng(4)
    for pose in _poses(fast, 30, 5):
        J = fast.jacobian(pose)
        ev = np.linalg.eigvalsh((J / SCALING).T @ (J / SCALING))
        lo, hi = ck.singular_values(J, SCALING)
        assert lo == pytest.approx(math.sqrt(ev[0]), rel=1e-10)
        assert hi == pytest.approx(math.sqrt(ev[-1]), rel=1e-12)
        tau, w = rng.normal(size=8), rng.normal(size=6)
        out = np.empty(8)
        assert ck.project(J, tau, w, out)
        ref = J @ np.linalg.solve(J.T @ J, J.T @ tau + w)
        assert np.max(np.abs(out - ref)) < 1e-12 * np.max(np.abs(ref))
    J = fast.jacobian(fast.home)
    J[3, 2] = np.nan
    assert math.isnan(ck.singular_values(J, SCALING)[0])


def test_spring_wrench_and_reading_checks(models):
    ck = models[0].compiled
    rng = np.random.default_rng(6)
    for _ in range(20):
        anchor = tuple(rng.uniform(-0.2, 0.2, 6))
        sp = Spring(anchor, tuple(rng.uniform(1, 100, 6)), tuple(rng.uniform(0, 5, 6)))
        pose, twist = rng.uniform(-0.3, 0.3, 6), rng.normal(size=6)
        got = np.empty(6)
        ck.spring_wrench(pose, twist, sp._p0, sp._R0t, sp._k, sp._d, got)
        assert np.max(np.abs(got - sp.wrench(pose, twist))) < 1e-13
        w = rng.normal(size=6)
        R = _rot(pose[3:])
        ck.rotate_wrench(pose[3:], w, got)
        assert np.allclose(got, np.r_[R @ w[:3], R @ w[3:]], rtol=0, atol=1e-15)
    a, w = np.array([0.1, -0.4, 0.2]), np.array([1.0, -3.0, 2.0, 0.1, -0.2, 0.05])
    assert reading_extremes(a, w) == (True, 0.4, 3.0, 0.2)
    w[4] = np.inf
    assert reading_extremes(a, w)[0] is False


def test_the_compiled_loop_follows_the_reference_loop():
    """0.5 s in-process closed loop (example scene) with either kinematics: the same
    trajectory up to rounding amplified by the loop (< 1e-9 m or rad)."""
    sc = dataclasses.replace(builtin_scene(), preset="octo")
    a = run_loopback(sc, load_model("octo"), 0.5)
    b = run_loopback(sc, load_model("octo", compiled=False), 0.5)
    assert len(a["pose"]) == len(b["pose"]) == 500
    assert np.max(np.abs(a["pose"] - b["pose"])) < 1e-9
    assert np.max(np.abs(a["tau_cmd"] - b["tau_cmd"])) < 1e-5   # float32 on the wire
    assert np.array_equal(a["refused"], b["refused"])


def test_the_first_cycle_compiles_nothing():
    """build() compiles every signature a control cycle uses (a compilation inside the
    first cycle would take a large fraction of a second): a short loop adds none."""
    import sys
    from distkin.control import cycle_kernels, frame_codec
    model = load_model("octo")

    def signatures():
        from distkin.control import cycle_common
        mods = [m for k, m in sys.modules.items() if k.startswith("distkin_cycle_")]
        out = {(m.__name__, n): len(getattr(m, n).signatures) for m in mods
               for n in ("ik", "jacobian", "closure", "forward", "cycle")}
        out.update({n: len(getattr(cycle_common, n).signatures)
                    for n in ("singular_values", "project", "rotate_wrench", "spring_wrench",
                              "rotate", "near_singular", "environment", "readings")})
        out.update({n: len(getattr(frame_codec, n).signatures)
                    for n in ("_encode_state", "_encode_command", "_decode_state",
                              "_decode_command")})
        out.update({k: len(f.signatures) for k, f in cycle_kernels._COMPILED.items()})
        return out

    frame_codec.state_decoder()      # made (and compiled) when a Link or loopback starts
    frame_codec.command_decoder()
    before = signatures()
    run_loopback(dataclasses.replace(builtin_scene(), preset="octo"), model, 0.05)
    assert signatures() == before


def _frames(model, n, seed):
    """State frames along a path that crosses the example's wall (x = 20 mm) with hand
    wrenches strong enough to drive the set point to the reach boundary."""
    rng = np.random.default_rng(seed)
    for k in range(n):
        pose = model.home + np.array([0.04 * math.sin(k / 60), 0.01, 0.0, 0.02, 0.0, 0.01])
        q, _ = model.ik(pose)
        q = q + 2e-4 * rng.standard_normal(model.L)
        f = -30.0 * np.sign(math.sin(k / 90)) if k > 50 else 2.0
        yield StateFrame(k, 1000 * k, 0, q, np.array([f, -f / 3, 1.0, 0.05, -0.02, 0.01])
                         + 0.02 * rng.standard_normal(6)), 1e-3 * (1 + 0.2 * rng.random())


@pytest.mark.parametrize("variant", [
    {},
    {"pd": {"distribution": "independent", "ki": 30.0, "derivative_filter_s": 0.0,
            "hand_feedforward": False, "torque_limit": 0.8}},
    {"pd": {"gravity_compensation": False, "hand_feedforward": False}},
    {"safety": {"sigma_min": 0.16}},
])
def test_the_fused_cycle_makes_the_same_decisions_as_the_python_steps(models, variant):
    """Controller.compute by the fused compiled cycle against the same controller's
    Python steps (same kinematic kernels, same frames): the same decisions (accepted,
    reason, mode, saturation, FK iterations) cycle by cycle, states and torques to
    rounding -- through wall contact, refusals at the reach boundary, a fault period
    (zero torque) and, with a stricter guard, singular stops."""
    fast = models[0]
    sc = builtin_scene()
    sc = dataclasses.replace(sc, preset="octo",
                             pd=dataclasses.replace(sc.pd, **variant.get("pd", {})),
                             safety=dataclasses.replace(sc.safety, **variant.get("safety", {})))
    a, b = Controller(sc, fast), Controller(sc, fast, fused=False)
    assert a._fused is not None and b._fused is None
    seen = set()
    for k, (frame, dt) in enumerate(_frames(fast, 600, 7)):
        for ctl in (a, b):
            ctl.state = FAULT if 300 <= k < 320 else RUN
        ra, rb = a.compute(frame, dt), b.compute(frame, dt)
        seen.add(rb.reason or ("saturated" if rb.saturated else "ok"))
        assert (ra.accepted, ra.reason, ra.mode, ra.saturated, ra.fk_iterations) == \
            (rb.accepted, rb.reason, rb.mode, rb.saturated, rb.fk_iterations), k
        for x, y in ((ra.torques, rb.torques), (ra.pose, rb.pose), (ra.wrench, rb.wrench),
                     (ra.desired, rb.desired), (a.adm.twist, b.adm.twist)):
            if y is None:
                assert x is None
            else:
                np.testing.assert_allclose(x, y, rtol=1e-10, atol=1e-12)
        assert ra.fk_residual == pytest.approx(rb.fk_residual, rel=1e-9, abs=1e-15)
    assert a.refused == b.refused
    expected = {"singular_stop"} if "safety" in variant else {"unreachable", "ok"}
    assert expected <= seen, seen


def test_the_compiled_plant_steps_like_the_numpy_plant(models):
    """Plant.step with the compiled drives and dynamics (a compiled model) against the
    numpy route (the reference model): run, hold and zero-torque periods, torques
    beyond what the drives deliver -- the same states to rounding, the same saturation
    flags and end-stop hits."""
    from distkin.control.plant import Plant
    from distkin.control.protocol import MODE_HOLD, MODE_RUN, MODE_ZERO_TORQUE
    sc = builtin_scene()
    fast, ref = (Plant(m, sc.simulator.motors, sc.simulator.hand, seed=3) for m in models)
    assert fast._ck is not None and ref._ck is None
    # seed 2: since the plant carries the rotors' velocity-product term, the walk of
    # seed 8 ends pressed on a reach boundary (margin 3e-12 m²), where the IK's sqrt
    # magnifies the routes' last-bit differences to 1e-9; this walk stays 0.02 m² away
    rng = np.random.default_rng(2)
    for k in range(1500):
        mode = MODE_RUN if k < 900 else MODE_HOLD if k < 1200 else MODE_ZERO_TORQUE
        tau = rng.normal(0.0, 0.4 if k % 300 else 60.0, fast.model.L)
        for p in (fast, ref):
            p.step(tau, mode, 2.5e-4)
        assert fast.saturated == ref.saturated and fast.end_stop_hits == ref.end_stop_hits
        # rounding (the 6 × 6 solve, sums in another order) grows through q̇ = Δq/dt
        for x, y, tol in ((fast.pose, ref.pose, 1e-12), (fast.q, ref.q, 1e-12),
                          (fast.twist, ref.twist, 1e-8), (fast.tau, ref.tau, 1e-8)):
            np.testing.assert_allclose(x, y, rtol=0, atol=tol)
    assert np.abs(fast.pose - fast.model.home).max() > 1e-3       # it moved
    assert fast.end_stop_hits == 0
    assert np.array_equal(fast.encoders(), ref.encoders())
