"""What the 6-6 forward kinematics (``kind = "platform66"`` and ``delta_transform`` with
``m_legs``) says about its answer: the reason of an empty answer, the proof verdict of
its count, and pose values at any length scale (QA V 1, 2, 5).

Independent references: the octahedral query on the l-legs that the m-legs map to by
eq. (8) (Rojas, Borràs, Thomas, *The Octahedral Manipulator Revisited*, Sec. V-VI),
the certified tier's count, and the poses' values in the JSON.
"""

import re
import warnings

import pytest

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene

GEOM = ('base = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]\n'
        'platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]\n')
OFFSETS = '["12/5", "6/5", "12/5", "6/5", "12/5", "6/5"]'
#: m-legs 1 map to the l-legs sqrt(745)/5, 1, ... (eq. (8)): no assembly
SHORT_M, SHORT_L = '[1, 1, 1, 1, 1, 1]', '["sqrt(745)/5", 1, "sqrt(745)/5", 1, "sqrt(745)/5", 1]'
#: m-legs mapping to six equal l-legs of 18: the equilateral octahedron's triple root
SYM_M = ('["sqrt(7524)/5", "sqrt(7956)/5", "sqrt(7524)/5", "sqrt(7956)/5", '
         '"sqrt(7524)/5", "sqrt(7956)/5"]')
GD_M = ('["6/25*sqrt(6170)", "6/5*sqrt(221)", "1/5*sqrt(7349)", "1/50*sqrt(674605)", '
        '"1/25*sqrt(136210)", "1/5*sqrt(8153)"]')


def _run(text):
    """(results, texts, the ConditioningWarnings that escaped to Python's warnings)."""
    from distkin.errors import ConditioningWarning
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        records, texts, worst = run_scene(loads_scene(text))
    assert worst == 0, texts
    escaped = [w for w in caught if issubclass(w.category, ConditioningWarning)]
    return [r["result"] for r in records], texts, escaped


def _p66(legs, method, unit="none"):
    return (f'[units]\nlength = "{unit}"\n[mechanism]\nkind = "platform66"\n{GEOM}'
            f'offsets = {OFFSETS}\n[[query]]\ntype = "forward_kinematics"\nlegs = {legs}\n'
            f'method = "{method}"\n')


def _octahedral(legs, method):
    return (f'[units]\nlength = "none"\n[mechanism]\nkind = "octahedral"\n{GEOM}'
            f'[[query]]\ntype = "forward_kinematics"\nlegs = {legs}\nmethod = "{method}"\n')


def _delta(legs, method):
    return (f'[units]\nlength = "none"\n[mechanism]\nkind = "octahedral"\n{GEOM}'
            f'[[query]]\ntype = "delta_transform"\noffsets = {OFFSETS}\nm_legs = {legs}\n'
            f'method = "{method}"\n')


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_no_pose_gives_the_octahedral_reason(method):
    """0 poses: the reason of the octahedral query on the mapped l-legs, in the JSON and
    the text, and no residual "over all poses" of no pose (QA V 1)."""
    (ref,), _, _ = _run(_octahedral(SHORT_L, method))
    assert ref["poses"] == [] and ref["reason"].startswith("cannot be assembled")
    (p66,), (t66,), _ = _run(_p66(SHORT_M, method))
    (dt,), (tdt,), _ = _run(_delta(SHORT_M, method))
    for res, text in ((p66, t66), (dt["forward_kinematics"], tdt)):
        assert res["count"] == 0 and res["poses"] == []
        assert res["reason"] == ref["reason"]
        assert res["certified"] == ref["certified"]
        assert ref["reason"] in text and "residual over all poses" not in text
        assert res["max_leg_error"] is None
    if method == "fast":          # the fast tier proves the empty answer, and says so
        assert ref["conditioning"]["trusted"] and p66["conditioning"]["trusted"]
        assert "the count: proved by the fast tier" in t66
        # the text names what JSON `certified: false` means (QA W 13)
        assert not p66["certified"] and "not by the certified tier" in t66
    else:
        assert p66["certified"] and "the count: certified" in t66


def test_fast_count_not_proved_is_flagged_as_the_octahedral_query_flags_it():
    """Six equal l-legs of 18: the fast tier finds 4 poses, the octic has a triple root
    at s15 = 252 it misses; the 6-6 answer carries the octahedral query's verdict
    (certified false, conditioning not trusted, the WARNING), and its warning goes into
    the result, not to stderr (QA V 2)."""
    (ref,), (ref_text,), _ = _run(_octahedral("[18, 18, 18, 18, 18, 18]", "fast"))
    assert not ref["certified"] and not ref["conditioning"]["trusted"]
    (p66,), (text,), escaped = _run(_p66(SYM_M, "fast"))
    assert escaped == []
    assert p66["count"] == len(ref["poses"])
    assert p66["certified"] is False
    assert p66["conditioning"]["trusted"] is False
    assert p66["conditioning"]["reason"] == ref["conditioning"]["reason"]
    assert f"WARNING: {ref['conditioning']['reason']}; the count may be wrong" in text
    assert "WARNING" in ref_text
    assert any("not proved" in n for n in p66["notes"])
    (dt,), (dtext,), escaped = _run(_delta(SYM_M, "fast"))
    assert escaped == [] and dt["forward_kinematics"]["conditioning"]["trusted"] is False
    assert "the count may be wrong" in dtext
    # and the count was indeed wrong: auto finds the three modes at s15 = 252 too
    (auto,), _, _ = _run(_p66(SYM_M, "auto"))
    assert auto["count"] > p66["count"]
    assert sum(abs(q["s15"] - 252) < 1e-9 for q in auto["poses"]) >= 2


def test_fast_count_proved_agrees_with_the_certified_count():
    """The Griffis-Duffy example (Sec. VI): the fast count is proved, and is the
    certified tier's."""
    (fast,), (text,), escaped = _run(_p66(GD_M, "fast"))
    (cert,), _, _ = _run(_p66(GD_M, "certified"))
    assert escaped == [] and fast["conditioning"]["trusted"] and "WARNING" not in text
    assert cert["certified"] and fast["count"] == cert["count"] == 12


_POSE = re.compile(r"pose +\d+: s15 = (\S+) m\^2, t = \(([^)]*)\) m")


@pytest.mark.parametrize("scale", ["1/1000000", "1/100000000000"])
def test_pose_lines_keep_their_digits_at_small_scales(scale):
    """A micrometre-scale (and 1e-11) scene: the text's s15 and translation are the
    JSON's to 6 digits (fixed-point printed 0.0000 and 0.000006, QA V 5)."""
    text = (f'[units]\nlength = "m"\n[mechanism]\nkind = "platform66"\n'
            f'base = [[0,0,0], ["6*{scale}","sqrt(108)*{scale}",0], ["12*{scale}",0,0]]\n'
            f'platform = [[0,0,0], ["6*{scale}",0,0], ["3*{scale}","sqrt(27)*{scale}",0]]\n'
            f'offsets = {[f"{o}*{scale}" for o in ("12/5", "6/5") * 3]}\n'.replace("'", '"')
            + '[[query]]\ntype = "forward_kinematics"\nlegs = '
            + str([f"{m}*{scale}" for m in GD_M.strip("[]").replace('"', "").split(", ")]
                  ).replace("'", '"') + '\nmethod = "certified"\n')
    (res,), (report,), _ = _run(text)
    shown = _POSE.findall(report)
    assert len(shown) == res["count"] == 12
    for (s15, t), pose in zip(shown, res["poses"]):
        assert float(s15) == pytest.approx(pose["s15"], rel=1e-6)
        assert [float(x) for x in t.split(",")] == pytest.approx(list(pose["translation"]),
                                                                 rel=1e-6)
