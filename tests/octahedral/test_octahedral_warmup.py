"""The first compile of the fast tier in two processes (:mod:`distkin.octahedral.warmup`).

* the child's placeholder arguments have the numba types of a real single solve's call
  of the proof (Griffis-Duffy, Sec. VI): the machine code it caches is the code the
  solve loads, not another specialisation;
* the orchestration: the child starts only when the proof is not cached, is waited
  for, and is killed when this process is interrupted (no process left behind);
* ``slow``: in a fresh numba cache, one call compiles both chains (the scan here, the
  proof in the child) and a later process solves the problem as a process that
  compiled everything itself does, bit for bit.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

from distkin.octahedral import forward_kinematics, warmup
from distkin.octahedral.descartes import vouch_buffer

ROOT = Path(__file__).resolve().parents[2]
#: Griffis-Duffy (Sec. VI): base side 12, platform side 6, legs 20 18 18 17 15 18
B = np.array([[0.0, 0.0, 0.0], [12.0, 0.0, 0.0], [6.0, 6.0 * 3 ** 0.5, 0.0]])
LEGS = [20.0, 18.0, 18.0, 17.0, 15.0, 18.0]


def test_placeholder_has_the_types_of_a_real_solve():
    """After a real single solve, the proof's compiled signatures include the one the
    child compiles: numba types of the placeholder against those of the solve."""
    forward_kinematics(B, 0.5 * B, LEGS)
    sig = tuple(numba.typeof(a) for a in warmup.placeholder())
    assert sig in [tuple(s) for s in vouch_buffer.signatures]


def test_child_imports_this_distkin_not_the_working_folders(tmp_path):
    """Run from a folder holding another ``distkin`` (a source checkout beside an
    installed one: ``python -c`` puts the working folder first on the path), the child
    imports this process's distkin (the README's first command, run in the clone, had
    the child compile the checkout's copy while the installed one compiled again)."""
    fake = tmp_path / "distkin"
    fake.mkdir()
    (fake / "__init__.py").write_text("raise ImportError('the copy in the working folder')\n")
    import distkin
    r = subprocess.run([sys.executable, "-c", warmup._child_program(
        "import distkin; print(distkin.__file__)")], cwd=tmp_path, capture_output=True,
        text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert Path(r.stdout.strip()).resolve() == Path(distkin.__file__).resolve()


class _Spy:
    """A stand-in for :class:`subprocess.Popen` that runs the given program and keeps
    the process for the test to look at."""
    made = []
    popen = subprocess.Popen        # the real one (the fixture replaces the module's)

    def __init__(self, argv, **kw):
        self.proc = _Spy.popen(argv, **kw)
        _Spy.made.append(self.proc)

    def __getattr__(self, name):
        return getattr(self.proc, name)


@pytest.fixture
def spy(monkeypatch):
    _Spy.made = []
    monkeypatch.setattr(warmup.subprocess, "Popen", _Spy)
    return _Spy


def test_nothing_runs_when_both_chains_are_cached(spy, monkeypatch):
    monkeypatch.setattr(warmup, "pending_chains", lambda: ())
    monkeypatch.setattr(warmup, "_compile_scan", lambda: pytest.fail("compiled again"))
    said = []
    assert warmup.compile_fast_tier(notice=said.append) == ()
    assert spy.made == [] and said == []              # nothing to compile: nothing said


def test_child_is_waited_for(spy, monkeypatch):
    """The child (here a program that exits 7 after 0.3 s) has ended when the call
    returns, and the scan was compiled in this process meanwhile."""
    monkeypatch.setattr(warmup, "pending_chains", lambda: ("scan", "proof"))
    monkeypatch.setattr(warmup, "_CHILD", "import time, sys; time.sleep(0.3); sys.exit(7)")
    done, said = [], []
    monkeypatch.setattr(warmup, "_compile_scan", lambda: done.append("scan"))
    import distkin.octahedral.single as single
    monkeypatch.setattr(single, "compile_notice", lambda: "compiling (stand-in)")
    assert warmup.compile_fast_tier(notice=said.append) == ("scan", "proof")
    assert done == ["scan"] and said == ["compiling (stand-in)"]   # said before, once
    assert [p.returncode for p in spy.made] == [7]


def test_child_is_killed_when_interrupted(spy, monkeypatch):
    """Ctrl-C during this process's compile: the KeyboardInterrupt goes on, and the
    child (a program that would sleep 60 s) is no longer running."""
    monkeypatch.setattr(warmup, "pending_chains", lambda: ("scan", "proof"))
    monkeypatch.setattr(warmup, "_CHILD", "import time; time.sleep(60)")

    def interrupted():
        raise KeyboardInterrupt
    monkeypatch.setattr(warmup, "_compile_scan", interrupted)
    with pytest.raises(KeyboardInterrupt):
        warmup.compile_fast_tier()
    assert len(spy.made) == 1 and spy.made[0].poll() is not None


def test_slow_child_is_given_up(spy, monkeypatch):
    """A child still running after ``timeout`` is killed and the call returns."""
    monkeypatch.setattr(warmup, "pending_chains", lambda: ("proof",))
    monkeypatch.setattr(warmup, "_CHILD", "import time; time.sleep(60)")
    assert warmup.compile_fast_tier(timeout=0.2) == ("proof",)
    assert spy.made[0].poll() is not None


_SOLVE = r"""
import json, sys, numpy as np
from distkin.octahedral import forward_kinematics, warmup
B = np.array([[0.0, 0.0, 0.0], [12.0, 0.0, 0.0], [6.0, 6.0 * 3 ** 0.5, 0.0]])
before = warmup.pending_chains()
done = warmup.compile_fast_tier() if sys.argv[1] == "warm" else ()
after = warmup.pending_chains()
r = forward_kinematics(B, 0.5 * B, [20.0, 18.0, 18.0, 17.0, 15.0, 18.0])
print(json.dumps({"before": before, "done": done, "after": after,
                  "s15": [float(x.value).hex() for x in r.roots],
                  "poses": [float(v).hex() for x in r.poses for v in x.translation],
                  "trusted": bool(r.conditioning.trusted)}))
"""


@pytest.mark.slow
def test_fresh_cache_compiled_in_two_processes(tmp_path):
    """Fresh numba caches (``NUMBA_CACHE_DIR``): ``compile_fast_tier`` leaves nothing
    pending, and the solve that follows, and one in a later process, equal bit for bit
    the solve of a process that compiled everything itself (another fresh cache)."""
    def run(cache, mode):
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / cache),
                   PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
        r = subprocess.run([sys.executable, "-c", _SOLVE, mode], capture_output=True,
                           text=True, env=env, timeout=900)
        assert r.returncode == 0, r.stderr
        return json.loads(r.stdout)
    warm, later, alone = run("a", "warm"), run("a", "plain"), run("b", "plain")
    assert warm["before"] == ["scan", "proof"] and warm["done"] == ["scan", "proof"]
    assert warm["after"] == [] and later["before"] == []
    assert alone["before"] == ["scan", "proof"]
    assert warm["s15"] == later["s15"] == alone["s15"] and warm["trusted"]
    assert warm["poses"] == later["poses"] == alone["poses"] and len(warm["s15"]) == 6
