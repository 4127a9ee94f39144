"""A Gauss-Newton start far from the pose (QA P 1, 6): the Octopod's angles of
examples/rss_octopod.toml (the IK of (25, -15, 320) mm, (10, -5, 15) deg, rounded to
0.01 deg) verify from the example's guess, and from a guess 300 mm off they stop in a
local minimum 38x residual_tol: the report must not call that the angles' least-squares
pose alone, and a tol float64 cannot take is refused."""

import json

import pytest

from distkin.app.cli import main
from distkin.app.scene import loads_scene
from distkin.errors import InputError

SCENE = """[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octopod"
[[query]]
type = "forward_kinematics"
angles = [18.99, 21.35, 31.55, 32.47, 30.91, 31.52, 18.66, 20.50]
guess = {guess}
residual_tol = 0.01
{extra}
"""


def _run(tmp_path, capsys, guess, extra=""):
    f = tmp_path / "s.toml"
    f.write_text(SCENE.format(guess=guess, extra=extra), encoding="utf-8")
    code = main(["run", str(f), "--json", str(tmp_path / "r.json")])
    out = capsys.readouterr().out
    return code, out, json.loads((tmp_path / "r.json").read_text())


def test_a_far_start_is_not_called_inconsistent_angles(tmp_path, capsys):
    code, out, doc = _run(tmp_path, capsys, "[0, 0, 300, 0, 0, 0]")
    assert code == 0 and "verified (fast tier): yes" in out       # the reference start
    code, out, doc = _run(tmp_path, capsys, "[300, 300, 50, 80, 0, 0]")
    assert code == 0 and "verified (fast tier): no" in out
    assert "or Gauss-Newton stopped in a local minimum from this start" in out


def test_a_tol_below_float64_is_refused():
    with pytest.raises(InputError) as exc:
        loads_scene(SCENE.format(guess="[0, 0, 300, 0, 0, 0]", extra="tol = 1e-30"))
    assert exc.value.field == "query[0].tol" and "1e-15" in str(exc.value)
