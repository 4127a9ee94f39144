"""The neglected-offset pose error never reports a wrong assembly mode as its answer
without saying so (distkin.delta.offset_study; docs/design.md, "Fast or warn").

The pose R = diag(1, -1, -1), t = (6, 3.46, 15) of the Griffis-Duffy example (Rojas,
Borràs, Thomas, *The Octahedral Manipulator Revisited*, Sec. VI: base side 12, platform
side 6) is nearly symmetric: the fast octahedral tier does not prove its real-root count
there and misses the assembly mode next to the true pose (QA: an "error" of 3.40 instead
of 0.048, with no warning).  References, each independent of the route under test:

* the first-order twist J^-1 (m - l) of eq. (5) (a linear solve, no octic);
* the certified octahedral forward kinematics called directly, and the exact residual
  of the octahedral legs at the mode it returns (they must be the 6-6 legs m);
* for Fig. 2(d), the Δ route of eq. (8), which recovers the true pose exactly (an
  analytic 0).
"""

import warnings

import numpy as np
import pytest

from distkin.delta import approximation, compare_approximations, neglected_offset_error
from distkin.delta.offset_study import leg_lengths, platform_frame
from distkin.errors import ConditioningWarning
from distkin.octahedral import forward_kinematics
from distkin.singularity import rotation_from_vector

GD = ([[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]], [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]])
R_SYM = np.diag([1.0, -1.0, -1.0])
T_SYM = np.array([6.0, 3.46, 15.0])


def _conditioning(caught):
    return [w for w in caught if issubclass(w.category, ConditioningWarning)]


def _call(*args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        e = neglected_offset_error(*args, **kwargs)
    return e, _conditioning(caught)


@pytest.fixture(scope="module")
def standard():
    return approximation(GD, "standard", "0.1")


@pytest.fixture(scope="module")
def certified_reference(standard):
    """Position and angle error of the certified mode nearest the true pose, and the
    worst residual of the octahedral legs at that mode against the 6-6 legs m."""
    from distkin.delta import octahedral_as_66
    m = leg_lengths(standard, R_SYM, T_SYM)
    res = forward_kinematics(*GD, [float(x) for x in m], method="certified")
    c, L = platform_frame(GD)
    best = None
    for p in res.poses:
        R, t = np.asarray(p.rotation, float), np.asarray(p.translation, float)
        pos = np.linalg.norm(R @ c + t - (R_SYM @ c + T_SYM))
        ang = np.arccos(np.clip((np.trace(R_SYM.T @ R) - 1) / 2, -1, 1))
        resid = np.max(np.abs(leg_lengths(octahedral_as_66(GD), R, t) - m))
        if best is None or np.hypot(pos, L * ang) < best[0]:
            best = (np.hypot(pos, L * ang), pos, ang, resid)
    return best[1:]


def test_default_finds_the_mode_next_to_the_pose(standard, certified_reference):
    e, warned = _call(GD, standard, R_SYM, T_SYM)
    pos, ang, resid = certified_reference
    assert resid < 1e-9                          # the reference mode carries the legs m
    assert e.trusted and warned == []
    assert e.position == pytest.approx(pos, rel=1e-9)
    assert e.orientation == pytest.approx(ang, rel=1e-6)
    # first order (eq. (5)): 0.04768 / 0.002893; the wrong branch was 3.40 / 2.68 rad
    assert e.position == pytest.approx(e.first_order_position, rel=5e-3)
    assert e.orientation == pytest.approx(e.first_order_orientation, rel=5e-3)


def test_fast_tier_warns_when_it_cannot_prove_the_modes(standard):
    e, warned = _call(GD, standard, R_SYM, T_SYM, method="fast")
    assert not e.trusted
    assert len(warned) == 1
    text = str(warned[0].message)
    assert "not proved" in text and "method='auto'" in text
    assert f"{e.position:.4g}" in text                   # the doubtful value is named


def test_fast_tier_is_silent_and_right_when_proved(standard):
    # away from the symmetric pose the fast tier proves its roots: no escalation needed
    R = rotation_from_vector(np.array([0.2, 0.0, 0.0])) @ R_SYM
    e, warned = _call(GD, standard, R, T_SYM + [0.5, -1.0, 0.0], method="fast")
    a, _ = _call(GD, standard, R, T_SYM + [0.5, -1.0, 0.0], method="auto")
    assert e.trusted and warned == []
    assert e.position == pytest.approx(a.position, rel=1e-12)
    assert e.position == pytest.approx(e.first_order_position, rel=2e-2)


def test_precise_tier_agrees_and_flags_its_own_doubt(standard, certified_reference):
    e, warned = _call(GD, standard, R_SYM, T_SYM, method="precise", dps=30)
    assert e.position == pytest.approx(certified_reference[0], rel=1e-9)
    # whatever the precise solver says about its count is passed on, once, and untrusted
    assert len(warned) == (0 if e.trusted else 1)


def test_delta_route_is_exact_or_flagged():
    plat = approximation(GD, "griffis_duffy", "0.1")
    a, warned = _call(GD, plat, R_SYM, T_SYM)           # auto: escalates to certified
    assert a.trusted and warned == []
    assert a.exact_position < 1e-10 and a.exact_orientation < 1e-10   # eq. (8): exact
    # fast: trusted means right; otherwise one warning says which solve is in doubt
    f, warned = _call(GD, plat, R_SYM, T_SYM, method="fast")
    assert (not f.trusted) == (len(warned) == 1)
    if f.trusted:
        assert f.exact_position < 1e-10
    else:                                       # (QA: 3.38, reported as trusted)
        assert "Δ route" in str(warned[0].message)


def test_compare_warns_once_for_fast_and_is_trusted_by_default(standard):
    Rs, ts = np.array([R_SYM, R_SYM]), np.array([T_SYM, T_SYM])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fast = compare_approximations(GD, Rs, ts, ["0.1"], kinds=("standard",),
                                      method="fast")
    assert fast.untrusted == 2 and len(_conditioning(caught)) == 1
    assert "2 of 2" in str(_conditioning(caught)[0].message)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        auto = compare_approximations(GD, Rs, ts, ["0.1"], kinds=("standard",))
    assert auto.method == "auto" and auto.untrusted == 0 and _conditioning(caught) == []
    np.testing.assert_allclose(auto.position["standard"],
                               auto.first_order_position["standard"], rtol=5e-3)
