"""The Griffis-Duffy example of Rojas et al. (ICRA 2012, Sec. VI; docs/design.md §5) in all
three tiers, the JSON contract and the demo scene."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from distkin.exact_roots import working_precision
from distkin.octahedral import forward_kinematics, forward_kinematics_batched
from distkin.octahedral.reference import GD_BASE, GD_LEGS, GD_PLATFORM, GD_ROOTS

ROOT = Path(__file__).resolve().parents[2]
BASE_F = np.array([[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]])
PLAT_F = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
LEGS_F = np.array([19.8, 18, 18, 17, 14.9, 17.8])
PAIRS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


@pytest.fixture(scope="module")
def certified():
    return forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="certified")


def _rounds_to(value: float, printed: str) -> bool:
    """Does ``value`` round to the printed decimal (to its printed digits)?"""
    d = Decimal(printed)
    return Decimal(repr(value)).quantize(d) == d


def _leg_rel_errors(points):
    P = {1: BASE_F[0], 2: BASE_F[1], 3: BASE_F[2], 4: points[0], 5: points[1], 6: points[2]}
    return [abs(np.linalg.norm(P[i] - P[j]) - l) / l for (i, j), l in zip(PAIRS, LEGS_F)]


def _exact(a) -> Fraction:
    """The value of an exact arb (an end of a ball)."""
    assert a.is_exact()
    m, e = a.man_exp()
    return Fraction(int(m)) * Fraction(2) ** int(e)


def test_certified_count_roots_and_poses(certified):
    res = certified
    assert res.certified and res.real_root_count == 6
    assert all(r.status == "assembly" and r.multiplicity == 1 for r in res.roots)
    # the printed roots, to the printed digits (the balls are far narrower than 0.05)
    assert all(_rounds_to(r.value, g) for r, g in zip(res.roots, GD_ROOTS))
    # the radius encloses the exact root about the float value: no wider than the
    # value's own rounding needs (the 64-bit balls are far narrower than an ulp), and
    # every ball inside value +- radius (arb comparison, exact)
    for r in res.roots:
        assert r.radius_kind == "certified" and 0 < r.radius <= math.ulp(r.value)
        v, rad = Fraction(r.value), Fraction(r.radius)
        with working_precision(1024):          # the ends of the ball, exactly
            lo, hi = _exact(r.native.lower()), _exact(r.native.upper())
        assert v - rad <= lo and hi <= v + rad
    assert len(res) == 12
    for pose in res:
        # rigorous upper bound from the balls, and an independent float check
        assert pose.max_leg_error_relative <= 1e-12
        assert max(_leg_rel_errors(pose.points)) <= 1e-13
        R = pose.rotation
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-14) and np.linalg.det(R) > 0
        assert np.allclose(PLAT_F @ R.T + pose.translation, pose.points, atol=1e-12)


def test_mirror_pairs_are_reflections_in_the_base_plane(certified):
    by_root = {}
    for pose in certified:
        by_root.setdefault(pose.s15, []).append(pose)
    assert len(by_root) == 6
    for a, b in by_root.values():
        mirrored = b.points * np.array([1, 1, -1])
        assert np.allclose(a.points, mirrored, atol=1e-12)
        assert a.side == -b.side


def test_fast_tier(certified):
    res = forward_kinematics(BASE_F, PLAT_F, LEGS_F)
    assert len(res) == 12 and res.real_root_count == 6 and not res.certified
    for pose in res:
        assert pose.max_leg_error_relative <= 1e-9
        assert max(_leg_rel_errors(pose.points)) <= 1e-9
    # the same poses as the certified tier (its enclosures are ~1e-22 wide)
    for a, b in zip(res, certified):
        assert abs(a.s15 - b.s15) <= 1e-9 * b.s15
        assert np.allclose(a.points, b.points, atol=1e-9)


def test_precise_tier_at_50_digits(certified):
    import mpmath
    res = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="precise", dps=50)
    assert len(res) == 12 and res.octic_exact
    assert res.octic == certified.octic          # same exact rationals
    for pose, cert in zip(res, certified):
        assert pose.max_leg_error_relative <= 1e-40
        # the 50-digit root lies in the certified ball
        with mpmath.workdps(60):
            ball = cert.native["s15"]
            mid, rad = mpmath.mpf(ball.mid().str(60, radius=False)), mpmath.mpf(
                ball.rad().str(5, radius=False))
            assert abs(pose.native["s15"] - mid) <= rad + mpmath.mpf(10) ** -45 * mid


def test_batched_equals_single():
    legs = np.tile(LEGS_F, (5, 1))
    legs[1:] *= 1 + 1e-3 * np.arange(1, 5)[:, None]
    br = forward_kinematics_batched(BASE_F, PLAT_F, legs)
    for i in range(5):
        single = forward_kinematics(BASE_F, PLAT_F, legs[i])
        assert br.count[i] == len(single)
        got = br.points[i][br.valid[i]]
        assert np.allclose(got, np.array([p.points for p in single]), atol=1e-12)


def test_exact_input_types_are_accepted():
    fr = [Fraction(198, 10), 18, 18, 17, Fraction(149, 10), Fraction(178, 10)]
    a = forward_kinematics(GD_BASE, GD_PLATFORM, fr, method="certified")
    assert a.octic == forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="certified").octic


def test_scene_json_contract(tmp_path):
    out = tmp_path / "gd.json"
    r = subprocess.run([sys.executable, "-m", "distkin", "run",
                        str(ROOT / "examples" / "octahedral_griffis_duffy.toml"),
                        "--json", str(out), "--plots", str(tmp_path / "plots")],
                       capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    q = doc["queries"][0]
    assert q["type"] == "forward_kinematics" and q["status"] == "ok"
    res = q["result"]
    assert set(res["real_roots"]) == {"count", "certified", "values", "radii"}
    assert res["real_roots"]["count"] == 6 and res["real_roots"]["certified"] is True
    # each radius says what it is; the certified ones enclose the root about the value
    assert [r["radius_kind"] for r in res["root_status"]] == ["certified"] * 6
    assert all(0 < r <= 2 ** -44 for r in res["real_roots"]["radii"])    # ulp(512)
    fast = doc["queries"][1]["result"]             # the scene's fast query: proved
    assert fast["conditioning"]["trusted"]
    assert [r["radius_kind"] for r in fast["root_status"]] == ["proved"] * 6
    assert fast["real_roots"]["radii"] == fast["conditioning"]["root_radii"]
    coeffs = res["octic"]["coefficients"]
    assert len(coeffs) == 9 and all(isinstance(c, str) for c in coeffs)
    assert Fraction(coeffs[0]) > 0
    assert len(res["poses"]) == 12
    pose = res["poses"][0]
    assert {"s15", "rotation", "translation", "points", "max_leg_error"} <= set(pose)
    assert set(pose["points"]) == {"P4", "P5", "P6"}
    assert np.shape(pose["rotation"]) == (3, 3) and len(pose["translation"]) == 3
    plots = list((tmp_path / "plots").glob("*.png"))
    assert len(plots) >= 2
    assert "12 poses" in r.stdout and "certified" in r.stdout


def test_demo_lists_the_scene_and_example_is_a_symlink():
    from distkin.app.cli import DEMO_SCENES
    assert "octahedral_griffis_duffy.toml" in DEMO_SCENES
    link = ROOT / "examples" / "octahedral_griffis_duffy.toml"
    assert link.is_symlink()
    assert link.resolve() == (ROOT / "distkin" / "scenes" / "octahedral_griffis_duffy.toml")


def test_scene_errors_name_the_field():
    from distkin.errors import InputError
    from distkin.app.scene import loads_scene
    text = (ROOT / "distkin" / "scenes" / "octahedral_griffis_duffy.toml").read_text()
    bad = text.replace('legs = ["19.8", "18", "18", "17", "14.9", "17.8"]\nmethod = "certified"',
                       'legs = ["19.8", "18", "18", "17", "14.9"]\nmethod = "certified"')
    with pytest.raises(InputError, match=r"query\[0\]\.legs"):
        loads_scene(bad)
    typo = text.replace('method = "fast"', 'methd = "fast"')
    with pytest.raises(InputError, match="methd"):
        loads_scene(typo)
    neg = text.replace('"14.9"', '"-14.9"', 1)
    with pytest.raises(InputError, match="positive"):
        loads_scene(neg)


def test_scene_in_millimetres_is_solved_in_millimetres():
    """A scene written in mm is solved as written: roots in mm^2, the paper's values (Sec.
    VI), as the scene's other queries report theirs (it was converted to m^2, QA R 4)."""
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = (ROOT / "distkin" / "scenes" / "octahedral_griffis_duffy.toml").read_text()
    scene = loads_scene(text.replace('length = "none"', 'length = "mm"'))
    records, texts, worst = run_scene(scene, progress=False)
    assert worst == 0
    res = records[0]["result"]
    assert res["real_roots"]["count"] == 6
    assert all(abs(v - float(g)) <= 0.05
               for v, g in zip(res["real_roots"]["values"], GD_ROOTS))
    assert res["unit"]["s15"] == "mm^2" and res["unit"]["translation"] == "mm"
    assert " mm^2" in texts[0] and " m^2" not in texts[0]


def test_results_compare_by_value(certified):
    """Two solves of the same problem are equal, pose by pose and as results; distinct
    poses and results are unequal, and comparing never raises (the arrays inside are
    compared element by element; the certified tier's arb balls are not compared)."""
    a = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS)
    b = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS)
    assert a == b and a.poses == b.poses and a.roots == b.roots
    assert a[0] != a[1] and a[0] == b[0]
    other = forward_kinematics(GD_BASE, GD_PLATFORM, [float(v) * 1.01 for v in GD_LEGS])
    assert a != other
    again = forward_kinematics(GD_BASE, GD_PLATFORM, GD_LEGS, method="certified")
    assert again.poses == certified.poses and again.roots == certified.roots
    assert certified[0].radius > 0 and a[0] != certified[0]   # fast poses have radius 0
    assert (a[0] == "pose") is False
