"""A TOML syntax error names its line: tomllib says only "(at end of document)" for an
array or multi-line string left open, so the scene loader names where it was opened
(QA: a missing ']' at the end of a 'legs = [...]' gave no line at all)."""

import subprocess
import sys

import pytest

from distkin.app.scene import loads_scene
from distkin.errors import InputError

HEAD = ('[mechanism]\nkind = "octahedral"\n'
        'base = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]]\n'
        'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n\n'
        '# a comment with a [ bracket and a " quote\n'
        '[[query]]\ntype = "forward_kinematics"\n')


@pytest.mark.parametrize("tail, opened", [
    # line 9 (the 8 lines of HEAD come first), column 8: after 'legs = '
    ('legs = ["19.8", "18", "18", "17", "14.9", "17.8"\n', "the '[' opened at line 9, column 8"),
    ('legs = [\n  "19.8", "18", "18",\n  "17", "14.9", "17.8"\n\n',
     "the '[' opened at line 9, column 8"),
    ('legs = ["19.8", "18", "18", "17", "14.9", "17.8"]\nnote = """text [\n',
     'the string """ opened at line 10, column 8'),
    ("legs = [\"]\", '[', 18, 17, 14.9, 17.8\n", "the '[' opened at line 9, column 8"),
])
def test_an_unclosed_array_or_string_names_the_line_it_opened(tail, opened):
    with pytest.raises(InputError) as err:
        loads_scene(HEAD + tail, "s.toml")
    msg = err.value.one_line()
    assert "(at end of document)" in msg and opened in msg and "never closed" in msg


def test_errors_that_name_their_line_are_unchanged():
    with pytest.raises(InputError) as err:
        loads_scene(HEAD + 'legs = ["19.8", 18]\nmethod = fast\n', "s.toml")
    msg = err.value.one_line()
    assert "(at line 10, column 10)" in msg and "never closed" not in msg


def test_the_cli_gives_one_line_with_the_line(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text(HEAD + 'legs = ["19.8", "18", "18", "17", "14.9", "17.8"\n')
    r = subprocess.run([sys.executable, "-m", "distkin", "run", str(scene)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("distkin: error: ")
    assert "line 9, column 8" in lines[0]


@pytest.mark.parametrize("text, said, opened", [
    # QA 2026-11-29: an array left open mid-file; tomllib names the next key's line
    ('[mechanism]\nkind = "octahedral"\nbase = [[0, 0, 0], [6, "sqrt(108)", 0], [12, 0, 0]\n'
     'platform = [[0, 0, 0], [6, 0, 0], [3, "sqrt(27)", 0]]\n',
     "(at line 4, column 1)", "the '[' opened at line 3, column 8"),
    ('a = [[1, 2], [3\nb = 3\n', "(at line 2, column 1)", "the '[' opened at line 1, column 14"),
    ('t = {x = 1\nb = 3\n', "(at line 1, column 11)", "the '{' opened at line 1, column 5"),
])
def test_an_array_left_open_mid_file_names_the_line_it_opened(text, said, opened):
    """The opening bracket counted by hand in each text (its line and column)."""
    with pytest.raises(InputError) as err:
        loads_scene(text, "s.toml")
    msg = err.value.one_line()
    assert said in msg and opened in msg and "never closed" in msg


@pytest.mark.parametrize("text", ['a = [1 2]\n', 'base = [[0, 0, 0] [6, 0, 0]]\n',
                                  't = {x = 1 y = 2}\n'])
def test_a_missing_comma_names_no_bracket(text):
    """tomllib says "Unclosed array" for a missing comma too; the bracket is closed
    later, so no "never closed" note (review 2026-11-29: it named the '[' of a closed
    array)."""
    with pytest.raises(InputError) as err:
        loads_scene(text, "s.toml")
    msg = err.value.one_line()
    assert "Unclosed" in msg and "never closed" not in msg
