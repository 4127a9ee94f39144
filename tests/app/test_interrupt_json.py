"""Ctrl-C or SIGTERM during ``distkin run SCENE --json F`` (QA 23 D1): the JSON contract
still comes out, written atomically, with the queries that finished, the interrupted one
(status ``error``, kind ``interrupted``) and, at the top level, ``"interrupted": true``
and ``not_run`` naming the queries that never started (README "Using it"); exit 130 as
before.  An earlier run's F is replaced, never left looking current."""

import json
import os
import signal
import time
from dataclasses import replace

import pytest

from distkin.app import cli, registry

SCENE = """
[units]
length = "mm"
angle = "deg"

[mechanism]
kind = "rss"
preset = "octopod"

[[query]]
type = "inverse_kinematics"
poses = [[0, 0, 300, 0, 0, 0]]

[[query]]
type = "jacobian"
poses = [[0, 0, 300, 0, 0, 0]]

[[query]]
type = "inverse_kinematics"
poses = [[0, 0, 310, 0, 0, 0]]
"""


@pytest.fixture
def jacobian_gets_sigterm(monkeypatch):
    """The jacobian query sends this process SIGTERM (as ``timeout`` or ``kill``), then
    would sleep: the real handler has to stop it."""
    real_get = registry.get

    def run(params, scene, ctx):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(30)
        raise AssertionError("the SIGTERM did not stop the query")

    def get(name, kind=None, field="type"):
        spec = real_get(name, kind, field)
        return replace(spec, run=run) if name == "jacobian" else spec

    monkeypatch.setattr(registry, "get", get)


def _check(doc, scene_path):
    assert doc["scene"] == scene_path
    assert doc["interrupted"] is True
    assert doc["not_run"] == [{"field": "query[2]", "type": "inverse_kinematics"}]
    first, second = doc["queries"]
    assert first["type"] == "inverse_kinematics" and first["status"] == "ok"
    assert len(first["result"]["poses"][0]["q"]) == 8   # the octopod's 8 cranks, finished
    assert second["type"] == "jacobian" and second["status"] == "error"
    assert second["error"]["kind"] == "interrupted"
    assert "query[1]" in second["error"]["message"]
    assert "query[2]" in second["error"]["message"]
    assert second["result"] == {}


def test_interrupt_writes_what_finished_over_a_stale_file(tmp_path, capsys,
                                                          jacobian_gets_sigterm):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE, encoding="utf-8")
    out = tmp_path / "r.json"
    out.write_text('{"distkin": "earlier run", "queries": []}\n', encoding="utf-8")
    assert cli.main(["run", str(scene), "--json", str(out), "--no-progress"]) == 130
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1] == "distkin: error: interrupted"
    _check(json.loads(out.read_text(encoding="utf-8")), str(scene))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json", "s.toml"]  # no .tmp


def test_interrupt_with_json_on_stdout(tmp_path, capsys, jacobian_gets_sigterm):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE, encoding="utf-8")
    assert cli.main(["run", str(scene), "--json", "-", "--no-progress"]) == 130
    _check(json.loads(capsys.readouterr().out), str(scene))


def test_an_uninterrupted_document_has_no_interrupt_keys(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE, encoding="utf-8")
    assert cli.main(["run", str(scene), "--json", "-", "--no-progress"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert "interrupted" not in doc and "not_run" not in doc
    assert [q["status"] for q in doc["queries"]] == ["ok"] * 3


def test_demo_interrupted_lists_the_built_in_queries_not_run(monkeypatch, tmp_path, capsys):
    """``distkin demo``: the same keys; ``not_run`` names each later query with its
    scene (the built-in scenes' own query lists, read here from their files)."""
    from importlib import resources

    from distkin.app.scene import loads_scene
    real_get = registry.get

    def run(params, scene, ctx):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(30)

    def get(name, kind=None, field="type"):
        spec = real_get(name, kind, field)
        return replace(spec, run=run) if name == "delta_transform" else spec

    monkeypatch.setattr(registry, "get", get)
    out = tmp_path / "demo.json"
    assert cli.main(["demo", "--json", str(out), "--no-progress"]) == 130
    doc = json.loads(out.read_text(encoding="utf-8"))
    scenes = {n: loads_scene(resources.files("distkin.scenes").joinpath(n).read_text(
        encoding="utf-8"), f"distkin/scenes/{n}") for n in cli.DEMO_SCENES}
    first, second = (scenes[n] for n in cli.DEMO_SCENES[:2])
    assert second.queries[0].type == "delta_transform"
    assert [(q["scene"], q["status"]) for q in doc["queries"]] == (
        [(first.path, "ok")] * len(first.queries) + [(second.path, "error")])
    assert doc["queries"][-1]["error"]["kind"] == "interrupted"
    assert doc["interrupted"] is True
    assert doc["not_run"] == [{"scene": s.path, "field": q.field, "type": q.type}
                              for s in scenes.values() for q in s.queries][
        len(first.queries) + 1:]
