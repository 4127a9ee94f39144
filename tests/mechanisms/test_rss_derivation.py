"""``derivations/rss_model.py`` checks its printed claims with ``check()`` (a
``SystemExit`` naming the claim), as ``octahedral_octic.py`` and ``delta_transform.py``
do: its ten bare ``assert`` statements were skipped under ``python -O`` (or
``PYTHONOPTIMIZE=1``), so a broken claim still exited 0 (QA G 8).

Reference: Python's own parse of the scripts (``ast``), and the script run under ``-O``,
where an ``assert`` would not run but ``check()`` does.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted((ROOT / "derivations").glob("*.py"))


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_derivation_scripts_check_without_assert(script):
    tree = ast.parse(script.read_text(encoding="utf-8"))
    asserts = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Assert)]
    assert asserts == [], f"{script.name}: assert on lines {asserts} (skipped under -O)"
    checks = [n for n in ast.walk(tree) if isinstance(n, ast.Call)
              and isinstance(n.func, ast.Name) and n.func.id == "check"]
    assert checks, f"{script.name}: no check() call"


def test_check_fails_loudly_even_under_optimisation():
    """check() of the script: a failed claim is a non-zero exit naming it, with -O too."""
    code = ("import runpy, sys; sys.argv = ['x']; "
            "ns = runpy.run_path('derivations/rss_model.py', run_name='not_main'); "
            "ns['check'](1 == 2, 'a false claim')")
    r = subprocess.run([sys.executable, "-O", "-c", code], cwd=ROOT, capture_output=True,
                       text=True, timeout=300,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 1 and r.stderr.strip() == "CHECK FAILED: a false claim"


@pytest.mark.slow
def test_rss_derivation_passes_under_python_O():
    """About 40 s: every claim checked (55 'ok:' lines) and exit 0, under -O."""
    r = subprocess.run([sys.executable, "-O", str(ROOT / "derivations" / "rss_model.py")],
                       capture_output=True, text=True, timeout=900,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert r.stdout.count("ok:") >= 50 and "all checks passed" in r.stdout
