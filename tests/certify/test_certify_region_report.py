"""certify_workspace regions and their report (QA): a rotation span above 360° is refused
by name in the scene's unit (±1e12° was accepted, "undecided 3.491e+10 rad"); a region
written in metres in a mm scene, entirely unreachable, is flagged as a likely unit slip;
a single pose has no volume in the JSON either (it said volume_unit "1", volumes 1.0);
the region's ranges are printed with the digits that tell their ends apart (z 300..300.001
mm was printed 300..300)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from distkin.app.queries.certify import certificate_json, certificate_text
from distkin.certify import certify_workspace
from distkin.errors import InputError
from distkin.mechanisms import preset

ROOT = Path(__file__).resolve().parents[2]
HUNT = preset("hunt")
SCENE = """[units]
length = "{length}"
angle = "{angle}"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "certify_workspace"
form = "quadratic"
tighten = 0
region = {{ lower = {lower}, upper = {upper} }}
"""


def _cli(tmp_path, lower, upper, length="mm", angle="deg", *extra):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE.format(length=length, angle=angle, lower=lower, upper=upper))
    env = dict(os.environ, DISTKIN_CACHE=str(tmp_path / "cache"),
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "distkin", "run", str(scene), *extra],
                          capture_output=True, text=True, env=env, timeout=300)


def _result(path):
    return json.loads(Path(path).read_text())["queries"][0]["result"]


@pytest.mark.parametrize("lower, upper, angle, shown", [
    ("[0, 0, 300, -1e12, 0, 0]", "[0, 0, 300, 1e12, 0, 0]", "deg", "got 2e+12 deg"),
    ("[0, 0, 300, 0, 0, -200]", "[0, 0, 300, 0, 0, 200]", "deg", "got 400 deg"),
    ("[0, 0, 300, 0, -3.2, 0]", "[0, 0, 300, 0, 3.2, 0]", "rad", "got 6.4 rad"),
])
def test_rotation_span_over_a_turn_is_refused(tmp_path, lower, upper, angle, shown):
    r = _cli(tmp_path, lower, upper, angle=angle)
    assert r.returncode == 2, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr and "Warning" not in r.stderr
    k = [a != b for a, b in zip(json.loads(lower), json.loads(upper))].index(True)
    assert f"region.upper[{k}]" in lines[0] and "r" + "xyz"[k - 3] in lines[0]
    limit = "360 deg" if angle == "deg" else f"{2 * np.pi:.6g} rad"
    assert f"at most {limit}" in lines[0] and shown in lines[0]


def test_rotation_span_api_refused_and_a_full_turn_accepted():
    with pytest.raises(InputError, match="rx"):
        certify_workspace(HUNT, [0, 0, 0.3, -3.2, 0, 0], [0, 0, 0.3, 3.2, 0, 0], 0.01)
    from distkin.app.scene import loads_scene
    text = SCENE.format(length="mm", angle="deg", lower="[0, 0, 300, -180, 0, 0]",
                        upper="[0, 0, 300, 180, 0, 0]")
    q = loads_scene(text, "full.toml").queries[0]
    assert q.params.upper[3] - q.params.lower[3] == pytest.approx(2 * np.pi)


def test_region_in_metres_in_a_mm_scene_is_flagged(tmp_path):
    r = _cli(tmp_path, "[-0.075, -0.075, 0.225, 0, 0, 0]", "[0.075, 0.075, 0.375, 0, 0, 0]",
             "mm", "deg", "--json", str(tmp_path / "o.json"))
    assert r.returncode == 0, r.stderr
    res = _result(tmp_path / "o.json")
    # every leaf unreachable: the fraction is exactly 1 (it read 0.9999999999999999), as
    # the text's 100.00 %
    assert res["unreachable_fraction"] == 1.0
    assert res["regular_fraction"] == 0.0
    # independent: the region's farthest corner, 0.39 mm from the base, is under 1/100 of
    # the home height z0 = 300 mm
    far = float(np.linalg.norm([0.075, 0.075, 0.375]))
    assert far < HUNT.z0 * 1e3 / 100
    assert len(res["warnings"]) == 1 and "unit" in res["warnings"][0]
    assert f"{far:.3g} mm" in res["warnings"][0]
    assert f"warning: {res['warnings'][0]}" in r.stdout       # the text says the same
    assert "Warning" not in r.stderr


def test_reachable_or_ordinary_regions_have_no_slip_warning():
    cert = certify_workspace(HUNT, [-0.075, -0.075, 0.225, 0, 0, 0],
                             [0.075, 0.075, 0.375, 0, 0, 0], 0.075, tighten=0)
    assert certificate_json(cert, "mm")["warnings"] == []
    # unreachable but at the mechanism's scale (far above it): not a unit slip
    far = certify_workspace(HUNT, [0, 0, 2.0, 0, 0, 0], [0.01, 0.01, 2.01, 0, 0, 0], 0.01,
                            tighten=0)
    assert np.all(far.status == 3)
    assert certificate_json(far, "mm")["warnings"] == []
    assert "warning" not in certificate_text(far, "mm", "deg")


def test_single_pose_json_has_no_volume_and_agrees_with_the_text():
    pose = [0, 0, 0.3, 0, 0, 0]
    cert = certify_workspace(HUNT, pose, pose, 0.01, tighten=0)
    js = certificate_json(cert, "mm")
    assert js["single_pose"] is True and js["verdict"] == "regular"
    for key in ("volume_unit", "total_volume", "regular_volume", "regular_fraction",
                "unreachable_volume", "singular_fraction"):
        assert js[key] is None, key
    assert js["undecided_budget"]["volume"] is None
    text = certificate_text(cert, "mm", "deg")
    assert f"no volume): {js['verdict']}" in text
    # independent: the fast tier at the pose, reachable and away from det Jx = 0
    _, jx = HUNT.jq_jx(np.array([pose]))
    assert abs(np.linalg.det(jx[0])) > 1e-6
    json.dumps(js["verdict"])
    region = certificate_json(certify_workspace(HUNT, pose, [0.01, 0, 0.3, 0, 0, 0], 0.01,
                                                tighten=0))
    assert region["single_pose"] is False and region["verdict"] is None
    assert region["total_volume"] == pytest.approx(0.01)


def test_region_range_shows_its_digits():
    lo, hi = [0, 0, 0.3, 0, 0, 0], [1e-6, 0, 0.300001, 0, 0, 0]
    cert = certify_workspace(HUNT, lo, hi, 1e-6, tighten=0)
    text = certificate_text(cert, "mm", "deg")
    assert "z 300..300.001 mm" in text and "x 0..0.001 mm" in text
    assert "y 0..0 mm" in text and "rx 0..0°" in text
