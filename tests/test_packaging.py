"""What the package declares (pyproject.toml) and ships (MANIFEST.in, LICENSE): QA pkg.

* python-flint's floor: distkin calls ``fmpz_poly.is_zero`` (exact_roots, exact,
  geometry/poses, app/queries/geometry), which python-flint has from 0.7; with the
  allowed 0.6 the certified octahedral FK crashed (``'fmpz_poly' object has no
  attribute 'is_zero'``)."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def _floor(name: str) -> tuple[int, ...]:
    spec = next(d for d in PYPROJECT["project"]["dependencies"]
                if re.match(rf"{re.escape(name)}\b", d))
    m = re.search(r">=\s*([\d.]+)", spec)
    assert m, f"expected a >= floor for {name}, got {spec!r}"
    return tuple(int(x) for x in m.group(1).split("."))


def test_the_python_flint_floor_has_what_distkin_calls():
    uses = [p.relative_to(ROOT) for p in (ROOT / "distkin").rglob("*.py")
            if ".is_zero()" in p.read_text(encoding="utf-8")]
    assert uses                                   # the reason for the floor is still there
    assert _floor("python-flint") >= (0, 7), "fmpz_poly.is_zero is new in python-flint 0.7"


def test_a_license_file_is_declared_and_shipped():
    """``License-Expression: MIT`` came without a LICENSE file (QA pkg 8)."""
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License") and "Copyright (c) 2026 the distkin developers" in text
    assert PYPROJECT["project"]["license"] == "MIT"
    assert PYPROJECT["project"]["license-files"] == ["LICENSE"]


def test_the_sdist_holds_what_the_tests_read():
    """The sdist shipped only the top-level tests/test_*.py (no conftest.py, no
    sub-folders), no examples and no docs (QA pkg 8): MANIFEST.in grafts the whole tests
    tree and every top-level folder the tests read (checked by ``python -m build
    --sdist`` and a listing of the archive when it changes)."""
    lines = [ln.split() for ln in (ROOT / "MANIFEST.in").read_text().splitlines()
             if ln.strip() and not ln.startswith("#")]
    grafted = {ln[1] for ln in lines if ln[0] == "graft"}
    included = {w for ln in lines if ln[0] == "include" for w in ln[1:]}
    assert {"tests", "examples", "docs"} <= grafted
    assert {"LICENSE", "README.md"} <= included
    read = set()
    for p in (ROOT / "tests").rglob("*.py"):
        text = p.read_text(encoding="utf-8")
        for top in ROOT.iterdir():
            if (top.is_dir() and not top.name.startswith(".") and top.name != "distkin"
                    and re.search(rf"[\"'/]{re.escape(top.name)}[\"'/]", text)):
                read.add(top.name)
    assert read - {"tests"} <= grafted, f"folders the tests read, not in the sdist: " \
                                        f"{sorted(read - grafted - {'tests'})}"
    for name in ("BENCHMARKS.md",):
        if name in "".join(p.read_text(encoding="utf-8")
                           for p in (ROOT / "tests").rglob("*.py")):
            assert name in included


def test_the_readme_says_how_to_remove_numbas_caches():
    """``pip uninstall distkin`` leaves numba's caches (``__pycache__/*.nbi``, ``*.nbc``,
    ~13 MB) in site-packages/distkin, after which ``import distkin`` finds an empty
    namespace package (QA pkg 10): while the package compiles with ``cache=True``, the
    README's set-up names the clean-up of that folder (the environment's purelib, never
    the current directory)."""
    caching = [p for p in (ROOT / "distkin").rglob("*.py")
               if "cache=True" in p.read_text(encoding="utf-8")]
    assert caching
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    setup = readme[:readme.index("## What is in it")]
    assert "pip uninstall -y distkin\n" in setup
    assert ("rm -rf \"$(python -c 'import sysconfig; print(sysconfig.get_paths()[\"purelib\"])')"
            "/distkin\"") in setup
