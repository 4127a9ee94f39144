"""The forward_kinematics query refuses joint values outside their legs' declared
ranges in every tier (QA: `distkin run` on the 6-UPS example with every leg at 600 mm,
stroke [350, 550] mm, printed "verified (fast tier): yes", and a proved box with
method = "certified").  References: the ranges as the scene declares them (in its
units), the inverse_kinematics query of the same scene at the pose (its "NOT reachable"
verdict), and, for legs in range, the Python API's answer (a second route)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.app.scene import load_scene

ROOT = Path(__file__).resolve().parents[2]


def _gough(queries: str) -> str:
    text = (ROOT / "examples" / "gough_stewart_6ups.toml").read_text()
    return text[:text.index("[[query]]")] + queries


def _rus8(queries: str) -> str:
    text = (ROOT / "examples" / "rus8_device.toml").read_text()
    return text[:text.index("[[query]]")] + queries


def _run_json(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text)
    out = tmp_path / "out.json"
    code = main(["run", str(f), "--json", str(out)])
    capsys.readouterr()
    return code, json.loads(out.read_text())["queries"]


@pytest.mark.parametrize("method", ["fast", "precise", "certified"])
def test_legs_beyond_the_stroke_refused_in_every_tier(tmp_path, capsys, method):
    code, qs = _run_json(tmp_path, capsys, _gough(f"""
[[query]]
type = "forward_kinematics"
angles = [600, 600, 600, 600, 600, 600]
method = "{method}"
[[query]]
type = "inverse_kinematics"
poses = [[0, 0, 562.534, 0, 0, 0]]
"""))
    assert code == 2
    fk, ik = qs
    assert ik["status"] == "ok" and not any(ik["result"]["poses"][0]["valid"])   # reference
    assert fk["status"] == "error" and fk["error"]["kind"] == "infeasible"
    msg = fk["error"]["message"]
    assert msg.startswith("query[0].angles[0]: ")
    assert "leg 1's length 600 mm outside its range [350, 550] mm (50 mm beyond it)" in msg
    assert "legs [2, 3, 4, 5, 6] outside theirs" in msg
    assert "verified" not in msg and fk["result"] == {}


def test_one_leg_beyond_the_stroke_named_in_scene_units(tmp_path, capsys):
    """Legs at the IK of (0, 0, 500) mm tilted 0.1 rad about x: legs 2 and 3 are
    552.3 and 555.0 mm."""
    mech = load_scene(ROOT / "examples" / "gough_stewart_6ups.toml").mechanism
    q, valid = mech.inverse_kinematics([0, 0, 0.5, 0.1, 0, 0])
    assert list(np.flatnonzero(~valid) + 1) == [2, 3]
    angles = ", ".join(f'"{float(v) * 1e3!r}"' for v in q)
    code, qs = _run_json(tmp_path, capsys, _gough(f"""
[[query]]
type = "forward_kinematics"
angles = [{angles}]
guess = [0, 0, 502, 5.7, 0, 0]
method = "certified"
"""))
    assert code == 2
    msg = qs[0]["error"]["message"]
    assert msg.startswith("query[0].angles[1]: ")
    assert "leg 2's length 552.3" in msg and "and legs [3] outside theirs" in msg


def test_rus8_crank_past_its_range_refused_in_degrees(tmp_path, capsys):
    mech = load_scene(ROOT / "examples" / "rus8_device.toml").mechanism
    pose = np.array([-0.0752094905463263, -0.014851539390435639, 0.22072957273270563,
                     0.2542062123180612, -0.051596236854160815, 0.14473940130738627])
    q, valid = mech.inverse_kinematics(pose)
    assert list(np.flatnonzero(~valid) + 1) == [2]             # the IK's verdict
    angles = ", ".join(f'"{float(v)!r}"' for v in np.degrees(q))
    guess = ", ".join(f'"{float(v)!r}"' for v in np.concatenate([pose[:3] * 1e3 + 1,
                                                         np.degrees(pose[3:])]))
    code, qs = _run_json(tmp_path, capsys, _rus8(f"""
[[query]]
type = "forward_kinematics"
angles = [{angles}]
guess = [{guess}]
method = "certified"
"""))
    assert code == 2
    msg = qs[0]["error"]["message"]
    assert msg.startswith("query[0].angles[1]: ")
    assert "leg 2's angle 91.98" in msg and "outside its range [-90, 90] deg" in msg


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_in_range_answer_unchanged_and_flagged_in_range(tmp_path, capsys, method):
    mech = load_scene(ROOT / "examples" / "gough_stewart_6ups.toml").mechanism
    pose = np.array([0.01, 0.005, 0.41, 0.05, -0.05, 0.08])
    q, valid = mech.inverse_kinematics(pose)
    assert valid.all()
    angles = ", ".join(f'"{float(v) * 1e3!r}"' for v in q)
    code, qs = _run_json(tmp_path, capsys, _gough(f"""
[[query]]
type = "forward_kinematics"
angles = [{angles}]
method = "{method}"
"""))
    assert code == 0
    res = qs[0]["result"]
    assert res["in_range"] is True and res["verified"] is True and res["round_trip"] is True
    api = mech.forward_kinematics(np.array(res["angles"]), mech.home)
    if method == "fast":
        assert res["pose"] == api.pose.tolist()                # bit for bit
    else:
        assert res["certified"] is True
        assert np.all(np.abs(np.array(res["pose"]) - pose) <= np.array(res["pose_error"])
                      + 1e-15)


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_a_stroke_end_written_in_the_scenes_unit_is_in_range(tmp_path, capsys, method):
    """Review 2026-11-29: 563 mm against a stroke end of 563 mm was refused "1.11e-13 mm
    beyond it" (the range read exactly, the angles as 563 * 0.001, one ulp above).  The
    ends are in the range (README); reference: 563 * 0.001 > 563/1000 in float64."""
    from fractions import Fraction
    assert 563 * 0.001 > float(Fraction(563, 1000))            # (premise: the product's ulp)
    text = _gough(f"""
[[query]]
type = "forward_kinematics"
angles = [563, 540, 540, 540, 540, 540]
guess = [0, 0, 520, 0, 0, 0]
method = "{method}"
""").replace("range = [350, 550]", "range = [350, 563]")
    code, qs = _run_json(tmp_path, capsys, text)
    assert code == 0 and qs[0]["status"] == "ok", qs[0].get("error")
    assert qs[0]["result"]["in_range"] and qs[0]["result"]["verified"]
