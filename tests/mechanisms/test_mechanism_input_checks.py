"""Bad input at the Python entry points of distkin.mechanisms: booleans, leg tables that
are not tables, duplicate legs, shapes, ``dps`` and ``bits`` with the wrong tier; each
an InputError naming the field (as the scene parser does).  Good input of the same kind
(a 4x4 FK guess) against an independent route: the IK round trip and the 6-vector
guess."""

from __future__ import annotations

import numpy as np
import pytest

from distkin.errors import InputError
from distkin.mechanisms import LegMechanism, preset
from distkin.mechanisms.legs import Leg, LegsDescription
from distkin.spatial import pose_to_matrix

RUS = dict(type="RUS", base=(0, 0, 0), platform=(0, 0, 0), axis=(0, 0, 1), crank0=(1, 0, 0),
           crank90=(0, 1, 0), crank=0.1, distal=0.2)


def _ups_legs():
    """Six UPS legs (m) of a hexapod: base radius 0.5, platform radius 0.3."""
    legs = []
    for k in range(6):
        b, p = np.deg2rad(60 * k + 10 * (-1) ** k), np.deg2rad(60 * k + 30 * (-1) ** k)
        legs.append(dict(type="UPS", base=(0.5 * np.cos(b), 0.5 * np.sin(b), 0.0),
                         platform=(0.3 * np.cos(p), 0.3 * np.sin(p), 0.0)))
    return legs


def _ups(legs=None, home=(0, 0, 0.6, 0, 0, 0)):
    return LegMechanism("ups", tuple(_ups_legs() if legs is None else legs), home,
                        route="numpy")


@pytest.mark.parametrize("make, field", [
    (lambda: Leg(type="SPS", base=(True, 0, 0), platform=(0, 0, 0)), "base[0]"),
    (lambda: Leg(type="SPS", base=(0, 0, 0), platform=(0, False, 0)), "platform[1]"),
    (lambda: Leg(type="SPS", base=(0, 0, 0), platform=(0, 0, 0), range=(False, True)),
     "range[0]"),
    (lambda: Leg(type="SPS", base=(0, 0, 0), platform=(0, 0, 0), limit=True), "limit"),
    (lambda: Leg(**RUS, branch=True), "branch"),
    (lambda: Leg(**{**RUS, "axis": (0, 0, True)}), "axis[2]"),
    (lambda: Leg(**{**RUS, "crank": True}), "crank"),
    (lambda: preset("hunt", l1=True), "l1"),
    (lambda: preset("hunt", beta=False), "beta"),
    (lambda: _ups(home=(0, 0, True, 0, 0, 0)), "home[2]"),
    (lambda: _ups([{**_ups_legs()[0], "base": (True, 0, 0)}] + _ups_legs()[1:]),
     "leg[0].base[0]"),
    (lambda: _ups().inverse_kinematics([0, 0, True, 0, 0, 0]), "poses[2]"),
    (lambda: _ups().jacobian([[0, 0, 0.6, 0, 0, 0], [0, 0, 0.6, 0, True, 0]]), "poses[1][4]"),
    (lambda: _ups().forward_kinematics([True] * 6), "q[0]"),
    (lambda: _ups().forward_kinematics([0.6] * 6, [0, 0, True, 0, 0, 0]), "guess[2]"),
    (lambda: _ups().forward_kinematics([0.6, 0.6, 0.6, True, 0.6, 0.6], method="precise"),
     "q[3]"),
])
def test_booleans_refused_naming_the_field(make, field):
    with pytest.raises(InputError, match="boolean") as exc:
        make()
    assert exc.value.field == field


def test_numeric_arrays_pass_the_boolean_check():
    """A numeric array is not walked (no_booleans returns on its dtype): the IK of an
    array of poses is the analytic leg lengths."""
    m = _ups()
    X = np.tile(m.home, (4, 1)) + np.linspace(0, 0.01, 4)[:, None]
    q, valid = m.inverse_kinematics(X)
    from distkin.spatial import rotation_matrix
    B = np.array([leg.base for leg in m.leg_table])
    p = np.array([leg.platform for leg in m.leg_table])
    ref = [np.linalg.norm(x[:3] + p @ rotation_matrix(x[3:]).T - B, axis=1) for x in X]
    np.testing.assert_allclose(q, ref, rtol=1e-14)
    assert valid.all()


@pytest.mark.parametrize("table, field", [
    ("abcdef", "leg"),
    (dict(type="SPS", base=(0, 0, 0), platform=(0, 0, 0)), "leg"),
    (42, "leg"),
    (["SPS"] * 6, "leg[0]"),
    ([("type", "SPS")] * 6, "leg[0]"),
])
def test_leg_table_not_a_table(table, field):
    with pytest.raises(InputError, match="expected a") as exc:
        LegMechanism("bad", table, (0, 0, 0.6, 0, 0, 0))
    assert exc.value.field == field


def test_duplicate_legs_refused_naming_both():
    legs = _ups_legs()
    with pytest.raises(InputError, match=r"leg\[5\] with the same line as leg\[0\]") as exc:
        _ups(legs[:5] + [legs[0]])
    assert exc.value.field == "leg[5]"
    # the same line with another joint type or stroke is the same constraint
    with pytest.raises(InputError, match=r"leg\[3\] .* leg\[1\]"):
        _ups(legs[:3] + [{**legs[1], "type": "SPS", "range": (0.1, 1.0)}] + legs[4:])
    rus = [dict(RUS, base=tuple(0.2 * np.array([np.cos(t), np.sin(t), 0])),
                platform=tuple(0.1 * np.array([np.cos(t), np.sin(t), 0])),
                crank0=(np.cos(t), np.sin(t), 0), crank90=(-np.sin(t), np.cos(t), 0))
           for t in np.linspace(0, 2 * np.pi, 6, endpoint=False)]
    with pytest.raises(InputError, match=r"leg\[4\] with the same joints.* as leg\[2\]"):
        LegsDescription("rus", rus[:4] + [dict(rus[2], branch=1), rus[5]], (0, 0, 0.2, 0, 0, 0))
    # the other branch of the same crank is another constraint (another row of J)
    LegsDescription("rus", rus[:4] + [dict(rus[2], branch=-rus[2].get("branch", 1)),
                                      rus[5]], (0, 0, 0.2, 0, 0, 0))


def test_shape_messages_say_n():
    m = _ups()
    for call, field in [(lambda: m.inverse_kinematics(np.zeros((3, 5))), "poses"),
                        (lambda: m.jacobian(np.zeros((2, 3, 6))), "poses"),
                        (lambda: m.forward_kinematics(np.zeros(5)), "q"),
                        (lambda: m.forward_kinematics(np.full(6, 0.6), np.zeros(5)), "guess")]:
        with pytest.raises(InputError, match=r"expected shape \(6,\) or \(N, 6\)") as exc:
            call()
        assert exc.value.field == field and "None" not in str(exc.value)


def test_fk_guess_as_4x4_matrix_as_the_ik_takes_it():
    """The guess as a 4x4 matrix (one, or one per q) gives the pose the 6-vector guess
    gives, and the IK at it gives back q (the pose given to the IK)."""
    m = preset("hunt")
    x = m.home + np.array([0.004, -0.003, 0.002, 0.03, -0.02, 0.05])
    q, _ = m.inverse_kinematics(pose_to_matrix(x))
    r4 = m.forward_kinematics(q, pose_to_matrix(m.home))
    r6 = m.forward_kinematics(q, m.home)
    assert r4.ok and np.array_equal(r4.pose, r6.pose)
    np.testing.assert_allclose(r4.pose, x, atol=1e-12)
    rb = m.forward_kinematics(np.stack([q, q]), pose_to_matrix(np.stack([m.home, x])))
    assert rb.ok.all()
    np.testing.assert_allclose(rb.pose, [x, x], atol=1e-12)
    prec = m.forward_kinematics(q, pose_to_matrix(m.home), method="precise")
    np.testing.assert_allclose(prec.pose, x, atol=1e-12)


def test_dps_only_with_precise_bits_only_with_certified():
    from distkin.mechanisms.forward_tiers import forward_tier
    from distkin.mechanisms.kinematics_tiers import ik_tier, jacobian_tier
    m = preset("hunt")
    q, _ = m.inverse_kinematics(m.home)
    for method in ("fast", "certified"):
        for call in (lambda: m.inverse_kinematics(m.home, method=method, dps=50),
                     lambda: m.jacobian(m.home, method=method, dps=50),
                     lambda: m.jq_jx(m.home, method=method, dps=50),
                     lambda: m.forward_kinematics(q, method=method, dps=50),
                     # the tier functions themselves, not only the methods above
                     lambda: ik_tier(m, m.home, method, dps=50),
                     lambda: jacobian_tier(m, m.home, method, dps=50),
                     lambda: forward_tier(m, q, method=method, dps=50)):
            with pytest.raises(InputError, match="'dps' only with method 'precise'") as exc:
                call()
            assert exc.value.field == "dps" and repr(method) in str(exc.value)
    with pytest.raises(InputError, match="'bits' with method 'certified'") as exc:
        m.forward_kinematics(q, bits=100)
    assert exc.value.field == "bits"
    with pytest.raises(InputError, match="integer 5..1233") as exc:
        m.inverse_kinematics(m.home, method="precise", dps=True)
    assert exc.value.field == "dps"
    # with the precise tier dps is its digits: the 50-digit IK agrees with the 30-digit
    # one to the 30-digit one's own accuracy
    q50 = m.inverse_kinematics(m.home, method="precise", dps=50)[0]
    q30 = m.inverse_kinematics(m.home, method="precise")[0]
    assert max(abs(a - b) for a, b in zip(q50, q30)) < 1e-28
    np.testing.assert_allclose([float(v) for v in q50], q, rtol=0, atol=1e-15)
