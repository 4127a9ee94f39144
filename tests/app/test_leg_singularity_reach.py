"""The ``singularity`` query on ``kind = "rss"`` and ``kind = "legs"`` gives no verdict
at a pose the device cannot take (QA: "det J certified < 0, singular: no" 3 m above the
Hunt preset, a crossing at 1.48 m where no leg closes, a 6-UPS beyond its strokes).

References, independent of the query: the ``inverse_kinematics`` query of the same scene
(its ``reachable`` and ``valid`` flags), the mechanism's own IK and reach margins, and
the leg lengths |P - B| recomputed here with numpy from the leg table."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import main

ROOT = Path(__file__).resolve().parents[2]
HUNT = '[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "rss"\npreset = "hunt"\n'


def _run(tmp_path, capsys, text):
    """(the JSON's query results, the report's text) of scene ``text``."""
    f = tmp_path / "s.toml"
    f.write_text(text, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "o.json")])
    out, err = capsys.readouterr()
    assert code == 0, err
    return [q["result"] for q in json.loads((tmp_path / "o.json").read_text())["queries"]], out


def _gough_table():
    """The 6-UPS example's mechanism block (strokes 350-550 mm), without its queries."""
    text = (ROOT / "examples" / "gough_stewart_6ups.toml").read_text(encoding="utf-8")
    return text[:text.index("[[query]]")]


def test_unreachable_pose_of_the_hunt_preset_gets_no_certificate(tmp_path, capsys):
    """3 m above the Hunt preset no leg closes (the IK query says so): no det J, no
    certified sign, no "singular: no"."""
    (sing, ik), out = _run(tmp_path, capsys, HUNT
                           + '[[query]]\ntype = "singularity"\npose = [0, 0, 3000, 0, 0, 0]\n'
                             'method = "certified"\n[[query]]\ntype = "inverse_kinematics"\n'
                             'pose = [0, 0, 3000, 0, 0, 0]\nmethod = "certified"\n')
    ref = ik["poses"][0]
    assert ref["reachable"] is False
    row = sing["poses"][0]
    block = out[:out.index("[1] inverse_kinematics")]
    assert "singular: no" not in block and "certified <" not in block
    assert row["singular"] is None and row["det_J"] is None and row["sigma_min"] is None
    assert row["det_sign_certified"] is None
    assert row["reachable"] is False
    assert row["unreachable_legs"] == [j + 1 for j, ok in enumerate(ref["valid"]) if not ok]
    assert row["unreachable_legs"] == [1, 2, 3, 4, 5, 6] and row["out_of_range_legs"] == []
    assert "certified >" not in block and "NOT reachable (legs [1, 2, 3, 4, 5, 6])" in block
    assert "no arb certificate" in row["verdict"]


def test_path_into_the_unreachable_region_reports_no_crossing_there(tmp_path, capsys):
    """z 300 -> 1500 mm on the Hunt preset: the legs stop closing near 0.5 m.  The
    unreachable samples are the runs where the mechanism's IK says a leg does not close,
    and every crossing reported is a reachable pose (it was one at z = 1484.94 mm)."""
    from distkin.mechanisms import preset
    (sing,), out = _run(tmp_path, capsys, HUNT
                        + '[[query]]\ntype = "singularity"\npath = { from = [0, 0, 300, 0, 0, 0], '
                          'to = [0, 0, 1500, 0, 0, 90], samples = 60 }\nmethod = "certified"\n')
    mech = preset("hunt")
    a = np.array([0, 0, 0.3, 0, 0, 0])
    b = np.array([0, 0, 1.5, 0, 0, np.pi / 2])
    X = a + np.linspace(0, 1, 60)[:, None] * (b - a)
    ok = np.all(mech.inverse_kinematics(X)[1], axis=1)
    assert ok[0] and not ok[-1]
    first = int(np.argmin(ok))
    assert ok[:first].all() and not ok[first:].any()         # one exit, no return
    for c in sing["crossings"]:
        assert np.all(mech.inverse_kinematics(np.array(c["pose"]))[1])
        assert c["pose"][2] < X[first, 2]
    assert "1484.94" not in out
    assert [r["reachable"] for r in sing["poses"]] == ok.tolist()
    assert [p["samples"] for p in sing["unreachable_parts"]] == [[first, 59]]
    assert sing["unreachable_parts"][0]["unreachable_legs"] == [1, 2, 3, 4, 5, 6]
    assert f"not reachable: samples {first}-59 of 0-59" in out


def test_gough_beyond_its_stroke_is_not_certified_regular(tmp_path, capsys):
    """The 6-UPS example 2 m up: every leg |P - B| (numpy, from the table) is beyond its
    550 mm stroke, so no verdict; legs named as outside their stroke."""
    (sing, ik), out = _run(tmp_path, capsys, _gough_table()
                           + '[[query]]\ntype = "singularity"\npose = [0, 0, 2000, 0, 0, 0]\n'
                             'method = "certified"\n[[query]]\ntype = "inverse_kinematics"\n'
                             'pose = [0, 0, 2000, 0, 0, 0]\n')
    base = np.array([[295.442326, -52.094453], [295.442326, 52.094453],
                     [-102.606043, 281.907786], [-192.836283, 229.813333],
                     [-192.836283, -229.813333], [-102.606043, -281.907786]])
    plat = np.array([[96.418141, -114.906666], [96.418141, 114.906666],
                     [51.303021, 140.953893], [-147.721163, 26.047227],
                     [-147.721163, -26.047227], [51.303021, -140.953893]])
    length = np.hypot(np.linalg.norm(plat - base, axis=1), 2000.0)
    outside = [j + 1 for j, v in enumerate(length) if not 350 <= v <= 550]
    assert outside == [1, 2, 3, 4, 5, 6]
    assert ik["poses"][0]["reachable"] is False
    row = sing["poses"][0]
    block = out[:out.index("[1] inverse_kinematics")]
    assert "singular: no" not in block and "certified <" not in block
    assert row["singular"] is None and row["det_J"] is None
    assert row["reachable"] is False and row["out_of_range_legs"] == outside
    assert row["unreachable_legs"] == outside
    assert "outside their declared joint range or stroke: legs [1, 2, 3, 4, 5, 6]" in block


def test_revolute_leg_closing_outside_its_range(tmp_path, capsys):
    """The 8-RUS example with every range narrowed to [30, 90] deg: at home each leg
    closes (the IK query's reach margin >= 0) at an angle below 30 deg (its q), so the
    pose is out of range, and σmin (L = 8) gets no verdict."""
    text = (ROOT / "examples" / "rus8_device.toml").read_text(encoding="utf-8")
    table = text[:text.index("[[query]]")].replace("range = [-90, 90]", "range = [30, 90]")
    (sing, ik), out = _run(tmp_path, capsys, table
                           + '[[query]]\ntype = "singularity"\npose = [0, 0, 200, 0, 0, 0]\n'
                             '[[query]]\ntype = "inverse_kinematics"\n'
                             'pose = [0, 0, 200, 0, 0, 0]\n')
    ref = ik["poses"][0]
    assert np.all(np.array(ref["reach_margin"]) >= 0)
    assert np.all(np.degrees(ref["q"]) < 30) and not any(ref["valid"])
    row = sing["poses"][0]
    assert "singular: no" not in out and "singular: undefined" in out
    assert row["singular"] is None and row["sigma_min"] is None
    assert row["reachable"] is False
    assert row["out_of_range_legs"] == row["unreachable_legs"] == list(range(1, 9))


@pytest.mark.parametrize("pose", [[0, 0, 300, 0, 0, 0], [20, -10, 320, 10, 0, 5]])
def test_reachable_pose_keeps_its_certified_verdict(tmp_path, capsys, pose):
    """A reachable pose of the Hunt preset (the IK query says so) keeps its verdict
    word for word, and det J and its certified sign equal numpy's det of the normalised
    lines D -> P of the mechanism's own joint positions."""
    from distkin.mechanisms import preset
    (sing, ik), out = _run(tmp_path, capsys, HUNT
                           + f'[[query]]\ntype = "singularity"\npose = {pose}\n'
                             f'method = "certified"\n[[query]]\ntype = "inverse_kinematics"\n'
                             f'pose = {pose}\n')
    assert ik["poses"][0]["reachable"] is True
    row = sing["poses"][0]
    assert row["reachable"] is True and row["unreachable_legs"] == []
    mech = preset("hunt")
    x = np.array(pose, dtype=float) * ([1e-3] * 3 + [np.pi / 180] * 3)
    pts = mech.points(x)
    u = pts["P"] - pts["D"]
    u /= np.linalg.norm(u, axis=1)[:, None]
    ref = np.linalg.det(np.hstack([u, np.cross(pts["D"] - x[:3], u) / mech.length_scale]))
    assert abs(ref) > 1e-3 and row["det_J"] == pytest.approx(ref, rel=1e-9)
    assert row["det_sign_certified"] == int(np.sign(ref)) and row["singular"] is False
    word = {1: "> 0", -1: "< 0"}[int(np.sign(ref))]
    assert row["verdict"] == (f"at the float64-rounded pose: det J certified {word}, "
                              "singular: no (arb certificate of sign det J)")
    assert "NOT reachable" not in out[:out.index("[1] inverse_kinematics")]


def test_poses_either_side_of_the_reach_top_read_apart(tmp_path, capsys):
    """Review 2026-11-29: two poses 40 nm apart either side of the Hunt preset's reach top
    (bisection on the mechanism's own ``reachable``), one NOT reachable, both read
    "(0, 0, 497.329) mm" in the singularity query (6 digits); they now read as the scene
    wrote them, as in the inverse_kinematics query."""
    from distkin.mechanisms import preset
    m = preset("hunt")
    lo, hi = 0.3, 1.5
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if m.reachable(np.array([0, 0, mid, 0, 0, 0])) else (lo, mid)
    zs = [round(lo * 1e3 - 2e-5, 7), round(lo * 1e3 + 2e-5, 7)]              # mm
    assert f"{zs[0]:.6g}" == f"{zs[1]:.6g}"                    # (premise: alike to 6 digits)
    poses = f"[[0, 0, {zs[0]!r}, 0, 0, 0], [0, 0, {zs[1]!r}, 0, 0, 0]]"
    (sing, ik), out = _run(tmp_path, capsys, HUNT + f'[[query]]\ntype = "singularity"\n'
                           f'poses = {poses}\n[[query]]\ntype = "inverse_kinematics"\n'
                           f'poses = {poses}\n')
    assert [r["reachable"] for r in sing["poses"]] == [r["reachable"] for r in ik["poses"]] \
        == [True, False]
    block = out[:out.index("[1] inverse_kinematics")]
    for i, z in enumerate(zs):
        assert f"pose {i}: (0, 0, {z!r}) mm, (0, 0, 0) deg" in block
