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


@pytest.mark.parametrize("length, m, m2, scale", [("mm", "mm", "mm^2", 1.0),
                                                  ("cm", "cm", "cm^2", 1.0),
                                                  ("none", "none", "none", 1.0)])
def test_octahedral_forward_kinematics_json_says_its_units(tmp_path, capsys, length, m, m2,
                                                           scale):
    """A length = "mm" scene's s15 are in mm² (the Griffis-Duffy root 269.2, [1] Sec. VI),
    as the delta_transform and 6-6 queries of the same scene report theirs (they were in
    m² here, 2.692e-4, QA R 4); a unitless scene's are unitless."""
    queries, out = _run(tmp_path, capsys, f'[units]\nlength = "{length}"\n' + OCTA
                      + f'[[query]]\ntype = "forward_kinematics"\nlegs = {LEGS}\n'
                        'method = "certified"\n')
    r = queries[0]["result"]
    assert r["unit"]["s15"] == m2 and r["unit"]["translation"] == m
    assert r["unit"]["max_leg_error"] == m and r["unit"]["real_roots"].startswith(m2)
    assert min(r["real_roots"]["values"]) == pytest.approx(269.2 * scale, rel=2e-4)
    if length != "none":
        assert f"s15 = 269.245" in out and f"{m2}" in out and " m^2" not in out


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
    # QA U 4: reach_margin had no unit; m^2, here (q - qmin)(qmax - q) or q^2 per leg
    assert res["unit"]["reach_margin"].startswith("m^2 per leg")
    margins = [(q - leg.range[0]) * (leg.range[1] - q) if leg.range else q * q
               for q, leg in zip(lengths, d.leg_table)]
    np.testing.assert_allclose(res["poses"][0]["reach_margin"], margins, rtol=1e-10)
    header = next(line for line in out.splitlines() if "qdot = J (v, omega)" in line)
    assert "rad/m" not in header and "m/m, m/rad" in header
    rss, _ = _run(tmp_path, capsys, RSS + '[[query]]\ntype = "inverse_kinematics"\n'
                  'pose = [0, 0, 300, 0, 0, 0]\n')
    assert rss[0]["result"]["unit"]["q"] == "rad"


CM_POINTS = [[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4]]


def _cm_scene(length, points, dets='["D(1)", "D(1,2)", "D(1,2,3)", "D(1,2,3,4)"]'):
    return (f'[units]\nlength = "{length}"\n[mechanism]\nkind = "points"\npoints = {points}\n'
            f'[[query]]\ntype = "cayley_menger"\ndeterminants = {dets}\nmethod = "certified"\n')


def test_cayley_menger_units_follow_the_number_of_points(tmp_path, capsys):
    """A determinant of n points is of degree n - 1 in the squared distances: unit^(2(n-1)).
    D(1) = -1 was printed '-1 mm' (a pure number), and the JSON values had no unit (QA G 4).
    References: the analytic values (D(1,2) = 2 d², D(1,2,3) = -16 area², D(1,2,3,4) =
    288 V² with V = |det| / 6 = 6·5·4 / 6 = 20), and the same points written in m (each
    coordinate / 1000), whose values must be those in mm times 1000^-(2(n-1))."""
    queries, out = _run(tmp_path, capsys, _cm_scene("mm", CM_POINTS))
    r = queries[0]["result"]
    by_name = {e["name"]: e for e in r["determinants"]}
    assert [(n, e["value"], e["unit"]) for n, e in by_name.items()] == [
        ("D(1)", "-1", "none"), ("D(1,2)", "72", "mm^2"),
        ("D(1,2,3)", str(-16 * (6 * 5 / 2) ** 2).removesuffix(".0"), "mm^4"),
        ("D(1,2,3,4)", str(288 * 20 ** 2), "mm^6")]
    # exact where exact (QA 23 D5): the certified interpretations are exact strings,
    # their floats beside them
    assert by_name["D(1,2,3)"]["triangle_area_squared"] == "225"
    assert by_name["D(1,2,3,4)"]["tetrahedron_volume_squared"] == "400"
    assert by_name["D(1,2,3)"]["triangle_area_squared_float"] == 225.0
    assert by_name["D(1,2,3,4)"]["tetrahedron_volume_squared_float"] == 400.0
    assert r["unit"]["triangle_area_squared"] == "mm^4"
    assert r["unit"]["tetrahedron_volume_squared"] == "mm^6"
    lines = out.splitlines()
    assert "  D(1) = -1" in lines                       # no unit at power 0
    assert "  D(1,2) = 72 mm^2" in lines
    assert "  D(1,2,3) = -3600 mm^4   (area^2 = 225 mm^4)" in lines
    assert "  D(1,2,3,4) = 115200 mm^6   (volume^2 = 400 mm^6)" in lines
    # the same geometry in m: the unit's power is the scaling exponent
    from fractions import Fraction
    metres = [[f'"{Fraction(x, 1000)}"' for x in row] for row in CM_POINTS]
    text = _cm_scene("m", "[" + ", ".join("[" + ", ".join(r) + "]" for r in metres) + "]")
    queries_m, _ = _run(tmp_path, capsys, text)
    for e_mm, e_m in zip(r["determinants"], queries_m[0]["result"]["determinants"]):
        power = int(e_mm["unit"].split("^")[1]) if e_mm["unit"] != "none" else 0
        assert Fraction(e_mm["value"]) == Fraction(e_m["value"]) * 1000 ** power
        assert e_m["unit"] == e_mm["unit"].replace("mm", "m")
    # a unitless scene: every unit "none", no unit in the text
    queries_n, out_n = _run(tmp_path, capsys, _cm_scene("none", CM_POINTS))
    assert {e["unit"] for e in queries_n[0]["result"]["determinants"]} == {"none"}
    assert "  D(1,2) = 72" in out_n.splitlines()


def test_cayley_menger_refuses_an_empty_list(tmp_path, capsys):
    f = tmp_path / "s.toml"
    f.write_text(_cm_scene("mm", CM_POINTS, dets="[]"))
    assert main(["run", str(f)]) == 2
    out, err = capsys.readouterr()
    assert err.strip() == ('distkin: error: query[0].determinants: expected at least one '
                           'determinant label, such as "D(1,2,3,4)" or "D(5,4,1,2;5,4,1,6)", '
                           'got an empty list []')


def test_jacobian_indices_are_undefined_where_the_pose_is_not_reachable(tmp_path, capsys):
    """At 3 m above the Hunt platform's base no leg closes: the text said 'J is
    meaningless' but printed kappa = 0.0828 and six singular values, and the JSON had
    them as numbers (QA G 7).  References: the preset's own IK (no leg valid there), and
    at the reachable home pose condition_number and numpy's SVD of preset('hunt').jacobian."""
    m = preset("hunt")
    far = np.array([0, 0, 3.0, 0, 0, 0])
    assert not m.inverse_kinematics(far)[1].any()
    home_mm = [float(round(v * 1000, 9)) for v in m.home[:3]] + [float(v) for v in m.home[3:]]
    queries, out = _run(tmp_path, capsys, MM.replace('angle = "deg"', 'angle = "rad"')
                        + '[mechanism]\nkind = "rss"\npreset = "hunt"\n[[query]]\n'
                        f'type = "jacobian"\nposes = [[0, 0, 3000, 0, 0, 0], {home_mm}]\n')
    far_row, home_row = queries[0]["result"]["poses"]
    assert far_row["reachable"] is False
    assert far_row["kappa"] is None and far_row["kappa_unscaled"] is None
    assert far_row["singular_values"] is None
    assert home_row["reachable"] is True
    J = m.jacobian(m.home)
    assert home_row["kappa"] == pytest.approx(float(condition_number(J)), rel=1e-12)
    assert home_row["singular_values"] == pytest.approx(np.linalg.svd(J, compute_uv=False),
                                                        rel=1e-12)
    text = out.split("pose 1:")
    assert "kappa = undefined (pose not reachable)" in text[0]
    assert "singular values of the unscaled J: undefined (pose not reachable)" in text[0]
    assert "kappa = 0.0828" not in out
    assert f"kappa = {home_row['kappa']:.6g} (eq. (4)" in text[1]
    assert "null where the pose is not reachable" in queries[0]["result"]["unit"]["kappa"]


def test_precise_cayley_menger_leaves_mpmath_precision_alone(tmp_path):
    """The precise cayley_menger query set mpmath.mp.dps for the rest of the process
    (QA G, noticed by fix-g); it now works at its dps inside the query only."""
    import mpmath
    from distkin.app.cli import main
    f = tmp_path / "cm.toml"
    f.write_text('[mechanism]\nkind = "points"\npoints = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n'
                 '[[query]]\ntype = "cayley_menger"\ndeterminants = ["D(1,2,3)"]\n'
                 'method = "precise"\ndps = 60\n', encoding="utf-8")
    before = mpmath.mp.dps
    assert main(["run", str(f), "--no-progress"]) == 0
    assert mpmath.mp.dps == before


def test_the_mechanism_block_of_ik_and_jacobian_has_units(tmp_path, capsys):
    """The JSON ``mechanism`` block (SI whatever the scene's units) carried no unit
    (QA Y1): ``l0: 0.17`` in a mm scene.  Now ``unit.mechanism`` names each parameter's;
    reference: the scene's own overrides, written in mm and deg, read back in m and rad."""
    text = (MM + '[mechanism]\nkind = "rss"\npreset = "octopod"\nl0 = 170\ngamma = 10\n'
            '[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]\n'
            '[[query]]\ntype = "jacobian"\npose = [0, 0, 300, 0, 0, 0]\n')
    queries, _ = _run(tmp_path, capsys, text)
    for q in queries:
        mech, unit = q["result"]["mechanism"], q["result"]["unit"]["mechanism"]
        numeric = {k for k, v in mech.items() if isinstance(v, (int, float))
                   and not isinstance(v, bool) and k != "legs"}
        assert numeric <= set(unit), numeric - set(unit)
        assert unit["l0"] == "m" and mech["l0"] == pytest.approx(170 / 1000)
        assert unit["gamma"] == "rad" and mech["gamma"] == pytest.approx(np.radians(10))
