"""Numbers the README quotes for an example scene are what that scene gives.

Each test reads the number from README.md's own text and runs the example's query, so a
README that drifts from the code fails here (the README once claimed σmin(Jx) ≥ 0.0040
for the Δ 6-6 platform, whose certified bound is 0.00395, and 5.7 % singular for
``examples/certify_hexa.toml``, which gives 5.3 %).
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from distkin.app.cli import run_scene
from distkin.app.scene import load_scene

ROOT = Path(__file__).resolve().parents[2]
README = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())


def _run(example: str, qtype: str) -> dict:
    scene = load_scene(ROOT / "examples" / example)
    q = next(q for q in scene.queries if q.type == qtype)
    records, _, worst = run_scene(dataclasses.replace(scene, queries=(q,)), progress=False)
    assert worst == 0, records
    return records[0]["result"]


def _readme(pattern: str):
    m = re.search(pattern, README)
    assert m, f"README.md no longer says {pattern!r}"
    return m


def test_platform_sigma_bounds_hold():
    """README: 'certified singularity-free over the 4 cm cube × ±10° (6-D; σmin(Jx) ≥ A
    and ≥ B)' for the octahedral manipulator and its Δ 6-6 platform: each is a lower
    bound, so the certified value must be at least the quoted one (and round to it)."""
    m = _readme(r"σmin\(Jx\) ≥ ([0-9.]+) and ≥ ([0-9.]+)\)")
    for example, quoted in (("griffis_duffy_indices.toml", m[1]),
                            ("delta66_indices.toml", m[2])):
        bound = _run(example, "certify_workspace")["sigma_lower_min"]
        digits = len(quoted.split(".")[1])
        assert bound >= float(quoted), (example, bound, quoted)
        assert bound < float(quoted) + 10.0 ** -digits, (example, bound, quoted)


def test_radial_hexa_singular_fraction():
    """README: '(`examples/certify_hexa.toml`) has certified singular regions (S % of the
    cube, U % undecided at the resolution'."""
    m = _readme(r"certify_hexa\.toml`\) has certified singular regions \(([0-9.]+) % of the "
                r"cube, ([0-9.]+) % undecided")
    res = _run("certify_hexa.toml", "certify_workspace")
    assert 100 * res["singular_fraction"] == pytest.approx(float(m[1]), abs=0.05)
    assert 100 * res["undecided_fraction"] == pytest.approx(float(m[2]), abs=0.05)
