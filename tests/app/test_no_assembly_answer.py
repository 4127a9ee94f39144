"""A proved empty answer is an answer (QA report M, finding 2; docs/design.md §4).

The same situation, legs that admit no assembly, gave exit 0 for ``kind = "octahedral"``,
exit 2 for ``platform66`` and exit 2 with a Gauss-Newton divergence for a ``legs`` table
with the octahedral topology.  Now all three are status ok, exit 0, 0 poses, with the
reason.  The independent reference: a triangle inequality that the legs violate (a path
base joint -> platform joint -> platform joint -> base joint shorter than the straight
line), so no pose can exist, checked here from the geometry alone.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from distkin.app.cli import main

GEOM = 'base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]\nplatform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]'
LEGS = [1, 1, 1, 1, 1, 100]


def _run(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text)
    code = main(["run", str(f), "--json", str(tmp_path / "out.json")])
    err = capsys.readouterr().err
    return code, json.loads((tmp_path / "out.json").read_text())["queries"][0], err


def test_no_assembly_is_impossible_by_the_triangle_inequality():
    """Legs 1 = P1P4 and 2 = P2P4 of length 1 cannot meet at P4: |P1P2| = 12 > 1 + 1."""
    assert math.dist((0, 0, 0), (6, math.sqrt(108), 0)) > LEGS[0] + LEGS[1]


@pytest.mark.parametrize("kind", ["octahedral", "legs"])
def test_octahedral_and_octahedral_legs_answer_no_pose(tmp_path, capsys, kind):
    if kind == "octahedral":
        text = (f'[mechanism]\nkind = "octahedral"\n{GEOM}\n[[query]]\ntype = '
                f'"forward_kinematics"\nlegs = {LEGS}\nmethod = "certified"\n')
    else:
        text = (f'[units]\nlength = "cm"\n[mechanism]\nkind = "legs"\nroute = "numpy"\n'
                f'octahedral = {{ {GEOM.replace(chr(10), ", ")} }}\nheight = 17\n'
                f'[[query]]\ntype = "forward_kinematics"\nangles = {LEGS}\n')
    code, rec, err = _run(tmp_path, capsys, text)
    assert code == 0 and rec["status"] == "ok", err
    assert rec["result"]["poses"] == []
    assert "cannot be assembled" in rec["result"]["reason"]
    # DESIGN §4: a proved empty answer is `poses: []`, `count: 0` (QA 23 D3: the
    # octahedral result had no count)
    assert rec["result"]["count"] == 0
    if kind == "legs":
        assert rec["result"]["pose"] is None
        assert "exact octic" in rec["result"]["reason"]


def test_legs_octahedral_certified_says_certified(tmp_path, capsys):
    text = (f'[mechanism]\nkind = "legs"\nroute = "generated"\n'
            f'octahedral = {{ {GEOM.replace(chr(10), ", ")} }}\nheight = 17\n'
            f'[[query]]\ntype = "forward_kinematics"\nangles = {LEGS}\nmethod = "certified"\n')
    code, rec, err = _run(tmp_path, capsys, text)
    assert code == 0 and rec["status"] == "ok", err
    assert rec["result"]["tier"] == "certified" and rec["result"]["poses"] == []


def test_platform66_answers_no_pose(tmp_path, capsys):
    from distkin.delta import equivalent_platform
    offsets = ["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]
    text = (f'[mechanism]\nkind = "platform66"\n{GEOM}\noffsets = {json.dumps(offsets)}\n'
            f'[[query]]\ntype = "forward_kinematics"\nlegs = {LEGS}\nmethod = "fast"\n')
    code, rec, err = _run(tmp_path, capsys, text)
    assert code == 0 and rec["status"] == "ok", err
    assert rec["result"]["count"] == 0 and rec["result"]["poses"] == []
    assert "eq. (8)" in rec["result"]["reason"]
    # independently: some pair of legs i, j cannot close the path b_i p_i p_j b_j
    base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
    plat = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
    b, p = equivalent_platform((base, plat), offsets).joints()
    m = np.array(LEGS, dtype=float)
    gap = max(np.linalg.norm(b[i] - b[j]) - (m[i] + m[j] + np.linalg.norm(p[i] - p[j]))
              for i in range(6) for j in range(6))
    assert gap > 0
