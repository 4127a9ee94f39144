"""Standard output and the demo's failed queries (QA pkg 3, 6).

* ``distkin demo`` whose query failed (a read-only HOME: no cache folder) exited 2 with
  the reason only in the stdout report; now one stderr line per failed query, as
  ``distkin run``, naming the built-in scene.
* ``distkin run S --json - >&-`` exited 0 and lost the JSON (``sys.stdout`` is None);
  now exit 2 with one line before any work.
* ``distkin demo >/dev/full``: "internal failure: OSError: [Errno 28] ..." (exit 1);
  now one line naming stdout, exit 2 (an output that cannot be written), and no
  "Exception ignored" at the interpreter's exit.
"""

from __future__ import annotations

import errno
import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from distkin.app import cli
from distkin.app import registry as queries
from distkin.app import scene as scene_mod
from distkin.errors import InfeasibleError

ROOT = Path(__file__).resolve().parents[2]
BANANA = ROOT / "examples" / "points_banana.toml"
ENV = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


def test_demo_prints_one_stderr_line_per_failed_query(monkeypatch, capsys):
    @queries.register("demo_fails_test", mechanisms=("points",))
    class _Fails:
        @staticmethod
        def parse(table, mechanism, units, field):
            return None

        @staticmethod
        def run(params, scene, ctx):
            raise InfeasibleError("expected closing distances, got h^2 = -1", margin=-1.0)

    monkeypatch.setitem(queries.QUERY_MODULES, "demo_fails_test", ())
    monkeypatch.setattr(cli, "DEMO_SCENES", ["cayley_menger_tetrahedron.toml"])
    real = scene_mod.loads_scene
    monkeypatch.setattr(scene_mod, "loads_scene", lambda text, path=None: real(
        text + '\n[[query]]\ntype = "demo_fails_test"\n', path))
    assert cli.main(["demo", "--no-progress"]) == 2
    out, err = capsys.readouterr()
    lines = [ln for ln in err.splitlines() if ln.startswith("distkin: error:")]
    assert lines == ["distkin: error: distkin/scenes/cayley_menger_tetrahedron.toml: "
                     "query[2]: expected closing distances, got h^2 = -1"], err
    assert "cayley_menger: ok" in out


def _banana(stdout, *args):
    return subprocess.run([sys.executable, "-m", "distkin", "run", str(BANANA), *args],
                          stdout=stdout, stderr=subprocess.PIPE, text=True, env=ENV,
                          cwd=ROOT, timeout=300)


def test_a_closed_stdout_is_refused_before_any_work():
    # a child with descriptor 1 closed (the shell's >&-); preexec runs after the set-up
    proc = subprocess.run([sys.executable, "-m", "distkin", "run", str(BANANA), "--json", "-"],
                          stderr=subprocess.PIPE, text=True, env=ENV, cwd=ROOT, timeout=300,
                          preexec_fn=lambda: os.close(1))
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().splitlines() == [
        "distkin: error: stdout: expected an open standard output (the report of run goes "
        "there, and --json -), got it closed (>&-) (hint: redirect it to /dev/null to "
        "discard the report)"], proc.stderr


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("args", [(), ("--json", "-")])
def test_a_full_stdout_is_one_line_and_exit_2(args):
    with open("/dev/full", "w") as full:
        proc = _banana(full, *args)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert lines[-1] == (
        "distkin: error: stdout: expected a standard output that can be written, got No "
        f"space left on device (errno {errno.ENOSPC}) writing it (hint: redirect the output "
        "to a file system with room)"), proc.stderr
    assert "internal failure" not in proc.stderr and "Exception ignored" not in proc.stderr
    assert "Traceback" not in proc.stderr


class _EIO(io.StringIO):
    def write(self, text):
        raise OSError(errno.EIO, "Input/output error")


def test_a_stdout_write_error_in_process(monkeypatch, capsys):
    """The wrapper is in place only while the command runs (sys.stdout restored)."""
    capsys.readouterr()
    broken = _EIO()
    monkeypatch.setattr(sys, "stdout", broken)
    assert cli.main(["run", str(BANANA), "--no-progress"]) == 2
    assert sys.stdout is broken
    err = capsys.readouterr().err
    assert "stdout: expected a standard output that can be written, got Input/output " \
           f"error (errno {errno.EIO}) writing it" in err and "internal failure" not in err
