"""A certified workspace of a device with joint ranges: revolute ranges (the arb kernel
``ranges``, QA Q 2 said they were not covered) and prismatic strokes (QA V 7) are part of
the certificate.  The reference is the inverse kinematics' own reachability (the fast
tier's atan2 angles and :func:`distkin.mechanisms.legs.in_revolute_range`), at poses
sampled in the boxes the certificate decides."""

import json
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.app.scene import load_scene

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _samples(lower, upper, rng, k=6):
    """Per box (m, rad: the JSON's boxes) the 8 corners of its x, y, z extent, its centre
    and k random points: (B, 9 + k, 6)."""
    lo, hi = np.asarray(lower), np.asarray(upper)
    corners = np.array([[(b >> d) & 1 for d in range(6)] for b in range(8)])
    t = np.concatenate([corners[None].repeat(len(lo), 0),
                        np.full((len(lo), 1, 6), 0.5),
                        rng.random((len(lo), k, 6))], axis=1)
    return lo[:, None] + t * (hi - lo)[:, None]


def test_revolute_ranges_are_part_of_the_certificate(tmp_path, capsys):
    """rus8 with its cranks limited to [-10, 30] deg over the example's region (the
    cranks span about -25..25 deg there): some boxes are proved regular, others
    unreachable; every sampled pose of a regular box has every crank inside its range (IK
    route), none of an unreachable box does.  With the example's [-90, 90] deg the same
    region is all regular (the ranges do not bind there)."""
    text = (EXAMPLES / "rus8_device.toml").read_text(encoding="utf-8")
    head = text[:text.index("[[query]]")]
    query = ('[[query]]\ntype = "certify_workspace"\nregion = { lower = [-15, -15, 185, 0, '
             '0, 0], upper = [15, 15, 215, 0, 0, 0] }\n')
    narrow = head.replace("range = [-90, 90]", "range = [-10, 30]")
    assert narrow != head
    certs = {}
    for name, body in (("narrow", narrow), ("wide", head)):
        scene = tmp_path / f"{name}.toml"
        scene.write_text(body + query, encoding="utf-8")
        assert main(["run", str(scene), "--json", str(tmp_path / f"{name}.json")]) == 0
        out = capsys.readouterr().out
        assert "revolute joint ranges (a leg's `range`) are part of this certificate" in out
        doc = json.loads((tmp_path / f"{name}.json").read_text())
        certs[name] = next(r["result"] for r in doc["queries"]
                           if r["type"] == "certify_workspace")
    assert certs["wide"]["regular_fraction"] == 1.0
    cert = certs["narrow"]
    assert "are part of this certificate" in cert["joint_ranges"]
    boxes = cert["boxes"]
    status = np.array(boxes["status"])
    lower, upper = np.array(boxes["lower"]), np.array(boxes["upper"])     # SI: m, rad
    mech = load_scene(tmp_path / "narrow.toml").mechanism
    rng = np.random.default_rng(0)
    for code, expect in ((1, True), (3, False)):
        sel = np.flatnonzero(status == code)
        assert sel.size >= 20                             # both verdicts occur
        P = _samples(lower[sel], upper[sel], rng).reshape(-1, 6)
        ok = mech.reachable(P)
        assert np.all(ok) if expect else not np.any(ok)
    # the legs do close over the unreachable boxes: the ranges alone exclude them
    P = _samples(lower[status == 3], upper[status == 3], rng).reshape(-1, 6)
    assert np.all(mech.reach_margin(P) > 0)


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


@pytest.mark.parametrize("form", ["quadratic", "affine", "centred", "plain"])
def test_every_form_reads_the_range_margins(form, tmp_path):
    """The arb forms of :mod:`distkin.certify.boxes` read the range margins as the
    batched binary64 form does: on a strip of the rus8 with its cranks in [-10, 30] deg
    (x fixed at 10 mm, the ranges binding along y and z), the regular and unreachable
    boxes agree with the IK's reachability at sampled poses, and both occur."""
    from distkin.certify import certify_workspace
    text = (EXAMPLES / "rus8_device.toml").read_text(encoding="utf-8")
    scene = tmp_path / "narrow.toml"
    scene.write_text(text[:text.index("[[query]]")].replace("range = [-90, 90]",
                                                            "range = [-10, 30]")
                     + '[[query]]\ntype = "inverse_kinematics"\nposes = [[0, 0, 200, 0, 0, 0]]\n',
                     encoding="utf-8")
    mech = load_scene(scene).mechanism
    lower = np.array([0.01, -0.015, 0.185, 0, 0, 0])
    upper = np.array([0.01, 0.015, 0.215, 0, 0, 0])
    cert = certify_workspace(mech, lower, upper, 0.004, form=form, split=1, tighten=0)
    rng = np.random.default_rng(1)
    seen = 0
    for code, expect in ((1, True), (3, False)):
        sel = np.flatnonzero(cert.status == code)
        if form != "plain":          # the natural interval extension proves little
            assert sel.size, (form, code)
        if sel.size:
            P = _samples(cert.lo[sel], cert.hi[sel], rng).reshape(-1, 6)
            ok = mech.reachable(P)
            assert np.all(ok) if expect else not np.any(ok)
            seen += sel.size
    assert seen


def test_ranges_that_do_not_bind_change_nothing(tmp_path):
    """Review of the ranges' commit: where a ranged leg's reach margin straddles 0 its
    range margin is not finite, and its inf/NaN split weights made every such box split
    along its first coordinate (2.3x the boxes for the same volumes).  Reference: the
    same rus8 without ranges, over a region that crosses the reach edge (z 255-285 mm)
    where the cranks stay within 40-100 deg (IK), inside [-120, 120] deg: the same
    verdict volumes, and about the same number of boxes."""
    from distkin.certify import certify_workspace
    text = (EXAMPLES / "rus8_device.toml").read_text(encoding="utf-8")
    head = text[:text.index("[[query]]")]
    ik = '[[query]]\ntype = "inverse_kinematics"\nposes = [[0, 0, 200, 0, 0, 0]]\n'
    lower = np.array([-0.015, -0.015, 0.255, 0, 0, 0])
    upper = np.array([0.015, 0.015, 0.285, 0, 0, 0])
    out = {}
    for name, body in (("ranges", head.replace("range = [-90, 90]", "range = [-120, 120]")),
                       ("none", head.replace("range = [-90, 90]\n", ""))):
        scene = tmp_path / f"{name}.toml"
        scene.write_text(body + ik, encoding="utf-8")
        mech = load_scene(scene).mechanism
        out[name] = certify_workspace(mech, lower, upper, 0.002, split=1, tighten=0)
    P = lower + np.random.default_rng(2).random((4000, 6)) * (upper - lower)
    q, _ = mech.inverse_kinematics(P)
    closes = mech.reach_margin(P) >= 0
    assert closes.any() and not closes.all()                   # the region crosses it
    assert np.all(np.abs(np.degrees(q[closes])) < 110)         # the ranges do not bind

    def shares(c):
        vol = np.prod(np.where(c.hi > c.lo, c.hi - c.lo, 1.0), axis=1)
        return [vol[c.status == k].sum() / vol.sum() for k in (0, 1, 2, 3)]
    np.testing.assert_allclose(shares(out["ranges"]), shares(out["none"]), rtol=1e-12)
    assert out["ranges"].evaluated <= 1.1 * out["none"].evaluated
