"""``distkin ... | head``: when the reader of stdout leaves, distkin stops quietly with
exit 141 (128 + SIGPIPE, as a program the signal kills), not 'internal failure:
BrokenPipeError' (seen with ``distkin demo | head``), and no 'Exception ignored' at
the interpreter's exit."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_a_closed_stdout_pipe_ends_the_run_quietly():
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r, w = os.pipe()
    os.close(r)                                   # nobody will read: the first write fails
    try:
        proc = subprocess.run([sys.executable, "-m", "distkin", "run",
                               str(ROOT / "examples" / "points_banana.toml")],
                              stdout=w, stderr=subprocess.PIPE, text=True, env=env,
                              cwd=ROOT, timeout=120)
    finally:
        os.close(w)
    assert proc.returncode == 141, proc.stderr
    assert "internal failure" not in proc.stderr and "Exception ignored" not in proc.stderr
    assert "Traceback" not in proc.stderr


def test_another_broken_pipe_is_still_an_internal_failure(monkeypatch, capsys):
    """Only stdout's reader leaving is the quiet exit (review: a closed socket inside a
    command was reported as 141 and stdout was redirected to devnull for good)."""
    import socket

    from distkin.app import cli

    def command(args):
        a, b = socket.socketpair()
        b.close()
        a.sendall(b"x" * 1_000_000)

    monkeypatch.setattr(cli, "_cmd_run", command)
    assert cli.main(["run", "x.toml"]) == 1
    assert "internal failure: BrokenPipeError" in capsys.readouterr().err
