"""The fast tier's error estimate of J = Jq^-1 Jx (Kühne et al., eqs. (1)-(2);
distkin.mechanisms.kinematics_tiers) next to a leg's reach boundary, where Jq_ii -> 0
(the serial singularity of an RSS leg) and float64 loses J: the stated figure is at least
the actual error of the fast J, Jq and Jx, measured against the precise tier at 50 digits
(the exact model in mpmath, another arithmetic), at every distance from the boundary
along z; poses where float64 cannot give J are flagged; away from the boundary the figure
stays within 100x of the old estimate 4 eps max|J row| max(1, l/|Jq_ii|)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from distkin.errors import ConditioningWarning
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics_tiers import J_REL_USEFUL, jacobian_tier

#: distances (m) below the reach boundary along z, 0 = the last float inside it
DISTANCES = (0.0, 1e-15, 1e-13, 1e-11, 1e-9, 1e-7, 5.4e-5, 1e-3, 1e-2)


def _boundary_line(mech, start):
    """Poses start + (0, 0, z_b - d) for d in DISTANCES, z_b the last z (float) with every
    leg closing (bisection on the reach kernel), and the start itself."""
    reach = mech.kernels("batched").reach
    lo, hi = 0.0, 0.5
    assert reach(start[None]).min() >= 0 and reach((start + [0, 0, hi, 0, 0, 0])[None]).min() < 0
    while (lo + hi) / 2 not in (lo, hi):
        mid = (lo + hi) / 2
        ok = reach((start + [0, 0, mid, 0, 0, 0])[None]).min() >= 0
        lo, hi = (mid, hi) if ok else (lo, mid)
    return np.array([start + [0, 0, lo - d, 0, 0, 0] for d in DISTANCES] + [start])


def _actual(fast, prec):
    """|fast - precise| of J, Jq, Jx (the precise values at 50 digits, rounded)."""
    f = np.vectorize(float, otypes=[float])
    return (np.abs(fast.J - f(prec.values)), np.abs(fast.Jq - f(prec.jq_values)),
            np.abs(fast.Jx - f(prec.jx_values)))


@pytest.mark.parametrize("name, start", [("octopod", (0, 0, 0.3, 0, 0, 0)),
                                         ("hexa", (0.01, -0.02, 0.3, 0.05, 0.1, -0.2))])
def test_stated_error_covers_the_actual_error_up_to_the_reach_boundary(name, start):
    mech = preset(name)
    X = _boundary_line(mech, np.array(start, dtype=float))
    with pytest.warns(ConditioningWarning, match="reach boundary"):
        fast = jacobian_tier(mech, X, "fast")
    prec = jacobian_tier(mech, X, "precise", dps=50)
    aJ, aq, ax = _actual(fast, prec)
    closes = fast.valid
    assert closes.all()                           # the line stays inside the boundary
    # stated >= actual, everywhere (inf where first order fails, right at the boundary)
    assert np.all(aJ <= fast.J_error) and np.all(aq <= fast.Jq_error)
    assert np.all(ax <= fast.Jx_error)
    # the boundary is where the old figure failed (QA: actual/stated 1e3..1e7 there)
    eps = np.finfo(float).eps
    old = 4 * eps * np.abs(fast.J).max(-1) * np.maximum(1, mech.length_scale / np.abs(fast.Jq))
    assert np.any(aJ[:4] > 100 * old[:4, :, None])
    # the flag: a pose whose actual relative error of a row exceeds J_REL_USEFUL is
    # flagged; one that is not flagged has every row within it
    ref = np.abs(np.vectorize(float, otypes=[float])(prec.values)).max(-1)
    rel = (aJ.max(-1) / ref).max(-1)
    assert np.all(fast.inaccurate[rel > J_REL_USEFUL])
    assert np.all(rel[~fast.inaccurate] <= J_REL_USEFUL)
    assert fast.inaccurate[:3].all() and not fast.inaccurate[5:].any()
    # away from the boundary (the start, 1 mm and 1 cm inside): a few times the old
    # rounding figure, never absurdly larger; and the other tiers are not flagged
    assert np.all(fast.J_error[-3:] <= 100 * old[-3:, :, None])
    assert not prec.inaccurate.any()


def test_qa_pose_next_to_the_octopod_boundary():
    """The QA's pose (z = 0.4973287 m, 54 nm below the boundary at z = 0.49732875445 m;
    every leg's reach margin 1.2e-7 m^2): the old figure stated 2e-9 for an actual
    error of 2.8e-6."""
    mech = preset("octopod")
    X = np.array([[0, 0, 0.4973287, 0, 0, 0]])
    fast = jacobian_tier(mech, X, "fast")
    prec = jacobian_tier(mech, X, "precise", dps=50)
    aJ, _, _ = _actual(fast, prec)
    assert aJ.max() > 1e-6 and np.all(aJ <= fast.J_error)
    assert fast.J_error.max() < 10 * aJ.max()          # and not absurdly above it


def test_no_warning_inside_the_workspace():
    mech = preset("octopod")
    X = mech.home + np.array([[0.01, -0.02, 0.03, 0.1, 0.05, -0.2], [0, 0, 0, 0, 0, 0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConditioningWarning)
        fast = jacobian_tier(mech, X, "fast")
    assert not fast.inaccurate.any() and np.all(np.isfinite(fast.J_error))


@pytest.mark.parametrize("kind", ["octopod", "mixed"])
def test_q_derivatives_match_differences_of_the_closure_kernel(kind):
    """dJq/dq and dJx/dq of reference.jacobian_q_derivatives (the formulas the estimate
    propagates the IK error through) against central differences in q of the generated
    closure kernel (Phi and -Jx at any q): Jq = dPhi/dq, so dJq/dq is the second
    difference of Phi; h = 1e-4 rad (m), truncation error ~1e-8 relative."""
    from distkin.mechanisms.kinematics import LegMechanism
    from distkin.mechanisms.reference import jacobian_q_derivatives
    m = preset("octopod")
    if kind == "mixed":                     # two legs replaced by prismatic ones
        legs = [leg.as_dict() for leg in m.leg_description().leg_table]
        for j in (2, 5):
            legs[j] = dict(type="SPS", base=legs[j]["base"], platform=legs[j]["platform"])
        m = LegMechanism("mixed", legs, home_pose=tuple(m.home))
    X = m.home + np.array([[0.01, -0.02, 0.03, 0.1, 0.05, -0.2], [0, 0, 0.02, 0, 0, 0]])
    q = m.inverse_kinematics(X)[0]
    djq, djx = jacobian_q_derivatives(m, X, q)
    closure = m.kernels("batched").closure
    h = 1e-4
    up, mid, dn = (closure(q + s, X) for s in (h, 0.0, -h))
    fd_jq = (up[..., 0] - 2 * mid[..., 0] + dn[..., 0]) / h ** 2
    fd_jx = -(up[..., 1:] - dn[..., 1:]) / (2 * h)
    np.testing.assert_allclose(djq, fd_jq, rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(djx, fd_jx, rtol=1e-5, atol=1e-9)
