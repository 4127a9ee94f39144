"""The performance study's run store is keyed by every parameter that changes a number
(QA store24 1): ``route`` was in the chunks' specs but not in the store's key, so a
``route = "numpy"`` run on a store the compiled route wrote resumed every chunk and
returned the compiled numbers (21 values differed in the last bits from a fresh
numpy-route run), defeating the cross-check.  Reference: a fresh numpy-route run in a
store of its own."""

from __future__ import annotations

import numpy as np

from distkin.indices.study import study_chunk
from distkin.indices.workspace import table2_grid

HEAD = """title = "route key"
[units]
length = "mm"
angle = "deg"
[mechanism]
kind = "rss"
preset = "octopod"
[[query]]
type = "performance"
grid = {{ half = 75, step = 75, rotation = 20, rotation_step = 20 }}
workers = 1
route = "{route}"
store = "{store}"
"""

_TIMES = {"seconds", "chunks_resumed"}


def _run(tmp_path, route, store):
    from distkin.app.cli import run_scene
    from distkin.app.scene import loads_scene
    text = HEAD.format(route=route, store=store)
    scene = loads_scene(text, str(tmp_path / f"{route}.toml"))
    records, _, worst = run_scene(scene, progress=False)
    assert worst == 0, records[0].get("error")
    return records[0]["result"]


def _numbers(result):
    return [{k: v for k, v in d.items() if k not in _TIMES} for d in result["devices"]]


def test_a_numpy_route_run_on_a_compiled_store_computes_its_own_numbers(tmp_path):
    compiled = _run(tmp_path, "kernels", "shared")
    again = _run(tmp_path, "numpy", "shared")              # the QA case
    fresh = _run(tmp_path, "numpy", "fresh")
    assert again["chunks_resumed"] == 0
    assert _numbers(again) == _numbers(fresh)
    assert _numbers(compiled) != _numbers(fresh)           # the routes differ in last bits
    # the JSON says which route computed the numbers
    assert (compiled["route"], again["route"], fresh["route"]) == ("kernels", "numpy",
                                                                   "numpy")
    # and each route resumes its own chunks
    assert _run(tmp_path, "kernels", "shared")["chunks_resumed"] > 0
    assert _run(tmp_path, "numpy", "shared")["chunks_resumed"] > 0


def test_batch_is_left_out_of_the_key_because_it_changes_no_number():
    """``batch`` (poses per evaluation) is in the specs, not in the key: each pose is
    evaluated on its own, so any batch gives the same bits (both routes)."""
    from distkin.mechanisms.rss import preset
    grid = table2_grid(step=0.075, rot_step_deg=20)
    spec = {"mech": preset("octopod"), "grid": grid, "lo": 0, "hi": 9,
            "actuators": {"nominal_torque": 2.5, "stall_torque": 34.2, "velocity": 51.0},
            "ST": (15, 15, 15, 1, 1, 1), "inner": None}
    for route in ("kernels", "numpy"):
        a = study_chunk({**spec, "route": route, "batch": 20000})
        b = study_chunk({**spec, "route": route, "batch": 100})
        assert a.keys() == b.keys()
        for k in a:
            np.testing.assert_array_equal(a[k], b[k])
