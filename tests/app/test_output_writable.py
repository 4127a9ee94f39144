"""A ``--json`` file that cannot be written is refused before any work (QA pkg 4-5):
into an existing read-only folder ``distkin run S --json rodir/out.json`` ran every query
and only then failed on the temporary file beside the target; a read-only existing file
was silently replaced (the atomic rename needs no write permission on the file, and the
new file had other modes), where the shell's ``>`` refuses it.

As root, permissions are not enforced: the in-process tests fake :func:`os.access` for
the one path; the subprocess test drops the capabilities that bypass them (setpriv)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from distkin.app import cli
from distkin.app import output_paths
from distkin.app.output_paths import check_output_path
from distkin.errors import InputError

ROOT = Path(__file__).resolve().parents[2]

POINTS = """
[mechanism]
kind = "points"
points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
"""


def _deny(monkeypatch, denied: Path):
    """os.access says no to writing ``denied`` (resolved), yes as before elsewhere."""
    real = os.access
    denied = os.path.realpath(denied)

    def access(path, mode, *a, **k):
        if os.path.realpath(path) == denied and mode & os.W_OK:
            return False
        return real(path, mode, *a, **k)
    monkeypatch.setattr(output_paths.os, "access", access)


def _no_run(*a, **k):
    raise AssertionError("the scene ran before the --json path was checked")


def test_a_read_only_folder_is_refused_before_the_run(tmp_path, monkeypatch, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(POINTS)
    rodir = tmp_path / "rodir"
    rodir.mkdir()
    _deny(monkeypatch, rodir)
    monkeypatch.setattr(cli, "run_scene", _no_run)
    code = cli.main(["run", str(scene), "--json", str(rodir / "out.json")])
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert lines[0].startswith("distkin: error: --json: expected a writable file path, got ")
    assert f"its folder {str(rodir)!r} is not writable" in lines[0]
    assert out == "" and not (rodir / "out.json").exists()


def test_a_read_only_existing_file_is_refused_and_kept(tmp_path, monkeypatch, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(POINTS)
    target = tmp_path / "out.json"
    target.write_text("earlier\n")
    target.chmod(0o444)
    _deny(monkeypatch, target)
    monkeypatch.setattr(cli, "run_scene", _no_run)
    code = cli.main(["run", str(scene), "--json", str(target)])
    out, err = capsys.readouterr()
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert f"got {str(target)!r} (an existing read-only file)" in err
    assert target.read_text() == "earlier\n" and (target.stat().st_mode & 0o777) == 0o444


def test_a_device_and_an_in_place_log_need_no_writable_folder(tmp_path, monkeypatch):
    """/dev/null is written in place (its folder is not written); a writer that opens
    an existing file in place (replace=False: the run logs) needs only the file."""
    _deny(monkeypatch, Path("/dev"))
    check_output_path("/dev/null")
    rodir = tmp_path / "rodir"
    rodir.mkdir()
    (rodir / "run.device.csv").write_text("")
    _deny(monkeypatch, rodir)
    check_output_path(rodir / "run.device.csv", "--log", replace=False)
    with pytest.raises(InputError, match="not writable"):
        check_output_path(rodir / "run.device.csv", "--json")
    with pytest.raises(InputError, match="not writable"):
        check_output_path(rodir / "new.device.csv", "--log", replace=False)


def _unprivileged(cmd):
    if os.geteuid() != 0:
        return cmd
    if shutil.which("setpriv") is None:
        pytest.skip("root without setpriv: permissions are not enforced")
    caps = "-dac_override,-dac_read_search,-fowner"
    return ["setpriv", "--bounding-set", caps, "--inh-caps", caps, *cmd]


@pytest.mark.parametrize("case", ["folder", "file"])
def test_real_permissions_refuse_before_the_run(tmp_path, case):
    scene = tmp_path / "s.toml"
    scene.write_text(POINTS)
    rodir = tmp_path / "rodir"
    rodir.mkdir()
    target = rodir / "out.json"
    if case == "file":
        target.write_text("earlier\n")
        target.chmod(0o444)
    else:
        rodir.chmod(0o555)
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    try:
        proc = subprocess.run(_unprivileged([sys.executable, "-m", "distkin", "run",
                                             str(scene), "--json", str(target)]),
                              capture_output=True, text=True, env=env, cwd=tmp_path,
                              timeout=300)
    finally:
        rodir.chmod(0o755)
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == ""                                    # nothing ran
    why = "an existing read-only file" if case == "file" else "is not writable"
    assert why in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    if case == "file":
        assert target.read_text() == "earlier\n"
