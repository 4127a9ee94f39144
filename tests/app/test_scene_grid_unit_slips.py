"""Unit slips in study grids and design-sweep ranges (QA r06): `grid = { half = 0.025,
step = 0.025 }` in a mm scene (25 mm meant) ran silently and reported a dexterous
workspace of "0 cm³ of 0 cm³"; `ld = [0.02, 0.04, 0.005]` said "optimum: ... ld = 0.0
mm".  Now one warning line per slipped value at load time, with the test and words of
the mechanism overrides' (more than SLIP_RATIO = 100 times off: here the device's
length scale lp = 55 mm and Table I's largest l2 = 30 mm, ld = 40 mm, Kühne et al.
Table I), and the printed values keep their digits.  The example scenes are loaded
only (their studies take minutes)."""

from __future__ import annotations

from pathlib import Path

import pytest

from distkin.app.scene import load_scene, loads_scene

ROOT = Path(__file__).resolve().parents[2]

HEAD = """[units]
length = "{length}"
angle = "deg"
[mechanism]
kind = "rss"
preset = "{preset}"
[[query]]
"""

PERF = HEAD + """type = "performance"
devices = [ {{ label = "Hunt-type", preset = "hunt", rotation = 10 }},
            {{ label = "HEXA", preset = "hexa", rotation = 10 }} ]
grid = {{ {grid}, rotation_step = 10 }}
"""

SWEEP = HEAD + """type = "design_sweep"
base = "hunt"
l2 = {l2}
beta = [0, 30, 10]
gamma = [0, 30, 10]
ld = {ld}
grid = {{ {grid}, rotation = 10, rotation_step = 10 }}
algorithm = "culling"
"""


def _warnings(capsys, text):
    loads_scene(text)
    return [ln for ln in capsys.readouterr().err.splitlines()
            if ln.startswith("distkin: warning: ")]


@pytest.mark.parametrize("length, grid, slipped", [
    ("mm", "half = 0.025, step = 0.025", ["half", "step"]),      # QA r06a
    ("mm", "half = 75, step = 25", []),
    ("mm", "half = 0, step = 0.025", []),                          # one position: no step
    ("m", "half = 0.075, step = 0.025", []),
    ("m", "half = 0.075e-3, step = 0.025e-3", ["half", "step"]),
    ("mm", "half = 5, step = 0.25", ["step"]),
])
def test_a_performance_grid_unit_slip_warns_once_per_value(capsys, length, grid, slipped):
    lines = _warnings(capsys, PERF.format(length=length, preset="octopod", grid=grid))
    assert [ln.split(": ")[2].split(".")[-1] for ln in lines] == slipped   # two devices
    lp_mm = 55.0                                  # the presets' lp (Kühne et al., Table I)
    for ln, key in zip(lines, slipped):
        written = float(grid.split(f"{key} = ")[1].split(",")[0])
        ratio = written * (1e3 if length == "m" else 1.0) / lp_mm
        assert ln.startswith(f"distkin: warning: query[0].grid.{key}: ")
        assert f"is {ratio:.3g} x the device's length scale" in ln
        assert f'the scene\'s [units] length is "{length}"' in ln


@pytest.mark.parametrize("l2, ld, slipped", [
    ("[0, 0.03, 0.005]", "[0.02, 0.04, 0.005]", ["l2[1]", "ld[1]"]),   # QA r06b
    ("[0, 30, 5]", "[0.02, 0.04, 0.005]", ["ld[1]"]),
    ("[0, 30, 5]", "[20, 40, 5]", []),
    ("[0, 0, 5]", "[20, 20, 5]", []),
])
def test_a_design_sweep_range_unit_slip_warns(capsys, l2, ld, slipped):
    lines = _warnings(capsys, SWEEP.format(length="mm", preset="hunt", l2=l2, ld=ld,
                                           grid="half = 25, step = 25"))
    assert [ln.split(": ")[2].removeprefix("query[0].") for ln in lines] == slipped
    table1_max = {"l2[1]": 30.0, "ld[1]": 40.0}
    for ln, key in zip(lines, slipped):
        hi = float((l2 if key == "l2[1]" else ld).strip("[]").split(",")[1])
        assert f"is {hi / table1_max[key]:.3g} x Table I's largest" in ln


def test_a_design_sweep_grid_unit_slip_warns(capsys):
    lines = _warnings(capsys, SWEEP.format(length="mm", preset="hunt", l2="[0, 30, 5]",
                                           ld="[20, 40, 5]", grid="half = 0.025, step = 0.025"))
    assert [ln.split(": ")[2] for ln in lines] == ["query[0].grid.half", "query[0].grid.step"]


@pytest.mark.parametrize("name", ["octopod_study_coarse.toml", "octopod_design_sweep.toml",
                                  "octopod_study.toml"])
def test_the_example_studies_load_without_a_warning(capsys, name):
    load_scene(ROOT / "examples" / name)
    assert "distkin: warning" not in capsys.readouterr().err


def test_printed_values_keep_their_digits():
    from distkin.app.design_report import _digits
    from distkin.app.study_report import _cm3
    # Table I's values as before, one decimal
    assert [_digits(x) for x in (0.0, 20.0, 25.0, 12.5, 30.0)] == \
        ["0.0", "20.0", "25.0", "12.5", "30.0"]
    # a sweep in the wrong unit: 0.02 mm, not "0.0 mm"
    assert [_digits(x) for x in (0.02, 0.025, 1e-4)] == ["0.02", "0.025", "0.0001"]
    # 15³ cells of 10 mm = 3375 cm³ (as before); (0.05 mm)³ = 1.25e-7 cm³, not "0"
    assert _cm3(3375e-6) == "3375" and _cm3(0.0) == "0"
    assert _cm3(0.05e-3 ** 3) == "1.25e-07"
