"""The ``singularity`` query along paths and at singular poses (QA F1, F2, F5, F6).

Independent reference: det J from an mpmath (50 digits) Plücker matrix written here
from the scene's points (Rojas et al., eq. (5): rows (u, b x u / L), u the unit leg
direction), not from the package's kernels."""

from __future__ import annotations

import json

import mpmath as mp
import pytest

from distkin.app.cli import main
from distkin.app.scene import loads_scene
from distkin.errors import InputError

HEAD = """
[units]
length = "none"
angle = "{angle}"
[mechanism]
kind = "octahedral"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
[[query]]
type = "singularity"
"""

LEGS = ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))


def _mp_det(t, w, deg):
    """det J (moments / L) at translation t, rotation vector w, in mpmath."""
    with mp.workdps(50):
        w = [mp.mpf(x) * (mp.pi / 180 if deg else 1) for x in w]
        th = mp.sqrt(sum(x * x for x in w))
        R = mp.eye(3)
        if th != 0:
            k = [x / th for x in w]
            K = mp.matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            R = mp.eye(3) + mp.sin(th) * K + (1 - mp.cos(th)) * K * K
        base = [mp.matrix([0, 0, 0]), mp.matrix([6, mp.sqrt(108), 0]), mp.matrix([12, 0, 0])]
        plat = [mp.matrix([0, 0, 0]), mp.matrix([6, 0, 0]), mp.matrix([3, mp.sqrt(27), 0])]
        P = base + [R * q + mp.matrix([mp.mpf(x) for x in t]) for q in plat]
        L = 6 / mp.sqrt(3)
        rows = []
        for i, j in LEGS:
            u = P[j - 1] - P[i - 1]
            u = u / mp.norm(u)
            b = P[i - 1]
            m = [(b[1] * u[2] - b[2] * u[1]) / L, (b[2] * u[0] - b[0] * u[2]) / L,
                 (b[0] * u[1] - b[1] * u[0]) / L]
            rows.append([u[0], u[1], u[2], *m])
        return mp.det(mp.matrix(rows))


def _mp_path(a, b, s, deg):
    s = mp.mpf(s)
    lerp = lambda u, v: [mp.mpf(x) + s * (mp.mpf(y) - mp.mpf(x)) for x, y in zip(u, v)]  # noqa: E731
    return _mp_det(lerp(a[0], b[0]), lerp(a[1], b[1]), deg)


def _run(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "out.json")])
    out, err = capsys.readouterr()
    return code, json.loads((tmp_path / "out.json").read_text())["queries"][0]["result"], out, err


# Griffis-Duffy path of examples/delta_griffis_duffy.toml (QA F1)
GD_FROM = (("3", "sqrt(3)", "10"), ("90*sqrt(3)", "90", "0"))
GD_TO = (("6", "0", "10"), ("90", "90*sqrt(3)", "0"))


def _gd_query(tolerance, method="certified"):
    return (HEAD.format(angle="deg") + f'method = "{method}"\ntolerance = {tolerance}\n'
            '[query.path]\nsamples = 60\n'
            '[query.path.from]\ntranslation = [3, "sqrt(3)", 10]\n'
            'rotation = ["90*sqrt(3)", 90, 0]\n'
            '[query.path.to]\ntranslation = [6, 0, 10]\nrotation = [90, "90*sqrt(3)", 0]\n')


def _mp_gd(s):
    ev = lambda v: [mp.mpf(eval(x, {"sqrt": mp.sqrt})) for x in v]  # noqa: E731
    return _mp_path((ev(GD_FROM[0]), ev(GD_FROM[1])), (ev(GD_TO[0]), ev(GD_TO[1])), s, True)


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_a_large_tolerance_keeps_a_transversal_crossing(tmp_path, capsys, method):
    """QA F1: tolerance = 0.05 (of the order of det J's change over one of 60 samples)
    deleted the crossing mpmath shows (det J -0.0398 at s = 0.49, +0.0281 at 0.51)."""
    code, r, out, err = _run(tmp_path, capsys, _gd_query(0.05, method))
    assert code == 0, err
    code, r2, _, err = _run(tmp_path, capsys, _gd_query("1e-9", method))
    assert code == 0, err
    assert len(r["crossings"]) == len(r2["crossings"]) == 1
    s = r["crossings"][0]["s"]
    assert s == pytest.approx(r2["crossings"][0]["s"], abs=1e-12)
    assert mp.sign(_mp_gd(s - 1e-6)) * mp.sign(_mp_gd(s + 1e-6)) < 0
    assert abs(_mp_gd(s)) < 1e-12
    if method == "certified":
        lo, hi = (float(eval(str(x))) if isinstance(x, str) else float(x)
                  for x in r["crossings"][0]["certified"]["bracket"])
        assert mp.sign(_mp_gd(lo)) == r["crossings"][0]["certified"]["signs"][0]
        assert mp.sign(_mp_gd(hi)) == r["crossings"][0]["certified"]["signs"][1]


F2_FROM = (("4.600749310927605", "0.7794051903049409", "10.35834177112095"),
           ("1.9638735043221598", "1.975015002843553", "0.20475660701544626"))
F2_TO = (("4.408779717087266", "0.9472923729966088", "9.639789994194691"),
         ("2.324716540906057", "2.3212240237206094", "-0.2058241153973472"))


def test_two_crossings_inside_one_sample_interval_are_found(tmp_path, capsys):
    """QA F2: a path grazing the singular surface crosses it twice about 0.005 apart in
    s, both inside one of 120 sample intervals; it was reported as 0 crossings.  mpmath
    confirms the signs: + at both ends, - between the two roots found."""
    vec = lambda v: "[" + ", ".join(f'"{x}"' for x in v) + "]"  # noqa: E731
    q = (HEAD.format(angle="rad") + 'method = "certified"\n[query.path.from]\n'
         f"translation = {vec(F2_FROM[0])}\nrotation = {vec(F2_FROM[1])}\n"
         f"[query.path.to]\ntranslation = {vec(F2_TO[0])}\nrotation = {vec(F2_TO[1])}\n")
    code, r, out, err = _run(tmp_path, capsys, q)
    assert code == 0, err
    mpd = lambda s: _mp_path(F2_FROM, F2_TO, s, False)  # noqa: E731
    s1, s2 = (c["s"] for c in r["crossings"])
    assert mp.sign(mpd(0)) == mp.sign(mpd(1)) == 1
    assert mp.sign(mpd((s1 + s2) / 2)) == -1
    assert abs(mpd(s1)) < 1e-12 and abs(mpd(s2)) < 1e-12
    assert all(c["certified"]["bracket"] is not None for c in r["crossings"])
    # certified: arb proves det J != 0 outside the two crossings' brackets
    cc = r["crossing_count"]
    assert cc["certified_complete"] and not cc["zero_exclusion"]["undecided"]
    for (a, b), c in zip(cc["zero_exclusion"]["brackets"], (s1, s2)):
        assert a < c < b and mp.sign(mpd(a)) == -mp.sign(mpd(b))
    assert "the count is certified complete" in out
    # each bracket holds exactly one zero: arb proves d(det J)/ds != 0 over it; the
    # sign of the derivative is the one mpmath sees across the bracket
    assert cc["zero_exclusion"]["simple"] == [True, True] and cc["exact"]
    assert "holds exactly one zero" in out


def test_fast_tier_count_is_a_lower_bound(tmp_path, capsys):
    """Without arb the count of crossings is not claimed complete (QA F2)."""
    code, r, out, err = _run(tmp_path, capsys, _gd_query("1e-9", "fast"))
    assert code == 0, err
    assert r["crossing_count"]["is_lower_bound"] and not r["crossing_count"]["certified_complete"]
    assert "lower bound, not certified" in out


def test_certified_pose_exactly_singular_keeps_its_results(tmp_path, capsys):
    """QA F5a: t = (3, sqrt 3, 10), no rotation, is exactly singular (mpmath: |det J| <
    1e-40); the certified query aborted with exit 2 and lost every other result."""
    q = HEAD.format(angle="deg") + ('method = "certified"\n'
                                    'pose = { translation = [3, "sqrt(3)", 10], rotation = [0, 0, 0] }\n')
    code, r, out, err = _run(tmp_path, capsys, q)
    assert code == 0, err
    assert abs(_mp_det([3, mp.sqrt(3), 10], [0, 0, 0], True)) < 1e-40
    assert r["certified_sign_det_J"] is None and abs(r["det_J"]) < 1e-12
    assert r["sigma_min"] < 1e-12 and r["four_planes"]["spread"] is not None
    assert "sign of det J not certified" in out and "contains 0" in out
    assert "raise the precision" not in out + err


def test_certified_path_from_a_singular_pose(tmp_path, capsys):
    """QA F5b: a path starting at that pose: the crossing at s = 0 cannot be bracketed
    inside [0, 1]; it is reported uncertified (not an abort), and all three tests fire
    there (their values vanish: mpmath det J < 1e-40).  Its float64 det J at s = 0 is
    within its rounding-error estimate of 0, so the sign change is possibly round-off
    and not counted (path24): it is reported under ``possible_crossings``."""
    q = HEAD.format(angle="deg") + (
        'method = "certified"\npath = { from = { translation = [3, "sqrt(3)", 10], '
        'rotation = [0, 0, 0] }, to = { translation = [4, "sqrt(3)", 11], rotation = [10, 0, 0] } }\n')
    code, r, out, err = _run(tmp_path, capsys, q)
    assert code == 0, err
    assert r["crossings"] == [] and r["crossing_count"]["possibly_round_off"] == 1
    c = r["possible_crossings"][0]
    assert c["s"] == 0.0 and c["certified"]["bracket"] is None
    assert c["all_fire"] is True
    assert "sign change not certified" in out and "possibly round-off" in out


@pytest.mark.parametrize("query,limit", [
    ('path = { from = { translation = [3, 1, 10] }, to = { translation = [3, 2, 10] }, '
     'samples = 100000001 }', "100000"),
])
def test_path_samples_are_capped(query, limit):
    """QA F6: samples = 1e8 was accepted and exhausted the memory."""
    with pytest.raises(InputError) as exc:
        loads_scene(HEAD.format(angle="deg") + query + "\n")
    assert exc.value.field == "query[0].path.samples" and limit in exc.value.message


def test_leg_path_samples_are_capped():
    from pathlib import Path
    ex = Path(__file__).resolve().parents[2] / "examples" / "griffis_duffy_indices.toml"
    text = ex.read_text(encoding="utf-8")
    head = text[:text.index("[[query]]")]
    with pytest.raises(InputError) as exc:
        loads_scene(head + '[[query]]\ntype = "singularity"\npath = { from = [6, 1, 17, 0, 0, 0], '
                    'to = [6, 1, 17, 0, 0, 135], samples = 10001 }\n')
    assert exc.value.field.endswith("].path.samples") and "10000" in exc.value.message


@pytest.mark.parametrize("query, field, words", [
    ('pose = { translation = [3e200, 1, 10], rotation = [0, 0, 0] }',
     "query[0].pose.translation", "times the mechanism's size 12"),
    ('path = { from = { translation = [3, 1, 10] }, to = { translation = [3, 1, "1e300"] } }',
     "query[0].path.to.translation", "got 1e+300"),
    ('pose = { translation = [3, 1, 10], rotation = [1e300, 0, 0] }',
     "query[0].pose.rotation", "angle unit"),
    ('pose = { translation = [3, 1, 10] }\nlength_scale = "1e-300"',
     "query[0].length_scale", "got 1e-300"),
])
def test_extreme_magnitudes_name_the_scene_field(query, field, words):
    """QA F7: these printed numpy RuntimeWarnings and then an error about internal
    arrays (query[0].sq, platform_joints[3][0][0]).  The size 12 is the base's largest
    coordinate (12, 0, 0)."""
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError) as exc:
            loads_scene(HEAD.format(angle="deg") + query + "\n")
    assert exc.value.field == field and words in exc.value.message


def test_tolerance_accepts_an_exact_string_and_root_distance_is_null(tmp_path, capsys):
    """QA F12: tolerance = "1e-6" was refused while other numeric fields take strings;
    a test without any root on the path wrote root_distance "inf" (a string)."""
    from distkin.exact import parse_float
    p = loads_scene(_gd_query('"1e-6"', "fast")).queries[0].params
    assert p.tolerance == parse_float("1e-6")
    code, r, _, err = _run(tmp_path, capsys, _gd_query('"1e-6"', "fast"))
    assert code == 0, err
    for d in r["crossings"][0]["root_distance"].values():
        assert d is None or isinstance(d, float)
    with pytest.raises(InputError) as exc:
        loads_scene(_gd_query('"2"', "fast"))
    assert exc.value.field == "query[0].tolerance"


@pytest.mark.parametrize("samples", [60, 61])
def test_a_sample_on_an_undefined_point_changes_nothing(tmp_path, samples):
    """QA W 3: a path through a flat tetrahedron P1P2P4P5 at s = 0.5 (the platform
    turned about z by -10 .. +10 deg at rx = 90 sqrt(3), ry = 90 deg): with 61 samples
    s = 0.5 is itself a sample, where the relative signed form is 0/0 (NaN), and its
    root was lost (a sign change was looked for only between neighbouring samples); with
    60 it was found.  Now both find it, and the note on undefined samples is in the JSON
    too, counting samples apart from the points of the root refinement.  Reference: the
    symmetric path, whose middle s = 0.5 is the flat pose."""
    text = ('[units]\nlength = "none"\nangle = "deg"\n'
            '[mechanism]\nkind = "octahedral"\nbase = [[0, 0, 0], [6, "sqrt(108)", 0], '
            '[12, 0, 0]]\nplatform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
            '[[query]]\ntype = "singularity"\nmethod = "fast"\n'
            f'[query.path]\nsamples = {samples}\n[query.path.from]\n'
            'translation = [3, "sqrt(3)", 10]\n'
            'rotation = ["90*sqrt(3)", 90, -10]\n[query.path.to]\n'
            'translation = [3, "sqrt(3)", 10]\nrotation = ["90*sqrt(3)", 90, 10]\n')
    scene = tmp_path / "p.toml"
    scene.write_text(text, encoding="utf-8")
    assert main(["run", str(scene), "--json", str(tmp_path / "o.json")]) == 0
    res = json.loads((tmp_path / "o.json").read_text())["queries"][0]["result"]
    assert any(abs(r - 0.5) < 1e-9 for r in res["signed_cm_roots"]), res["signed_cm_roots"]
    note = next(n for n in res["notes"] if n.startswith("the signed CM form undefined"))
    assert ("at 1 of the 61 samples (s = 0.5)" in note) == (samples == 61)
    assert "(s = 0.5, 0.5)" not in note
