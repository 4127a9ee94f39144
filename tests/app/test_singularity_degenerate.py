"""The ``singularity`` scene query at degenerate but legitimate poses (Rojas et al.,
Sec. IV): the platform in the base plane is a singular pose, reported as such with the
tests that are undefined there named; a zero-length leg is bad input (exit 2, one line
naming the leg).  Expected values come from the geometry (all points in z = 0: det J =
0; P4 the midpoint of P1P2: plane P1P2P4 undefined), not from the program's output."""

from __future__ import annotations

import json

from distkin.app.cli import main

SCENE = """
[units]
length = "none"
angle = "deg"
[mechanism]
kind = "octahedral"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
[[query]]
type = "singularity"
"""


def _run(tmp_path, capsys, query):
    f = tmp_path / "s.toml"
    f.write_text(SCENE + query, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "out.json")])
    out, err = capsys.readouterr()
    return code, json.loads((tmp_path / "out.json").read_text())["queries"][0], out, err


def test_platform_in_the_base_plane_is_reported_singular(tmp_path, capsys):
    # P4 = t = (3, 3 sqrt 3, 0) is the midpoint of P1P2, P5 of P2P3: all in z = 0
    code, q, out, err = _run(tmp_path, capsys, 'pose = { translation = [3, "sqrt(27)", 0], '
                                               'rotation = [0, 0, 0] }\nmethod = "certified"\n')
    assert code == 0, err
    r = q["result"]
    assert r["det_J"] == 0.0 and r["singular"] is True and r["sigma_min"] < 1e-12
    assert r["certified_sign_det_J"] == 0                  # exact: zero columns of Jhat
    assert r["cm_condition_relative"] is None and "P1P2P4P5" in r["undefined"]["cm_condition_relative"]
    assert r["four_planes"]["relative"] is None
    assert "P1P2P4 (P1, P2, P4 collinear)" in r["undefined"]["four_planes"]
    assert "a singular pose" in out and "four planes: undefined" in out


def test_path_from_the_base_plane_names_the_undefined_samples(tmp_path, capsys):
    code, q, out, err = _run(tmp_path, capsys,
                             'path = { from = { translation = [3, "sqrt(27)", 0], '
                             'rotation = [0, 0, 0] }, to = { translation = [3, "sqrt(27)", 6], '
                             'rotation = [0, 0, 0] }, samples = 5 }\n')
    assert code == 0, err
    assert "undefined at s = 0:" in out                    # only the flat start


def test_zero_length_leg_is_exit_2_naming_the_leg(tmp_path, capsys):
    # t = 0 puts P4 on P1: leg 1 (P1-P4) has length 0
    f = tmp_path / "z.toml"
    f.write_text(SCENE + 'pose = { translation = [0, 0, 0], rotation = [0, 0, 0] }\n',
                 encoding="utf-8")
    code = main(["run", str(f), "--no-progress"])
    _, err = capsys.readouterr()
    assert code == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "query[0].pose" in lines[0] and "leg 1 (P1–P4)" in lines[0]
    assert "Traceback" not in err


def test_a_path_along_the_singular_locus_reports_no_crossings(tmp_path, capsys):
    """QA F 07: the platform parallel to the base, turned about the vertical: every pose
    of the path is singular (independent check: numpy's smallest singular value of the
    Plücker matrix is at round-off).  Its round-off sign changes were 29 "crossings"."""
    import numpy as np
    from distkin.singularity import octahedral_joints, plucker_jacobian
    q = ('path = { from = { translation = [3, 1.7, 15], rotation = [0, 0, 0] }, '
         'to = { translation = [3, 1.7, 15], rotation = [0, 0, 120] }, samples = 40 }\n'
         'method = "fast"\n')
    code, rec, out, err = _run(tmp_path, capsys, q)
    assert code == 0, err
    r = rec["result"]
    assert r["crossings"] == [] and r["on_singular_locus"] and r["samples_on_locus"] == 40
    assert r["cm_spurious_roots"] == []
    assert "the whole path lies on the singular locus" in out
    base = np.array([[0, 0, 0], [6, np.sqrt(108), 0], [12, 0, 0]])
    plat = np.array([[0, 0, 0], [6, 0, 0], [3, np.sqrt(27), 0]])
    for deg in (0, 47, 120):
        c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
        R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        pts = np.vstack([base, plat @ R.T + [3, 1.7, 15]])
        J = plucker_jacobian(*octahedral_joints(pts[None]), normalised=True)[0]
        assert np.linalg.svd(J, compute_uv=False)[-1] < 1e-12
