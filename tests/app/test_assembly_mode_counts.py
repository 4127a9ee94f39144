"""The forward-kinematics report's pose and mode counts (QA F 10): at a multiple root
several modes meet (the equilateral pair with six equal legs: roots of multiplicity
1, 3, 3, 1, sixteen distinct poses), and a flat mode is its own mirror image.  The
counts are checked against the poses the JSON lists (distinct point sets)."""

from __future__ import annotations

import itertools
import json

import numpy as np

from distkin.app.cli import main

HEAD = """
[units]
length = "none"
[mechanism]
kind = "octahedral"
"""


def _run(tmp_path, capsys, body):
    f = tmp_path / "s.toml"
    f.write_text(HEAD + body, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "o.json")])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads((tmp_path / "o.json").read_text())["queries"][0]["result"], out


def _distinct(poses):
    P = [np.array(p["points"]["P4"] + p["points"]["P5"] + p["points"]["P6"], float)
         for p in poses]
    return all(np.abs(a - b).max() > 1e-6 for a, b in itertools.combinations(P, 2))


def test_modes_at_a_multiple_root(tmp_path, capsys):
    r, out = _run(tmp_path, capsys, """
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
[[query]]
type = "forward_kinematics"
legs = [18, 18, 18, 18, 18, 18]
method = "precise"
""")
    assert len(r["poses"]) == 16 and _distinct(r["poses"])
    assert r["assembly_modes"] == 8                       # (it said 4: the roots)
    assert "16 poses (8 assembly modes x 2 mirror images in the base plane)" in out


def test_a_flat_mode_is_counted_once(tmp_path, capsys):
    r, out = _run(tmp_path, capsys, """
base = [[0, 0, 0], [10, 0, 0], [3, 8, 0]]
platform = [[0, 0, 0], [3, 1, 0], [1, 4, 0]]
[[query]]
type = "forward_kinematics"
legs = ["sqrt(5)", "sqrt(65)", "sqrt(29)", "sqrt(40)", "3", "sqrt(34)"]
method = "certified"
""")
    assert len(r["poses"]) == 1 and r["assembly_modes"] == 1
    assert all(abs(v) == 0 for k in ("P4", "P5", "P6") for v in [r["poses"][0]["points"][k][2]])
    assert "1 pose (1 assembly mode in the base plane, each its own mirror image)" in out
