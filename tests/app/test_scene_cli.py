"""Scenes and the command line: the JSON contract, and bad input -> exit 2, one line."""

import json
import subprocess
import sys
import textwrap
from fractions import Fraction

import pytest

from distkin.app import registry as queries
from distkin.app.cli import main, run_scene
from distkin.errors import InfeasibleError, InputError
from distkin.app.scene import loads_scene

GOOD = """
[units]
length = "mm"

[mechanism]
kind = "points"
points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)", "D(1,2,3)"]
method = "certified"

[[query]]
type = "cayley_menger"
determinants = ["D(1,2,3,4)"]
method = "fast"
"""


def _cli(args, cwd=None):
    return subprocess.run([sys.executable, "-m", "distkin", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


def test_json_contract(tmp_path):
    f = tmp_path / "good.toml"
    f.write_text(GOOD)
    r = _cli(["run", str(f), "--json", "-"])
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert set(doc) == {"distkin", "scene", "queries"}
    assert doc["scene"] == str(f)
    assert len(doc["queries"]) == 2
    for q in doc["queries"]:
        assert q["type"] == "cayley_menger" and q["status"] == "ok"
        assert isinstance(q["seconds"], float) and "result" in q
    # analytic: D(1,2,3,4) of the unit right-angled corner = 288 * (1/6)^2 = 8 (in mm^6)
    d = doc["queries"][0]["result"]["determinants"][0]
    assert d["value"] == "8" and d["exact"] is True
    assert doc["queries"][1]["result"]["determinants"][0]["value"] == pytest.approx(8.0, rel=1e-14)
    # the readable report went to stderr, with units
    assert "mm^6" in r.stderr


def test_scene_objects_are_frozen():
    s = loads_scene(GOOD)
    assert s.units.length_factor == Fraction(1, 1000)
    with pytest.raises(AttributeError):
        s.queries = ()
    with pytest.raises(TypeError):
        s.mechanism_table["kind"] = "x"


# (fault name, scene text or None for a missing file, text expected in the one-line reason)
FAULTS = [
    ("missing file", None, "does not exist"),
    ("invalid TOML", "[mechanism\nkind=1", "valid TOML"),
    ("no mechanism", '[[query]]\ntype = "cayley_menger"\n', "mechanism"),
    ("unknown mechanism kind", '[mechanism]\nkind = "gizmo"\n', "mechanism.kind"),
    ("unknown query type",
     '[mechanism]\nkind = "points"\npoints=[[0,0,0]]\n[[query]]\ntype = "teleport"\n',
     "query[0].type"),
    ("missing field",
     '[mechanism]\nkind = "points"\npoints=[[0,0,0]]\n[[query]]\ntype = "cayley_menger"\n',
     "query[0].determinants"),
    ("wrong shape",
     '[mechanism]\nkind = "octahedral"\nbase=[[0,0,0],[1,0,0]]\nplatform=[[0,0,0],[1,0,0],[0,1,0]]\n'
     '[[query]]\ntype = "cayley_menger"\ndeterminants=["D(1,2)"]\n', "mechanism.base"),
    ("malformed number",
     '[mechanism]\nkind = "points"\npoints=[[0,0,"19,8"]]\n[[query]]\ntype = "cayley_menger"\n'
     'determinants=["D(1,1)"]\n', "mechanism.points[0][2]"),
    ("typo in a field",
     '[mechanism]\nkind = "points"\npoints=[[0,0,0],[1,0,0]]\n[[query]]\ntype = "cayley_menger"\n'
     'determinant=["D(1,2)"]\n', "unknown field"),
    ("no queries", '[mechanism]\nkind = "points"\npoints=[[0,0,0]]\n', "query"),
    ("bad method",
     '[mechanism]\nkind = "points"\npoints=[[0,0,0],[1,0,0]]\n[[query]]\ntype = "cayley_menger"\n'
     'determinants=["D(1,2)"]\nmethod="exact"\n', "query[0].method"),
    ("label out of range",
     '[mechanism]\nkind = "points"\npoints=[[0,0,0],[1,0,0]]\n[[query]]\ntype = "cayley_menger"\n'
     'determinants=["D(1,7)"]\n', "out of range"),
    ("bad units", '[units]\nlength = "furlong"\n[mechanism]\nkind = "points"\npoints=[[0]]\n',
     "units.length"),
    ("query for another mechanism",
     '[mechanism]\nkind = "octahedral"\nbase=[[0,0,0],[1,0,0],[0,1,0]]\n'
     'platform=[[0,0,0],[1,0,0],[0,1,0]]\n[[query]]\ntype = "cayley_menger"\ndeterminants=["D(1,2)"]\n',
     "needs a mechanism of kind"),
]


@pytest.mark.parametrize("name, text, expect", FAULTS, ids=[f[0] for f in FAULTS])
def test_malformed_scene_exit_2_one_line(tmp_path, name, text, expect):
    f = tmp_path / "scene.toml"
    if text is not None:
        f.write_text(text)
    r = _cli(["run", str(f)])
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert "Traceback" not in r.stderr and "Traceback" not in r.stdout
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, lines
    assert lines[0].startswith("distkin: error:") and expect in lines[0], lines[0]


def test_one_query_error_does_not_hide_others(monkeypatch):
    @queries.register("always_infeasible_test", mechanisms=("points",))
    class _Boom:
        @staticmethod
        def parse(table, mechanism, units, field):
            return None

        @staticmethod
        def run(params, scene, ctx):
            raise InfeasibleError("expected closing distances, got h^2 = -1", margin=-1.0)

    monkeypatch.setitem(queries.QUERY_MODULES, "always_infeasible_test", ())
    text = GOOD + '\n[[query]]\ntype = "always_infeasible_test"\n'
    records, texts, worst = run_scene(loads_scene(text), progress=False)
    assert [r["status"] for r in records] == ["ok", "ok", "error"]
    assert records[2]["error"]["kind"] == "infeasible"
    assert "query[2]" in records[2]["error"]["message"]
    assert worst == 2


def test_demo_runs_in_process(capsys):
    assert main(["demo", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "cayley_menger: ok" in out


def test_demo_json_follows_the_run_contract(tmp_path, capsys):
    """docs/design.md §4: the top level is {distkin, scene, queries}; the demo's was
    {distkin, demo: [one document per scene]} (QA G 2).  Reference: the [[query]] tables
    of the built-in scene files read with tomllib, and 'distkin run' of one of them."""
    import tomllib
    from importlib import resources
    from distkin._version import __version__
    from distkin.app.cli import DEMO_SCENE, DEMO_SCENES
    target = tmp_path / "demo.json"
    assert main(["demo", "--no-progress", "--json", str(target)]) == 0
    capsys.readouterr()
    doc = json.loads(target.read_text())
    assert list(doc) == ["distkin", "scene", "queries"]
    assert doc["distkin"] == __version__
    assert doc["scene"] == DEMO_SCENE and all(name in DEMO_SCENE for name in DEMO_SCENES)
    expected = []                   # (scene, type) of every [[query]], scene after scene
    for name in DEMO_SCENES:
        text = resources.files("distkin.scenes").joinpath(name).read_text(encoding="utf-8")
        expected += [(f"distkin/scenes/{name}", q["type"]) for q in tomllib.loads(text)["query"]]
    assert [(q["scene"], q["type"]) for q in doc["queries"]] == expected
    assert all(q["status"] == "ok" and {"result", "seconds"} <= set(q)
               for q in doc["queries"])
    # a scene's records are the ones 'distkin run' writes for its file
    name = DEMO_SCENES[0]
    scene = tmp_path / name
    scene.write_text(resources.files("distkin.scenes").joinpath(name).read_text("utf-8"))
    assert main(["run", str(scene), "--no-progress", "--json", str(tmp_path / "r.json")]) == 0
    capsys.readouterr()
    run = json.loads((tmp_path / "r.json").read_text())["queries"]
    demo = [q for q in doc["queries"] if q["scene"] == f"distkin/scenes/{name}"]
    assert [q["result"] for q in demo] == [q["result"] for q in run]


def test_cli_usage_errors_exit_2():
    assert _cli(["run"]).returncode == 2
    assert _cli(["frobnicate"]).returncode == 2
