"""Values of the wrong TOML type or beyond float64 in a scene are bad input, never an
internal failure (QA, found by replacing each value of the examples: ``kind = ["rss"]``
and ``[units] length = ["mm"]`` raised TypeError (unhashable), a performance grid's
``half = 1e308`` OverflowError (2 half / step is inf))."""

import subprocess
import sys

import pytest

from distkin.app.scene import loads_scene
from distkin.errors import InputError

RSS = '[mechanism]\nkind = "rss"\npreset = "hunt"\n'
IK = '[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 0.3, 0, 0, 0]\n'


@pytest.mark.parametrize("text, field, got", [
    ('[mechanism]\nkind = ["rss"]\n' + IK, "mechanism.kind", "got ['rss']"),
    ('[mechanism]\nkind = { name = "rss" }\n' + IK, "mechanism.kind", "got {'name': 'rss'}"),
    ('[units]\nlength = ["mm"]\n' + RSS + IK, "units.length", "got ['mm']"),
    ('[units]\nangle = { deg = 1 }\n' + RSS + IK, "units.angle", "got {'deg': 1}"),
])
def test_a_name_given_as_a_list_or_table_is_refused_naming_the_field(text, field, got):
    with pytest.raises(InputError) as err:
        loads_scene(text)
    assert err.value.field == field and "expected " in err.value.one_line()
    assert got in err.value.one_line()


def _performance(grid):
    return ('[units]\nlength = "mm"\nangle = "deg"\n' + RSS +
            f'[[query]]\ntype = "performance"\ndevices = [{{ label = "Hunt", preset = "hunt", rotation = 20 }}]\ngrid = {{ {grid} }}\n')


@pytest.mark.parametrize("grid, field, words", [
    # 1e308 mm is 1e305 m: 2 half / step overflowed before the reach check ran
    ("half = 1e308, step = 25", "query[0].grid.half", "expected a half of at most"),
    # a subnormal step: 2 half / step is inf though both are finite
    ("half = 75, step = 1e-320", "query[0].grid.step", "finite"),
])
def test_a_grid_beyond_float64_is_refused_naming_the_field(grid, field, words):
    with pytest.raises(InputError) as err:
        loads_scene(_performance(grid))
    assert err.value.field == field and words in err.value.one_line()


def test_the_cli_exits_2_with_one_line(tmp_path):
    (tmp_path / "s.toml").write_text('[mechanism]\nkind = ["rss"]\n' + IK)
    r = subprocess.run([sys.executable, "-m", "distkin", "run", "s.toml"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [
        "distkin: error: mechanism.kind: expected one of 'points', 'octahedral', 'rss', "
        "'legs', 'platform66', got ['rss']"]


@pytest.mark.parametrize("where", ["translation", "rotation"])
def test_a_singularity_pose_beyond_float64_is_refused_naming_the_component(where):
    """QA: '1e400' in a singularity path's pose was OverflowError (float of the exact
    value in the size check)."""
    vec = {"translation": '[3, "1e400", 10]', "rotation": '[180, "-1e400", 0]'}
    other = "rotation" if where == "translation" else "translation"
    scene = ('[units]\nlength = "none"\n[mechanism]\nkind = "octahedral"\n'
             'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
             'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n'
             '[[query]]\ntype = "singularity"\n'
             f'pose = {{ {where} = {vec[where]}, {other} = [0, 0, 1] }}\n')
    with pytest.raises(InputError) as err:
        loads_scene(scene)
    assert err.value.field == f"query[0].pose.{where}[1]"
    assert "float64 range" in err.value.one_line()


@pytest.mark.parametrize("kind, extra", [("octahedral", ""),
                                         ("platform66", 'offsets = ["12/5", "6/5", "12/5", '
                                                        '"6/5", "12/5", "6/5"]\n')])
def test_a_platform_coordinate_beyond_float64_is_refused_for_both_kinds(kind, extra):
    """QA: kind = "octahedral" refused base = [["1e400", 0, 0], ...] at load; kind =
    "platform66" took it and answered "0 poses, cannot be assembled"."""
    scene = (f'[mechanism]\nkind = "{kind}"\n'
             'base = [["1e400", 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
             'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n' + extra +
             '[[query]]\ntype = "forward_kinematics"\nlegs = [18, 18, 18, 17, 15, 18]\n')
    with pytest.raises(InputError) as err:
        loads_scene(scene)
    assert err.value.field == "mechanism.base[0][0]" and "float64 range" in err.value.one_line()


@pytest.mark.parametrize("text", ["", "\n# only a comment\n", "   \n"])
def test_an_empty_scene_says_so(text):
    with pytest.raises(InputError) as err:
        loads_scene(text)
    assert err.value.field == "scene" and "empty scene" in err.value.one_line()
