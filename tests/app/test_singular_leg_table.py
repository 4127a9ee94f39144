"""A scene whose leg table is singular at every pose (QA 2026-12: six parallel legs of a
platform congruent to its base).  It loaded silently, the ``jacobian`` query printed
``kappa = 0`` beside "ok" with nothing naming the pose singular, and the forward
kinematics failed with a generic no-convergence message.  Now: a GeometryWarning at
load, the jacobian query names the pose singular (JSON ``singular``), and the FK's
error is a singular configuration.

References: the analytic J of vertical parallel legs at home (rows (0, 0, 1, p_y,
-p_x, 0): rank 3, so κ = 0 exactly), numpy's SVD of the J the JSON reports, and the
example's regular pose (its J of full rank)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import main
from distkin.errors import GeometryWarning
from distkin.indices import condition_number
from distkin.indices.zonotope import RANK_TOL

EXAMPLE = Path(__file__).parents[2] / "examples" / "gough_stewart_6ups.toml"


def _parallel_scene() -> str:
    """The 6-UPS example with every base joint right below its platform joint."""
    text = EXAMPLE.read_text(encoding="utf-8").split("[[query]]")[0]
    plats = iter(re.findall(r'platform = \[("[^"]+", "[^"]+"), 0\]', text))
    return re.sub(r"base = \[[^\]]*\]", lambda _: f"base = [{next(plats)}, 0]", text)


def _run(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text, encoding="utf-8")
    code = main(["run", str(f), "--no-progress", "--json", str(tmp_path / "out.json")])
    out, err = capsys.readouterr()
    return code, json.loads((tmp_path / "out.json").read_text())["queries"], out, err


def test_parallel_legs_warn_and_the_jacobian_names_the_singular_pose(tmp_path, capsys):
    q = ('[[query]]\ntype = "jacobian"\nposes = [[0, 0, 400, 0, 0, 0], '
         '[30, -20, 430, 5, -3, 10]]\n')
    with pytest.warns(GeometryWarning, match="architecturally singular"):
        code, queries, out, _ = _run(tmp_path, capsys, _parallel_scene() + q)
    assert code == 0
    rows = queries[0]["result"]["poses"]
    J0 = np.array(rows[0]["J"])
    # analytic: vertical unit lines, moments p x z = (p_y, -p_x, 0): columns x, y, rz zero
    np.testing.assert_array_equal(J0[:, [0, 1, 5]], 0.0)
    np.testing.assert_allclose(J0[:, 2], 1.0, rtol=1e-15)
    assert rows[0]["kappa"] == 0.0 and rows[0]["singular"] is True
    for r in rows:                     # numpy's SVD of the J reported: rank-deficient
        assert condition_number(np.array(r["J"])) <= RANK_TOL and r["singular"] is True
    lines = [line for line in out.splitlines() if "SINGULAR pose" in line]
    assert len(lines) == 2 and "J has rank 3 of 6" in lines[0]
    assert "J has rank 5 of 6" in lines[1]


def test_parallel_legs_forward_kinematics_says_singular(tmp_path, capsys):
    q = ('[[query]]\ntype = "forward_kinematics"\n'
         'angles = ["449.672992", "471.224532", "465.566713", "458.704719", "450.839781", '
         '"466.785149"]\nguess = [0, 0, 400, 0, 0, 0]\n')
    with pytest.warns(GeometryWarning):
        code, queries, out, err = _run(tmp_path, capsys, _parallel_scene() + q)
    assert code == 2
    e = queries[0]["error"]
    assert e["kind"] == "singular_configuration"      # was not_found, "no convergence"
    assert "the closure Jacobian is singular" in e["message"]
    assert "architecturally singular" in e["message"]


def test_a_regular_pose_is_not_called_singular(tmp_path, capsys):
    text = EXAMPLE.read_text(encoding="utf-8").split("[[query]]")[0]
    q = '[[query]]\ntype = "jacobian"\npose = [30, -20, 430, 5, -3, 10]\n'
    code, queries, out, _ = _run(tmp_path, capsys, text + q)
    assert code == 0
    row = queries[0]["result"]["poses"][0]
    assert row["singular"] is False
    assert row["kappa"] == pytest.approx(condition_number(np.array(row["J"])), rel=1e-12)
    assert row["kappa"] > 1e-3 and "SINGULAR" not in out
    assert queries[0]["result"]["unit"]["singular"].startswith("none")
