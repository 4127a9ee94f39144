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
