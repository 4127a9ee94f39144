"""The octahedral forward kinematics' JSON poses (QA 23 D3, D4, D6).

* ``count`` is the number of poses (DESIGN §4: a proved empty answer is ``poses: []``,
  ``count: 0``; the empty case is in test_no_assembly_answer.py), beside
  ``assembly_modes`` and ``real_roots.count`` (roots, not poses).
* A pose's ``max_leg_error`` is of the float64 ``points`` printed next to it (DESIGN §3:
  an accuracy statement is of the float number it stands beside): recomputed here from
  the JSON's points at 60 digits with mpmath, it bounds every leg's error and is not
  far above the worst.  The certified tier's own figure (6.5e-23, of the exact pose) is
  ``max_leg_error_solver``.
* ``side``: +1 when P5 lies on the side of the base plane that (P2-P1) x (P3-P1) points
  to, -1 for its mirror image; checked from the JSON's points.
"""

import json
from pathlib import Path

import mpmath
import pytest

from distkin.app.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "octahedral_griffis_duffy.toml"
# the example's geometry and legs (Rojas et al.; Fig. 4 labelling, docs/design.md §3)
BASE = [("0", "0", "0"), ("6", "sqrt(108)", "0"), ("12", "0", "0")]
LEGS = ["19.8", "18", "18", "17", "14.9", "17.8"]
PAIRS = [(1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6)]   # legs 1..6


@pytest.fixture(scope="module")
def doc(tmp_path_factory):
    out = tmp_path_factory.mktemp("gd") / "gd.json"
    assert main(["run", str(EXAMPLE), "--json", str(out)]) == 0
    return json.loads(out.read_text(encoding="utf-8"))


def _leg_errors(pose):
    with mpmath.workdps(60):
        pts = {i + 1: [mpmath.mpmathify(c) if c != "sqrt(108)" else mpmath.sqrt(108)
                       for c in row] for i, row in enumerate(BASE)}
        for k in (4, 5, 6):
            pts[k] = [mpmath.mpf(x) for x in pose["points"][f"P{k}"]]   # exact floats
        return [abs(mpmath.sqrt(sum((a - b) ** 2 for a, b in zip(pts[i], pts[j])))
                    - mpmath.mpf(leg))
                for (i, j), leg in zip(PAIRS, LEGS)]


def test_count_is_the_number_of_poses(doc):
    for q in doc["queries"]:
        r = q["result"]
        assert r["count"] == len(r["poses"]) == 12          # 6 modes x 2 mirror images
        assert r["assembly_modes"] == 6 and r["real_roots"]["count"] == 6


def test_max_leg_error_is_that_of_the_printed_points(doc):
    certified = doc["queries"][0]["result"]
    assert certified["method"] == "certified"
    for q in doc["queries"]:
        for pose in q["result"]["poses"]:
            worst = max(_leg_errors(pose))
            assert worst <= pose["max_leg_error"] <= 2 * worst + 1e-30
    # the certified tier's figure for the exact pose stays, under its own name
    assert all(p["max_leg_error_solver"] < 1e-20 for p in certified["poses"])
    assert certified["unit"]["max_leg_error_solver"] == certified["unit"]["max_leg_error"]


def test_side_is_the_side_of_the_base_plane(doc):
    import numpy as np
    b = np.array([[0, 0, 0], [6, 108 ** 0.5, 0], [12, 0, 0]])
    normal = np.cross(b[1] - b[0], b[2] - b[0])
    for pose in doc["queries"][0]["result"]["poses"]:
        above = float(np.dot(np.array(pose["points"]["P5"]) - b[0], normal))
        assert pose["side"] == (1 if above > 0 else -1)
    assert "(P2-P1) x (P3-P1)" in doc["queries"][0]["result"]["unit"]["side"]
