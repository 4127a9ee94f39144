"""``--log`` names files, and Ctrl-C ends ``distkin control`` with the line every
command prints (QA: ``--log ""`` wrote nothing while the JSON listed ``.cycles.csv``;
``--log dir/`` wrote hidden files ``dir/.cycles.csv``; an interrupted run printed no
``distkin: error: interrupted``).  The refusals are checked in-process on
:func:`distkin.app.cli.main` (exit code, one stderr line, nothing written), and the
interrupted line against the one :func:`distkin.app.cli.main` prints for a
KeyboardInterrupt in any other command (a second route)."""

import argparse
import os
import signal
import subprocess
import sys
import time

import pytest

from distkin.app import cli
from distkin.app.control_commands import closing_lines

from control_helpers import ROOT


@pytest.mark.parametrize("cmd", [["control", "--sim"], ["sim"],
                                 ["control", "--delay-margin"]])
@pytest.mark.parametrize("prefix", ["", "  ", "out/", "out" + os.sep + ".", "..", "."])
def test_a_log_prefix_that_names_no_file_is_refused(tmp_path, monkeypatch, capsys, cmd,
                                                    prefix):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    code = cli.main([*cmd, "--log", prefix])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].startswith("distkin: error: --log: expected a file "
                                               "name prefix"), err
    assert repr(prefix) in err[0]
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["out"]     # nothing written


def test_the_help_says_what_prefix_is(capsys):
    with pytest.raises(SystemExit):
        cli.main(["control", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "trailing / are refused" in text and "docs/protocol.md" in text


def test_an_interrupted_run_prints_the_line_of_every_command(monkeypatch, capsys):
    def _interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", lambda: _parser(_interrupted))
    assert cli.main(["x"]) == 130
    want = capsys.readouterr().err.strip()
    assert want == "distkin: error: interrupted"
    assert closing_lines({"exit_reason": "interrupted", "error": None}, sim=True) == [want]
    assert closing_lines({"exit_reason": "completed", "error": None}, sim=False) == []
    # the runs the device ended keep their line
    assert closing_lines({"exit_reason": "disconnect", "error": "expected X, got Y"},
                         sim=False)[0].startswith("distkin: error: --port: expected X")


def _parser(func):
    p = argparse.ArgumentParser()
    p.add_argument("x")
    p.add_argument("--debug", action="store_true")
    p.set_defaults(func=func)
    return p


def test_the_simulator_logs_a_closing_event_on_sigint(tmp_path):
    from distkin.control.runlog import read_events
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    port = tmp_path / "port"
    proc = subprocess.Popen([sys.executable, "-m", "distkin", "sim", "--port-file", str(port),
                             "--log", str(tmp_path / "d"), "--idle-timeout", "30"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    try:
        end = time.monotonic() + 60
        while not port.exists() and time.monotonic() < end and proc.poll() is None:
            time.sleep(0.02)
        assert port.exists(), proc.stderr.read()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130 and b"Traceback" not in err, err     # README: 130
    assert b"stopped (signal SIGINT)" in out
    ev = read_events(tmp_path / "d.device-events.jsonl")
    assert ev and ev[-1]["event"] == "stopped_by_signal" and ev[-1]["signal"] == "SIGINT"
    assert ev[-1]["last_max_abs_torque"] == 0.0
