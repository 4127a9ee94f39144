"""A certified workspace of a device with joint ranges (QA Q 2): the certificate proves
reach and regularity only, so it must say that joint ranges are not part of it; the
reference is the inverse kinematics' own reachability, which applies the ranges, at
the centre of a box the certificate calls regular."""

import json
from pathlib import Path

import numpy as np

from distkin.app.cli import main
from distkin.app.scene import load_scene

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_a_certificate_says_joint_ranges_are_not_part_of_it(tmp_path, capsys):
    text = (EXAMPLES / "rus8_device.toml").read_text(encoding="utf-8")
    narrow = text.replace("range = [-90, 90]", "range = [-1, 1]")
    assert narrow != text
    scene = tmp_path / "narrow.toml"
    scene.write_text(narrow, encoding="utf-8")
    code = main(["run", str(scene), "--json", str(tmp_path / "r.json")])
    out = capsys.readouterr().out
    assert code == 0 and "joint ranges (a leg's `range`) are not part of this" in out
    doc = json.loads((tmp_path / "r.json").read_text())
    cert = next(r["result"] for r in doc["queries"] if r["type"] == "certify_workspace")
    assert "not part of this certificate" in cert["joint_ranges"]
    boxes = cert["boxes"]
    regular = np.flatnonzero(np.array(boxes["status"]) == 1)
    assert regular.size
    mech = load_scene(scene).mechanism
    centres = (np.array(boxes["lower"])[regular] + np.array(boxes["upper"])[regular]) / 2
    assert not np.all(mech.reachable(centres))      # the ranges exclude some of them


def test_poses_excluded_by_the_ranges_alone_name_the_ranges(tmp_path, capsys):
    """QA Q 5: an IK where every leg closes but every angle is outside its range was
    told to check its units; the reach margins (all > 0: a second route, the IK
    equation's own discriminant) show that the legs close."""
    text = (EXAMPLES / "rus8_device.toml").read_text(encoding="utf-8")
    i = text.index("[[query]]")
    scene = tmp_path / "r.toml"
    scene.write_text(text[:i].replace("range = [-90, 90]", "range = [20, 30]")
                     + '[[query]]\ntype = "inverse_kinematics"\n'
                       'poses = [[0, 0, 200, 0, 0, 0]]\n', encoding="utf-8")
    mech = load_scene(scene).mechanism
    assert np.all(mech.reach_margin(np.array([0, 0, 0.2, 0, 0, 0])) > 0)
    assert main(["run", str(scene)]) == 0
    out = capsys.readouterr().out
    assert "outside the legs' joint ranges" in out and "units" not in out.split("note:")[1]
