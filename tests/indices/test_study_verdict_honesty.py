"""The study's verdicts say what was computed (QA round L, items 2, 3, 4, 12): a value at
its threshold within float64 rounding is undecided, not NOT held; Table IV's range is
the one the grid covers; a device that reaches nothing has no GII, no σ and undecided
criteria; rotations beyond 180° are refused.  References: the analytic 1 m/s of
prismatic legs (unit Plücker rows), the grid's own angle values, an empty grid."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from distkin.indices.workspace import PoseGrid, axis_values, design_criteria

EX = Path(__file__).resolve().parents[2] / "examples"


def _performance_only(text: str) -> str:
    """The example scene with its performance query only (no certificate)."""
    head, *queries = text.split("[[query]]")
    perf = next(q for q in queries if 'type = "performance"' in q)
    perf = re.sub(r"(?m)^certify.*$", "", perf)
    return head + "[[query]]" + perf


def test_an_exact_1_m_s_is_not_a_shortfall(tmp_path):
    """Griffis-Duffy with prismatic legs at 1 m/s: each row of J is a unit Plücker line
    (‖J_{i,S}‖ = 1), so the worst translational velocity is exactly 1 m/s at every pose.
    Float64 gives 1 - 1 ulp; criterion 3 (>= 1 m/s) must not call that NOT held (the
    old verdict): it is at the threshold, undecided."""
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = _performance_only((EX / "griffis_duffy_indices.toml").read_text(encoding="utf-8"))
    scene = loads_scene(text, str(tmp_path / "gd.toml"))
    records, texts, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    dev = records[0]["result"]["devices"][0]
    c3 = dev["criteria"][2]
    assert c3["number"] == 3
    assert c3["value"]["velocity_m_s"] == pytest.approx(1.0, rel=1e-12, abs=0)
    assert c3["held"] is not False
    assert "at the threshold" in c3["value"]["note"]
    assert "3) undecided: velocity at the threshold" in texts[0]


def test_at_the_threshold_within_rounding_is_undecided_in_the_criteria():
    """One ulp below 1 m/s on a grid covering the 150 mm cube and ±30°, everything else
    passing: undecided; a real shortfall (1e-9 relative) is still NOT held, a real
    margin held."""
    t = tuple(axis_values(-0.075, 0.075, 0.075))
    r = tuple(np.radians([-30, 0, 30]))
    g = PoseGrid(t, t, tuple(0.3 + np.array(t)), r, r, r)
    n = g.n_positions
    minima = {"velocity": np.full(n, np.nextafter(1.0, 0.0)),
              "acceleration": np.full(n, 20.0), "force": np.full(n, 5.0)}
    kw = dict(sigma_min=0.1, transmission_min=0.5, sensitivities_max=[1, 1, 1, 1])
    c3 = design_criteria(8, g, np.ones(n, bool), minima, **kw)[2]
    assert c3["held"] is None and "at the threshold" in c3["value"]["note"]
    minima["velocity"][:] = 1 - 1e-9
    assert design_criteria(8, g, np.ones(n, bool), minima, **kw)[2]["held"] is False
    minima["velocity"][:] = 1 + 1e-9
    assert design_criteria(8, g, np.ones(n, bool), minima, **kw)[2]["held"] is True


PERF = """[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octopod"
[[query]]
type = "performance"
devices = [ DEVICES ]
grid = GRID
workers = 1
"""


def _run(tmp_path, devices, grid):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = PERF.replace("DEVICES", devices).replace("GRID", grid)
    scene = loads_scene(text, str(tmp_path / "p.toml"))
    records, texts, worst = run_scene(scene, progress=False)
    return records[0], texts[0], worst


def test_table_iv_range_is_the_one_the_grid_covers(tmp_path, capsys):
    """rotation ±30° in steps of 15°: the grid's angles are 0, ±15°, ±30°, so the
    orientations within the default inner ±20° cover ±15°.  The old label said ±20°."""
    rec, text, worst = _run(tmp_path, '{ label = "Octopod", preset = "octopod", rotation = 30 }',
                            "{ half = 50, step = 50, rotation_step = 15 }")
    assert worst == 0, rec.get("error")
    iso = rec["result"]["devices"][0]["isotropy"]
    angles = np.degrees(axis_values(-math.radians(30), math.radians(30), math.radians(15)))
    within = max(a for a in angles if a <= 20 + 1e-9)
    assert iso["rotation_deg"] == pytest.approx(within)           # 15°
    assert iso["rotation_requested_deg"] == pytest.approx(20)
    assert f"orientations (±{within:.0f}°; the paper: Table II's ±20°)" in text
    assert "not on the grid" in iso["rotation_note"]
    assert "inner_rotation ±20° is not on the grid" in capsys.readouterr().err


@pytest.mark.parametrize("devices, grid, field", [
    ('{ label = "Octopod", preset = "octopod", rotation = 200 }',
     "{ half = 50, step = 50, rotation_step = 100 }", "devices[0].rotation"),
    ('{ label = "Octopod", preset = "octopod" }',
     "{ half = 50, step = 50, rotation = 190, rotation_step = 190 }", "grid.rotation")])
def test_a_rotation_beyond_180_degrees_is_refused(tmp_path, devices, grid, field):
    """±200° about an axis wraps onto ∓160°: the same orientations twice (the old code
    accepted it and reduced Table IV over orientation 0 only)."""
    from distkin.app.scene import loads_scene
    from distkin.errors import InputError
    text = PERF.replace("DEVICES", devices).replace("GRID", grid)
    with pytest.raises(InputError, match="at most 180 deg") as err:
        loads_scene(text, str(tmp_path / "p.toml"))
    assert err.value.field.endswith(field)


def test_a_device_that_reaches_nothing_has_no_gii_and_undecided_criteria(tmp_path):
    """The Hunt-type with its home 5 m up (z0 = 5000 mm): no pose of its grid is
    reachable.  Table IV shows "—" (None in the JSON), not 0.0000, and no criterion is
    NOT held on placeholder zeros; its criterion 5 names the Octopod it does not compare
    with (8 legs > 6).  A study in which *no* device reaches a pose has no answer at all:
    exit 2 (QA V 14; it was exit 0 with every value null, where a design sweep refuses)."""
    rec, text, worst = _run(
        tmp_path, '{ label = "Octopod", preset = "octopod", rotation = 20 }, '
                  '{ label = "Hunt-type", preset = "hunt", rotation = 20, z0 = 5000 }',
        "{ half = 10, step = 10, rotation_step = 20 }")
    assert worst == 0, rec.get("error")
    octopod, dev = rec["result"]["devices"]
    assert octopod["reachable_poses"] > 0 and dev["reachable_poses"] == 0
    iso = dev["isotropy"]
    assert iso["gii"] is None and iso["sigma_min"] is None and iso["sigma_max"] is None
    assert all(c["held"] is None for c in dev["criteria"])
    assert [c["value"]["note"] for c in dev["criteria"]] == \
        ["undecided: no reachable pose"] * 6
    table4 = [ln for ln in text.splitlines() if ln.startswith("| Hunt-type | yes |")]
    assert table4 and table4[0].split(" | ")[2] == "—"
    hunt = next(ln for ln in text.splitlines() if ln.strip().startswith("Hunt-type: 1)"))
    assert "not compared: Octopod" in hunt and "NOT held" not in hunt
    assert "Hunt-type: reaches no pose of its grid" in text
    json.dumps(rec["result"], allow_nan=False)     # None, not NaN or "inf"
    rec, text, worst = _run(
        tmp_path, '{ label = "Octopod", preset = "octopod", rotation = 20 }, '
                  '{ label = "Hunt-type", preset = "hunt", rotation = 20 }',
        "{ half = 5000, step = 10000, rotation_step = 20 }")
    assert worst == 2 and rec["error"]["kind"] == "infeasible"
    assert "got none that does (Octopod: home z = " in rec["error"]["message"]


def test_study_json_says_the_units_of_unlabelled_fields(tmp_path):
    """QA V: the worst poses, the actuator figures and the dexterous-workspace thresholds
    had no unit.  Every key of those gets one, and a worst pose is a pose of the grid in
    m and rad (reference: the grid's own axes, from its JSON, in m)."""
    rec, _, worst = _run(tmp_path, '{ label = "Hunt-type", preset = "hunt", rotation = 20 }',
                         "{ half = 75, step = 75, rotation_step = 20 }")
    assert worst == 0, rec.get("error")
    res = rec["result"]
    unit = res["unit"]
    assert set(unit["actuators"]) == set(res["actuators"]) and \
        unit["actuators"]["nominal_torque"] == "N·m"
    dev = res["devices"][0]
    assert set(unit["devices[].dexterous_workspace.thresholds"]) == \
        set(dev["dexterous_workspace"]["thresholds"])
    g = res["grid"]["Hunt-type"]
    for pose in dev["worst_poses"].values():
        assert any(abs(pose[0] - v) < 1e-12 for v in g["x_m"])
        assert any(abs(pose[3] - v) < 1e-12 for v in g["rx_rad"])
    assert unit["devices[].worst_poses"].startswith("x, y, z in m, rx, ry, rz in rad")
