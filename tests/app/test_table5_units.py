"""QA X1 D5: the ``table5`` query in a mm/deg scene.  ``step_angle = -5`` was refused as
``query[0].step: expected positive steps, got 0.04 m, -0.0873 rad`` (the wrong field,
in SI units the user never wrote); its JSON gave the worst poses in m and rad with no
unit while the scene says mm and deg, and its text named a 40 mm / 0.4 rad step
whatever the scene asked for."""

import math

import pytest

import distkin.app.queries.control as q5
from distkin.app.queries.control import Table5Query
from distkin.app.registry import RunContext
from distkin.app.scene import loads_scene
from distkin.errors import InputError

SCENE = """
[units]
length = "{length}"
angle = "{angle}"
[mechanism]
kind = "rss"
preset = "octo"
[[query]]
type = "table5"
{extra}
"""


@pytest.mark.parametrize("extra, field, got", [
    ("step_angle = -5", "query[0].step_angle", "got -5 deg"),
    ("step = 0", "query[0].step", "got 0 mm"),
    ("step = -40\nstep_angle = 5", "query[0].step", "got -40 mm"),
])
def test_a_bad_step_is_named_in_the_scene_units(extra, field, got):
    with pytest.raises(InputError) as exc:
        loads_scene(SCENE.format(length="mm", angle="deg", extra=extra))
    assert exc.value.field == field and exc.value.message.endswith(got)
    assert "rad" not in exc.value.message and " m," not in exc.value.message


def test_the_steps_reach_the_run_in_si():
    s = loads_scene(SCENE.format(length="mm", angle="deg",
                                 extra="step = 20\nstep_angle = 10"))
    _, _, step, ang, _ = s.queries[0].params
    assert step == pytest.approx(0.020) and ang == pytest.approx(math.radians(10))


def test_json_poses_are_in_the_scene_units_with_a_unit_block(monkeypatch):
    """The run replaced by one row at a known pose (m, rad): 75 mm, 30 deg by hand."""
    seen = {}

    def fake(name, *, trials, step_m, step_rad, units):
        seen.update(step_m=step_m, step_rad=step_rad, units=units)
        return {"velocity": {"unit": "m/s", "emulated": 1.0, "analysis": 2.0,
                             "paper_experiment": 1.12, "paper_simulation": 2.93,
                             "pose": [0.075, -0.075, 0.375, math.pi / 6, 0.0, -math.pi / 6],
                             "direction": [1, 0, 0, 0, 0, 0], "end_stop_hits": 0,
                             "kind": "free"}}
    monkeypatch.setattr(q5, "run_table5", fake)
    s = loads_scene(SCENE.format(length="mm", angle="deg", extra="step = 20\nstep_angle = 10"))
    out = Table5Query.run(s.queries[0].params, s, RunContext())
    assert seen["step_m"] == pytest.approx(0.02)
    # a refused step is named in the scene's units (table5._reachable_step)
    assert seen["units"]["step"][:2] == ("step", "mm")
    assert seen["units"]["step"][2] == pytest.approx(1000.0)
    assert seen["units"]["step_angle"][:2] == ("step_angle", "deg")
    assert seen["units"]["step_angle"][2] == pytest.approx(180 / math.pi)
    pose = out.result["rows"]["velocity"]["pose"]
    assert pose == pytest.approx([75, -75, 375, 30, 0, -30])
    assert out.result["unit"]["pose"] == "mm, mm, mm, deg, deg, deg"
    assert (out.result["step"], out.result["step_angle"]) == pytest.approx((20, 10))
    assert "a 20 mm / 10 deg step" in out.text and "40 mm" not in out.text
    assert "velocity (75, -75, 375, 30, 0, -30)" in out.text


def test_the_table_prints_ours_alike_in_fixed_notation(monkeypatch):
    """QA 24: one column mixed "10.3", "9.921" and "2.346e+04".  Reference: the rows the
    run returned (faked here), read back from the printed table."""
    rows = {"force": (9.9213, 10.3, 15.27, 16.02, "N"),
            "angular_acceleration": (5353.2, 23456.7, 7051.21, 34341.13, "rad/s²")}

    def fake(name, *, trials, step_m, step_rad, units):
        return {k: {"unit": u, "emulated": e, "analysis": a, "paper_experiment": pe,
                    "paper_simulation": ps, "pose": [0.0] * 6, "direction": [1, 0, 0, 0, 0, 0],
                    "end_stop_hits": 0, "kind": "free"} for k, (e, a, pe, ps, u) in rows.items()}
    monkeypatch.setattr(q5, "run_table5", fake)
    s = loads_scene(SCENE.format(length="mm", angle="deg", extra=""))
    text = Table5Query.run(s.queries[0].params, s, RunContext()).text
    got = {line.split("|")[1].split("[")[0].strip().replace(" ", "_"): line.split("|")[2:5]
           for line in text.splitlines() if line.startswith("| ") and "[" in line.split("|")[1]}
    assert [c.strip() for c in got["force"]] == ["9.921", "10.30", "0.963×"]
    assert [c.strip() for c in got["angular_acceleration"]] == ["5353", "23457", "0.228×"]
    assert "e+0" not in text
    for k, (e, a, *_rest) in rows.items():              # the printed values are the run's
        assert float(got[k][0]) == pytest.approx(e, rel=5e-4)
        assert float(got[k][1]) == pytest.approx(a, rel=5e-4)
