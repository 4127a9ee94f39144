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
