"""The ``singularity`` query on a leg table says what it decided and for which pose
(QA: the Δ 6-6 platform's crossing at the 90° twist read "det J certified < 0,
singular: no" while its octahedral twin read "singular: undecided" and README says both
are singular there).  Every tier evaluates det J at the float64-rounded pose, and a path's
crossing is located on the float64 det J: the verdict is that pose's, and the report (text
and JSON alike) must say so, for both scenes.

Reference (independent of the query): det J at the exact 90° pose, in sympy, of the
octahedral table (Rojas et al. Sec. VI) and of its Δ 6-6 platform (joints from
:func:`distkin.delta.equivalent_platform`, exact): 0, so the crossing is a singular
pose, which a certified "< 0" at its rounded pose must not be read as denying."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import sympy as sp

from distkin.app.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
S3 = sp.sqrt(3)
BASE = [[0, 0, 0], [6, sp.sqrt(108), 0], [12, 0, 0]]
PLAT = [[0, 0, 0], [6, 0, 0], [3, sp.sqrt(27), 0]]


def _exact_det_at_twist(kind):
    """det of the unnormalised Plücker rows (p - b, b x (p - b)) at translation
    (6, sqrt(12), 17) of the platform triangle's centroid and a 90° turn about z."""
    if kind == "delta66":
        from distkin.delta import equivalent_platform
        plat = equivalent_platform((BASE, PLAT), [sp.Rational(12, 5), sp.Rational(6, 5)] * 3)
        legs = list(zip(plat.base_joints, plat.platform_joints))
    else:                                  # leg k = P_i P_j (docs: 14 24 25 35 36 16)
        legs = [(BASE[i - 1], PLAT[j - 4]) for i, j in
                ((1, 4), (2, 4), (2, 5), (3, 5), (3, 6), (1, 6))]
    R = sp.Matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    origin, t = sp.Matrix([3, S3, 0]), sp.Matrix([6, sp.sqrt(12), 17])
    rows = []
    for b, q in legs:
        b = sp.Matrix([sp.nsimplify(x) for x in b])
        p = t + R * (sp.Matrix([sp.nsimplify(x) for x in q]) - origin)
        u = p - b
        rows.append(list(u) + list(b.cross(u)))
    return sp.simplify(sp.Matrix(rows).det())


def _run(tmp_path, capsys, name):
    text = (EXAMPLES / f"{name}.toml").read_text(encoding="utf-8")
    head, last = text.split("[[query]]")[0], text.split("[[query]]")[-1]
    assert 'type = "singularity"' in last and "path" in last
    scene = tmp_path / f"{name}.toml"
    scene.write_text(head + "[[query]]" + last, encoding="utf-8")
    out_json = tmp_path / "o.json"
    assert main(["run", str(scene), "--no-progress", "--json", str(out_json)]) == 0
    out = capsys.readouterr().out
    return json.loads(out_json.read_text())["queries"][0]["result"], out


@pytest.mark.parametrize("name, kind", [("delta66_indices", "delta66"),
                                        ("griffis_duffy_indices", "octahedral")])
def test_crossing_verdict_says_it_is_the_rounded_pose(tmp_path, capsys, name, kind):
    assert _exact_det_at_twist(kind) == 0            # the exact 90° pose is singular
    res, out = _run(tmp_path, capsys, name)
    (c,) = res["crossings"]
    assert c["pose"][5] == pytest.approx(math.pi / 2, abs=1e-9)
    assert c["decided_at"] == "the float64-rounded pose" and c["near_singular"] is True
    # a certified "not singular" (delta66) or "undecided" (octahedral) is said to be the
    # rounded pose's, with the near-singularity and where the crossing lies
    assert c["singular"] is not True
    v = c["verdict"]
    assert v.startswith("at the float64-rounded pose: ")
    assert "near-singular" in v and "the verdict is this pose's, not the crossing's" in v
    line = next(x for x in out.splitlines() if "crossing at" in x)
    assert line.endswith(v)                            # text and JSON say the same
    # no bare "singular: no" / "undecided" that does not say for which pose
    before = line[: line.index(v)]
    assert "singular:" not in before


def test_both_scenes_decide_the_same_way_at_the_twist(tmp_path, capsys):
    """Consistency: the octahedral table and its Δ 6-6 platform (det(AJ) = det(A)
    det(J), Sec. IV) get verdicts of the same form at the same crossing."""
    verdicts = []
    for name in ("delta66_indices", "griffis_duffy_indices"):
        res, _ = _run(tmp_path, capsys, name)
        verdicts.append(res["crossings"][0]["verdict"])
    tail = lambda v: v[v.index("; |det J| <"):]        # noqa: E731
    assert tail(verdicts[0]) == tail(verdicts[1])
