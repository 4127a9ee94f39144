"""Design criterion 6 named its four maximum sensitivities by position only (QA Z2 8:
``6) held [max 0.3949, 25.87, 43.13, 0.6176]`` and a bare list in the JSON).  They are
named, as the keys of :func:`distkin.indices.max_sensitivities`, with units.  Reference:
the Table III rows of the same run (``devices[].table["sens_*"]``: their maxima and units,
computed and labelled independently of the criteria)."""

from __future__ import annotations

import numpy as np

SCENE = """title = "criterion 6"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "hunt"
[[query]]
type = "performance"
grid = { half = 25, step = 25, rotation = 10, rotation_step = 10 }
"""

NAMES = ("translational", "rotational", "force", "torque")
UNITS = {"translational": "m/rad", "rotational": "rad/rad", "force": "N/(N·m)",
         "torque": "(N·m)/(N·m)"}


def test_criterion_6_names_and_units(tmp_path):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    from distkin.app.study_report import _f
    from distkin.indices import max_sensitivities
    scene = loads_scene(SCENE, str(tmp_path / "s.toml"))
    records, texts, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    dev = records[0]["result"]["devices"][0]
    c6 = dev["criteria"][5]
    assert c6["number"] == 6
    ms, units = c6["value"]["max_sensitivities"], c6["value"]["units"]
    assert tuple(ms) == NAMES == tuple(max_sensitivities(np.eye(6)[None]))
    assert units == UNITS
    for name in NAMES:
        row = dev["table"][f"sens_{name}"]
        assert ms[name] == row["max"] and units[name] == row["unit"]
    want = "6) held [max " + ", ".join(f"{n} {_f(ms[n])} {UNITS[n]}" for n in NAMES) + "]"
    assert want in texts[0], [ln for ln in texts[0].splitlines() if "6) " in ln]
