"""Report wording a user reads (QA round G, cosmetic): a prismatic leg's IK has no crank
branch to state; a legs-scene singularity query in the certified tier states the sign
of det J in words ("None" was printed when its ball contains 0); a squared area that is
exactly zero is printed 0, not -0."""

from __future__ import annotations

from pathlib import Path

from distkin.app.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gough_stewart_6ups.toml"


def _scene(tmp_path, queries: str) -> Path:
    text = EXAMPLE.read_text(encoding="utf-8")
    head = text[:text.index("[[query]]")]
    f = tmp_path / "s.toml"
    f.write_text(head + queries, encoding="utf-8")
    return f


def test_prismatic_ik_states_no_crank_branch(tmp_path, capsys):
    f = _scene(tmp_path, '[[query]]\ntype = "inverse_kinematics"\n'
                         'poses = [[0, 0, 400, 0, 0, 0]]\n')
    assert main(["run", str(f), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "inverse_kinematics: ok" in out and "branch: the crank angle" not in out
    # a revolute device states it
    g = tmp_path / "rss.toml"
    g.write_text('[mechanism]\nkind = "rss"\npreset = "octo"\n[[query]]\n'
                 'type = "inverse_kinematics"\nposes = [[0, 0, 0.3, 0, 0, 0]]\n',
                 encoding="utf-8")
    assert main(["run", str(g), "--no-progress"]) == 0
    assert "branch: the crank angle" in capsys.readouterr().out


def test_certified_singularity_sign_is_in_words(tmp_path, capsys):
    f = _scene(tmp_path, '[[query]]\ntype = "singularity"\n'
                         'poses = [[0, 0, 400, 0, 0, 0], [30, -20, 430, 5, -3, 10]]\n'
                         'method = "certified"\n')
    assert main(["run", str(f), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "None" not in out
    assert "det J certified" in out or "sign of det J not certified" in out


def test_a_zero_squared_area_is_not_negative(tmp_path, capsys):
    f = tmp_path / "cm.toml"
    f.write_text('[units]\nlength = "mm"\n[mechanism]\nkind = "points"\n'
                 'points = [[0, 0, 0], [10, 0, 0], [0, 10, 0]]\n'
                 '[[query]]\ntype = "cayley_menger"\ndeterminants = ["D(1,1,2)"]\n',
                 encoding="utf-8")
    assert main(["run", str(f), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "area^2 = -0" not in out and "area^2 = 0" in out
