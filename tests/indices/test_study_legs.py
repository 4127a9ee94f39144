"""The study on leg tables (issue 16): per-leg transmission lengths, per-leg actuator
limits with units per actuator type (distkin.indices.actuators), checked against
independent routes: |Jq| and the cranks directly, linear programs and the closed-form
box of the true velocity set."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize import linprog

from distkin.errors import InputError
from distkin.indices.actuators import leg_limits, limit_text, uniform_limits
from distkin.indices.study import evaluate_poses
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics import LegMechanism
from distkin.mechanisms.platforms import platform_mechanism

BASE = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]


def _gd(limits):
    m = platform_mechanism((BASE, PLAT), unit=0.01, height=17, name="gd_study",
                           mass=0.17, inertia=3e-4, route="numpy")
    legs = tuple(dataclasses.replace(leg, limit=(-f, f)) for leg, f in zip(m.leg_table, limits))
    return dataclasses.replace(m, leg_table=legs)


def _poses(m, n=6, seed=2):
    rng = np.random.default_rng(seed)
    return m.home + rng.uniform(-1, 1, (n, 6)) * [0.015, 0.015, 0.015, 0.15, 0.15, 0.15]


def test_transmission_is_per_leg():
    """A Hunt-type table with one crank lengthened: transmission_min = min_i |Jq_ii|/l1_i
    with each leg's own crank (not the largest one for every leg)."""
    legs = list(preset("hunt").leg_description().leg_table)
    legs[2] = dataclasses.replace(legs[2], crank=legs[2].crank * 1.5)
    m = LegMechanism("hunt_long", tuple(legs), preset("hunt").home, route="numpy")
    X = _poses(m)
    ok, v = evaluate_poses(m, X, route="numpy", compiled=False)
    Jq, _ = m.jq_jx(X[ok])
    cranks = np.array([leg.crank for leg in legs])
    assert np.allclose(v["transmission_min"], np.min(np.abs(Jq) / cranks, axis=1), rtol=1e-14)
    assert not np.allclose(v["transmission_min"], np.min(np.abs(Jq), axis=1) / cranks.max())
    gd = _gd([50] * 6)
    ok, v = evaluate_poses(gd, _poses(gd), actuators={"stall_force": 100, "speed": 1},
                           route="numpy")
    assert np.allclose(v["transmission_min"], 1.0)        # |Jq_ii| = 1 for a prismatic leg


def _lp_force(J, lim, d):
    L = J.shape[0]
    A = np.hstack([J.T, -np.concatenate([d, np.zeros(3)])[:, None]])
    res = linprog(np.r_[np.zeros(L), -1.0], A_eq=A, b_eq=np.zeros(6),
                  bounds=[(-f, f) for f in lim] + [(0, None)], method="highs")
    return res.x[-1]


def test_per_leg_force_limits_against_linprog_and_true_velocity_box():
    """Legs of 30 ... 80 N: the worst continuous force (zonotope with per-leg limits) is the
    smallest force a linear program finds over 300 directions (to 2 %, never above); the
    worst true velocity at zero ω with per-leg speeds is min over directions of
    min_i v_i / |J_i (d, 0)| (closed form)."""
    f = np.array([30.0, 40.0, 50.0, 60.0, 70.0, 80.0])
    m = _gd(f)
    speeds = {"stall_force": 100, "speed": 1.0}
    X = _poses(m, 3)
    ok, v = evaluate_poses(m, X, actuators=speeds, route="numpy")
    assert ok.all()
    rng = np.random.default_rng(11)
    D = rng.normal(size=(300, 3))
    D /= np.linalg.norm(D, axis=1)[:, None]
    for k, x in enumerate(X):
        J = m.jacobian(x)
        lp = min(_lp_force(J, f, d) for d in D)
        assert v["force"][k] <= lp * (1 + 1e-9) and lp <= v["force"][k] * 1.02
        box = np.min(1.0 / np.abs(D @ J[:, :3].T), axis=1).min()
        assert v["velocity_true"][k] <= box * (1 + 1e-9) and box <= v["velocity_true"][k] * 1.02
    # equal limits take the scalar one-facet route (compiled); the per-leg route on the
    # same limits gives the same capabilities
    from distkin.indices.actuators import per_leg_capabilities
    from distkin.indices.study import CAPABILITIES, TRUE_VELOCITIES
    m50 = _gd([50] * 6)
    ok2, v50 = evaluate_poses(m50, X, actuators=speeds, route="numpy")
    per = per_leg_capabilities(m50.jacobian(X), np.array([0.17] * 3 + [3e-4] * 3),
                               leg_limits(m50, speeds), CAPABILITIES, TRUE_VELOCITIES)
    for name, vals in per.items():
        assert np.allclose(vals, v50[name], rtol=1e-9), name


def test_units_per_actuator_type_and_missing_keys():
    m = _gd([50] * 6)
    with pytest.raises(InputError) as exc:
        leg_limits(m, {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51})
    assert exc.value.field == "actuators.stall_force"
    lim = leg_limits(m, {"stall_force": 100, "speed": 1})
    assert uniform_limits(lim) == {"nominal_torque": 50.0, "stall_torque": 100.0,
                                   "velocity": 1.0}
    assert limit_text(lim, "nominal") == "50 N" and limit_text(lim, "rate") == "1 m/s"
    hunt = preset("hunt")
    lim = leg_limits(hunt, {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51})
    assert limit_text(lim, "nominal") == "2.5 N·m" and limit_text(lim, "rate") == "51 rad/s"
    mixed = LegMechanism("mixed", tuple(preset("hunt").leg_description().leg_table[:5])
                         + (m.leg_table[0],) + tuple(m.leg_table[1:2]), preset("hunt").home,
                         route="numpy")
    lim = leg_limits(mixed, {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51,
                             "stall_force": 100, "speed": 1})
    assert uniform_limits(lim) is None
    assert limit_text(lim, "nominal") == "2.5 N·m (revolute legs), 50 N (prismatic legs)"
