"""A late frame's gap is stepped in periods by the admittance (distkin.control.admittance).

The loop steps the virtual model with the measured gap between state frames, up to 5
periods, while ``check_step`` checks its stability at the nominal period only.  One
semi-implicit Euler step of 5 h multiplies the state of a stiff spring that the step h
keeps stable by up to the spectral radius at 5 h; a few late frames in a row made the
set point diverge (review note of the last sessions).  Now a gap over one period is
taken as ceil(gap / h) equal steps.  References: the same device time in nominal steps
(the late-frame run must equal it), the stability bound per axis h²k/m + 2hd/m < 4
(``step_spectral_radius``), and the two controller routes (fused compiled, Python
steps) against each other."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.control.admittance import Admittance, Spring, step_spectral_radius, substeps

H = 1e-3                                          # s, the nominal period (1 kHz)
M, K, D = 1.0, 2.0 / H ** 2, 0.25 / H             # kg, N/m, N·s/m: h²k/m = 2, 2hd/m = 0.5
ROT = dict(mass=[0.005] * 3, k=[0.0] * 3, d=[0.1] * 3)


def _adm():
    spring = Spring(anchor=(0.0,) * 6, stiffness=(K, K, K, 0.0, 0.0, 0.0),
                    damping=(D, D, D, 0.0, 0.0, 0.0))
    a = Admittance([M] * 3 + ROT["mass"], [0.0] * 3 + ROT["d"], [spring])
    a.reset(np.array([1e-3, -2e-3, 5e-4, 0.0, 0.0, 0.0]))         # m from the anchor
    return a


def test_substeps():
    assert substeps(H, H) == 1 and substeps(H * (1 + 1e-12), H) == 1
    assert substeps(2.5 * H, H) == 3 and substeps(5 * H, H) == 5
    assert substeps(5 * H, None) == 1 and substeps(5 * H, 0.0) == 1


def test_the_premise_stable_at_the_period_not_at_five():
    rho_h = step_spectral_radius([M] * 3 + ROT["mass"], [0.0] * 3 + ROT["d"],
                                 _adm().environment, H)[0]
    rho_5h = step_spectral_radius([M] * 3 + ROT["mass"], [0.0] * 3 + ROT["d"],
                                  _adm().environment, 5 * H)[0]
    assert rho_h < 1.0 < rho_5h


def test_late_frames_are_the_same_time_in_periods():
    """200 frames 5 periods apart: the same motion as 1000 nominal steps (to rounding:
    5h/5 is h within an ulp), and it decays; one 5h step at a time it diverges."""
    late, nominal, single = _adm(), _adm(), _adm()
    x0 = np.abs(late.pose[:3]).max()
    for k in range(200):
        late.commit(*late.propose(np.zeros(6), 5 * H, max_step=H))
        for _ in range(5):
            nominal.commit(*nominal.propose(np.zeros(6), H, max_step=H))
        if k < 20:
            single.commit(*single.propose(np.zeros(6), 5 * H))       # the old way
        np.testing.assert_allclose(late.pose, nominal.pose, rtol=0, atol=1e-12)
    assert np.abs(late.pose[:3]).max() < 1e-3 * x0                    # it settled
    assert np.abs(single.pose[:3]).max() > 1e3 * x0                   # 20 steps: diverged


@pytest.mark.parametrize("gap", [1.0, 2.5, 5.0])
def test_the_fused_cycle_steps_a_late_frame_as_the_python_steps(gap):
    """The Octo's controller with this spring: the fused compiled cycle and the Python
    steps give the same set point after frames ``gap`` periods apart."""
    from pathlib import Path

    from distkin.control.config import loads_control_scene
    from distkin.control.controller import Controller
    from distkin.control.kinematics import load_model
    from distkin.control.protocol import StateFrame
    root = Path(__file__).resolve().parents[2]
    text = (root / "examples" / "control_octo.toml").read_text()
    m = load_model("octo")
    sc = loads_control_scene(text)
    poses = []
    for fused in (True, False):
        ctl = Controller(sc, m, fused=fused)
        assert (ctl._fused is not None) == fused
        spring = Spring(anchor=tuple(m.home), stiffness=(K / 50,) * 3 + (0.0,) * 3,
                        damping=(D / 50,) * 3 + (0.0,) * 3)
        ctl.adm.environment = (spring,)
        if fused:
            from distkin.control.cycle_kernels import cycle_params
            from distkin.control.controller import SCALING
            ctl._fused = cycle_params(ctl.pd, ctl.safety, ctl.adm, ctl.weight, SCALING,
                                      period=ctl.dt_nominal)
        start = m.home + np.array([2e-3, -1e-3, 1e-3, 0, 0, 0])
        ctl.start_at(start)
        ctl.started = True
        q = m.ik(start)[0]
        for k in range(30):
            r = ctl.compute(StateFrame(k + 1, 1000 * k, 0, q, np.zeros(6)), gap * H)
            assert r.reason == ""
        poses.append(ctl.adm.pose.copy())
    np.testing.assert_allclose(poses[0], poses[1], rtol=0, atol=1e-12)


def test_gaps_beyond_the_cap_are_refused():
    """Review of e5ba69d: no cap on the count (1e303 periods looped for ever);
    :data:`MAX_SUBSTEPS` periods are the most, a gap past it is an InputError that names
    the cap and the gap."""
    from distkin.control.admittance import MAX_SUBSTEPS
    from distkin.errors import InputError
    assert substeps(MAX_SUBSTEPS * H, H) == MAX_SUBSTEPS
    for bad in (MAX_SUBSTEPS * H * 1.001, 1e300, np.inf, np.nan, 0.0, -H):
        with pytest.raises(InputError, match="dt"):
            substeps(bad, H)
    with pytest.raises(InputError, match=f"at most {MAX_SUBSTEPS} periods"):
        _adm().propose(np.zeros(6), 1e6 * H, max_step=H)


@pytest.mark.parametrize("fused", [True, False])
def test_the_controller_refuses_a_bad_gap_on_both_routes(fused):
    """Review of e5ba69d: the fused route took any gap (an infinite one overflowed its
    step count into an accepted step, 0 divided by zero, a negative one stepped back);
    now both routes refuse 0, negative, non-finite and over-cap gaps before any state
    changes, and then take the next good frame as if nothing had come."""
    from pathlib import Path

    from distkin.control.config import loads_control_scene
    from distkin.control.controller import Controller
    from distkin.control.kinematics import load_model
    from distkin.control.protocol import StateFrame
    from distkin.errors import InputError
    root = Path(__file__).resolve().parents[2]
    m = load_model("octo")
    ctl = Controller(loads_control_scene((root / "examples" / "control_octo.toml")
                                         .read_text()), m, fused=fused)
    assert (ctl._fused is not None) == fused
    q = m.ik(m.home + np.array([1e-3, 0, 0, 0, 0, 0]))[0]
    ref = Controller(loads_control_scene((root / "examples" / "control_octo.toml")
                                         .read_text()), m, fused=fused)
    for bad in (np.inf, 1e16 * H, 0.0, -H, np.nan):
        with pytest.raises(InputError, match="dt"):
            ctl.compute(StateFrame(1, 0, 0, q, np.ones(6)), bad)
    a = ctl.compute(StateFrame(1, 0, 0, q, np.ones(6)), H)
    b = ref.compute(StateFrame(1, 0, 0, q, np.ones(6)), H)
    assert a.reason == b.reason and np.array_equal(a.torques, b.torques)
    assert np.array_equal(ctl.adm.pose, ref.adm.pose)
