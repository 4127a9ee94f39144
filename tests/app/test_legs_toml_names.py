"""legs_toml_text quotes names as TOML strings: a name with ' or " wrote invalid TOML
(QA).  Reference: the scene read back has the same name and the same leg table."""

from __future__ import annotations

import tomllib

import pytest

from distkin.app.legs_scene import legs_toml_text
from distkin.app.scene import loads_scene
from distkin.mechanisms import LegMechanism, preset

QUERY = '\n[[query]]\ntype = "inverse_kinematics"\npose = [0, 0, 300, 0, 0, 0]\n'


@pytest.mark.parametrize("name", ["Kühne's rig", 'a "quoted" name', "back\\slash", "tab\there"])
def test_names_with_quotes_round_trip(name, tmp_path):
    m = LegMechanism.from_description(preset("hunt"))
    m = LegMechanism(name, m.leg_description().leg_table, m.home)
    text = legs_toml_text(m)
    assert tomllib.loads(text)["mechanism"]["name"] == name
    back = loads_scene(text + QUERY, path=str(tmp_path / "s.toml")).mechanism
    assert back.name == name
    assert back.leg_description().leg_table == m.leg_description().leg_table


def test_codegen_names_the_queries_of_a_legs_scene_without_kernel(tmp_path):
    """docs/design.md §4: the stderr line names the queries that get no kernel; a legs
    or rss scene said nothing about its certify_workspace query (QA)."""
    import subprocess
    import sys
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    out = tmp_path / "k.py"
    r = subprocess.run([sys.executable, "-m", "distkin", "codegen",
                        str(root / "examples" / "gough_stewart_6ups.toml"), "-o", str(out)],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "no kernel for the queries: certify_workspace" in r.stderr
    assert "def certify" not in out.read_text()
