"""A controller scene (``distkin control`` / ``distkin sim --scene``) that is not UTF-8
is bad input, exit 2 naming ``--scene`` (QA: exit 1, "internal failure:
UnicodeDecodeError"), and a TOML array left open names the line it was opened on, as a
run scene's does."""

import subprocess
import sys

import pytest

from distkin.app.scene import toml_text
from distkin.errors import InputError


def _distkin(*args, cwd):
    return subprocess.run([sys.executable, "-m", "distkin", *args], capture_output=True,
                          text=True, timeout=60, cwd=cwd)


@pytest.mark.parametrize("command", [["control", "--delay-margin", "1"], ["sim"]])
def test_a_controller_scene_that_is_not_utf8_is_bad_input(tmp_path, command):
    (tmp_path / "c.toml").write_bytes(b"[device]\npreset = \"octo\"\n# \xff\xfe\n")
    r = _distkin(*command, "--scene", "c.toml", cwd=tmp_path)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2, r.stderr
    assert len(lines) == 1 and lines[0].startswith("distkin: error: --scene: ")
    assert "UTF-8" in lines[0] and "'c.toml'" in lines[0] and "byte 27" in lines[0]


def test_an_unclosed_array_in_a_controller_scene_names_its_line(tmp_path):
    (tmp_path / "c.toml").write_text('[device]\npreset = "octo"\n[pd]\nkp = [110,\n  0.4\n')
    r = _distkin("control", "--delay-margin", "1", "--scene", "c.toml", cwd=tmp_path)
    assert r.returncode == 2
    assert "the '[' opened at line 4, column 6 is never closed" in r.stderr


def test_toml_text_names_the_option(tmp_path):
    with pytest.raises(InputError) as err:
        toml_text(tmp_path / "missing.toml", "--scene", "controller scene")
    assert err.value.field == "--scene" and "No such file" in err.value.one_line()
    (tmp_path / "ok.toml").write_text("[device]\npreset = 'octo'\n")
    assert toml_text(tmp_path / "ok.toml", "--scene", "x").startswith("[device]")


def test_an_unclosed_array_names_its_line_through_the_python_api_too():
    # (loads_control_scene said only "at end of document": the CLI read the file with
    # toml_text first, which named the line, and the API had no such step)
    from distkin.control.config import loads_control_scene
    with pytest.raises(InputError) as err:
        loads_control_scene('[device]\npreset = "octo"\n[pd]\nkp = [110,\n  0.4\n', "c.toml")
    msg = err.value.one_line()
    assert "(at end of document)" in msg
    assert "the '[' opened at line 4, column 6 is never closed" in msg
    assert err.value.field == "c.toml"
