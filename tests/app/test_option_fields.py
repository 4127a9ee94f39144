"""An error whose field is a command-line option (``--store``, ``--scheduler``) is not
prefixed with the query's ``query[N].`` (the scene has no such field), and a chunk
store's error names ``--store`` when the store came from ``distkin sweep --store``
(QA: it said ``query[0].store``); a store written in the scene keeps ``query[0].store``.

Reference: where each value came from (the option given, or the scene's field), written
here, and the error the store's loader raises for an unreadable ``sweep.json``
(:func:`distkin.runstore.check_store`)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from distkin.app import registry
from distkin.app.cli import main, run_scene
from distkin.app.scene import loads_scene
from distkin.errors import InputError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SCENE = ('[mechanism]\nkind = "octahedral"\nbase = [[0,0,0], [6,"sqrt(108)",0], [12,0,0]]\n'
         'platform = [[0,0,0], [6,0,0], [3,"sqrt(27)",0]]\n[[query]]\n'
         'type = "forward_kinematics"\nlegs = ["19.8", "18", "18", "17", "14.9", "17.8"]\n'
         '[[query]]\ntype = "forward_kinematics"\n'
         'legs = ["19.8", "18", "18", "17", "14.9", "17.8"]\n')


@pytest.mark.parametrize("field, shown", [
    ("--store", "--store"), ("--scheduler.address", "--scheduler.address"),
    ("legs[0]", "query[1].legs[0]"), (None, "query[1]"), ("store", "query[1].store")])
def test_option_fields_keep_their_name(monkeypatch, field, shown):
    """Every query raises with ``field``: an option's stays as it is, a query's own field
    is prefixed with its query (the second one here, query[1])."""
    def fail(params, scene, ctx):
        raise InputError("expected something, got nothing", field=field)
    scene = loads_scene(SCENE)
    monkeypatch.setattr(registry, "get", lambda *a, **k: SimpleNamespace(run=fail))
    records, _, worst = run_scene(scene, progress=False)
    assert worst == 2
    assert records[1]["error"]["message"].startswith(f"{shown}: expected something")


def _sweep_error(capsys, args):
    code = main(args)
    out, err = capsys.readouterr()
    assert code == 2, out + err
    return err.strip().splitlines()[-1]


def test_a_store_error_names_where_the_store_came_from(tmp_path, capsys, monkeypatch):
    from distkin.runstore import check_store
    store = tmp_path / "st"
    store.mkdir()
    (store / "sweep.json").write_text("not json", encoding="utf-8")
    with pytest.raises(InputError) as ref:            # the store's own refusal, field store
        check_store(store, {"n": 1}, 1)
    assert ref.value.field == "store"
    reason = ref.value.message.split(" got ")[0]
    monkeypatch.chdir(tmp_path)
    line = _sweep_error(capsys, ["sweep", str(EXAMPLES / "certify_hunt.toml"), "--store", "st",
                                 "--no-progress"])
    assert line.startswith(f"distkin: error: --store: {reason}"), line
    scene = tmp_path / "s.toml"
    scene.write_text((EXAMPLES / "certify_hunt.toml").read_text(encoding="utf-8")
                     + 'store = "st"\n', encoding="utf-8")
    line = _sweep_error(capsys, ["run", str(scene), "--no-progress"])
    assert line.startswith(f"distkin: error: query[0].store: {reason}"), line
