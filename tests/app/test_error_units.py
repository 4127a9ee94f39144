"""Errors say lengths in the scene's unit, as its report does (QA: an rss octopod scene
in mm refused its angles with "rms closure error 0.0811 m"; a platform66 scene with no
[units], whose report prints "m", refused an offset with "(length units)").  References:
the same scene written in another unit (a second route: the number scales by the
unit's factor), and the scene's own input (the offset and the side it was checked
against)."""

from __future__ import annotations

import re

import pytest

from distkin.app.cli import run_scene
from distkin.app.scene import loads_scene
from distkin.errors import DistkinError

RSS = """
[units]
length = "{unit}"
angle = "deg"

[mechanism]
kind = "rss"
preset = "octopod"

[[query]]
type = "forward_kinematics"
angles = [170, -60, 10, 90, 170, -60, 10, 90]
"""

P66 = """{units}
[mechanism]
kind = "platform66"
base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]
platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]
offsets = [{offset}, "6/5", "12/5", "6/5", "12/5", "6/5"]

[[query]]
type = "forward_kinematics"
legs = ["19", "18", "18", "17", "15", "18"]
"""


def _residual(unit):
    records, _, worst = run_scene(loads_scene(RSS.format(unit=unit)), progress=False)
    assert worst == 2
    err = records[0]["error"]
    assert err["kind"] == "not_found"
    m = re.search(r"rms closure error ([0-9.e+-]+) (\w+)\)", err["message"])
    assert m, err["message"]
    return float(m.group(1)), m.group(2)


def test_rss_not_found_says_its_residual_in_the_scene_unit():
    mm, unit_mm = _residual("mm")
    m, unit_m = _residual("m")
    assert (unit_mm, unit_m) == ("mm", "m")
    # the preset is SI: the same residual, written in each scene's unit (3 digits)
    assert mm == pytest.approx(1000 * m, rel=5e-3)


@pytest.mark.parametrize("units, name", [("", "m"), ('[units]\nlength = "mm"\n', "mm"),
                                         ('[units]\nlength = "cm"\n', "cm")])
def test_platform66_offset_refusal_names_the_scene_unit(units, name):
    with pytest.raises(DistkinError) as info:
        loads_scene(P66.format(units=units, offset='"15"'))
    msg = str(info.value)
    assert msg.startswith("mechanism.offsets[0]: ")
    # the scene's own numbers: the side P1P2 = |(6, sqrt(108), 0)| = 12 and delta1 = 15
    assert f"d12 = 12 {name} " in msg and f"got delta1 = 15 {name}" in msg
    assert "length units" not in msg


def test_platform66_offset_refusal_in_a_unitless_scene_keeps_length_units():
    with pytest.raises(DistkinError) as info:
        loads_scene(P66.format(units='[units]\nlength = "none"\n', offset='"15"'))
    assert "d12 = 12 (length units)" in str(info.value)


def test_delta_transform_offsets_refusal_names_the_scene_unit():
    text = ('[units]\nlength = "mm"\n[mechanism]\nkind = "octahedral"\n'
            'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
            'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
            '[[query]]\ntype = "forward_kinematics"\nlegs = ["19.8", "18", "18", "17", '
            '"14.9", "17.8"]\n[[query]]\ntype = "delta_transform"\n'
            'offsets = ["12/5", "7", "12/5", "6/5", "12/5", "6/5"]\n')
    with pytest.raises(DistkinError) as info:
        loads_scene(text)
    msg = str(info.value)
    # the platform side P4P5 = 6 (the scene's platform) and delta2 = 7 as written
    assert msg.startswith("query[1].offsets[1]: ")
    assert "= 6 mm " in msg and "got delta2 = 7 mm" in msg and "length units" not in msg
