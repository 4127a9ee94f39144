"""Radians written in a deg scene (``rotation = 0.35``, a pose's ``0.26, -0.17, 0.35``)
passed silently: now one GeometryWarning naming the field when every nonzero angle of a
pose or range is below π/2 in magnitude (the largest at least 0.01) and none is a round
number of degrees (a multiple of 0.1° or 0.25°), the reverse of :func:`distkin.app.units.degrees_hint`.
Conservative: a round or large angle, a rad scene, or no nonzero angle says nothing,
and no example scene warns (loaded only: their queries take minutes).

Reference: the conversions of the angles written, computed here with ``math.degrees``
and ``math.radians``."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import pytest

from distkin.app.scene import load_scene, loads_scene
from distkin.app.units import Units, radians_hint
from distkin.errors import GeometryWarning

ROOT = Path(__file__).resolve().parents[2]

HEAD = """[units]
length = "mm"
angle = "{angle}"
[mechanism]
kind = "rss"
preset = "octopod"
[[query]]
"""


def _loaded(text):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        loads_scene(text)
    return [str(w.message) for w in rec if issubclass(w.category, GeometryWarning)]


@pytest.mark.parametrize("query, field, big", [
    ('type = "inverse_kinematics"\npose = [40, -30, 330, 0.26, -0.17, 0.35]',
     "query[0].pose", 0.35),
    ('type = "jacobian"\nposes = [[0, 0, 300, 0, 0, 0], [40, -30, 330, 0.12, 0, 0.45]]',
     "query[0].poses", 0.45),
    ('type = "forward_kinematics"\nangles = [19, 21, 31, 32, 31, 31, 19, 20]\n'
     'guess = [0, 0, 300, 0.05, 0, 0]', "query[0].guess", 0.05),
    ('type = "performance"\ndevices = [ { label = "Hunt", preset = "hunt", '
     'rotation = 0.35 } ]\ngrid = { half = 0, rotation = 0.35, rotation_step = 0.35 }',
     "query[0].grid.rotation and rotation_step", 0.35),
])
def test_radians_in_a_deg_scene_warn_naming_the_field(query, field, big):
    (msg,) = [m for m in _loaded(HEAD.format(angle="deg") + query) if m.startswith(field)]
    assert "radians? the scene's [units] angle is \"deg\"" in msg
    assert f"{big:g} deg is {math.radians(big):.4g} rad" in msg
    assert f"{big:g} rad would be {math.degrees(big):.4g} deg" in msg


@pytest.mark.parametrize("angle, pose", [
    ("deg", "[40, -30, 330, 15, -10, 20]"),         # degrees
    ("deg", "[40, -30, 330, 0.5, -0.25, 0.1]"),     # small, but round degrees
    ("deg", "[40, -30, 330, 0.35, 0, 20]"),         # one large angle: degrees
    ("deg", "[40, -30, 330, 0, 0, 0]"),             # no rotation
    ("rad", "[40, -30, 330, 0.26, -0.17, 0.35]"),   # radians in a rad scene
])
def test_ordinary_poses_do_not_warn(angle, pose):
    text = HEAD.format(angle=angle) + f'type = "inverse_kinematics"\npose = {pose}'
    assert _loaded(text) == []


def test_the_rule_on_its_own():
    deg, rad = Units("mm", "deg"), Units("mm", "rad")
    assert radians_hint([0.26, -0.17, 0.35], deg) is not None
    assert radians_hint([0.26, -0.17, 0.35], rad) is None
    assert radians_hint([0.3, 0.2], deg) is None                  # multiples of 0.1 deg
    assert radians_hint([1.6, 0.35], deg) is None                 # 1.6 > π/2
    assert radians_hint([math.pi / 2 - 0.01, 0.35], deg) is not None
    assert radians_hint([0.001, 0.001], deg) is None              # both readings < 0.6 deg
    assert radians_hint([0.012, 0.003], deg) is not None


def test_no_example_scene_warns():
    for path in sorted((ROOT / "examples").glob("*.toml")):
        if "[device]" in path.read_text(encoding="utf-8"):
            continue                                   # controller scenes: not run scenes
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            load_scene(path)
        assert not [w for w in rec if "radians?" in str(w.message)], path.name
