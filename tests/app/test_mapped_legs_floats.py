"""A 6-6 platform's m-legs and mapped l-legs in the JSON (QA 23 D7): each exact
``mapped_legs`` entry (~52 KB of nested radicals for measured float data) has its float
beside it in ``mapped_legs_float``, and ``m_legs`` are given as used: the scene's bare
floats as JSON numbers (their binary values, which ``inputs_from_float`` lists), an
exact text as its string (report.py: a string is an exact value).

Independent routes: the floats against the exact strings evaluated by sympy at 50
digits, and against the legs of the 6-6 platform's own poses (each pose closes its
m-legs within ``max_leg_error``; its equivalent octahedron's legs are the l-legs)."""

import json
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from distkin.app.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "platform66_measured.toml"


def _run(tmp_path, capsys, text):
    f = tmp_path / "s.toml"
    f.write_text(text, encoding="utf-8")
    assert main(["run", str(f), "--json", "-"]) == 0
    return json.loads(capsys.readouterr().out)["queries"][0]["result"]


def test_measured_platform_gives_floats_beside_the_radicals(tmp_path, capsys):
    text = EXAMPLE.read_text(encoding="utf-8")
    r = _run(tmp_path, capsys, text)
    assert r["m_legs"] == [17.4, 17.9, 17.4, 17.9, 17.4, 17.9]      # the scene's floats
    assert all(f"query[0].legs[{i}]" in r["inputs_from_float"] for i in range(6))
    assert r["unit"]["mapped_legs_float"] == r["unit"]["mapped_legs"] == "mm"
    for exact, value in zip(r["mapped_legs"], r["mapped_legs_float"]):
        assert isinstance(value, float)
        assert value == pytest.approx(float(sp.N(sp.sympify(exact), 50)), rel=2e-16)
    # the equivalent octahedron's legs P_iP_j at each pose are the l-legs (eq. (8))
    pairs = [(0, "P4"), (1, "P4"), (1, "P5"), (2, "P5"), (2, "P6"), (0, "P6")]
    base = np.array([[0, 0, 0], [6.1, 10.2, 0], [12.3, 0.4, 0]])
    for pose in r["poses"]:
        legs = [np.linalg.norm(base[i] - np.array(pose["points"][k])) for i, k in pairs]
        assert legs == pytest.approx(r["mapped_legs_float"], rel=1e-9)


def test_exact_m_legs_stay_strings(tmp_path, capsys):
    text = EXAMPLE.read_text(encoding="utf-8").replace(
        "legs = [17.4, 17.9, 17.4, 17.9, 17.4, 17.9]",
        'legs = ["17.4", "17.9", "17.4", "17.9", "17.4", "17.9"]')
    r = _run(tmp_path, capsys, text)
    assert r["m_legs"] == ["17.4", "17.9", "17.4", "17.9", "17.4", "17.9"]
    assert not any(n.startswith("query[0].legs") for n in r["inputs_from_float"])
