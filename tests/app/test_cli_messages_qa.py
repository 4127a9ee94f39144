"""User-facing messages of the CLI (QA round "cli"):

1. the kappa line named ST without units and not where it comes from;
2. a GeometryWarning printed in Python's raw format (``/path/file.py:10: GeometryWarning:``);
3. "lengths in this message in m (SI)" appended to messages holding no length;
4. a joint value just beyond a stroke end printed rounded onto the end ("550 mm outside
   its range [350, 550] mm");
5. a CSV with trailing commas or ';' separators;
6. degrees written in a scene whose angles are in rad, refused without a word on units.

References: Kühne et al. Sec. III-B-2 for ST (diag[15N 15N 15N 1N·m 1N·m 1N·m]), numpy's
SVD of the JSON's J for kappa, numpy's norms of the scene's leg vectors for the
warning's lengths, the scene's declared stroke for the refusal, and the same CSV
written without the slip for the rows read.
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from distkin.app.cli import format_warning, main
from distkin.app.csv_rows import csv_rows
from distkin.app.design_report import scaling_note
from distkin.app.scene import loads_scene
from distkin.app.units import Units, has_si_length, si_length_hint
from distkin.errors import GeometryWarning, InputError
from distkin.numfmt import apart

ROOT = Path(__file__).resolve().parents[2]

#: Kühne et al. Sec. III-B-2: "ST = diag[15N 15N 15N 1N·m 1N·m 1N·m]"
PAPER_ST = "diag(15 N, 15 N, 15 N, 1 N·m, 1 N·m, 1 N·m)"


def _example(name: str, queries: str) -> str:
    text = (ROOT / "examples" / name).read_text()
    return text[:text.index("[[query]]")] + queries


def _run(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text)
    out = tmp_path / "out.json"
    code = main(["run", str(f), "--json", str(out), "--no-progress"])
    cap = capsys.readouterr()
    return code, json.loads(out.read_text())["queries"], cap.out, cap.err


# 1 ------------------------------------------------------------------ the kappa line
def test_kappa_line_names_st_with_units_and_its_origin(tmp_path, capsys):
    """A user device (the 8-RUS example): kappa is σmin/σmax of ST⁻¹Jᵀ with the paper's
    ST, and the report says ST's units and where the paper sets it: Sec. III-B-2, the GII
    optimisation of the 6-RSS kinematics, as Ergin's device's intended output
    capabilities (QA 23: it was called "the paper's Octopod scaling", which the paper
    never says)."""
    code, qs, out, _ = _run(tmp_path, capsys, _example("rus8_device.toml", """
[[query]]
type = "jacobian"
pose = [20, -10, 220, 10, 0, 5]
"""))
    assert code == 0
    row = qs[0]["result"]["poses"][0]
    J = np.array(row["J"])
    st = np.array([15, 15, 15, 1, 1, 1.0])              # the paper's, Sec. III-B-2
    sv = np.linalg.svd(J.T / st[:, None], compute_uv=False)
    assert row["kappa"] == pytest.approx(sv[-1] / sv[0], rel=1e-12)
    line = next(ln for ln in out.splitlines() if "kappa = " in ln)
    assert f"ST = {PAPER_ST}" in line, line
    assert "diag(15, 15, 15, 1, 1, 1)" not in out
    assert "Octopod" not in next(ln for ln in out.splitlines() if "ST of kappa" in ln)
    assert ("ST of kappa: the paper's ST (Kühne et al. Sec. III-B-2, the GII optimisation "
            "of the 6-RSS kinematics: the originally intended output capabilities of "
            "Ergin's device)" in out
            and "used for every mechanism (this query has no field for a device's own" in out)
    assert PAPER_ST in qs[0]["result"]["unit"]["kappa"]


def test_scaling_note_says_whose_st():
    assert scaling_note((15, 15, 15, 1, 1, 1)).startswith(
        f"ST = {PAPER_ST}, the paper's ST (Kühne et al. Sec. III-B-2, the GII optimisation")
    own = scaling_note((10, 20, 30, 1, 2, 3))
    assert own == ("ST = diag(10 N, 20 N, 30 N, 1 N·m, 2 N·m, 3 N·m), the query's "
                   "`scaling`")


# 2 --------------------------------------------------------------- warnings, one line
def test_geometry_warning_is_one_line_on_the_cli(tmp_path):
    """The 6-UPS example with home at 600 mm, where every leg is beyond its 550 mm
    stroke: one "distkin: warning:" line naming the legs' length (numpy's norm of the
    scene's leg vector), never Python's "file.py:10: GeometryWarning:" format."""
    text = _example("gough_stewart_6ups.toml", """
[[query]]
type = "inverse_kinematics"
pose = [0, 0, 400, 0, 0, 0]
""").replace("home = [0, 0, 400, 0, 0, 0]", "home = [0, 0, 600, 0, 0, 0]")
    (tmp_path / "s.toml").write_text(text)
    r = subprocess.run([sys.executable, "-m", "distkin", "run", "s.toml", "--no-progress"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=300,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 0, r.stderr
    base = np.array([295.442326, -52.094453, 0.0])      # leg 1 of the scene (mm)
    plat = np.array([96.418141, -114.906666, 600.0])
    length = np.linalg.norm(plat - base) / 1e3
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    # every line distkin's own (a first run also says it derives the kernels)
    assert all(ln.startswith("distkin: ") for ln in lines), r.stderr
    lines = [ln for ln in lines if ln.startswith("distkin: warning: ")]
    # named with the scene's field and its length unit, as an RSS scene's warnings are
    assert len(lines) == 1 and lines[0].startswith("distkin: warning: mechanism.home: "), \
        r.stderr
    assert f"leg 1 length {length:.4g} m outside its range [0.35, 0.55] m" in lines[0]
    assert lines[0].endswith("(lengths in this message in m (SI), the scene's in mm)")
    assert "GeometryWarning" not in r.stderr and ".py:" not in r.stderr


def test_format_warning_keeps_other_packages_format():
    assert format_warning(GeometryWarning("a\n  b"), GeometryWarning, "/x/y.py", 3) == \
        "distkin: warning: a b\n"
    assert format_warning(UserWarning("u"), UserWarning, "/x/y.py", 3) == \
        warnings.formatwarning(UserWarning("u"), UserWarning, "/x/y.py", 3)


# 3 ------------------------------------------------------------------- the SI hint
@pytest.mark.parametrize("message, length", [
    ("expected at least 6 legs, got 5", False),
    ("expected branch +1 or -1, got 2", False),
    ("got leg[1] with the same line as leg[0] (base (0.295442, -0.0520945, 0) m, ", True),
    ("leg 1 length 0.6353 m outside its range [0.35, 0.55] m", True),
    ("leg 2 margin -0.0121 m^2", True),
    ("a stroke of 1e-07 mm", False),        # the scene's unit, not SI
    ("a limit of 2.5 N·m", False),
])
def test_si_hint_only_for_a_message_with_a_length(message, length):
    assert has_si_length(message) is length
    exc = InputError(message, field="leg")
    hint = si_length_hint(exc, Units("mm", "deg"))
    assert (hint == "lengths in this message in m (SI), the scene's in mm") is length
    assert (hint is None) is not length
    assert si_length_hint(exc, Units("m", "rad")) is None     # an SI scene needs none


# 4 --------------------------------------------------------- a value beyond its stroke
@pytest.mark.parametrize("value", ["550.0000001", "550.000000000001", "349.99999999"])
def test_stroke_refusal_prints_the_value_outside_its_bound(tmp_path, capsys, value):
    code, qs, _, _ = _run(tmp_path, capsys, _example("gough_stewart_6ups.toml", f"""
[[query]]
type = "forward_kinematics"
angles = ["449.672992", "471.224532", "465.566713", "458.704719", "450.839781", "{value}"]
guess = [0, 0, 400, 0, 0, 0]
method = "certified"
"""))
    assert code == 2
    msg = qs[0]["error"]["message"]
    m = re.search(r"leg 6's length (\S+) mm outside its range \[(\S+), (\S+)\] mm", msg)
    assert m, msg
    v, lo, hi = map(float, m.groups())
    assert (lo, hi) == (350.0, 550.0)                    # the scene's stroke
    assert not lo <= v <= hi, msg                        # visibly outside
    assert v == pytest.approx(float(value), rel=1e-15)


@pytest.mark.parametrize("v, bounds", [
    (550.0000001, (350.0, 550.0)), (1 + 2.2e-16, (0.0, 1.0)), (-1e-300, (0.0, 1.0)),
    (0.1 + 0.2, (0.3,)), (123456.7, (123456.0, 1e6)), (2.0, (2.0, 1.0)),
])
def test_apart_tells_distinct_numbers_apart(v, bounds):
    texts = apart(v, *bounds)
    assert len(texts) == 1 + len(bounds)
    for b, t in zip(bounds, texts[1:]):
        # the printed pair compares as the numbers do
        assert (float(texts[0]) > float(t)) == (v > b) and (float(texts[0]) < float(t)) == (v < b)
    assert apart(550.0, 350.0, 550.0) == ("550", "350", "550")   # 6 digits when enough


# 5 ------------------------------------------------------------------- the CSV rows
HEAD = "type,base_x,base_y,base_z,range_min,range_max"
ROWS = ["UPS,1.5,2,0,350,550", "UPS,3,,0,350,550", "UPS,4,5,0,,"]


@pytest.mark.parametrize("slip", ["every row", "data rows", "one row"])
def test_trailing_comma_is_read_as_without(slip):
    """A row's empty cells beyond the header's last column are dropped: the rows are
    those of the same file without the trailing commas; an empty cell inside a row (a
    field not given) is kept."""
    plain = "\n".join([HEAD, *ROWS])
    rows = {"every row": [HEAD + ",", *(r + "," for r in ROWS)],
            "data rows": [HEAD, *(r + ",," for r in ROWS)],
            "one row": [HEAD, ROWS[0], ROWS[1] + ",", ROWS[2]]}[slip]
    assert csv_rows("\n".join(rows), "legs.csv", "f") == csv_rows(plain, "legs.csv", "f")
    assert csv_rows(plain, "legs.csv", "f")[3] == (4, ["UPS", "4", "5", "0", "", ""])


def test_a_value_beyond_the_header_is_refused_naming_its_line():
    text = "\n".join([HEAD, ROWS[0], "", ROWS[1] + ",7", ROWS[2]])
    with pytest.raises(InputError) as err:
        csv_rows(text, "legs.csv", "mechanism.legs_csv")
    assert err.value.field == "mechanism.legs_csv[1]"
    assert err.value.message == ("expected 6 cells (line 4 of legs.csv), got 7: a value in "
                                 "cell 7, beyond the header's last column 'range_max'")


@pytest.mark.parametrize("where, line", [("all", 1), ("data", 2)])
def test_semicolon_separated_values_are_named(where, line):
    rows = [HEAD, *ROWS] if where == "data" else [HEAD.replace(",", ";"), *ROWS]
    if where == "data":
        rows[1] = rows[1].replace(",", ";")
    with pytest.raises(InputError) as err:
        csv_rows("\n".join(rows), "legs.csv", "mechanism.legs_csv")
    assert err.value.message == ("expected comma-separated values, got semicolon-separated "
                                 f"values (line {line} of legs.csv): distkin reads "
                                 "comma-separated")
    assert "comma-separated" in err.value.hint


def test_an_empty_header_cell_between_names_is_named():
    with pytest.raises(InputError, match=r"got an empty cell \(column 2\)"):
        csv_rows("type,,base_y\nUPS,1,2", "legs.csv", "f")


# 6 --------------------------------------------------------------- angle unit slips
RAD = '[units]\nlength = "mm"\nangle = "{angle}"\n[mechanism]\nkind = "rss"\npreset = "hunt"\n'
GRID = ('[[query]]\ntype = "performance"\nworkers = 1\n'
        'grid = {{ half = 10, step = 10, rotation = {v}, rotation_step = 10 }}\n')
IK = '[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]\n'


@pytest.mark.parametrize("text, field, v", [
    (RAD + GRID.format(v=30), "query[0].grid.rotation", 30),
    (RAD + '[[query]]\ntype = "design_sweep"\nbeta = [0, 30, 10]\n', "query[0].beta[1]", 30),
    (RAD + 'gamma = 13.18\n' + IK, "mechanism.gamma", 13.18),
])
def test_degrees_in_a_rad_scene_are_named(text, field, v):
    """An angle refused in a rad scene that degrees would allow: the hint says so, with
    the value in rad (math.radians); in a deg scene, or beyond what degrees allow, none."""
    with pytest.raises(InputError) as err:
        loads_scene(text.replace("{angle}", "rad"))
    assert err.value.field == field
    assert err.value.hint == (f"an angle in degrees? the scene's [units] angle is \"rad\" "
                              f"({v:g} deg would be {math.radians(v):.4g} rad; angle = "
                              f"\"deg\" reads degrees)")


@pytest.mark.parametrize("text", [RAD.replace("{angle}", "deg") + GRID.format(v=200),
                                  RAD.replace("{angle}", "rad") + GRID.format(v=500)])
def test_no_degrees_hint_where_degrees_would_not_do(text):
    with pytest.raises(InputError) as err:
        loads_scene(text)
    assert err.value.field == "query[0].grid.rotation" and not err.value.hint
