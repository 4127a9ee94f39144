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
