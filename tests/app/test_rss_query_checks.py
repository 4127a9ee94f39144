"""The checks of the mechanisms' tiers as the ``jacobian`` and ``forward_kinematics``
scene queries report them (distkin.app.queries.mechanisms): the fast Jacobian's
``inaccurate`` flag and ``inf`` errors next to a leg's reach boundary (the serial
singularity of an RSS leg, Jq_ii -> 0; distkin.mechanisms.kinematics_tiers), and the
forward kinematics' verification (the closed-form IK at the returned pose must give back
the angles; distkin.mechanisms.forward)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import run_scene
from distkin.app.report import document, dumps
from distkin.app.scene import load_scene, loads_scene
from distkin.errors import ConditioningWarning
from distkin.mechanisms import preset
from distkin.mechanisms.kinematics_tiers import jacobian_tier

ROOT = Path(__file__).resolve().parents[2]

SCENE = """
[units]
length = "{length}"
angle = "{angle}"

[mechanism]
kind = "rss"
preset = "octopod"

[[query]]
{query}
"""


def _run(query, length="m", angle="rad"):
    s = loads_scene(SCENE.format(length=length, angle=angle, query=query))
    return run_scene(s, progress=False)


def _last_inside(mech, start):
    """start + (0, 0, z, 0, 0, 0) with z the last float for which every leg closes
    (bisection on the reach kernel)."""
    reach = mech.kernels("batched").reach
    lo, hi = 0.0, 0.5
    while (lo + hi) / 2 not in (lo, hi):
        mid = (lo + hi) / 2
        ok = reach((start + [0, 0, mid, 0, 0, 0])[None]).min() >= 0
        lo, hi = (mid, hi) if ok else (lo, mid)
    return start + [0, 0, lo, 0, 0, 0]


def _toml(poses):
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in p) + "]"
                           for p in poses) + "]"


def _no_nan(text):
    assert not re.search(r"\bnan\b", text, flags=re.IGNORECASE), text


@pytest.mark.filterwarnings("error::distkin.errors.ConditioningWarning")
def test_jacobian_at_the_reach_boundary_is_flagged_not_nan():
    """At the last float inside the octopod's reach along z every leg's estimate is inf
    (first order fails); the pose is flagged, the text says "not resolved" instead of a
    number (it used to print no figure, or the largest finite one), the JSON carries
    ``inaccurate`` and "inf" as strict JSON; the interior pose is not flagged.  The
    query says it in its report: the tier's warning does not escape it."""
    mech = preset("octopod")
    edge = _last_inside(mech, np.array([0, 0, 0.3, 0, 0, 0.0]))
    X = np.array([edge, [0, 0, 0.3, 0, 0, 0]])
    records, texts, worst = _run(f'type = "jacobian"\nposes = {_toml(X)}')
    assert worst == 0 and records[0]["status"] == "ok", records
    rows = records[0]["result"]["poses"]
    np.testing.assert_array_equal(np.array([r["pose"] for r in rows]), X)
    assert [r["inaccurate"] for r in rows] == [True, False]
    with pytest.warns(ConditioningWarning, match="reach boundary"):
        tier = jacobian_tier(mech, X, "fast")
    assert np.isinf(tier.J_error[0]).all() and np.isfinite(tier.J_error[1]).all()
    doc = json.loads(dumps(document("s.toml", records, "0")))     # strict JSON
    err = doc["queries"][0]["result"]["poses"][0]["J_error"]
    assert all(v == "inf" for row in err for v in row)
    assert all(isinstance(v, float) for row in doc["queries"][0]["result"]["poses"][1]
               ["J_error"] for v in row)
    text = texts[0]
    _no_nan(text)
    assert text.count("J not resolved in float64 near the reach boundary") == 1
    assert "legs [1, 2, 3, 4, 5, 6, 7, 8]: inf, first order fails" in text
    assert ('largest error of an entry of J over the valid legs: not resolved in float64 '
            '(use method = "precise")') in text
    assert "4 eps" not in text and "propagated through Jq, Jx and J = Jx/Jq" in text


@pytest.mark.filterwarnings("error::distkin.errors.ConditioningWarning")
def test_jacobian_with_mixed_rows_does_not_understate():
    """Offset by 1 cm in x, legs 5 and 6 reach their boundary first: their rows are inf
    while the others are about 1e-12; the largest error is "not resolved", not the
    largest finite one, and the flag names legs 5 and 6."""
    mech = preset("octopod")
    edge = _last_inside(mech, np.array([0.01, 0, 0.3, 0, 0, 0]))
    with pytest.warns(ConditioningWarning, match="reach boundary"):
        tier = jacobian_tier(mech, edge[None], "fast")
    inf_rows = np.isinf(tier.J_error[0]).any(-1)
    assert list(np.flatnonzero(inf_rows) + 1) == [5, 6]
    assert tier.J_error[0][~inf_rows].max() < 1e-9 and tier.valid.all()
    records, texts, worst = _run(f'type = "jacobian"\npose = {_toml([edge])[1:-1]}')
    assert worst == 0 and records[0]["result"]["poses"][0]["inaccurate"] is True
    text = texts[0]
    _no_nan(text)
    assert "legs [5, 6]: inf, first order fails" in text
    assert 'over the valid legs: not resolved in float64 (use method = "precise")' in text


def test_jacobian_precise_at_the_boundary_is_not_flagged():
    mech = preset("octopod")
    edge = _last_inside(mech, np.array([0, 0, 0.3, 0, 0, 0.0]))
    records, texts, worst = _run(f'type = "jacobian"\npose = {_toml([edge])[1:-1]}\n'
                                 'method = "precise"')
    assert worst == 0 and records[0]["result"]["poses"][0]["inaccurate"] is False
    assert "not resolved" not in texts[0]
    _no_nan(texts[0])


@pytest.mark.parametrize("method", ["fast", "precise"])
def test_fk_of_angles_no_pose_gives_back_is_an_error_naming_angles(method):
    """All eight cranks at 200 deg: Gauss-Newton from home converges (residual ~1e-17 m)
    to z = 0.292 m, where the IK gives 16.7 deg, not 200 deg (the other crank branch):
    a not_found record naming the scene's field (no guess given: angles, from the default
    start), exit code 2 as other query errors."""
    records, texts, worst = _run('type = "forward_kinematics"\nangles = [200, 200, 200, '
                                 f'200, 200, 200, 200, 200]\nmethod = "{method}"',
                                 length="mm", angle="deg")
    assert worst == 2 and records[0]["status"] == "error", records
    assert records[0]["error"]["kind"] == "not_found"
    assert records[0]["error"]["message"].startswith("query[0].angles: expected a pose "
                                                     "whose inverse kinematics gives back")


def test_fk_of_consistent_angles_is_verified():
    """Angles from the closed-form IK of a pose: verified, the round trip within a few
    eps, the pose back to about 1e-15 m."""
    mech = preset("octopod")
    pose = np.array([0.02, -0.01, 0.31, 0.1, 0.0, -0.05])
    q, valid = mech.inverse_kinematics(pose)
    assert valid.all()
    records, texts, worst = _run('type = "forward_kinematics"\nangles = '
                                 f'{_toml([q])[1:-1]}')
    assert worst == 0, records
    r = records[0]["result"]
    assert r["verified"] is True and r["round_trip"] is True
    assert 0 <= r["q_mismatch"] < 1e-12 and r["residual"] <= r["residual_tol"]
    assert r["residual_tol"] == pytest.approx(1024 * np.finfo(float).eps * mech.l3)
    np.testing.assert_allclose(r["pose"], pose, atol=1e-12)
    assert r["unit"]["q_mismatch"].startswith("rad") and r["unit"]["residual_tol"] == "m"
    assert ("verified (fast tier): yes: round trip ok (the inverse kinematics at the pose "
            "gives back the angles)") in texts[0]


def test_fk_of_rounded_octopod_angles_is_their_least_squares_pose():
    """The example's angles (an IK rounded to 0.01 deg; L = 8, so inconsistent): the
    round trip holds (within 0.005 deg, the rounding); with the example's
    ``residual_tol = 0.01`` mm the answer is verified, and without it (the default,
    1024 eps times a leg) the residual is far above residual_tol, so not verified, and
    the text says why, in the scene's units."""
    from distkin.app.scene import loads_scene
    text = (ROOT / "examples" / "rss_octopod.toml").read_text()
    s = load_scene(ROOT / "examples" / "rss_octopod.toml")
    records, texts, worst = run_scene(s, progress=False)
    assert worst == 0
    r = records[2]["result"]
    assert r["round_trip"] is True and r["verified"] is True
    assert r["residual"] <= r["residual_tol"] == pytest.approx(1e-5)
    assert "verified (fast tier): yes" in texts[2]
    strict = "\n".join(line for line in text.splitlines()
                       if not line.startswith("residual_tol"))
    with pytest.warns(ConditioningWarning, match="inconsistent"):  # the certified query
        records, texts, worst = run_scene(loads_scene(strict), progress=False)
    r = records[2]["result"]
    assert r["round_trip"] is True and r["verified"] is False
    assert r["residual"] > r["residual_tol"]
    assert r["q_mismatch"] <= math.radians(0.005)
    m = re.search(r"verified \(fast tier\): no: round trip ok .*largest \|IK\(pose\) - "
                  r"angle\| ([0-9.e+-]+) deg; rms closure residual ([0-9.e+-]+) mm ABOVE "
                  r"residual_tol ([0-9.e+-]+) mm", texts[2])
    assert m, texts[2]
    assert float(m[1]) == pytest.approx(math.degrees(r["q_mismatch"]), rel=5e-3)
    assert float(m[2]) == pytest.approx(1e3 * r["residual"], rel=5e-3)
    assert float(m[3]) == pytest.approx(1e3 * r["residual_tol"], rel=5e-3)


def test_fk_mismatch_of_a_mixed_leg_table_in_both_units():
    """Two of the octopod's legs replaced by prismatic ones: the round trip's mismatch is
    stated per kind of joint, deg for the cranks and mm for the prismatic legs, and
    matches FKResult.q_mismatch (rad or m, the largest of both)."""
    import dataclasses

    from distkin.app.queries.forward_kinematics import _verified_line
    from distkin.mechanisms.kinematics import LegMechanism
    m = preset("octopod")
    legs = [leg.as_dict() for leg in m.leg_description().leg_table]
    for j in (2, 5):
        legs[j] = dict(type="SPS", base=legs[j]["base"], platform=legs[j]["platform"])
    mixed = LegMechanism("mixed", legs, home_pose=tuple(m.home))
    q = mixed.inverse_kinematics(mixed.home + np.array([0.01, -0.02, 0.03, 0.1, 0.05, -0.2]))[0]
    q[0] += 1e-3                                  # a crank 1 mrad off: inconsistent
    with pytest.warns(ConditioningWarning):   # no verified pose: said
        fk = mixed.forward_kinematics(q, mixed.home)
    assert fk.round_trip and not fk.verified
    scene = dataclasses.replace(
        loads_scene(SCENE.format(length="mm", angle="deg",
                                 query='type = "jacobian"\npose = [0, 0, 300, 0, 0, 0]')),
        mechanism=mixed)
    line = _verified_line(fk, q, mixed, scene, "fast")
    m_ = re.search(r"\|IK\(pose\) - joint value\| ([0-9.e+-]+) deg \(cranks\), ([0-9.e+-]+) "
                   r"mm \(prismatic legs\); rms closure residual [0-9.e+-]+ mm ABOVE", line)
    assert m_, line
    assert max(math.radians(float(m_[1])), 1e-3 * float(m_[2])) == pytest.approx(
        fk.q_mismatch, rel=5e-3)


def test_rus8_example_fk_of_angles_rounded_to_1e_6_deg_is_verified():
    """QA X3 D5: the shipped rus8 example printed "verified (fast tier): no" for its own
    angles (rounded to 1e-6 deg, 8 legs: inconsistent in the last digit) under the
    default residual_tol of 1024 eps times a leg.  The example now states the
    tolerance of that rounding: half a unit, 5e-7 deg, moves a 60 mm crank tip by
    60 * 5e-7 * pi / 180 = 5.2e-7 mm <= residual_tol = 1e-6 mm."""
    import dataclasses
    scene = load_scene(ROOT / "examples" / "rus8_device.toml")
    fk = [q for q in scene.queries if q.type == "forward_kinematics"]
    records, texts, worst = run_scene(dataclasses.replace(scene, queries=tuple(fk)),
                                      progress=False)
    r = records[0]["result"]
    assert worst == 0 and r["verified"] is True and r["round_trip"] is True
    assert r["residual_tol"] == pytest.approx(1e-9)                 # m
    assert r["residual"] <= 60e-3 * math.radians(5e-7)
    assert "verified (fast tier): yes: round trip ok" in texts[0]
