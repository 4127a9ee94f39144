"""The octic's coefficient cache (``octic_*.pickle``, :func:`distkin.codegen.octic.
octic_in_legs`) under parallel workers: like the derived modules
(:func:`distkin.sourcecache.cached_source`), one process derives a missing entry while
the others wait for its lock and load it (before, each worker derived it again).

The derivation is replaced by a slow stub in the child processes (it prints BUILD and
returns nine known integers), so the test checks who derives and what the waiting
process loads: the stub's coefficients, from the first process's file."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest

_WORKER = """
import sys, time
from pathlib import Path
import sympy
import distkin.codegen.octic as o
marker = Path(sys.argv[1])

def slow(values):
    print("BUILD", flush=True)
    marker.write_text("building")
    time.sleep(2.0)
    return [sympy.Integer(k) for k in range(9)]

o._octic_coeffs = slow
c = o.octic_in_legs({(1, 2): 144, (2, 3): 144, (1, 3): 144, (4, 5): 36, (5, 6): 36,
                     (4, 6): 36})
print("COEFFS", [int(v) for v in c], flush=True)
"""


def _worker(tmp_path):
    env = {**os.environ, "DISTKIN_CACHE": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.Popen([sys.executable, "-c", _WORKER, str(tmp_path / "building")],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


@pytest.mark.skipif(sys.platform == "win32", reason="no fcntl: may derive twice")
def test_two_workers_derive_the_octic_once(tmp_path):
    first = _worker(tmp_path)
    t0 = time.monotonic()
    while not (tmp_path / "building").exists():       # the first holds the lock
        assert first.poll() is None, first.communicate()[1]
        assert time.monotonic() - t0 < 120, "the first worker never started deriving"
        time.sleep(0.02)
    second = _worker(tmp_path)
    out1, err1 = first.communicate(timeout=180)
    out2, err2 = second.communicate(timeout=180)
    assert first.returncode == 0 and second.returncode == 0, err1 + err2
    assert out1.count("BUILD") == 1 and "BUILD" not in out2
    expected = f"COEFFS {list(range(9))}"
    assert expected in out1 and expected in out2
    assert len(list((tmp_path / "cache").glob("octic_*.pickle"))) == 1
