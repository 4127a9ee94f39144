"""Messages of a CSV leg table (``legs_csv``, QA G 5): a pair or a vector given in part
said ``limit[0]: expected a number or a numeric string, got NoneType None``, and a column
named twice in the header was read as the last of them (then reported as a missing
``base_y``).  Each is now named with the CSV columns, the file's line and what is missing
or repeated.

Reference: the line numbers are found in the CSV text itself (the line holding a marker
value), not taken from the program; blank lines count, as an editor counts them.
"""

from __future__ import annotations

import pytest

from distkin.app.scene import load_scene
from distkin.errors import InputError

HEAD = ("type,base_x,base_y,base_z,platform_x,platform_y,platform_z,range_min,range_max,"
        "limit_min,limit_max")
ROWS = [
    "UPS,295.442326,-52.094453,0,96.418141,-114.906666,0,350,550,-1000,1000",
    "UPS,295.442326,52.094453,0,96.418141,114.906666,0,350,550,-1000,1000",
    "UPS,-102.606043,281.907786,0,51.303021,140.953893,0,350,550,-1000,1000",
    "UPS,-192.836283,229.813333,0,-147.721163,26.047227,0,350,550,-1000,1000",
    "UPS,-192.836283,-229.813333,0,-147.721163,-26.047227,0,350,550,-1000,1000",
    "UPS,-102.606043,-281.907786,0,51.303021,-140.953893,0,350,550,-1000,1000",
]
SCENE = """[units]
length = "mm"
[mechanism]
kind = "legs"
home = [0, 0, 400, 0, 0, 0]
mass = 10
inertia = "0.2"
legs_csv = "legs.csv"
[[query]]
type = "inverse_kinematics"
pose = [0, 0, 400, 0, 0, 0]
"""


def _drop_column(lines, name):
    cols = lines[0].split(",")
    k = cols.index(name)
    return [",".join(c for j, c in enumerate(line.split(",")) if j != k) for line in lines]


def _error(tmp_path, csv_lines) -> InputError:
    (tmp_path / "legs.csv").write_text("\n".join(csv_lines) + "\n")
    (tmp_path / "s.toml").write_text(SCENE)
    with pytest.raises(InputError) as exc:
        load_scene(tmp_path / "s.toml")
    return exc.value


def _line_of(csv_lines, marker) -> int:
    return next(i + 1 for i, line in enumerate(csv_lines) if marker in line)


def test_the_table_as_given_loads(tmp_path):
    (tmp_path / "legs.csv").write_text("\n".join([HEAD, *ROWS]) + "\n")
    (tmp_path / "s.toml").write_text(SCENE)
    legs = load_scene(tmp_path / "s.toml").mechanism.leg_table
    assert len(legs) == 6 and legs[0].limit == (-1000.0, 1000.0)
    assert legs[0].range == pytest.approx((0.35, 0.55), abs=1e-15)


def test_a_missing_min_column_is_named(tmp_path):
    lines = _drop_column([HEAD, *ROWS], "limit_min")
    exc = _error(tmp_path, lines)
    assert exc.field == "mechanism.legs_csv[0].limit"
    assert exc.message == ("expected limit_min and limit_max together (line 2 of legs.csv), "
                           "got limit_max = 1000 but no limit_min (no such column)")


def test_an_empty_cell_is_named_with_its_line(tmp_path):
    rows = list(ROWS)
    rows[3] = rows[3].replace(",350,550,", ",,550,")           # leg 3: no range_min
    lines = [HEAD, "", *rows[:2], "", *rows[2:]]                # blank lines count
    exc = _error(tmp_path, lines)
    line = _line_of(lines, "-192.836283,229.813333")
    assert line == 7
    assert exc.field == "mechanism.legs_csv[3].range"
    assert exc.message == (f"expected range_min and range_max together (line {line} of "
                           "legs.csv), got range_max = 550 but no range_min (an empty cell)")


def test_a_vector_in_part_names_the_missing_coordinates(tmp_path):
    lines = _drop_column(_drop_column([HEAD, *ROWS], "base_z"), "base_y")
    exc = _error(tmp_path, lines)
    assert exc.field == "mechanism.legs_csv[0].base"
    assert exc.message == ("expected base_x, base_y and base_z together (line 2 of legs.csv), "
                           "got base_x = 295.442326 but no base_y (no such column) and "
                           "base_z (no such column)")


def test_a_repeated_column_is_refused(tmp_path):
    """The header 'type,base_x,base_x,...' was read as one base_x (the last cell) and
    then reported as a missing base_y."""
    lines = [HEAD.replace("base_y", "base_x", 1), *ROWS]
    exc = _error(tmp_path, lines)
    assert exc.field == "mechanism.legs_csv"
    assert exc.message == ("expected each column once in the header (line 1 of legs.csv), "
                           "got 'base_x' 2 times (columns 2 and 3)")


def test_a_bad_cell_names_its_line_and_column(tmp_path):
    rows = list(ROWS)
    rows[4] = rows[4].replace("-147.721163,-26.047227", "-147.721163,abc")
    lines = [HEAD, "", *rows]
    exc = _error(tmp_path, lines)
    assert exc.field == "mechanism.legs_csv[4].platform[1]"
    assert exc.hint.startswith(f"line {_line_of(lines, ',abc,')} of legs.csv, column "
                               "platform_y; ")


def test_five_legs_name_the_csv(tmp_path):
    """QA M 8: five rows said ``mechanism.leg``; the table is ``mechanism.legs_csv``."""
    err = _error(tmp_path, [HEAD] + ROWS[:5])
    assert err.field == "mechanism.legs_csv" and "at least 6 legs, got 5" in err.message


def _load(tmp_path, csv_lines):
    (tmp_path / "legs.csv").write_text("\n".join(csv_lines) + "\n")
    (tmp_path / "s.toml").write_text(SCENE)
    return load_scene(tmp_path / "s.toml")


def test_trailing_commas_load_the_table_without_them(tmp_path):
    """A spreadsheet's trailing commas (QA): the scene loads the same leg table as the
    file without them (the reference: the same scene, commas removed)."""
    plain = _load(tmp_path, [HEAD] + ROWS).mechanism.leg_table
    slipped = _load(tmp_path, [HEAD + ","] + [r + "," for r in ROWS]).mechanism.leg_table
    assert slipped == plain


def test_a_semicolon_file_is_named_as_such(tmp_path):
    """A semicolon-separated export was read as one unknown column holding the whole
    header line (QA); now the scene names the separator and the file's line."""
    err = _error(tmp_path, [HEAD.replace(",", ";")] + [r.replace(",", ";") for r in ROWS])
    assert err.field == "mechanism.legs_csv"
    assert "semicolon-separated values (line 1 of legs.csv)" in err.message


def test_no_si_hint_on_a_message_without_lengths(tmp_path):
    """"expected at least 6 legs, got 5" holds no length: no "lengths in this message in
    m (SI)" hint (QA); a message with a length in m keeps it (two equal legs: the
    description names their joints in m, 0.295442 m for the 295.442326 mm of the CSV)."""
    err = _error(tmp_path, [HEAD] + ROWS[:5])
    assert "(SI)" not in (err.hint or "")
    err = _error(tmp_path, [HEAD] + ROWS[:5] + ROWS[:1])
    assert "0.295442" in err.message
    assert "lengths in this message in m (SI), the scene's in mm" in err.hint
