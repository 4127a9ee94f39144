"""The ``singularity`` query's verdict and conditions under ``method = "certified"``
(QA V 1, 2): the verdict follows the arb certificate, not the float tolerance, and the
Cayley-Menger conditions are evaluated in arb.  References are independent of the
program: det J of the normalised Plücker lines (eq. (5)) recomputed here in mpmath at
60 digits, and the flat pose's products exactly 0 (every point in z = 0)."""

from __future__ import annotations

import json

import mpmath
import numpy as np
import pytest

from distkin.app.cli import main

HEAD = """
[units]
length = "none"
angle = "deg"
[mechanism]
kind = "octahedral"
base = [[0,0,0],[6,"sqrt(108)",0],[12,0,0]]
platform = [[0,0,0],[6,0,0],[3,"sqrt(27)",0]]
[[query]]
type = "singularity"
"""

#: 2e-10 along the example path past its crossing at s = 0.501671357764296 (QA V 1)
S = 0.501671357764296 + 2e-10
T0, T1 = np.array([3, np.sqrt(3), 10]), np.array([6, 0, 10.0])
W0, W1 = np.array([90 * np.sqrt(3), 90, 0]), np.array([90, 90 * np.sqrt(3), 0])
T, W = T0 + S * (T1 - T0), W0 + S * (W1 - W0)


def _run(tmp_path, capsys, query):
    f = tmp_path / "s.toml"
    f.write_text(HEAD + query, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "o.json")])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads((tmp_path / "o.json").read_text())["queries"][0]["result"], out


def _det_j_mp(t, w_deg, dps=60):
    """det J (eq. (5), moments / L) by hand in mpmath: Rodrigues' rotation, unit leg
    directions, moments b x u."""
    with mpmath.workdps(dps):
        w = [mpmath.mpf(float(x)) * mpmath.pi / 180 for x in w_deg]
        th = mpmath.sqrt(sum(x * x for x in w))
        k = [x / th for x in w]
        K = mpmath.matrix([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R = mpmath.eye(3) + mpmath.sin(th) * K + (1 - mpmath.cos(th)) * K * K
        s3 = mpmath.sqrt(3)
        base = [mpmath.matrix([0, 0, 0]), mpmath.matrix([6, 6 * s3, 0]),
                mpmath.matrix([12, 0, 0])]
        plat = [R * mpmath.matrix(q) + mpmath.matrix([mpmath.mpf(float(x)) for x in t])
                for q in ([0, 0, 0], [6, 0, 0], [3, 3 * s3, 0])]
        L = 2 * s3                                   # the platform's circumradius
        rows = []
        for b, p in ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6)):
            bb, pp = base[b - 1], plat[p - 4]
            u = (pp - bb) / mpmath.norm(pp - bb)
            m = [bb[1] * u[2] - bb[2] * u[1], bb[2] * u[0] - bb[0] * u[2],
                 bb[0] * u[1] - bb[1] * u[0]]
            rows.append([u[0], u[1], u[2]] + [x / L for x in m])
        return mpmath.det(mpmath.matrix(rows))


def _pose(t, w):
    return (f"pose = {{ translation = [{t[0]!r}, {t[1]!r}, {t[2]!r}], "
            f"rotation = [{w[0]!r}, {w[1]!r}, {w[2]!r}] }}\n")


def test_certified_verdict_follows_the_certificate_not_the_tolerance(tmp_path, capsys):
    ref = _det_j_mp([float(x) for x in T], [float(x) for x in W])
    assert 1e-10 < ref < 1e-9                      # within the tolerance, but not 0
    r, out = _run(tmp_path, capsys, 'method = "certified"\n' + _pose(list(map(float, T)), list(map(float, W))))
    assert r["certified_sign_det_J"] == 1 == mpmath.sign(ref)
    assert r["singular"] is False and r["near_singular"] is True
    assert abs(r["det_J"] - float(ref)) < 1e-6 * float(ref)
    det_line = next(x for x in out.splitlines() if "det J (eq. 5" in x)
    assert "near-singular" in det_line and "a singular pose" not in det_line
    assert "det J != 0, not a singular pose" in out


def test_fast_verdict_says_it_is_a_tolerance_test(tmp_path, capsys):
    r, out = _run(tmp_path, capsys, 'method = "fast"\n' + _pose(list(map(float, T)), list(map(float, W))))
    assert r["singular"] is True and "tolerance" in r["singular_test"]
    assert "near_singular" not in r and "tolerance test" in out


def test_certified_flat_pose_conditions_are_undefined_not_noise(tmp_path, capsys):
    # every point in z = 0: every Cayley-Menger determinant is exactly 0, both products
    # are 0 and the relative conditions are 0/0 (QA V 2: they read 0.9796 and -1)
    r, out = _run(tmp_path, capsys, 'method = "certified"\n'
                                    'pose = { translation = [3, 1, 0], rotation = [0, 0, 0] }\n')
    assert r["singular"] is True and r["certified_sign_det_J"] == 0
    for key in ("cm_condition_relative", "signed_cm_relative"):
        assert r[key] is None and key in r["undefined"]
    assert r["conditions_tier"].startswith("certified")
    assert "9.796e-01" not in out and "-1.000e+00" not in out



def test_fast_flat_pose_conditions_are_undefined_not_noise(tmp_path, capsys):
    r, out = _run(tmp_path, capsys, 'method = "fast"\n'
                                    'pose = { translation = [3, 1, 0], rotation = [0, 0, 0] }\n')
    for key in ("cm_condition_relative", "signed_cm_relative"):
        assert r[key] is None and "rounding" in r["undefined"][key]
    assert r["conditions_tier"].startswith("fast")


def test_certified_verdict_at_float_rounding_of_the_crossing_is_decided(tmp_path, capsys):
    # on the crossing itself to float64 rounding: the pose's floats are exact binary
    # values, and there det J is ~1e-17, not 0 (the 60-digit reference).  At flint's
    # default 53 bits the ball contained 0 ("undecided"); the query now raises the arb
    # precision (128, 512, 2048 bits) until the sign is decided, and it is the
    # reference's
    s = 0.501671357764296
    t, w = [float(x) for x in T0 + s * (T1 - T0)], [float(x) for x in W0 + s * (W1 - W0)]
    ref = _det_j_mp(t, w)
    assert 0 < abs(ref) < 1e-14
    r, out = _run(tmp_path, capsys, 'method = "certified"\n' + _pose(t, w))
    assert r["certified_sign_det_J"] == int(mpmath.sign(ref)) and r["singular"] is False
    assert r["near_singular"] is True and r["arb_precision_bits"] >= 128
    assert "det J != 0, not a singular pose" in out


def test_certified_verdict_is_undecided_on_an_exact_irrational_singular_pose(tmp_path, capsys):
    # the platform turned 90 deg about the vertical through the base's centroid
    # (6, 2 sqrt 3, 10): t = (6 + sqrt 3, 2 sqrt 3 - 3, 10) exactly.  det J = 0 there (the
    # 60-digit reference at the float pose is 0 to its precision), not structurally (no
    # zero row), so no ball of any precision excludes 0: undecided at 2048 bits
    t = [6 + 3 ** 0.5, 2 * 3 ** 0.5 - 3, 10.0]
    assert abs(_det_j_mp(t, [0, 0, 90])) < 1e-40
    r, out = _run(tmp_path, capsys, 'method = "certified"\npose = { translation = '
                  '["6+sqrt(3)", "2*sqrt(3)-3", 10], rotation = [0, 0, 90] }\n')
    assert r["certified_sign_det_J"] is None and r["singular"] is None
    assert r["near_singular"] is True and "undecided" in r["singular_test"]
    assert r["arb_precision_bits"] == 2048
    assert "certified (arb, 2048 bits): sign of det J not certified" in out
    assert "singular undecided" in out


def test_certified_balls_are_tight_and_contain_a_60_digit_reference(tmp_path, capsys):
    # the JSON's ball of det J printed with 5 digits read [-4.8486e+8 +/- 3.38e+3] (the
    # printing widened it), and the scene's sqrt(108) was a ball of 53 bits whatever the
    # working precision.  Reference: det J by hand in mpmath at 60 digits; det Jhat =
    # det J * prod |p - b| * L^3 is not recomputed: J's normalised det is compared
    from flint import arb
    r, _ = _run(tmp_path, capsys, 'method = "certified"\n'
                                  'pose = { translation = [3, 2, 10], rotation = [10, 20, 30] }\n')
    ball = arb(r["certified_det_J_hat"].strip("[]"))
    assert ball.rad() < 1e-15 * abs(ball.mid())
    ref = _det_j_mp([3, 2, 10], [10, 20, 30])
    assert r["det_J"] == pytest.approx(float(ref), rel=1e-12)
    assert r["certified_sign_det_J"] == int(mpmath.sign(ref))
    for key in ("cm_condition_relative", "signed_cm_relative"):
        b = arb(r[key + "_ball"].strip("[]"))
        assert b.rad() < 1e-15 * max(1.0, abs(float(b.mid())))


def test_offsets_of_the_singularity_query_are_checked_at_load():
    """QA W 7: offsets [-1, ...] of a singularity query failed at run time, where README
    and check_offsets say the offsets are refused at load (as delta_transform's and
    platform66's).  Reference: delta1 must lie in (0, d12) with d12 = 12, the side
    P1P2 of the example's base."""
    from distkin.app.scene import loads_scene
    from distkin.errors import InputError
    text = ('[mechanism]\nkind = "octahedral"\nbase = [[0, 0, 0], [6, "sqrt(108)", 0], '
            '[12, 0, 0]]\nplatform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
            '[[query]]\ntype = "singularity"\noffsets = ["OFF", "6/5", "12/5", "6/5", '
            '"12/5", "6/5"]\npose = { translation = [3, 2, 10], rotation = [10, 20, 30] }\n')
    with pytest.raises(InputError, match=r"expected 0 < delta1 < d12 = 12 .* got delta1 = -1"):
        loads_scene(text.replace("OFF", "-1"), "s.toml")
    loads_scene(text.replace("OFF", "12/5"), "s.toml")            # inside: loads


def test_fast_conditions_escalate_where_float64_cannot_vouch(tmp_path):
    """QA W 2: a 0.6 µm platform over a 12 mm base, at a regular pose: the fast query
    said the relative Cayley-Menger conditions were undefined (their a priori rounding
    estimate, 0.2, above the denominator 4.7e-5), where arb gives -0.1083 +/- 1.2e-5.
    Now the precise tier (30 digits) decides there and the result says so.  Reference:
    the certified query's balls, which must contain the fast query's values."""
    from flint import arb
    text = ('[units]\nlength = "mm"\nangle = "deg"\n[mechanism]\nkind = "octahedral"\n'
            'base = [[0, 0, 0], [6, 10.392304845413264, 0], [12, 0, 0]]\n'
            'platform = [[0, 0, 0], [0.0006, 0, 0], [0.0003, 0.0005196152422706632, 0]]\n')
    query = ('[[query]]\ntype = "singularity"\npose = { translation = [5, 4, 10], '
             'rotation = [10, 5, 3] }\nmethod = "M"\n')
    scene = tmp_path / "s.toml"
    scene.write_text(text + query.replace("M", "fast") + query.replace("M", "certified"),
                     encoding="utf-8")
    assert main(["run", str(scene), "--json", str(tmp_path / "o.json")]) == 0
    fast, cert = (q["result"] for q in
                  json.loads((tmp_path / "o.json").read_text())["queries"])
    assert fast["undefined"] == {} and set(fast["escalated"]) == {"cm_condition_relative",
                                                                  "signed_cm_relative"}
    # the fast query evaluates at the float64 pose (its rotation matrix rounded), where
    # these conditions, with a denominator of 4.7e-5, move by ~1e-12 relative: the
    # certified ball of the exact pose (now ~1e-19 wide) is met within 1e-9
    for key in ("cm_condition_relative", "signed_cm_relative"):
        ball = arb(cert[key + "_ball"].strip("[]"))
        assert ball.rad() < 1e-15
        assert fast[key] == pytest.approx(float(ball.mid()), rel=1e-9), (key, fast[key])
