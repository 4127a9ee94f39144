"""Exact where exact (QA 23 D5; report.py: exact numbers travel as strings): a certified
Cayley-Menger determinant of rational points is an exact string ("2809/2"), and so is
its area or volume interpretation ("2809/576"), with its float beside it in
``*_float``.  Checked against the triangle's and tetrahedra's own areas and volumes,
computed here with Fractions from the points (cross and triple products)."""

import json
from fractions import Fraction

import pytest

from distkin.app.cli import main

P = [(0, 0, 0), (6, 0, 0), (2, 5, 0), (1, 1, 4), (3, -2, Fraction(5, 2)),
     (Fraction(-1, 2), 3, 2)]          # examples/points_banana.toml's points P1..P6

SCENE = """
[mechanism]
kind = "points"
points = [[0, 0, 0], [6, 0, 0], [2, 5, 0], [1, 1, 4], [3, -2, "5/2"], ["-1/2", 3, 2]]

[[query]]
type = "cayley_menger"
determinants = ["D(5,4,1,2)", "D(5,4,1,6)", "D(1,2,3)"]
method = "{method}"
"""


def _sub(a, b):
    return [Fraction(x) - Fraction(y) for x, y in zip(a, b)]


def _cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def _volume_squared(i, j, k, m):
    a, b, c = (_sub(P[n - 1], P[i - 1]) for n in (j, k, m))
    return (sum(x * y for x, y in zip(a, _cross(b, c))) / 6) ** 2


def _area_squared(i, j, k):
    n = _cross(_sub(P[j - 1], P[i - 1]), _sub(P[k - 1], P[i - 1]))
    return sum(x * x for x in n) / 4


def _run(tmp_path, capsys, method):
    f = tmp_path / "s.toml"
    f.write_text(SCENE.format(method=method), encoding="utf-8")
    assert main(["run", str(f), "--json", "-"]) == 0
    return json.loads(capsys.readouterr().out)["queries"][0]["result"]


def _text(x: Fraction) -> str:
    return str(x.numerator) if x.denominator == 1 else f"{x.numerator}/{x.denominator}"


def test_certified_interpretations_are_exact_strings(tmp_path, capsys):
    r = _run(tmp_path, capsys, "certified")
    want = [("tetrahedron_volume_squared", _volume_squared(5, 4, 1, 2)),
            ("tetrahedron_volume_squared", _volume_squared(5, 4, 1, 6)),
            ("triangle_area_squared", _area_squared(1, 2, 3))]
    assert want[1][1] == Fraction(2809, 576)
    for entry, (key, exact) in zip(r["determinants"], want):
        assert entry[key] == _text(exact)
        assert entry[f"{key}_float"] == float(exact)
        assert r["unit"][f"{key}_float"] == r["unit"][key] == {
            "tetrahedron_volume_squared": "m^6", "triangle_area_squared": "m^4"}[key]


@pytest.mark.parametrize("method", ["fast", "precise"])
def test_other_tiers_give_floats(tmp_path, capsys, method):
    r = _run(tmp_path, capsys, method)
    entry = r["determinants"][1]
    assert entry["tetrahedron_volume_squared"] == entry["tetrahedron_volume_squared_float"]
    assert entry["tetrahedron_volume_squared"] == pytest.approx(2809 / 576, rel=1e-12)
