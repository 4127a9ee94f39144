"""QA 23 D7, D10, D12: options of ``distkin control`` and ``distkin sim`` refused up
front, each one ``distkin: error:`` line naming the option, exit 2.

* ``--port`` naming no serial device: ``/dev/null`` (a character device that takes no
  line settings), a regular file, a directory; ``--port ''`` before anything opens.
* ``--wall-limit`` no longer than ``--seconds``: device time passes at most as fast as
  wall time, so the run could only end at the limit, blaming the device.
* ``--port-file`` naming a symbolic link or a file that is not an earlier port file:
  it was replaced by a regular file holding the URL."""

import os
import re

import pytest

from distkin.app.cli import main
from distkin.control.simulator import check_port_file, write_port_file
from distkin.errors import InputError


def _one_error(capsys):
    err = [x for x in capsys.readouterr().err.splitlines()
           if x.startswith("distkin: error")]
    assert len(err) == 1, err
    return err[0]


@pytest.mark.parametrize("what", ["devnull", "file", "dir"])
def test_a_port_that_is_no_serial_device_is_named(tmp_path, capsys, what):
    path = {"devnull": os.devnull, "file": tmp_path / "f.txt", "dir": tmp_path}[what]
    if what == "file":
        path.write_text("x\n")
    assert main(["control", "--port", str(path), "--seconds", "1"]) == 2
    line = _one_error(capsys)
    assert line.startswith(f"distkin: error: --port: expected a serial device (a tty) or "
                           f"a URL, got {str(path)!r}")
    assert "not a serial device (tty)" in line


def test_an_empty_port_is_a_usage_error_before_anything_opens(capsys, monkeypatch):
    import distkin.app.control_scene_files as files
    monkeypatch.setattr(files, "scene_and_inputs", lambda *a, **k: pytest.fail("loaded"))
    assert main(["control", "--port", "", "--seconds", "1"]) == 2
    assert _one_error(capsys).startswith("distkin: error: --port: expected a serial port "
                                         "URL")


@pytest.mark.parametrize("wall", ["3", "5"])
def test_a_wall_limit_no_longer_than_the_run_is_refused(capsys, wall):
    assert main(["control", "--sim", "--seconds", "5", "--wall-limit", wall]) == 2
    line = _one_error(capsys)
    assert line.startswith(f"distkin: error: --wall-limit: expected --wall-limit longer "
                           f"than the run's --seconds 5 s")
    assert f"got {wall} s" in line
    # without --seconds, the default run of 5 s
    assert main(["control", "--sim", "--wall-limit", "4"]) == 2
    assert "--seconds 5 s" in _one_error(capsys)


def test_the_port_file_never_replaces_a_link_or_another_file(tmp_path, capsys):
    target = tmp_path / "notes.txt"
    target.write_text("my notes\n")
    link = tmp_path / "port"
    link.symlink_to(target)
    for path, why in ((link, "a symbolic link"), (target, "not a port file")):
        assert main(["sim", "--port-file", str(path), "--seconds", "0.01"]) == 2
        line = _one_error(capsys)
        assert line.startswith(f"distkin: error: --port-file: expected a new file or an "
                               f"earlier port file to replace, got {str(path)!r}")
        assert why in line
    assert link.is_symlink() and target.read_text() == "my notes\n"


def test_an_earlier_port_file_is_replaced_atomically(tmp_path):
    p = tmp_path / "port"
    for old in ("/dev/pts/7\n", "socket://127.0.0.1:40123\n"):
        p.write_text(old)
        check_port_file(p)                       # an earlier port file: accepted
    (tmp_path / "port.tmp").write_text("someone's\n")        # not ours to replace
    write_port_file(p, "/dev/pts/9")
    assert p.read_text() == "/dev/pts/9\n" and not p.is_symlink()
    assert (tmp_path / "port.tmp").read_text() == "someone's\n"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["port", "port.tmp"]
    d = tmp_path / "d"
    d.mkdir()
    with pytest.raises(InputError) as exc:
        check_port_file(d)
    assert exc.value.field == "port_file" and "not a regular file" in exc.value.message


def test_the_help_lists_every_fault_kind_with_its_default():
    from distkin.app.control_commands import FAULTS_HELP
    from distkin.control.faults import FAULT_KINDS
    for kind, default in FAULT_KINDS.items():
        assert f"{kind}@T" in FAULTS_HELP
        if default:
            assert re.search(rf"{kind}@T:\w+ \([^)]*default {default}\)", FAULTS_HELP), kind
