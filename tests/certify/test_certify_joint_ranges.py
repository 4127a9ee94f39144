"""A certified workspace of a device with joint ranges (QA Q 2): the certificate proves
reach and regularity only, so it must say that joint ranges are not part of it; the
reference is the inverse kinematics' own reachability, which applies the ranges, at
the centre of a box the certificate calls regular."""

import json
from pathlib import Path

import numpy as np
import pytest

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
    assert code == 0 and "revolute joint ranges (a leg's `range`) are not part of" in out
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


def test_prismatic_strokes_are_part_of_the_certificate(tmp_path, capsys):
    """QA V 7: the note "joint ranges are not part of this certificate" was printed for
    the Gough-Stewart 6-UPS legs too, whose strokes decide the classification (reach
    margin (q - qmin)(qmax - q)).  Reference: the leg lengths |P - B| at the corners of a
    box far out (5 m), all beyond the 550 mm stroke, and the same scene without strokes,
    which certifies the box regular."""
    text = (EXAMPLES / "gough_stewart_6ups.toml").read_text(encoding="utf-8")
    head = text[:text.index("[[query]]")]
    query = ('[[query]]\ntype = "certify_workspace"\nregion = { lower = [5000, 5000, 5000, '
             '0, 0, 0], upper = [5100, 5100, 5100, 0, 0, 0] }\n')
    results = {}
    for name, body in (("strokes", head), ("free", head.replace("range = [350, 550]\n", ""))):
        scene = tmp_path / f"{name}.toml"
        scene.write_text(body + query, encoding="utf-8")
        assert main(["run", str(scene), "--json", str(tmp_path / f"{name}.json")]) == 0
        out = capsys.readouterr().out
        results[name] = (json.loads((tmp_path / f"{name}.json").read_text())
                         ["queries"][0]["result"], out)
    cert, out = results["strokes"]
    mech = load_scene(tmp_path / "strokes.toml").mechanism
    corners = np.array([[x, y, z, 0, 0, 0] for x in (5, 5.1) for y in (5, 5.1)
                        for z in (5, 5.1)])
    q, _ = mech.inverse_kinematics(corners)
    assert np.all(q > 0.55)                               # beyond every stroke
    # every leaf unreachable (the volumes are the leaves' sum and the ranges' product:
    # equal up to rounding; the fraction, of the leaves' own sum, is exactly 1)
    assert cert["unreachable_fraction"] == 1.0
    assert cert["unreachable_volume"] == pytest.approx(cert["total_volume"], rel=1e-12)
    assert "not part of" not in out and "prismatic strokes (a leg's `range`) are part " \
        "of this certificate" in out
    assert cert["joint_ranges"].startswith("prismatic strokes")
    free, out = results["free"]
    assert free["regular_fraction"] == 1.0 and "joint_ranges" not in free
