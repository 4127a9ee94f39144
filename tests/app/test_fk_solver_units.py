"""The rss/legs forward kinematics names the unit of every figure it gives (QA 23 D6):
``guess`` (given back in SI, though the scene wrote mm and deg), ``sigma_min``,
``condition`` and, certified, ``other_legs_closure_bound`` (m, DESIGN/README) and
``contraction`` had no entry in the result's ``unit`` block.  The stated unit of
``guess`` is checked against the scene's guess converted by hand (mm -> m, deg -> rad)."""

import json
import math

import pytest

from distkin.app.cli import main

SCENE = """
[units]
length = "mm"
angle = "deg"

[mechanism]
kind = "rss"
preset = "octopod"

[[query]]
type = "forward_kinematics"
angles = [18.99, 21.35, 31.55, 32.47, 30.91, 31.52, 18.66, 20.50]
guess = [5, -3, 300, 2, -1, 4]
residual_tol = 0.01
method = "{method}"
"""


@pytest.mark.parametrize("method", ["fast", "certified"])
def test_every_solver_figure_has_a_unit(tmp_path, capsys, method):
    f = tmp_path / "s.toml"
    f.write_text(SCENE.format(method=method), encoding="utf-8")
    assert main(["run", str(f), "--json", "-"]) == 0
    r = json.loads(capsys.readouterr().out)["queries"][0]["result"]
    figures = ["guess", "sigma_min", "condition"]
    if method == "certified":
        figures += ["other_legs_closure_bound", "contraction"]
        assert r["unit"]["other_legs_closure_bound"].split()[0] == "m"
        assert 0 <= r["contraction"] < 1
    for key in figures:
        assert key in r and key in r["unit"], key
    assert r["unit"]["guess"].startswith("m, rad")
    want = [0.005, -0.003, 0.3] + [math.radians(a) for a in (2, -1, 4)]
    assert r["guess"] == pytest.approx(want, rel=1e-15)
    assert r["unit"]["sigma_min"].startswith("none")
    assert r["unit"]["condition"].startswith("none")
    assert r["condition"] >= 1
