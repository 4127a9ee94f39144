"""What the reports print and the JSON says about units (QA round 2): κ of eq. (4) is the
scaled Jacobian's, as :func:`distkin.indices.condition_number` computes it; no
placeholder (``nan``, ``1 1``) where a number has no meaning; and every kinematics
query's JSON has a ``unit`` block, the octahedral ones included."""

from __future__ import annotations

import json

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.indices import condition_number
from distkin.mechanisms import preset

MM = '[units]\nlength = "mm"\nangle = "deg"\n'
RSS = MM + '[mechanism]\nkind = "rss"\npreset = "octopod"\n'
OCTA = ('[mechanism]\nkind = "octahedral"\nbase = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]'
        '\nplatform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n')
LEGS = '["19.8", "18", "18", "17", "14.9", "17.8"]'


def _run(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "out.json")])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads((tmp_path / "out.json").read_text())["queries"], out


def test_jacobian_kappa_is_eq_4_of_the_scaled_jacobian(tmp_path, capsys):
    """It printed 0.00668 = σmin/σmax of the unscaled J as 'kappa (eq. (4))', where
    condition_number gives 0.0711 (Kühne et al. eq. (4) with Stocco's scaling ST)."""
    queries, out = _run(tmp_path, capsys, RSS + '[[query]]\ntype = "jacobian"\n'
                        'pose = [40, -30, 330, 15, -10, 20]\nmass_matrix = true\n')
    pose = np.array([0.040, -0.030, 0.330, *np.radians([15, -10, 20])])
    want = float(condition_number(preset("octopod").jacobian(pose)))
    assert want == pytest.approx(0.0711, abs=5e-5)
    row = queries[0]["result"]["poses"][0]
    assert row["kappa"] == pytest.approx(want, rel=1e-12)
    sv = np.linalg.svd(np.array(row["J"]), compute_uv=False)
    assert row["kappa_unscaled"] == pytest.approx(sv[-1] / sv[0], rel=1e-12)
    assert row["kappa_unscaled"] == pytest.approx(0.00668, abs=5e-6)
    assert f"kappa = {want:.6g} (eq. (4): sigma_min/sigma_max of the scaled ST⁻¹Jᵀ" in out
    unscaled = next(line for line in out.splitlines() if "unscaled J" in line)
    assert f"{row['kappa_unscaled']:.6g} (unscaled)" in unscaled and "eq. (4)" not in unscaled


def test_jacobian_json_has_a_unit_block(tmp_path, capsys):
    queries, _ = _run(tmp_path, capsys, RSS + '[[query]]\ntype = "jacobian"\n'
                      'pose = [0, 0, 300, 0, 0, 0]\nmass_matrix = true\n'
                      '[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]\n')
    unit = queries[0]["result"]["unit"]
    for key in ("pose", "J", "Jq", "Jx", "kappa", "Mq", "acceleration_map",
                "cartesian_mass_matrix"):
        assert unit[key], key
    assert unit["pose"] == queries[1]["result"]["unit"]["pose"] == "m, rad"   # as IK's
    assert "rad/m" in unit["J"] and "m/rad" in unit["Jq"] and "kg m^2" in unit["Mq"]
    assert "N·m" in unit["acceleration_map"]


def test_no_valid_leg_is_said_not_printed_as_nan(tmp_path, capsys):
    far = "pose = [4000, 0, 300, 0, 0, 0]"
    _, out = _run(tmp_path, capsys, RSS + f'[[query]]\ntype = "inverse_kinematics"\n{far}\n'
                  f'[[query]]\ntype = "jacobian"\n{far}\n')
    assert "nan" not in out
    assert out.count("over the valid legs: no valid leg") == 2


def test_certified_single_pose_prints_its_status_not_a_volume(tmp_path, capsys):
    """It printed 'regular 1 1 (100.00 % of 1 1; 1 boxes)'."""
    text = MM + '[mechanism]\nkind = "rss"\npreset = "hunt"\n[[query]]\n' \
        'type = "certify_workspace"\nregion = { lower = [0, 0, 300, 0, 0, 0], ' \
        'upper = [0, 0, 300, 0, 0, 0] }\n'
    queries, out = _run(tmp_path, capsys, text)
    assert "a single pose (no coordinate varies, so no volume): regular" in out
    assert " 1 1 " not in out and "position fixed, rotation fixed" in out
    assert queries[0]["result"]["counts"]["regular"] == 1


@pytest.mark.parametrize("length, m, m2, scale", [("mm", "m", "m^2", 1e-6),
                                                  ("none", "none", "none", 1.0)])
def test_octahedral_forward_kinematics_json_says_its_units(tmp_path, capsys, length, m, m2,
                                                           scale):
    """A length = "mm" scene's s15 are in m² (the Griffis-Duffy root 269.2 mm² is
    2.692e-4 m², docs/design.md §5), with nothing saying so; a unitless scene's are
    unitless."""
    queries, _ = _run(tmp_path, capsys, f'[units]\nlength = "{length}"\n' + OCTA
                      + f'[[query]]\ntype = "forward_kinematics"\nlegs = {LEGS}\n'
                        'method = "certified"\n')
    r = queries[0]["result"]
    assert r["unit"]["s15"] == m2 and r["unit"]["translation"] == m
    assert r["unit"]["max_leg_error"] == m and r["unit"]["real_roots"].startswith(m2)
    assert min(r["real_roots"]["values"]) == pytest.approx(269.2 * scale, rel=2e-4)


def test_delta_and_singularity_json_say_their_units(tmp_path, capsys):
    """These two use the octahedral geometry as written: the scene's own unit."""
    text = ('[units]\nlength = "mm"\n' + OCTA
            + '[[query]]\ntype = "delta_transform"\n'
              'offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]\n'
              f'm_legs = {LEGS}\nmethod = "fast"\n'
              '[[query]]\ntype = "singularity"\n'
              'pose = { translation = [6, 3.4641, 10], rotation = [0, 0, 0] }\n')
    queries, out = _run(tmp_path, capsys, text)
    d, s = queries[0]["result"], queries[1]["result"]
    assert d["unit"]["b"] == "mm^2" and d["unit"]["mapped_legs"] == "mm"
    assert d["unit"]["forward_kinematics"]["s15"] == "mm^2"
    assert "b = [576/25, 144/25, 576/25, 144/25, 576/25, 144/25] mm^2" in out
    assert s["unit"]["translation"] == "mm" and s["pose"]["translation"] == [6, 3.4641, 10]
    assert s["unit"]["det_J"].startswith("none")


def test_joint_units_follow_the_leg_type(tmp_path, capsys):
    """The IK JSON said q was in rad for prismatic legs, whose q is a length in m (QA);
    the J header gave revolute units to an all-prismatic mechanism.  Reference: the
    analytic leg lengths |b + R p - a| of the Gough-Stewart example, in m."""
    from distkin.app.scene import load_scene
    from distkin.spatial import rotation_matrix
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / "examples" / "gough_stewart_6ups.toml"
    scene = load_scene(str(path))
    mech = scene.mechanism
    text = path.read_text(encoding="utf-8").split("[[query]]")[0]
    queries, out = _run(tmp_path, capsys, text + '[[query]]\ntype = "inverse_kinematics"\n'
                        'pose = [0, 0, 0, 0, 0, 0]\n[[query]]\ntype = "jacobian"\n'
                        'pose = [0, 0, 0, 0, 0, 0]\n')
    res = queries[0]["result"]
    assert res["unit"]["q"] == res["unit"]["q_error"] == "m"
    d = mech.leg_description()
    X = np.array(res["poses"][0]["pose"])
    R = rotation_matrix(X[3:])
    lengths = [np.linalg.norm(X[:3] + R @ np.array(leg.platform) - np.array(leg.base))
               for leg in d.leg_table]
    np.testing.assert_allclose(res["poses"][0]["q"], lengths, rtol=1e-12)
    header = next(line for line in out.splitlines() if "qdot = J (v, omega)" in line)
    assert "rad/m" not in header and "m/m, m/rad" in header
    rss, _ = _run(tmp_path, capsys, RSS + '[[query]]\ntype = "inverse_kinematics"\n'
                  'pose = [0, 0, 300, 0, 0, 0]\n')
    assert rss[0]["result"]["unit"]["q"] == "rad"
